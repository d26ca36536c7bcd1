//! Sending ports: a publisher plus the notifier of the service's event twin.

use std::fmt::Debug;
use std::time::{Duration, Instant};

use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::publisher::{Publisher, PublisherCreateError};
use iceoryx2::port::{BackpressureAction, BackpressureInfo};
use iceoryx2::prelude::PortFactory as _;
use iceoryx2::prelude::{BackpressureStrategy, ZeroCopySend, ipc};
use iceoryx2::service::port_factory::publish_subscribe::PortFactory;

use super::error::{IpcError, IpcResult};
use super::services::ServicePair;
use super::settings::Delivery;

/// Publishes values of `T` on one service and wakes its event listeners.
pub struct Sender<T: Debug + ZeroCopySend + Copy + 'static> {
    name: String,
    publisher: Publisher<ipc::Service, T, ()>,
    notifier: Notifier<ipc::Service>,
    notify_each: bool,
    service: PortFactory<ipc::Service, T, ()>,
}

impl<T: Debug + ZeroCopySend + Copy + 'static> Sender<T> {
    pub(crate) fn new(pair: ServicePair<T>, delivery: Delivery, notify_each: bool) -> IpcResult<Self> {
        let builder = pair.data.publisher_builder();
        let builder = match delivery {
            Delivery::Lossless { give_up_after: None } => {
                builder.backpressure_strategy(BackpressureStrategy::RetryUntilDelivered)
            }
            Delivery::Lossless { give_up_after: Some(limit) } => builder
                .backpressure_strategy(BackpressureStrategy::RetryUntilDelivered)
                .set_backpressure_handler(move |info: &BackpressureInfo| {
                    if info.elapsed_time >= limit {
                        BackpressureAction::DiscardDataAndFail
                    } else {
                        BackpressureAction::Retry
                    }
                }),
            Delivery::DropNewest => builder.backpressure_strategy(BackpressureStrategy::DiscardData),
        };
        let publisher = builder.create().map_err(|e| match e {
            PublisherCreateError::ExceedsMaxSupportedPublishers => {
                IpcError::PublisherTaken { service: pair.name.clone(), holders: Vec::new() }
            }
            e => IpcError::iox("create publisher", &pair.name, e),
        })?;
        let notifier =
            pair.event.notifier_builder().create().map_err(|e| IpcError::iox("create notifier", &pair.name, e))?;
        Ok(Self { name: pair.name, publisher, notifier, notify_each, service: pair.data })
    }

    /// Sends `value` and, unless notifications are off, wakes the listeners.
    /// An error means at least one subscriber did not get it (see [`Delivery`]).
    pub fn send(&self, value: T) -> IpcResult<()> {
        self.send_quiet(value)?;
        if self.notify_each {
            self.notify()?;
        }
        Ok(())
    }

    /// Sends `value` without notifying (batch several, then call [`Sender::notify`] once).
    /// Returns how many subscribers received it.
    pub fn send_quiet(&self, value: T) -> IpcResult<usize> {
        let sample = self.publisher.loan_uninit().map_err(|e| IpcError::iox("loan sample", &self.name, e))?;
        sample.write_payload(value).send().map_err(|e| IpcError::iox("send sample", &self.name, e))
    }

    /// Whether [`Sender::send`] notifies after each sample (the settings' `notify`).
    pub fn notifies(&self) -> bool {
        self.notify_each
    }

    /// Wakes the listeners of the event service.
    pub fn notify(&self) -> IpcResult<()> {
        self.notifier.notify().map(|_| ()).map_err(|e| IpcError::iox("notify", &self.name, e))
    }

    /// Connects subscribers that appeared since the last send (sends do this by themselves).
    pub fn update_connections(&self) -> IpcResult<()> {
        use iceoryx2::port::update_connections::UpdateConnections;
        self.publisher.update_connections().map_err(|e| IpcError::iox("update connections", &self.name, e))
    }

    /// How many publishers the service has now (any process, this one included).
    pub fn publisher_count(&self) -> usize {
        self.service.dynamic_config().number_of_publishers()
    }

    pub(crate) fn port_factory(&self) -> &PortFactory<ipc::Service, T, ()> {
        &self.service
    }

    /// How many subscribers the service has now (any process).
    pub fn subscriber_count(&self) -> usize {
        self.service.dynamic_config().number_of_subscribers()
    }

    /// Waits until the service has at least one subscriber; returns whether it has. Samples sent
    /// before a subscriber exists are lost (history 0), so a client calls this before sending.
    pub fn wait_for_subscriber(&self, timeout: Duration) -> bool {
        let start = Instant::now();
        while self.subscriber_count() == 0 {
            if start.elapsed() >= timeout {
                return false;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        true
    }

    /// The service name.
    pub fn service(&self) -> &str {
        &self.name
    }
}
