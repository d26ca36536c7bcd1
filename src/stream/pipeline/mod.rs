//! The per-sample pipeline shared by the daemon, the replay tool and `gyrocomp compensate`
//! (docs/design.md "One pipeline, three drivers"): input check → gap check → sample period (measured
//! when `input.rate_hz = "auto"`) → per-axis drift estimate ([`DriftEstimator`], `[drift]`) →
//! static/moving detector ([`MotionDetector`], `[motion]`) → compensation → pending queue →
//! delayed commit to the self-calibration ([`NoiseCalibration`]) and the estimator, for three
//! axes, plus the retrain schedule of estimators that take models. `docs/drift-estimation.md`
//! describes the default (Kalman tracker, statistical detector).
//!
//! Per sample t and axis:
//! - **Accepted sample**: the estimator predicts the drift `d[t]` and its variance from committed
//!   samples only (before t); the detector judges `r = x[t] − d[t]`. Output = raw − `d[t]` (moving
//!   samples: the estimator's [`DriftEstimator::predict_moving`], the last static forecast for
//!   `cpso-lssvm`). On a detected onset the detector's look-back discards the newest pending
//!   samples and the older ones are committed.
//! - **Static sample**: joins the pending queue; once the detector's commit delay has passed
//!   (0 for the threshold gate: at once) it is committed — to the calibration, then to the
//!   estimator (`cpso-lssvm`: the denoiser, the denoised history and its fallback running mean;
//!   the paper's method: db4 denoising, PSR Eq. 15–16, scaler Eq. 21, an LS-SVM forecasting the
//!   denoised series L + 1 steps ahead, [`Config::cpso_lssvm`](crate::config::Config::cpso_lssvm),
//!   or iterated, [`InstalledModel::predict_ahead`](super::InstalledModel::predict_ahead)).
//!   The output at t uses `x[t]` only through "raw −".
//! - **Moving sample** (detector or publisher flag; status bit 1): neither pending nor
//!   committed; the horizon counts samples since the last static one. The static series is
//!   concatenated across motion.
//! - **Rejected sample** (status bit 2; see [`InputCheck`] for the tests: duplicate `seq`, time
//!   going backwards, NaN/Inf or |rate| > `input.range_dps` on any axis, robust spike test, and
//!   the sensor faults of status bit 4 — saturation at the range, an axis stuck on one value for
//!   `input.stuck_s`, whose run's pending samples are discarded as well):
//!   enters no buffer — not the pending queue, the estimator, the calibration, the detector or
//!   the spike estimates. The best safe output, per axis: a finite in-range rate minus the
//!   current (held) drift, as for a moving sample; a bad rate is replaced by the last accepted
//!   compensated value (0 before any). Never NaN.
//! - **Gap** (skipped `seq`, t_ns step above `gap_factor` nominal periods, or backwards; status
//!   bit 3): flagged and counted; the buffers are kept, i.e. the static series is concatenated
//!   across the gap like across motion (drift is slow; only PSR rows straddling the seam are
//!   affected).
//!
//! - **Temperature** ±∞ or implausible: ignored for the sample (taken as none), counted.
//!
//! Snapshots ([`Pipeline::warm_state`], [`Pipeline::stream_state`], [`Pipeline::restore_state`]):
//! a pipeline restored before its first sample continues the stored sample index and gives the
//! output the stored one would have given.
//!
//! Retraining: see [`RetrainSchedule`](super::RetrainSchedule) and `retrain.rs`. Requests are made after sample index i when due, with
//! snapshots of the training windows; in deterministic mode the result is installed right before
//! sample `i + apply_delay_samples` (waiting for the trainer if necessary); in live mode at the
//! first sample after it arrives. A request due while another is pending is skipped and counted.
//!
//! No heap allocation per sample: buffers are allocated in [`Pipeline::new`]; only retrain
//! requests (every `every_samples`) copy the windows (tests/pipeline.rs counts allocations).
//!
//! Files: this one holds the per-sample path; `config.rs` the settings, counters and errors;
//! `retrain.rs` the retrain schedule and model installation; `restore.rs` the warm state handed
//! out for a snapshot and taken back.

mod config;
mod restore;
mod retrain;

use std::sync::Arc;
use std::time::Instant;

pub use config::{PipelineConfig, PipelineError, PipelineStats};

