//! The signals that stop a run: Ctrl-C (SIGINT) and SIGTERM.

#[cfg(unix)]
use tokio::signal::unix::{signal, Signal, SignalKind};

/// Listens for Ctrl-C and SIGTERM from the moment it is made: a signal sent after
/// [`Interrupts::listen`] returns is never missed, however late [`Interrupts::next`] is polled.
pub(super) struct Interrupts {
    #[cfg(unix)]
    streams: Vec<Signal>,
}

impl Interrupts {
    pub(super) fn listen() -> Interrupts {
        #[cfg(unix)]
        {
            let streams = [SignalKind::interrupt(), SignalKind::terminate()]
                .into_iter()
                .filter_map(|kind| signal(kind).ok())
                .collect();
            Interrupts { streams }
        }
        #[cfg(not(unix))]
        Interrupts {}
    }

    /// Resolves on the next Ctrl-C or SIGTERM (cancel-safe: a signal is kept until taken).
    pub(super) async fn next(&mut self) {
        #[cfg(unix)]
        {
            if self.streams.is_empty() {
                return std::future::pending().await;
            }
            std::future::poll_fn(|cx| {
                for stream in &mut self.streams {
                    if stream.poll_recv(cx).is_ready() {
                        return std::task::Poll::Ready(());
                    }
                }
                std::task::Poll::Pending
            })
            .await
        }
        #[cfg(not(unix))]
        {
            let _ = tokio::signal::ctrl_c().await;
        }
    }
}
