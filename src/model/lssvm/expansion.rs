//! The data of a fitted LS-SVM regressor `f(x) = Σ_i c_i K(x, x_i) + b` (paper Eq. 4 in its
//! dual form, kernel Eq. 8): [`KernelExpansion`], [`LssvmModel`] and the [`Solver`] that produced
//! it. Plain data that a model snapshot stores ([`crate::model::snapshot`]); the [`Predict`]
//! implementation is in [`super::model`], so this file depends on no model trait.
//!
//! The exact model keeps every training row as a support vector (`c = α`); the fixed-size model
//! ([`super::nystrom`]) keeps its prototypes with the coefficients `β = L⁻ᵀw` of its primal
//! weights. Both predict through [`KernelExpansion`], reading the PSR input vector (Eq. 15)
//! straight out of the history, so `predict` allocates nothing.
//!
//! [`Predict`]: crate::model::Predict

use serde::{Deserialize, Serialize};

use super::kernel::sq_dist;
use crate::model::embed::Embedding;

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
    pub(super) fn eval_lagged(&self, history: &[f64], embedding: &Embedding) -> f64 {
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

/// Which LS-SVM solves the problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Solver {
    /// Exact dual solve (Eq. 7).
    Exact,
    /// Fixed-size LS-SVM with this many retained prototypes (the Nyström rank r).
    Nystrom {
        /// Retained prototypes r ≤ m_p.
        rank: usize,
    },
}
