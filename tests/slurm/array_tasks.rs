//! The worker side of Slurm (array tasks, packing, signals) and the watch loop, run by hand
//! with stand-ins for sbatch, squeue and scontrol.

use crate::common;
use crate::*;

/// Stand-ins for sbatch, squeue and scontrol (MaxArraySize = 5), so array tasks can be run by
/// hand: the worker side of Slurm runs, packing and signals, without waiting for a scheduler.
fn fake_slurm(dir: &Path) -> String {
    let bin = dir.join("fake-bin");
    std::fs::create_dir_all(&bin).unwrap();
    for (name, body) in [
        (
            "sbatch",
            "echo \"$@\" >> \"$(dirname \"$0\")/sbatch.log\"; echo $((RANDOM + 1000))",
        ),
        ("squeue", "exit 0"),
        ("scontrol", "echo 'MaxArraySize            = 5'"),
    ] {
        let path = bin.join(name);
        std::fs::write(&path, format!("#!/bin/bash\n{body}\n")).unwrap();
        Command::new("chmod").arg("+x").arg(&path).status().unwrap();
    }
    format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    )
}

#[test]
fn array_tasks_respect_max_array_size_stop_cleanly_on_usr1_and_resume() {
    let dir = workdir("usr1");
    let sweep = write_sweep(&dir, "slurm-usr1");
    let text = std::fs::read_to_string(&sweep)
        .unwrap()
        .replace("collide_time = 2", "collide_time = 16")
        .replace("replicates = 2", "replicates = 3");
    std::fs::write(&sweep, text).unwrap();
    let path = fake_slurm(&dir);
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_cellsweep"))
            .current_dir(&dir)
            .env("PATH", &path)
            .args(args)
            .output()
            .unwrap()
    };

    // 12 jobs at 1 per task would need indices 0..11; MaxArraySize = 5 allows 0..4: packed 3 per task.
    let out = run(&[
        "submit",
        "s.toml",
        "--backend",
        "slurm",
        "--db",
        "r.sqlite",
        "--jobs-per-task",
        "1",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("12 collisions in 4 array tasks (3 per task)"),
        "{stdout}"
    );
    let sub = std::fs::read_dir(dir.join("cellsweep-runs/slurm-usr1"))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .find(|p| p.file_name().unwrap().to_string_lossy().starts_with("sub-"))
        .unwrap();
    let collide_script = std::fs::read_to_string(sub.join("collide.sbatch")).unwrap();
    assert!(
        collide_script.contains("#SBATCH --array=0-3\n"),
        "{collide_script}"
    );
    let log = std::fs::read_to_string(dir.join("fake-bin/sbatch.log")).unwrap();
    assert!(
        log.lines()
            .nth(1)
            .unwrap()
            .contains("--dependency=afterany:"),
        "collisions wait for the preps: {log}"
    );

    let task = |kind: &str, id: usize| {
        Command::new(env!("CARGO_BIN_EXE_cellsweep"))
            .args(["worker", "--slurm", sub.to_str().unwrap(), "--kind", kind])
            .env("SLURM_ARRAY_TASK_ID", id.to_string())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap()
    };
    for k in 0..2 {
        assert!(task("prep", k).wait().unwrap().success());
    }
    // Task 0 holds three jobs. USR1 while the second runs (the task says on stderr when a
    // record starts): it finishes that record, then stops.
    let results = sub.join("results/collide-0.jsonl");
    let mut child = task("collide", 0);
    let mut stderr = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut said = String::new();
    loop {
        let mut line = String::new();
        use std::io::BufRead as _;
        assert!(
            stderr.read_line(&mut line).unwrap() > 0,
            "the task ended: {said}"
        );
        said += &line;
        if line.contains("record 2 of 3 started") {
            break;
        }
    }
    common::send_signal(&child, libc::SIGUSR1);
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut stderr, &mut rest).unwrap();
    assert!(child.wait().unwrap().success());
    assert!(rest.contains("SIGUSR1"), "{said}{rest}");
    assert!(!rest.contains("record 3 of 3"), "{rest}");
    let first = std::fs::read_to_string(&results).unwrap();
    assert_eq!(
        first.lines().count(),
        2,
        "the record in flight completes, the next is not started"
    );
    assert!(first.ends_with('\n'));

    // A task killed mid-write leaves a torn last line. Rerunning the task (as a requeue would)
    // skips the finished records and starts the next on a fresh line, so the torn fragment
    // stays alone (reported by collect) instead of swallowing the new record.
    let mut torn = first.clone().into_bytes();
    torn.extend_from_slice(b"{\"type\":\"collide\",\"task\":");
    std::fs::write(&results, torn).unwrap();
    assert!(task("collide", 0).wait().unwrap().success());
    assert_eq!(
        std::fs::read_to_string(&results).unwrap().lines().count(),
        4
    );
    let c = run(&["collect", "--db", "r.sqlite"]);
    assert!(
        String::from_utf8_lossy(&c.stdout).contains("2 preps and 3 results new"),
        "{}",
        String::from_utf8_lossy(&c.stdout)
    );
    assert!(
        String::from_utf8_lossy(&c.stderr).contains("collide-0.jsonl: line 3: malformed record"),
        "{}",
        String::from_utf8_lossy(&c.stderr)
    );
}

