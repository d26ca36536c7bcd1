//! The registries: what `[drift] estimator` and `[motion] detector` name, built. The one place
//! that maps a configured kind ([`EstimatorKind`], [`DetectorKind`]) to its implementation, so
//! the [`Pipeline`](super::Pipeline) only sees the traits ([`DriftEstimator`],
//! [`MotionDetector`]); a new estimator or detector adds one arm here.

use super::causal_denoise::CausalConfig;
use super::detector::{
    DetectorKind, MotionDetector, NoDetector, StatisticalConfig, StatisticalDetector, ThresholdDetector,
};
use super::drift::{
    AdaptiveKalman, DriftConfig, DriftEstimator, EstimatorKind, HybridForecast, KalmanBias, ModelForecast,
    MultiScaleKalman, StartupHold,
};
use super::motion_gate::MotionConfig;

impl EstimatorKind {
    /// One axis' estimator of this kind with the settings of `drift`; the model forecasters
    /// keep `history` static samples (the causal denoiser `causal` and the start-up bias average
    /// of `bias_samples` are the `cpso-lssvm` path's). The message of an error names the key.
    pub fn build(
        self,
        drift: &DriftConfig,
        causal: &CausalConfig,
        history: usize,
        bias_samples: u64,
    ) -> Result<Box<dyn DriftEstimator>, String> {
        Ok(match self {
            Self::Kalman => Box::new(KalmanBias::new(drift.innovation_gate, drift.temperature)),
            Self::BiasHold => Box::new(StartupHold::new(drift.startup_s)),
            Self::Multiscale => Box::new(MultiScaleKalman::new(drift.innovation_gate)),
            Self::Adaptive => Box::new(AdaptiveKalman::new(drift.innovation_gate, drift.temperature)),
            Self::Hybrid => Box::new(HybridForecast::new(drift.innovation_gate, drift.temperature, history)),
            Self::CpsoLssvm => {
                Box::new(ModelForecast::new(causal.clone(), history, bias_samples).map_err(|e| e.to_string())?)
            }
        })
    }
}

impl DetectorKind {
    /// The detector of this kind: the statistical one with `statistical`, the threshold gate
    /// with `threshold`, or none (only the publisher's flag).
    pub fn build(self, statistical: &StatisticalConfig, threshold: MotionConfig) -> Box<dyn MotionDetector> {
        match self {
            Self::Statistical => Box::new(StatisticalDetector::new(statistical.clone())),
            Self::Threshold => Box::new(ThresholdDetector::new(threshold)),
            Self::None => Box::new(NoDetector::new()),
        }
    }
}
