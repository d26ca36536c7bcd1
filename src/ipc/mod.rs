//! The iceoryx2 layer (the only module that knows iceoryx2): wire types, service names and
//! quality of service, private domains, and thin sending/receiving ports.
//!
//! - [`wire`]: `RawSample`, `CompSample`, `StatusSample` (`#[repr(C)]`, iceoryx2 type names).
//! - [`settings`]: service names, subscriber buffer, [`WaitMode`], [`Delivery`].
//! - [`domain`]: the default iceoryx2 domain or a private one (own prefix and root path).
//! - [`node`]: [`IpcNode`], which creates the ports ([`RawSubscriber`], [`CompPublisher`], …).
//! - [`holders`]: the stream services' single publisher, and naming who holds it.
//! - [`client`]: [`prime`], the start-up handshake a lossless client does before streaming.
//! - [`echo`]: a pass-through responder (tests, benches, client development).

pub mod client;
pub mod domain;
pub mod echo;
pub mod error;
pub mod holders;
pub mod node;
pub mod receiver;
pub mod sender;
pub mod services;
pub mod settings;
pub mod wire;

pub use client::prime;
pub use domain::IpcDomain;
pub use echo::run_echo;
pub use error::{IpcError, IpcResult};
pub use holders::{PublisherHolder, STREAM_MAX_PUBLISHERS};
pub use node::{
    CompPublisher, CompSubscriber, IpcNode, NodeCensus, RawPublisher, RawSubscriber, StatusPublisher, StatusSubscriber,
};
pub use receiver::Receiver;
pub use sender::Sender;
pub use settings::{DEFAULT_PREFIX, DEFAULT_SUBSCRIBER_BUFFER, Delivery, IpcSettings, ServiceNames, WaitMode};
pub use wire::{
    CompSample, RAW_FLAG_MOVING, RawSample, STATUS_GAP, STATUS_MOVING, STATUS_NO_MODEL, STATUS_REJECTED,
    STATUS_SENSOR_FAULT, StatusEvent, StatusSample,
};
