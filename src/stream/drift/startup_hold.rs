//! Start-up bias-hold as an online estimator: the mean of the committed static samples of the
//! first `startup_s` seconds (an INS's alignment), then held for the rest of the run. Until the
//! span is complete the pending samples count too, so the estimate exists from the second sample.

use super::{DriftEstimate, DriftEstimator, PendingMean};
use crate::stream::calibration::NoiseCalibration;
use crate::stream::snapshot::AxisWarm;

/// Start-up mean, then held (module documentation).
#[derive(Debug, Clone)]
pub struct StartupHold {
    span_samples: u64,
    sum: f64,
    count: u64,
}

impl StartupHold {
    /// Averages the first `span_samples` committed samples (at least 1).
    pub fn new(span_samples: u64) -> Self {
        Self { span_samples: span_samples.max(1), sum: 0.0, count: 0 }
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

    fn warm(&self, warm: &mut AxisWarm) {
        warm.bias = if self.count > 0 { self.sum / self.count as f64 } else { 0.0 };
        warm.bias_count = self.count;
    }

    fn restore(&mut self, warm: &AxisWarm) {
        self.count = warm.bias_count.min(self.span_samples);
        self.sum = warm.bias * self.count as f64;
    }
}
