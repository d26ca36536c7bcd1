//! The error type of the iceoryx2 layer.

/// A failure of the iceoryx2 layer: what was attempted, on which service, and iceoryx2's reason.
#[derive(Debug, thiserror::Error)]
pub enum IpcError {
    /// An iceoryx2 call failed.
    #[error("iceoryx2: {op} `{service}` failed: {detail}")]
    Iceoryx {
        /// The operation, e.g. "open or create publish-subscribe service".
        op: &'static str,
        /// The service (or node, or domain) it concerned.
        service: String,
        /// iceoryx2's error value, as text.
        detail: String,
    },
    /// A name or setting was refused before reaching iceoryx2.
    #[error("iceoryx2 setting: {0}")]
    Setting(String),
    /// The stream service already has its one publisher (see [`super::holders`]): another
    /// daemon on `compensated`, another INS client on `raw`.
    #[error("iceoryx2: `{service}` already has its publisher (a stream service allows one): held by {}", super::holders::describe(.holders))]
    PublisherTaken {
        /// The service.
        service: String,
        /// Who holds the publisher, as far as the node listing tells.
        holders: Vec<super::holders::PublisherHolder>,
    },
    /// No peer showed up or answered in time.
    #[error("iceoryx2 peer: {0}")]
    NoPeer(String),
}

impl IpcError {
    /// Wraps an iceoryx2 error value (all of them implement `Debug`).
    pub(crate) fn iox(op: &'static str, service: impl Into<String>, err: impl core::fmt::Debug) -> Self {
        Self::Iceoryx { op, service: service.into(), detail: format!("{err:?}") }
    }
}

/// Result of the iceoryx2 layer.
pub type IpcResult<T> = Result<T, IpcError>;
