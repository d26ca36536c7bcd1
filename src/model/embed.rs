//! Phase-space reconstruction (PSR) by delay embedding, paper Eq. 15–16 and 25–26.
//!
//! With delay τ and dimension m, input row k (0-based) is
//! `[x_k, x_{k+τ}, …, x_{k+(m−1)τ}]` and its target is the next sample `x_{k+(m−1)τ+1}`:
//! for τ = 10, m = 3 the first row is `[x_0, x_10, x_20] → x_21` (the paper's 1-based
//! `[x_1, x_11, x_21] → x_22`). A series of n samples gives `n − (m−1)τ − 1` rows.
//!
//! A forecast horizon h ≥ 1 generalises the target to `x_{k+(m−1)τ+h}` (direct multi-step
//! forecasting; h = 1 is the paper's Eq. 16) and gives `n − (m−1)τ − h` rows. The streaming
//! pipeline uses h = denoiser lag + 1, so one model evaluation reaches the sample being
//! compensated instead of iterating a one-step model h times.

use serde::{Deserialize, Serialize};

/// Delay-embedding parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Embedding {
    /// Delay τ in samples (≥ 1).
    pub tau: usize,
    /// Embedding dimension m (≥ 1).
    pub dim: usize,
    /// Forecast horizon h (≥ 1): the target lies h samples after the row's last element
    /// (1 = the paper's one-step target, Eq. 16).
    #[serde(default = "one_step")]
    pub horizon: usize,
}

fn one_step() -> usize {
    1
}

/// Embedded series: `rows` input vectors of length `dim` (row-major) and their targets.
#[derive(Debug, Clone, PartialEq)]
pub struct Embedded {
    /// Dimension of each input vector.
    pub dim: usize,
    /// Input vectors, row-major, `rows × dim`.
    pub inputs: Vec<f64>,
    /// Target of each row (h samples after its last element).
    pub targets: Vec<f64>,
}

impl Embedded {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.targets.len()
    }

    /// Input vector `k`.
    pub fn row(&self, k: usize) -> &[f64] {
        &self.inputs[k * self.dim..(k + 1) * self.dim]
    }
}

impl Embedding {
    /// The paper's choice (C-C method on its data): τ = 10, m = 3.
    pub const PAPER: Self = Self::new(10, 3);

    /// A one-step embedding (h = 1) with delay `tau` and dimension `dim`.
    pub const fn new(tau: usize, dim: usize) -> Self {
        Self { tau, dim, horizon: 1 }
    }

    /// The same delays with forecast horizon `horizon` (direct multi-step targets).
    pub const fn with_horizon(self, horizon: usize) -> Self {
        Self { horizon, ..self }
    }

    /// Delay window τw = (m − 1)·τ (paper Eq. 17): the span of one input vector minus one.
    pub fn window(&self) -> usize {
        (self.dim - 1) * self.tau
    }

    /// Samples of history one prediction needs: τw + 1.
    pub fn history(&self) -> usize {
        self.window() + 1
    }

    /// Number of (input, target) rows a series of `n` samples gives: `n − τw − h` (or 0).
    pub fn rows(&self, n: usize) -> usize {
        n.saturating_sub(self.window() + self.horizon)
    }

    /// Samples a series needs to give `rows` rows: `τw + h + rows` (inverse of [`Self::rows`]).
    pub fn samples_for_rows(&self, rows: usize) -> usize {
        self.window() + self.horizon + rows
    }

    /// Embeds a whole series (Eq. 15–16, target h samples ahead).
    pub fn embed(&self, x: &[f64]) -> Embedded {
        assert!(self.tau >= 1 && self.dim >= 1 && self.horizon >= 1, "τ, m and h must be at least 1");
        let rows = self.rows(x.len());
        let mut inputs = Vec::with_capacity(rows * self.dim);
        for k in 0..rows {
            inputs.extend((0..self.dim).map(|j| x[k + j * self.tau]));
        }
        let first_target = self.window() + self.horizon;
        let targets = x.get(first_target..).map_or_else(Vec::new, <[f64]>::to_vec);
        Embedded { dim: self.dim, inputs, targets }
    }

    /// Fills `out` (length m) with the input vector that predicts the sample h after the end of
    /// `history`: `[h_{n−1−τw}, …, h_{n−1−τ}, h_{n−1}]`. `history` needs at least τw + 1 samples.
    pub fn latest_into(&self, history: &[f64], out: &mut [f64]) {
        let n = history.len();
        assert!(n >= self.history(), "need {} samples of history, have {n}", self.history());
        assert_eq!(out.len(), self.dim);
        let first = n - 1 - self.window();
        for (j, slot) in out.iter_mut().enumerate() {
            *slot = history[first + j * self.tau];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_rows_are_x1_x11_x21_to_x22() {
        // x_i = i (0-based), so values name their own indices.
        let x: Vec<f64> = (0..30).map(|i| i as f64).collect();
        let e = Embedding::PAPER.embed(&x);
        assert_eq!(e.rows(), 30 - 21);
        assert_eq!(e.row(0), &[0.0, 10.0, 20.0]);
        assert_eq!(e.targets[0], 21.0);
        assert_eq!(e.row(8), &[8.0, 18.0, 28.0]);
        assert_eq!(e.targets[8], 29.0);
        assert_eq!(Embedding::PAPER.window(), 20);
    }

    #[test]
    fn latest_vector_predicts_the_next_sample() {
        let x: Vec<f64> = (0..50).map(|i| i as f64).collect();
        let emb = Embedding::new(4, 4);
        let all = emb.embed(&x);
        // The row whose target is x[49] is the latest vector of history x[..49].
        let mut v = vec![0.0; 4];
        emb.latest_into(&x[..49], &mut v);
        assert_eq!(v.as_slice(), all.row(all.rows() - 1));
        assert_eq!(*all.targets.last().unwrap(), 49.0);
    }

    #[test]
    fn horizon_moves_the_target_and_drops_rows() {
        let x: Vec<f64> = (0..30).map(|i| i as f64).collect();
        let e = Embedding::PAPER.with_horizon(6).embed(&x);
        assert_eq!(e.rows(), 30 - 20 - 6);
        assert_eq!(e.row(0), &[0.0, 10.0, 20.0]);
        assert_eq!(e.targets[0], 26.0);
        assert_eq!(*e.targets.last().unwrap(), 29.0);
        assert_eq!(e.row(e.rows() - 1), &[3.0, 13.0, 23.0]);
    }

    #[test]
    fn short_series_give_no_rows() {
        assert_eq!(Embedding::PAPER.rows(21), 0);
        assert_eq!(Embedding::PAPER.rows(22), 1);
        assert_eq!(Embedding::PAPER.embed(&[1.0; 10]).rows(), 0);
    }
}
