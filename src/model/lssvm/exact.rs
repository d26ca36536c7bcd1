//! Exact LS-SVM regression (Suykens & Vandewalle 1999; paper Eq. 4–8) in LS-SVMlab
//! conventions, and its closed-form leave-one-out residuals (Cawley & Talbot 2004).
//!
//! The dual system (paper Eq. 7, standard Suykens form; the paper's typesetting is garbled)
//!
//! ```text
//! [ 0   1ᵀ      ] [ b ]   [ 0 ]
//! [ 1   Ω + I/γ ] [ α ] = [ y ],    Ω_ij = exp(−‖x_i − x_j‖² / σ²)   (Eq. 8)
//! ```
//!
//! is solved through the Cholesky factor of the SPD block `H = Ω + I/γ` (no general LU): with
//! `η = H⁻¹1` and `ν = H⁻¹y`, `b = 1ᵀν / 1ᵀη` and `α = ν − b η`. The model is
//! `f(x) = Σ α_i K(x, x_i) + b`.
//!
//! Leave-one-out: for the bordered matrix `C = [0 1ᵀ; 1 H]`, the LOO residual of sample i is
//! `r_i = y_i − f⁽⁻ⁱ⁾(x_i) = α_i / (C⁻¹)_{i+1,i+1}` (Cawley & Talbot 2004, Eq. 9, which applies
//! to any system whose solution is `C⁻¹[0; y]`). The Schur complement of `H` in `C` is
//! `−1ᵀH⁻¹1 = −s`, so the α block of `C⁻¹` is `H⁻¹ − η ηᵀ / s` and
//! `(C⁻¹)_{i+1,i+1} = (H⁻¹)_ii − η_i² / s`, from the same factor.

use nalgebra::DMatrix;

use super::dense::{cholesky_in_place, inverse_diagonal, solve_cholesky};
use super::kernel::kernel_plus_ridge;
use super::validate::{check_hyper, check_rows};
use crate::model::FitError;

/// The solution of the dual system (Eq. 7): Lagrange multipliers α, bias b, and (on request)
/// the leave-one-out residuals `y_i − f⁽⁻ⁱ⁾(x_i)`.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactSolution {
    /// Lagrange multipliers α, one per training row (support value).
    pub alpha: Vec<f64>,
    /// Bias b.
    pub bias: f64,
    /// Closed-form leave-one-out residuals (Cawley & Talbot 2004), when asked for.
    pub loo_residuals: Option<Vec<f64>>,
}

/// Solves the exact LS-SVM system (Eq. 7) for the row-major `inputs` (`targets.len()` rows of
/// `dim` values) with regularisation γ and RBF width σ² (Eq. 8). `loo` also computes the
/// closed-form leave-one-out residuals (about n³/6 extra multiply-adds). `threads`: 0 = all cores.
pub fn solve_exact(
    inputs: &[f64],
    dim: usize,
    targets: &[f64],
    gamma: f64,
    sigma2: f64,
    loo: bool,
    threads: usize,
) -> Result<ExactSolution, FitError> {
    check_hyper(gamma, sigma2)?;
    check_rows(inputs, dim, targets, if loo { 2 } else { 1 })?;
    let h = kernel_plus_ridge(inputs, dim, sigma2, gamma);
    solve_with_system(h, targets, loo, threads)
}

