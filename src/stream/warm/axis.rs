//! One axis' warm state ([`AxisWarm`]): what a drift estimator and the self-calibration hold
//! besides the model (its own file so that the estimators, which fill it, import nothing of the
//! detector or the pending queue that [`StreamWarm`](super::StreamWarm) holds).

use serde::{Deserialize, Serialize};

use crate::stream::calibration::NoiseCalibration;

/// One axis' pipeline state beside its model (see the module documentation); each drift
/// estimator fills the fields it uses and leaves the others at their defaults.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct AxisWarm {
    /// Raw static samples in the causal denoiser's window, oldest first.
    pub denoiser_window: Vec<f64>,
    /// Static denoised samples (model input and training window), oldest first.
    pub history: Vec<f64>,
    /// Bias estimate: the running static mean (cpso-lssvm's fallback), the Kalman state, or
    /// the start-up mean.
    pub bias: f64,
    /// Samples the bias estimate has averaged (cpso-lssvm: capped at `pipeline.bias_samples`).
    pub bias_count: u64,
    /// Kalman: variance of `bias`, (deg/s)² (+∞ before the first commit).
    pub variance: f64,
    /// Kalman: sample index of the last committed sample.
    pub last_commit: u64,
    /// Kalman temperature term, once a temperature was committed: coefficient c (deg/s/°C),
    /// Cov(b, c), Var(c) and T₀ (°C).
    pub temperature: Option<[f64; 4]>,
    /// Kalman: the last finite temperature seen (°C), which stands in for a sample without one.
    pub last_temp_c: Option<f64>,
    /// The axis' self-calibration (online Allan variance, running σ).
    pub noise: NoiseCalibration,
    /// Drift subtracted from the last accepted sample (held during motion).
    pub drift: f64,
    /// Last compensated value of an accepted sample (the substitute for a rejected one).
    pub comp: f64,
    /// Whether the last accepted sample's drift came from the estimator's model (status bit 0
    /// of a rejected sample).
    pub from_model: bool,
    /// Standard deviation of the last accepted sample's drift, deg/s (+∞ while unknown).
    pub drift_std: f64,
}

impl AxisWarm {
    /// Whether every value is finite.
    pub fn is_finite(&self) -> bool {
        // The Kalman variance is +∞ before its first commit; NaN and negative values are not.
        self.variance >= 0.0
            && self.drift_std >= 0.0
            && self.noise.is_valid()
            && [self.bias, self.drift, self.comp]
                .iter()
                .chain(self.temperature.iter().flatten())
                .chain(self.last_temp_c.iter())
                .chain(&self.denoiser_window)
                .chain(&self.history)
                .all(|v| v.is_finite())
    }
}
