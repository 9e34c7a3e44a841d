//! Missing and corrupt databases, and malformed sweep files.

use crate::{cellsweep, workdir, write_sweep};

#[test]
fn missing_and_corrupt_databases_get_a_clear_error_and_are_never_overwritten() {
    let dir = workdir("db");
    let missing = dir.join("missing.sqlite");
    let out = cellsweep(&["status", "--db", missing.to_str().unwrap()], &[]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no database at") && err.trim_end().lines().count() == 1,
        "{err}"
    );
    assert!(!missing.exists());

    let corrupt = dir.join("corrupt.sqlite");
    let bytes: Vec<u8> = (0..4096u32).map(|i| (i * 7 + 3) as u8).collect();
    std::fs::write(&corrupt, &bytes).unwrap();
    let sweep = write_sweep(&dir, "db", 1, 2.0);
    for args in [
        vec!["status", "--db", corrupt.to_str().unwrap()],
        vec![
            "run",
            sweep.to_str().unwrap(),
            "--db",
            corrupt.to_str().unwrap(),
        ],
    ] {
        let out = cellsweep(&args, &[]);
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(
            err.contains("corrupt") && err.contains("left untouched"),
            "{err}"
        );
        assert_eq!(
            std::fs::read(&corrupt).unwrap(),
            bytes,
            "the file must not change"
        );
    }
}

#[test]
fn a_malformed_sweep_file_is_one_line_naming_file_and_key() {
    let dir = workdir("bad");
    let sweep = write_sweep(&dir, "bad", 1, 2.0);
    std::fs::write(
        &sweep,
        std::fs::read_to_string(&sweep)
            .unwrap()
            .replace("L = [48]", "L = [47]"),
    )
    .unwrap();
    let db = dir.join("r.sqlite");
    let out = cellsweep(
        &["run", sweep.to_str().unwrap(), "--db", db.to_str().unwrap()],
        &[],
    );
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("bad.toml: grid.L: 47 is odd"), "{err}");
    assert!(!db.exists(), "nothing is created for a bad sweep");
}
