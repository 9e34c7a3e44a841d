//! `compare` pairing the replicates of two sweeps by seed.

use crate::{cellsweep, workdir, write_sweep};

#[test]
fn compare_pairs_the_replicates_of_two_sweeps_by_seed() {
    let dir = workdir("compare");
    let db = dir.join("r.sqlite");
    let db_s = db.to_str().unwrap();
    // "a" and "b" are the same sweep under two names (same seed: the same preps and noise,
    // replicate by replicate); "c" differs only in its seed.
    let a = write_sweep(&dir, "a", 2, 2.0);
    let b = write_sweep(&dir, "b", 2, 2.0);
    let c = write_sweep(&dir, "c", 2, 2.0);
    let text = std::fs::read_to_string(&c).unwrap();
    std::fs::write(&c, text.replace("seed = 5", "seed = 6")).unwrap();
    for sweep in [&a, &b, &c] {
        let out = cellsweep(&["run", sweep.to_str().unwrap(), "--db", db_s], &[]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let json = |x: &str, y: &str| -> serde_json::Value {
        let out = cellsweep(&["compare", x, y, "--db", db_s, "--format", "json"], &[]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).unwrap()
    };

    // Identical computations: every replicate matched, every pair alike to the bit (decision
    // times too, where there are any), nothing to test.
    let ab = json("a", "b");
    assert_eq!(ab["points"].as_array().unwrap().len(), 4);
    assert_eq!(
        (ab["matched"].as_u64(), ab["alike"].as_u64()),
        (Some(8), Some(8))
    );
    assert_eq!(ab["labels_differ"], 0);
    assert_eq!(ab["p_value_paired"], 1.0);
    for p in ab["points"].as_array().unwrap() {
        assert_eq!(p["test"], "paired");
        assert_eq!(p["counts_a"], p["counts_b"]);
        assert!(p["decision_shift_max"].is_null() || p["decision_shift_max"] == 0.0);
    }
    assert_eq!(ab["a"]["sweep"], "a");

    // Another seed: the same points, but no replicate pairs with its namesake, so each point's
    // counts are compared as independent samples.
    let ac = json("a", "c");
    assert_eq!(ac["matched"], 0);
    assert!(ac["p_value_paired"].is_null());
    for p in ac["points"].as_array().unwrap() {
        assert_eq!(p["test"], "independent");
        let p_value = p["p_value"].as_f64().unwrap();
        assert!(p_value > 0.0 && p_value <= 1.0);
    }

    let text = cellsweep(&["compare", "a", "b", "--db", db_s], &[]);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(text.contains("8 of 8 matched pairs end alike"), "{text}");
    assert!(text.contains("labels differ at 0 of 4 points"), "{text}");

    // A version with no results: one line that names the versions there are.
    let out = cellsweep(
        &[
            "compare",
            "a",
            "b",
            "--db",
            db_s,
            "--version-a",
            "cellsweep-solver 0.0.1",
        ],
        &[],
    );
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("has no results under") && err.contains("cellsweep-solver"),
        "{err}"
    );
}
