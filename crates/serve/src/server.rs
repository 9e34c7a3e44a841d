//! The HTTP side: an axum router on a tokio runtime of its own, GET only.
//!
//! - `/`: the page, with the current live fragment in it (it reads without its script);
//! - `/live.js`: the script that polls;
//! - `/api/live?since=N`: `{generation, finished, html}`, or `{generation, finished}` alone
//!   when the page at generation `N` is still current;
//! - `/api/status`: the snapshot as JSON (the numbers of `cellsweep status --json`).
//!
//! SQLite is read on the blocking pool, through one read-only connection behind a mutex, so a
//! slow gathering never stalls the server and many clients cost one gathering.

use std::net::{IpAddr, SocketAddr};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use axum::extract::{Query, State};
use axum::http::{header, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;
use serde::Deserialize;

use crate::page;
use crate::watcher::{Live, Watcher};

/// How `cellsweep serve` was asked to run.
#[derive(Debug, Clone)]
pub struct ServeOptions {
    pub db: PathBuf,
    pub bind: IpAddr,
    /// 0 picks a free port (printed by `on_ready`).
    pub port: u16,
    /// The static part below the live one (the diagrams of `--data`), as HTML.
    pub exports_html: String,
    /// How often the page asks for news, and the least time between two gatherings.
    pub poll: Duration,
}

/// Why the server could not start or stopped.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    #[error("cannot listen on {addr}: {source}")]
    Bind {
        addr: SocketAddr,
        source: std::io::Error,
    },
    #[error("the server stopped: {0}")]
    Io(#[from] std::io::Error),
}

#[derive(Clone)]
struct AppState {
    watcher: Arc<Mutex<Watcher>>,
    db: Arc<String>,
    exports: Arc<String>,
    poll_ms: u64,
}

#[derive(Deserialize)]
struct Since {
    since: Option<u64>,
}

/// Serve until Ctrl-C or SIGTERM; `on_ready` gets the address once it listens.
pub fn serve(opts: ServeOptions, on_ready: impl FnOnce(SocketAddr)) -> Result<(), ServeError> {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .max_blocking_threads(4)
        .enable_all()
        .build()?;
    rt.block_on(async move {
        let addr = SocketAddr::new(opts.bind, opts.port);
        let listener = tokio::net::TcpListener::bind(addr)
            .await
            .map_err(|source| ServeError::Bind { addr, source })?;
        let state = AppState {
            watcher: Arc::new(Mutex::new(Watcher::new(opts.db.clone(), opts.poll / 2))),
            db: Arc::new(opts.db.display().to_string()),
            exports: Arc::new(opts.exports_html),
            poll_ms: opts.poll.as_millis() as u64,
        };
        on_ready(listener.local_addr()?);
        axum::serve(listener, router(state))
            .with_graceful_shutdown(stop_signal())
            .await?;
        Ok(())
    })
}

fn router(state: AppState) -> Router {
    Router::new()
        .route("/", get(index))
        .route("/live.js", get(script))
        .route("/api/live", get(live))
        .route("/api/status", get(status))
        .with_state(state)
}

/// The current view, gathered on the blocking pool.
async fn current(state: &AppState) -> Result<Arc<Live>, Response> {
    let watcher = state.watcher.clone();
    tokio::task::spawn_blocking(move || match watcher.lock() {
        Ok(mut w) => w.current(),
        // A panic while gathering poisons the lock: keep serving with what it holds.
        Err(poisoned) => poisoned.into_inner().current(),
    })
    .await
    .map_err(|e| {
        (
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("gathering failed: {e}"),
        )
            .into_response()
    })
}

/// Headers every answer carries: never cached, and the page may load nothing from elsewhere.
fn answer(content_type: &'static str, body: String) -> Response {
    let mut r = body.into_response();
    let h = r.headers_mut();
    h.insert(header::CONTENT_TYPE, HeaderValue::from_static(content_type));
    h.insert(header::CACHE_CONTROL, HeaderValue::from_static("no-store"));
    h.insert(
        header::X_CONTENT_TYPE_OPTIONS,
        HeaderValue::from_static("nosniff"),
    );
    h.insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static(
            "default-src 'none'; script-src 'self'; connect-src 'self'; \
             style-src 'unsafe-inline'; img-src data:",
        ),
    );
    r
}

async fn index(State(state): State<AppState>) -> Response {
    match current(&state).await {
        Ok(live) => answer(
            "text/html; charset=utf-8",
            page::page(
                &state.db,
                &live.html,
                live.generation,
                &state.exports,
                state.poll_ms,
            ),
        ),
        Err(r) => r,
    }
}

async fn script() -> Response {
    answer("text/javascript; charset=utf-8", page::SCRIPT.to_string())
}

async fn live(State(state): State<AppState>, Query(q): Query<Since>) -> Response {
    match current(&state).await {
        Ok(live) => {
            let mut v = serde_json::json!({
                "generation": live.generation,
                "finished": live.finished,
            });
            if q.since != Some(live.generation) {
                v["html"] = serde_json::Value::String(live.html.clone());
            }
            answer("application/json", v.to_string())
        }
        Err(r) => r,
    }
}

async fn status(State(state): State<AppState>) -> Response {
    match current(&state).await {
        Ok(live) => answer("application/json", live.json.clone()),
        Err(r) => r,
    }
}

/// Ctrl-C or SIGTERM.
async fn stop_signal() {
    let term = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut s) => {
                s.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    tokio::select! {
        _ = tokio::signal::ctrl_c() => {},
        _ = term => {},
    }
}
