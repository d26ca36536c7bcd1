//! The pipeline's sections — `[denoise]`, `[embedding]`, `[pipeline]`, `[drift]`, `[motion]`,
//! `[input]`, `[retrain]` — and the validated settings built from them ([`Config::pipeline`],
//! [`Config::cpso_lssvm`]).

use serde::Deserialize;

use super::{Config, ConfigError, DEFAULT_DENOISE_LAG, DEFAULT_DENOISE_WINDOW};
use crate::model::cpso::{CpsoConfig, CpsoError};
use crate::model::embed::Embedding;
use crate::model::lssvm::CpsoLssvm;
use crate::stream::{
    CausalConfig, DetectorKind, DriftConfig, EstimatorKind, InputConfig, MotionConfig, PipelineConfig, RetrainMode,
    RetrainSchedule, StatisticalConfig,
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

/// `[drift]` keys.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DriftSection {
    /// `kalman`, `cpso-lssvm`, `bias-hold` or `hybrid`.
    pub estimator: EstimatorKind,
    /// Kalman innovation gate: χ²(1) tail probability.
    pub innovation_gate: f64,
    /// bias-hold: start-up seconds averaged.
    pub startup_s: f64,
    /// Kalman: learn a temperature coefficient when samples carry `temp_c`.
    pub temperature: bool,
}

impl Default for DriftSection {
    fn default() -> Self {
        let d = DriftConfig::default();
        Self { estimator: d.kind, innovation_gate: d.innovation_gate, startup_s: d.startup_s, temperature: d.temperature }
    }
}

/// `[motion]` keys.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MotionSection {
    /// `statistical` or `threshold`.
    pub detector: DetectorKind,
    /// statistical: false-alarm probability of each test.
    pub false_alarm: f64,
    /// statistical: mean-shift windows, s.
    pub windows_s: Vec<f64>,
    /// statistical: variance-test window, s.
    pub variance_window_s: f64,
    /// statistical: hysteresis after the last alarm, s.
    pub settle_s: f64,
    /// statistical: extra look-back discarded before an onset, s.
    pub guard_s: f64,
    /// statistical: seconds of unexplained, unchanging "moving" after which the drift estimate
    /// is relearnt (0: never).
    pub relearn_s: f64,
    /// threshold: |rate − drift| above which a sample is moving, deg/s.
    pub rate_dps: f64,
    /// threshold: short-window variance above which a sample is moving, (deg/s)².
    pub variance_dps2: f64,
    /// threshold: samples in the variance window.
    pub window: usize,
}

impl Default for MotionSection {
    fn default() -> Self {
        let s = StatisticalConfig::default();
        Self {
            detector: DetectorKind::Statistical,
            false_alarm: s.false_alarm,
            windows_s: s.windows_s,
            variance_window_s: s.variance_window_s,
            settle_s: s.settle_s,
            guard_s: s.guard_s,
            relearn_s: s.relearn_s,
            rate_dps: 2.0,
            variance_dps2: 0.6,
            window: 20,
        }
    }
}

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
            Raw::Word(w) => Err(serde::de::Error::custom(format!("input.rate_hz: {w:?} is neither a number nor \"auto\""))),
        }
    }
}

/// `[input]` keys.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct InputSection {
    /// Largest accepted |rate|, deg/s.
    pub range_dps: f64,
    /// Nominal sample rate, Hz, or measured.
    pub rate_hz: RateSetting,
    /// A timestamp step above this many nominal periods is a gap.
    pub gap_factor: f64,
    /// Spike threshold in σ of the recent static samples (0 = off).
    pub spike_z: f64,
    /// Longest run of outliers rejected as spikes (a longer run is a real change).
    pub spike_max_run: u32,
    /// Seconds of one bit-identical value on an axis after which the sensor is stuck (0 = off).
    pub stuck_s: f64,
}

impl Default for InputSection {
    fn default() -> Self {
        Self { range_dps: 2000.0, rate_hz: RateSetting::Auto, gap_factor: 3.0, spike_z: 8.0, spike_max_run: 3, stuck_s: 2.0 }
    }
}

