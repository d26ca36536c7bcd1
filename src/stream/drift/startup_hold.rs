//! Start-up bias-hold as an online estimator: the mean of the committed static samples of the
//! first `startup_s` seconds (an INS's alignment), then held for the rest of the run. Until the
//! span is complete the pending samples count too, so the estimate exists from the second sample.

use super::{DriftEstimate, DriftEstimator, PendingMean};
use crate::stream::calibration::NoiseCalibration;
use crate::stream::warm::AxisWarm;

/// Start-up mean, then held (module documentation).
#[derive(Debug, Clone)]
pub struct StartupHold {
    startup_s: f64,
    /// `startup_s` in samples once the period is known (unbounded before).
    span_samples: u64,
    sum: f64,
    count: u64,
}

impl StartupHold {
    /// Averages the committed samples of the first `startup_s` seconds (at least one sample).
    pub fn new(startup_s: f64) -> Self {
        Self { startup_s, span_samples: u64::MAX, sum: 0.0, count: 0 }
    }
}

impl DriftEstimator for StartupHold {
    fn name(&self) -> &'static str {
        "bias-hold"
    }

    fn predict(&mut self, _now: u64, pending: PendingMean, noise: &NoiseCalibration) -> DriftEstimate {
        let (sum, count) = if self.count < self.span_samples {
            let take = pending.count.min(self.span_samples - self.count);
            let part = if pending.count == 0 { 0.0 } else { pending.sum * take as f64 / pending.count as f64 };
            (self.sum + part, self.count + take)
        } else {
            (self.sum, self.count)
        };
        if count == 0 {
            return DriftEstimate { drift: 0.0, variance: f64::INFINITY, from_model: false };
        }
        let variance = noise.mean_variance(count as usize).unwrap_or(f64::INFINITY);
        DriftEstimate { drift: sum / count as f64, variance, from_model: self.count >= self.span_samples }
    }

    fn commit(&mut self, _index: u64, raw: f64, _noise: &NoiseCalibration) {
        if self.count < self.span_samples {
            self.sum += raw;
            self.count += 1;
        }
    }

    fn set_period(&mut self, period_s: f64) {
        self.span_samples = (self.startup_s / period_s).round().max(1.0) as u64;
    }

    fn has_reference(&self) -> bool {
        self.count > 0
    }

    fn warm(&self, warm: &mut AxisWarm) {
        warm.bias = if self.count > 0 { self.sum / self.count as f64 } else { 0.0 };
        warm.bias_count = self.count;
    }

    fn restore(&mut self, warm: &AxisWarm) {
        self.count = warm.bias_count.min(self.span_samples);
        self.sum = warm.bias * self.count as f64;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn averages_the_start_up_span_then_holds() {
        let noise = NoiseCalibration::new();
        let mut h = StartupHold::new(1.0);
        h.set_period(0.1); // 10 samples
        let nothing = h.predict(0, PendingMean::default(), &noise);
        assert_eq!((nothing.drift, nothing.from_model), (0.0, false));
        // Pending samples count while the span is not complete.
        let early = h.predict(0, PendingMean { count: 4, sum: 2.0 }, &noise);
        assert_eq!((early.drift, early.from_model), (0.5, false));
        for i in 0..10 {
            h.commit(i, 1.0 + i as f64, &noise);
        }
        // Mean of 1 … 10, held: later commits and pending samples change nothing.
        h.commit(10, 100.0, &noise);
        let held = h.predict(20, PendingMean { count: 5, sum: 500.0 }, &noise);
        assert_eq!((held.drift, held.from_model), (5.5, true));
    }
}
