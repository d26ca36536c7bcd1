//! Receiving ports: a subscriber plus (in event mode) the listener of the service's event twin.

use std::fmt::Debug;
use std::time::{Duration, Instant};

use iceoryx2::port::listener::{Listener, ListenerWaitError};
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::{ZeroCopySend, ipc};

use super::error::{IpcError, IpcResult};
use super::services::ServicePair;
use super::settings::WaitMode;

/// Longest single sleep on the event service. Checking for samples also attaches this subscriber
/// to publishers that appeared meanwhile (iceoryx2 connects a subscriber lazily, and treats a
/// not-yet-attached one as gone once its buffer is full), so an idle receiver looks this often.
const ATTACH_POLL: Duration = Duration::from_millis(10);

/// Shortest single sleep on the event service. iceoryx2 0.10 hands the sleep to the kernel as a
/// `SO_RCVTIMEO` `timeval` truncated to whole microseconds, and a zero `timeval` means *no
/// timeout*: a remaining wait under 1 µs would block until the next event, for ever on an idle
/// service (seen: a test's echo thread stuck 15 min in `UnixDatagramReceiver::timed_receive`).
/// Sleeping at least this long overshoots a deadline by at most 1 ms instead.
pub(crate) const MIN_NAP: Duration = Duration::from_millis(1);

/// The length of one sleep on the event service when `left` of the caller's timeout remains:
/// at most [`ATTACH_POLL`], never under [`MIN_NAP`] (see there why).
pub(crate) fn nap(left: Duration) -> Duration {
    left.min(ATTACH_POLL).max(MIN_NAP)
}

/// Receives values of `T` from one service; waits by event or by spinning ([`WaitMode`]).
pub struct Receiver<T: Debug + ZeroCopySend + Copy + 'static> {
    name: String,
    subscriber: Subscriber<ipc::Service, T, ()>,
    listener: Option<Listener<ipc::Service>>,
}

impl<T: Debug + ZeroCopySend + Copy + 'static> Receiver<T> {
    pub(crate) fn new(pair: ServicePair<T>, buffer: usize, mode: WaitMode) -> IpcResult<Self> {
        let subscriber = pair
            .data
            .subscriber_builder()
            .buffer_size(buffer.max(1))
            .create()
            .map_err(|e| IpcError::iox("create subscriber", &pair.name, e))?;
        let listener = match mode {
            WaitMode::Event => Some(
                pair.event.listener_builder().create().map_err(|e| IpcError::iox("create listener", &pair.name, e))?,
            ),
            WaitMode::Spin => None,
        };
        Ok(Self { name: pair.name, subscriber, listener })
    }

    /// The next value if one is waiting.
    pub fn try_recv(&self) -> IpcResult<Option<T>> {
        let sample = self.subscriber.receive().map_err(|e| IpcError::iox("receive", &self.name, e))?;
        Ok(sample.map(|s| *s))
    }

    /// The next value, waiting up to `timeout` for one (`None` on timeout).
    pub fn recv_timeout(&self, timeout: Duration) -> IpcResult<Option<T>> {
        if let Some(v) = self.try_recv()? {
            return Ok(Some(v));
        }
        if self.wait(timeout)? { self.try_recv() } else { Ok(None) }
    }

    /// Appends every waiting value to `out` (at most `max`); returns how many.
    pub fn drain_into(&self, out: &mut Vec<T>, max: usize) -> IpcResult<usize> {
        let mut n = 0;
        while n < max {
            match self.try_recv()? {
                Some(v) => {
                    out.push(v);
                    n += 1;
                }
                None => break,
            }
        }
        Ok(n)
    }

    /// Waits until a value is waiting or `timeout` passed; returns whether one is waiting.
    /// Event mode sleeps on the event service (spurious or stale wake-ups are absorbed; it looks
    /// at least every 10 ms and sleeps at least 1 ms, so it may overshoot `timeout` by up to 1 ms;
    /// a signal delivered to the process ends the wait early); spin mode polls.
    pub fn wait(&self, timeout: Duration) -> IpcResult<bool> {
        let start = Instant::now();
        let mut spins: u32 = 0;
        loop {
            if self.has_samples()? {
                return Ok(true);
            }
            let left = timeout.saturating_sub(start.elapsed());
            if left.is_zero() {
                return Ok(false);
            }
            match &self.listener {
                Some(listener) => match listener.timed_wait(|_| {}, nap(left)) {
                    Ok(_) => {}
                    // A signal (SIGHUP, SIGTERM, …) cut the sleep short: not an error; return so
                    // that the caller sees it promptly.
                    Err(ListenerWaitError::InterruptSignal) => return self.has_samples(),
                    Err(e) => return Err(IpcError::iox("wait on event", &self.name, e)),
                },
                None => {
                    spins = spins.wrapping_add(1);
                    if spins.is_multiple_of(4096) {
                        std::thread::yield_now();
                    } else {
                        std::hint::spin_loop();
                    }
                }
            }
        }
    }

    /// Whether a value is waiting.
    pub fn has_samples(&self) -> IpcResult<bool> {
        self.subscriber.has_samples().map_err(|e| IpcError::iox("check for samples", &self.name, e))
    }

    /// The wait mode this receiver was created with.
    pub fn wait_mode(&self) -> WaitMode {
        if self.listener.is_some() { WaitMode::Event } else { WaitMode::Spin }
    }

    /// The service name.
    pub fn service(&self) -> &str {
        &self.name
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_nap_is_never_shorter_than_a_microsecond_timeval_can_hold() {
        // A zero SO_RCVTIMEO blocks for ever: every remaining wait, however small, maps to a
        // sleep of at least 1 ms, and long waits are cut to the attach poll.
        for left_ns in [1u64, 999, 1_000, 999_999, 1_000_000, 5_000_000, 10_000_000, 3_000_000_000] {
            let n = nap(Duration::from_nanos(left_ns));
            assert!(n.as_micros() >= 1_000, "{left_ns} ns -> {n:?}");
            assert!(n <= ATTACH_POLL, "{left_ns} ns -> {n:?}");
        }
        assert_eq!(nap(Duration::from_millis(4)), Duration::from_millis(4));
    }
}
