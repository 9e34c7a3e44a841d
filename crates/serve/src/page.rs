//! The live page as HTML, rendered on the server: the shell with its script, and the live
//! fragment the script swaps in when the store changes. Every name, path and error is
//! escaped here, as in the report; the script never builds markup from data.

use std::fmt::Write as _;

use cellsweep_report::html::{escape, utc_stamp};
use cellsweep_stats::throughput::speed_line;
use cellsweep_stats::Tally;
use cellsweep_store::StateCounts;

use crate::snapshot::{Snapshot, SweepView};

const STYLE: &str = "
body { font-family: 'DejaVu Sans', Verdana, sans-serif; max-width: 1400px; margin: 1.5em auto;
       padding: 0 1em; color: #222; line-height: 1.45; }
h1 { font-size: 1.5em; margin-bottom: .2em; } h2 { margin-top: 1.6em; border-bottom: 1px solid #ccc; }
.small { font-size: .85em; color: #555; } .message { background: #fbecc0; padding: .5em 1em; }
table { border-collapse: collapse; margin: .6em 0; } td, th { border: 1px solid #ccc;
       padding: .25em .55em; text-align: left; vertical-align: top; }
th { background: #f3f3f3; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
progress { width: 100%; height: 1.2em; }
.state { font-size: .8em; padding: .1em .5em; border-radius: .3em; vertical-align: middle; }
.running { background: #d4e4f7; } .finished { background: #d4f0d4; } .idle { background: #e4e4e4; }
.failed { background: #f6cccc; }
figure { margin: 1em 0; } figure svg { max-width: 100%; height: auto; }
code { background: #f3f3f3; padding: 0 .2em; }
";

/// The script: poll `/api/live`, swap in the fragment when its generation moves on, and say
/// when the server stops answering. It inserts only markup the server rendered.
pub const SCRIPT: &str = r#"(function () {
  var live = document.getElementById('live');
  var note = document.getElementById('connection');
  var every = Number(document.body.getAttribute('data-poll-ms')) || 2000;
  var generation = Number(live.getAttribute('data-generation')) || 0;
  function tick() {
    fetch('api/live?since=' + generation, { cache: 'no-store' })
      .then(function (r) { if (!r.ok) { throw new Error('HTTP ' + r.status); } return r.json(); })
      .then(function (v) {
        note.textContent = 'live: checked ' + new Date().toLocaleTimeString();
        if (v.generation !== generation && typeof v.html === 'string') {
          generation = v.generation;
          live.innerHTML = v.html;
          live.setAttribute('data-generation', String(generation));
        }
      })
      .catch(function () { note.textContent = 'the server does not answer: retrying'; })
      .then(function () { setTimeout(tick, every); });
  }
  setTimeout(tick, every);
})();
"#;

/// The whole page: `live` (the current fragment) inside the shell, and `exports` (the
/// static diagrams of `--data`, already HTML) below it.
pub fn page(store: &str, live: &str, generation: u64, exports: &str, poll_ms: u64) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <link rel=\"icon\" href=\"data:,\">\n<title>cellsweep live: {store}</title>\n<style>{STYLE}</style>\n</head>\n\
         <body data-poll-ms=\"{poll_ms}\">\n<h1>cellsweep live</h1>\n\
         <p class=\"small\">store <code>{store}</code> · <span id=\"connection\">live</span></p>\n\
         <div id=\"live\" data-generation=\"{generation}\">{live}</div>\n{exports}\
         <script src=\"live.js\"></script>\n</body>\n</html>\n",
        store = escape(store),
    );
    h
}

/// The live part: each sweep's progress, standings, failures, arrays and diagrams.
pub fn live_fragment(s: &Snapshot) -> String {
    let mut h = String::new();
    let stamp = utc_stamp(s.at as i64);
    let _ = writeln!(
        h,
        "<p class=\"small\">as of <span data-field=\"at\">{stamp}</span></p>"
    );
    if let Some(m) = &s.message {
        let _ = writeln!(
            h,
            "<p class=\"message\" data-field=\"message\">{}</p>",
            escape(m)
        );
    }
    for v in &s.sweeps {
        sweep_section(&mut h, v);
    }
    h
}

fn sweep_section(h: &mut String, v: &SweepView) {
    let st = &v.status;
    let j = &st.jobs;
    let (class, word) = match (v.finished, j.running > 0, j.failed > 0) {
        (true, _, true) => ("failed", "finished with failures"),
        (true, _, false) => ("finished", "finished"),
        (false, true, _) if v.live => ("running", "running"),
        (false, true, _) => (
            "idle",
            "stopped (no run holds the store: its running jobs were interrupted)",
        ),
        (false, false, _) => ("idle", "waiting (nothing running)"),
    };
    let other = if v.current {
        ""
    } else {
        " (another solver version)"
    };
    let _ = writeln!(
        h,
        "<section class=\"sweep\" data-sweep=\"{name}\" data-version=\"{ver}\">\n\
         <h2>{name} <span class=\"small\">[{ver}{other}]</span> \
         <span class=\"state {class}\" data-field=\"state\">{word}</span></h2>\n\
         <progress max=\"{total}\" value=\"{done}\"></progress>",
        name = escape(&st.sweep),
        ver = escape(&st.solver_version),
        total = j.total().max(1),
        done = j.done,
    );
    jobs_table(h, j, st.preps_done, st.preps_total);
    let speed = match speed_line(st.jobs_per_s, (j.pending + j.running) as f64) {
        Some(line) if !v.live && j.pending + j.running > 0 => {
            format!(
                "stopped (the last run's speed: {})",
                line.split(" · ETA").next().unwrap_or(&line)
            )
        }
        Some(line) => line,
        None => "no job finished yet".to_string(),
    };
    let _ = writeln!(
        h,
        "<p>speed <span data-field=\"speed\">{}</span></p>",
        escape(&speed)
    );
    outcomes_line(h, &st.outcomes);
    rounds(h, v);
    failures(h, v);
    arrays(h, v);
    match &v.diagrams {
        Ok(svgs) => {
            for svg in svgs {
                let _ = writeln!(h, "<figure>{svg}</figure>");
            }
        }
        Err(why) => {
            let _ = writeln!(h, "<p class=\"small\">diagrams: {}</p>", escape(&why.0));
        }
    }
    h.push_str("</section>\n");
}

fn jobs_table(h: &mut String, j: &StateCounts, preps_done: i64, preps_total: i64) {
    h.push_str("<table><tr>");
    for k in [
        "done",
        "total",
        "pending",
        "running",
        "failed",
        "preps done",
    ] {
        let _ = write!(h, "<th>{k}</th>");
    }
    h.push_str("</tr><tr>");
    for (k, n) in [
        ("done", j.done),
        ("total", j.total()),
        ("pending", j.pending),
        ("running", j.running),
        ("failed", j.failed),
    ] {
        let _ = write!(h, "<td class=\"num\" data-field=\"{k}\">{n}</td>");
    }
    let _ = writeln!(
        h,
        "<td class=\"num\" data-field=\"preps\">{preps_done} / {preps_total}</td></tr></table>"
    );
}

fn outcomes_line(h: &mut String, o: &Tally) {
    let _ = write!(h, "<p>outcomes: ");
    let shown: Vec<String> = o
        .iter()
        .map(|(e, n)| {
            let (words, field) = (e.words(), e.name());
            format!("{words} <span data-field=\"{field}\">{n}</span>")
        })
        .collect();
    let _ = writeln!(h, "{}</p>", shown.join(" · "));
}

/// The adaptive standings and what refinement added.
fn rounds(h: &mut String, v: &SweepView) {
    if let Some(by) = &v.standings {
        let parts: Vec<String> = by
            .iter()
            .map(|(k, n)| format!("<span data-standing=\"{k}\">{n}</span> {k}"))
            .collect();
        let _ = writeln!(
            h,
            "<p>adaptive rounds, points by standing: {} <span class=\"small\">(open points \
             get another round of replicates; settled and sign points are decided at the \
             sweep's error, exhausted ones reached the budget, verdict ones are decided by \
             their prep)</span></p>",
            parts.join(" · ")
        );
    }
    let refined = v.refined_points.map_or(String::new(), |n| {
        format!(", <span data-field=\"refined\">{n}</span> of them added by refinement")
    });
    let _ = writeln!(
        h,
        "<p>points: <span data-field=\"points\">{}</span>{refined}</p>",
        v.points
    );
    // The refined columns as `cellsweep status` words them (the same function).
    if let Some((rule, columns)) = &v.refinement {
        let (lines, _) = cellsweep_report::status::refinement::lines(columns, rule, "");
        let _ = writeln!(
            h,
            "<p>refine: <span data-field=\"refine\">{}</span></p>",
            escape(&lines.join("; "))
        );
    }
    if !v.box_limited.is_empty() {
        let _ = writeln!(
            h,
            "<p>box-limited: <span data-field=\"box-limited\">{}</span> \
             <span class=\"small\">(SPEC 4.5: the prepped cell leaves its fronts under \
             0.35 Nx<sub>s</sub> apart, so the outcome depends on the pair lattice; squares in \
             the diagrams): {}</span></p>",
            v.box_limited.len(),
            escape(&v.box_limited.join("; "))
        );
    }
}

fn failures(h: &mut String, v: &SweepView) {
    if v.failures.is_empty() {
        return;
    }
    h.push_str(
        "<h3>Failures</h3>\n<table><tr><th>what</th><th>where</th><th>attempts</th>\
         <th>error</th></tr>\n",
    );
    for f in &v.failures {
        let rep = f
            .replicate
            .map_or(String::new(), |r| format!(", replicate {r}"));
        let _ = writeln!(
            h,
            "<tr><td>{} {}</td><td>α = {}, β = {}, L = {}, σ = {}{rep}</td>\
             <td class=\"num\">{}</td><td>{}</td></tr>",
            escape(&f.kind),
            f.id,
            f.alpha,
            f.beta,
            f.L,
            f.sigma,
            f.attempts,
            escape(&f.error)
        );
    }
    h.push_str("</table>\n");
    if let Some(cmd) = &v.retry {
        let _ = writeln!(
            h,
            "<p>retry them: <code data-field=\"retry\">{}</code></p>",
            escape(cmd)
        );
    }
}

fn arrays(h: &mut String, v: &SweepView) {
    if v.arrays.is_empty() {
        return;
    }
    h.push_str(
        "<h3>Slurm arrays</h3>\n<table><tr><th>array</th><th>kind</th><th>tasks</th>\
         <th>jobs</th><th>submitted</th></tr>\n",
    );
    for a in &v.arrays {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>\
             <td>{}</td></tr>",
            escape(&a.label()),
            escape(&a.kind),
            a.tasks,
            a.jobs,
            utc_stamp(a.submitted_at as i64)
        );
    }
    h.push_str("</table>\n");
    let queue = match &v.queue {
        Err(e) => format!("the queue could not be asked ({})", escape(&e.0)),
        Ok(q) if q.is_empty() => "none queued or running".to_string(),
        Ok(q) => q
            .iter()
            .map(|(k, n)| format!("{n} {}", escape(k)))
            .collect::<Vec<_>>()
            .join(", "),
    };
    let _ = writeln!(
        h,
        "<p>tasks in the queue: <span data-field=\"queue\">{queue}</span></p>"
    );
}

/// The diagrams of exported results (`--data`), drawn once: they do not change.
pub fn exports_section(all: &[cellsweep_report::Results]) -> String {
    if all.is_empty() {
        return String::new();
    }
    let mut h = String::from("<h2>Exported results</h2>\n");
    for r in all {
        let _ = writeln!(
            h,
            "<section class=\"export\" data-sweep=\"{name}\"><h3>{name} \
             <span class=\"small\">({} points, from {})</span></h3>",
            r.counts.len(),
            escape(r.provenance.as_ref().map_or("", |p| p.source.as_str())),
            name = escape(&r.name),
        );
        for key in cellsweep_report::figures::diagrams(&r.counts) {
            let svg = cellsweep_report::figures::diagram_of(r, &key, None).to_svg();
            let _ = writeln!(h, "<figure>{svg}</figure>");
        }
        h.push_str("</section>\n");
    }
    h
}
