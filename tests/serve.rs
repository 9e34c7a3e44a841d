//! `cellsweep serve`: the live page of a store, watched in a real headless browser (Debian's
//! chromium over its DevTools protocol) while a small sweep runs, from before the store exists
//! to the sweep's end.

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::browser::{browser, Page};
use common::{send_signal, workdir};
use serde_json::Value;

/// The real model on small lattices: 4 points x 12 replicates of 20 tau0 collisions, a few
/// seconds of work on one worker.
fn write_sweep(dir: &Path) -> std::path::PathBuf {
    let path = dir.join("live.toml");
    std::fs::write(
        &path,
        "name = \"live\"\nseed = 5\nreplicates = 12\n[grid]\nalpha = [0.1, 0.12]\nbeta = [10]\n\
         L = [48]\nsigma = [5, 0]\n[params]\nR0 = 24\n[protocol]\nsingle_lattice = [96, 96]\n\
         relax_time = 5\nfree_time = 10\ncollide_time = 20\n",
    )
    .unwrap();
    path
}

/// `cellsweep serve` on a free port: the child and its address.
fn start_server(dir: &Path, db: &Path) -> (Child, String) {
    start_server_with(dir, db, &[])
}

/// [`start_server`] with more flags.
fn start_server_with(dir: &Path, db: &Path, more: &[&str]) -> (Child, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_cellsweep"))
        .current_dir(dir)
        .args(["serve", "--port", "0", "--poll", "0.3"])
        .args(more)
        .arg("--db")
        .arg(db)
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let at = line.find("http://").unwrap_or_else(|| panic!("{line}"));
    let url = line[at..].split_whitespace().next().unwrap().to_string();
    (child, url)
}

/// A raw HTTP request to `url` (host:port from it): the status line and the body.
fn request(url: &str, method: &str, path: &str) -> (String, String) {
    let host = url.trim_start_matches("http://").trim_end_matches('/');
    let mut s = TcpStream::connect(host).unwrap();
    write!(
        s,
        "{method} {path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\nContent-Length: 0\r\n\r\n"
    )
    .unwrap();
    let mut text = String::new();
    s.read_to_string(&mut text).unwrap();
    let status = text.lines().next().unwrap_or("").to_string();
    let body = text.split_once("\r\n\r\n").map_or("", |x| x.1).to_string();
    (status, body)
}

/// The text of the page's element `[data-field=NAME]` (None while there is none).
fn field(page: &mut Page, name: &str) -> Option<String> {
    page.eval(&format!(
        "(function () {{ var e = document.querySelector('[data-field={name}]'); \
         return e ? e.textContent : null; }})()"
    ))
    .as_str()
    .map(String::from)
}

fn wait_for(page: &mut Page, what: &str, mut ok: impl FnMut(&mut Page) -> bool) {
    let t = Instant::now();
    while !ok(page) {
        assert!(t.elapsed() < Duration::from_secs(120), "waited for {what}");
        std::thread::sleep(Duration::from_millis(100));
    }
}

#[test]
fn the_live_page_follows_a_running_sweep_to_its_end_in_a_real_browser() {
    let b = browser().unwrap_or_else(|e| panic!("{e}"));
    let dir = workdir("live");
    // A folder whose name is markup and a shell substitution: shown as text, never run.
    let odd = dir.join("d'<b>$(touch x)\"");
    std::fs::create_dir_all(&odd).unwrap();
    let db = odd.join("live.sqlite");
    let sweep = write_sweep(&dir);
    let (mut server, url) = start_server(&dir, &db);

    // GET only; the JSON answers name the store.
    assert!(request(&url, "POST", "/").0.contains("405"));
    assert!(request(&url, "DELETE", "/api/status").0.contains("405"));
    assert!(request(&url, "GET", "/nothing").0.contains("404"));
    let (st, body) = request(&url, "GET", "/api/live?since=0");
    assert!(st.contains("200"), "{st}");
    let v: Value = serde_json::from_str(&body).unwrap();
    assert!(v["html"].as_str().unwrap().contains("no store at"), "{v}");

    // Before the run: the page says there is no store yet.
    let mut page = Page::open(&b, &url, &dir.join("profile"));
    wait_for(&mut page, "the page", |p| {
        p.eval("document.readyState") == "complete"
    });
    wait_for(&mut page, "the missing store's message", |p| {
        field(p, "message").is_some_and(|m| m.contains("no store at"))
    });
    // Set on the page: a reload would lose it.
    page.eval("window.stayed = 42");

    // The run, with its first job failing every attempt (a test hook of the workers).
    let mut run = Command::new(env!("CARGO_BIN_EXE_cellsweep"))
        .current_dir(&dir)
        .arg("run")
        .arg(&sweep)
        .args(["--workers", "1", "--max-attempts", "2", "--db"])
        .arg(&db)
        .env("CELLSWEEP_TEST_FAIL_TASK", "1:99")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut seen: Vec<String> = Vec::new();
    let t = Instant::now();
    let ended = loop {
        if let Some(done) = field(&mut page, "done") {
            if seen.last() != Some(&done) {
                seen.push(done);
            }
        }
        let finished = field(&mut page, "state").is_some_and(|s| s.starts_with("finished"));
        if let Some(status) = run.try_wait().unwrap() {
            if finished {
                break status;
            }
        }
        assert!(
            t.elapsed() < Duration::from_secs(300),
            "the page never said finished; done values seen: {seen:?}"
        );
        std::thread::sleep(Duration::from_millis(150));
    };
    // The failed job makes the run's exit status non-zero; it ended on its own.
    assert!(ended.code().is_some(), "{ended:?}");
    assert!(
        seen.len() >= 3,
        "the page's done count changed too rarely: {seen:?}"
    );
    assert_eq!(page.eval("window.stayed"), 42, "the page reloaded");

    // The final numbers are status's.
    let out = Command::new(env!("CARGO_BIN_EXE_cellsweep"))
        .args(["status", "--json", "--db"])
        .arg(&db)
        .output()
        .unwrap();
    let status: Value = serde_json::from_slice(&out.stdout).unwrap();
    let jobs = &status[0]["jobs"];
    for k in ["done", "pending", "running", "failed"] {
        assert_eq!(
            field(&mut page, k),
            Some(jobs[k].to_string()),
            "{k}: page against status {jobs}"
        );
    }
    assert_eq!(jobs["failed"], 1);
    assert_eq!(jobs["done"], 47);
    assert_eq!(
        field(&mut page, "state").as_deref(),
        Some("finished with failures")
    );
    let undetermined = status[0]["outcomes"]["undetermined"].to_string();
    assert_eq!(field(&mut page, "undetermined"), Some(undetermined));
    // The failure with its error, and the command that retries it.
    let text = page.eval("document.body.textContent").to_string();
    assert!(text.contains("injected failure"), "{text}");
    let retry = field(&mut page, "retry").unwrap();
    assert!(retry.contains("--retry-failed"), "{retry}");
    assert!(
        retry.contains("'\\''<b>$(touch x)\"/live.sqlite'"),
        "{retry}"
    );
    // The store's name is text, not markup; nothing ran.
    let shown = page.eval("document.querySelector('code').textContent");
    assert_eq!(shown.as_str(), Some(db.to_str().unwrap()));
    assert_eq!(page.eval("document.querySelectorAll('b').length"), 0);
    assert!(!dir.join("x").exists() && !odd.join("x").exists());
    // The diagram is drawn, a tooltip per point with its counts and Wilson intervals.
    let tips = page.eval(
        "Array.from(document.querySelectorAll('#live svg title')).map(t => t.textContent).join('\\n')",
    );
    assert!(
        tips.as_str().unwrap().contains("95% Wilson intervals"),
        "{tips}"
    );
    // A last look for anything the page complained about.
    page.eval("1");
    assert!(page.problems.is_empty(), "{:#?}", page.problems);

    send_signal(&server, libc::SIGINT);
    let code = server.wait().unwrap();
    assert!(code.success(), "serve ended with {code:?}");
}

