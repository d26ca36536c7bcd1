//! The daemon loop (start-up is `startup.rs`, the per-sample work `worker.rs`, the
//! start-up errors [`super::errors`]).
//!
//! Start-up: configuration → pipeline and retrainer (`build_pipeline`, shared with the offline
//! driver), warm-started from the model snapshot of `[state] dir` when there is a compatible one
//! ([`super::state`]) → iceoryx2 node (stale resources of dead nodes, e.g. a killed earlier
//! daemon, are cleaned first) and ports (opened or created, so clients may start first) → a
//! `Started` status. After each model swap, every `[state] every_s` seconds and at a clean stop
//! the snapshot writer thread is handed the models and the pipeline state (never blocking the
//! loop). Loop: wait for raw samples (event or spin, `[ipc] wait`), answer
//! each with exactly one `CompSample` of the same `seq` (listeners woken once per burst), publish a
//! `Periodic` status every second and a `ModelSwapped`/`RetrainFailed` status when those counters
//! move. Between samples, SIGHUP reloads the configuration ([`super::reload`]) and SIGTERM/SIGINT
//! end the loop: the samples already waiting are answered, a `Stopping` status is published and
//! [`Daemon::run`] returns.
//!
//! IPC errors while running are logged (rate-limited) and counted, never fatal; only start-up
//! failures (bad configuration, services that cannot be opened) end the daemon with an error.

use std::path::PathBuf;
use std::time::Duration;

use super::errors::DaemonError;
use super::reload;
use super::signals::Signals;
use super::startup::start;
use crate::config::Config;
use crate::ipc::StatusEvent;
use crate::stream::Pipeline;

/// Longest single wait for a raw sample, so that signals are seen promptly.
const POLL: Duration = Duration::from_millis(50);

/// Totals at the end of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RunSummary {
    /// Raw samples received.
    pub samples_in: u64,
    /// Compensated samples published.
    pub samples_out: u64,
    /// Compensated samples that at least one subscriber did not get.
    pub send_failures: u64,
    /// Version of the model in use at the end (0 = none).
    pub model_version: u64,
}

/// The daemon: a configuration (and the file it came from, for reloads) and its signal flags.
#[derive(Debug)]
pub struct Daemon {
    config: Config,
    config_path: Option<PathBuf>,
    signals: Signals,
}

impl Daemon {
    /// A daemon with a validated configuration; `config_path` is re-read on SIGHUP.
    pub fn new(config: Config, config_path: Option<PathBuf>, signals: Signals) -> Self {
        Self { config, config_path, signals }
    }

    /// Starts the services and runs until a stop is requested; see the module documentation.
    pub fn run(mut self) -> Result<RunSummary, DaemonError> {
        let started = start(&self.config)?;
        // Dropped in this order's reverse when `run` returns: the worker (pipeline, node, ports),
        // the raw subscriber, the instance lock, the domain.
        let (_domain, settings, _instance_lock) = (started.domain, started.settings, started.instance_lock);
        let raw = started.raw;
        let mut worker = started.worker;
        worker.report(StatusEvent::Started);

        let mut recv_errors = 0u64;
        while !self.signals.stop_requested() {
            if self.signals.take_reload() {
                self.reload(&mut worker.pipeline);
            }
            match raw.recv_timeout(POLL) {
                Ok(Some(sample)) => {
                    worker.handle(&sample);
                    worker.drain(&raw, settings.subscriber_buffer, &mut recv_errors);
                    worker.notify();
                }
                Ok(None) => {}
                Err(e) => {
                    recv_errors += 1;
                    if recv_errors.is_power_of_two() {
                        tracing::warn!(error = %e, count = recv_errors, "receiving raw samples failed");
                    }
                    std::thread::sleep(POLL);
                }
            }
            worker.tick();
        }
        // Answer what has already arrived (at most one buffer: a client may still be sending).
        let before = worker.counters.samples_in;
        worker.drain(&raw, settings.subscriber_buffer, &mut recv_errors);
        worker.notify();
        worker.report(StatusEvent::Stopping);
        let summary = RunSummary {
            samples_in: worker.counters.samples_in,
            samples_out: worker.counters.samples_out,
            send_failures: worker.counters.send_failures,
            model_version: worker.pipeline.model_version(),
        };
        // A last snapshot of the state at the stop; the writer finishes it before it ends.
        worker.snapshot();
        drop(worker.snapshots.take());
        tracing::info!(drained = summary.samples_in - before, ?summary, "gyrocompd stopped");
        Ok(summary)
    }

    /// Re-reads the configuration file and applies what can change while running.
    fn reload(&mut self, pipeline: &mut Pipeline) {
        let Some(path) = &self.config_path else {
            tracing::warn!("SIGHUP: started without --config, nothing to reload");
            return;
        };
        let new = match Config::load(Some(path)) {
            Ok(c) => c,
            Err(e) => {
                tracing::warn!(error = %e, "SIGHUP: configuration refused; keeping the running one");
                return;
            }
        };
        match reload::apply(pipeline, &self.config, &new) {
            Ok(outcome) => {
                for changed in &outcome.needs_restart {
                    tracing::warn!(
                        changed,
                        "SIGHUP: {changed} changed and needs a restart; the running value stays in effect"
                    );
                }
                tracing::info!(
                    motion = ?pipeline.config().motion,
                    input = ?pipeline.config().input,
                    retrain = ?pipeline.config().retrain,
                    "SIGHUP: configuration reloaded"
                );
                self.config = outcome.effective;
            }
            Err(e) => tracing::warn!(error = %e, "SIGHUP: configuration refused; keeping the running one"),
        }
    }
}
