//! The replay loop: every sample of a recording out on the raw service, one answer per sample
//! back, lossless.
//!
//! Flow control: at most `window` samples are in flight (sent, not yet answered), well below the
//! services' subscriber buffer, so neither side's buffer can fill — the daemon never has to wait
//! for replay, and replay waits for answers instead of dropping (backpressure). Samples go out in
//! batches with one event notification each (`send_quiet` + `notify`), not one per sample.
//! The first sample goes through [`prime`], which waits until both directions are attached.
//!
//! Answers must come in order, one per sample, with the sample's `seq` (= its row index). An
//! answer with another `seq` is counted as `unexpected` and ignored (another publisher on the same
//! services). If no answer arrives for `timeout`, the replay stops: the missing samples are
//! reported as `dropped`, never silently lost.

use std::time::{Duration, Instant};

use gyrocomp::daemon::convert::{output_from_comp, raw_from_input};
use gyrocomp::io::Recording;
use gyrocomp::ipc::{CompSample, IpcError, prime};
use gyrocomp::stream::OutputSample;

use crate::connect::Client;

/// How fast samples are sent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Pacing {
    /// As fast as the daemon answers (`--max`).
    Max,
    /// At the recording's own rate times this factor (`--speed X`): sample i is due
    /// `(t_i − t_0) / X` seconds after the start.
    Speed(f64),
}

/// Settings of one replay.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReplayOptions {
    /// Pacing.
    pub pacing: Pacing,
    /// Longest wait for the next answer before the replay gives up.
    pub timeout: Duration,
    /// Most samples in flight; clamped to half the subscriber buffer.
    pub window: usize,
}

impl Default for ReplayOptions {
    fn default() -> Self {
        Self { pacing: Pacing::Max, timeout: Duration::from_secs(10), window: 1024 }
    }
}

/// Samples sent per event notification.
const SEND_BATCH: usize = 64;

/// What a replay collected.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplayResult {
    /// Answer of each sample in recording order; shorter than the recording when answers are
    /// missing (the rest were dropped).
    pub outputs: Vec<OutputSample>,
    /// Samples published.
    pub sent: usize,
    /// Answers with a `seq` that was not the next expected one (ignored).
    pub unexpected: usize,
    /// From the first send to the last answer.
    pub duration: Duration,
}

impl ReplayResult {
    /// Samples sent but never answered.
    pub fn dropped(&self) -> usize {
        self.sent - self.outputs.len()
    }
}

/// Why a replay failed.
#[derive(Debug, thiserror::Error)]
pub enum ReplayError {
    /// The recording has no samples.
    #[error("the recording has no samples")]
    Empty,
    /// The pacing factor is not a positive finite number.
    #[error("--speed must be a positive finite number, not {0}")]
    Speed(f64),
    /// iceoryx2 failed (no daemon answered the first sample, a port error).
    #[error(transparent)]
    Ipc(#[from] IpcError),
}

/// Replays `rec` through the daemon behind `client`; `progress(answered)` is called after each
/// batch of answers.
pub fn replay(
    rec: &Recording,
    client: &Client,
    options: &ReplayOptions,
    mut progress: impl FnMut(usize),
) -> Result<ReplayResult, ReplayError> {
    let n = rec.len();
    if n == 0 {
        return Err(ReplayError::Empty);
    }
    if let Pacing::Speed(x) = options.pacing
        && !(x > 0.0 && x.is_finite())
    {
        return Err(ReplayError::Speed(x));
    }
    let window = options.window.clamp(1, (client.buffer / 2).max(1));
    let t0 = rec.t_s()[0];
    let due = |i: usize| match options.pacing {
        Pacing::Max => Duration::ZERO,
        Pacing::Speed(x) => Duration::from_secs_f64(((rec.t_s()[i] - t0) / x).max(0.0)),
    };

    let start = Instant::now();
    let first = prime(&client.raw, &client.comp, raw_from_input(&rec.input(0)), options.timeout)?;
    let mut outputs = Vec::with_capacity(n);
    outputs.push(output_from_comp(&first));
    let (mut sent, mut unexpected) = (1usize, 0usize);
    let mut answers: Vec<CompSample> = Vec::with_capacity(window);
    let mut last_answer = Instant::now();
    while outputs.len() < n {
        // Send what is due, within the window, in notified batches.
        let mut batch = 0;
        while sent < n && sent - outputs.len() < window && start.elapsed() >= due(sent) {
            client.raw.send_quiet(raw_from_input(&rec.input(sent)))?;
            sent += 1;
            batch += 1;
            if batch == SEND_BATCH {
                client.raw.notify()?;
                batch = 0;
            }
        }
        if batch > 0 {
            client.raw.notify()?;
        }
        // Collect the answers waiting now.
        answers.clear();
        client.comp.drain_into(&mut answers, window)?;
        for a in &answers {
            if a.seq == outputs.len() as u64 && outputs.len() < sent {
                outputs.push(output_from_comp(a));
            } else {
                unexpected += 1;
            }
        }
        if !answers.is_empty() {
            last_answer = Instant::now();
            progress(outputs.len());
            continue;
        }
        if outputs.len() < sent && last_answer.elapsed() >= options.timeout {
            tracing::warn!(
                answered = outputs.len(),
                sent,
                timeout = ?options.timeout,
                "no answer from the daemon within the timeout; stopping"
            );
            break;
        }
        // Nothing waiting: sleep until an answer comes or the next sample is due.
        let mut wait = options.timeout.saturating_sub(last_answer.elapsed());
        if sent < n && sent - outputs.len() < window {
            wait = wait.min(due(sent).saturating_sub(start.elapsed()));
        }
        if outputs.len() < sent {
            client.comp.wait(wait)?;
        } else {
            std::thread::sleep(wait);
        }
    }
    let duration = start.elapsed();
    progress(outputs.len());
    Ok(ReplayResult { outputs, sent, unexpected, duration })
}