use super::calibration::NoiseCalibration;
use super::detector::{Decision, DetectorInput, MotionDetector};
use super::drift::{DriftEstimate, DriftEstimator};
use super::input_check::{InputCheck, InputConfig};
use super::model_slot::ModelSlot;
use super::motion_gate::MotionConfig;
use super::pending::PendingQueue;
use super::period::PeriodEstimate;
use super::retrain::Trainer;
use super::sample::{FLAG_MOVING, InputSample, OutputSample, STATUS_MOVING, STATUS_NO_MODEL, STATUS_REJECTED};

/// The shortest τ\* a drift estimator may track at, as a fraction of the detector's longest
/// window ([`NoiseCalibration::set_min_block`]). 1 keeps a tracker from following any rotation
/// the detector could still find but makes it lag a warming-up sensor; 0 lets it follow both.
/// Chosen on simulated recordings (adis16405 preset at 10, 100 and 1000 Hz, mpu6050 preset, the
/// tactical preset; seeds 100–105, turns and mixed profiles; 0, 0.3 and 1 tried: pooled median
/// 0.59×, 0.57×, 0.62× bias-hold, whole-run 1.02×, 0.35×, 0.43×), never on reported recordings.
pub const MIN_TRACKING_FRACTION: f64 = 0.3;

/// One axis: its drift estimator and the values held for moving and rejected samples.
#[derive(Debug)]
struct AxisState {
    estimator: Box<dyn DriftEstimator>,
    /// Drift subtracted from the last accepted sample (held for rejects).
    drift: f64,
    /// Last compensated value of an accepted sample (the substitute for a rejected one).
    comp: f64,
    /// Whether the last accepted sample's drift came from the estimator's model.
    from_model: bool,
    /// Standard deviation of the last accepted sample's drift (+∞ while unknown).
    std: f64,
}

impl AxisState {
    fn set(&mut self, e: DriftEstimate, raw: f64) {
        self.drift = e.drift;
        self.comp = raw - e.drift;
        self.from_model = e.from_model;
        // A NaN variance (never expected) is reported as unknown, not as NaN.
        self.std = if e.variance >= 0.0 { e.variance.sqrt() } else { f64::INFINITY };
    }
}

/// A retrain request waiting for its result.
#[derive(Debug, Clone, Copy)]
struct Pending {
    request_index: u64,
}

/// The per-sample compensation pipeline for three axes.
#[derive(Debug)]
pub struct Pipeline {
    config: PipelineConfig,
    axes: [AxisState; 3],
    noise: [NoiseCalibration; 3],
    detector: Box<dyn MotionDetector>,
    queue: PendingQueue,
    period: PeriodEstimate,
    check: InputCheck,
    /// Samples since the last accepted static sample (0 while static).
    horizon: u64,
    /// Index of the first sample processed (0; a restored snapshot's sample index).
    first_index: u64,
    next_version: u64,
    stats: PipelineStats,
    trainer: Option<Trainer>,
    pending: Option<Pending>,
    last_request: Instant,
}

impl Pipeline {
    /// Builds the pipeline; every per-sample buffer is allocated here (the statistical
    /// detector's windows once the sample period is known: here when `input.rate_hz` is given,
    /// after the first timestamps when it is "auto").
    pub fn new(config: PipelineConfig) -> Result<Self, PipelineError> {
        config.causal.validate().map_err(|e| PipelineError::Config(format!("denoise.window/denoise.lag: {e}")))?;
        config.statistical.validate().map_err(PipelineError::Config)?;
        let history = config.retrain.window.max(config.embedding.history());
        let period = PeriodEstimate::new(config.input.period_ns);
        let axis = || -> Result<AxisState, PipelineError> {
            let estimator = (config.drift.kind)
                .build(&config.drift, &config.causal, history, config.bias_samples)
                .map_err(PipelineError::Config)?;
            Ok(AxisState { estimator, drift: 0.0, comp: 0.0, from_model: false, std: f64::INFINITY })
        };
        let axes = [axis()?, axis()?, axis()?];
        let detector = config.detector.build(&config.statistical, config.motion);
        let known = period.period_s();
        let mut pipeline = Self {
            noise: Default::default(),
            queue: PendingQueue::new(detector.commit_delay()),
            detector,
            period,
            check: InputCheck::new(config.input),
            axes,
            config,
            horizon: 0,
            first_index: 0,
            next_version: 1,
            stats: PipelineStats::default(),
            trainer: None,
            pending: None,
            last_request: Instant::now(),
        };
        if let Some(t) = known {
            pipeline.apply_period(t);
        }
        Ok(pipeline)
    }

