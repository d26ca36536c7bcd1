//! The paper's method as a forecaster of the *bias trajectory* (`hybrid`, issue 13 item 5): the
//! Kalman tracker ([`KalmanBias`]) estimates the drift while the platform is static, exactly as
//! the `kalman` estimator does; while it moves, a CPSO-LSSVM model with phase-space
//! reconstruction (paper §2.2, Eq. 15–21) forecasts how the drift goes on changing, on the
//! drift's own time scale.
//!
//! The series the model learns is that of *block means* of the committed static samples, one
//! per [`BLOCK_S`] seconds of committed data: the white noise of a block mean is N/√(10 s)
//! (0.01 deg/s on an ADIS16405), while the bias moves by less than that within a block (its Allan
//! minimum lies near 100 s). The background retrainer fits a one-step model on that series
//! (the `[embedding]` τ and m count blocks here; `[retrain] window` and `min_samples` too), with
//! the same CPSO-LSSVM configuration as `cpso-lssvm`.
//!
//! While moving, with k = ⌊(now − last commit)/block⌋ blocks elapsed since the last committed
//! sample, the drift is the tracker's estimate plus the model's forecast change,
//! b̂ + (f_k − f_1), f_j the model iterated j blocks past the newest block mean (for k ≤ 1 the
//! tracker's estimate alone). The trajectory f_1, f_2, … is computed lazily, at most one model
//! evaluation per sample, up to [`MAX_BLOCKS_AHEAD`] blocks (held beyond), and recomputed after
//! each commit or a new model. The variance reported is the tracker's (a kernel forecast carries
//! none of its own).
//!
//! Whether this beats holding the tracker's estimate is measured in docs/drift-estimation.md
//! ("The paper's model as a bias-trajectory forecaster"); the default stays `kalman`.

use std::sync::Arc;

use super::{DriftEstimate, DriftEstimator, KalmanBias, KalmanCounters, PendingMean};
use crate::stream::calibration::NoiseCalibration;
use crate::stream::model_slot::ModelSlot;
use crate::stream::ring::RingBuffer;
use crate::stream::warm::AxisWarm;

/// Seconds of committed static data per block mean of the series the model learns.
pub const BLOCK_S: f64 = 10.0;
/// Blocks the trajectory is forecast ahead at most (one hour at 10 s blocks); beyond it the last
/// forecast is held.
pub const MAX_BLOCKS_AHEAD: usize = 360;

/// One axis of the hybrid estimator (module documentation). Every buffer is allocated in
/// [`HybridForecast::new`]; the per-sample methods allocate nothing.
#[derive(Debug)]
pub(crate) struct HybridForecast {
    tracker: KalmanBias,
    /// Committed samples per block (0 until the sample period is known).
    block_samples: u64,
    block_sum: f64,
    block_filled: u64,
    /// Block means, oldest first: the model's input and training window.
    blocks: RingBuffer,
    slot: Arc<ModelSlot>,
    /// The normalised newest blocks the model reads, then the forecasts f_1, f_2, … (normalised).
    scratch: Vec<f64>,
    /// Forecasts computed so far into `scratch`, and the (last commit, model version) they
    /// belong to.
    computed: usize,
    trajectory_of: Option<(u64, u64)>,
    last_commit: Option<u64>,
}

impl HybridForecast {
    /// An estimator whose tracker gates innovations at `gate_probability` and learns a temperature
    /// term when `temperature` is set ([`KalmanBias::new`]); it keeps `history` block means.
    pub(crate) fn new(gate_probability: f64, temperature: bool, history: usize) -> Self {
        let history = history.max(1);
        Self {
            tracker: KalmanBias::new(gate_probability, temperature),
            block_samples: 0,
            block_sum: 0.0,
            block_filled: 0,
            blocks: RingBuffer::new(history),
            slot: Arc::new(ModelSlot::new()),
            scratch: vec![0.0; history + MAX_BLOCKS_AHEAD],
            computed: 0,
            trajectory_of: None,
            last_commit: None,
        }
    }

