//! When the cluster misbehaves (issue 51): tasks that die as a whole reach the ledger, a queue
//! that does not answer is not an empty one, the watch waits out a flaky controller, and a
//! submission is recorded before it can be lost. A real time limit runs on the local Slurm; the
//! faults that cannot be made on demand there come from stand-ins for sbatch and squeue.

use crate::*;

/// Stand-ins for sbatch, squeue, scontrol and sacct, steered by files in their folder:
/// - sbatch queues the script (`queue`: one `ID SCRIPT` line per array) and prints its id; it
///   fails while `sbatch-fail` holds a number above 0 (counting it down), and with
///   `sbatch-kill-parent` present it kills its caller after printing the id (once: a stop
///   between sbatch and the store).
/// - squeue, by the word in `mode`: `hold` lists every queued task as PENDING; `run` (the
///   default) runs each queued array's tasks to their end first (a collide task as
///   `timeout` says: with `timeout` present it writes slurmstepd's time-limit line into the
///   task's log instead of running it) and then answers that nothing is queued; `fail` prints
///   Slurm's socket time-out and exits 1.
/// - sacct answers as a cluster without accounting does.
pub(crate) struct FakeSlurm {
    pub bin: PathBuf,
}

impl FakeSlurm {
    pub fn new(dir: &Path) -> FakeSlurm {
        let bin = dir.join("fake-bin");
        std::fs::create_dir_all(&bin).unwrap();
        let sbatch = r#"d="$(dirname "$0")"
echo "$@" >> "$d/sbatch.log"
n=$(cat "$d/sbatch-fail" 2>/dev/null || echo 0)
if [ "$n" -gt 0 ]; then echo $((n - 1)) > "$d/sbatch-fail"; echo "sbatch: error: Batch job submission failed: Socket timed out on send/recv operation" >&2; exit 1; fi
id=$(( $(wc -l < "$d/sbatch.log") + 1000 ))
echo "$id ${@: -1}" >> "$d/queue"
echo "$id"
if [ -f "$d/sbatch-kill-parent" ]; then rm "$d/sbatch-kill-parent"; kill -9 $PPID; fi"#;
        let squeue = r#"d="$(dirname "$0")"
mode=$(cat "$d/mode" 2>/dev/null || echo run)
if [ "$mode" = fail ]; then echo "slurm_load_jobs error: Socket timed out on send/recv operation" >&2; exit 1; fi
[ -f "$d/queue" ] || exit 0
if [ "$mode" = hold ]; then
  while read -r id script; do
    last=$(sed -n 's/^#SBATCH --array=0-\([0-9]*\).*/\1/p' "$script")
    for i in $(seq 0 "$last"); do echo "$id|PENDING|$script"; done
  done < "$d/queue"
  exit 0
fi
while read -r id script; do
  last=$(sed -n 's/^#SBATCH --array=0-\([0-9]*\).*/\1/p' "$script")
  sub=$(dirname "$script")
  for i in $(seq 0 "$last"); do
    if [ -f "$d/timeout" ] && [ "$(basename "$script")" = collide.sbatch ]; then
      echo "slurmstepd-node: error: *** JOB $id ON node CANCELLED AT 2026-12-07T00:00:00 DUE TO TIME LIMIT ***" > "$sub/logs/collide-$i.out"
    else
      SLURM_ARRAY_TASK_ID=$i bash "$script" > "$sub/logs/$(basename "$script" .sbatch)-$i.out" 2>&1
    fi
  done
done < "$d/queue"
rm "$d/queue""#;
        for (name, body) in [
            ("sbatch", sbatch),
            ("squeue", squeue),
            ("scontrol", "echo 'MaxArraySize            = 1000'"),
            (
                "sacct",
                "echo 'Slurm accounting storage is disabled' >&2; exit 1",
            ),
        ] {
            let path = bin.join(name);
            std::fs::write(&path, format!("#!/bin/bash\n{body}\n")).unwrap();
            Command::new("chmod").arg("+x").arg(&path).status().unwrap();
        }
        FakeSlurm { bin }
    }