    /// Sizes everything that works in seconds for the sample period: the detector's windows, the
    /// pending queue, the calibrations' shortest τ\*, the estimators' spans.
    fn apply_period(&mut self, period_s: f64) {
        self.detector.set_period(period_s);
        self.queue.set_capacity(self.detector.commit_delay());
        for n in &mut self.noise {
            n.set_min_block(MIN_TRACKING_FRACTION * self.detector.longest_window() as f64);
        }
        for a in &mut self.axes {
            a.estimator.set_period(period_s);
        }
    }

    /// Applies new motion-gate and input thresholds from the next sample on (a reloaded
    /// configuration); buffers, models and counters are kept (see [`MotionGate::reconfigure`](crate::stream::MotionGate::reconfigure)).
    pub fn update_thresholds(&mut self, motion: MotionConfig, input: InputConfig) {
        self.detector.reconfigure_thresholds(motion);
        let input = InputConfig { period_ns: self.check.config().period_ns, ..input };
        self.check.reconfigure(input);
        self.config.motion = motion;
        self.config.input = input;
    }

    /// The settings.
    pub fn config(&self) -> &PipelineConfig {
        &self.config
    }

    /// Counters.
    pub fn stats(&self) -> PipelineStats {
        let input = self.check.counters();
        PipelineStats { input, gaps: input.gaps, detector: self.detector.counters(), ..self.stats }
    }

    /// The self-calibration of one axis (online Allan variance of its committed samples).
    pub fn noise(&self, axis: usize) -> Option<&NoiseCalibration> {
        self.noise.get(axis)
    }

    /// The drift estimator of one axis.
    pub fn estimator(&self, axis: usize) -> Option<&dyn DriftEstimator> {
        self.axes.get(axis).map(|a| a.estimator.as_ref())
    }

    /// The sample period in use, seconds (`None` while "auto" has not measured it yet).
    pub fn period_s(&self) -> Option<f64> {
        self.period.period_s()
    }

    /// Forecast horizon: samples (moving or rejected) since the last accepted static sample
    /// (0 while static).
    pub fn horizon(&self) -> u64 {
        self.horizon
    }

    /// Version of the newest model installed on any axis (0 = none).
    pub fn model_version(&self) -> u64 {
        self.axes.iter().filter_map(|a| a.estimator.model_slot()).map(|s| s.version()).max().unwrap_or(0)
    }

    /// The model slot of an axis, for installing from another thread (`None` also when the
    /// estimator takes no models).
    pub fn model_slot(&self, axis: usize) -> Option<Arc<ModelSlot>> {
        self.axes.get(axis).and_then(|a| a.estimator.model_slot()).map(Arc::clone)
    }

    /// Processes one sample and returns its output (never NaN, same `seq`).
    pub fn process(&mut self, input: &InputSample) -> OutputSample {
        self.poll_trainer();
        let out = self.compensate(input);
        self.stats.samples += 1;
        self.maybe_request();
        out
    }

