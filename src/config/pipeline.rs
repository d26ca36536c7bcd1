//! The pipeline's sections — `[denoise]`, `[embedding]`, `[pipeline]`, `[drift]`, `[motion]`,
//! `[input]`, `[retrain]` — and the validated settings built from them ([`Config::pipeline`],
//! [`Config::cpso_lssvm`]). `[drift]`, `[motion]`, `[input]` and `[retrain]` deserialise straight
//! into the runtime types ([`section_keys!`](super::keys) names each key once); each runtime
//! type validates itself (`validate` beside it), so a key is checked in one place.

use serde::Deserialize;

use super::keys::{by_name, section_keys};
use super::{Config, ConfigError, DEFAULT_DENOISE_LAG, DEFAULT_DENOISE_WINDOW};
use crate::model::cpso::{CpsoConfig, CpsoError};
use crate::model::embed::Embedding;
use crate::model::lssvm::CpsoLssvm;
use crate::stream::{
    CausalConfig, DetectorKind, DriftConfig, InputConfig, MotionConfig, PipelineConfig, RetrainMode, RetrainSchedule,
    StatisticalConfig,
};
use crate::wavelet::{DenoiseConfig, Wavelet};

/// `[pipeline]` keys.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PipelineSection {
    /// Static samples averaged by the bias estimate used before the first model.
    pub bias_samples: u64,
}

impl Default for PipelineSection {
    fn default() -> Self {
        Self { bias_samples: 1000 }
    }
}

// `[drift]`: straight into the estimators' [`DriftConfig`] (`estimator` is its `kind`).
section_keys!(DriftConfig {
    "estimator" => kind,
    "innovation_gate" => innovation_gate,
    "startup_s" => startup_s,
    "temperature" => temperature,
});

impl<'de> Deserialize<'de> for RetrainMode {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let modes = [Self::Deterministic, Self::Live].map(|m| (m.name(), m));
        by_name(d, "retrain.mode", &modes)
    }
}

/// `[motion]`: which detector, and the settings of each, as the detectors take them.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionSection {
    /// `statistical`, `threshold` or `none`.
    pub detector: DetectorKind,
    /// The statistical detector's keys (`false_alarm` … `relearn_s`).
    pub statistical: StatisticalConfig,
    /// The threshold gate's keys (`rate_dps`, `variance_dps2`, `window`).
    pub threshold: MotionConfig,
}

impl Default for MotionSection {
    fn default() -> Self {
        Self {
            detector: DetectorKind::Statistical,
            statistical: StatisticalConfig::default(),
            threshold: MotionConfig::default(),
        }
    }
}

section_keys!(MotionSection {
    "detector" => detector,
    "false_alarm" => statistical.false_alarm,
    "windows_s" => statistical.windows_s,
    "variance_window_s" => statistical.variance_window_s,
    "settle_s" => statistical.settle_s,
    "guard_s" => statistical.guard_s,
    "relearn_s" => statistical.relearn_s,
    "rate_dps" => threshold.rate_dps,
    "variance_dps2" => threshold.variance_dps2,
    "window" => threshold.window,
});

/// `[input] rate_hz`: a nominal rate in Hz, or `"auto"` (measured from the first timestamps).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RateSetting {
    /// Measured: the median of the first timestamp steps.
    Auto,
    /// Given, Hz.
    Hz(f64),
}

impl<'de> Deserialize<'de> for RateSetting {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Raw {
            Number(f64),
            Word(String),
        }
        match Raw::deserialize(d)? {
            Raw::Number(hz) => Ok(Self::Hz(hz)),
            Raw::Word(w) if w == "auto" => Ok(Self::Auto),
            Raw::Word(w) => {
                Err(serde::de::Error::custom(format!("input.rate_hz: {w:?} is neither a number nor \"auto\"")))
            }
        }
    }
}

/// `[input]`: the nominal rate, and the input checks' thresholds as they take them (their
/// `period_ns` is set from `rate_hz` by [`Config::pipeline`]).
#[derive(Debug, Clone, PartialEq)]
pub struct InputSection {
    /// Nominal sample rate, Hz, or measured.
    pub rate_hz: RateSetting,
    /// `range_dps`, `gap_factor`, `spike_z`, `spike_max_run`, `stuck_s`.
    pub check: InputConfig,
}

impl Default for InputSection {
    fn default() -> Self {
        Self { rate_hz: RateSetting::Auto, check: InputConfig::default() }
    }
}

section_keys!(InputSection {
    "range_dps" => check.range_dps,
    "rate_hz" => rate_hz,
    "gap_factor" => check.gap_factor,
    "spike_z" => check.spike_z,
    "spike_max_run" => check.spike_max_run,
    "stuck_s" => check.stuck_s,
});

/// `[retrain]`: the pipeline's retrain schedule and the retrainer's CPSO-LSSVM, as they take
/// them (the model's embedding is set from `[embedding]` and `denoise.lag` by
/// [`Config::cpso_lssvm`]), and the retrain thread's nice value.
#[derive(Debug, Clone, PartialEq)]
pub struct RetrainSection {
    /// `mode`, `window`, `every_samples`, `interval_s`, `apply_delay_samples`, `min_samples`:
    /// reloadable (SIGHUP).
    pub schedule: RetrainSchedule,
    /// `exact_max_rows`, `prototypes`, `cpso_candidates`, `cpso_particles`, `cpso_iterations`,
    /// `seed`, `threads` (0 = all cores).
    pub fit: CpsoLssvm,
    /// Nice value of the retrain thread(s), 0 … 19 (higher = yields the CPU to the sample loop).
    pub nice: i32,
}

