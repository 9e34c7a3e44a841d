//! `cellsweep plot`: phase diagrams, frequency heat maps with beta_crit lines, free speeds.

use std::path::{Path, PathBuf};

use anyhow::Context;
use cellsweep_plot::phase::{diagram_figure, speed_figure, BetaLine, Diagram, Mark, Point, Series};
use cellsweep_plot::{Color, Figure};
use cellsweep_store::{
    fit::PAPER_A, fit::PAPER_B, fit_line, wilson, Assessment, Counts, Label, Scales, Standing,
};

use super::counts::{self, Loaded};
use super::table::diagrams;
use crate::cli::PlotArgs;

fn mark(l: Label) -> Mark {
    match l {
        Label::Train => Mark::Train,
        Label::WalkPast => Mark::WalkPast,
        Label::Reversal => Mark::Reversal,
        Label::Coexist => Mark::Coexist,
        Label::Unstable => Mark::Unstable,
        Label::Breakup => Mark::Breakup,
        Label::Undetermined => Mark::Undetermined,
        Label::Mixed => Mark::Mixed,
    }
}

/// beta = a x(alpha) + b as a line in the (alpha, beta) plane of diagram (L, sigma).
fn beta_line(
    scales: &Scales,
    a: f64,
    b: f64,
    spacing: u32,
    sigma: f64,
    label: String,
    color: Color,
) -> BetaLine {
    let x0 = scales.x(0.0, spacing, sigma);
    let x1 = scales.x(1.0, spacing, sigma);
    BetaLine {
        label,
        color,
        slope: a * (x1 - x0),
        intercept: a * x0 + b,
    }
}

fn write(fig: &Figure, dir: &Path, stem: &str, written: &mut Vec<PathBuf>) -> anyhow::Result<()> {
    let svg = dir.join(format!("{stem}.svg"));
    std::fs::write(&svg, fig.to_svg())
        .with_context(|| format!("cannot write {}", svg.display()))?;
    let png = dir.join(format!("{stem}.png"));
    std::fs::write(&png, fig.to_png(2.0)?)
        .with_context(|| format!("cannot write {}", png.display()))?;
    written.extend([svg, png]);
    Ok(())
}

/// Write every picture of `loaded` into `dir`; returns the files written.
pub fn write_plots(loaded: &Loaded, dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let fitted = fit_line(&loaded.counts, &loaded.scales, 0, 1).ok();
    let mut written = Vec::new();
    for (l, sigma) in diagrams(&loaded.counts) {
        let pts: Vec<&Counts> = loaded
            .counts
            .iter()
            .filter(|c| c.L == l && c.sigma == sigma)
            .collect();
        // The adaptive assessment of a point, if the sweep is adaptive.
        let assessment = |c: &Counts| {
            loaded.standings.as_ref().and_then(|st| {
                loaded
                    .counts
                    .iter()
                    .zip(st)
                    .find(|(k, _)| std::ptr::eq(*k, c))
                    .map(|(_, a)| a)
            })
        };
        let points = pts
            .iter()
            .map(|c| {
                let n = (c.n_train + c.n_walk + c.n_reversal + c.n_undetermined) as f64;
                let f = |k: u64| {
                    if c.collided() && n > 0.0 {
                        k as f64 / n
                    } else {
                        f64::NAN
                    }
                };
                Point {
                    alpha: c.alpha,
                    beta: c.beta,
                    mark: c.label().map(mark),
                    freq: [f(c.n_train), f(c.n_walk), f(c.n_reversal)],
                    n: c.total(),
                    open: assessment(c).is_some_and(|a| a.standing == Standing::Open),
                    detail: detail(c, assessment(c)),
                }
            })
            .collect();
        let mut lines = vec![beta_line(
            &loaded.scales,
            PAPER_A,
            PAPER_B,
            l,
            sigma,
            "paper\u{2019}s β_{crit}".into(),
            Color::BLACK,
        )];
        if let Some(fit) = &fitted {
            lines.push(beta_line(
                &loaded.scales,
                fit.a,
                fit.b,
                l,
                sigma,
                format!("fit: a = {:.2}, b = {:.1}", fit.a, fit.b),
                Color::ORANGE,
            ));
        }
        let d = Diagram {
            title: format!(
                "{}: L = {l} ({} µm), σ = {sigma}",
                loaded.name,
                l as f64 * cellsweep_plot::frames::SITE_UM
            ),
            points,
            lines,
        };
        write(
            &diagram_figure(&d),
            dir,
            &format!("phase-L{l}-sigma{sigma}"),
            &mut written,
        )?;
    }
    // Free speed against beta, one curve per (L, alpha); sigma does not change the prep.
    let palette = [
        Color::BLUE,
        Color::RED,
        Color::GREEN,
        Color::ORANGE,
        Color::CYAN,
        Color(120, 60, 160),
        Color::GREY,
        Color::BLACK,
    ];
    let mut keys: Vec<(u32, f64)> = Vec::new();
    for c in &loaded.counts {
        if c.free_speed.is_some() && !keys.contains(&(c.L, c.alpha)) {
            keys.push((c.L, c.alpha));
        }
    }
    let series: Vec<Series> = keys
        .iter()
        .enumerate()
        .map(|(k, &(l, alpha))| {
            let mut points: Vec<(f64, f64)> = Vec::new();
            let mut errors: Vec<f64> = Vec::new();
            for (i, c) in loaded.counts.iter().enumerate() {
                if c.L != l || c.alpha != alpha || points.iter().any(|p| p.0 == c.beta) {
                    continue;
                }
                if let Some(v) = c.free_speed {
                    points.push((c.beta, v));
                    // The standard error of the mean over the point's prepped cells.
                    let cells = loaded.prep_speeds.as_ref().map_or(&[][..], |s| &s[i][..]);
                    errors.push(standard_error(cells));
                }
            }
            let several = errors.iter().any(|e| e.is_finite());
            Series {
                label: format!("L = {l}, α = {alpha}"),
                color: palette[k % palette.len()],
                points,
                errors: if several { errors } else { Vec::new() },
            }
        })
        .collect();
    let title = if series.iter().any(|s| !s.errors.is_empty()) {
        format!(
            "{}: mean free speed of the prepped cells ± standard error",
            loaded.name
        )
    } else {
        format!("{}: free speed of the prepped cell", loaded.name)
    };
    write(
        &speed_figure(&title, &series),
        dir,
        "free-speed",
        &mut written,
    )?;
    Ok(written)
}