    fn compensate(&mut self, input: &InputSample) -> OutputSample {
        let publisher_moving = input.flags & FLAG_MOVING != 0;
        let index = self.first_index + self.stats.samples;
        let verdict = self.check.check(index, input.seq, input.t_ns, &input.rate_dps, publisher_moving);
        let mut status = verdict.status;
        let mut rate = [0.0; 3];
        let mut drift = [0.0; 3];
        let mut drift_std = [f64::INFINITY; 3];
        if verdict.rejected() {
            status |= STATUS_REJECTED;
            self.stats.rejected += 1;
            if let Some(from) = verdict.stuck_since {
                // A stuck sensor: what it sent since the run began must never be learnt.
                self.stats.discarded += self.queue.drop_from(from) as u64;
            }
            self.horizon += 1;
            for (k, a) in self.axes.iter().enumerate() {
                let r = input.rate_dps[k];
                drift[k] = a.drift;
                drift_std[k] = a.std;
                rate[k] = if self.check.in_range(r) { r - a.drift } else { a.comp };
                if !a.from_model {
                    status |= STATUS_NO_MODEL;
                }
            }
        } else {
            // ±∞ or implausible temperatures are ignored (counted): they never reach the estimators.
            let temp_c = self.check.temperature(input.temp_c);
            self.observe_time(input.t_ns);
            let estimates = self.predict(index, &input.rate_dps, temp_c);
            let decision = self.detector.push(&DetectorInput {
                rate: &input.rate_dps,
                drift: &estimates,
                noise: &self.noise,
                publisher_moving,
            });
            self.settle_pending(decision);
            if decision.moving {
                status |= STATUS_MOVING;
                self.stats.moving += 1;
                self.horizon += 1;
            } else {
                self.horizon = 0;
            }
            for (k, a) in self.axes.iter_mut().enumerate() {
                let e = if decision.moving {
                    // Commits may have set another sample's temperature since the prediction.
                    a.estimator.set_temperature(temp_c);
                    a.estimator.predict_moving(index, self.queue.mean(k), &self.noise[k])
                } else {
                    estimates[k]
                };
                a.set(e, input.rate_dps[k]);
                drift[k] = a.drift;
                drift_std[k] = a.std;
                rate[k] = a.comp;
                if !e.from_model {
                    status |= STATUS_NO_MODEL;
                }
            }
            if !decision.moving {
                self.queue.push(index, input.rate_dps, temp_c);
                while self.queue.len() > self.detector.commit_delay() {
                    let Some((i, r, t)) = self.queue.pop_oldest() else { break };
                    self.commit(i, &r, t);
                }
                self.check.accept_static(&input.rate_dps);
            }
        }
        OutputSample {
            seq: input.seq,
            t_ns: input.t_ns,
            rate_dps: rate,
            drift_dps: drift,
            model_version: self.model_version(),
            status,
            drift_std_dps: drift_std,
        }
    }

    /// Measures the sample period from the timestamps when `input.rate_hz` is "auto"; once it is
    /// known, the gap check and the detector's windows use it.
    fn observe_time(&mut self, t_ns: u64) {
        if let Some(period_ns) = self.period.observe(t_ns) {
            let input = InputConfig { period_ns, ..*self.check.config() };
            self.check.reconfigure(input);
            self.apply_period(period_ns as f64 * 1e-9);
            tracing::info!(period_ns, "sample period measured from the timestamps");
        }
    }

    /// Each axis' drift estimate for the sample at `index` (temperature `temp_c`, NaN: none);
    /// feeds the start-up σ first.
    fn predict(&mut self, index: u64, rate: &[f64; 3], temp_c: f64) -> [DriftEstimate; 3] {
        std::array::from_fn(|k| {
            self.noise[k].observe(rate[k]);
            self.axes[k].estimator.set_temperature(temp_c);
            self.axes[k].estimator.predict(index, self.queue.mean(k), &self.noise[k])
        })
    }

    /// Applies a detector's look-back: on an onset the newest `discard` pending samples are
    /// dropped and the older ones committed. When that would discard every pending sample while
    /// no estimator has a committed reference yet (start-up, or after a relearn), only the
    /// motion's estimated span is discarded, without the guard before it, and the oldest pending
    /// sample is always kept: otherwise nothing would be committed, the estimate would fall
    /// back to the mean of the samples that follow (moving ones), and the detector, with no
    /// reference to test against, would call them static. Seen on an independently generated
    /// quiet floor whose first turn began 1.1 s in: the estimate locked onto the turn's 20 deg/s
    /// plateau for the rest of the run. (Without the guard an early false alarm, whose span is
    /// short, keeps most of the start-up samples; applied to every onset without a reference,
    /// it let the lead-in of slow rotations after a relearn into the estimate on ADIS run 1.)
    fn settle_pending(&mut self, decision: Decision) {
        if decision.relearn {
            let dropped = self.queue.drop_newest(self.queue.len());
            self.stats.discarded += dropped as u64;
            for a in &mut self.axes {
                a.estimator.relearn();
            }
            tracing::warn!(
                sample = self.stats.samples,
                dropped,
                "moving for long with an unchanging residual and no publisher flag: the drift estimate is relearnt"
            );
            return;
        }
        if !decision.flush {
            return;
        }
        let len = self.queue.len();
        let discard = if decision.discard < len || self.axes.iter().all(|a| a.estimator.has_reference()) {
            decision.discard
        } else {
            decision.onset.min(len.saturating_sub(1))
        };
        self.stats.discarded += self.queue.drop_newest(discard) as u64;
        while let Some((i, r, t)) = self.queue.pop_oldest() {
            self.commit(i, &r, t);
        }
    }

