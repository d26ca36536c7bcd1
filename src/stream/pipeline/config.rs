//! The pipeline's vocabulary: its settings ([`PipelineConfig`], validated by the guard of each
//! part's own type), its counters ([`PipelineStats`]) and its errors ([`PipelineError`]).

use std::fmt;

use crate::model::embed::Embedding;
use crate::stream::causal_denoise::CausalConfig;
use crate::stream::detector::{DetectorCounters, DetectorKind, StatisticalConfig};
use crate::stream::drift::DriftConfig;
use crate::stream::input_check::{InputConfig, InputCounters};
use crate::stream::motion_gate::MotionConfig;
use crate::stream::retrain::RetrainSchedule;

/// Everything the pipeline needs (built from [`crate::config::Config::pipeline`]).
#[derive(Debug, Clone, PartialEq)]
pub struct PipelineConfig {
    /// Causal denoiser of each axis.
    pub causal: CausalConfig,
    /// PSR embedding of the models (sets the least history kept).
    pub embedding: Embedding,
    /// Samples the running static bias estimate averages (used before the first model).
    pub bias_samples: u64,
    /// Thresholds of the `threshold` detector.
    pub motion: MotionConfig,
    /// Which static/moving detector.
    pub detector: DetectorKind,
    /// Settings of the `statistical` detector.
    pub statistical: StatisticalConfig,
    /// Which drift estimator, and its settings.
    pub drift: DriftConfig,
    /// Input validation and gaps.
    pub input: InputConfig,
    /// Retrain schedule (used once a trainer is attached).
    pub retrain: RetrainSchedule,
}

impl PipelineConfig {
    /// Checks every setting with the guard of its own type (and the bias average and the
    /// retrain window against the embedding); the message names the key.
    pub fn validate(&self) -> Result<(), String> {
        self.causal.validate().map_err(|e| format!("denoise.window/denoise.lag: {e}"))?;
        if self.bias_samples == 0 {
            return Err("pipeline.bias_samples must be at least 1".into());
        }
        self.statistical.validate()?;
        self.drift.validate()?;
        self.motion.validate()?;
        self.input.validate()?;
        self.retrain.validate(self.embedding.history())
    }
}

/// Counters of what the pipeline has done.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PipelineStats {
    /// Samples processed.
    pub samples: u64,
    /// Rejected samples (status bit 2), all causes.
    pub rejected: u64,
    /// Moving samples (status bit 1).
    pub moving: u64,
    /// Gaps detected (status bit 3).
    pub gaps: u64,
    /// What the input checks found, by cause.
    pub input: InputCounters,
    /// Retrain requests sent.
    pub retrain_requests: u64,
    /// Retrain requests skipped because the previous one was still running.
    pub retrain_skipped: u64,
    /// Retrain requests not sent for want of static samples (< `min_samples`).
    pub retrain_starved: u64,
    /// Fits that failed (the old model was kept).
    pub retrain_failed: u64,
    /// Successful retrains installed.
    pub models_installed: u64,
    /// Static samples committed to the drift estimators.
    pub committed: u64,
    /// Pending static samples discarded as the lead-in of a detected motion.
    pub discarded: u64,
    /// What the static detector did.
    pub detector: DetectorCounters,
}

/// Why a pipeline could not be built or a model installed.
#[derive(Debug, Clone, PartialEq)]
pub enum PipelineError {
    /// A configuration value is unusable; the message names it.
    Config(String),
    /// Axis index not in 0..3.
    NoSuchAxis(usize),
    /// The model forecasts neither one step nor the pipeline's L + 1 steps ahead.
    HorizonMismatch {
        /// The model's horizon.
        model: usize,
        /// The pipeline's horizon (denoiser lag + 1).
        pipeline: usize,
    },
    /// The estimator takes no models (its name).
    NoModels(&'static str),
    /// The model needs more history than the pipeline keeps.
    HistoryTooLong {
        /// Samples the model reads.
        need: usize,
        /// Samples kept.
        kept: usize,
    },
}

impl fmt::Display for PipelineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Config(m) => f.write_str(m),
            Self::NoSuchAxis(a) => write!(f, "axis {a} does not exist (0, 1, 2)"),
            Self::NoModels(name) => write!(f, "the {name} drift estimator takes no models"),
            Self::HorizonMismatch { model, pipeline } => write!(
                f,
                "model forecasts {model} samples ahead; the pipeline needs 1 (iterated) or {pipeline} (denoise.lag + 1)"
            ),
            Self::HistoryTooLong { need, kept } => {
                write!(f, "model reads {need} samples of history, the pipeline keeps {kept}")
            }
        }
    }
}

impl std::error::Error for PipelineError {}
