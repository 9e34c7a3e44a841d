//! The report as one self-contained HTML page: no script, no network, no other file (the
//! figures are inline SVG, the style inline CSS).

use std::fmt::Write as _;

use cellsweep_stats::Standing;

use crate::analysis::Analysis;
use crate::claims::{evaluate, Claim, Verdict};
use crate::collection::PAPER_DIAGRAMS;
use crate::Results;

mod collapse;
mod convergence;
mod diagrams;
mod line;
mod planes;
mod provenance;
mod shift;

use collapse::collapse_section;
use convergence::convergence_section;
use diagrams::{checks_section, diagrams_section};
use line::{columns_section, cost_section, fit_section};
use planes::planes_section;
use provenance::provenance_section;

/// A value with its 95% interval ("18.21 [17.60, 18.83]"), or alone where it has none.
pub(crate) fn interval(v: f64, ci: [f64; 2], digits: usize) -> String {
    if ci[0].is_finite() {
        format!("{v:.digits$} [{:.digits$}, {:.digits$}]", ci[0], ci[1])
    } else {
        format!("{v:.digits$}")
    }
}

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

/// Write the whole report of `all` (generated at `generated`, a time stamp), with `variants`
/// (result sets of the numerics' variants, never shown as diagrams) compared column by column
/// against the shown diagrams.
pub fn render(all: &[Results], variants: &[Results], generated: &str) -> String {
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
    collapse_section(&mut h, &an);
    columns_section(&mut h, &an);
    convergence_section(&mut h, &an, variants);
    cost_section(&mut h, &an);
    diagrams_section(&mut h, &an);
    planes_section(&mut h, &an);
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
         <nav><a href=\"#claims\">Claims</a><a href=\"#fit\">The line</a><a href=\"#collapse\">One line?</a>\
         <a href=\"#columns\">β* per column</a><a href=\"#converged\">Converged?</a>\
         <a href=\"#diagrams\">Diagrams</a>{planes}\
         <a href=\"#checks\">Speed and spindle</a><a href=\"#provenance\">Provenance</a></nav>\n",
        escape(generated),
        claims.len(),
        count(Verdict::Reproduced),
        count(Verdict::Partly),
        count(Verdict::Not),
        count(Verdict::NoData),
        planes = if an.planes.is_empty() { "" } else { "<a href=\"#planes\">Other planes</a>" },
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