    /// The forecast change f_k − f_1 (raw units) for `k` blocks ahead, computing at most one more
    /// step of the trajectory; `None` without a usable model.
    fn forecast_change(&mut self, k: usize) -> Option<f64> {
        let guard = self.slot.load();
        let model = guard.as_ref()?;
        let h = model.model.history_len();
        let history = self.blocks.as_slice();
        if h == 0 || history.len() < h || model.model.horizon() != 1 {
            return None;
        }
        let key = (self.last_commit?, model.version);
        if self.trajectory_of != Some(key) {
            for (s, &v) in self.scratch.iter_mut().zip(&history[history.len() - h..]) {
                *s = model.scaler.transform(v);
            }
            self.computed = 0;
            self.trajectory_of = Some(key);
        }
        let k = k.min(MAX_BLOCKS_AHEAD);
        if self.computed < k {
            let next = model.model.predict(&self.scratch[..h + self.computed]);
            if !next.is_finite() {
                return None;
            }
            self.scratch[h + self.computed] = next;
            self.computed += 1;
        }
        let newest = self.computed.min(k);
        if newest < 2 {
            return Some(0.0);
        }
        let change = model.scaler.inverse(self.scratch[h + newest - 1]) - model.scaler.inverse(self.scratch[h]);
        change.is_finite().then_some(change)
    }
}

