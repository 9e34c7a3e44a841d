//! Faults a worker fakes on request, for the test suite to exercise both engines with real
//! processes. Compiled only with the `fault-injection` feature, which the workspace's tests
//! enable (the root package's dev-dependency): a release build of `cellsweep` has none of it.
//!
//! Environment variables: `CELLSWEEP_TEST_CRASH_TASK=ID` aborts the process on collision task ID
//! while its attempt number is at most `CELLSWEEP_TEST_CRASH_ATTEMPTS` (default 1);
//! `CELLSWEEP_TEST_HANG_TASK=ID` makes the worker hang on collision task ID (first attempt
//! only); `CELLSWEEP_TEST_FAIL_TASK=ID:N` (a collision) or `CELLSWEEP_TEST_FAIL_PREP=ID:N` (a
//! prep) answers that task with a failure while its attempt number is at most N: a fault that
//! both engines record the same way, where a crash is seen only by the local one.

use crate::wire::Request;

fn env_i64(name: &str) -> Option<i64> {
    std::env::var(name).ok()?.trim().parse().ok()
}

/// A crash or hang asked for this request, if any (`CELLSWEEP_TEST_CRASH_TASK`,
/// `CELLSWEEP_TEST_HANG_TASK`).
pub fn crash_or_hang(req: &Request) {
    if let Request::Collide { task, attempt, .. } = req {
        if env_i64("CELLSWEEP_TEST_CRASH_TASK") == Some(*task) {
            let upto = env_i64("CELLSWEEP_TEST_CRASH_ATTEMPTS").unwrap_or(1);
            if (*attempt as i64) <= upto {
                eprintln!("test hook: crashing on task {task}, attempt {attempt}");
                std::process::abort();
            }
        }
        if env_i64("CELLSWEEP_TEST_HANG_TASK") == Some(*task) && *attempt == 1 {
            loop {
                std::thread::sleep(std::time::Duration::from_secs(3600));
            }
        }
    }
}

/// The injected failure of `CELLSWEEP_TEST_FAIL_TASK` / `CELLSWEEP_TEST_FAIL_PREP`, if it
/// applies to this request.
pub fn failure(req: &Request) -> Option<String> {
    let (var, task, attempt) = match req {
        Request::Prep { task, attempt, .. } => ("CELLSWEEP_TEST_FAIL_PREP", task, attempt),
        Request::Collide { task, attempt, .. } => ("CELLSWEEP_TEST_FAIL_TASK", task, attempt),
    };
    let value = std::env::var(var).ok()?;
    let (id, upto) = value.split_once(':')?;
    let fails =
        id.trim().parse() == Ok(*task) && upto.trim().parse().is_ok_and(|n: u32| *attempt <= n);
    fails.then(|| format!("test hook: injected failure of task {task}, attempt {attempt}"))
}
