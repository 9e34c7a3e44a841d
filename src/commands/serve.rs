//! `cellsweep serve`: the live page of a store (crates/serve), with the diagrams of exported
//! results below it.

use std::time::Duration;

use anyhow::bail;
use cellsweep_serve::{page, serve, ServeOptions};

use crate::cli::ServeArgs;

pub fn run(args: ServeArgs) -> anyhow::Result<()> {
    if !(args.poll.is_finite() && (0.2..=3600.0).contains(&args.poll)) {
        bail!("--poll {}: give seconds between 0.2 and 3600", args.poll);
    }
    if args.db.db.is_dir() {
        bail!(
            "--db {}: a directory, not a store (give the store's file, e.g. {}/cellsweep.sqlite)",
            args.db.db.display(),
            args.db.db.display()
        );
    }
    let mut exports = Vec::new();
    for path in &args.data {
        for f in super::report::export_files(path)? {
            exports.push(cellsweep_report::load::from_export(&f)?);
        }
    }
    if !args.bind.is_loopback() {
        eprintln!(
            "warning: listening on {}: the page has no authentication, and anyone who can \
             reach this address can read it (an ssh tunnel to 127.0.0.1 is safer)",
            args.bind
        );
    }
    let opts = ServeOptions {
        db: args.db.db.clone(),
        bind: args.bind,
        port: args.port,
        exports_html: page::exports_section(&exports),
        poll: Duration::from_secs_f64(args.poll),
    };
    serve(opts, |addr| {
        println!(
            "serving {} on http://{addr}/ (read-only; Ctrl-C stops)",
            args.db.db.display()
        );
        use std::io::Write as _;
        let _ = std::io::stdout().flush();
    })?;
    Ok(())
}
