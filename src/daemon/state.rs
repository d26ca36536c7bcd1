//! The daemon's state directory (`[state] dir`): the snapshot file (models, estimator, detector
//! and input-check state: [`crate::stream::snapshot`]), written by a writer thread after each
//! successful retrain, every `[state] every_s` seconds and at a clean stop, and read once at
//! start.
//!
//! Writing is atomic: the bytes go to a temporary file in the same directory, which is synced
//! and renamed over the snapshot, and the directory is synced; a crash at any moment leaves
//! either the old or the new snapshot, never a mix. The sample loop only hands the writer
//! thread a job (shared model handles and copies of the pipeline buffers) through a bounded
//! channel without blocking; encoding and disk I/O happen on the writer thread.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::thread::JoinHandle;

use crossbeam_channel::{Sender, TrySendError, bounded};

use crate::stream::InstalledModel;
use crate::stream::snapshot::{Compat, Snapshot, SnapshotError};
use crate::stream::warm::{AxisWarm, StreamWarm};

/// File name of the snapshot inside the state directory.
pub const SNAPSHOT_FILE: &str = "gyrocompd.snapshot";
/// File name of the temporary file a snapshot is written to before the rename.
pub const TEMP_FILE: &str = "gyrocompd.snapshot.tmp";

/// Why a snapshot file could not be read or used.
#[derive(Debug, thiserror::Error)]
pub enum StateError {
    /// The file exists but could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// The content is corrupt, truncated, of another format or incompatible.
    #[error("{path}: {source}")]
    Snapshot {
        /// The file.
        path: PathBuf,
        /// The reason.
        source: SnapshotError,
    },
}

/// Permissions of the snapshot file: read and write for the daemon's user only (like its
/// iceoryx2 services); the model and buffers are nobody else's business.
pub const SNAPSHOT_MODE: u32 = 0o600;

/// Writes `bytes` to `path` atomically: temporary file (mode [`SNAPSHOT_MODE`]) in the same
/// directory, `fsync`, rename, `fsync` of the directory.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::os::unix::fs::{OpenOptionsExt, PermissionsExt};
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let tmp = dir.join(TEMP_FILE);
    let mut file =
        std::fs::OpenOptions::new().write(true).create(true).truncate(true).mode(SNAPSHOT_MODE).open(&tmp)?;
    // A temporary file left by an earlier build may have wider permissions: `mode` applies to
    // new files only.
    file.set_permissions(std::fs::Permissions::from_mode(SNAPSHOT_MODE))?;
    file.write_all(bytes)?;
    file.sync_all()?;
    drop(file);
    std::fs::rename(&tmp, path)?;
    File::open(dir)?.sync_all()
}

/// Reads and decodes the snapshot at `path`: `Ok(None)` when there is none. The compatibility
/// with the running configuration is checked when it is restored
/// ([`Snapshot::restore_into`]).
pub fn read_snapshot(path: &Path) -> Result<Option<Snapshot>, StateError> {
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(source) => return Err(StateError::Read { path: path.into(), source }),
    };
    Snapshot::decode(&bytes).map(Some).map_err(|source| StateError::Snapshot { path: path.into(), source })
}

/// What the sample loop hands the writer: shared model handles and copies of the buffers.
pub struct SnapshotJob {
    /// Settings the snapshot depends on.
    pub compat: Compat,
    /// The installed model of each axis.
    pub models: [Option<Arc<InstalledModel>>; 3],
    /// The warm state of each axis.
    pub warm: [AxisWarm; 3],
    /// The state the axes share (detector, pending queue, input checks).
    pub stream: StreamWarm,
}

/// The writer thread; dropping it lets the thread finish the queued job and joins it.
pub struct SnapshotWriter {
    jobs: Option<Sender<SnapshotJob>>,
    thread: Option<JoinHandle<()>>,
    /// A job the channel had no room for (the newest wins); offered again by [`Self::flush`].
    unsent: Option<SnapshotJob>,
}

impl SnapshotWriter {
    /// Starts the writer thread for the snapshot file `path`.
    pub fn spawn(path: PathBuf) -> std::io::Result<Self> {
        let (tx, rx) = bounded::<SnapshotJob>(1);
        let thread = std::thread::Builder::new().name("gyrocomp-snapshot".into()).spawn(move || {
            for job in rx {
                write_job(&path, job);
            }
        })?;
        Ok(Self { jobs: Some(tx), thread: Some(thread), unsent: None })
    }

    /// Queues `job` without blocking; while the thread is busy with an earlier one the newest
    /// job waits here (replacing an older waiting one) until [`Self::flush`].
    pub fn offer(&mut self, job: SnapshotJob) {
        self.unsent = Some(job);
        self.flush();
    }