    /// Commits a confirmed static sample: calibration first (so the first commit has a noise
    /// figure), then the estimator.
    fn commit(&mut self, index: u64, rate: &[f64; 3], temp_c: f64) {
        self.stats.committed += 1;
        for (k, a) in self.axes.iter_mut().enumerate() {
            self.noise[k].commit(index, rate[k]);
            a.estimator.set_temperature(temp_c);
            a.estimator.commit(index, rate[k], &self.noise[k]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Config;
    use crate::model::Predict;
    use crate::model::scaler::MinMaxScaler;
    use crate::stream::retrain::RetrainMode;

    fn pipeline() -> Pipeline {
        let mut c = Config::paper();
        c.retrain.schedule.window = 100;
        c.retrain.schedule.min_samples = 50;
        Pipeline::new(c.pipeline().unwrap()).unwrap()
    }

    fn sample(k: u64, r: f64) -> InputSample {
        InputSample::new(k, k * 10_000_000, [r, -r, 0.0])
    }

    #[test]
    fn before_a_model_the_drift_is_the_mean_of_earlier_static_samples() {
        let mut p = pipeline();
        let first = p.process(&sample(0, 0.3));
        assert_eq!((first.drift_dps, first.rate_dps), ([0.0; 3], [0.3, -0.3, 0.0]));
        let second = p.process(&sample(1, 0.5));
        assert_eq!(second.drift_dps, [0.3, -0.3, 0.0]);
        let third = p.process(&sample(2, 0.5));
        assert!((third.drift_dps[0] - 0.4).abs() < 1e-15);
        assert!(third.status & STATUS_NO_MODEL != 0);
    }

    /// Returns NaN: the pipeline must fall back to the bias estimate.
    struct Broken;
    impl Predict for Broken {
        fn history_len(&self) -> usize {
            1
        }
        fn predict(&self, _: &[f64]) -> f64 {
            f64::NAN
        }
    }

    /// Needs more history than the pipeline keeps.
    struct Greedy;
    impl Predict for Greedy {
        fn history_len(&self) -> usize {
            1_000_000
        }
        fn predict(&self, _: &[f64]) -> f64 {
            0.0
        }
    }

    #[test]
    fn thresholds_and_schedule_change_without_losing_state() {
        let mut p = pipeline();
        for k in 0..30 {
            p.process(&sample(k, 0.5));
        }
        let before = p.process(&sample(30, 0.5));
        assert_eq!(before.status & STATUS_MOVING, 0);
        let mut motion = p.config().motion;
        motion.rate_dps = 0.4;
        // Constant input: any step is a spike to the robust test; switch it off to see the gate.
        let input = InputConfig { spike_z: 0.0, ..p.config().input };
        p.update_thresholds(motion, input);
        // 0.5 above the running bias of 0.5: moving at the new threshold, not at the default.
        let after = p.process(&sample(31, 1.0));
        assert!(after.status & STATUS_MOVING != 0, "{after:?}");
        // The drift estimate (state) survived the change.
        assert_eq!(after.drift_dps, before.drift_dps);
        assert_eq!(p.stats().samples, 32);

        let mut schedule = p.config().retrain;
        schedule.every_samples = 7;
        schedule.mode = RetrainMode::Deterministic;
        p.set_retrain_schedule(schedule).unwrap();
        assert_eq!(p.config().retrain.every_samples, 7);
        schedule.window = 1_000_000;
        assert!(
            matches!(p.set_retrain_schedule(schedule), Err(PipelineError::Config(m)) if m.contains("retrain.window"))
        );
        assert_eq!(p.config().retrain.every_samples, 7);
    }

    #[test]
    fn a_model_returning_nan_falls_back_and_long_histories_are_refused() {
        let mut p = pipeline();
        let scaler = MinMaxScaler { min: -1.0, max: 1.0 };
        p.install_model(0, Arc::new(Broken), scaler, 3).unwrap();
        assert!(matches!(p.install_model(1, Arc::new(Greedy), scaler, 4), Err(PipelineError::HistoryTooLong { .. })));
        for k in 0..50 {
            let o = p.process(&sample(k, 0.2));
            assert!(o.rate_dps.iter().all(|v| v.is_finite()));
            assert!(o.status & STATUS_NO_MODEL != 0);
            assert_eq!(o.model_version, 3);
        }
    }
}
