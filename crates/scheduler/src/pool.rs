//! Worker processes: each is a child process of the same binary (`cellsweep worker`) driven by
//! one tokio task that writes requests, reads responses with a timeout, and replaces the process
//! when it crashes, hangs or talks nonsense.

use std::collections::VecDeque;
use std::path::PathBuf;
use std::process::Stdio;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::io::{AsyncBufReadExt, AsyncWriteExt, BufReader, Lines};
use tokio::process::{Child, ChildStdin, ChildStdout, Command};
use tokio::sync::mpsc;

use crate::error::CallError;
use crate::wire::{Request, Response};

/// How to start a worker process.
#[derive(Debug, Clone)]
pub struct WorkerCommand {
    pub exe: PathBuf,
    pub args: Vec<String>,
}

/// What a worker task reports to the coordinator.
#[derive(Debug)]
pub enum Event {
    /// The worker answered its current request.
    Reply { worker: usize, response: Response },
    /// The worker's process was lost on its current request (crash, hang, bad reply); a fresh
    /// process has taken its place (with an empty prep cache).
    Lost { worker: usize, error: CallError },
    /// No process could be started for this worker; it is gone.
    Dead { worker: usize, error: String },
}

struct Process {
    child: Child,
    stdin: ChildStdin,
    stdout: Lines<BufReader<ChildStdout>>,
    stderr_tail: Arc<Mutex<VecDeque<String>>>,
    stderr_task: tokio::task::JoinHandle<()>,
}

impl Process {
    fn spawn(cmd: &WorkerCommand) -> std::io::Result<Process> {
        let mut command = Command::new(&cmd.exe);
        command
            .args(&cmd.args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .kill_on_drop(true);
        #[cfg(unix)]
        {
            // Own process group: a Ctrl-C at the terminal reaches the coordinator only, which
            // then stops its workers itself.
            command.process_group(0);
        }
        #[cfg(target_os = "linux")]
        unsafe {
            // SAFETY: prctl is async-signal-safe; it only sets a flag of the child. The worker
            // dies with the coordinator even if the coordinator is SIGKILLed.
            command.pre_exec(|| {
                libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL);
                Ok(())
            });
        }
        let mut child = command.spawn()?;
        // All three were piped by the command above, so each take() finds its pipe.
        let stdin = child.stdin.take().expect("piped stdin");
        let stdout = child.stdout.take().expect("piped stdout"); // piped above
        let stdout = BufReader::new(stdout).lines();
        let stderr = child.stderr.take().expect("piped stderr"); // piped above
        let stderr_tail = Arc::new(Mutex::new(VecDeque::new()));
        let tail = stderr_tail.clone();
        let stderr_task = tokio::spawn(async move {
            let mut lines = BufReader::new(stderr).lines();
            while let Ok(Some(line)) = lines.next_line().await {
                let mut t = tail.lock().unwrap_or_else(|e| e.into_inner());
                if t.len() == 8 {
                    t.pop_front();
                }
                t.push_back(line);
            }
        });
        Ok(Process {
            child,
            stdin,
            stdout,
            stderr_tail,
            stderr_task,
        })
    }

    /// Send one request and wait for its response.
    async fn call(&mut self, req: &Request, timeout: Duration) -> Result<Response, CallError> {
        let mut line = serde_json::to_string(req).map_err(CallError::Encode)?;
        line.push('\n');
        let sent = async {
            self.stdin.write_all(line.as_bytes()).await?;
            self.stdin.flush().await
        }
        .await;
        if sent.is_err() {
            return Err(CallError::Exited(self.exit_message().await));
        }
        match tokio::time::timeout(timeout, self.stdout.next_line()).await {
            Err(_) => {
                let _ = self.child.start_kill();
                Err(CallError::TimedOut(timeout.as_secs_f64()))
            }
            Ok(Ok(Some(reply))) => match serde_json::from_str::<Response>(&reply) {
                Ok(r) if r.task() == req.task() => Ok(r),
                Ok(r) => Err(CallError::WrongTask {
                    got: r.task(),
                    sent: req.task(),
                }),
                Err(e) => Err(CallError::Malformed(e)),
            },
            Ok(_) => Err(CallError::Exited(self.exit_message().await)),
        }
    }

    /// How the process ended, with the last line it wrote to stderr.
    async fn exit_message(&mut self) -> String {
        let status = match tokio::time::timeout(Duration::from_secs(5), self.child.wait()).await {
            Ok(Ok(s)) => describe_status(s),
            _ => {
                let _ = self.child.start_kill();
                "stopped answering".to_string()
            }
        };
        let _ = tokio::time::timeout(Duration::from_millis(500), &mut self.stderr_task).await;
        let tail = self.stderr_tail.lock().unwrap_or_else(|e| e.into_inner());
        match tail.back() {
            Some(last) => format!("worker {status}: {last}"),
            None => format!("worker {status}"),
        }
    }

    async fn stop(mut self) {
        let _ = self.child.start_kill();
        let _ = self.child.wait().await;
        self.stderr_task.abort();
    }
}

fn describe_status(s: std::process::ExitStatus) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(sig) = s.signal() {
            return format!("crashed (signal {sig})");
        }
    }
    match s.code() {
        Some(c) => format!("exited with status {c}"),
        None => "exited".to_string(),
    }
}

/// Run worker `index`: serve requests from `requests` until it closes or `cancel` turns true
/// (then the process is killed at once, whatever it is doing).
pub async fn worker_task(
    index: usize,
    cmd: WorkerCommand,
    timeout: Duration,
    mut requests: mpsc::Receiver<Request>,
    events: mpsc::UnboundedSender<Event>,
    mut cancel: tokio::sync::watch::Receiver<bool>,
) {
    let spawn = |events: &mpsc::UnboundedSender<Event>| match Process::spawn(&cmd) {
        Ok(p) => Some(p),
        Err(e) => {
            let _ = events.send(Event::Dead {
                worker: index,
                error: format!("cannot start {}: {e}", cmd.exe.display()),
            });
            None
        }
    };
    let Some(mut proc) = spawn(&events) else {
        return;
    };
    while let Some(req) = requests.recv().await {
        // A cancelled run does not wait for the answer: the process is killed below.
        let answer = tokio::select! {
            a = proc.call(&req, timeout) => a,
            _ = cancel.wait_for(|&c| c) => break,
        };
        match answer {
            Ok(response) => {
                let _ = events.send(Event::Reply {
                    worker: index,
                    response,
                });
            }
            Err(error) => {
                proc.stop().await;
                let _ = events.send(Event::Lost {
                    worker: index,
                    error,
                });
                match spawn(&events) {
                    Some(p) => proc = p,
                    None => return,
                }
            }
        }
    }
    proc.stop().await;
}
