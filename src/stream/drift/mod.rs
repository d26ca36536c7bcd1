//! Online per-axis drift estimators (issue 13, "a drift-estimator seam"): one trait, chosen by
//! `[drift] estimator` through [`EstimatorKind`], used by the [`Pipeline`](super::Pipeline) and so
//! by every driver (daemon, `replay`, `compensate`, `eval --protocol motion`).
//!
//! The pipeline asks for the drift of the sample it is about to compensate
//! ([`DriftEstimator::predict`]) and *commits* static samples to the estimator only once the
//! static detector has confirmed them (delayed commit, [`super::detector`]). Between the last
//! commit and now lie the *pending* samples: seen as static, not yet confirmed; their running sum
//! is handed to `predict` so an estimator may use them provisionally ([`PendingMean`]).
//!
//! | name | what it is |
//! |---|---|
//! | `kalman` | scalar Kalman filter, bias as a random walk, Q and R from the unit's own Allan variance ([`KalmanBias`]) |
//! | `cpso-lssvm` | the paper's method: db4 causal denoising, PSR, CPSO-tuned LS-SVM forecast retrained in the background (`ModelForecast`) |
//! | `bias-hold` | the mean of the start-up static span, then held for ever ([`StartupHold`]) |
//! | `multiscale` | Kalman filter, random-walk bias plus Gauss–Markov states at 3 s … 1000 s, its noise model fitted to the unit's Allan variance across static stretches ([`MultiScaleKalman`]) |
//! | `adaptive` | `kalman` and `multiscale` side by side, the one whose model predicts the unit's committed samples better (Bayes factor) driving ([`AdaptiveKalman`]) |
//! | `hybrid` | the Kalman tracker while static; while moving, plus the change a CPSO-LSSVM model of the tracker's 10 s block means forecasts (`HybridForecast`) |

mod adaptive;
mod bank_model;
mod hybrid;
mod kalman;
mod model_forecast;
mod multiscale;
mod startup_hold;

use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

use serde::Deserialize;

pub use adaptive::AdaptiveKalman;
pub use bank_model::{BANK_TAUS_S, MIN_FIT_DIFFERENCES, fit_bank};
pub(crate) use hybrid::HybridForecast;
pub use kalman::{KalmanBias, KalmanCounters, TEMPERATURE_EVIDENCE};
pub(crate) use model_forecast::ModelForecast;
pub use multiscale::{MultiScaleKalman, REFIT_S};
pub use startup_hold::StartupHold;

use super::calibration::NoiseCalibration;
use super::model_slot::ModelSlot;
use super::warm::AxisWarm;

/// The samples seen as static since the last commit (not yet confirmed): count and sum of the
/// raw rates, deg/s.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PendingMean {
    /// Samples pending.
    pub count: u64,
    /// Their sum, deg/s.
    pub sum: f64,
}

impl PendingMean {
    /// The drift of a tracker with nothing committed yet (start-up, or after a relearn): the
    /// pending samples' plain mean, of variance `white`/n (+∞ without a positive white-noise
    /// variance per sample, or without samples), not from the tracker's model.
    pub fn startup_estimate(self, white: f64) -> DriftEstimate {
        match self.count {
            0 => DriftEstimate { drift: 0.0, variance: f64::INFINITY, from_model: false },
            n => {
                let variance = if white > 0.0 { white / n as f64 } else { f64::INFINITY };
                DriftEstimate { drift: self.sum / n as f64, variance, from_model: false }
            }
        }
    }
}

/// An estimator's drift for one sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriftEstimate {
    /// Drift to subtract, deg/s.
    pub drift: f64,
    /// Variance of `drift` as an estimate of the true drift, (deg/s)²; +∞ while unknown.
    pub variance: f64,
    /// Whether the estimator's own model made it (`false`: a start-up fallback; status bit 0).
    pub from_model: bool,
}

/// One axis' online drift estimator (module documentation). Implementations allocate nothing
/// per sample.
pub trait DriftEstimator: fmt::Debug + Send {
    /// The estimator's name in the configuration and in snapshots.
    fn name(&self) -> &'static str;

    /// The drift of the sample with index `now` (samples since start), from the committed
    /// samples and, where the estimator uses them, the `pending` ones; `noise` is the axis'
    /// self-calibration.
    fn predict(&mut self, now: u64, pending: PendingMean, noise: &NoiseCalibration) -> DriftEstimate;

    /// The drift while the platform moves; by default the same as [`DriftEstimator::predict`].
    fn predict_moving(&mut self, now: u64, pending: PendingMean, noise: &NoiseCalibration) -> DriftEstimate {
        self.predict(now, pending, noise)
    }

    /// A confirmed static sample `raw` (deg/s) taken at index `index`.
    fn commit(&mut self, index: u64, raw: f64, noise: &NoiseCalibration);

    /// The temperature (°C; NaN when the sample has none) of the sample the next
    /// [`DriftEstimator::predict`], [`DriftEstimator::predict_moving`] or
    /// [`DriftEstimator::commit`] refers to; the pipeline sets it before each. Estimators without
    /// a temperature term ignore it.
    fn set_temperature(&mut self, _temp_c: f64) {}

