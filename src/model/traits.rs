//! The common shape of every drift predictor, after linfa's `Fit`/`Predict` split: a
//! configuration implements [`Fit`] and returns a fitted model that implements [`Predict`].
//! The paper's CPSO-LSSVM, the BP-ANN and every baseline (persistence, mean, AR, startup
//! bias-hold, …) share it, so evaluation and the streaming pipeline treat them alike.
//!
//! Data are one contiguous series in normalised units (paper Eq. 21): a model decides itself
//! how it reads the history — PSR rows (Eq. 15–16), consecutive lags, or nothing at all.

use std::fmt;

use super::snapshot::ModelState;

/// A fitted predictor of the sample [`horizon`](Self::horizon) steps after its history
/// (one step unless the model was fitted on direct multi-step targets).
pub trait Predict {
    /// Samples of history one prediction reads (the most recent `history_len` of the slice).
    fn history_len(&self) -> usize;

    /// Predicts the sample `horizon()` steps after the end of `history` (oldest first; 1 = the
    /// sample that follows it). `history` holds at least [`history_len`](Self::history_len)
    /// samples; only the last ones are read.
    fn predict(&self, history: &[f64]) -> f64;

    /// How many samples after the end of its history a prediction lies (1 by default).
    fn horizon(&self) -> usize {
        1
    }

    /// The fitted model as a storable [`ModelState`] (model snapshots), or `None` when this kind
    /// of model cannot be stored (the default). Restoring the state must give a model whose
    /// predictions are bit-identical.
    fn state(&self) -> Option<ModelState> {
        None
    }
}

/// A model configuration that can be fitted to a training series.
pub trait Fit {
    /// The fitted model.
    type Model: Predict;

    /// Fits on `train`: every sample with enough history before it inside `train` is a
    /// training target.
    fn fit(&self, train: &[f64]) -> Result<Self::Model, FitError>;
}

/// Why a model could not be fitted.
#[derive(Debug, Clone, PartialEq)]
pub enum FitError {
    /// The training series is too short for the model's history and parameters.
    TooFewSamples {
        /// Samples needed.
        need: usize,
        /// Samples given.
        have: usize,
    },
    /// A training value is NaN or infinite.
    NonFinite,
    /// The linear system is not (numerically) positive definite, or another numerical failure.
    Numerical(String),
    /// A configuration value is out of range.
    InvalidConfig(String),
}

impl fmt::Display for FitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooFewSamples { need, have } => {
                write!(f, "training series too short: need {need} samples, have {have}")
            }
            Self::NonFinite => write!(f, "training series holds NaN or infinite values"),
            Self::Numerical(msg) => write!(f, "numerical failure: {msg}"),
            Self::InvalidConfig(msg) => write!(f, "invalid model configuration: {msg}"),
        }
    }
}

impl std::error::Error for FitError {}

/// One-step-ahead predictions of `series[start..]`, each from the samples before it
/// (`start` must be at least the model's history length).
pub fn predict_from(model: &impl Predict, series: &[f64], start: usize) -> Vec<f64> {
    assert!(start >= model.history_len(), "start {start} leaves less history than the model needs");
    (start..series.len()).map(|t| model.predict(&series[..t])).collect()
}

/// A stored model predicts like the model it came from (bit-identical, [`ModelState`]'s
/// contract): a restored snapshot is used through the same trait.
impl Predict for ModelState {
    fn history_len(&self) -> usize {
        match self {
            Self::Lssvm(t) => t.model.history_len(),
            Self::Constant { .. } => 0,
        }
    }

    fn predict(&self, history: &[f64]) -> f64 {
        match self {
            Self::Lssvm(t) => t.model.predict(history),
            Self::Constant { value } => *value,
        }
    }

    fn horizon(&self) -> usize {
        match self {
            Self::Lssvm(t) => t.model.horizon(),
            Self::Constant { .. } => 1,
        }
    }

    fn state(&self) -> Option<ModelState> {
        Some(self.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A toy model: the mean of the last two samples.
    struct MeanOfTwo;

    impl Predict for MeanOfTwo {
        fn history_len(&self) -> usize {
            2
        }
        fn predict(&self, history: &[f64]) -> f64 {
            let n = history.len();
            0.5 * (history[n - 1] + history[n - 2])
        }
    }

    #[test]
    fn predictions_use_only_the_past() {
        let series = [1.0, 3.0, 5.0, 100.0];
        assert_eq!(predict_from(&MeanOfTwo, &series, 2), vec![2.0, 4.0]);
    }
}
