//! Why the daemon could not start.

use crate::config::ConfigError;
use crate::drive::BuildError;
use crate::ipc::IpcError;
use std::path::PathBuf;

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
/// sections) is a [`BuildError::Config`], as in [`build_pipeline`](crate::drive::build_pipeline).
impl From<ConfigError> for DaemonError {
    fn from(e: ConfigError) -> Self {
        Self::Build(BuildError::Config(e))
    }
}
