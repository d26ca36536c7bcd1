//! The fitted LS-SVM regressor as a [`Predict`] (its data, [`LssvmModel`] and
//! [`KernelExpansion`], are in [`super::expansion`]) and the exact-LSSVM configuration
//! [`LssvmConfig`] (paper §2.2, Eq. 7).

use super::exact::solve_exact;
use super::expansion::{KernelExpansion, LssvmModel};
use super::validate::check_hyper;
use crate::model::baselines::linear_psr::check_embedding;
use crate::model::embed::{Embedded, Embedding};
use crate::model::{Fit, FitError, Predict};

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
