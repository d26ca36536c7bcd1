//! An iceoryx2 node in a domain, and the gyrocomp ports it creates.

use iceoryx2::node::{Node, NodeBuilder, NodeState};
use iceoryx2::prelude::{CallbackProgression, NodeName, SignalHandlingMode, ZeroCopySend, ipc};

use super::domain::IpcDomain;
use super::error::{IpcError, IpcResult};
use super::holders::{STREAM_MAX_PUBLISHERS, publisher_holders};
use super::receiver::Receiver;
use super::sender::Sender;
use super::services::{Qos, STATUS_BUFFER, open_pair};
use super::settings::{Delivery, IpcSettings};
use super::wire::{CompSample, RawSample, StatusSample};

/// Daemon side: raw samples in.
pub type RawSubscriber = Receiver<RawSample>;
/// Daemon side: compensated samples out, one per raw sample.
pub type CompPublisher = Sender<CompSample>;
/// Daemon side: model events and counters out.
pub type StatusPublisher = Sender<StatusSample>;
/// Client side (INS, replay, tests): raw samples out.
pub type RawPublisher = Sender<RawSample>;
/// Client side: compensated samples in.
pub type CompSubscriber = Receiver<CompSample>;
/// Client side: model events and counters in.
pub type StatusSubscriber = Receiver<StatusSample>;

/// How many nodes of a domain are in each state ([`IpcNode::dead_nodes`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NodeCensus {
    /// Nodes whose process is alive.
    pub alive: usize,
    /// Nodes whose process died without cleaning up.
    pub dead: usize,
    /// Nodes this process may not inspect.
    pub inaccessible: usize,
    /// Nodes with missing or inconsistent files.
    pub undefined: usize,
}

/// An iceoryx2 node plus the settings of the ports it creates.
///
/// Ports outlive nothing: they keep their services alive by themselves, so they may be moved
/// out and the node dropped. Ports are not `Send`: create them on the thread that uses them.
/// The node installs no signal handler (iceoryx2 `SignalHandlingMode::Disabled`); the daemon
/// handles termination itself.
pub struct IpcNode {
    node: Node<ipc::Service>,
    settings: IpcSettings,
}

impl IpcNode {
    /// Creates a node called `name` in `domain`.
    pub fn new(domain: &IpcDomain, name: &str, settings: IpcSettings) -> IpcResult<Self> {
        let node_name = NodeName::new(name).map_err(|e| IpcError::iox("parse node name", name, e))?;
        let node = NodeBuilder::new()
            .name(&node_name)
            .config(domain.config())
            .signal_handling_mode(SignalHandlingMode::Disabled)
            .create::<ipc::Service>()
            .map_err(|e| IpcError::iox("create node", name, e))?;
        tracing::debug!(node = name, prefix = %domain.prefix(), root = %domain.root_path(), "iceoryx2 node created");
        Ok(Self { node, settings })
    }

    /// Nodes of `domain` whose process died without cleaning up (iceoryx2's dead-node
    /// detection: the node's monitor lock is no longer held), and nodes whose state this process
    /// may not inspect (another user's).
    pub fn dead_nodes(domain: &IpcDomain) -> IpcResult<NodeCensus> {
        let mut census = NodeCensus::default();
        Node::<ipc::Service>::list(domain.config(), |state| {
            match state {
                NodeState::Alive(_) => census.alive += 1,
                NodeState::Dead(_) => census.dead += 1,
                NodeState::Inaccessible(_) => census.inaccessible += 1,
                NodeState::Undefined(_) => census.undefined += 1,
            }
            CallbackProgression::Continue
        })
        .map_err(|e| IpcError::iox("list nodes", domain.prefix(), e))?;
        Ok(census)
    }

    /// Removes the stale resources of every dead node of the domain (iceoryx2
    /// `Node::try_cleanup_dead_nodes`: their shared memory, and their ports from every service,
    /// so that lossless publishers stop waiting for their subscribers). Returns (cleaned,
    /// failed); a node of another user fails for want of permission.
    pub fn cleanup_dead_nodes(&self) -> (u64, u64) {
        let state = self.node.try_cleanup_dead_nodes();
        (state.cleanups, state.failed_cleanups)
    }