pub fn run(args: PlotArgs) -> anyhow::Result<()> {
    let loaded = counts::load(&args.source)?;
    for f in write_plots(&loaded, &args.out)? {
        println!("wrote {}", f.display());
    }
    Ok(())
}

/// A point's tooltip: where it is, its counts, its label, and its adaptive standing.
fn detail(c: &Counts, a: Option<&Assessment>) -> String {
    let mut out = format!(
        "α = {}, β = {}, L = {}, σ = {}: n = {} (training {}, walk-past {}, reversal {}, \
         undetermined {}",
        c.alpha,
        c.beta,
        c.L,
        c.sigma,
        c.total(),
        c.n_train,
        c.n_walk,
        c.n_reversal,
        c.n_undetermined
    );
    if c.n_unstable + c.n_breakup > 0 {
        out += &format!(", unstable {}, breakup {}", c.n_unstable, c.n_breakup);
    }
    out += ")";
    let collided = c.n_train + c.n_walk + c.n_reversal + c.n_undetermined;
    if collided > 0 {
        let f = |k: u64| {
            let w = wilson(k, collided);
            format!("{:.2} [{:.2}, {:.2}]", w.value, w.low, w.high)
        };
        out += &format!(
            "; fractions with 95% Wilson intervals: training {}, walk-past {}, reversal {}",
            f(c.n_train),
            f(c.n_walk),
            f(c.n_reversal)
        );
    }
    if let Some(label) = c.label() {
        out += &format!("; label {}", label.as_str());
    }
    if let Some(a) = a {
        out += &format!("; adaptive: {}", a.standing.as_str());
        if let Some(b) = &a.bounds {
            out += &format!(
                "; bounds at the stated error: p_train [{:.2}, {:.2}], p_walk [{:.2}, {:.2}], \
                 p_walk - p_train [{:.2}, {:.2}]",
                b.train[0],
                b.train[1],
                b.walk_past[0],
                b.walk_past[1],
                b.walk_minus_train[0],
                b.walk_minus_train[1]
            );
        }
    }
    out
}

/// The standard error of the mean of `xs` (NaN for fewer than two).
fn standard_error(xs: &[f64]) -> f64 {
    let n = xs.len() as f64;
    if xs.len() < 2 {
        return f64::NAN;
    }
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (var / n).sqrt()
}

#[cfg(test)]
mod tests {
    use super::standard_error;

    #[test]
    fn the_standard_error_is_of_the_mean() {
        // Sample sd of 1, 2, 3, 4 is sqrt(5/3); over sqrt(4).
        let se = standard_error(&[1.0, 2.0, 3.0, 4.0]);
        assert!((se - (5.0f64 / 3.0).sqrt() / 2.0).abs() < 1e-12);
        assert!(standard_error(&[1.0]).is_nan());
    }
}
