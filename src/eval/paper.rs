//! The paper's evaluation protocol (§4.3, docs/design.md "Evaluation protocols: paper"):
//! the first `samples` samples are wavelet-denoised (batch), embedded (τ = 10, m = 3), scaled to
//! [−1, 1] (Eq. 21) on the training part, and split 80/20 by rows; each model predicts every test
//! target one step ahead from the actual samples before it. Errors are given in normalised units
//! (as the paper's Table 1) and in deg/s, with the standard deviation before and after
//! compensation both of the raw test signal (raw − prediction) and of the denoised drift
//! (denoised − prediction, the paper's Table 2 figure).

use std::fmt;

use serde::Serialize;

use crate::model::embed::Embedding;
use crate::model::metrics::{Metrics, sample_std_dev};
use crate::model::scaler::MinMaxScaler;
use crate::wavelet::{DenoiseConfig, denoise_batch};

/// Settings of the paper protocol.
#[derive(Debug, Clone, PartialEq)]
pub struct PaperProtocol {
    /// Samples taken from the start of the recording (paper: the first group of 5000).
    pub samples: usize,
    /// Phase-space embedding (paper: τ = 10, m = 3).
    pub embedding: Embedding,
    /// Fraction of embedded rows used for training (paper: 80 %).
    pub train_fraction: f64,
    /// Batch denoiser (paper: db4, 3 levels, soft threshold).
    pub denoise: DenoiseConfig,
}

impl Default for PaperProtocol {
    fn default() -> Self {
        Self { samples: 5000, embedding: Embedding::PAPER, train_fraction: 0.8, denoise: DenoiseConfig::paper() }
    }
}

/// Why the protocol could not be prepared.
#[derive(Debug, Clone, PartialEq)]
pub enum ProtocolError {
    /// Too few samples for the embedding and split.
    TooShort {
        /// Samples needed.
        need: usize,
        /// Samples given.
        have: usize,
    },
    /// A setting is out of range.
    Invalid(String),
}

impl fmt::Display for ProtocolError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooShort { need, have } => {
                write!(f, "the paper protocol needs at least {need} samples, the series has {have}")
            }
            Self::Invalid(msg) => f.write_str(msg),
        }
    }
}

impl std::error::Error for ProtocolError {}

/// The data of one protocol run, shared by every model so that all are scored on the same split.
#[derive(Debug, Clone)]
pub struct Prepared {
    /// Raw samples (deg/s), the first `samples` of the recording.
    pub raw: Vec<f64>,
    /// Batch-denoised samples (deg/s).
    pub denoised: Vec<f64>,
    /// Denoised samples in normalised units (scaler fitted on the training part).
    pub normalised: Vec<f64>,
    /// The scaler (fitted on samples `..train_end`).
    pub scaler: MinMaxScaler,
    /// Index of the first test target; samples `..train_end` are the training series.
    pub train_end: usize,
}

impl Prepared {
    /// The training series in normalised units.
    pub fn train(&self) -> &[f64] {
        &self.normalised[..self.train_end]
    }

    /// Number of test targets.
    pub fn test_len(&self) -> usize {
        self.normalised.len() - self.train_end
    }
}

impl PaperProtocol {
    /// Takes the first `samples` of `raw`, denoises, scales on the training part and splits.
    pub fn prepare(&self, raw: &[f64]) -> Result<Prepared, ProtocolError> {
        if !(self.train_fraction > 0.0 && self.train_fraction < 1.0) {
            return Err(ProtocolError::Invalid(format!("train fraction {} is outside (0, 1)", self.train_fraction)));
        }
        let history = self.embedding.history();
        let need = history + 10;
        let n = self.samples.min(raw.len());
        if n < need {
            return Err(ProtocolError::TooShort { need, have: raw.len() });
        }
        let raw = raw[..n].to_vec();
        let (denoised, _) = denoise_batch(&raw, &self.denoise);
        let rows = self.embedding.rows(n);
        let train_rows = ((rows as f64) * self.train_fraction).round() as usize;
        let train_end = (train_rows + history).clamp(history + 1, n - 1);
        let scaler = MinMaxScaler::fit(&denoised[..train_end])
            .ok_or_else(|| ProtocolError::Invalid("the training part holds non-finite values".into()))?;
        let normalised = denoised.iter().map(|&v| scaler.transform(v)).collect();
        Ok(Prepared { raw, denoised, normalised, scaler, train_end })
    }
}

