//! Client-side start-up: making sure both directions are attached before streaming.
//!
//! iceoryx2 0.10 attaches a subscriber to a publisher's connection lazily, the first time the
//! subscriber looks for samples after the publisher appeared. Until then the publisher queues
//! samples for it, but once that buffer is full it treats the subscriber as gone and drops
//! (even a lossless publisher: it waits only for attached subscribers). A client that streams
//! faster than the daemon wakes up could therefore lose the start of its stream. [`prime`] sends
//! one sample and waits for its answer: after that both subscribers (the daemon's raw one and the
//! client's compensated one) are attached and the stream is lossless.

use std::time::{Duration, Instant};

use super::error::{IpcError, IpcResult};
use super::node::{CompSubscriber, RawPublisher};
use super::wire::{CompSample, RawSample};

/// Waits for a subscriber on the raw service, sends `first` and waits for the `CompSample` with
/// the same `seq` (answers to other `seq`s are skipped). Errors if none comes within `timeout`.
pub fn prime(raw: &RawPublisher, comp: &CompSubscriber, first: RawSample, timeout: Duration) -> IpcResult<CompSample> {
    let start = Instant::now();
    if !raw.wait_for_subscriber(timeout) {
        return Err(IpcError::NoPeer(format!("no subscriber on `{}` within {timeout:?}", raw.service())));
    }
    raw.send(first)?;
    loop {
        let left = timeout.saturating_sub(start.elapsed());
        match comp.recv_timeout(left)? {
            Some(answer) if answer.seq == first.seq => return Ok(answer),
            Some(_) => continue,
            None => {
                return Err(IpcError::NoPeer(format!(
                    "no answer to seq {} on `{}` within {timeout:?}",
                    first.seq,
                    comp.service()
                )));
            }
        }
    }
}
