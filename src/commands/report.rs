//! `cellsweep report`: the paper's results and claims as one self-contained HTML page.

use anyhow::{bail, Context};
use cellsweep_store::Store;

use crate::cli::ReportArgs;

pub fn run(args: ReportArgs) -> anyhow::Result<()> {
    let results = match &args.db {
        Some(db) => {
            let names = Store::open_read(db)?.sweep_names()?;
            if names.is_empty() {
                bail!("no sweeps in {}", db.display());
            }
            names
                .iter()
                .map(|n| cellsweep_report::load::from_store(db, Some(n)))
                .collect::<Result<Vec<_>, _>>()?
        }
        None if args.data.is_empty() => bail!("report needs --db PATH or --data DIR"),
        None => {
            let mut results = Vec::new();
            for dir in &args.data {
                for f in export_files(dir)? {
                    results.push(cellsweep_report::load::from_export(&f)?);
                }
            }
            results
        }
    };
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() as i64);
    let mut variants = Vec::new();
    for dir in &args.variants {
        for f in export_files(dir)? {
            variants.push(cellsweep_report::load::from_export(&f)?);
        }
    }
    let html =
        cellsweep_report::render(&results, &variants, &cellsweep_report::html::utc_stamp(now));
    let out = &args.out;
    crate::output::replace_file(out, |w| Ok(std::io::Write::write_all(w, html.as_bytes())?))?;
    println!("wrote {} ({})", out.display(), summary(&results));
    Ok(())
}

/// What a report was made of: "2 result sets of 1 sweep: a (2 sets)", each sweep named once.
fn summary(results: &[cellsweep_report::Results]) -> String {
    let mut names: Vec<(&str, usize)> = Vec::new();
    for r in results {
        match names.iter_mut().find(|(n, _)| *n == r.name) {
            Some((_, k)) => *k += 1,
            None => names.push((&r.name, 1)),
        }
    }
    let plural =
        |k: usize, one: &str, many: &str| format!("{k} {}", if k == 1 { one } else { many });
    let list: Vec<String> = names
        .iter()
        .map(|&(n, k)| {
            if k == 1 {
                n.to_string()
            } else {
                format!("{n} ({k} sets)")
            }
        })
        .collect();
    format!(
        "{} of {}: {}",
        plural(results.len(), "result set", "result sets"),
        plural(names.len(), "sweep", "sweeps"),
        list.join(", ")
    )
}

/// The export files a `--data` path names: the file itself, or every *.csv of a folder, sorted
/// (an error if it has none).
pub fn export_files(dir: &std::path::Path) -> anyhow::Result<Vec<std::path::PathBuf>> {
    if dir.is_file() {
        return Ok(vec![dir.to_path_buf()]);
    }
    let mut files: Vec<std::path::PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("cannot read the folder {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "csv") && p.is_file())
        .collect();
    files.sort();
    if files.is_empty() {
        bail!("{}: no export files (*.csv) in this folder", dir.display());
    }
    Ok(files)
}