/// As [`solve_exact`], given the lower triangle of `H = Ω + I/γ` (consumed: it becomes the factor).
pub fn solve_with_system(
    mut h: DMatrix<f64>,
    targets: &[f64],
    loo: bool,
    threads: usize,
) -> Result<ExactSolution, FitError> {
    let n = targets.len();
    cholesky_in_place(&mut h, threads)
        .map_err(|j| FitError::Numerical(format!("Ω + I/γ is not positive definite (pivot {j} of {n})")))?;
    let mut eta = vec![1.0; n];
    solve_cholesky(&h, &mut eta);
    let mut nu = targets.to_vec();
    solve_cholesky(&h, &mut nu);
    let s: f64 = eta.iter().sum();
    if !(s > 0.0 && s.is_finite()) {
        return Err(FitError::Numerical(format!("1ᵀ(Ω + I/γ)⁻¹1 = {s} is not positive")));
    }
    let bias = nu.iter().sum::<f64>() / s;
    let alpha: Vec<f64> = nu.iter().zip(&eta).map(|(v, e)| v - bias * e).collect();
    if !bias.is_finite() || alpha.iter().any(|a| !a.is_finite()) {
        return Err(FitError::Numerical("non-finite LS-SVM solution".into()));
    }
    let loo_residuals = if loo {
        let hinv = inverse_diagonal(&h, threads);
        let r: Vec<f64> = alpha.iter().zip(&hinv).zip(&eta).map(|((a, d), e)| a / (d - e * e / s)).collect();
        if r.iter().any(|v| !v.is_finite()) {
            return Err(FitError::Numerical("non-finite leave-one-out residual".into()));
        }
        Some(r)
    } else {
        None
    };
    Ok(ExactSolution { alpha, bias, loo_residuals })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::lssvm::kernel::rbf;

    fn data(n: usize) -> (Vec<f64>, Vec<f64>) {
        let x: Vec<f64> = (0..n * 2).map(|i| ((i * 37 % 101) as f64 / 50.0) - 1.0).collect();
        let y: Vec<f64> = (0..n).map(|i| (3.0 * x[2 * i]).sin() + 0.5 * x[2 * i + 1]).collect();
        (x, y)
    }

    fn predict(x: &[f64], sol: &ExactSolution, q: &[f64], sigma2: f64) -> f64 {
        sol.alpha.iter().enumerate().map(|(i, a)| a * rbf(&x[2 * i..2 * i + 2], q, sigma2)).sum::<f64>() + sol.bias
    }

    #[test]
    fn satisfies_the_bordered_system() {
        let (x, y) = data(40);
        let (gamma, sigma2) = (20.0, 0.5);
        let sol = solve_exact(&x, 2, &y, gamma, sigma2, false, 1).unwrap();
        assert!(sol.alpha.iter().sum::<f64>().abs() < 1e-9);
        for i in 0..40 {
            // Row i of [1  Ω + I/γ]: b + Σ_j Ω_ij α_j + α_i/γ = y_i.
            let fi = predict(&x, &sol, &x[2 * i..2 * i + 2], sigma2) + sol.alpha[i] / gamma;
            assert!((fi - y[i]).abs() < 1e-9);
        }
    }

    #[test]
    fn closed_form_loo_equals_refitting() {
        let (x, y) = data(30);
        let (gamma, sigma2) = (50.0, 0.3);
        let sol = solve_exact(&x, 2, &y, gamma, sigma2, true, 1).unwrap();
        let loo = sol.loo_residuals.unwrap();
        for i in 0..30 {
            let keep: Vec<usize> = (0..30).filter(|&k| k != i).collect();
            let xs: Vec<f64> = keep.iter().flat_map(|&k| x[2 * k..2 * k + 2].to_vec()).collect();
            let ys: Vec<f64> = keep.iter().map(|&k| y[k]).collect();
            let s = solve_exact(&xs, 2, &ys, gamma, sigma2, false, 1).unwrap();
            let r = y[i] - predict(&xs, &s, &x[2 * i..2 * i + 2], sigma2);
            assert!((r - loo[i]).abs() < 1e-9 * r.abs().max(1.0), "i = {i}: {r} vs {}", loo[i]);
        }
    }

    #[test]
    fn rejects_bad_input() {
        let (x, y) = data(5);
        assert!(matches!(solve_exact(&x, 2, &y, 0.0, 1.0, false, 1), Err(FitError::InvalidConfig(_))));
        assert!(matches!(solve_exact(&x, 2, &y, 1.0, f64::NAN, false, 1), Err(FitError::InvalidConfig(_))));
        assert!(matches!(solve_exact(&x[..9], 2, &y, 1.0, 1.0, false, 1), Err(FitError::InvalidConfig(_))));
        let mut bad = y.clone();
        bad[2] = f64::INFINITY;
        assert_eq!(solve_exact(&x, 2, &bad, 1.0, 1.0, false, 1), Err(FitError::NonFinite));
        assert!(matches!(solve_exact(&[], 2, &[], 1.0, 1.0, false, 1), Err(FitError::TooFewSamples { .. })));
    }
}
