//! Start-up and the daemon loop.
//!
//! Start-up: configuration → pipeline and retrainer ([`build_pipeline`], shared with the offline
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

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use super::instance_lock::{InstanceLock, LockError};
use super::convert::{LoopCounters, comp_from_output, input_from_raw, status_sample};
use super::reload;
use super::signals::Signals;
use super::state::{self, SNAPSHOT_FILE, SnapshotJob, SnapshotWriter};
use crate::config::{Config, ConfigError, DomainChoice};
use crate::ipc::{
    CompPublisher, IpcDomain, IpcError, IpcNode, RawSample, RawSubscriber, StatusEvent, StatusPublisher,
};
use crate::stream::snapshot::Compat;
use crate::drive::{BuildError, build_pipeline};
use crate::stream::Pipeline;

/// Longest single wait for a raw sample, so that signals are seen promptly.
const POLL: Duration = Duration::from_millis(50);
/// Period of the `Periodic` status report.
const STATUS_PERIOD: Duration = Duration::from_secs(1);
/// Node name of the daemon.
const NODE_NAME: &str = "gyrocompd";
/// Least time between two dead-node cleanups triggered by failed sends.
const CLEANUP_PERIOD: Duration = Duration::from_secs(1);

/// Why the daemon could not start.
#[derive(Debug, thiserror::Error)]
pub enum DaemonError {
    /// The pipeline could not be built: an invalid configuration (the message names the key),
    /// settings the pipeline refused, or a retrain thread that could not be started. Shown as the
    /// [`BuildError`] itself.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// The state directory could not be created or its writer thread started.
    #[error("state directory {path}: {source}")]
    State {
        /// The directory.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// Another daemon already serves this service prefix (it holds the compensated service's one
    /// publisher) or uses this state directory (it holds its lock); `detail` names it.
    #[error(
        "gyrocompd is already running for service prefix `{prefix}`: {detail}; stop that one first, or give this \
         one its own [ipc] service_prefix and [state] dir"
    )]
    AlreadyRunning {
        /// The service prefix this daemon was to serve.
        prefix: String,
        /// Which check refused it and the running daemon's pid or iceoryx2 node.
        detail: String,
    },
    /// The iceoryx2 services or ports could not be opened.
    #[error(transparent)]
    Ipc(#[from] IpcError),
}

