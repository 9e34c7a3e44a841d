//! `cellsweep table`: each (L, sigma) phase diagram as a grid, and every point's counts,
//! fractions with 95% Wilson intervals, and label; as text, CSV or JSON (`report::table`).

use cellsweep_report::{table, text};

use crate::cli::{Format, TableArgs};

pub fn run(args: TableArgs) -> anyhow::Result<()> {
    let loaded = args.select.apply(args.source.load()?)?;
    let counts = &loaded.counts;
    if counts.is_empty() {
        anyhow::bail!("no points in {}", loaded.name);
    }
    // An adaptive sweep's standing of each point.
    let standings = loaded.standings.as_deref();
    let plane = args.plane.plane();
    // A plane is checked whatever the format, so that a bad axis is one line, never ignored.
    let grids = if plane.is_paper() {
        text::grids_text(counts)
    } else {
        text::plane_grids_text(counts, &plane, &loaded.scales)?
    };
    match args.format {
        Format::Text => print!("{}", table::text(&grids, counts, standings)),
        Format::Csv => print!("{}", table::csv(counts, standings)),
        Format::Json => println!(
            "{}",
            serde_json::to_string_pretty(&table::json(counts, standings))?
        ),
    }
    Ok(())
}
