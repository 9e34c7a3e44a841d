//! `cellsweep fit`: the beta_crit line with its intervals, beside the paper's; each column's
//! beta* by the model and by interpolation.

use cellsweep_stats::{fit_line, Column, Fit, Method};
use serde_json::json;

use crate::cli::{FitArgs, FitFormat};

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

fn print_fit(fit: &Fit, name: &str) {
    let how = match fit.method {
        Method::Model => {
            "beta* from a logistic model of each column; the line weighted by their intervals"
        }
        Method::Interpolate => "beta* interpolated between grid points (the paper's reading)",
    };
    println!("beta_crit = a alpha~/L~ + b, fitted to {name} (alpha~ = 2 pi R0 d alpha_eff, L~ = L/R0; {how}):");
    println!(
        "  a  = {:>8.4}   95% CI [{:.4}, {:.4}]   (paper: {})",
        fit.a, fit.a_ci[0], fit.a_ci[1], fit.paper_a
    );
    println!(
        "  b  = {:>8.3}   95% CI [{:.3}, {:.3}]   (paper: {})",
        fit.b, fit.b_ci[0], fit.b_ci[1], fit.paper_b
    );
    match fit.scatter {
        Some(r) => println!(
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
        None => println!(
            "  R^2 = {:.4}, {} bootstrap resamples over replicates",
            fit.r2, fit.bootstrap
        ),
    }
    println!("columns:");
    for c in &fit.columns {
        println!("{}", column_line(c));
    }
}

pub fn run(args: FitArgs) -> anyhow::Result<i32> {
    let loaded = args.select.apply(args.source.load()?)?;
    let method = args.method.method();
    match fit_line(
        &loaded.counts,
        &loaded.scales,
        args.bootstrap as usize,
        args.seed,
        method,
    ) {
        Ok(fit) => {
            // SPEC 4.5: the line with and without the box-limited points.
            let boxed = loaded.counts.iter().filter(|c| c.box_limited).count();
            let without = (boxed > 0).then(|| {
                let kept: Vec<_> = loaded
                    .counts
                    .iter()
                    .filter(|c| !c.box_limited)
                    .cloned()
                    .collect();
                fit_line(
                    &kept,
                    &loaded.scales,
                    args.bootstrap as usize,
                    args.seed,
                    method,
                )
            });
            if args.format == FitFormat::Json {
                let mut out = serde_json::to_value(&fit)?;
                out["box_limited_points"] = json!(boxed);
                if let Some(w) = &without {
                    out["without_box_limited"] = match w {
                        Ok(f) => serde_json::to_value(f)?,
                        Err(no) => json!({ "error": no.reason }),
                    };
                }
                println!("{}", serde_json::to_string_pretty(&out)?);
            } else {
                print_fit(&fit, &loaded.name);
                match &without {
                    Some(Ok(f)) => println!(
                        "without the {boxed} box-limited points (SPEC 4.5): a = {:.4} [{:.4}, \
                         {:.4}], b = {:.3} [{:.3}, {:.3}]",
                        f.a, f.a_ci[0], f.a_ci[1], f.b, f.b_ci[0], f.b_ci[1]
                    ),
                    Some(Err(no)) => println!(
                        "without the {boxed} box-limited points (SPEC 4.5): no line ({})",
                        no.reason
                    ),
                    None => {}
                }
            }
            Ok(0)
        }
        Err(no) => {
            if args.format == FitFormat::Json {
                let out = json!({ "error": no.reason, "method": method, "columns": no.columns });
                println!("{}", serde_json::to_string_pretty(&out)?);
            } else {
                println!("columns:");
                for c in &no.columns {
                    println!("{}", column_line(c));
                }
            }
            eprintln!(
                "error: cannot fit the beta_crit line to {}: {}",
                loaded.name, no.reason
            );
            Ok(1)
        }
    }
}