/// Accuracy and compensation figures of one model under the paper protocol.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PaperScores {
    /// MAE of the normalised test predictions (Eq. 22).
    pub mae_norm: f64,
    /// RMSE of the normalised test predictions (Eq. 23).
    pub rmse_norm: f64,
    /// ARE (Eq. 24) with |y|: mean |ŷ − y| / |y| over normalised test targets. Unstable: the
    /// normalised series crosses zero, where single terms explode (infinite, `null` in JSON,
    /// when a target is exactly 0). For comparison with the paper only, never for ranking.
    pub are: f64,
    /// MAE in deg/s.
    pub mae_dps: f64,
    /// RMSE in deg/s.
    pub rmse_dps: f64,
    /// Standard deviation (n − 1, as MATLAB's `std`) of the raw test samples, deg/s.
    pub std_raw_before: f64,
    /// Standard deviation of raw − prediction over the test part, deg/s.
    pub std_raw_after: f64,
    /// Standard deviation of the denoised test samples (the "random drift"), deg/s.
    pub std_drift_before: f64,
    /// Standard deviation of denoised − prediction over the test part (paper Table 2), deg/s.
    pub std_drift_after: f64,
}

/// Scores normalised one-step predictions of the test targets `prepared.normalised[train_end..]`.
pub fn score(prepared: &Prepared, predictions: &[f64]) -> PaperScores {
    let start = prepared.train_end;
    let targets = &prepared.normalised[start..];
    assert_eq!(predictions.len(), targets.len(), "one prediction per test target");
    let m = Metrics::new(predictions, targets).expect("a non-empty test part");
    let in_dps: Vec<f64> = predictions.iter().map(|&p| prepared.scaler.inverse(p)).collect();
    let raw = &prepared.raw[start..];
    let drift = &prepared.denoised[start..];
    let raw_after: Vec<f64> = raw.iter().zip(&in_dps).map(|(r, p)| r - p).collect();
    let drift_after: Vec<f64> = drift.iter().zip(&in_dps).map(|(d, p)| d - p).collect();
    let std = |x: &[f64]| sample_std_dev(x).unwrap_or(0.0);
    PaperScores {
        mae_norm: m.mae,
        rmse_norm: m.rmse,
        are: m.are,
        mae_dps: prepared.scaler.inverse_scale(m.mae),
        rmse_dps: prepared.scaler.inverse_scale(m.rmse),
        std_raw_before: std(raw),
        std_raw_after: std(&raw_after),
        std_drift_before: std(drift),
        std_drift_after: std(&drift_after),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series(n: usize) -> Vec<f64> {
        (0..n).map(|i| 0.01 * (i as f64 * 0.01).sin() + 0.001 * ((i * 7919 % 101) as f64 / 101.0 - 0.5)).collect()
    }

    #[test]
    fn split_follows_rows_and_scaler_sees_only_training_data() {
        let raw = series(6000);
        let p = PaperProtocol::default().prepare(&raw).unwrap();
        assert_eq!(p.raw.len(), 5000);
        // 4979 rows, 80 % = 3983 training rows → targets start after 3983 + 21 samples.
        assert_eq!(p.train_end, 3983 + 21);
        assert_eq!(p.test_len(), 5000 - 4004);
        let train = &p.normalised[..p.train_end];
        assert!(train.iter().all(|v| (-1.0 - 1e-12..=1.0 + 1e-12).contains(v)));
        assert!(train.iter().any(|&v| (v + 1.0).abs() < 1e-12) && train.iter().any(|&v| (v - 1.0).abs() < 1e-12));
    }

    #[test]
    fn perfect_predictions_remove_the_whole_drift() {
        let p = PaperProtocol::default().prepare(&series(5000)).unwrap();
        let perfect = p.normalised[p.train_end..].to_vec();
        let s = score(&p, &perfect);
        assert_eq!((s.mae_norm, s.rmse_norm, s.are), (0.0, 0.0, 0.0));
        assert!(s.std_drift_after < 1e-15);
        let noise: Vec<f64> = p.raw[p.train_end..].iter().zip(&p.denoised[p.train_end..]).map(|(r, d)| r - d).collect();
        assert!((s.std_raw_after - sample_std_dev(&noise).unwrap()).abs() < 1e-15);
        assert!(s.std_drift_before > 0.0);
    }

    #[test]
    fn errors_convert_to_deg_per_s_with_the_half_range() {
        let p = PaperProtocol::default().prepare(&series(5000)).unwrap();
        let shifted: Vec<f64> = p.normalised[p.train_end..].iter().map(|v| v + 0.1).collect();
        let s = score(&p, &shifted);
        assert!((s.mae_norm - 0.1).abs() < 1e-12 && (s.rmse_norm - 0.1).abs() < 1e-12);
        let half_range = 0.5 * (p.scaler.max - p.scaler.min);
        assert!((s.rmse_dps - 0.1 * half_range).abs() < 1e-15);
    }

    #[test]
    fn too_short_series_is_an_error() {
        assert!(matches!(PaperProtocol::default().prepare(&series(20)), Err(ProtocolError::TooShort { .. })));
    }
}
