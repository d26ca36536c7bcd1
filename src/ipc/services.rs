//! Opening (or creating) the gyrocomp services.
//!
//! Each pub-sub service comes with an event service of the same name: a sender notifies it after
//! each send, a receiver in [`super::WaitMode::Event`] sleeps on it.
//!
//! Quality of service (iceoryx2 0.10.0):
//! - `gyrocomp/raw` and `gyrocomp/compensated`: `enable_safe_overflow(false)` (a full subscriber
//!   buffer is never overwritten; the publisher's [`super::Delivery`] decides between waiting and
//!   dropping), `subscriber_max_buffer_size(subscriber_buffer)`, history 0, and
//!   `max_publishers(1)` ([`super::holders`]: one daemon per service prefix, one INS per daemon).
//! - `gyrocomp/status`: safe overflow on (a slow status reader loses the oldest reports, the daemon
//!   never waits for it), history 1 (a late subscriber gets the latest report), buffer
//!   [`STATUS_BUFFER`].
//!
//! A setting given to the builder is verified when the service already exists, so a peer that created
//! it with safe overflow on, or a smaller buffer, is refused with a clear error instead of silently
//! getting other semantics. The Python client uses the same settings.
//!
//! A subscriber attaches to a publisher's connection lazily (see [`super::client`]); until then a
//! lossless publisher waits only while that subscriber's buffer has room, so a client primes the
//! stream with [`super::prime`] before sending fast.

use std::fmt::Debug;

use iceoryx2::node::Node;
use iceoryx2::prelude::{ServiceName, ZeroCopySend, ipc};
use iceoryx2::service::port_factory::{event, publish_subscribe};

use super::error::{IpcError, IpcResult};

/// Subscriber buffer of the status service.
pub const STATUS_BUFFER: usize = 64;

/// A pub-sub service of payload `T` and its event service.
pub(crate) struct ServicePair<T: Debug + ZeroCopySend + 'static> {
    pub(crate) name: String,
    pub(crate) data: publish_subscribe::PortFactory<ipc::Service, T, ()>,
    pub(crate) event: event::PortFactory<ipc::Service>,
}

/// How a pub-sub service is created or what it must offer when opened.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Qos {
    /// Backpressure-capable stream with this subscriber buffer.
    Stream { buffer: usize },
    /// Overwriting report channel with history 1.
    Reports,
}

fn service_name(name: &str) -> IpcResult<ServiceName> {
    ServiceName::new(name).map_err(|e| IpcError::iox("parse service name", name, e))
}

/// Opens the pub-sub service `name` of payload `T` and its event service, creating them if needed.
pub(crate) fn open_pair<T: Debug + ZeroCopySend + 'static>(
    node: &Node<ipc::Service>,
    name: &str,
    qos: Qos,
) -> IpcResult<ServicePair<T>> {
    let sname = service_name(name)?;
    let builder = node.service_builder(&sname).publish_subscribe::<T>();
    let builder = match qos {
        Qos::Stream { buffer } => builder
            .enable_safe_overflow(false)
            .subscriber_max_buffer_size(buffer.max(1))
            .history_size(0)
            .max_publishers(super::holders::STREAM_MAX_PUBLISHERS),
        Qos::Reports => builder.enable_safe_overflow(true).subscriber_max_buffer_size(STATUS_BUFFER).history_size(1),
    };
    let data =
        builder.open_or_create().map_err(|e| IpcError::iox("open or create publish-subscribe service", name, e))?;
    let event = node
        .service_builder(&sname)
        .event()
        .open_or_create()
        .map_err(|e| IpcError::iox("open or create event service", name, e))?;
    tracing::debug!(service = name, ?qos, "iceoryx2 services ready");
    Ok(ServicePair { name: name.to_owned(), data, event })
}
