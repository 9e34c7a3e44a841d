//! What `cellsweep fit` prints: the beta_crit line with its intervals beside the paper's, each
//! column's beta* by the model and by interpolation, and (SPEC 4.5) the line again without
//! the box-limited points. Main type: [`FittedLine`], rendered by [`FittedLine::text`] and
//! [`FittedLine::json`].

use std::fmt::Write;

use cellsweep_stats::{fit_line, Column, Counts, Fit, Method, NoFit, Scales};
use serde_json::json;

/// The line fitted to a sweep's points, and to them less the box-limited ones.
#[derive(Debug)]
pub struct FittedLine {
    pub method: Method,
    pub line: Result<Fit, NoFit>,
    /// How many points are box-limited.
    pub box_limited: usize,
    /// The line without them, where there are any.
    pub without_box_limited: Option<Result<Fit, NoFit>>,
}

impl FittedLine {
    /// Fit the line (`resamples` bootstrap draws from `seed`) with and without the
    /// box-limited points.
    pub fn fit(
        counts: &[Counts],
        scales: &Scales,
        resamples: usize,
        seed: u64,
        method: Method,
    ) -> FittedLine {
        let line = fit_line(counts, scales, resamples, seed, method);
        let box_limited = counts.iter().filter(|c| c.box_limited).count();
        let without_box_limited = (line.is_ok() && box_limited > 0).then(|| {
            let kept: Vec<Counts> = counts.iter().filter(|c| !c.box_limited).cloned().collect();
            fit_line(&kept, scales, resamples, seed, method)
        });
        FittedLine {
            method,
            line,
            box_limited,
            without_box_limited,
        }
    }

    /// The line, its columns and the line without box-limited points, for `name`d results;
    /// where no line could be fitted, the columns alone (the reason is the caller's to say).
    pub fn text(&self, name: &str) -> String {
        let fit = match &self.line {
            Ok(fit) => fit,
            Err(no) => {
                let mut out = "columns:\n".to_string();
                for c in &no.columns {
                    let _ = writeln!(out, "{}", column_line(c));
                }
                return out;
            }
        };
        let mut out = line_text(fit, name);
        let boxed = self.box_limited;
        match &self.without_box_limited {
            Some(Ok(f)) => {
                let _ = writeln!(
                    out,
                    "without the {boxed} box-limited points (SPEC 4.5): a = {:.4} [{:.4}, \
                     {:.4}], b = {:.3} [{:.3}, {:.3}]",
                    f.a, f.a_ci[0], f.a_ci[1], f.b, f.b_ci[0], f.b_ci[1]
                );
            }
            Some(Err(no)) => {
                let _ = writeln!(
                    out,
                    "without the {boxed} box-limited points (SPEC 4.5): no line ({})",
                    no.reason
                );
            }
            None => {}
        }
        out
    }

    /// The fit as JSON, with `box_limited_points` and the line without them under
    /// `without_box_limited`; or the reason there is no line, with the columns.
    pub fn json(&self) -> serde_json::Value {
        let fit = match &self.line {
            Ok(fit) => fit,
            Err(no) => {
                return json!({ "error": no.reason, "method": self.method, "columns": no.columns })
            }
        };
        let mut out = json!(fit);
        out["box_limited_points"] = json!(self.box_limited);
        if let Some(w) = &self.without_box_limited {
            out["without_box_limited"] = match w {
                Ok(f) => json!(f),
                Err(no) => json!({ "error": no.reason }),
            };
        }
        out
    }
}

/// "18.21 [17.60, 18.83]", or the value alone without an interval.
fn with_interval(v: f64, ci: Option<[f64; 2]>) -> String {
    match ci {
        Some([lo, hi]) if lo.is_finite() => format!("{v:.2} [{lo:.2}, {hi:.2}]"),
        _ => format!("{v:.2}"),
    }
}

/// One column: its beta* by the method in use, and the other reading beside it.
fn column_line(c: &Column) -> String {
    let mut head = format!(
        "  L = {:>3}  sigma = {:>3}  alpha = {:<5}  alpha~/L~ = {:>7.2}",
        c.L, c.sigma, c.alpha, c.x
    );
    if !c.others.is_empty() {
        head += &format!("  ({})", c.others);
    }
    let primary = match (c.beta_star, &c.skipped) {
        (Some(b), _) => format!("beta* = {}", with_interval(b, c.beta_ci)),
        (None, why) => format!(
            "no beta*: {}{}",
            why.as_deref().unwrap_or("no crossing"),
            c.censored_above.map_or(String::new(), |v| format!(
                "; the line counts it as censored (beta* above {v})"
            ))
        ),
    };
    if c.method == Method::Interpolate {
        return format!("{head}  {primary}");
    }
    let interpolated = c
        .interpolated
        .map_or("none".to_string(), |b| with_interval(b, c.interpolated_ci));
    let check = c.model.as_ref().map_or(String::new(), |m| {
        let fit = match m.fit_p {
            Some(p) if m.dispersion > 1.0 => format!(
                "lack of fit p = {p:.3}: interval widened by dispersion {:.2}",
                m.dispersion
            ),
            Some(p) => format!("fit p = {p:.2}"),
            None => "no df left to check the fit".to_string(),
        };
        let cut = m.cut_at.map_or(String::new(), |b| {
            format!("; falls back to training at beta = {b}: points from there left out")
        });
        format!(
            "\n      slope {:.3}/beta, {} points, deviance {:.1} on {} df, {fit}{cut}",
            m.slope, m.points, m.deviance, m.df
        )
    });
    format!("{head}  {primary}   (interpolated: {interpolated}){check}")
}

/// The line's coefficients beside the paper's, its spread, and every column.
fn line_text(fit: &Fit, name: &str) -> String {
    let how = match fit.method {
        Method::Model => {
            "beta* from a logistic model of each column; the line weighted by their intervals"
        }
        Method::Interpolate => "beta* interpolated between grid points (the paper's reading)",
    };
    let mut out = format!(
        "beta_crit = a alpha~/L~ + b, fitted to {name} (alpha~ = 2 pi R0 d alpha_eff, L~ = \
         L/R0; {how}):\n"
    );
    let _ = writeln!(
        out,
        "  a  = {:>8.4}   95% CI [{:.4}, {:.4}]   (paper: {})",
        fit.a, fit.a_ci[0], fit.a_ci[1], fit.paper_a
    );
    let _ = writeln!(
        out,
        "  b  = {:>8.3}   95% CI [{:.3}, {:.3}]   (paper: {})",
        fit.b, fit.b_ci[0], fit.b_ci[1], fit.paper_b
    );
    let _ = match fit.scatter {
        Some(r) => writeln!(
            out,
            "  R^2 = {:.4}, {} draws from the columns' intervals; scatter about the line {:.2} \
             times their intervals{}",
            fit.r2,
            fit.bootstrap,
            r,
            if r > 1.0 {
                " (the line's intervals widened by it)"
            } else {
                ""
            }
        ),
        None => writeln!(
            out,
            "  R^2 = {:.4}, {} bootstrap resamples over replicates",
            fit.r2, fit.bootstrap
        ),
    };
    out.push_str("columns:\n");
    for c in &fit.columns {
        let _ = writeln!(out, "{}", column_line(c));
    }
    out
}