/// `[retrain]` keys.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RetrainSection {
    /// `deterministic` (every `every_samples`, applied after `apply_delay_samples`) or `live`
    /// (every `interval_s` of wall time, applied when ready).
    pub mode: String,
    /// Static denoised samples per axis in a training window.
    pub window: usize,
    /// Deterministic mode: input samples between requests.
    pub every_samples: u64,
    /// Live mode: seconds between requests.
    pub interval_s: f64,
    /// Deterministic mode: samples between a request and its model's application.
    pub apply_delay_samples: u64,
    /// Fewest static samples per axis for a request.
    pub min_samples: usize,
    /// Largest number of training rows solved exactly; above, the fixed-size LS-SVM.
    pub exact_max_rows: usize,
    /// Prototypes m_p of the fixed-size LS-SVM.
    pub prototypes: usize,
    /// CPSO chaotic candidates M.
    pub cpso_candidates: usize,
    /// CPSO particles N.
    pub cpso_particles: usize,
    /// CPSO iterations t_max.
    pub cpso_iterations: usize,
    /// CPSO seed.
    pub seed: u64,
    /// Threads for the CPSO fitness evaluations (0 = all cores).
    pub threads: usize,
    /// Nice value of the retrain thread(s), 0 … 19 (higher = yields the CPU to the sample loop).
    pub nice: i32,
}

