//! Sim-to-real gap diagnosis (docs/design.md "Sim-to-real diagnosis"; `gyrocomp simgap`): where a
//! simulation of a gyro differs from a real recording, which unmodelled effect explains the
//! difference, and how far the gap shrinks once that effect is simulated, checked on a held-out
//! part of the recording.
//!
//! - [`robust`]: quantiles, median, MAD, block means, kurtosis; [`robust_allan`]: the median-based
//!   Allan deviation the noise terms are fitted to.
//! - [`stats`]: the statistics compared (Allan deviation per τ band, PSD bands, spectral line,
//!   distribution, compensation, bias trajectory).
//! - [`band`]: Monte-Carlo bands and the standard score of a value in them.
//! - [`gap`]: the scalar gap, its null distribution from the ensemble, significance.
//! - [`model`], [`baseline`], [`refit`]: the simulated model, the IEEE Std 952 baseline fit and
//!   its refit once fitted effects are removed.
//! - [`effects`] (catalogue) with [`params`] (the effects and their fitted parameters) and
//!   [`fit_time`], [`fit_spectral`], [`fit_events`] (the fits); [`fast_line`]: the strongest line
//!   of a whole part's periodogram.
//! - [`ensemble`]: the seeded ensemble of a model, compared on the training and hold-out parts;
//!   [`uncertainty`]: the noise terms' uncertainty carried into it.
//! - [`greedy`]: acceptance, ranking and the greedy combination of effects; [`nested`]: the
//!   nested-model test of a Gauss–Markov process the baseline may have absorbed,
//!   [`nested_temperature`] that of a temperature response and [`nested_warmup`] that of a
//!   warm-up, on the Whittle likelihood of [`whittle`] (a regressor's gain in
//!   [`nested_regressor`]); [`nested_ramp`] that of a ramp, by generalised least squares on block
//!   means; [`nested_jumps`] that of a step process, a piecewise-constant level against a random
//!   walk ([`segmentation`]).
//! - [`diagnose`](mod@diagnose): the whole diagnosis of one recording; [`inputs`] (settings,
//!   baseline, recording), [`outcome`] (verdict, effect results, diagnosis), [`builder`] (the
//!   models it simulates).
//! - [`selftest`]: recordings with a known injected effect, and the confusion table.
//!
//! Pure numerics: nothing here reads or writes files.

pub mod band;
pub mod baseline;
pub mod builder;
pub mod diagnose;
pub mod effects;
pub mod ensemble;
pub mod fast_line;
pub mod fit_events;
pub mod fit_spectral;
pub mod fit_time;
pub mod gap;
pub mod greedy;
pub mod inputs;
pub mod model;
pub mod naming;
pub mod nested;
pub mod nested_jumps;
pub mod nested_ramp;
pub mod nested_regressor;
pub mod nested_temperature;
pub mod nested_warmup;
pub mod outcome;
pub mod params;
pub mod refit;
pub mod robust;
pub mod robust_allan;
pub mod segmentation;
pub mod selftest;
pub mod stats;
pub mod uncertainty;
pub mod whittle;

pub use diagnose::diagnose;
pub use inputs::{Baseline, Recording, Settings};
pub use outcome::{Diagnosis, EffectResult, Verdict};
pub use params::{EffectKind, EffectParams};

use crate::diag::allan::AllanError;
use crate::diag::noise_fit::NoiseFitError;
use crate::diag::psd::PsdError;
use crate::sim::ConfigError;

/// Why a diagnosis could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimgapError {
    /// A part of the recording is too short for the statistics.
    #[error("{samples} samples in a part of the recording; at least {need} are needed")]
    TooShort {
        /// Samples in the part.
        samples: usize,
        /// Samples needed.
        need: usize,
    },
    /// A setting or input is out of range.
    #[error("{0}")]
    BadSetting(String),
    /// The model uses the temperature but the recording has none.
    #[error("the model needs the recorded temperature (temp_c), which is absent")]
    NoTemperature,
    /// The Allan deviation failed.
    #[error("Allan deviation: {0}")]
    Allan(#[from] AllanError),
    /// The PSD failed.
    #[error("PSD: {0}")]
    Psd(#[from] PsdError),
    /// The noise-term fit failed.
    #[error("noise-term fit: {0}")]
    NoiseFit(#[from] NoiseFitError),
    /// The simulator refused the model.
    #[error("simulator: {0}")]
    Config(#[from] ConfigError),
    /// Another numerical failure.
    #[error("{0}")]
    Numerical(String),
}
