//! Service names and quality-of-service settings of the gyrocomp services.

use std::time::Duration;

/// Default service-name prefix: services are `gyrocomp/raw`, `gyrocomp/compensated`, `gyrocomp/status`.
pub const DEFAULT_PREFIX: &str = "gyrocomp";

/// Default subscriber buffer (samples): absorbs a burst of two seconds of 1 kHz data.
pub const DEFAULT_SUBSCRIBER_BUFFER: usize = 2048;

/// The three pub-sub service names (each has an event service of the same name for wake-ups).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ServiceNames {
    /// Raw samples in (INS → daemon).
    pub raw: String,
    /// Compensated samples out (daemon → INS).
    pub compensated: String,
    /// Model events and counters (daemon → anyone).
    pub status: String,
}

impl ServiceNames {
    /// `<prefix>/raw`, `<prefix>/compensated`, `<prefix>/status`.
    pub fn with_prefix(prefix: &str) -> Self {
        let p = prefix.trim_end_matches('/');
        Self { raw: format!("{p}/raw"), compensated: format!("{p}/compensated"), status: format!("{p}/status") }
    }
}

impl Default for ServiceNames {
    fn default() -> Self {
        Self::with_prefix(DEFAULT_PREFIX)
    }
}

/// How a receiving port waits for the next sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WaitMode {
    /// Sleep on the event service until the sender notifies (default; no CPU while idle).
    #[default]
    Event,
    /// Poll the subscriber in a busy loop (lowest latency, one core at 100 %).
    Spin,
}

/// What a publisher does when a subscriber's buffer is full.
///
/// Every gyrocomp pub-sub service is created with safe overflow **off**
/// (`enable_safe_overflow(false)`), so a full subscriber buffer is never silently overwritten;
/// each publisher then decides between waiting and dropping.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Delivery {
    /// Wait until the subscriber makes room (iceoryx2 `BackpressureStrategy::RetryUntilDelivered`,
    /// through a backpressure handler that retries). After `give_up_after` the sample is dropped for
    /// that subscriber and `send` returns an error (`None` = wait forever). iceoryx2 itself stops
    /// waiting when the subscriber disconnects.
    Lossless {
        /// Longest wait for one full subscriber.
        give_up_after: Option<Duration>,
    },
    /// Never wait: a subscriber whose buffer is full misses the new sample
    /// (`BackpressureStrategy::DiscardData`). For a real-time INS that must never block.
    DropNewest,
}

impl Default for Delivery {
    fn default() -> Self {
        Self::Lossless { give_up_after: Some(Duration::from_secs(1)) }
    }
}

/// Settings shared by all ports a [`super::IpcNode`] creates.
#[derive(Debug, Clone, PartialEq)]
pub struct IpcSettings {
    /// Service names.
    pub names: ServiceNames,
    /// Buffer of each subscriber port, in samples. Services are created with
    /// `subscriber_max_buffer_size` equal to this; opening an existing service requires at least it.
    pub subscriber_buffer: usize,
    /// How receivers wait.
    pub wait_mode: WaitMode,
    /// What publishers do on a full subscriber buffer.
    pub delivery: Delivery,
    /// Whether publishers notify the event service after each send (needed by [`WaitMode::Event`]
    /// receivers; a pair that both spin may switch it off).
    pub notify: bool,
}

impl Default for IpcSettings {
    fn default() -> Self {
        Self {
            names: ServiceNames::default(),
            subscriber_buffer: DEFAULT_SUBSCRIBER_BUFFER,
            wait_mode: WaitMode::Event,
            delivery: Delivery::default(),
            notify: true,
        }
    }
}
