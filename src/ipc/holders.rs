//! Single-publisher services: who holds the publisher of a stream service.
//!
//! `gyrocomp/raw` and `gyrocomp/compensated` are created with `max_publishers(1)`
//! (docs/design.md "One daemon per service prefix, one INS per daemon"): the compensated
//! publisher is the daemon's, so a second daemon with the same service prefix cannot create its
//! own, and the raw publisher is the one INS client's, so a second client cannot interleave its
//! samples with the first one's. When creating the publisher fails because the service already
//! has one, `publisher_holders` names the holder from the service's dynamic configuration (the
//! publisher's node id) and iceoryx2's node listing (`Node::list`: the node's name, process id
//! and executable, and whether its process still lives).

use std::fmt::Debug;

use iceoryx2::node::{Node, NodeState, NodeView};
use iceoryx2::prelude::{CallbackProgression, ZeroCopySend, ipc};
use iceoryx2::service::port_factory::publish_subscribe::PortFactory;

/// The most publishers a gyrocomp stream service allows.
pub const STREAM_MAX_PUBLISHERS: usize = 1;

/// A node that holds a publisher of a service, as far as the node listing tells.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PublisherHolder {
    /// iceoryx2's unique node id (hex).
    pub node_id: String,
    /// The node's name (empty when its details could not be read).
    pub node_name: String,
    /// The process id of the node's process (`None` when unknown).
    pub pid: Option<i32>,
    /// The executable of the node's process (empty when unknown).
    pub executable: String,
    /// Whether the node's process is alive (`false`: dead, or its state is not readable).
    pub alive: bool,
}

impl std::fmt::Display for PublisherHolder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let name = if self.node_name.is_empty() { "?" } else { &self.node_name };
        write!(f, "iceoryx2 node `{name}` (id {}", self.node_id)?;
        if let Some(pid) = self.pid {
            write!(f, ", pid {pid}")?;
        }
        if !self.executable.is_empty() {
            write!(f, ", executable {}", self.executable)?;
        }
        f.write_str(if self.alive { ")" } else { ", not alive)" })
    }
}

/// The nodes holding a publisher of `service`, except the node whose id value is `own` (the
/// caller's, if it holds one too). Nodes missing from the listing are still returned, with what the id alone tells.
pub(crate) fn publisher_holders<T: Debug + ZeroCopySend + 'static>(
    node: &Node<ipc::Service>,
    service: &PortFactory<ipc::Service, T, ()>,
    own: Option<u128>,
) -> Vec<PublisherHolder> {
    use iceoryx2::prelude::PortFactory as _;
    let mut ids = Vec::new();
    service.dynamic_config().list_publishers(|details| {
        if own != Some(details.node_id.value()) {
            ids.push(details.node_id);
        }
        CallbackProgression::Continue
    });
    let mut holders: Vec<PublisherHolder> = ids
        .iter()
        .map(|id| PublisherHolder {
            node_id: id.to_string(),
            node_name: String::new(),
            pid: id.pid::<ipc::Service>().ok().map(|p| p.value()),
            executable: String::new(),
            alive: false,
        })
        .collect();
    let listed = Node::<ipc::Service>::list(node.config(), |state| {
        let (view_id, details, alive) = match &state {
            NodeState::Alive(v) => (*v.id(), v.details().clone(), true),
            NodeState::Dead(v) => (*v.id(), v.details().clone(), false),
            NodeState::Inaccessible(_) | NodeState::Undefined(_) => return CallbackProgression::Continue,
        };
        if let Some(h) = holders.iter_mut().find(|h| h.node_id == view_id.to_string()) {
            h.alive = alive;
            if let Some(d) = details {
                h.node_name = d.name().as_str().to_owned();
                h.pid = Some(d.process_id().value());
                h.executable = d.executable().to_string();
            }
        }
        CallbackProgression::Continue
    });
    if let Err(e) = listed {
        tracing::debug!(error = ?e, "listing iceoryx2 nodes failed; holders named by id only");
    }
    holders
}

/// The holders as one line of text ("unknown holder" when there is none).
pub fn describe(holders: &[PublisherHolder]) -> String {
    if holders.is_empty() {
        return "an unknown holder".into();
    }
    holders.iter().map(ToString::to_string).collect::<Vec<_>>().join("; ")
}
