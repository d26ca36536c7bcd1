//! The loop's per-sample work: answering each raw sample with its compensated one, waking the
//! listeners once per burst, status reports, model-swap events and snapshots handed to the
//! writer thread.

use std::time::{Duration, Instant};

use super::convert::{LoopCounters, comp_from_output, input_from_raw, status_sample};
use super::state::{SnapshotJob, SnapshotWriter};
use crate::ipc::{CompPublisher, IpcNode, RawSample, RawSubscriber, StatusEvent, StatusPublisher};
use crate::stream::Pipeline;
use crate::stream::snapshot::Compat;

/// Period of the `Periodic` status report.
const STATUS_PERIOD: Duration = Duration::from_secs(1);
/// Least time between two dead-node cleanups triggered by failed sends.
const CLEANUP_PERIOD: Duration = Duration::from_secs(1);

/// Everything the loop touches per sample.
pub(super) struct Worker {
    pub(super) pipeline: Pipeline,
    pub(super) node: IpcNode,
    /// The snapshot writer (`[state] dir` set) and the settings snapshots depend on.
    pub(super) snapshots: Option<SnapshotWriter>,
    pub(super) compat: Compat,
    /// `[state] every_s` and when the last snapshot was handed to the writer.
    pub(super) snapshot_every: Option<Duration>,
    pub(super) last_snapshot: Instant,
    pub(super) last_cleanup: Option<Instant>,
    pub(super) comp: CompPublisher,
    pub(super) status: StatusPublisher,
    pub(super) counters: LoopCounters,
    pub(super) started: Instant,
    pub(super) last_report: Instant,
    pub(super) reported_version: u64,
    pub(super) reported_failed: u64,
    pub(super) status_errors: u64,
    /// Retrain requests seen so far, and when the newest one was made.
    pub(super) requests_seen: u64,
    pub(super) request_at: Option<Instant>,
    /// Answers sent since the last notification of the compensated event service.
    pub(super) unnotified: usize,
}

/// Answers sent quietly before the compensated listeners are woken, within one burst of raw
/// samples: well below any subscriber buffer, so a client sleeping on the event service is woken
/// long before a lossless publisher could wait for room in its buffer.
const NOTIFY_BATCH: usize = 32;

impl Worker {
    /// Compensates one raw sample and publishes its answer; the listeners are woken by
    /// [`Worker::notify`] after the burst, or every [`NOTIFY_BATCH`] answers within it (one
    /// notification per burst instead of one per sample: replay throughput).
    pub(super) fn handle(&mut self, raw: &RawSample) {
        self.counters.samples_in += 1;
        self.counters.last_seq = raw.seq;
        let out = self.pipeline.process(&input_from_raw(raw));
        let sent = self.comp.send_quiet(comp_from_output(&out));
        self.unnotified += 1;
        if self.unnotified >= NOTIFY_BATCH {
            self.notify();
        }
        match sent.map(|_| ()) {
            Ok(()) => self.counters.samples_out += 1,
            Err(e) => {
                self.counters.send_failures += 1;
                if self.counters.send_failures.is_power_of_two() {
                    tracing::warn!(seq = raw.seq, error = %e, count = self.counters.send_failures, "publishing a compensated sample failed");
                }
                self.cleanup_after_failure();
            }
        }
        // A model is installed (or a fit fails) before the sample it first serves; a request is
        // made after the sample that completes the schedule: check in that order.
        let stats = self.pipeline.stats();
        let swapped = out.model_version != self.reported_version;
        let failed = stats.retrain_failed != self.reported_failed;
        if (swapped || failed)
            && let Some(at) = self.request_at.take()
        {
            self.counters.last_retrain_ns = u64::try_from(at.elapsed().as_nanos()).unwrap_or(u64::MAX);
        }
        if stats.retrain_requests != self.requests_seen {
            self.requests_seen = stats.retrain_requests;
            self.request_at = Some(Instant::now());
        }
        if swapped {
            self.reported_version = out.model_version;
            self.report(StatusEvent::ModelSwapped);
            self.snapshot();
        } else if failed {
            self.reported_failed = stats.retrain_failed;
            self.report(StatusEvent::RetrainFailed);
        }
    }

    /// Wakes the compensated listeners if answers were sent since the last time (and the
    /// settings ask for notifications).
    pub(super) fn notify(&mut self) {
        if self.unnotified == 0 || !self.comp.notifies() {
            self.unnotified = 0;
            return;
        }
        self.unnotified = 0;
        if let Err(e) = self.comp.notify() {
            tracing::debug!(error = %e, "notifying the compensated listeners failed");
        }
    }

    /// Handles the samples waiting now, at most `max`.
    pub(super) fn drain(&mut self, raw: &RawSubscriber, max: usize, errors: &mut u64) {
        for _ in 0..max {
            match raw.try_recv() {
                Ok(Some(sample)) => self.handle(&sample),
                Ok(None) => return,
                Err(e) => {
                    *errors += 1;
                    if errors.is_power_of_two() {
                        tracing::warn!(error = %e, count = *errors, "receiving raw samples failed");
                    }
                    return;
                }
            }
        }
    }

    /// Hands the installed models and copies of the pipeline buffers to the snapshot writer.
    pub(super) fn snapshot(&mut self) {
        let Some(writer) = &mut self.snapshots else { return };
        let p = &self.pipeline;
        let models = [0, 1, 2].map(|axis| p.model_slot(axis).and_then(|slot| (*slot.load()).clone()));
        writer.offer(SnapshotJob {
            compat: self.compat.clone(),
            models,
            warm: p.warm_state(),
            stream: p.stream_state(),
        });
        self.last_snapshot = Instant::now();
    }

    /// A failed send may mean a client died with a full buffer: a lossless publisher then waits
    /// for it on every sample. Cleaning dead nodes removes its ports (at most once a second).
    fn cleanup_after_failure(&mut self) {
        if self.last_cleanup.is_some_and(|t| t.elapsed() < CLEANUP_PERIOD) {
            return;
        }
        self.last_cleanup = Some(Instant::now());
        let (cleaned, failed) = self.node.cleanup_dead_nodes();
        if cleaned + failed > 0 {
            tracing::info!(cleaned, failed, "dead iceoryx2 nodes cleaned after a failed send");
        }
    }

    /// Publishes the periodic report when it is due, and hands a waiting snapshot on.
    pub(super) fn tick(&mut self) {
        if let Some(writer) = &mut self.snapshots {
            writer.flush();
        }
        if self.snapshot_every.is_some_and(|every| self.last_snapshot.elapsed() >= every) {
            self.snapshot();
        }
        if self.last_report.elapsed() >= STATUS_PERIOD {
            self.report(StatusEvent::Periodic);
        }
    }

    /// Publishes a status report now.
    pub(super) fn report(&mut self, event: StatusEvent) {
        self.last_report = Instant::now();
        let t_ns = u64::try_from(self.started.elapsed().as_nanos()).unwrap_or(u64::MAX);
        let sample = status_sample(event, t_ns, &self.pipeline.stats(), self.pipeline.model_version(), &self.counters);
        if let Err(e) = self.status.send(sample) {
            self.status_errors += 1;
            if self.status_errors.is_power_of_two() {
                tracing::warn!(error = %e, count = self.status_errors, "publishing a status report failed");
            }
        }
        tracing::debug!(?event, samples_in = sample.samples_in, model_version = sample.model_version, "status");
    }
}
