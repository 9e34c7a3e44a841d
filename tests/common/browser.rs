//! The headless browser of the page tests: Debian's chromium (installed by
//! scripts/chromium-local.sh where it is missing), and a small client of its DevTools
//! protocol, so that a test can watch one page change over time without reloading it.

use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::OnceLock;
use std::time::Duration;

use serde_json::{json, Value};
use tungstenite::stream::MaybeTlsStream;
use tungstenite::{Message, WebSocket};

/// The headless browser of this machine: `CELLSWEEP_BROWSER`, or Debian's chromium, which
/// scripts/chromium-local.sh installs where it is missing (as the Slurm tests start their
/// cluster), once per test binary.
pub fn browser() -> Result<PathBuf, String> {
    static BROWSER: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    BROWSER
        .get_or_init(|| {
            let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/chromium-local.sh");
            let out = Command::new("bash")
                .arg(&script)
                .arg("up")
                .output()
                .map_err(|e| format!("cannot run {}: {e}", script.display()))?;
            let path = String::from_utf8_lossy(&out.stdout).trim().to_string();
            if out.status.success() && !path.is_empty() {
                Ok(PathBuf::from(path))
            } else {
                Err(format!(
                    "no headless browser, and scripts/chromium-local.sh could not install one \
                     ({}): install Debian's chromium (apt-get install chromium) or point \
                     CELLSWEEP_BROWSER at a chromium",
                    String::from_utf8_lossy(&out.stderr).trim()
                ))
            }
        })
        .clone()
}

/// One page in a headless chromium, driven over the DevTools protocol. Everything the page
/// reports as a problem (an exception, a console error or warning, a failed load) is kept in
/// `problems`.
pub struct Page {
    ws: WebSocket<MaybeTlsStream<TcpStream>>,
    chromium: Child,
    session: String,
    next_id: u64,
    pub problems: Vec<String>,
}

impl Page {
    /// Open `url` in a fresh headless chromium whose profile lives in `profile`.
    pub fn open(browser: &Path, url: &str, profile: &Path) -> Page {
        let mut chromium = Command::new(browser)
            .args([
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--no-first-run",
                "--remote-debugging-port=0",
                "--window-size=1400,2000",
            ])
            .arg(format!("--user-data-dir={}", profile.display()))
            .arg("about:blank")
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start chromium");
        // Chromium names its DevTools address on stderr; the rest of stderr is drained.
        let mut lines = BufReader::new(chromium.stderr.take().unwrap()).lines();
        let address = loop {
            let line = lines
                .next()
                .expect("chromium ended before naming its DevTools address")
                .unwrap();
            if let Some(at) = line.find("ws://") {
                break line[at..].trim().to_string();
            }
        };
        std::thread::spawn(move || for _ in lines {});
        let (mut ws, _) = tungstenite::connect(address.as_str()).expect("DevTools connection");
        if let MaybeTlsStream::Plain(s) = ws.get_mut() {
            s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
        }
        let mut page = Page {
            ws,
            chromium,
            session: String::new(),
            next_id: 0,
            problems: Vec::new(),
        };
        let target = page.call("Target.createTarget", json!({"url": "about:blank"}));
        let attached = page.call(
            "Target.attachToTarget",
            json!({"targetId": target["targetId"], "flatten": true}),
        );
        page.session = attached["sessionId"].as_str().unwrap().to_string();
        for domain in ["Runtime.enable", "Log.enable", "Page.enable"] {
            page.call(domain, json!({}));
        }
        page.call("Page.navigate", json!({"url": url}));
        page
    }

    /// The value of JavaScript `expression` in the page.
    pub fn eval(&mut self, expression: &str) -> Value {
        let r = self.call(
            "Runtime.evaluate",
            json!({"expression": expression, "returnByValue": true}),
        );
        assert!(r.get("exceptionDetails").is_none(), "{expression}: {r}");
        r["result"]["value"].clone()
    }

    /// Send one command and wait for its answer, keeping the events that arrive meanwhile.
    fn call(&mut self, method: &str, params: Value) -> Value {
        self.next_id += 1;
        let id = self.next_id;
        let mut msg = json!({"id": id, "method": method, "params": params});
        if !self.session.is_empty() {
            msg["sessionId"] = json!(self.session);
        }
        self.ws
            .send(Message::Text(msg.to_string().into()))
            .expect("send to DevTools");
        loop {
            let text = match self.ws.read().expect("read from DevTools") {
                Message::Text(t) => t.to_string(),
                _ => continue,
            };
            let v: Value = serde_json::from_str(&text).unwrap();
            if v["id"] == json!(id) {
                assert!(v.get("error").is_none(), "{method}: {v}");
                return v["result"].clone();
            }
            self.event(&v);
        }
    }

    fn event(&mut self, v: &Value) {
        let p = &v["params"];
        let problem = match v["method"].as_str() {
            Some("Runtime.exceptionThrown") => Some(p["exceptionDetails"].to_string()),
            Some("Runtime.consoleAPICalled")
                if matches!(p["type"].as_str(), Some("error" | "warning" | "assert")) =>
            {
                Some(p["args"].to_string())
            }
            Some("Log.entryAdded")
                if matches!(p["entry"]["level"].as_str(), Some("error" | "warning")) =>
            {
                Some(p["entry"].to_string())
            }
            _ => None,
        };
        self.problems.extend(problem);
    }
}

impl Drop for Page {
    /// Close chromium as a user would (DevTools `Browser.close`), so that it ends its helper
    /// processes before the test's folder is removed: killed outright, they went on writing
    /// the profile after the folder was gone and left it behind. Killed after 10 s regardless.
    fn drop(&mut self) {
        let msg = json!({"id": self.next_id + 1, "method": "Browser.close"});
        let _ = self.ws.send(Message::Text(msg.to_string().into()));
        let deadline = std::time::Instant::now() + Duration::from_secs(10);
        while std::time::Instant::now() < deadline {
            if let Ok(Some(_)) = self.chromium.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let _ = self.chromium.kill();
        let _ = self.chromium.wait();
    }
}
