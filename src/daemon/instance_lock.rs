//! One daemon per state directory: an exclusive advisory lock (`flock(2)`, through
//! [`std::fs::File::try_lock`]) on `gyrocompd.lock` in `[state] dir`, held for the daemon's
//! whole life.
//!
//! Two daemons writing the same snapshot file would overwrite each other's models, so the
//! second one refuses to start (docs/design.md "One daemon per service prefix, one INS per daemon"). The kernel
//! drops the lock when its holder's file descriptor closes, also when the process is killed
//! with SIGKILL, so a stale lock file never blocks a restart: the file's content (the holder's
//! pid and service prefix, written after locking) only names the holder in the refusal
//! message; it is not the lock. The file is never removed (removing a lock file races with a
//! starting daemon that has just opened it).

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

/// File name of the lock inside the state directory.
pub const LOCK_FILE: &str = "gyrocompd.lock";

/// Permissions of the lock file (like the snapshot: the daemon's user only).
const LOCK_MODE: u32 = 0o600;

/// Why the lock could not be taken.
#[derive(Debug, thiserror::Error)]
pub enum LockError {
    /// Another process holds it: another daemon uses this state directory.
    #[error("another gyrocompd holds the state directory lock {path} ({holder})")]
    Held {
        /// The lock file.
        path: PathBuf,
        /// What the holder wrote into it ("pid 1234, service prefix gyrocomp"), or why that
        /// is unknown.
        holder: String,
    },
    /// The lock file could not be opened, locked or written.
    #[error("lock file {path}: {source}")]
    Io {
        /// The lock file.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
}

/// The held lock; dropping it (or the process ending in any way) releases it.
#[derive(Debug)]
pub struct InstanceLock {
    _file: File,
    path: PathBuf,
}

impl InstanceLock {
    /// Takes the lock of the state directory `dir` (which must exist) without waiting, and
    /// records this process (`pid`, `service_prefix`) in the lock file for a refused
    /// successor's message.
    pub fn acquire(dir: &Path, service_prefix: &str) -> Result<Self, LockError> {
        use std::os::unix::fs::OpenOptionsExt;
        let path = dir.join(LOCK_FILE);
        let io = |source| LockError::Io { path: path.clone(), source };
        // Not truncated on open: the holder's record must survive a refused successor.
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .mode(LOCK_MODE)
            .open(&path)
            .map_err(io)?;
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => {
                let mut text = String::new();
                let holder = match file.read_to_string(&mut text) {
                    Ok(_) if !text.trim().is_empty() => text.trim().to_owned(),
                    Ok(_) => "holder not recorded yet".to_owned(),
                    Err(e) => format!("holder unreadable: {e}"),
                };
                return Err(LockError::Held { path, holder });
            }
            Err(TryLockError::Error(e)) => return Err(io(e)),
        }
        let record = format!("pid {}, service prefix {service_prefix}\n", std::process::id());
        file.set_len(0).map_err(io)?;
        file.rewind().map_err(io)?;
        file.write_all(record.as_bytes()).map_err(io)?;
        file.sync_data().map_err(io)?;
        Ok(Self { _file: file, path })
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn second_lock_is_refused_with_the_holder_named_and_released_on_drop() {
        let dir = tempfile::tempdir().unwrap();
        let first = InstanceLock::acquire(dir.path(), "gyrocomp").unwrap();
        // flock conflicts between open file descriptions, also within one process.
        let err = InstanceLock::acquire(dir.path(), "other").unwrap_err();
        let text = err.to_string();
        assert!(matches!(err, LockError::Held { .. }), "{text}");
        let me = format!("pid {}, service prefix gyrocomp", std::process::id());
        assert!(text.contains(&me) && text.contains(LOCK_FILE), "{text}");
        drop(first);
        let again = InstanceLock::acquire(dir.path(), "next").unwrap();
        let record = std::fs::read_to_string(again.path()).unwrap();
        assert_eq!(record, format!("pid {}, service prefix next\n", std::process::id()));
        use std::os::unix::fs::PermissionsExt;
        assert_eq!(std::fs::metadata(again.path()).unwrap().permissions().mode() & 0o777, LOCK_MODE);
    }

    #[test]
    fn a_stale_lock_file_without_a_holder_does_not_block() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join(LOCK_FILE), "pid 999999, service prefix gyrocomp\n").unwrap();
        let lock = InstanceLock::acquire(dir.path(), "gyrocomp").unwrap();
        let record = std::fs::read_to_string(lock.path()).unwrap();
        assert_eq!(record, format!("pid {}, service prefix gyrocomp\n", std::process::id()));
    }
}