    /// The settings ports are created with.
    pub fn settings(&self) -> &IpcSettings {
        &self.settings
    }

    fn stream(&self) -> Qos {
        Qos::Stream { buffer: self.settings.subscriber_buffer }
    }

    /// Subscribes to the raw service (daemon input).
    pub fn raw_subscriber(&self) -> IpcResult<RawSubscriber> {
        let pair = open_pair::<RawSample>(&self.node, &self.settings.names.raw, self.stream())?;
        Receiver::new(pair, self.settings.subscriber_buffer, self.settings.wait_mode)
    }

    /// Publishes on the compensated service (daemon output). The service has one publisher
    /// ([`super::holders`]): while another daemon serves the same service prefix this fails with
    /// [`IpcError::PublisherTaken`] naming it.
    pub fn comp_publisher(&self) -> IpcResult<CompPublisher> {
        self.stream_sender(&self.settings.names.compensated)
    }

    /// Publishes on the status service (never waits for readers: the service overwrites).
    pub fn status_publisher(&self) -> IpcResult<StatusPublisher> {
        let pair = open_pair::<StatusSample>(&self.node, &self.settings.names.status, Qos::Reports)?;
        Sender::new(pair, Delivery::DropNewest, self.settings.notify)
    }

    /// Publishes on the raw service (client side). The service has one publisher
    /// ([`super::holders`]): while another client streams to the same daemon this fails with
    /// [`IpcError::PublisherTaken`] naming it.
    pub fn raw_publisher(&self) -> IpcResult<RawPublisher> {
        self.stream_sender(&self.settings.names.raw)
    }

    /// How many publishers the stream service `name` allows (1 when gyrocomp created it; a peer
    /// that created it first may have allowed more).
    pub fn stream_publisher_limit(&self, name: &str) -> IpcResult<usize> {
        let pair = open_pair::<RawSample>(&self.node, name, self.stream())?;
        use iceoryx2::prelude::PortFactory as _;
        Ok(pair.data.static_config().max_publishers())
    }

    /// The one publisher of a stream service. When the service already has one, dead nodes are
    /// cleaned (a killed client or daemon keeps its port until then) and creating is tried once
    /// more; if it still has one, the error names its holder. A service a peer created with
    /// room for more publishers is held to one all the same: a publisher that finds another one
    /// beside it is dropped again with the same error.
    fn stream_sender<T: std::fmt::Debug + ZeroCopySend + Copy + 'static>(&self, name: &str) -> IpcResult<Sender<T>> {
        let open = || {
            Sender::new(open_pair::<T>(&self.node, name, self.stream())?, self.settings.delivery, self.settings.notify)
        };
        let mut sender = open();
        if matches!(sender, Err(IpcError::PublisherTaken { .. })) && self.cleanup_dead_nodes().0 > 0 {
            sender = open();
        }
        let taken = |holders| IpcError::PublisherTaken { service: name.to_owned(), holders };
        match sender {
            Err(IpcError::PublisherTaken { .. }) => {
                let pair = open_pair::<T>(&self.node, name, self.stream())?;
                Err(taken(publisher_holders(&self.node, &pair.data, None)))
            }
            Ok(s) if s.publisher_count() > STREAM_MAX_PUBLISHERS => {
                Err(taken(publisher_holders(&self.node, s.port_factory(), Some(self.node.id().value()))))
            }
            other => other,
        }
    }

    /// Subscribes to the compensated service (client side).
    pub fn comp_subscriber(&self) -> IpcResult<CompSubscriber> {
        let pair = open_pair::<CompSample>(&self.node, &self.settings.names.compensated, self.stream())?;
        Receiver::new(pair, self.settings.subscriber_buffer, self.settings.wait_mode)
    }

    /// Subscribes to the status service.
    pub fn status_subscriber(&self) -> IpcResult<StatusSubscriber> {
        let pair = open_pair::<StatusSample>(&self.node, &self.settings.names.status, Qos::Reports)?;
        Receiver::new(pair, STATUS_BUFFER, self.settings.wait_mode)
    }
}
