//! `[ipc]`: the daemon's iceoryx2 services and domain, and their validation.

use std::path::PathBuf;
use std::time::Duration;

use serde::Deserialize;

use super::keys::by_name;
use super::{Config, ConfigError};
use crate::ipc::{Delivery, IpcSettings, ServiceNames, WaitMode};

/// `[ipc]` keys (used by `gyrocompd`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct IpcSection {
    /// Services are `<service_prefix>/raw`, `/compensated` and `/status`.
    pub service_prefix: String,
    /// How the daemon waits for raw samples: `event` (sleep on the event service) or `spin`.
    pub wait: WaitMode,
    /// Subscriber buffer of the raw and compensated services, samples.
    pub subscriber_buffer: usize,
    /// Compensated publisher on a full subscriber buffer: `lossless` (wait) or `drop-newest`.
    pub delivery: DeliveryMode,
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
            wait: WaitMode::Event,
            subscriber_buffer: crate::ipc::DEFAULT_SUBSCRIBER_BUFFER,
            delivery: DeliveryMode::Lossless,
            give_up_ms: 1000,
            domain_prefix: String::new(),
            domain_root: String::new(),
        }
    }
}

impl<'de> Deserialize<'de> for WaitMode {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        by_name(d, "ipc.wait", &[("event", Self::Event), ("spin", Self::Spin)])
    }
}

/// `[ipc] delivery`: what the compensated publisher does on a full subscriber buffer (with
/// `give_up_ms`, the [`Delivery`] of the port).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DeliveryMode {
    /// `lossless`: wait for room, up to `give_up_ms`.
    Lossless,
    /// `drop-newest`: never wait.
    DropNewest,
}

impl<'de> Deserialize<'de> for DeliveryMode {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        by_name(d, "ipc.delivery", &[("lossless", Self::Lossless), ("drop-newest", Self::DropNewest)])
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
        if i.subscriber_buffer == 0 {
            return Err(ConfigError("ipc.subscriber_buffer must be at least 1".into()));
        }
        let delivery = match i.delivery {
            DeliveryMode::Lossless => {
                Delivery::Lossless { give_up_after: (i.give_up_ms > 0).then(|| Duration::from_millis(i.give_up_ms)) }
            }
            DeliveryMode::DropNewest => Delivery::DropNewest,
        };
        Ok(IpcSettings {
            names: ServiceNames::with_prefix(prefix),
            subscriber_buffer: i.subscriber_buffer,
            wait_mode: i.wait,
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
