//! The n₀–H–1 feed-forward network of paper §2.1: hidden inputs `v_i = Σ_j w_ij x_j + b_i`
//! (Eq. 1), logistic sigmoid `g(v) = 1/(1 + e^{−v})` (Eq. 2), hidden outputs `g(v_i)` (Eq. 3),
//! and one output neuron `y = f(Σ_i w2_i g(v_i) + b2)`.
//!
//! Parameters live in one flat vector, `[W (H × n₀, row-major) | b (H) | w2 (H) | b2]`, so the
//! Levenberg–Marquardt step works on a single vector of `H·n₀ + 2H + 1` entries (51 for 3-10-1).

use serde::{Deserialize, Serialize};

use crate::model::rng::SplitMix64;

/// Activation of the output neuron.
///
/// The paper (§2.1) says the output uses the same logistic sigmoid as the hidden layer; its range
/// (0, 1) cannot reach the negative half of targets normalised to [−1, 1] (Eq. 21), so that
/// reading cannot be what was run. MATLAB's `feedforwardnet`, which the paper's training times
/// suggest, uses a linear (`purelin`) output by default; that is the default here.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum OutputActivation {
    /// `f(z) = z` (MATLAB `purelin`).
    #[default]
    Linear,
    /// `f(z) = tanh z`, range (−1, 1) (MATLAB `tansig`).
    Tanh,
}

impl OutputActivation {
    /// `(f(z), f'(z))`.
    #[inline]
    fn apply(self, z: f64) -> (f64, f64) {
        match self {
            Self::Linear => (z, 1.0),
            Self::Tanh => {
                let y = z.tanh();
                (y, 1.0 - y * y)
            }
        }
    }
}

/// Logistic sigmoid, Eq. 2.
#[inline]
fn sigmoid(v: f64) -> f64 {
    1.0 / (1.0 + (-v).exp())
}

/// Shape of an n₀–H–1 network.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Layout {
    pub(super) inputs: usize,
    pub(super) hidden: usize,
    pub(super) output: OutputActivation,
}

impl Layout {
    /// Number of weights and thresholds: `H·n₀ + 2H + 1`.
    pub(super) fn n_params(&self) -> usize {
        self.hidden * self.inputs + 2 * self.hidden + 1
    }

    /// Network output for the input `x(j)`, j < n₀ (Eq. 1–3 and the output neuron).
    #[inline]
    pub(super) fn forward(&self, p: &[f64], x: impl Fn(usize) -> f64) -> f64 {
        let (m, h) = (self.inputs, self.hidden);
        let (w, rest) = p.split_at(h * m);
        let (b, rest) = rest.split_at(h);
        let (w2, b2) = rest.split_at(h);
        let mut z = b2[0];
        for i in 0..h {
            let row = &w[i * m..(i + 1) * m];
            let v = row.iter().enumerate().fold(b[i], |acc, (j, wij)| acc + wij * x(j));
            z += w2[i] * sigmoid(v);
        }
        self.output.apply(z).0
    }

    /// Network output for `x` and its gradient with respect to every parameter, into `g`
    /// (length [`n_params`](Self::n_params)): one row of the Jacobian.
    pub(super) fn forward_grad(&self, p: &[f64], x: &[f64], g: &mut [f64]) -> f64 {
        let (m, h) = (self.inputs, self.hidden);
        let (w, rest) = p.split_at(h * m);
        let (b, rest) = rest.split_at(h);
        let (w2, b2) = rest.split_at(h);
        let (gw, grest) = g.split_at_mut(h * m);
        let (gb, grest) = grest.split_at_mut(h);
        let (gw2, gb2) = grest.split_at_mut(h);
        let mut z = b2[0];
        for i in 0..h {
            let row = &w[i * m..(i + 1) * m];
            let v = row.iter().zip(x).fold(b[i], |acc, (wij, xj)| acc + wij * xj);
            let s = sigmoid(v);
            gw2[i] = s;
            z += w2[i] * s;
        }
        let (y, dy) = self.output.apply(z);
        for i in 0..h {
            let s = gw2[i];
            let dv = dy * w2[i] * s * (1.0 - s);
            gb[i] = dv;
            for (gij, xj) in gw[i * m..(i + 1) * m].iter_mut().zip(x) {
                *gij = dv * xj;
            }
            gw2[i] = dy * s;
        }
        gb2[0] = dy;
        y
    }

    /// Initial parameters. Hidden layer: Nguyen–Widrow as MATLAB's `initnw` — row directions
    /// random (uniform in [−1, 1]ⁿ⁰, normalised), magnitude `β = 0.7·H^{1/n₀}`, thresholds
    /// `β·linspace(−1, 1, H)·sign(w_i1)`, then scaled by 4, the half-width of the logistic
    /// sigmoid's active input range [−4, 4] (inputs assumed in [−1, 1], as after Eq. 21).
    /// Output layer: uniform in [−1, 1] (MATLAB's `rands`).
    pub(super) fn init(&self, rng: &mut SplitMix64) -> Vec<f64> {
        let (m, h) = (self.inputs, self.hidden);
        let beta = 0.7 * (h as f64).powf(1.0 / m as f64);
        const ACTIVE: f64 = 4.0;
        let mut p = vec![0.0; self.n_params()];
        for i in 0..h {
            let row = &mut p[i * m..(i + 1) * m];
            let norm = loop {
                for w in row.iter_mut() {
                    *w = rng.symmetric();
                }
                let n = row.iter().map(|w| w * w).sum::<f64>().sqrt();
                if n > 1e-6 {
                    break n;
                }
            };
            for w in row.iter_mut() {
                *w *= ACTIVE * beta / norm;
            }
            let spread = if h == 1 { 0.0 } else { -1.0 + 2.0 * i as f64 / (h - 1) as f64 };
            p[h * m + i] = ACTIVE * beta * spread * p[i * m].signum();
        }
        for v in &mut p[h * m + h..] {
            *v = rng.symmetric();
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout(output: OutputActivation) -> Layout {
        Layout { inputs: 3, hidden: 4, output }
    }

    #[test]
    fn gradient_matches_finite_differences() {
        for output in [OutputActivation::Linear, OutputActivation::Tanh] {
            let l = layout(output);
            let p = l.init(&mut SplitMix64::new(3));
            assert_eq!(p.len(), 3 * 4 + 2 * 4 + 1);
            let x = [0.3, -0.7, 0.9];
            let mut g = vec![0.0; p.len()];
            let y = l.forward_grad(&p, &x, &mut g);
            assert!((y - l.forward(&p, |j| x[j])).abs() < 1e-15);
            for k in 0..p.len() {
                let (mut hi, mut lo) = (p.clone(), p.clone());
                hi[k] += 1e-6;
                lo[k] -= 1e-6;
                let fd = (l.forward(&hi, |j| x[j]) - l.forward(&lo, |j| x[j])) / 2e-6;
                assert!((fd - g[k]).abs() < 1e-7, "parameter {k}: {fd} vs {}", g[k]);
            }
        }
    }

    #[test]
    fn nguyen_widrow_magnitudes() {
        let l = layout(OutputActivation::Linear);
        let p = l.init(&mut SplitMix64::new(1));
        let beta = 4.0 * 0.7 * 4f64.powf(1.0 / 3.0);
        for i in 0..4 {
            let n = p[i * 3..i * 3 + 3].iter().map(|w| w * w).sum::<f64>().sqrt();
            assert!((n - beta).abs() < 1e-12);
        }
        assert!((p[12].abs() - beta).abs() < 1e-12 && (p[15].abs() - beta).abs() < 1e-12);
    }
}