    pub fn set(&self, file: &str, text: &str) {
        std::fs::write(self.bin.join(file), text).unwrap();
    }

    pub fn path(&self) -> String {
        format!(
            "{}:{}",
            self.bin.display(),
            std::env::var("PATH").unwrap_or_default()
        )
    }

    /// The arrays sbatch was asked for.
    pub fn sbatch_calls(&self) -> usize {
        std::fs::read_to_string(self.bin.join("sbatch.log")).map_or(0, |t| t.lines().count())
    }

    pub fn run(&self, dir: &Path, args: &[&str]) -> Output {
        Command::new(env!("CARGO_BIN_EXE_cellsweep"))
            .current_dir(dir)
            .env("PATH", self.path())
            .args(args)
            .output()
            .unwrap()
    }
}

const SUBMIT: [&str; 6] = ["submit", "s.toml", "--backend", "slurm", "--db", "r.sqlite"];

fn text(out: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

#[test]
fn a_sweep_whose_every_collision_task_times_out_ends_failed_after_its_attempts_not_resent_for_ever()
{
    let dir = workdir("all-time-out");
    write_sweep(&dir, "timing-out");
    let slurm = FakeSlurm::new(&dir);
    slurm.set("timeout", "");
    let mut args = SUBMIT.to_vec();
    args.extend(["--watch", "--poll", "0.1", "--time", "00:10:00"]);
    let out = slurm.run(&dir, &args);
    let said = text(&out);
    // One prep array, then the collide array three times (attempts 1, 2, 3), then no more.
    assert_eq!(out.status.code(), Some(1), "{said}");
    assert!(
        said.contains("8 jobs of \"timing-out\" failed after retries"),
        "{said}"
    );
    assert_eq!(slurm.sbatch_calls(), 4, "{said}");
    let db = dir.join("r.sqlite");
    assert_eq!(
        db_count(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'failed' AND attempts = 3 AND error LIKE 'time limit: Slurm stopped the task at its time limit%--time 00:10:00%'"),
        8
    );
    // status --failed shows each with the reason and the command that retries them.
    let status = slurm.run(&dir, &["status", "--db", "r.sqlite", "--failed"]);
    let st = text(&status);
    assert!(st.contains("8 failed"), "{st}");
    assert!(st.contains("after 3 attempts: time limit"), "{st}");
}

#[test]
fn a_task_that_cannot_write_its_run_directory_fails_its_preps_with_the_worker_s_error() {
    let dir = workdir("unwritable");
    write_sweep(&dir, "unwritable");
    let slurm = FakeSlurm::new(&dir);
    slurm.set("mode", "hold");
    assert!(slurm.run(&dir, &SUBMIT).status.success());
    // The run directory's preps folder cannot be written into (here: it is a file).
    let preps = dir.join("cellsweep-runs/unwritable/preps");
    std::fs::remove_dir_all(&preps).unwrap();
    std::fs::write(&preps, "").unwrap();
    slurm.set("mode", "run");
    let c = slurm.run(&dir, &["collect", "--db", "r.sqlite"]);
    let said = text(&c);
    assert!(c.status.success(), "{said}");
    assert!(said.contains("2 jobs or preps ended without a result (the worker failed): a failed attempt each; the first: the worker failed:"), "{said}");
    let db = dir.join("r.sqlite");
    assert_eq!(
        db_count(&db, "SELECT COUNT(*) FROM preps WHERE attempts = 1 AND error LIKE 'the worker failed: %preps/%Not a directory%'"),
        2
    );
    // Collecting again counts nothing twice.
    slurm.run(&dir, &["collect", "--db", "r.sqlite"]);
    assert_eq!(db_count(&db, "SELECT SUM(attempts) FROM preps"), 2);
    assert_eq!(db_count(&db, "SELECT SUM(attempts) FROM jobs"), 0);
}

#[test]
fn a_damaged_prep_file_fails_an_attempt_and_is_written_again_by_the_next_submit() {
    let dir = workdir("damaged-prep");
    write_sweep(&dir, "damaged");
    let slurm = FakeSlurm::new(&dir);
    let mut watch = SUBMIT.to_vec();
    watch.extend(["--watch", "--poll", "0.1"]);
    assert!(slurm.run(&dir, &watch).status.success());
    // Grow the sweep, damage a prep file its new jobs need, and let the tasks run.
    let text_of = std::fs::read_to_string(dir.join("s.toml")).unwrap();
    std::fs::write(
        dir.join("s.toml"),
        text_of.replace("replicates = 2", "replicates = 3"),
    )
    .unwrap();
    slurm.set("mode", "hold");
    assert!(slurm.run(&dir, &SUBMIT).status.success());
    let prep = dir.join("cellsweep-runs/damaged/preps/1.json");
    std::fs::write(&prep, "not a prep {").unwrap();
    slurm.set("mode", "run");
    let out = slurm.run(&dir, &watch);
    let said = text(&out);
    assert!(out.status.success(), "{said}");
    let db = dir.join("r.sqlite");
    // The jobs of prep 1 failed one attempt each, naming the file, then ran.
    assert_eq!(
        db_count(
            &db,
            "SELECT COUNT(*) FROM jobs WHERE state = 'done' AND attempts = 1"
        ),
        2,
        "{said}"
    );
    let records: String = std::fs::read_dir(dir.join("cellsweep-runs/damaged"))
        .unwrap()
        .flatten()
        .filter_map(|sub| std::fs::read_dir(sub.path().join("results")).ok())
        .flatten()
        .flatten()
        .map(|f| std::fs::read_to_string(f.path()).unwrap())
        .collect();
    assert_eq!(
        records.matches("cannot read its prep file: ").count(),
        2,
        "{records}"
    );
    assert!(records.contains("1.json"));
    assert_eq!(
        db_count(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'done'"),
        12
    );
    assert!(std::fs::read_to_string(&prep).unwrap().starts_with('{'));
}

#[test]
fn a_silent_queue_is_not_an_empty_one_for_submit_status_run_and_the_watch() {
    let dir = workdir("squeue-fails");
    write_sweep(&dir, "silent");
    let slurm = FakeSlurm::new(&dir);
    slurm.set("mode", "hold");
    assert!(slurm.run(&dir, &SUBMIT).status.success());
    assert_eq!(slurm.sbatch_calls(), 2);
    slurm.set("mode", "fail");
    // submit: nothing sent, one line naming squeue's error.
    let again = slurm.run(&dir, &SUBMIT);
    let err = String::from_utf8_lossy(&again.stderr);
    assert!(!again.status.success());
    assert!(
        err.contains("Socket timed out") && err.contains("nothing was sent"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    // status says the queue could not be asked (not "none queued").
    let st = text(&slurm.run(&dir, &["status", "--db", "r.sqlite"]));
    assert!(st.contains("the queue could not be asked"), "{st}");
    assert!(!st.contains("none queued"), "{st}");
    // A local run refuses to compute what may still be queued.
    let run = slurm.run(&dir, &["run", "s.toml", "--db", "r.sqlite"]);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    assert!(err.contains("--force"), "{err}");
    // The watch waits, saying so, and gives up with one clear line after --give-up-after.
    let mut watch = SUBMIT.to_vec();
    watch.extend(["--watch", "--poll", "0.1", "--give-up-after", "1"]);
    let w = slurm.run(&dir, &watch);
    let err = String::from_utf8_lossy(&w.stderr);
    assert!(!w.status.success());
    assert!(err.contains("trying again in"), "{err}");
    assert!(
        err.lines().last().unwrap().contains("the watch stops"),
        "{err}"
    );
    assert_eq!(slurm.sbatch_calls(), 2, "nothing was sent again");
    assert_eq!(
        db_count(&dir.join("r.sqlite"), "SELECT COUNT(*) FROM results"),
        0
    );
    // Once squeue answers, the watch carries on and every job is done exactly once.
    slurm.set("mode", "run");
    let mut watch = SUBMIT.to_vec();
    watch.extend(["--watch", "--poll", "0.1"]);
    let w = slurm.run(&dir, &watch);
    assert!(w.status.success(), "{}", text(&w));
    assert_each_job_counted_once(&dir.join("r.sqlite"));
    assert_eq!(slurm.sbatch_calls(), 2);
}

#[test]
fn a_local_run_waits_for_queued_arrays_unless_forced() {
    let dir = workdir("run-while-queued");
    write_sweep(&dir, "queued");
    let slurm = FakeSlurm::new(&dir);
    slurm.set("mode", "hold");
    assert!(slurm.run(&dir, &SUBMIT).status.success());
    let run = slurm.run(&dir, &["run", "s.toml", "--db", "r.sqlite"]);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    assert!(err.contains("still queued or running on Slurm"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert_eq!(
        db_count(&dir.join("r.sqlite"), "SELECT COUNT(*) FROM results"),
        0
    );
    let forced = slurm.run(&dir, &["run", "s.toml", "--db", "r.sqlite", "--force"]);
    assert!(forced.status.success(), "{}", text(&forced));
    assert_eq!(
        db_count(&dir.join("r.sqlite"), "SELECT COUNT(*) FROM results"),
        8
    );
}

#[test]
fn the_watch_waits_out_a_failing_sbatch_and_sends_each_job_once() {
    let dir = workdir("sbatch-flaky");
    write_sweep(&dir, "flaky");
    let slurm = FakeSlurm::new(&dir);
    // The collide array's sbatch fails twice (after the prep array went through).
    slurm.set("sbatch-fail", "0");
    let mut watch = SUBMIT.to_vec();
    watch.extend(["--watch", "--poll", "0.1"]);
    std::fs::write(slurm.bin.join("sbatch-fail"), "0").unwrap();
    // Make the second call (the collide array) and the third fail: a wrapper counts calls.
    let real = std::fs::read_to_string(slurm.bin.join("sbatch")).unwrap();
    std::fs::write(
        slurm.bin.join("sbatch"),
        real.replacen(
            "n=$(cat",
            "c=$(wc -l < \"$d/sbatch.log\"); if [ \"$c\" = 2 ]; then echo 2 > \"$d/sbatch-fail\"; fi\nn=$(cat",
            1,
        ),
    )
    .unwrap();
    let out = slurm.run(&dir, &watch);
    let said = text(&out);
    assert!(out.status.success(), "{said}");
    assert_eq!(said.matches("Socket timed out").count(), 2, "{said}");
    assert!(said.contains("trying again in"), "{said}");
    assert_each_job_counted_once(&dir.join("r.sqlite"));
    // No submission directory of a refused sbatch is left behind.
    let subs = std::fs::read_dir(dir.join("cellsweep-runs/flaky"))
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with("sub-"))
        .filter(|e| {
            !e.path().join("prep.sbatch").exists() && !e.path().join("collide.sbatch").exists()
        })
        .count();
    assert_eq!(subs, 0);
}

#[test]
fn an_array_sent_but_not_recorded_is_found_again_and_not_sent_twice() {
    let dir = workdir("kill-after-sbatch");
    write_sweep(&dir, "lost");
    let slurm = FakeSlurm::new(&dir);
    slurm.set("mode", "hold");
    // A stop right after sbatch took the prep array, before the store heard its id.
    slurm.set("sbatch-kill-parent", "");
    let killed = slurm.run(&dir, &SUBMIT);
    assert!(!killed.status.success());
    assert_eq!(slurm.sbatch_calls(), 1);
    let db = dir.join("r.sqlite");
    assert_eq!(
        db_count(
            &db,
            "SELECT COUNT(*) FROM slurm_arrays WHERE slurm_job_id IS NULL"
        ),
        1,
        "recorded before sbatch ran"
    );
    // The next submit finds it in the queue by its script and sends nothing while it runs.
    let again = slurm.run(&dir, &SUBMIT);
    let said = text(&again);
    assert!(!again.status.success(), "{said}");
    assert!(said.contains("found again 1 array"), "{said}");
    assert!(said.contains("still queued or running"), "{said}");
    assert_eq!(slurm.sbatch_calls(), 1);
    assert_eq!(
        db_count(
            &db,
            "SELECT COUNT(*) FROM slurm_arrays WHERE slurm_job_id = '1001'"
        ),
        1
    );
    // Then the watch finishes the sweep with each job once.
    slurm.set("mode", "run");
    let mut watch = SUBMIT.to_vec();
    watch.extend(["--watch", "--poll", "0.1"]);
    let w = slurm.run(&dir, &watch);
    assert!(w.status.success(), "{}", text(&w));
    assert_each_job_counted_once(&db);
    assert_eq!(
        slurm.sbatch_calls(),
        2,
        "the prep array once, the collide array once"
    );
}

#[test]
fn a_refused_submission_leaves_nothing_and_collect_warns_of_odd_result_entries() {
    let dir = workdir("refused");
    write_sweep(&dir, "refused");
    let slurm = FakeSlurm::new(&dir);
    slurm.set("sbatch-fail", "1");
    let out = slurm.run(&dir, &SUBMIT);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("Socket timed out"), "{err}");
    let db = dir.join("r.sqlite");
    assert_eq!(db_count(&db, "SELECT COUNT(*) FROM slurm_arrays"), 0);
    let subs = std::fs::read_dir(dir.join("cellsweep-runs/refused"))
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with("sub-"))
        .count();
    assert_eq!(subs, 0, "no directory of the refused submission");
    // A submission that went through, and a directory where a results file would be.
    slurm.set("mode", "hold");
    assert!(slurm.run(&dir, &SUBMIT).status.success());
    let sub = std::fs::read_dir(dir.join("cellsweep-runs/refused"))
        .unwrap()
        .flatten()
        .find(|e| e.file_name().to_string_lossy().starts_with("sub-"))
        .unwrap()
        .path();
    std::fs::create_dir_all(sub.join("results/collide-7.jsonl")).unwrap();
    let c = slurm.run(&dir, &["collect", "--db", "r.sqlite"]);
    let err = String::from_utf8_lossy(&c.stderr);
    assert!(err.contains("collide-7.jsonl: not a results file"), "{err}");
}

/// A real time limit on the local Slurm: a collision far longer than a one-minute limit. The
/// task is killed by Slurm (its log says so), and its jobs fail an attempt naming the limit.
#[test]
fn a_task_killed_at_its_time_limit_on_slurm_fails_its_jobs_with_the_limit() {
    slurm_up();
    let dir = workdir("time-limit");
    let sweep = write_sweep_of(&dir, "time-limit", 1);
    let text_of = std::fs::read_to_string(&sweep)
        .unwrap()
        .replace("alpha = [0.1, 0.12]", "alpha = [0.1]")
        .replace("sigma = [5, 0]", "sigma = [5]")
        .replace(
            "collide_time = 2",
            "collide_time = 100000\nstop_early = false",
        );
    std::fs::write(&sweep, text_of).unwrap();
    let first = cellsweep(
        &dir,
        &[
            "submit",
            "s.toml",
            "--backend",
            "slurm",
            "--db",
            "r.sqlite",
            "--time",
            "1",
        ],
    );
    assert!(first.status.success(), "{}", text(&first));
    wait_for(&slurm_ids(&first.stdout));
    let again = cellsweep(
        &dir,
        &[
            "submit",
            "s.toml",
            "--backend",
            "slurm",
            "--db",
            "r.sqlite",
            "--time",
            "1",
            "--max-attempts",
            "1",
        ],
    );
    let said = text(&again);
    assert_eq!(again.status.code(), Some(1), "{said}");
    assert!(
        said.contains("ended without a result (time limit)"),
        "{said}"
    );
    assert_eq!(
        db_count(
            &dir.join("r.sqlite"),
            "SELECT COUNT(*) FROM jobs WHERE state = 'failed' AND error LIKE 'time limit:%--time 1%'"
        ),
        1,
        "{said}"
    );
}
