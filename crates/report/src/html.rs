//! The report as one self-contained HTML page: no script, no network, no other file (the
//! figures are inline SVG, the style inline CSS).

use std::fmt::Write as _;

use cellsweep_stats::{Column, Fit, NoFit, Standing};

use crate::analysis::{Analysis, RESAMPLES};
use crate::claims::{evaluate, Claim, Verdict};
use crate::collection::{DiagramKey, Shown, PAPER_DIAGRAMS};
use crate::figures::{diagram_of, speed_of};
use crate::Results;

/// Text made safe for HTML content and attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// "YYYY-MM-DD HH:MM UTC" of a Unix time (proleptic Gregorian; days-from-civil inverted).
pub fn utc_stamp(unix_s: i64) -> String {
    let (days, secs) = (unix_s.div_euclid(86_400), unix_s.rem_euclid(86_400));
    // Howard Hinnant's civil_from_days: era of 400 years, day of era, year of era.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02} UTC",
        secs / 3600,
        secs % 3600 / 60
    )
}

const STYLE: &str = "
body { font-family: 'DejaVu Sans', Verdana, sans-serif; max-width: 1400px; margin: 2em auto;
       padding: 0 1em; color: #222; line-height: 1.45; }
h1 { font-size: 1.6em; margin-bottom: .2em; } h2 { margin-top: 2em; border-bottom: 1px solid #ccc; }
.lead { font-size: 1.1em; } .small { font-size: .85em; color: #555; }
table { border-collapse: collapse; margin: .8em 0; } td, th { border: 1px solid #ccc;
       padding: .3em .55em; vertical-align: top; text-align: left; }
th { background: #f3f3f3; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
.verdict { font-weight: bold; white-space: nowrap; padding: .1em .5em; border-radius: .3em; }
.reproduced { background: #d4f0d4; } .partly { background: #fbecc0; }
.not { background: #f6cccc; } .nodata { background: #e4e4e4; }
blockquote { margin: 0; font-style: italic; } figure { margin: 1em 0; }
figure svg { max-width: 100%; height: auto; } figcaption { font-size: .9em; color: #444; }
nav a { margin-right: 1em; } code { background: #f3f3f3; padding: 0 .2em; }
";

fn verdict_class(v: Verdict) -> &'static str {
    match v {
        Verdict::Reproduced => "reproduced",
        Verdict::Partly => "partly",
        Verdict::Not => "not",
        Verdict::NoData => "nodata",
    }
}

fn interval(v: f64, ci: [f64; 2], digits: usize) -> String {
    if ci[0].is_finite() {
        format!("{v:.digits$} [{:.digits$}, {:.digits$}]", ci[0], ci[1])
    } else {
        format!("{v:.digits$}")
    }
}

/// The sweep file that makes diagram `key` in this repository.
fn sweep_file(key: DiagramKey) -> String {
    format!("sweeps/adaptive/L{}-sigma{}.toml", key.L, key.sigma)
}

/// Write the whole report of `all` (generated at `generated`, a time stamp).
pub fn render(all: &[Results], generated: &str) -> String {
    let an = Analysis::of(all);
    let claims = evaluate(&an);
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>cellsweep: Luo, Nain &amp; Camley (2025) reproduced</title>\n\
         <style>{STYLE}</style>\n</head>\n<body>\n"
    );
    header(&mut h, &an, &claims, generated);
    claims_section(&mut h, &claims);
    fit_section(&mut h, &an);
    columns_section(&mut h, &an);
    diagrams_section(&mut h, &an);
    checks_section(&mut h, &an);
    provenance_section(&mut h, all, &an, generated);
    h.push_str("</body>\n</html>\n");
    h
}

fn header(h: &mut String, an: &Analysis<'_>, claims: &[Claim], generated: &str) {
    let shown = PAPER_DIAGRAMS
        .iter()
        .filter(|k| an.collection.diagram(k.L, k.sigma).is_some())
        .count();
    let trajectories: u64 = an
        .collection
        .diagrams
        .iter()
        .map(|s| s.replicates().1)
        .sum();
    let count = |v: Verdict| claims.iter().filter(|c| c.verdict == v).count();
    // Diagrams whose adaptive points still take rounds: their verdicts may yet change.
    let running: Vec<String> = an
        .collection
        .diagrams
        .iter()
        .filter_map(|s| {
            let st = s.results.standings.as_ref()?;
            let open = s
                .points
                .iter()
                .filter(|&&i| st[i].standing == Standing::Open)
                .count();
            (open > 0).then(|| {
                format!(
                    "{} ({open} of {} points open)",
                    s.key.title(),
                    s.points.len()
                )
            })
        })
        .collect();
    let running = if running.is_empty() {
        String::new()
    } else {
        format!(
            "<p><b>Still running:</b> {}. Their numbers and the verdicts that use them may yet \
             change.</p>\n",
            escape(&running.join("; "))
        )
    };
    let _ = write!(
        h,
        "<h1>Cell-cell collisions on nanofibers, reproduced</h1>\n\
         <p class=\"small\">Luo, Nain &amp; Camley, <i>Soft Matter</i> 2025 (arXiv 2503.06239), \
         checked against cellsweep's own runs of the same model. Generated {}.</p>\n\
         <p class=\"lead\">{shown} of the paper's 6 phase diagrams are here, from {trajectories} \
         collisions. Of the paper's {} claims checked below, {} are reproduced, {} partly, {} \
         not, and {} wait for diagrams not yet run.</p>\n{running}\
         <nav><a href=\"#claims\">Claims</a><a href=\"#fit\">The line</a>\
         <a href=\"#columns\">β* per column</a><a href=\"#diagrams\">Diagrams</a>\
         <a href=\"#checks\">Speed and spindle</a><a href=\"#provenance\">Provenance</a></nav>\n",
        escape(generated),
        claims.len(),
        count(Verdict::Reproduced),
        count(Verdict::Partly),
        count(Verdict::Not),
        count(Verdict::NoData),
    );
}

fn claims_section(h: &mut String, claims: &[Claim]) {
    h.push_str(
        "<h2 id=\"claims\">The paper's claims</h2>\n<p>Each claim in the paper's words, the \
         numbers from the data (95% Wilson intervals on frequencies), and the rule that gives \
         the verdict.</p>\n<table>\n<tr><th>verdict</th><th>claim</th><th>data</th>\
         <th>rule</th></tr>\n",
    );
    for c in claims {
        let _ = writeln!(
            h,
            "<tr><td><span class=\"verdict {}\">{}</span></td><td><blockquote>{}</blockquote>\
             <span class=\"small\">{}</span></td><td>{}</td><td class=\"small\">{}</td></tr>",
            verdict_class(c.verdict),
            c.verdict.as_str(),
            escape(c.quote),
            escape(c.source),
            escape(&c.evidence),
            escape(c.rule)
        );
    }
    h.push_str("</table>\n");
}

fn fit_row(h: &mut String, what: &str, fit: &Result<Fit, NoFit>, paper: &str) {
    match fit {
        Ok(f) => {
            let used = f.columns.iter().filter(|c| c.beta_star.is_some()).count();
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>\
                 <td class=\"num\">{:.3}</td><td class=\"num\">{used} of {}</td><td>{}</td></tr>",
                escape(what),
                interval(f.a, f.a_ci, 3),
                interval(f.b, f.b_ci, 1),
                f.r2,
                f.columns.len(),
                escape(paper)
            );
        }
        Err(no) => {
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td colspan=\"5\">no line: {}</td></tr>",
                escape(what),
                escape(&no.reason)
            );
        }
    }
}

fn fit_section(h: &mut String, an: &Analysis<'_>) {
    let _ = write!(
        h,
        "<h2 id=\"fit\">The transition line β<sub>crit</sub> = a α̃/L̃ + b</h2>\n\
         <p>Per α column of each diagram, β* is where n<sub>walk</sub> − n<sub>train</sub> \
         changes sign as β rises (linear interpolation); the line is fitted to the β* of every \
         spacing by least squares, with α̃ = 2π R<sub>0</sub> d α<sub>eff</sub> / ε<sub>0</sub> \
         and L̃ = L / R<sub>0</sub>. At σ = 0, α<sub>eff</sub> = α + 0.0134 (the paper's \
         shift), so a line that agrees with the paper's at both σ has the same a and b. \
         Intervals: 95% from {RESAMPLES} bootstrap resamples over replicates, each point \
         redrawn with its own n. They cover the sampling noise only: where the frequencies jump \
         between two β rows 4 apart, the interpolated crossing can sit up to 2 from the true one \
         without the bootstrap seeing it.</p>\n<table>\n<tr><th></th><th>a</th><th>b</th><th>R²</th>\
         <th>columns with a crossing</th><th>paper</th></tr>\n"
    );
    for (sigma, what, fit, paper) in [
        (5.0, "σ = 5, every L", &an.fit5, "a = 0.6, b = −12"),
        (0.0, "σ = 0, every L (shifted α)", &an.fit0, "the same line"),
    ] {
        if an.collection.diagrams.iter().any(|s| s.key.sigma == sigma) {
            fit_row(h, what, fit, paper);
        } else {
            let _ = writeln!(
                h,
                "<tr><td>{what}</td><td colspan=\"5\">no diagram at this σ yet</td></tr>"
            );
        }
    }
    h.push_str("</table>\n");
    match &an.shift {
        Some(s) => {
            let _ = writeln!(
                h,
                "<p><b>The shift from σ = 5 to σ = 0</b>, measured without assuming it: the σ = 0 \
                 crossings fitted as the σ = 5 line (a = {:.3}, b = {:.1}, unshifted α) moved \
                 to smaller α by one δ for every L: <b>δ = {}</b> from {} columns at σ = 5 and \
                 {} at σ = 0, against the paper's {}.</p>",
                s.a,
                s.b,
                interval(s.delta, s.delta_ci, 4),
                s.columns_sigma5,
                s.columns_sigma0,
                s.paper_delta
            );
        }
        None => h.push_str(
            "<p><b>The shift from σ = 5 to σ = 0</b> needs crossings at both σ: not measured \
             yet.</p>\n",
        ),
    }
}

fn star_cell(c: &Column) -> String {
    match (c.beta_star, c.beta_ci, c.skipped.as_deref()) {
        (Some(b), Some(ci), _) => interval(b, ci, 1),
        (Some(b), None, _) => format!("{b:.1}"),
        (None, _, Some(why)) => format!("<span class=\"small\">{}</span>", escape(why)),
        (None, _, None) => "–".into(),
    }
}

fn columns_section(h: &mut String, an: &Analysis<'_>) {
    h.push_str(
        "<h2 id=\"columns\">β* per column</h2>\n<p>With 95% bootstrap intervals (shown where at \
         least half the resamples have a crossing), beside the paper's line at that α.</p>\n",
    );
    if an.per_diagram.is_empty() {
        h.push_str("<p>No diagram yet.</p>\n");
        return;
    }
    for (key, cols, _) in &an.per_diagram {
        let Some(shown) = an.collection.diagram(key.L, key.sigma) else {
            continue;
        };
        let scales = shown.results.scales;
        let _ = write!(
            h,
            "<h3>{}</h3>\n<table>\n<tr><th>α</th>",
            escape(&key.title())
        );
        for c in cols {
            let _ = write!(h, "<th>{}</th>", c.alpha);
        }
        h.push_str("</tr>\n<tr><td>β* (data)</td>");
        for c in cols {
            let _ = write!(h, "<td class=\"num\">{}</td>", star_cell(c));
        }
        h.push_str("</tr>\n<tr><td>paper's line</td>");
        for c in cols {
            let b = scales.beta_on_line(
                cellsweep_stats::fit::PAPER_A,
                cellsweep_stats::fit::PAPER_B,
                c.alpha,
                c.L,
                c.sigma,
            );
            let _ = write!(h, "<td class=\"num\">{b:.1}</td>");
        }
        h.push_str("</tr>\n</table>\n");
    }
}

/// n per point and the adaptive standings of a shown diagram, in words.
fn diagram_summary(s: &Shown<'_>) -> String {
    let (rows, collisions) = s.replicates();
    let ns: Vec<u64> = s.counts().map(|c| c.total()).collect();
    let (lo, hi) = (
        ns.iter().copied().min().unwrap_or(0),
        ns.iter().copied().max().unwrap_or(0),
    );
    let mut out = format!(
        "{} points, {rows} replicates ({collisions} collisions), {lo} to {hi} per point",
        s.points.len()
    );
    if let Some(st) = &s.results.standings {
        let count = |w: Standing| s.points.iter().filter(|&&i| st[i].standing == w).count();
        out += &format!(
            "; adaptive: {} settled on their label, {} on their sign away from the crossing, {} \
             decided by their prep, {} at the full budget, {} still open",
            count(Standing::Settled),
            count(Standing::Sign),
            count(Standing::Verdict),
            count(Standing::Exhausted),
            count(Standing::Open)
        );
    }
    // SPEC section 5: collisions in which a cell broke up are artefacts of the lattice, counted
    // and named where they are.
    let broke: Vec<String> = s
        .counts()
        .filter(|c| c.n_collision_breakup > 0)
        .map(|c| {
            format!(
                "{}/{} at (α {}, β {})",
                c.n_collision_breakup,
                c.total(),
                c.alpha,
                c.beta
            )
        })
        .collect();
    if !broke.is_empty() {
        let n: u64 = s.counts().map(|c| c.n_collision_breakup).sum();
        out += &format!(
            "; {n} collisions broke up (a cell split during the collision, SPEC section 5): {}",
            broke.join(", ")
        );
    }
    out
}

fn diagrams_section(h: &mut String, an: &Analysis<'_>) {
    h.push_str(
        "<h2 id=\"diagrams\">The six diagrams</h2>\n<p>Panels as in the paper: (a) the label of \
         each point by SPEC section 6 (dominant at 55%, coexistence, or the prep's verdict), \
         (b)–(d) the frequencies of training, walk-past and reversal. The number beside each \
         mark is its n (a + marks an adaptive point still taking rounds); hovering a point \
         shows its counts and intervals. Dashed: the paper's line (black) and the line fitted \
         over every spacing at that σ (orange).</p>\n",
    );
    for key in PAPER_DIAGRAMS {
        let fig_name = key.paper_figure().unwrap_or("");
        let _ = writeln!(
            h,
            "<h3 id=\"L{}-sigma{}\">{} (paper {fig_name})</h3>",
            key.L,
            key.sigma,
            escape(&key.title())
        );
        let Some(s) = an.collection.diagram(key.L, key.sigma) else {
            let _ = writeln!(
                h,
                "<p>Not run yet: <code>cellsweep run {}</code>.</p>",
                sweep_file(key)
            );
            continue;
        };
        let fit = if key.sigma == 5.0 {
            an.fit5.as_ref().ok()
        } else {
            an.fit0.as_ref().ok()
        };
        let svg = diagram_of(s.results, (key.L, key.sigma), fit).to_svg();
        let _ = writeln!(
            h,
            "<figure>{svg}<figcaption>{} (sweep {})</figcaption></figure>",
            escape(&diagram_summary(s)),
            escape(&s.results.name)
        );
    }
    for s in an
        .collection
        .diagrams
        .iter()
        .filter(|s| !PAPER_DIAGRAMS.contains(&s.key))
    {
        let svg = diagram_of(s.results, (s.key.L, s.key.sigma), None).to_svg();
        let _ = writeln!(
            h,
            "<h3>{} (not one of the paper's)</h3>\n<figure>{svg}<figcaption>{} (sweep {})\
             </figcaption></figure>",
            escape(&s.key.title()),
            escape(&diagram_summary(s)),
            escape(&s.results.name)
        );
    }
}

fn checks_section(h: &mut String, an: &Analysis<'_>) {
    h.push_str("<h2 id=\"checks\">Speed and spindle</h2>\n");
    match an.collection.speed {
        Some(r) => {
            let _ = writeln!(
                h,
                "<figure>{}<figcaption>The paper's Fig. A4: free speed of the prepped cells \
                 against β (sweep {}).</figcaption></figure>",
                speed_of(r).to_svg(),
                escape(&r.name)
            );
        }
        None => h.push_str(
            "<p>The speed figure is not run yet: <code>cellsweep run \
             sweeps/check-speed-alpha0.20.toml</code>.</p>\n",
        ),
    }
    match an.collection.spindle {
        Some(r) => {
            h.push_str(
                "<table>\n<tr><th>one fiber: α, β, σ</th><th>n</th><th>training</th>\
                 <th>walk-past</th><th>reversal</th><th>undetermined</th></tr>\n",
            );
            for c in &r.counts {
                let _ = writeln!(
                    h,
                    "<tr><td>{}, {}, {}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>\
                     <td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td></tr>",
                    c.alpha,
                    c.beta,
                    c.sigma,
                    c.total(),
                    c.n_train,
                    c.n_walk,
                    c.n_reversal,
                    c.n_undetermined
                );
            }
            h.push_str("</table>\n");
        }
        None => h.push_str(
            "<p>The spindle check is not run yet: <code>cellsweep run \
             sweeps/check-spindle.toml</code>.</p>\n",
        ),
    }
}

fn provenance_section(h: &mut String, all: &[Results], an: &Analysis<'_>, generated: &str) {
    let _ = write!(
        h,
        "<h2 id=\"provenance\">Provenance</h2>\n<p>Every replicate's seed derives from its \
         sweep's seed, its point and its index; the exports list each one. Core-hours are the \
         wall times recorded on the workers (collisions and preps, each prep once).</p>\n\
         <table>\n<tr><th>sweep</th><th>source</th><th>solver</th><th>seed</th>\
         <th>collisions</th><th>budget per point</th><th>replicates</th><th>collisions run</th>\
         <th>core-hours</th><th>shown</th></tr>\n"
    );
    for r in all {
        let shown = an
            .collection
            .unused
            .iter()
            .find(|(u, _)| std::ptr::eq(*u, r))
            .map_or("yes".to_string(), |(_, why)| format!("no: {why}"));
        match &r.provenance {
            Some(p) => {
                let budget = match &p.adaptive {
                    Some(a) => format!(
                        "adaptive, {} to {} in rounds of {}, error {}",
                        a.min_replicates, a.max_replicates, a.batch, a.error
                    ),
                    None => format!("{} fixed", p.replicates),
                };
                let ch = p.core_hours();
                let ch = if ch >= 0.1 {
                    format!("{ch:.2}")
                } else {
                    format!("{ch:.4}")
                };
                let hours = if p.untimed > 0 {
                    format!("{ch} (+ {} collisions imported without times)", p.untimed)
                } else {
                    ch
                };
                let _ = writeln!(
                    h,
                    "<tr><td>{}</td><td>{}</td><td>{}</td><td class=\"num\">{}</td><td>{}, {} τ<sub>0</sub></td>\
                     <td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td>{}</td></tr>",
                    escape(&r.name),
                    escape(&p.source),
                    escape(&p.solver_versions.join(", ")),
                    p.seed,
                    escape(&p.precision),
                    p.collide_time,
                    escape(&budget),
                    p.rows,
                    p.collisions,
                    escape(&hours),
                    escape(&shown)
                );
            }
            None => {
                let _ = writeln!(
                    h,
                    "<tr><td>{}</td><td colspan=\"8\">a counts file: no provenance</td><td>{}</td></tr>",
                    escape(&r.name),
                    escape(&shown)
                );
            }
        }
    }
    let _ = writeln!(
        h,
        "</table>\n<p class=\"small\">Generated {} by cellsweep {}: <code>cellsweep report \
         --data DIR --out report.html</code> regenerates this page from the exports.</p>",
        escape(generated),
        env!("CARGO_PKG_VERSION")
    );
}

#[cfg(test)]
mod tests {
    use super::{escape, utc_stamp};

    #[test]
    fn time_stamps_are_civil_dates() {
        assert_eq!(utc_stamp(0), "1970-01-01 00:00 UTC");
        // 2000-02-29 12:34 (a leap day of a century leap year) and 2026-12-02 01:00.
        assert_eq!(utc_stamp(951_827_640), "2000-02-29 12:34 UTC");
        assert_eq!(utc_stamp(1_796_173_200), "2026-12-02 01:00 UTC");
    }

    #[test]
    fn markup_is_escaped() {
        assert_eq!(
            escape("<a href=\"x\">'$(rm)'&</a>"),
            "&lt;a href=&quot;x&quot;&gt;&#39;$(rm)&#39;&amp;&lt;/a&gt;"
        );
    }
}
