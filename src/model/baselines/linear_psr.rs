//! Linear regression on the PSR rows (paper Eq. 15–16: the same rows the LSSVM sees, delay τ and
//! dimension m) with intercept: `x̂ = c + Σ_j w_j·x_{k+jτ}` — the linear counterpart of the
//! paper's model. Fitted by least squares (Householder QR, see `lstsq`).

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use super::check_series;
use super::lstsq::QrFit;
use crate::model::embed::Embedding;
use crate::model::{Fit, FitError, Predict};

/// Linear-PSR configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct LinearPsr {
    /// PSR delay and dimension; default the paper's τ = 10, m = 3.
    pub embedding: Embedding,
}

impl Default for LinearPsr {
    fn default() -> Self {
        Self { embedding: Embedding::PAPER }
    }
}

/// Fitted linear-PSR model.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearPsrModel {
    embedding: Embedding,
    intercept: f64,
    /// One weight per PSR column, oldest first (`w_0` multiplies `x_k`, `w_{m−1}` the newest).
    weights: Vec<f64>,
}

impl LinearPsrModel {
    /// The embedding the model reads.
    pub fn embedding(&self) -> Embedding {
        self.embedding
    }

    /// The intercept c.
    pub fn intercept(&self) -> f64 {
        self.intercept
    }

    /// Weights of the PSR columns, oldest first.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }
}

/// Checks τ ≥ 1 and m ≥ 1 (shared with the BP-ANN).
pub(crate) fn check_embedding(e: Embedding) -> Result<(), FitError> {
    if e.tau == 0 || e.dim == 0 || e.horizon == 0 {
        return Err(FitError::InvalidConfig(format!(
            "embedding needs τ ≥ 1, m ≥ 1 and h ≥ 1, got τ = {}, m = {}, h = {}",
            e.tau, e.dim, e.horizon
        )));
    }
    Ok(())
}

impl Fit for LinearPsr {
    type Model = LinearPsrModel;

    /// Needs more PSR rows than parameters: `N ≥ (m−1)τ + 1 + m + 2`.
    fn fit(&self, train: &[f64]) -> Result<LinearPsrModel, FitError> {
        let e = self.embedding;
        check_embedding(e)?;
        check_series(train, e.samples_for_rows(e.dim + 2))?;
        let rows = e.embed(train);
        let d = DMatrix::from_fn(rows.rows(), e.dim + 1, |r, c| if c == 0 { 1.0 } else { rows.row(r)[c - 1] });
        let beta = QrFit::new(d, DVector::from_vec(rows.targets)).coefficients(e.dim + 1)?;
        Ok(LinearPsrModel { embedding: e, intercept: beta[0], weights: beta[1..].to_vec() })
    }
}

impl Predict for LinearPsrModel {
    fn history_len(&self) -> usize {
        self.embedding.history()
    }

    /// Reads the latest PSR row of `history` in place (as `Embedding::latest_into`, no buffer).
    fn predict(&self, history: &[f64]) -> f64 {
        let first = history.len() - 1 - self.embedding.window();
        let tau = self.embedding.tau;
        self.weights.iter().enumerate().fold(self.intercept, |acc, (j, w)| acc + w * history[first + j * tau])
    }

    fn horizon(&self) -> usize {
        self.embedding.horizon
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_config() {
        let bad = LinearPsr { embedding: Embedding::new(0, 3) };
        assert!(matches!(bad.fit(&[0.0; 100]), Err(FitError::InvalidConfig(_))));
        assert_eq!(LinearPsr::default().fit(&[0.0; 25]), Err(FitError::TooFewSamples { need: 26, have: 25 }));
        assert!(matches!(LinearPsr::default().fit(&[0.0; 26]), Err(FitError::Numerical(_))));
    }
}