#[test]
fn serve_refuses_bad_flags_in_one_line() {
    let dir = workdir("flags");
    for (args, says) in [
        (vec!["--poll", "nan"], "--poll"),
        (vec!["--poll", "0"], "--poll"),
        (vec!["--bind", "not-an-address"], "--bind"),
        (vec!["--data", "/nonexistent/folder"], "/nonexistent/folder"),
        (vec!["--db", "."], "a directory, not a store"),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_cellsweep"))
            .current_dir(&dir)
            .arg("serve")
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
}

/// `--bind localhost` is the loopback address, as a user would write it (issue 50, 6).
#[test]
fn serve_binds_localhost_as_the_loopback() {
    let dir = workdir("localhost");
    // (A store not made yet: the page waits for it.)
    let db = dir.join("s.sqlite");
    let (mut child, url) = start_server_with(&dir, &db, &["--bind", "localhost"]);
    let _ = child.kill();
    let _ = child.wait();
    assert!(url.starts_with("http://127.0.0.1:"), "{url}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A store replaced under a running `serve` (its files removed, another sweep run into the
/// same path) is shown as the new store, not the deleted one (issue 50, 5).
#[test]
fn serve_follows_a_store_replaced_at_its_path() {
    let dir = workdir("replaced");
    let db = dir.join("s.sqlite");
    common::write_sweep(&dir, "first", 1, "");
    common::write_sweep(&dir, "second", 1, "");
    let run = |name: &str| {
        let out = common::cellsweep_in(&dir, &["run", &format!("{name}.toml"), "--db", "s.sqlite"]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    run("first");
    let (mut child, url) = start_server(&dir, &db);
    let shows = |name: &str| {
        let t0 = Instant::now();
        loop {
            let (_, body) = request(&url, "GET", "/api/status");
            if body.contains(&format!("\"{name}\"")) {
                return body;
            }
            assert!(
                t0.elapsed() < Duration::from_secs(30),
                "never showed {name}: {body}"
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    };
    shows("first");
    for tail in ["", "-wal", "-shm"] {
        let _ = std::fs::remove_file(dir.join(format!("s.sqlite{tail}")));
    }
    run("second");
    let body = shows("second");
    let _ = child.kill();
    let _ = child.wait();
    assert!(!body.contains("\"first\""), "{body}");
}

/// The live page counts and lists box-limited points as `status` does (issue 48, 1).
#[test]
fn serve_lists_the_box_limited_points() {
    let dir = workdir("box");
    std::fs::write(dir.join("bx.toml"), common::BOX_SWEEP).unwrap();
    let out = common::cellsweep_in(&dir, &["run", "bx.toml", "--db", "b.sqlite"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (mut child, url) = start_server(&dir, &dir.join("b.sqlite"));
    let (_, json) = request(&url, "GET", "/api/status");
    let (_, page) = request(&url, "GET", "/");
    let _ = child.kill();
    let _ = child.wait();
    let v: Value = serde_json::from_str(&json).unwrap();
    assert_eq!(
        v["sweeps"][0]["box_limited"],
        serde_json::json!(["alpha = 0.1, beta = 10, L = 48, sigma = 5"]),
        "{json}"
    );
    assert!(page.contains("data-field=\"box-limited\">1<"), "{page}");
}
