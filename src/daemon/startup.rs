//! Start-up of the daemon: configuration → pipeline and retrainer ([`build_pipeline`], shared
//! with the offline driver), warm-started from the model snapshot of `[state] dir` when there is a
//! compatible one ([`super::state`]) → iceoryx2 node (stale resources of dead nodes, e.g. a killed
//! earlier daemon, are cleaned first) and ports (opened or created, so clients may start first).

use std::path::Path;
use std::time::Instant;

use super::convert::LoopCounters;
use super::errors::DaemonError;
use super::instance_lock::{InstanceLock, LockError};
use super::state::{self, SNAPSHOT_FILE, SnapshotWriter};
use super::worker::Worker;
use crate::config::{Config, DomainChoice};
use crate::drive::build_pipeline;
use crate::ipc::{IpcDomain, IpcError, IpcNode, IpcSettings, RawSubscriber};
use crate::stream::Pipeline;
use crate::stream::snapshot::Compat;

/// Node name of the daemon.
const NODE_NAME: &str = "gyrocompd";

/// A started daemon: what the loop runs on and what must live as long as it.
pub(super) struct Started {
    /// The iceoryx2 domain of the node.
    pub(super) domain: IpcDomain,
    /// The `[ipc]` settings in effect.
    pub(super) settings: IpcSettings,
    /// The state directory's lock (held until the daemon ends; the kernel releases it however
    /// the process ends).
    pub(super) instance_lock: Option<InstanceLock>,
    /// The raw samples' subscriber.
    pub(super) raw: RawSubscriber,
    /// The pipeline, node, publishers and counters of the loop.
    pub(super) worker: Worker,
}

/// Builds everything the loop needs from `config` (module documentation); logs "gyrocompd
/// running" when done.
pub(super) fn start(config: &Config) -> Result<Started, DaemonError> {
    let domain = match config.ipc_domain()? {
        DomainChoice::Global => IpcDomain::global(),
        DomainChoice::Private { prefix, root } => IpcDomain::private(&prefix, &root)?,
    };
    let settings = config.ipc_settings()?;
    let mut pipeline = build_pipeline(config)?;
    let compat = Compat::of(pipeline.config());
    let prefix = config.ipc.service_prefix.clone();
    // Held until `run` returns (the kernel releases it however the process ends).
    let mut _instance_lock = None;
    let snapshots = match config.state_dir()? {
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
        IpcError::PublisherTaken { .. } => {
            DaemonError::AlreadyRunning { prefix: prefix.clone(), detail: e.to_string() }
        }
        e => e.into(),
    })?;
    let raw = node.raw_subscriber()?;
    warn_if_shared_raw(&node, &settings.names.raw);
    let reported_version = pipeline.model_version();
    let worker = Worker {
        pipeline,
        comp,
        status: node.status_publisher()?,
        node,
        snapshots,
        compat,
        snapshot_every: config.snapshot_every()?,
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
    Ok(Started { domain, settings, instance_lock: _instance_lock, raw, worker })
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
        Err(e @ LockError::Held { .. }) => {
            Err(DaemonError::AlreadyRunning { prefix: prefix.into(), detail: e.to_string() })
        }
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
