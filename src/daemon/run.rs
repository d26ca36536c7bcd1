//! Start-up and the daemon loop.
//!
//! Start-up: configuration → pipeline and retrainer ([`build_pipeline`], shared with the offline
//! driver) → iceoryx2 node and ports (opened or created, so clients may start first) → a
//! `Started` status. Loop: wait for raw samples (event or spin, `[ipc] wait`), answer each with
//! exactly one `CompSample` of the same `seq`, publish a `Periodic` status every second and a
//! `ModelSwapped`/`RetrainFailed` status when those counters move. Between samples, SIGHUP
//! reloads the configuration ([`super::reload`]) and SIGTERM/SIGINT end the loop: the samples
//! already waiting are answered, a `Stopping` status is published and [`Daemon::run`] returns.
//!
//! IPC errors while running are logged (rate-limited) and counted, never fatal; only start-up
//! failures (bad configuration, services that cannot be opened) end the daemon with an error.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use super::convert::{LoopCounters, comp_from_output, input_from_raw, status_sample};
use super::reload;
use super::signals::Signals;
use crate::config::{Config, ConfigError, DomainChoice};
use crate::stream::ipc::{
    CompPublisher, IpcDomain, IpcError, IpcNode, RawSample, RawSubscriber, StatusEvent, StatusPublisher,
};
use crate::stream::{BuildError, Pipeline, PipelineError, build_pipeline};

/// Longest single wait for a raw sample, so that signals are seen promptly.
const POLL: Duration = Duration::from_millis(50);
/// Period of the `Periodic` status report.
const STATUS_PERIOD: Duration = Duration::from_secs(1);
/// Node name of the daemon.
const NODE_NAME: &str = "gyrocompd";

