//! A corpus of bad inputs through the real binary: sweep files, counts files, flags and stores.
//! Each must exit 1 with one line on stderr naming the file and key (or the flag), never a
//! panic or an abort, and leave an existing store byte for byte as it was.

#[path = "../common/mod.rs"]
mod common;

mod counts;
mod exports;
mod flags;
mod sweep_files;

use std::path::Path;

use common::cellsweep_in;

/// A valid tiny sweep; each case edits it.
pub(crate) const BASE: &str = "name = \"bad\"\nseed = 1\nreplicates = 2\ngeometry = \"two\"\n\
[grid]\nalpha = [0.1]\nbeta = [10]\nL = [48]\nsigma = [5]\n\
[params]\nR0 = 24\n\
[protocol]\nsingle_lattice = [96, 96]\nrelax_time = 5\nfree_time = 10\ncollide_time = 2\n\
[classifier]\nsustain_window = 25\n\
[run]\njob_timeout = 3600\n";

/// A store made by a valid run, and its bytes.
pub(crate) fn store(dir: &Path) -> Vec<u8> {
    std::fs::write(
        dir.join("good.toml"),
        BASE.replace("name = \"bad\"", "name = \"good\""),
    )
    .unwrap();
    let out = cellsweep_in(dir, &["run", "good.toml", "--db", "r.sqlite"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::read(dir.join("r.sqlite")).unwrap()
}

/// One line, exit 1, no panic, naming `what`; else the reason it is not.
pub(crate) fn check(out: &std::process::Output, what: &str, case: &str) -> Result<(), String> {
    let err = String::from_utf8_lossy(&out.stderr);
    if out.status.code() != Some(1) {
        return Err(format!("{case}: exit {:?}: {err}", out.status));
    }
    if err.trim_end().lines().count() != 1 || err.contains("panicked") {
        return Err(format!("{case}: not one clean line: {err}"));
    }
    if !err.contains(what) {
        return Err(format!("{case}: {err:?} does not name {what:?}"));
    }
    Ok(())
}

pub(crate) fn refused(out: &std::process::Output, what: &str, case: &str) {
    if let Err(why) = check(out, what, case) {
        panic!("{why}");
    }
}

/// Every case's failure at once, so that the corpus reads as a list.
pub(crate) fn all_ok(failures: Vec<String>) {
    assert!(
        failures.is_empty(),
        "{} cases failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
