//! A `gyrocompd` run in-process, in a private iceoryx2 domain of its own, for `replay` when no
//! daemon is running (the embedded default): the same `Daemon` type the binary runs, on a thread,
//! stopped like SIGTERM would (answer what arrived, final status, exit).

use std::thread::JoinHandle;

use gyrocomp::config::Config;
use gyrocomp::daemon::{Daemon, DaemonError, RunSummary, Signals};
use gyrocomp::ipc::{IpcDomain, IpcError};

/// How the embedded daemon ended badly.
#[derive(Debug, thiserror::Error)]
pub enum EmbeddedError {
    /// The daemon returned an error (it could not start).
    #[error("embedded gyrocompd: {0}")]
    Daemon(#[from] DaemonError),
    /// The daemon thread panicked or was already joined.
    #[error("embedded gyrocompd thread ended abnormally")]
    Thread,
}

/// A daemon thread and the private domain it serves.
pub struct EmbeddedDaemon {
    domain: IpcDomain,
    signals: Signals,
    thread: Option<JoinHandle<Result<RunSummary, DaemonError>>>,
}

impl EmbeddedDaemon {
    /// Starts a daemon with `config` in a fresh private domain (unique prefix and root path under
    /// the temporary directory). Returns it and `config` pointed at that domain, for the client.
    pub fn start(config: &Config) -> Result<(Self, Config), IpcError> {
        let domain = IpcDomain::unique("replay")?;
        let mut config = config.clone();
        config.ipc.domain_prefix = domain.prefix();
        config.ipc.domain_root = domain.root_path();
        let signals = Signals::new();
        let daemon = Daemon::new(config.clone(), None, signals.clone());
        let thread = std::thread::Builder::new()
            .name("gyrocompd-embedded".into())
            .spawn(move || daemon.run())
            .map_err(|e| IpcError::Setting(format!("cannot start the embedded daemon thread: {e}")))?;
        tracing::info!(domain_prefix = %domain.prefix(), "started an embedded gyrocompd (no daemon was running)");
        Ok((Self { domain, signals, thread: Some(thread) }, config))
    }

    /// Whether the daemon thread has ended (it failed to start, or was stopped).
    pub fn finished(&self) -> bool {
        self.thread.as_ref().is_none_or(JoinHandle::is_finished)
    }

    /// Stops the daemon (as SIGTERM would), waits for it and removes the private domain's
    /// files. Call after the client's ports are dropped.
    pub fn stop(mut self) -> Result<RunSummary, EmbeddedError> {
        self.join()
    }

    fn join(&mut self) -> Result<RunSummary, EmbeddedError> {
        self.signals.request_stop();
        let result = match self.thread.take() {
            Some(t) => match t.join() {
                Ok(run) => run.map_err(EmbeddedError::from),
                Err(_) => Err(EmbeddedError::Thread),
            },
            None => Err(EmbeddedError::Thread),
        };
        if let Err(e) = self.domain.remove_private_files() {
            tracing::warn!(error = %e, "could not remove the embedded daemon's iceoryx2 files");
        }
        result
    }
}

impl Drop for EmbeddedDaemon {
    fn drop(&mut self) {
        if self.thread.is_some() {
            let _ = self.join();
        }
    }
}
