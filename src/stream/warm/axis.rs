//! One axis' warm state ([`AxisWarm`]): what a drift estimator and the self-calibration hold
//! besides the model (its own file so that the estimators, which fill it, import nothing of the
//! detector or the pending queue that [`StreamWarm`](super::StreamWarm) holds).

use serde::{Deserialize, Serialize};

use super::bank::BankWarm;
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
    /// Kalman temperature filter, once a temperature was committed (`bias` and `variance`
    /// above are the scalar filter's).
    pub temperature: Option<TemperatureWarm>,
    /// Kalman: the last finite temperature seen (°C), which stands in for a sample without one.
    pub last_temp_c: Option<f64>,
    /// Multi-scale tracker: its whole state (`None` for the other estimators).
    pub bank: Option<BankWarm>,
    /// Adaptive tracker: log Bayes factor of the multi-scale model against the scalar one.
    pub model_evidence: f64,
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

/// The Kalman tracker's temperature filter (state (b, c), measurement b + c·(T − T₀)) and the
/// evidence that decides whether it drives the output (`stream::drift::kalman`): the tracker's
/// own state, copied as it is into a snapshot.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct TemperatureWarm {
    /// Bias b at T₀, deg/s.
    pub bias: f64,
    /// Var(b), (deg/s)².
    pub variance: f64,
    /// Temperature coefficient c, deg/s per °C.
    pub coef: f64,
    /// Cov(b, c).
    pub cov_bc: f64,
    /// Var(c).
    pub var_c: f64,
    /// T₀, °C.
    pub reference_c: f64,
    /// Log Bayes factor of this filter against the scalar one.
    pub evidence: f64,
    /// Whether this filter drives the output.
    pub in_use: bool,
}

impl TemperatureWarm {
    /// Its real values, for a finiteness check.
    pub fn values(&self) -> [f64; 7] {
        [self.bias, self.variance, self.coef, self.cov_bc, self.var_c, self.reference_c, self.evidence]
    }
}

impl AxisWarm {
    /// Whether every value is finite.
    pub fn is_finite(&self) -> bool {
        // The Kalman variance is +∞ before its first commit; NaN and negative values are not.
        self.variance >= 0.0
            && self.drift_std >= 0.0
            && self.noise.is_valid()
            && self.temperature.iter().flat_map(TemperatureWarm::values).all(f64::is_finite)
            && self.bank.iter().all(BankWarm::is_valid)
            && [self.bias, self.drift, self.comp, self.model_evidence]
                .iter()
                .chain(self.last_temp_c.iter())
                .chain(&self.denoiser_window)
                .chain(&self.history)
                .all(|v| v.is_finite())
    }
}
