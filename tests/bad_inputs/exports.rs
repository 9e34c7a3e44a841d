//! Exports read with `--data` that are wrong in one way each.

use crate::common::{cellsweep_in, workdir};
use crate::{all_ok, check};

#[test]
fn bad_exports_read_with_data_get_one_line_naming_the_file() {
    let dir = workdir("data");
    let export = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/paper/adaptive-L90-sigma5.csv"
    ))
    .unwrap();
    let lines: Vec<&str> = export.lines().collect();
    let head = lines[..3].join("\n");
    let row = lines[3];
    let cases: Vec<(String, &str)> = vec![
        ("alpha,beta\n0.1,10\n".into(), "not a cellsweep export"),
        (format!("{head}\n{row}\n{row}\n"), "appears twice"),
        (
            format!(
                "{head}\n{}\n",
                row.replacen(",train,", ",sideways,", 1)
                    .replacen(",walk_past,", ",sideways,", 1)
            ),
            "is not a result",
        ),
        (
            format!(
                "{head}\n{}\n",
                row.replacen("adaptive-L90-sigma5,0.1,", "adaptive-L90-sigma5,0.7,", 1)
            ),
            "is not a point",
        ),
        (
            format!("{head}\n{}\n", row.replacen(",0,", ",999,", 1)),
            "beyond",
        ),
        (format!("{}\n# spec {{\n", lines[0]), "line 2"),
    ];
    let mut failures = Vec::new();
    for (k, (text, what)) in cases.iter().enumerate() {
        let file = format!("d{k}.csv");
        std::fs::write(dir.join(&file), text).unwrap();
        for cmd in ["table", "fit", "plot"] {
            let mut args = vec![cmd, "--data", file.as_str()];
            if cmd == "plot" {
                args.extend(["--out", "p"]);
            }
            let out = cellsweep_in(&dir, &args);
            for need in [file.as_str(), what] {
                if let Err(why) = check(&out, need, &format!("{cmd} data case {k}")) {
                    failures.push(why);
                }
            }
        }
    }
    all_ok(failures);
}
