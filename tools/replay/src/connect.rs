//! The replay client's iceoryx2 ports in the domain and services of a configuration.

use std::time::{Duration, Instant};

use gyrocomp::config::{Config, ConfigError, DomainChoice};
use gyrocomp::ipc::{CompSubscriber, Delivery, IpcDomain, IpcError, IpcNode, RawPublisher};

/// Why the client could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum ClientError {
    /// The configuration's `[ipc]` section is invalid (the message names the key).
    #[error("{0}")]
    Config(#[from] ConfigError),
    /// iceoryx2 refused a port or the domain.
    #[error(transparent)]
    Ipc(#[from] IpcError),
}

/// The replay side of the services: a raw publisher and a compensated subscriber.
pub struct Client {
    /// Publishes the recording's samples on `<prefix>/raw`.
    pub raw: RawPublisher,
    /// Receives the daemon's answers on `<prefix>/compensated`.
    pub comp: CompSubscriber,
    /// The subscriber buffer of the services (bounds the samples in flight).
    pub buffer: usize,
    _node: IpcNode,
}

impl Client {
    /// Opens (or creates) the services of `config` in its iceoryx2 domain. The raw publisher is
    /// lossless and gives up on one sample after `give_up` (the daemon stopped draining); the
    /// daemon's own `[ipc] delivery` governs the answers.
    pub fn connect(config: &Config, give_up: Duration) -> Result<Self, ClientError> {
        let domain = match config.ipc_domain()? {
            DomainChoice::Global => IpcDomain::global(),
            DomainChoice::Private { prefix, root } => IpcDomain::private(&prefix, &root)?,
        };
        let mut settings = config.ipc_settings()?;
        settings.delivery = Delivery::Lossless { give_up_after: Some(give_up) };
        let buffer = settings.subscriber_buffer;
        let node = IpcNode::new(&domain, "replay", settings)?;
        let raw = node.raw_publisher()?;
        let comp = node.comp_subscriber()?;
        Ok(Self { raw, comp, buffer, _node: node })
    }

    /// Whether a daemon (a subscriber of the raw service) appears within `timeout`.
    pub fn daemon_running(&self, timeout: Duration) -> bool {
        let start = Instant::now();
        loop {
            if self.raw.subscriber_count() > 0 {
                return true;
            }
            if start.elapsed() >= timeout {
                return false;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }
}
