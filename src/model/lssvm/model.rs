//! The fitted LS-SVM regressor `f(x) = Σ_i c_i K(x, x_i) + b` (paper Eq. 4 in its dual form,
//! kernel Eq. 8) and the exact-LSSVM configuration [`LssvmConfig`] (paper §2.2, Eq. 7).
//!
//! The exact model keeps every training row as a support vector (`c = α`); the fixed-size model
//! ([`super::nystrom`]) keeps its prototypes with the coefficients `β = L⁻ᵀw` of its primal
//! weights. Both predict through [`KernelExpansion`], reading the PSR input vector (Eq. 15)
//! straight out of the history, so `predict` allocates nothing.

use serde::{Deserialize, Serialize};

use super::exact::solve_exact;
use super::kernel::sq_dist;
use super::validate::check_hyper;
use crate::model::baselines::linear_psr::check_embedding;
use crate::model::{Fit, FitError, Predict};
use crate::model::embed::{Embedded, Embedding};

/// A kernel expansion `f(x) = Σ_i coef_i · exp(−‖x − centre_i‖² / σ²) + bias`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct KernelExpansion {
    /// Input dimension.
    pub dim: usize,
    /// Centres (support vectors or prototypes), row-major `coef.len() × dim`.
    pub centres: Vec<f64>,
    /// Coefficient of each centre (α for the exact model).
    pub coef: Vec<f64>,
    /// Bias b.
    pub bias: f64,
    /// RBF width σ² (Eq. 8).
    pub sigma2: f64,
}

impl KernelExpansion {
    /// Number of centres.
    pub fn len(&self) -> usize {
        self.coef.len()
    }

    /// True when there are no centres (the model is the constant b).
    pub fn is_empty(&self) -> bool {
        self.coef.is_empty()
    }

    /// `f(x)` for one input vector of length `dim` (NaN for an expansion with `dim = 0`).
    pub fn eval(&self, x: &[f64]) -> f64 {
        if self.dim == 0 {
            return f64::NAN;
        }
        let s = -1.0 / self.sigma2;
        let mut acc = 0.0;
        for (c, &a) in self.centres.chunks_exact(self.dim).zip(&self.coef) {
            acc += a * (sq_dist(x, c) * s).exp();
        }
        acc + self.bias
    }

    /// `f` at every row of the row-major `rows`.
    pub fn eval_rows(&self, rows: &[f64]) -> Vec<f64> {
        rows.chunks_exact(self.dim.max(1)).map(|x| self.eval(x)).collect()
    }

    /// `f` at the PSR vector `[h_{n−1−τw}, …, h_{n−1}]` of `history` (Eq. 15), read in place.
    fn eval_lagged(&self, history: &[f64], embedding: &Embedding) -> f64 {
        if self.dim == 0 || self.dim != embedding.dim {
            return f64::NAN;
        }
        let first = history.len() - 1 - embedding.window();
        let s = -1.0 / self.sigma2;
        let mut acc = 0.0;
        for (c, &a) in self.centres.chunks_exact(self.dim).zip(&self.coef) {
            let mut d = 0.0;
            for (j, &cj) in c.iter().enumerate() {
                let v = history[first + j * embedding.tau] - cj;
                d += v * v;
            }
            acc += a * (d * s).exp();
        }
        acc + self.bias
    }
}

/// A fitted one-step-ahead LS-SVM predictor on PSR rows (exact or fixed-size).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LssvmModel {
    /// The PSR embedding its inputs are read with (Eq. 15–16).
    pub embedding: Embedding,
    /// The regression function.
    pub expansion: KernelExpansion,
}

impl Predict for LssvmModel {
    fn history_len(&self) -> usize {
        self.embedding.history()
    }

    /// `f` at the latest PSR vector of `history`; NaN when `history` is too short.
    fn predict(&self, history: &[f64]) -> f64 {
        if history.len() < self.embedding.history() {
            return f64::NAN;
        }
        self.expansion.eval_lagged(history, &self.embedding)
    }

    fn horizon(&self) -> usize {
        self.embedding.horizon
    }
}

