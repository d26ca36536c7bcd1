//! A pass-through responder: answers every raw sample with a `CompSample` of the same `seq`,
//! the rate unchanged and zero drift (status "no model yet"). It stands in for the daemon in
//! tests, benches and client development, and is the baseline of the daemon's latency.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use super::domain::IpcDomain;
use super::error::IpcResult;
use super::node::IpcNode;
use super::settings::IpcSettings;
use super::wire::{CompSample, STATUS_NO_MODEL};

/// Longest single wait of the echo loop, so that `stop` is seen promptly.
const POLL: Duration = Duration::from_millis(20);

/// Runs the echo until `stop` is set or `limit` samples were answered; returns how many.
/// `ready` is set once the ports exist (so a caller can start publishing without losing samples).
pub fn run_echo(
    domain: &IpcDomain,
    settings: &IpcSettings,
    stop: &AtomicBool,
    ready: &AtomicBool,
    limit: Option<u64>,
) -> IpcResult<u64> {
    let node = IpcNode::new(domain, "gyrocomp_echo", settings.clone())?;
    let input = node.raw_subscriber()?;
    let output = node.comp_publisher()?;
    ready.store(true, Ordering::Release);
    let mut answered = 0u64;
    while !stop.load(Ordering::Acquire) && limit.is_none_or(|l| answered < l) {
        if let Some(raw) = input.recv_timeout(POLL)? {
            output.send(CompSample::passthrough(&raw, STATUS_NO_MODEL))?;
            answered += 1;
        }
    }
    tracing::debug!(answered, "echo stopped");
    Ok(answered)
}
