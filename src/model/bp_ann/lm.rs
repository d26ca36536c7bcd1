//! Levenberg–Marquardt training (Hagan & Menhaj 1994), following MATLAB's `trainlm`.
//!
//! With residuals `r = ŷ − t` over the training rows and the Jacobian `J = ∂ŷ/∂p`, each epoch
//! tries `p' = p − (JᵀJ + μI)⁻¹ Jᵀr` (Cholesky): if the training MSE falls the step is taken
//! and `μ ← max(μ·μ_dec, 1e-20)`, else `μ ← μ·μ_inc` and the step is retried. Training stops
//! at `max_epochs`, when the MSE reaches `goal`, when `‖∇MSE‖ = (2/n)‖Jᵀr‖ < min_grad`, when μ
//! exceeds `mu_max`, or when the validation MSE has risen above its best for `max_fail`
//! consecutive epochs (early stopping); the weights with the best validation MSE are returned, as MATLAB
//! does (the final weights when there is no validation set).

use nalgebra::{Cholesky, DMatrix, DVector};

use super::net::Layout;
use super::{StopReason, TrainReport};

/// `trainlm` settings (a subset of [`BpAnn`](super::BpAnn)).
pub(super) struct LmSettings {
    pub(super) max_epochs: usize,
    pub(super) mu: f64,
    pub(super) mu_dec: f64,
    pub(super) mu_inc: f64,
    pub(super) mu_max: f64,
    pub(super) min_grad: f64,
    pub(super) goal: f64,
    pub(super) max_fail: usize,
}

/// Row-major inputs (`rows × inputs`) and targets.
pub(super) struct Rows<'a> {
    pub(super) x: &'a [f64],
    pub(super) t: &'a [f64],
}

impl Rows<'_> {
    fn len(&self) -> usize {
        self.t.len()
    }
}

/// Mean squared error of the network `p` on `rows`.
fn mse(l: &Layout, p: &[f64], rows: &Rows) -> f64 {
    let m = l.inputs;
    let ss: f64 = rows
        .t
        .iter()
        .enumerate()
        .map(|(k, &t)| {
            let x = &rows.x[k * m..(k + 1) * m];
            let e = l.forward(p, |j| x[j]) - t;
            e * e
        })
        .sum();
    ss / rows.len() as f64
}

/// Trains `p` in place; `val` may be empty (no early stopping).
pub(super) fn train(l: &Layout, p: &mut Vec<f64>, train: &Rows, val: &Rows, s: &LmSettings) -> TrainReport {
    let (n, np, m) = (train.len(), l.n_params(), l.inputs);
    let has_val = val.len() > 0;
    let mut j = DMatrix::<f64>::zeros(n, np);
    let mut jt = DMatrix::<f64>::zeros(np, n);
    let mut jj = DMatrix::<f64>::zeros(np, np);
    let mut je = DVector::<f64>::zeros(np);
    let mut r = DVector::<f64>::zeros(n);
    let mut g = vec![0.0; np];
    let mut trial = vec![0.0; np];

    let mut perf = mse(l, p, train);
    let mut best_val = if has_val { mse(l, p, val) } else { f64::INFINITY };
    let mut best = p.clone();
    let (mut best_epoch, mut fails, mut mu) = (0, 0, s.mu);
    let mut epochs = 0;
    let stop = loop {
        if perf <= s.goal {
            break StopReason::Goal;
        }
        if epochs == s.max_epochs {
            break StopReason::MaxEpochs;
        }
        for k in 0..n {
            let x = &train.x[k * m..(k + 1) * m];
            r[k] = l.forward_grad(p, x, &mut g) - train.t[k];
            for (c, &gk) in g.iter().enumerate() {
                j[(k, c)] = gk;
            }
        }
        j.transpose_to(&mut jt);
        jj.gemm(1.0, &jt, &j, 0.0);
        je.gemv(1.0, &jt, &r, 0.0);
        if 2.0 / n as f64 * je.norm() < s.min_grad {
            break StopReason::MinGradient;
        }
        let stepped = loop {
            let mut a = jj.clone();
            for d in 0..np {
                a[(d, d)] += mu;
            }
            if let Some(chol) = Cholesky::new(a) {
                let step = chol.solve(&je);
                for ((t, pk), dk) in trial.iter_mut().zip(p.iter()).zip(step.iter()) {
                    *t = pk - dk;
                }
                let perf2 = mse(l, &trial, train);
                if perf2 < perf {
                    std::mem::swap(p, &mut trial);
                    perf = perf2;
                    mu = (mu * s.mu_dec).max(1e-20);
                    break true;
                }
            }
            mu *= s.mu_inc;
            if mu > s.mu_max {
                break false;
            }
        };
        if !stepped {
            break StopReason::MuMax;
        }
        epochs += 1;
        if has_val {
            let v = mse(l, p, val);
            if v < best_val {
                best_val = v;
                best.clone_from(p);
                best_epoch = epochs;
                fails = 0;
            } else if v > best_val {
                // As `trainlm`: an equal validation error is neither a gain nor a failure.
                fails += 1;
                if fails >= s.max_fail {
                    break StopReason::ValidationFailures;
                }
            }
        }
    };
    if has_val {
        p.clone_from(&best);
    } else {
        best_epoch = epochs;
    }
    TrainReport {
        epochs,
        best_epoch,
        stop,
        train_mse: mse(l, p, train),
        val_mse: has_val.then_some(best_val),
        train_rows: n,
        val_rows: val.len(),
    }
}