impl DriftEstimator for HybridForecast {
    fn name(&self) -> &'static str {
        "hybrid"
    }

    /// The tracker's estimate (static samples, pending or confirmed).
    #[inline]
    fn predict(&mut self, now: u64, pending: PendingMean, noise: &NoiseCalibration) -> DriftEstimate {
        self.tracker.predict(now, pending, noise)
    }

    /// The tracker's estimate plus the model's forecast change over the blocks elapsed since the
    /// last commit (module documentation).
    fn predict_moving(&mut self, now: u64, pending: PendingMean, noise: &NoiseCalibration) -> DriftEstimate {
        let held = self.tracker.predict(now, pending, noise);
        let (Some(last), true) = (self.last_commit, self.block_samples > 0 && held.from_model) else {
            return held;
        };
        let k = usize::try_from(now.saturating_sub(last) / self.block_samples).unwrap_or(usize::MAX);
        match self.forecast_change(k) {
            Some(change) => DriftEstimate { drift: held.drift + change, ..held },
            None => held,
        }
    }

    /// Feeds the tracker and the block in progress.
    #[inline]
    fn commit(&mut self, index: u64, raw: f64, noise: &NoiseCalibration) {
        self.tracker.commit(index, raw, noise);
        self.last_commit = Some(index);
        if self.block_samples == 0 {
            return;
        }
        self.block_sum += raw;
        self.block_filled += 1;
        if self.block_filled == self.block_samples {
            self.blocks.push(self.block_sum / self.block_samples as f64);
            self.block_sum = 0.0;
            self.block_filled = 0;
        }
    }

    fn set_temperature(&mut self, temp_c: f64) {
        self.tracker.set_temperature(temp_c);
    }

    fn model_slot(&self) -> Option<&Arc<ModelSlot>> {
        Some(&self.slot)
    }

    fn training_history(&self) -> &[f64] {
        self.blocks.as_slice()
    }

    fn max_model_history(&self) -> usize {
        self.blocks.capacity()
    }

    /// One block ahead: the trajectory is iterated from one-step forecasts.
    fn model_steps(&self) -> usize {
        1
    }

    /// The tracker's state and the block means (in `history`); the block in progress is not
    /// kept (a restart starts a new one).
    fn warm(&self, warm: &mut AxisWarm) {
        self.tracker.warm(warm);
        warm.history = self.blocks.as_slice().to_vec();
    }

    /// The newest block means that fit are kept.
    fn restore(&mut self, warm: &AxisWarm) {
        self.tracker.restore(warm);
        self.blocks.clear();
        for &x in &warm.history[warm.history.len().saturating_sub(self.blocks.capacity())..] {
            self.blocks.push(x);
        }
        (self.block_sum, self.block_filled) = (0.0, 0);
        self.last_commit = None;
        self.trajectory_of = None;
    }

    fn has_reference(&self) -> bool {
        self.tracker.has_reference()
    }

    /// The tracker relearns; the block means, learnt against the same wrong reference, are
    /// dropped with it.
    fn relearn(&mut self) {
        self.tracker.relearn();
        self.blocks.clear();
        (self.block_sum, self.block_filled) = (0.0, 0);
        self.trajectory_of = None;
    }

    fn set_period(&mut self, period_s: f64) {
        self.tracker.set_period(period_s);
        if period_s.is_finite() && period_s > 0.0 {
            self.block_samples = ((BLOCK_S / period_s).round() as u64).max(1);
        }
    }

    fn kalman_counters(&self) -> Option<KalmanCounters> {
        self.tracker.kalman_counters()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Predict;
    use crate::model::scaler::MinMaxScaler;
    use crate::stream::model_slot::InstalledModel;

    /// x̂[t+1] = x[t] + 0.1 in normalised units: a drift that keeps rising.
    struct Rising;
    impl Predict for Rising {
        fn history_len(&self) -> usize {
            2
        }
        fn predict(&self, history: &[f64]) -> f64 {
            history[history.len() - 1] + 0.1
        }
    }

    fn calibrated() -> NoiseCalibration {
        let mut n = NoiseCalibration::new();
        for i in 0..200 {
            let x = if i % 2 == 0 { 0.01 } else { -0.01 };
            n.observe(x);
            n.commit(i, x);
        }
        n
    }

    #[test]
    fn holds_the_tracker_when_static_and_adds_the_forecast_change_while_moving() {
        let noise = calibrated();
        let mut h = HybridForecast::new(1e-6, false, 64);
        h.set_period(1.0); // 10 committed samples per block
        for i in 0..40u64 {
            h.commit(i, 0.5, &noise);
        }
        assert_eq!(h.training_history(), &[0.5, 0.5, 0.5, 0.5]);
        let pending = PendingMean::default();
        let kalman = h.predict(40, pending, &noise);
        // Without a model: the tracker's estimate, static or moving (its variance grown).
        assert_eq!(h.predict_moving(100, pending, &noise), h.predict(100, pending, &noise));
        // Identity scaler on [-1, 1]: normalised = raw.
        let scaler = MinMaxScaler { min: -1.0, max: 1.0 };
        h.slot.install(InstalledModel { model: Arc::new(Rising), scaler, version: 1 });
        assert_eq!(h.predict(41, pending, &noise).drift, kalman.drift, "static samples ignore the model");
        // 5 blocks after the last commit (index 39): f_5 − f_1 = 0.4, reached one step per sample.
        let mut last = 0.0;
        for _ in 0..10 {
            last = h.predict_moving(89, pending, &noise).drift;
        }
        assert!((last - (kalman.drift + 0.4)).abs() < 1e-9, "{last} vs {}", kalman.drift + 0.4);
        // A commit restarts the trajectory from the new newest blocks.
        h.commit(40, 0.5, &noise);
        let first = h.predict_moving(45, pending, &noise).drift;
        assert!((first - h.predict(45, pending, &noise).drift).abs() < 1e-12, "k = 0: the tracker alone");
    }

    #[test]
    fn relearn_drops_the_block_series_and_restore_keeps_it() {
        let noise = calibrated();
        let mut h = HybridForecast::new(1e-6, false, 3);
        h.set_period(0.5); // 20 samples per block
        for i in 0..100u64 {
            h.commit(i, i as f64, &noise);
        }
        assert_eq!(h.training_history(), &[49.5, 69.5, 89.5], "the ring keeps the newest 3 blocks");
        let mut warm = AxisWarm::default();
        h.warm(&mut warm);
        let mut g = HybridForecast::new(1e-6, false, 2);
        g.restore(&warm);
        assert_eq!(g.training_history(), &[69.5, 89.5]);
        h.relearn();
        assert!(h.training_history().is_empty());
    }
}