/// Exact LS-SVM regression on PSR rows (paper §2.2, Eq. 7–8) with fixed γ and σ². The series
/// given to [`Fit::fit`] must already be normalised (Eq. 21); the model stores all
/// `n − τw − 1` rows as support vectors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LssvmConfig {
    /// Regularisation γ (Eq. 5).
    pub gamma: f64,
    /// RBF width σ² (Eq. 8, LS-SVMlab `sig2`).
    pub sigma2: f64,
    /// PSR embedding (default τ = 10, m = 3).
    pub embedding: Embedding,
}

impl Default for LssvmConfig {
    /// The paper's tuned values for its first group (§4.3): γ = 29.358, σ² = 83.162; τ = 10, m = 3.
    fn default() -> Self {
        Self { gamma: 29.358, sigma2: 83.162, embedding: Embedding::PAPER }
    }
}

/// Checks the embedding and the series and embeds it: at least `min_rows` rows.
pub(crate) fn embed_series(embedding: &Embedding, train: &[f64], min_rows: usize) -> Result<Embedded, FitError> {
    check_embedding(*embedding)?;
    if embedding.rows(train.len()) < min_rows {
        return Err(FitError::TooFewSamples { need: embedding.samples_for_rows(min_rows), have: train.len() });
    }
    if train.iter().any(|v| !v.is_finite()) {
        return Err(FitError::NonFinite);
    }
    Ok(embedding.embed(train))
}

impl LssvmConfig {
    /// Fits on explicit row-major `inputs` (`targets.len()` rows of `dim` values) and returns the
    /// regression function with all rows as support vectors (the lower-level entry point).
    pub fn fit_rows(&self, inputs: &[f64], dim: usize, targets: &[f64]) -> Result<KernelExpansion, FitError> {
        let sol = solve_exact(inputs, dim, targets, self.gamma, self.sigma2, false, 0)?;
        Ok(KernelExpansion { dim, centres: inputs.to_vec(), coef: sol.alpha, bias: sol.bias, sigma2: self.sigma2 })
    }
}

impl Fit for LssvmConfig {
    type Model = LssvmModel;

    fn fit(&self, train: &[f64]) -> Result<LssvmModel, FitError> {
        check_hyper(self.gamma, self.sigma2)?;
        let e = embed_series(&self.embedding, train, 1)?;
        let expansion = self.fit_rows(&e.inputs, e.dim, &e.targets)?;
        Ok(LssvmModel { embedding: self.embedding, expansion })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::predict_from;

    #[test]
    fn predicts_from_history_like_the_embedded_rows() {
        let x: Vec<f64> = (0..80).map(|i| (i as f64 * 0.3).sin()).collect();
        let cfg = LssvmConfig { gamma: 100.0, sigma2: 1.0, embedding: Embedding::new(2, 3) };
        let m = cfg.fit(&x[..60]).unwrap();
        let e = cfg.embedding.embed(&x);
        let via_rows = m.expansion.eval_rows(&e.inputs);
        let via_history = predict_from(&m, &x, cfg.embedding.history());
        assert_eq!(via_rows, via_history);
        assert!(m.predict(&x[..3]).is_nan());
    }

    #[test]
    fn bad_configs_and_series_are_errors() {
        let x = vec![0.1; 30];
        let bad = |c: LssvmConfig| c.fit(&x).is_err();
        let e = Embedding::new(2, 3);
        assert!(bad(LssvmConfig { gamma: -1.0, sigma2: 1.0, embedding: e }));
        assert!(bad(LssvmConfig { gamma: 1.0, sigma2: 0.0, embedding: e }));
        assert!(bad(LssvmConfig { gamma: 1.0, sigma2: 1.0, embedding: Embedding::new(0, 3) }));
        assert_eq!(
            LssvmConfig { gamma: 1.0, sigma2: 1.0, embedding: e }.fit(&x[..5]),
            Err(FitError::TooFewSamples { need: 6, have: 5 })
        );
        let mut nan = x.clone();
        nan[3] = f64::NAN;
        assert_eq!(LssvmConfig { gamma: 1.0, sigma2: 1.0, embedding: e }.fit(&nan), Err(FitError::NonFinite));
    }
}