    /// Hands a waiting job to the thread if it has room now (never blocks).
    pub fn flush(&mut self) {
        let (Some(tx), Some(job)) = (&self.jobs, self.unsent.take()) else { return };
        match tx.try_send(job) {
            Ok(()) => {}
            Err(TrySendError::Full(job)) => self.unsent = Some(job),
            Err(TrySendError::Disconnected(_)) => {
                tracing::error!("snapshot writer thread stopped; no more snapshots are written");
                self.jobs = None;
            }
        }
    }
}

impl Drop for SnapshotWriter {
    fn drop(&mut self) {
        if let (Some(tx), Some(job)) = (&self.jobs, self.unsent.take()) {
            let _ = tx.send(job);
        }
        self.jobs.take();
        if let Some(t) = self.thread.take()
            && t.join().is_err()
        {
            tracing::error!("snapshot writer thread panicked");
        }
    }
}

fn write_job(path: &Path, job: SnapshotJob) {
    let started = std::time::Instant::now();
    let snapshot = match Snapshot::capture(job.compat, job.models, job.warm, job.stream) {
        Ok(s) => s,
        Err(e) => {
            tracing::warn!(file = %path.display(), error = %e, "snapshot not written");
            return;
        }
    };
    let written = snapshot
        .encode()
        .map_err(|e| e.to_string())
        .and_then(|bytes| write_atomic(path, &bytes).map(|()| bytes.len()).map_err(|e| e.to_string()));
    match written {
        Ok(bytes) => tracing::info!(
            file = %path.display(),
            model_version = snapshot.model_version(),
            bytes,
            seconds = started.elapsed().as_secs_f64(),
            "snapshot written"
        ),
        Err(e) => tracing::warn!(file = %path.display(), error = %e, "writing the snapshot failed"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_write_replaces_the_file_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(SNAPSHOT_FILE);
        write_atomic(&path, b"first").unwrap();
        write_atomic(&path, b"second").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"second");
        // Owner-only, also over a file (and a leftover temporary) that had wider permissions.
        use std::os::unix::fs::PermissionsExt;
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&path), SNAPSHOT_MODE);
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o644)).unwrap();
        std::fs::write(dir.path().join(TEMP_FILE), b"stale").unwrap();
        std::fs::set_permissions(dir.path().join(TEMP_FILE), std::fs::Permissions::from_mode(0o666)).unwrap();
        write_atomic(&path, b"third").unwrap();
        assert_eq!((mode(&path), std::fs::read(&path).unwrap()), (SNAPSHOT_MODE, b"third".to_vec()));
        assert!(!dir.path().join(TEMP_FILE).exists());
        assert!(read_snapshot(&dir.path().join("none")).unwrap().is_none());
        let err = read_snapshot(&path).unwrap_err();
        assert!(matches!(err, StateError::Snapshot { source: SnapshotError::BadMagic, .. }), "{err}");
        assert!(err.to_string().contains(SNAPSHOT_FILE), "{err}");
    }

    /// A real snapshot of a default (Kalman) pipeline after `n` samples.
    fn snapshot_bytes(n: u64) -> (Snapshot, Vec<u8>) {
        let mut c = crate::config::Config::default();
        c.input.rate_hz = crate::config::RateSetting::Hz(100.0);
        let mut p = crate::stream::Pipeline::new(c.pipeline().unwrap()).unwrap();
        for k in 0..n {
            let x = 0.01 * ((k * 7919) % 13) as f64;
            p.process(&crate::stream::InputSample::new(k, k * 10_000_000, [x, -x, 0.5 * x]));
        }
        let s = Snapshot::of_pipeline(&p).unwrap();
        let bytes = s.encode().unwrap();
        (s, bytes)
    }

    #[test]
    fn a_write_killed_half_way_leaves_the_previous_snapshot_usable() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(SNAPSHOT_FILE);
        let (first, bytes) = snapshot_bytes(300);
        write_atomic(&path, &bytes).unwrap();
        // kill -9 while the next one was being written: its temporary file is left truncated
        // (the rename never happened).
        let (second, newer) = snapshot_bytes(600);
        std::fs::write(dir.path().join(TEMP_FILE), &newer[..newer.len() / 2]).unwrap();
        // (Compared as bytes: pending temperatures are NaN, "none".)
        let encoded = |s: Option<Snapshot>| s.unwrap().encode().unwrap();
        assert_eq!(encoded(read_snapshot(&path).unwrap()), bytes, "the previous snapshot is read");
        // The truncated file itself would be refused, never half-used.
        let half = std::fs::read(dir.path().join(TEMP_FILE)).unwrap();
        assert!(matches!(Snapshot::decode(&half), Err(SnapshotError::Truncated { .. })));
        // The restarted daemon's next write replaces the leftover and the snapshot.
        write_atomic(&path, &newer).unwrap();
        assert_eq!(encoded(read_snapshot(&path).unwrap()), second.encode().unwrap());
        assert!(!dir.path().join(TEMP_FILE).exists());
        assert_eq!((first.stream.index, second.stream.index), (300, 600));
    }
}