    /// The model slot a background retrainer installs into (`None`: the estimator needs none).
    fn model_slot(&self) -> Option<&Arc<ModelSlot>> {
        None
    }

    /// The committed, denoised history a retrainer trains on (empty: none).
    fn training_history(&self) -> &[f64] {
        &[]
    }

    /// Longest model history this estimator can serve (0: it takes no models).
    fn max_model_history(&self) -> usize {
        0
    }

    /// Forecast horizon a model must reach (denoiser lag + 1; 1 for estimators without models).
    fn model_steps(&self) -> usize {
        1
    }

    /// Copies the state a warm restart needs into `warm` (the fields this estimator uses).
    fn warm(&self, warm: &mut AxisWarm);

    /// Restores what [`DriftEstimator::warm`] copied.
    fn restore(&mut self, warm: &AxisWarm);

    /// Whether a committed static sample backs the estimate: false at start-up and after
    /// [`DriftEstimator::relearn`], while only the pending samples' mean stands in.
    fn has_reference(&self) -> bool;

    /// Forgets the estimate: the detector found it wrong ([`Decision::relearn`]); the next
    /// commits start afresh (and until then the pending samples' mean stands in, as at
    /// start-up). Estimators that hold no such state ignore it (start-up bias-hold holds by
    /// definition).
    ///
    /// [`Decision::relearn`]: crate::stream::detector::Decision::relearn
    fn relearn(&mut self) {}

    /// The sample period (s) became known: estimators that work in seconds size themselves.
    fn set_period(&mut self, _period_s: f64) {}

    /// Innovation counters of a Kalman-type estimator (`None` for the others).
    fn kalman_counters(&self) -> Option<KalmanCounters> {
        None
    }
}

/// The registry of estimators: `[drift] estimator` in the configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum EstimatorKind {
    /// [`KalmanBias`] (the default).
    Kalman,
    /// `ModelForecast` with the CPSO-LSSVM retrainer (the paper's method).
    CpsoLssvm,
    /// [`StartupHold`].
    BiasHold,
    /// [`MultiScaleKalman`].
    Multiscale,
    /// [`AdaptiveKalman`].
    Adaptive,
    /// `HybridForecast`: the Kalman tracker, plus a CPSO-LSSVM forecast of the bias trajectory
    /// while moving.
    Hybrid,
}

impl EstimatorKind {
    /// Every estimator, in documentation order.
    pub const ALL: [Self; 6] =
        [Self::Kalman, Self::CpsoLssvm, Self::BiasHold, Self::Multiscale, Self::Adaptive, Self::Hybrid];

    /// The name in the configuration.
    pub fn name(self) -> &'static str {
        match self {
            Self::Kalman => "kalman",
            Self::CpsoLssvm => "cpso-lssvm",
            Self::BiasHold => "bias-hold",
            Self::Multiscale => "multiscale",
            Self::Adaptive => "adaptive",
            Self::Hybrid => "hybrid",
        }
    }

    /// Whether the estimator takes models from a background retrainer.
    pub fn uses_models(self) -> bool {
        matches!(self, Self::CpsoLssvm | Self::Hybrid)
    }
}

impl fmt::Display for EstimatorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for EstimatorKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL.into_iter().find(|k| k.name() == s).ok_or_else(|| {
            let names: Vec<_> = Self::ALL.iter().map(|k| k.name()).collect();
            format!("unknown drift estimator {s:?} (one of {})", names.join(", "))
        })
    }
}

/// Settings of the estimators (`[drift]` and what the model forecaster needs from
/// `[denoise]`, `[retrain]` and `[pipeline]`).
#[derive(Debug, Clone, PartialEq)]
pub struct DriftConfig {
    /// Which estimator.
    pub kind: EstimatorKind,
    /// Kalman: innovation gate, a χ²(1) tail probability (a committed sample whose normalised
    /// innovation squared is less likely than this is not used, and counted).
    pub innovation_gate: f64,
    /// bias-hold: seconds of start-up static samples averaged.
    pub startup_s: f64,
    /// Kalman: when samples carry a temperature, run a filter with a temperature coefficient
    /// (bias = b + c·(T − T₀)) beside the scalar one, used once the data favour it
    /// ([`TEMPERATURE_EVIDENCE`]).
    pub temperature: bool,
}

impl Default for DriftConfig {
    fn default() -> Self {
        Self { kind: EstimatorKind::Kalman, innovation_gate: 1e-6, startup_s: 60.0, temperature: true }
    }
}

impl DriftConfig {
    /// Checks the values; the message names the key.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.innovation_gate >= crate::model::normal::MIN_PROBABILITY && self.innovation_gate < 0.5) {
            return Err(format!("drift.innovation_gate: {} must lie in [1e-12, 0.5)", self.innovation_gate));
        }
        if !(self.startup_s > 0.0 && self.startup_s.is_finite()) {
            return Err(format!("drift.startup_s: {} must be positive and finite", self.startup_s));
        }
        Ok(())
    }
}