/// Why the daemon could not start.
#[derive(Debug, thiserror::Error)]
pub enum DaemonError {
    /// The configuration file could not be read.
    #[error("cannot read config file {path}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// The configuration is invalid (the message names the key).
    #[error("{0}")]
    Config(#[from] ConfigError),
    /// The pipeline refused its settings.
    #[error("pipeline: {0}")]
    Pipeline(#[from] PipelineError),
    /// The retrain thread could not be started.
    #[error("cannot start the retrain thread: {0}")]
    Trainer(std::io::Error),
    /// The iceoryx2 services or ports could not be opened.
    #[error(transparent)]
    Ipc(#[from] IpcError),
}

impl From<BuildError> for DaemonError {
    fn from(e: BuildError) -> Self {
        match e {
            BuildError::Config(e) => Self::Config(e),
            BuildError::Pipeline(e) => Self::Pipeline(e),
            BuildError::Trainer(e) => Self::Trainer(e),
        }
    }
}

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

/// Reads and validates a configuration file; `None` gives the built-in defaults.
pub fn load_config(path: Option<&Path>) -> Result<Config, DaemonError> {
    let Some(path) = path else { return Ok(Config::default()) };
    let text = std::fs::read_to_string(path).map_err(|source| DaemonError::Read { path: path.into(), source })?;
    Ok(Config::from_toml(&text, &path.display().to_string())?)
}

/// The daemon: a configuration (and the file it came from, for reloads) and its signal flags.
#[derive(Debug)]
pub struct Daemon {
    config: Config,
    config_path: Option<PathBuf>,
    signals: Signals,
}

/// Everything the loop touches per sample.
struct Worker {
    pipeline: Pipeline,
    comp: CompPublisher,
    status: StatusPublisher,
    counters: LoopCounters,
    started: Instant,
    last_report: Instant,
    reported_version: u64,
    reported_failed: u64,
    status_errors: u64,
    /// Retrain requests seen so far, and when the newest one was made.
    requests_seen: u64,
    request_at: Option<Instant>,
    /// Answers sent since the last notification of the compensated event service.
    unnotified: usize,
}

/// Answers sent quietly before the compensated listeners are woken, within one burst of raw
/// samples: well below any subscriber buffer, so a client sleeping on the event service is woken
/// long before a lossless publisher could wait for room in its buffer.
const NOTIFY_BATCH: usize = 32;

impl Daemon {
    /// A daemon with a validated configuration; `config_path` is re-read on SIGHUP.
    pub fn new(config: Config, config_path: Option<PathBuf>, signals: Signals) -> Self {
        Self { config, config_path, signals }
    }

    /// Starts the services and runs until a stop is requested; see the module documentation.
    pub fn run(mut self) -> Result<RunSummary, DaemonError> {
        let domain = match self.config.ipc_domain()? {
            DomainChoice::Global => IpcDomain::global(),
            DomainChoice::Private { prefix, root } => IpcDomain::private(&prefix, &root)?,
        };
        let settings = self.config.ipc_settings()?;
        let pipeline = build_pipeline(&self.config)?;
        let node = IpcNode::new(&domain, NODE_NAME, settings.clone())?;
        let raw = node.raw_subscriber()?;
        let mut worker = Worker {
            pipeline,
            comp: node.comp_publisher()?,
            status: node.status_publisher()?,
            counters: LoopCounters::default(),
            started: Instant::now(),
            last_report: Instant::now(),
            reported_version: 0,
            reported_failed: 0,
            status_errors: 0,
            requests_seen: 0,
            request_at: None,
            unnotified: 0,
        };
        tracing::info!(
            raw = %settings.names.raw,
            compensated = %settings.names.compensated,
            status = %settings.names.status,
            wait = ?settings.wait_mode,
            delivery = ?settings.delivery,
            domain_prefix = %domain.prefix(),
            domain_root = %domain.root_path(),
            "gyrocompd running"
        );
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
        tracing::info!(drained = summary.samples_in - before, ?summary, "gyrocompd stopped");
        Ok(summary)
    }

    /// Re-reads the configuration file and applies what can change while running.
    fn reload(&mut self, pipeline: &mut Pipeline) {
        let Some(path) = &self.config_path else {
            tracing::warn!("SIGHUP: started without --config, nothing to reload");
            return;
        };
        let new = match load_config(Some(path)) {
            Ok(c) => c,
            Err(e) => {
                tracing::warn!(error = %e, "SIGHUP: configuration refused; keeping the running one");
                return;
            }
        };
        match reload::apply(pipeline, &self.config, &new) {
            Ok(outcome) => {
                if !outcome.needs_restart.is_empty() {
                    tracing::warn!(sections = ?outcome.needs_restart, "SIGHUP: these changes take effect after a restart");
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

impl Worker {
    /// Compensates one raw sample and publishes its answer; the listeners are woken by
    /// [`Worker::notify`] after the burst, or every [`NOTIFY_BATCH`] answers within it (one
    /// notification per burst instead of one per sample: replay throughput).
    fn handle(&mut self, raw: &RawSample) {
        self.counters.samples_in += 1;
        self.counters.last_seq = raw.seq;
        let out = self.pipeline.process(&input_from_raw(raw));
        let sent = self.comp.send_quiet(comp_from_output(&out));
        self.unnotified += 1;
        if self.unnotified >= NOTIFY_BATCH {
            self.notify();
        }
        match sent.map(|_| ()) {
            Ok(()) => self.counters.samples_out += 1,
            Err(e) => {
                self.counters.send_failures += 1;
                if self.counters.send_failures.is_power_of_two() {
                    tracing::warn!(seq = raw.seq, error = %e, count = self.counters.send_failures, "publishing a compensated sample failed");
                }
            }
        }
        // A model is installed (or a fit fails) before the sample it first serves; a request is
        // made after the sample that completes the schedule: check in that order.
        let stats = self.pipeline.stats();
        let swapped = out.model_version != self.reported_version;
        let failed = stats.retrain_failed != self.reported_failed;
        if (swapped || failed)
            && let Some(at) = self.request_at.take()
        {
            self.counters.last_retrain_ns = u64::try_from(at.elapsed().as_nanos()).unwrap_or(u64::MAX);
        }
        if stats.retrain_requests != self.requests_seen {
            self.requests_seen = stats.retrain_requests;
            self.request_at = Some(Instant::now());
        }
        if swapped {
            self.reported_version = out.model_version;
            self.report(StatusEvent::ModelSwapped);
        } else if failed {
            self.reported_failed = stats.retrain_failed;
            self.report(StatusEvent::RetrainFailed);
        }
    }

    /// Wakes the compensated listeners if answers were sent since the last time (and the
    /// settings ask for notifications).
    fn notify(&mut self) {
        if self.unnotified == 0 || !self.comp.notifies() {
            self.unnotified = 0;
            return;
        }
        self.unnotified = 0;
        if let Err(e) = self.comp.notify() {
            tracing::debug!(error = %e, "notifying the compensated listeners failed");
        }
    }

    /// Handles the samples waiting now, at most `max`.
    fn drain(&mut self, raw: &RawSubscriber, max: usize, errors: &mut u64) {
        for _ in 0..max {
            match raw.try_recv() {
                Ok(Some(sample)) => self.handle(&sample),
                Ok(None) => return,
                Err(e) => {
                    *errors += 1;
                    if errors.is_power_of_two() {
                        tracing::warn!(error = %e, count = *errors, "receiving raw samples failed");
                    }
                    return;
                }
            }
        }
    }

    /// Publishes the periodic report when it is due.
    fn tick(&mut self) {
        if self.last_report.elapsed() >= STATUS_PERIOD {
            self.report(StatusEvent::Periodic);
        }
    }

    /// Publishes a status report now.
    fn report(&mut self, event: StatusEvent) {
        self.last_report = Instant::now();
        let t_ns = u64::try_from(self.started.elapsed().as_nanos()).unwrap_or(u64::MAX);
        let sample = status_sample(event, t_ns, &self.pipeline.stats(), self.pipeline.model_version(), &self.counters);
        if let Err(e) = self.status.send(sample) {
            self.status_errors += 1;
            if self.status_errors.is_power_of_two() {
                tracing::warn!(error = %e, count = self.status_errors, "publishing a status report failed");
            }
        }
        tracing::debug!(?event, samples_in = sample.samples_in, model_version = sample.model_version, "status");
    }
}