impl Default for RetrainSection {
    fn default() -> Self {
        let fit = CpsoLssvm { cpso: CpsoConfig { threads: 1, ..CpsoConfig::default() }, ..CpsoLssvm::default() };
        Self { schedule: RetrainSchedule::default(), fit, nice: 10 }
    }
}

section_keys!(RetrainSection {
    "mode" => schedule.mode,
    "window" => schedule.window,
    "every_samples" => schedule.every_samples,
    "interval_s" => schedule.interval_s,
    "apply_delay_samples" => schedule.apply_delay_samples,
    "min_samples" => schedule.min_samples,
    "exact_max_rows" => fit.exact_max_rows,
    "prototypes" => fit.prototypes,
    "cpso_candidates" => fit.cpso.candidates,
    "cpso_particles" => fit.cpso.particles,
    "cpso_iterations" => fit.cpso.iterations,
    "seed" => fit.cpso.seed,
    "threads" => fit.cpso.threads,
    "nice" => nice,
});

/// `[denoise]` keys.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DenoiseSection {
    /// Mother wavelet, `db1` … `db10` (paper: db4).
    pub wavelet: String,
    /// Decomposition levels (paper: 3).
    pub level: usize,
    /// Causal mode: samples in the sliding window.
    pub window: usize,
    /// Causal mode: samples between the newest input and the emitted estimate.
    pub lag: usize,
}

impl Default for DenoiseSection {
    fn default() -> Self {
        Self { wavelet: "db4".into(), level: 3, window: DEFAULT_DENOISE_WINDOW, lag: DEFAULT_DENOISE_LAG }
    }
}

/// `[embedding]` keys.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct EmbeddingSection {
    /// Delay τ in samples (paper: 10).
    pub tau: usize,
    /// Embedding dimension m (paper: 3).
    pub dim: usize,
}

impl Default for EmbeddingSection {
    fn default() -> Self {
        Self { tau: Embedding::PAPER.tau, dim: Embedding::PAPER.dim }
    }
}

impl Config {
    /// The pipeline settings of `[denoise]`, `[embedding]`, `[pipeline]`, `[drift]`, `[motion]`,
    /// `[input]` and `[retrain]`, validated ([`PipelineConfig::validate`]: each setting by the
    /// guard of its own type).
    pub fn pipeline(&self) -> Result<PipelineConfig, ConfigError> {
        self.limits()?;
        let period_ns = match self.input.rate_hz {
            RateSetting::Auto => 0,
            RateSetting::Hz(hz) if hz > 0.0 && hz.is_finite() => (1e9 / hz).round().max(1.0) as u64,
            RateSetting::Hz(hz) => return Err(ConfigError(format!("input.rate_hz: {hz} must be positive and finite"))),
        };
        if !(0..=19).contains(&self.retrain.nice) {
            return Err(ConfigError(format!("retrain.nice: {} is outside 0..=19", self.retrain.nice)));
        }
        let settings = PipelineConfig {
            causal: self.causal_denoise()?,
            embedding: self.embedding(),
            bias_samples: self.pipeline.bias_samples,
            motion: self.motion.threshold,
            detector: self.motion.detector,
            statistical: self.motion.statistical.clone(),
            drift: self.drift.clone(),
            input: InputConfig { period_ns, ..self.input.check },
            retrain: self.retrain.schedule,
        };
        settings.validate().map_err(ConfigError)?;
        self.cpso_lssvm()?;
        Ok(settings)
    }

    /// The retrainer's CPSO-LSSVM (paper §2.2) from `[retrain]` and `[embedding]`; the other
    /// settings are [`CpsoLssvm::default`]. Its targets lie `denoise.lag + 1` samples ahead
    /// (direct multi-step forecasting, [`Embedding::horizon`]): the pipeline's newest denoised
    /// value is L samples old when a sample arrives, and one model evaluation then reaches that
    /// sample — instead of iterating a one-step model L + 1 times, which costs L + 1 evaluations
    /// per sample and compounds its error; CPSO also tunes γ, σ² on the forecast actually used.
    pub fn cpso_lssvm(&self) -> Result<CpsoLssvm, ConfigError> {
        let fit = &self.retrain.fit;
        if fit.prototypes == 0 {
            return Err(ConfigError("retrain.prototypes must be at least 1".into()));
        }
        fit.cpso.validate().map_err(|(CpsoError::Config(m) | CpsoError::Bounds(m))| {
            ConfigError(format!("retrain.cpso_particles/retrain.cpso_candidates: {m}"))
        })?;
        if fit.cpso.iterations == 0 {
            return Err(ConfigError("retrain.cpso_iterations must be at least 1".into()));
        }
        Ok(CpsoLssvm { embedding: self.embedding().with_horizon(self.denoise.lag + 1), ..fit.clone() })
    }

    /// The batch denoiser settings of `[denoise]`.
    pub fn denoise(&self) -> Result<DenoiseConfig, ConfigError> {
        let wavelet =
            Wavelet::from_name(&self.denoise.wavelet).map_err(|e| ConfigError(format!("denoise.wavelet: {e}")))?;
        if !(1..=32).contains(&self.denoise.level) {
            return Err(ConfigError(format!("denoise.level: {} is outside 1..=32", self.denoise.level)));
        }
        Ok(DenoiseConfig { wavelet, level: self.denoise.level })
    }

    /// The causal denoiser settings of `[denoise]`.
    pub fn causal_denoise(&self) -> Result<CausalConfig, ConfigError> {
        let causal = CausalConfig { denoise: self.denoise()?, window: self.denoise.window, lag: self.denoise.lag };
        causal.validate().map_err(|e| ConfigError(format!("denoise.window/denoise.lag: {e}")))?;
        Ok(causal)
    }

    /// The embedding of `[embedding]`.
    pub fn embedding(&self) -> Embedding {
        Embedding::new(self.embedding.tau, self.embedding.dim)
    }
}