impl Default for RetrainSection {
    fn default() -> Self {
        let cpso = CpsoConfig::default();
        Self {
            mode: "live".into(),
            window: 4000,
            every_samples: 6000,
            interval_s: 60.0,
            apply_delay_samples: 1000,
            min_samples: 500,
            exact_max_rows: 1000,
            prototypes: 100,
            cpso_candidates: cpso.candidates,
            cpso_particles: cpso.particles,
            cpso_iterations: cpso.iterations,
            seed: 0,
            threads: 1,
            nice: 10,
        }
    }
}

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
    /// The pipeline settings of `[denoise]`, `[embedding]`, `[pipeline]`, `[motion]`, `[input]`
    /// and `[retrain]`, validated.
    pub fn pipeline(&self) -> Result<PipelineConfig, ConfigError> {
        fn err<T>(m: String) -> Result<T, ConfigError> {
            Err(ConfigError(m))
        }
        let positive = |key: &str, v: f64| {
            if v > 0.0 && v.is_finite() { Ok(()) } else { err(format!("{key}: {v} must be positive and finite")) }
        };
        self.limits()?;
        if self.pipeline.bias_samples == 0 {
            return err("pipeline.bias_samples must be at least 1".into());
        }
        let m = &self.motion;
        let statistical = StatisticalConfig {
            false_alarm: m.false_alarm,
            windows_s: m.windows_s.clone(),
            variance_window_s: m.variance_window_s,
            settle_s: m.settle_s,
            guard_s: m.guard_s,
            relearn_s: m.relearn_s,
        };
        statistical.validate().map_err(ConfigError)?;
        let d = &self.drift;
        if !(d.innovation_gate >= crate::model::normal::MIN_PROBABILITY && d.innovation_gate < 0.5) {
            return err(format!("drift.innovation_gate: {} must lie in [1e-12, 0.5)", d.innovation_gate));
        }
        positive("drift.startup_s", d.startup_s)?;
        positive("motion.rate_dps", m.rate_dps)?;
        positive("motion.variance_dps2", m.variance_dps2)?;
        if m.window < 2 {
            return err(format!("motion.window: {} must be at least 2", m.window));
        }
        let i = &self.input;
        positive("input.range_dps", i.range_dps)?;
        let period_ns = match i.rate_hz {
            RateSetting::Auto => 0,
            RateSetting::Hz(hz) => {
                positive("input.rate_hz", hz)?;
                (1e9 / hz).round().max(1.0) as u64
            }
        };
        if !(i.gap_factor > 1.0 && i.gap_factor.is_finite()) {
            return err(format!("input.gap_factor: {} must be finite and above 1", i.gap_factor));
        }
        if !(i.spike_z >= 0.0 && i.spike_z.is_finite()) || (i.spike_z > 0.0 && i.spike_z < 3.0) {
            return err(format!("input.spike_z: {} must be 0 (off) or a finite value of at least 3", i.spike_z));
        }
        if !(i.stuck_s == 0.0 || (0.1..=3600.0).contains(&i.stuck_s)) {
            return err(format!("input.stuck_s: {} must be 0 (off) or lie in [0.1, 3600] s", i.stuck_s));
        }
        let r = &self.retrain;
        if !(0..=19).contains(&r.nice) {
            return err(format!("retrain.nice: {} is outside 0..=19", r.nice));
        }
        let mode = match r.mode.as_str() {
            "deterministic" => RetrainMode::Deterministic,
            "live" => RetrainMode::Live,
            other => return err(format!("retrain.mode: {other:?} is neither \"deterministic\" nor \"live\"")),
        };
        let embedding = self.embedding();
        if r.window < embedding.history() + 3 {
            return err(format!(
                "retrain.window: {} is shorter than the embedding needs ({})",
                r.window,
                embedding.history() + 3
            ));
        }
        if r.every_samples == 0 {
            return err("retrain.every_samples must be at least 1".into());
        }
        positive("retrain.interval_s", r.interval_s)?;
        if r.min_samples > r.window {
            return err(format!("retrain.min_samples: {} exceeds retrain.window {}", r.min_samples, r.window));
        }
        self.cpso_lssvm()?;
        Ok(PipelineConfig {
            causal: self.causal_denoise()?,
            embedding,
            bias_samples: self.pipeline.bias_samples,
            motion: MotionConfig { rate_dps: m.rate_dps, variance_dps2: m.variance_dps2, window: m.window },
            detector: m.detector,
            statistical,
            drift: DriftConfig {
                kind: d.estimator,
                innovation_gate: d.innovation_gate,
                startup_s: d.startup_s,
                temperature: d.temperature,
            },
            input: InputConfig {
                range_dps: i.range_dps,
                period_ns,
                gap_factor: i.gap_factor,
                spike_z: i.spike_z,
                spike_max_run: i.spike_max_run,
                stuck_s: i.stuck_s,
            },
            retrain: RetrainSchedule {
                mode,
                window: r.window,
                every_samples: r.every_samples,
                interval_s: r.interval_s,
                apply_delay_samples: r.apply_delay_samples,
                min_samples: r.min_samples,
            },
        })
    }

    /// The retrainer's CPSO-LSSVM (paper §2.2) from `[retrain]` and `[embedding]`; the other
    /// settings are [`CpsoLssvm::default`]. Its targets lie `denoise.lag + 1` samples ahead
    /// (direct multi-step forecasting, [`Embedding::horizon`]): the pipeline's newest denoised
    /// value is L samples old when a sample arrives, and one model evaluation then reaches that
    /// sample — instead of iterating a one-step model L + 1 times, which costs L + 1 evaluations
    /// per sample and compounds its error; CPSO also tunes γ, σ² on the forecast actually used.
    pub fn cpso_lssvm(&self) -> Result<CpsoLssvm, ConfigError> {
        let r = &self.retrain;
        if r.prototypes == 0 {
            return Err(ConfigError("retrain.prototypes must be at least 1".into()));
        }
        let cpso = CpsoConfig {
            candidates: r.cpso_candidates,
            particles: r.cpso_particles,
            iterations: r.cpso_iterations,
            seed: r.seed,
            threads: r.threads,
            ..CpsoConfig::default()
        };
        cpso.validate().map_err(|(CpsoError::Config(m) | CpsoError::Bounds(m))| {
            ConfigError(format!("retrain.cpso_particles/retrain.cpso_candidates: {m}"))
        })?;
        if r.cpso_iterations == 0 {
            return Err(ConfigError("retrain.cpso_iterations must be at least 1".into()));
        }
        Ok(CpsoLssvm {
            embedding: self.embedding().with_horizon(self.denoise.lag + 1),
            cpso,
            exact_max_rows: r.exact_max_rows,
            prototypes: r.prototypes,
            ..CpsoLssvm::default()
        })
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
