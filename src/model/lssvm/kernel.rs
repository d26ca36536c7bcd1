//! The Gaussian (RBF) kernel of paper Eq. 8 in LS-SVMlab's convention,
//! `K(x, y) = exp(−‖x − y‖² / σ²)`, where σ² (LS-SVMlab's `sig2`) is the tuned parameter, and
//! the σ²-independent squared distances the kernel matrices are built from.
//!
//! Input vectors are rows of a row-major slice (`rows × dim`), as PSR rows are stored
//! ([`crate::model::embed::Embedded`]).

use nalgebra::DMatrix;

/// Squared Euclidean distance ‖x − y‖².
#[inline]
pub fn sq_dist(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(a, b)| (a - b) * (a - b)).sum()
}

/// The RBF kernel of paper Eq. 8: `exp(−‖x − y‖² / σ²)`.
#[inline]
pub fn rbf(x: &[f64], y: &[f64], sigma2: f64) -> f64 {
    (-sq_dist(x, y) / sigma2).exp()
}

/// Squared distances between every row of `a` and every row of `b` (both row-major with `dim`
/// columns, `dim ≥ 1`), as a column-major `a_rows × b_rows` matrix: entry (i, j) = ‖a_i − b_j‖².
pub fn sq_dist_matrix(a: &[f64], b: &[f64], dim: usize) -> DMatrix<f64> {
    let dim = dim.max(1);
    let (na, nb) = (a.len() / dim, b.len() / dim);
    let mut d = DMatrix::zeros(na, nb);
    for (j, mut col) in d.column_iter_mut().enumerate() {
        let y = &b[j * dim..(j + 1) * dim];
        for (i, v) in col.iter_mut().enumerate() {
            *v = sq_dist(&a[i * dim..(i + 1) * dim], y);
        }
    }
    d
}

/// The LS-SVM system block `H = Ω + I/γ` (paper Eq. 7) for the rows of `x`, Ω_ij = K(x_i, x_j).
/// Only the lower triangle (and diagonal) is filled: the Cholesky factorisation reads no more.
pub fn kernel_plus_ridge(x: &[f64], dim: usize, sigma2: f64, gamma: f64) -> DMatrix<f64> {
    let dim = dim.max(1);
    let n = x.len() / dim;
    let mut h = DMatrix::zeros(n, n);
    let s = -1.0 / sigma2;
    let ridge = 1.0 / gamma;
    let data = h.as_mut_slice();
    for j in 0..n {
        let y = &x[j * dim..(j + 1) * dim];
        let col = &mut data[j * n..(j + 1) * n];
        col[j] = 1.0 + ridge;
        for (i, v) in col.iter_mut().enumerate().skip(j + 1) {
            *v = (sq_dist(&x[i * dim..(i + 1) * dim], y) * s).exp();
        }
    }
    h
}

/// As [`kernel_plus_ridge`], from precomputed squared distances (lower triangle read).
pub fn kernel_plus_ridge_from_sq_dist(d: &DMatrix<f64>, sigma2: f64, gamma: f64) -> DMatrix<f64> {
    let n = d.nrows();
    let mut h = DMatrix::zeros(n, n);
    let s = -1.0 / sigma2;
    let ridge = 1.0 / gamma;
    let src = d.as_slice();
    let data = h.as_mut_slice();
    for j in 0..n {
        let col = &mut data[j * n..(j + 1) * n];
        col[j] = 1.0 + ridge;
        for (v, &dd) in col[j + 1..].iter_mut().zip(&src[j * n + j + 1..(j + 1) * n]) {
            *v = (dd * s).exp();
        }
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kernel_follows_ls_svmlab_sig2_convention() {
        // ‖x − y‖² = 2, σ² = 4: exp(−0.5), not exp(−2/(2·4)).
        assert!((rbf(&[0.0, 1.0], &[1.0, 0.0], 4.0) - (-0.5f64).exp()).abs() < 1e-15);
        assert_eq!(rbf(&[0.3], &[0.3], 0.1), 1.0);
    }

    #[test]
    fn matrices_agree_with_the_pointwise_kernel() {
        let x = [0.0, 0.5, 1.0, -0.5, 0.2, 0.2];
        let h = kernel_plus_ridge(&x, 2, 0.7, 10.0);
        let d = sq_dist_matrix(&x, &x, 2);
        let h2 = kernel_plus_ridge_from_sq_dist(&d, 0.7, 10.0);
        for i in 0..3 {
            for j in 0..=i {
                let want = rbf(&x[2 * i..2 * i + 2], &x[2 * j..2 * j + 2], 0.7) + if i == j { 0.1 } else { 0.0 };
                assert!((h[(i, j)] - want).abs() < 1e-15);
                assert!((h2[(i, j)] - want).abs() < 1e-15);
            }
        }
    }
}
