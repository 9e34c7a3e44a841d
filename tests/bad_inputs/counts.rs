//! Counts files (`--counts`) that are wrong in one way each, through `table`, `fit` and `plot`.

use crate::common::{cellsweep_in, workdir};
use crate::refused;

const HEADER: &str = "alpha,beta,L,sigma,n_train,n_walk,n_reversal,n_undetermined\n";

/// (counts file body after the header, or a whole file if it starts with '!', what to name).
const COUNTS: &[(&str, &str)] = &[
    ("1e308,10,90,5,1,2,0,0\n0.12,10,90,5,2,1,0,0\n", "alpha"),
    ("0.1,10,90,5,18446744073709551615,1,0,0\n", "n_train"),
    ("0.1,10,90,5,1000000001,1,0,0\n", "n_train"),
    ("0.1,10,90,5,-1,1,0,0\n", "n_train"),
    ("0.1,10,90,5,1.5,1,0,0\n", "n_train"),
    ("0.1,10,90,5,1,2,0,0\n0.1,10,90,5,2,1,0,0\n", "appears twice"),
    ("nan,10,90,5,1,2,0,0\n", "alpha"),
    ("inf,10,90,5,1,2,0,0\n", "alpha"),
    ("0.1,10,90.5,5,1,2,0,0\n", "L"),
    ("0.1,10,1e10,5,1,2,0,0\n", "L"),
    ("0.1,10,90,-5,1,2,0,0\n", "sigma"),
    ("0.1,x,90,5,1,2,0,0\n", "beta"),
    ("0.1,10,90,5,1,2,0\n", "n_undetermined"),
    ("", "no data rows"),
    ("!alpha,beta,L,sigma\n0.1,10,90,5\n", "missing column \"n_train\""),
    ("!", "empty file"),
    ("!\u{feff}alpha,beta,L,sigma,n_train,n_walk,n_reversal,n_undetermined,label\n0.1,10,90,5,1,2,0,0,sideways\n", "unknown label"),
    ("!\"alpha,beta,L,sigma,n_train,n_walk,n_reversal,n_undetermined\n", "line"),
];

#[test]
fn bad_counts_files_get_one_line_naming_the_problem() {
    let dir = workdir("counts");
    for (k, (body, what)) in COUNTS.iter().enumerate() {
        let text = match body.strip_prefix('!') {
            Some(whole) => whole.to_string(),
            None => format!("{HEADER}{body}"),
        };
        let file = format!("c{k}.csv");
        std::fs::write(dir.join(&file), text).unwrap();
        for cmd in ["table", "fit", "plot"] {
            let mut args = vec![cmd, "--counts", file.as_str()];
            if cmd == "plot" {
                args.extend(["--out", "plots"]);
            }
            let out = cellsweep_in(&dir, &args);
            refused(&out, what, &format!("{cmd} counts case {k}"));
            refused(&out, &file, &format!("{cmd} counts case {k}"));
        }
    }
    // A byte-order mark and quoted cells are fine.
    std::fs::write(
        dir.join("ok.csv"),
        format!("\u{feff}{HEADER}\"0.1\",10,90,5,1,2,0,0\n0.12,10,90,5,2,1,0,0\n"),
    )
    .unwrap();
    let out = cellsweep_in(&dir, &["table", "--counts", "ok.csv", "--format", "json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    println!(
        "{} counts-file cases, each through table, fit and plot",
        COUNTS.len()
    );
}