/// An invalid configuration met at start-up (parsing the file, or its `[ipc]` and `[state]`
/// sections) is a [`BuildError::Config`], as in [`build_pipeline`].
impl From<ConfigError> for DaemonError {
    fn from(e: ConfigError) -> Self {
        Self::Build(BuildError::Config(e))
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

/// Restores the snapshot at `path` into `pipeline` when there is a usable one; a missing,
/// corrupt, truncated or incompatible snapshot is reported and the pipeline starts cold.
fn warm_start(pipeline: &mut Pipeline, path: &Path) {
    let file = path.display();
    match state::read_snapshot(path) {
        Ok(None) => tracing::info!(%file, "no model snapshot yet: starting without a model"),
        Ok(Some(snapshot)) => match snapshot.restore_into(pipeline) {
            Ok(()) => tracing::info!(
                %file,
                model_version = snapshot.model_version(),
                "model snapshot loaded: compensating with it from the first sample"
            ),
            Err(e) => tracing::warn!(%file, error = %e, "model snapshot ignored; starting without a model"),
        },
        Err(e) => tracing::warn!(error = %e, "model snapshot ignored; starting without a model"),
    }
}

/// Takes the state directory's instance lock; held by another process, it is refused as
/// [`DaemonError::AlreadyRunning`].
fn lock_state_dir(dir: &Path, prefix: &str) -> Result<InstanceLock, DaemonError> {
    match InstanceLock::acquire(dir, prefix) {
        Ok(lock) => {
            tracing::debug!(file = %lock.path().display(), "state directory locked");
            Ok(lock)
        }
        Err(e @ LockError::Held { .. }) => Err(DaemonError::AlreadyRunning { prefix: prefix.into(), detail: e.to_string() }),
        Err(LockError::Io { path, source }) => Err(DaemonError::State { path, source }),
    }
}

/// A raw service created by a peer with room for several publishers lets a second INS client
/// interleave its samples with the first one's (gyrocomp's own clients refuse to, others may
/// not): said once at start.
fn warn_if_shared_raw(node: &IpcNode, raw: &str) {
    match node.stream_publisher_limit(raw) {
        Ok(limit) if limit > crate::ipc::STREAM_MAX_PUBLISHERS => tracing::warn!(
            service = raw,
            max_publishers = limit,
            "the raw service allows several publishers (a peer created it so); a second INS client's samples would \
             interleave with the first one's: recreate it with max_publishers = 1"
        ),
        Ok(_) => {}
        Err(e) => tracing::debug!(error = %e, "publisher limit of the raw service unknown"),
    }
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
    node: IpcNode,
    /// The snapshot writer (`[state] dir` set) and the settings snapshots depend on.
    snapshots: Option<SnapshotWriter>,
    compat: Compat,
    /// `[state] every_s` and when the last snapshot was handed to the writer.
    snapshot_every: Option<Duration>,
    last_snapshot: Instant,
    last_cleanup: Option<Instant>,
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
        let mut pipeline = build_pipeline(&self.config)?;
        let compat = Compat::of(pipeline.config());
        let prefix = self.config.ipc.service_prefix.clone();
        // Held until `run` returns (the kernel releases it however the process ends).
        let mut _instance_lock = None;
        let snapshots = match self.config.state_dir()? {
            Some(dir) => {
                let state_err = |source| DaemonError::State { path: dir.clone(), source };
                std::fs::create_dir_all(&dir).map_err(state_err)?;
                _instance_lock = Some(lock_state_dir(&dir, &prefix)?);
                let path = dir.join(SNAPSHOT_FILE);
                warm_start(&mut pipeline, &path);
                Some(SnapshotWriter::spawn(path).map_err(state_err)?)
            }
            None => None,
        };
        let stale = IpcNode::dead_nodes(&domain)?;
        let node = IpcNode::new(&domain, NODE_NAME, settings.clone())?;
        let (cleaned, failed) = node.cleanup_dead_nodes();
        let after = IpcNode::dead_nodes(&domain)?;
        tracing::info!(
            dead_before = stale.dead,
            cleaned,
            failed,
            dead_after = after.dead,
            inaccessible = after.inaccessible,
            "stale iceoryx2 nodes cleaned"
        );
        // The compensated publisher first: a second daemon is refused before it subscribes to
        // (and takes samples from) the running one's raw stream.
        let comp = node.comp_publisher().map_err(|e| match e {
            IpcError::PublisherTaken { .. } => DaemonError::AlreadyRunning { prefix: prefix.clone(), detail: e.to_string() },
            e => e.into(),
        })?;
        let raw = node.raw_subscriber()?;
        warn_if_shared_raw(&node, &settings.names.raw);
        let reported_version = pipeline.model_version();
        let mut worker = Worker {
            pipeline,
            comp,
            status: node.status_publisher()?,
            node,
            snapshots,
            compat,
            snapshot_every: self.config.snapshot_every()?,
            last_snapshot: Instant::now(),
            last_cleanup: None,
            counters: LoopCounters::default(),
            started: Instant::now(),
            last_report: Instant::now(),
            reported_version,
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
                self.cleanup_after_failure();
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
            self.snapshot();
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

    /// Hands the installed models and copies of the pipeline buffers to the snapshot writer.
    fn snapshot(&mut self) {
        let Some(writer) = &mut self.snapshots else { return };
        let p = &self.pipeline;
        let models = [0, 1, 2].map(|axis| p.model_slot(axis).and_then(|slot| (*slot.load()).clone()));
        writer.offer(SnapshotJob { compat: self.compat.clone(), models, warm: p.warm_state(), stream: p.stream_state() });
        self.last_snapshot = Instant::now();
    }

    /// A failed send may mean a client died with a full buffer: a lossless publisher then waits
    /// for it on every sample. Cleaning dead nodes removes its ports (at most once a second).
    fn cleanup_after_failure(&mut self) {
        if self.last_cleanup.is_some_and(|t| t.elapsed() < CLEANUP_PERIOD) {
            return;
        }
        self.last_cleanup = Some(Instant::now());
        let (cleaned, failed) = self.node.cleanup_dead_nodes();
        if cleaned + failed > 0 {
            tracing::info!(cleaned, failed, "dead iceoryx2 nodes cleaned after a failed send");
        }
    }

    /// Publishes the periodic report when it is due, and hands a waiting snapshot on.
    fn tick(&mut self) {
        if let Some(writer) = &mut self.snapshots {
            writer.flush();
        }
        if self.snapshot_every.is_some_and(|every| self.last_snapshot.elapsed() >= every) {
            self.snapshot();
        }
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
