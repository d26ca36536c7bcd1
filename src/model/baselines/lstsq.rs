//! Linear least squares by Householder QR (nalgebra), shared by [`Ar`](super::Ar) and
//! [`LinearPsr`](super::LinearPsr).
//!
//! `X = QR`, so `‖Xβ − y‖² = ‖Rβ − Qᵀy[..k]‖² + ‖Qᵀy[k..]‖²`: β solves the triangular system and
//! the residual sum of squares is the tail of `Qᵀy`. Because the first j columns of Q span the
//! first j columns of X, one factorisation also gives the fit of every leading-column prefix —
//! the nested models AR(1) ⊂ AR(2) ⊂ … on a common sample ([`QrFit::rss`]). QR avoids squaring
//! the condition number, as the normal equations would.

use nalgebra::{DMatrix, DVector};

use crate::model::FitError;

/// A column whose part orthogonal to the previous columns is below this fraction of its norm is
/// treated as linearly dependent on them.
const RANK_TOL: f64 = 1e-10;

/// QR factorisation of a design matrix with `Qᵀy` applied.
pub(super) struct QrFit {
    /// R, `k × k` upper triangular.
    r: DMatrix<f64>,
    /// `Qᵀy`, length n.
    qty: DVector<f64>,
    /// Leading columns that are linearly independent (numerical rank of every prefix).
    rank: usize,
}

impl QrFit {
    /// Factorises `x` (n × k, n ≥ k) against the target `y` (length n).
    pub(super) fn new(x: DMatrix<f64>, y: DVector<f64>) -> Self {
        debug_assert!(x.nrows() >= x.ncols() && x.nrows() == y.len());
        let norms: Vec<f64> = x.column_iter().map(|c| c.norm()).collect();
        let qr = x.qr();
        let mut qty = y;
        qr.q_tr_mul(&mut qty);
        let r = qr.unpack_r();
        let rank = norms.iter().enumerate().take_while(|&(i, &n)| n > 0.0 && r[(i, i)].abs() > RANK_TOL * n).count();
        Self { r, qty, rank }
    }

    /// Numerical rank of the leading columns: prefixes of at most this many columns are solvable.
    pub(super) fn rank(&self) -> usize {
        self.rank
    }

    /// Residual sum of squares of the fit on the first `k` columns.
    pub(super) fn rss(&self, k: usize) -> f64 {
        self.qty.rows_range(k..).norm_squared()
    }

    /// Coefficients of the fit on the first `k` columns (`k ≤ rank`, else a numerical error).
    pub(super) fn coefficients(&self, k: usize) -> Result<Vec<f64>, FitError> {
        if k > self.rank {
            return Err(FitError::Numerical(format!(
                "rank-deficient design: column {} depends on the previous ones (constant series?)",
                self.rank
            )));
        }
        let r = self.r.view((0, 0), (k, k));
        let mut beta = self.qty.rows(0, k).clone_owned();
        if !r.solve_upper_triangular_mut(&mut beta) || beta.iter().any(|b| !b.is_finite()) {
            return Err(FitError::Numerical("triangular solve failed".into()));
        }
        Ok(beta.iter().copied().collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_an_overdetermined_system_and_its_prefixes() {
        // y = 1 + 2a − b exactly, plus a third column orthogonal to the residual-free fit.
        let a = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        let b = [1.0, -1.0, 0.5, 2.0, 0.0, 3.0];
        let x = DMatrix::from_fn(6, 3, |i, j| match j {
            0 => 1.0,
            1 => a[i],
            _ => b[i],
        });
        let y = DVector::from_fn(6, |i, _| 1.0 + 2.0 * a[i] - b[i]);
        let fit = QrFit::new(x.clone(), y.clone());
        assert_eq!(fit.rank(), 3);
        let beta = fit.coefficients(3).unwrap();
        for (got, want) in beta.iter().zip([1.0, 2.0, -1.0]) {
            assert!((got - want).abs() < 1e-12, "{beta:?}");
        }
        assert!(fit.rss(3) < 1e-20);
        // The two-column prefix equals a separate fit on two columns.
        let sub = QrFit::new(x.columns(0, 2).clone_owned(), y.clone());
        assert!((fit.rss(2) - sub.rss(2)).abs() < 1e-10);
        let (p, q) = (fit.coefficients(2).unwrap(), sub.coefficients(2).unwrap());
        assert!((p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12);
    }

    #[test]
    fn detects_dependent_columns() {
        let x = DMatrix::from_fn(5, 2, |_, _| 1.0);
        let fit = QrFit::new(x, DVector::from_element(5, 2.0));
        assert_eq!(fit.rank(), 1);
        assert!(matches!(fit.coefficients(2), Err(FitError::Numerical(_))));
        assert!((fit.coefficients(1).unwrap()[0] - 2.0).abs() < 1e-14);
    }
}