/// Stand-ins for a Slurm whose array tasks finish at the moment the queue is asked about them:
/// sbatch queues the script, and squeue first runs every queued task to its end, then answers
/// that nothing is queued.
fn finishing_slurm(dir: &Path) -> String {
    let bin = dir.join("fake-bin");
    std::fs::create_dir_all(&bin).unwrap();
    for (name, body) in [
        (
            "sbatch",
            "q=\"$(dirname \"$0\")/queue\"; echo \"${@: -1}\" >> \"$q\"; echo \"$@\" >> \"$q.log\"; echo $((RANDOM + 1000))",
        ),
        (
            "squeue",
            "q=\"$(dirname \"$0\")/queue\"; [ -f \"$q\" ] || exit 0\n\
             while read -r script; do\n\
               last=$(sed -n 's/^#SBATCH --array=0-\\([0-9]*\\).*/\\1/p' \"$script\")\n\
               for i in $(seq 0 \"$last\"); do SLURM_ARRAY_TASK_ID=$i bash \"$script\" >/dev/null 2>&1 || exit 1; done\n\
             done < \"$q\"\n\
             rm \"$q\"",
        ),
        ("scontrol", "echo 'MaxArraySize            = 1000'"),
    ] {
        let path = bin.join(name);
        std::fs::write(&path, format!("#!/bin/bash\n{body}\n")).unwrap();
        Command::new("chmod").arg("+x").arg(&path).status().unwrap();
    }
    format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    )
}

#[test]
fn an_array_that_ends_while_submit_watches_is_collected_not_sent_again() {
    let dir = workdir("race");
    write_sweep(&dir, "slurm-race");
    let path = finishing_slurm(&dir);
    let out = Command::new(env!("CARGO_BIN_EXE_cellsweep"))
        .current_dir(&dir)
        .env("PATH", &path)
        .args([
            "submit",
            "s.toml",
            "--backend",
            "slurm",
            "--db",
            "r.sqlite",
            "--watch",
            "--poll",
            "0.1",
        ])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The queue is asked before the run directory is read: the tasks that ended as squeue
    // answered are collected in the same round, and nothing is sent twice.
    assert_eq!(text.matches("submitted").count(), 1, "{text}");
    let sbatch = std::fs::read_to_string(dir.join("fake-bin/queue.log")).unwrap();
    assert_eq!(
        sbatch.lines().count(),
        2,
        "one prep and one collide array: {sbatch}"
    );
    assert_each_job_counted_once(&dir.join("r.sqlite"));
    let records: usize = std::fs::read_dir(dir.join("cellsweep-runs/slurm-race"))
        .unwrap()
        .flatten()
        .filter_map(|sub| std::fs::read_dir(sub.path().join("results")).ok())
        .flatten()
        .flatten()
        .filter(|f| f.file_name().to_string_lossy().starts_with("collide-"))
        .map(|f| std::fs::read_to_string(f.path()).unwrap().lines().count())
        .sum();
    assert_eq!(records, 8, "each collision ran once");
}

#[test]
fn submit_sends_nothing_again_while_the_queue_cannot_be_asked() {
    let dir = workdir("no-squeue");
    write_sweep(&dir, "slurm-no-squeue");
    // Only sbatch and scontrol, in bash builtins: no squeue anywhere on the PATH.
    let bin = dir.join("fake-bin");
    std::fs::create_dir_all(&bin).unwrap();
    for (name, body) in [
        (
            "sbatch",
            "echo \"$@\" >> \"${0%/*}/sbatch.log\"; echo $((RANDOM + 1000))",
        ),
        ("scontrol", "echo 'MaxArraySize            = 1000'"),
    ] {
        let path = bin.join(name);
        std::fs::write(&path, format!("#!/bin/bash\n{body}\n")).unwrap();
        Command::new("chmod").arg("+x").arg(&path).status().unwrap();
    }
    let submit = || {
        Command::new(env!("CARGO_BIN_EXE_cellsweep"))
            .current_dir(&dir)
            .env("PATH", &bin)
            .args(["submit", "s.toml", "--backend", "slurm", "--db", "r.sqlite"])
            .output()
            .unwrap()
    };
    let first = submit();
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let again = submit();
    let err = String::from_utf8_lossy(&again.stderr);
    assert!(!again.status.success(), "{err}");
    assert!(err.contains("squeue could not be run"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    let log = std::fs::read_to_string(bin.join("sbatch.log")).unwrap();
    assert_eq!(log.lines().count(), 2, "nothing sent again: {log}");
}
