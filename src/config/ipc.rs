//! `[ipc]`: the daemon's iceoryx2 services and domain, and their validation.

use std::path::PathBuf;
use std::time::Duration;

use serde::Deserialize;

use super::{Config, ConfigError};
use crate::ipc::{Delivery, IpcSettings, ServiceNames, WaitMode};

/// `[ipc]` keys (used by `gyrocompd`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct IpcSection {
    /// Services are `<service_prefix>/raw`, `/compensated` and `/status`.
    pub service_prefix: String,
    /// How the daemon waits for raw samples: `event` (sleep on the event service) or `spin`.
    pub wait: String,
    /// Subscriber buffer of the raw and compensated services, samples.
    pub subscriber_buffer: usize,
    /// Compensated publisher on a full subscriber buffer: `lossless` (wait) or `drop-newest`.
    pub delivery: String,
    /// `lossless`: longest wait for one full subscriber before the sample is dropped for it, ms
    /// (0 = wait as long as the subscriber exists).
    pub give_up_ms: u64,
    /// iceoryx2 `global.prefix` of a private domain (empty with `domain_root`: iceoryx2's own
    /// configuration lookup, `config/iceoryx2.toml` in the working directory first).
    pub domain_prefix: String,
    /// iceoryx2 `global.root_path` of a private domain, an absolute directory.
    pub domain_root: String,
}

impl Default for IpcSection {
    fn default() -> Self {
        Self {
            service_prefix: crate::ipc::DEFAULT_PREFIX.into(),
            wait: "event".into(),
            subscriber_buffer: crate::ipc::DEFAULT_SUBSCRIBER_BUFFER,
            delivery: "lossless".into(),
            give_up_ms: 1000,
            domain_prefix: String::new(),
            domain_root: String::new(),
        }
    }
}

/// The iceoryx2 domain of `[ipc] domain_prefix/domain_root`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DomainChoice {
    /// iceoryx2's own configuration lookup.
    Global,
    /// A private domain with this prefix and root path.
    Private {
        /// `global.prefix`.
        prefix: String,
        /// `global.root_path`.
        root: PathBuf,
    },
}

impl Config {
    /// The iceoryx2 port settings of `[ipc]`, validated.
    pub fn ipc_settings(&self) -> Result<IpcSettings, ConfigError> {
        let i = &self.ipc;
        let prefix = i.service_prefix.trim_end_matches('/');
        if prefix.is_empty() {
            return Err(ConfigError("ipc.service_prefix must not be empty".into()));
        }
        let wait_mode = match i.wait.as_str() {
            "event" => WaitMode::Event,
            "spin" => WaitMode::Spin,
            other => return Err(ConfigError(format!("ipc.wait: {other:?} is neither \"event\" nor \"spin\""))),
        };
        if i.subscriber_buffer == 0 {
            return Err(ConfigError("ipc.subscriber_buffer must be at least 1".into()));
        }
        let delivery = match i.delivery.as_str() {
            "lossless" => {
                Delivery::Lossless { give_up_after: (i.give_up_ms > 0).then(|| Duration::from_millis(i.give_up_ms)) }
            }
            "drop-newest" => Delivery::DropNewest,
            other => {
                return Err(ConfigError(format!(
                    "ipc.delivery: {other:?} is neither \"lossless\" nor \"drop-newest\""
                )));
            }
        };
        Ok(IpcSettings {
            names: ServiceNames::with_prefix(prefix),
            subscriber_buffer: i.subscriber_buffer,
            wait_mode,
            delivery,
            notify: true,
        })
    }

    /// The iceoryx2 domain of `[ipc]`: both `domain_prefix` and `domain_root` set (root
    /// absolute), or neither.
    pub fn ipc_domain(&self) -> Result<DomainChoice, ConfigError> {
        let (prefix, root) = (&self.ipc.domain_prefix, &self.ipc.domain_root);
        match (prefix.is_empty(), root.is_empty()) {
            (true, true) => Ok(DomainChoice::Global),
            (false, false) => {
                let root = PathBuf::from(root);
                if !root.is_absolute() {
                    return Err(ConfigError(format!("ipc.domain_root: {} is not an absolute path", root.display())));
                }
                Ok(DomainChoice::Private { prefix: prefix.clone(), root })
            }
            _ => Err(ConfigError("ipc.domain_prefix/ipc.domain_root: give both or neither".into())),
        }
    }
}
