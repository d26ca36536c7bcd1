//! Large-window LS-SVM: fixed-size LS-SVM (Suykens, Van Gestel, De Brabanter, De Moor &
//! Vandewalle 2002, §6.4) with a Nyström feature map, solved in the primal as ridge regression.
//!
//! With m_p prototypes `z_1..z_{m_p}` ([`super::prototypes`]) and `W = K(z, z)`, a pivoted
//! Cholesky factorisation `W_SS = L Lᵀ` keeps the r ≤ m_p prototypes S whose kernel columns are
//! numerically independent (residual diagonal above `rank_tol`; for wide kernels W is nearly
//! singular). The feature map `φ(x) = L⁻¹ k_S(x)` has `φ(x)ᵀφ(y) = k_S(x)ᵀ W_SS⁻¹ k_S(y)`, the
//! Nyström approximation of `K(x, y)`. The LS-SVM problem (paper Eq. 5) in the primal,
//! `min ½‖w‖² + ½γ Σ (y_i − wᵀφ(x_i) − b)²`, has the (r+1)-dimensional normal equations
//!
//! ```text
//! [ ΦᵀΦ + I/γ   Φᵀ1 ] [ w ]   [ Φᵀy ]
//! [ 1ᵀΦ         n   ] [ b ] = [ 1ᵀy ]
//! ```
//!
//! solved by Cholesky. The model is `f(x) = βᵀ k_S(x) + b` with `β = L⁻ᵀw`, a kernel expansion
//! over the prototypes. Memory O(n·m_p); time O(n·m_p² + m_p³). When every training row is a
//! prototype and W is well conditioned, Φ Φᵀ = K and the solution equals the exact LS-SVM.
//!
//! Leave-one-out residuals of this linear smoother (prototypes held fixed) are closed-form too:
//! `r_i = e_i / (1 − h_i)`, `h_i = φ̃_iᵀ M⁻¹ φ̃_i` with `φ̃ = [φ; 1]` and M the matrix above.

use nalgebra::{DMatrix, DMatrixView};

use super::dense::{cholesky_in_place, solve_cholesky};
use super::expansion::{KernelExpansion, LssvmModel};
use super::kernel::sq_dist_matrix;
use super::model::embed_series;
use super::prototypes::{PrototypeSelection, select_prototypes};
use super::validate::{check_hyper, check_rows};
use crate::model::embed::Embedding;
use crate::model::{Fit, FitError};

/// Default relative tolerance of the pivoted Cholesky of the prototype kernel matrix: prototypes
/// whose Nyström residual `K(z, z) − k̂(z, z)` is below it are dropped (cond(L) ≤ 10⁵).
pub const DEFAULT_RANK_TOL: f64 = 1e-10;

/// The σ²-independent part of a fixed-size LS-SVM problem: training rows, targets, prototypes and
/// their squared distances. [`NystromProblem::solve`] is then cheap to repeat for many (γ, σ²).
#[derive(Debug, Clone)]
pub struct NystromProblem {
    dim: usize,
    protos: Vec<f64>,
    /// ‖z_a − z_b‖², m_p × m_p.
    d_pp: DMatrix<f64>,
    /// ‖z_a − x_i‖², m_p × n (column-major: one column per training row).
    d_px: DMatrix<f64>,
    targets: Vec<f64>,
}

/// A solved fixed-size LS-SVM.
#[derive(Debug, Clone, PartialEq)]
pub struct NystromSolution {
    /// `f(x) = Σ_a β_a K(x, z_a) + b` over the r retained prototypes.
    pub expansion: KernelExpansion,
    /// Number of retained prototypes r (the rank of the Nyström map).
    pub rank: usize,
    /// `f(x_i)` on the training rows.
    pub train_predictions: Vec<f64>,
    /// Closed-form leave-one-out residuals `y_i − f⁽⁻ⁱ⁾(x_i)`, when asked for.
    pub loo_residuals: Option<Vec<f64>>,
}

impl NystromProblem {
    /// Prepares a problem on row-major `inputs` (`targets.len()` rows of `dim`) with the given
    /// row-major prototypes (at least one).
    pub fn new(inputs: &[f64], dim: usize, targets: &[f64], protos: Vec<f64>) -> Result<Self, FitError> {
        check_rows(inputs, dim, targets, 2)?;
        if protos.is_empty() || !protos.len().is_multiple_of(dim) || protos.iter().any(|v| !v.is_finite()) {
            return Err(FitError::InvalidConfig(
                "prototypes must be at least one finite row of the input dimension".into(),
            ));
        }
        let d_pp = sq_dist_matrix(&protos, &protos, dim);
        let d_px = sq_dist_matrix(&protos, inputs, dim);
        Ok(Self { dim, protos, d_pp, d_px, targets: targets.to_vec() })
    }

    /// Number of training rows.
    pub fn rows(&self) -> usize {
        self.targets.len()
    }

    /// Training targets.
    pub fn targets(&self) -> &[f64] {
        &self.targets
    }

    /// Number of prototypes m_p.
    pub fn prototypes(&self) -> usize {
        self.d_pp.nrows()
    }

    /// Solves the primal system for (γ, σ²); `loo` adds the closed-form LOO residuals.
    pub fn solve(&self, gamma: f64, sigma2: f64, rank_tol: f64, loo: bool) -> Result<NystromSolution, FitError> {
        check_hyper(gamma, sigma2)?;
        let n = self.rows();
        let mp = self.prototypes();
        let s = -1.0 / sigma2;
        let (pivots, linv) = pivoted_basis(&self.d_pp, s, rank_tol)?;
        let r = pivots.len();
        // Cᵀ = K(z_S, x) (r × n, one column per training row), then Φᵀ = L⁻¹ Cᵀ.
        let mut ct = DMatrix::<f64>::zeros(r, n);
        for (dst, src) in ct.as_mut_slice().chunks_exact_mut(r).zip(self.d_px.as_slice().chunks_exact(mp)) {
            for (v, &p) in dst.iter_mut().zip(&pivots) {
                *v = (src[p] * s).exp();
            }
        }
        let mut phit = DMatrix::<f64>::zeros(r, n);
        phit.gemm(1.0, &linv, &ct, 0.0);
        drop(ct);
        // M = [ΦᵀΦ + I/γ, Φᵀ1; 1ᵀΦ, n] (lower triangle used), rhs = [Φᵀy; 1ᵀy].
        let mut m = DMatrix::<f64>::zeros(r + 1, r + 1);
        if r > 5 && n > 5 {
            // Φ as a strided view of Φᵀ. nalgebra's small-size gemm fallback (any dimension ≤ 5)
            // mis-sizes strided vectors, hence the owned transpose below in that case.
            let phi = DMatrixView::from_slice_with_strides(phit.as_slice(), n, r, r, 1);
            m.view_mut((0, 0), (r, r)).gemm(1.0, &phit, &phi, 0.0);
        } else {
            m.view_mut((0, 0), (r, r)).gemm(1.0, &phit, &phit.transpose(), 0.0);
        }
        let mut rhs = vec![0.0; r + 1];
        let mut ones = vec![0.0; r];
        for (col, &y) in phit.as_slice().chunks_exact(r).zip(&self.targets) {
            for ((t, o), &p) in rhs.iter_mut().zip(ones.iter_mut()).zip(col) {
                *t += p * y;
                *o += p;
            }
        }
        for (a, &o) in ones.iter().enumerate() {
            m[(a, a)] += 1.0 / gamma;
            m[(r, a)] = o;
        }
        m[(r, r)] = n as f64;
        rhs[r] = self.targets.iter().sum();
        cholesky_in_place(&mut m, 1)
            .map_err(|j| FitError::Numerical(format!("fixed-size LS-SVM normal equations singular at pivot {j}")))?;
        let mut sol = rhs;
        solve_cholesky(&m, &mut sol);
        let (w, bias) = (&sol[..r], sol[r]);
        let train_predictions: Vec<f64> = phit
            .as_slice()
            .chunks_exact(r)
            .map(|col| bias + col.iter().zip(w).map(|(p, w)| p * w).sum::<f64>())
            .collect();
        let loo_residuals = if loo { Some(loo_residuals(&phit, &m, &self.targets, &train_predictions)?) } else { None };
        // β = L⁻ᵀ w (L⁻¹ is lower triangular).
        let beta: Vec<f64> = (0..r).map(|a| (a..r).map(|k| linv[(k, a)] * w[k]).sum()).collect();
        if !bias.is_finite() || beta.iter().any(|v| !v.is_finite()) {
            return Err(FitError::Numerical("non-finite fixed-size LS-SVM solution".into()));
        }
        let centres =
            pivots.iter().flat_map(|&p| self.protos[p * self.dim..(p + 1) * self.dim].iter().copied()).collect();
        Ok(NystromSolution {
            expansion: KernelExpansion { dim: self.dim, centres, coef: beta, bias, sigma2 },
            rank: r,
            train_predictions,
            loo_residuals,
        })
    }
}

/// Pivoted Cholesky of `W = exp(s · d_pp)`: the retained pivots S (in pivot order) and `L⁻¹`
/// for `W_SS = L Lᵀ`. Stops when the largest residual diagonal falls to `tol` (W_ii = 1).
fn pivoted_basis(d_pp: &DMatrix<f64>, s: f64, tol: f64) -> Result<(Vec<usize>, DMatrix<f64>), FitError> {
    let mp = d_pp.nrows();
    let mut resid = vec![1.0_f64; mp];
    let mut chosen = vec![false; mp];
    // Column k of `g` is the k-th pivot column of the partial factor, over all m_p rows.
    let mut g: Vec<Vec<f64>> = Vec::new();
    let mut pivots = Vec::new();
    while pivots.len() < mp {
        let mut p = usize::MAX;
        for i in 0..mp {
            if !chosen[i] && (p == usize::MAX || resid[i] > resid[p]) {
                p = i;
            }
        }
        if resid[p].is_nan() || resid[p] <= tol {
            break;
        }
        let lpp = resid[p].sqrt();
        let col: Vec<f64> = (0..mp)
            .map(|i| {
                if chosen[i] {
                    return 0.0;
                }
                let mut v = (d_pp[(i, p)] * s).exp();
                for gk in &g {
                    v -= gk[i] * gk[p];
                }
                if i == p { lpp } else { v / lpp }
            })
            .collect();
        chosen[p] = true;
        for i in 0..mp {
            if !chosen[i] {
                resid[i] -= col[i] * col[i];
            }
        }
        pivots.push(p);
        g.push(col);
    }
    let r = pivots.len();
    if r == 0 {
        return Err(FitError::Numerical("no prototype retained by the pivoted Cholesky".into()));
    }
    // L (r × r, lower): L[a][k] = g_k[S_a] (rows of not-yet-chosen entries, so zero above).
    let mut l = DMatrix::<f64>::zeros(r, r);
    for (k, gk) in g.iter().enumerate() {
        for a in k..r {
            l[(a, k)] = gk[pivots[a]];
        }
    }
    let linv = l
        .solve_lower_triangular(&DMatrix::identity(r, r))
        .ok_or_else(|| FitError::Numerical("prototype kernel factor is singular".into()))?;
    Ok((pivots, linv))
}

/// `e_i / (1 − h_i)` with `h_i = ‖L_M⁻¹ φ̃_i‖²`, `φ̃_i = [φ_i; 1]`, `M = L_M L_Mᵀ`; `phit` is Φᵀ.
fn loo_residuals(
    phit: &DMatrix<f64>,
    m_factor: &DMatrix<f64>,
    y: &[f64],
    fitted: &[f64],
) -> Result<Vec<f64>, FitError> {
    let (r, n) = phit.shape();
    let linv = m_factor
        .solve_lower_triangular(&DMatrix::identity(r + 1, r + 1))
        .ok_or_else(|| FitError::Numerical("singular normal-equation factor".into()))?;
    // Z = L_M⁻¹ Φ̃ᵀ = L_M⁻¹[:, ..r] Φᵀ + L_M⁻¹[:, r] 1ᵀ ((r+1) × n); h_i = ‖Z[:, i]‖².
    let mut z = DMatrix::<f64>::zeros(r + 1, n);
    z.gemm(1.0, &linv.columns(0, r), phit, 0.0);
    let last: Vec<f64> = linv.column(r).iter().copied().collect();
    let h =
        z.as_slice().chunks_exact(r + 1).map(|col| col.iter().zip(&last).map(|(v, l)| (v + l) * (v + l)).sum::<f64>());
    Ok(y.iter().zip(fitted).zip(h).map(|((y, f), h)| (y - f) / (1.0 - h)).collect())
}

/// Fixed-size (Nyström) LS-SVM on PSR rows with fixed γ and σ² (Suykens et al. 2002): the
/// large-window counterpart of [`super::LssvmConfig`]. The series must already be normalised.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NystromConfig {
    /// Regularisation γ (Eq. 5).
    pub gamma: f64,
    /// RBF width σ² (Eq. 8).
    pub sigma2: f64,
    /// PSR embedding (default τ = 10, m = 3).
    pub embedding: Embedding,
    /// Number of prototypes m_p (all rows when m_p ≥ n).
    pub prototypes: usize,
    /// How the prototypes are chosen.
    pub selection: PrototypeSelection,
    /// Relative tolerance of the pivoted Cholesky of the prototype kernel matrix.
    pub rank_tol: f64,
}

impl Default for NystromConfig {
    /// The paper's γ = 29.358, σ² = 83.162 (§4.3), τ = 10, m = 3, 100 k-means++ prototypes.
    fn default() -> Self {
        Self {
            gamma: 29.358,
            sigma2: 83.162,
            embedding: Embedding::PAPER,
            prototypes: 100,
            selection: PrototypeSelection::default(),
            rank_tol: DEFAULT_RANK_TOL,
        }
    }
}

impl NystromConfig {
    /// Fits on explicit row-major `inputs` (`targets.len()` rows of `dim` values).
    pub fn fit_rows(&self, inputs: &[f64], dim: usize, targets: &[f64]) -> Result<NystromSolution, FitError> {
        check_hyper(self.gamma, self.sigma2)?;
        if self.prototypes == 0 || !(self.rank_tol >= 0.0 && self.rank_tol < 1.0) {
            return Err(FitError::InvalidConfig(format!(
                "need prototypes >= 1 and 0 <= rank_tol < 1, got {} and {}",
                self.prototypes, self.rank_tol
            )));
        }
        check_rows(inputs, dim, targets, 2)?;
        let protos = select_prototypes(inputs, dim, self.prototypes, self.selection);
        NystromProblem::new(inputs, dim, targets, protos)?.solve(self.gamma, self.sigma2, self.rank_tol, false)
    }
}

impl Fit for NystromConfig {
    type Model = LssvmModel;

    fn fit(&self, train: &[f64]) -> Result<LssvmModel, FitError> {
        check_hyper(self.gamma, self.sigma2)?;
        let e = embed_series(&self.embedding, train, 2)?;
        let sol = self.fit_rows(&e.inputs, e.dim, &e.targets)?;
        Ok(LssvmModel { embedding: self.embedding, expansion: sol.expansion })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::lssvm::exact::solve_exact;

    fn data(n: usize) -> (Vec<f64>, Vec<f64>) {
        let x: Vec<f64> = (0..n * 2).map(|i| ((i * 37 % 101) as f64 / 50.0) - 1.0).collect();
        let y: Vec<f64> = (0..n).map(|i| (3.0 * x[2 * i]).sin() + 0.5 * x[2 * i + 1]).collect();
        (x, y)
    }

    #[test]
    fn all_rows_as_prototypes_equals_exact() {
        let (x, y) = data(40);
        let (gamma, sigma2) = (30.0, 0.02);
        let exact = solve_exact(&x, 2, &y, gamma, sigma2, true, 1).unwrap();
        let p = NystromProblem::new(&x, 2, &y, x.clone()).unwrap();
        let sol = p.solve(gamma, sigma2, 1e-14, true).unwrap();
        assert_eq!(sol.rank, 40);
        let fx = sol.expansion.eval_rows(&x);
        for i in 0..40 {
            let k: f64 = (0..40)
                .map(|j| exact.alpha[j] * super::super::kernel::rbf(&x[2 * i..2 * i + 2], &x[2 * j..2 * j + 2], sigma2))
                .sum();
            assert!((fx[i] - (k + exact.bias)).abs() < 1e-7, "row {i}");
            assert!((sol.train_predictions[i] - fx[i]).abs() < 1e-7);
        }
        let (a, b) = (exact.loo_residuals.unwrap(), sol.loo_residuals.unwrap());
        for i in 0..40 {
            assert!((a[i] - b[i]).abs() < 1e-6, "LOO {i}: {} vs {}", a[i], b[i]);
        }
    }

    #[test]
    fn closed_form_loo_equals_refitting_with_the_same_prototypes() {
        let (x, y) = data(30);
        // 3 prototypes exercise nalgebra's small-matrix path, 12 the general one.
        for mp in [3, 12] {
            let protos = x[..2 * mp].to_vec();
            let sol = NystromProblem::new(&x, 2, &y, protos.clone()).unwrap().solve(20.0, 0.3, 1e-12, true).unwrap();
            let loo = sol.loo_residuals.unwrap();
            for i in 0..30 {
                let xs: Vec<f64> = (0..30).filter(|&k| k != i).flat_map(|k| x[2 * k..2 * k + 2].to_vec()).collect();
                let ys: Vec<f64> = (0..30).filter(|&k| k != i).map(|k| y[k]).collect();
                let s =
                    NystromProblem::new(&xs, 2, &ys, protos.clone()).unwrap().solve(20.0, 0.3, 1e-12, false).unwrap();
                let r = y[i] - s.expansion.eval(&x[2 * i..2 * i + 2]);
                assert!((r - loo[i]).abs() < 1e-9, "m_p = {mp}, row {i}: {r} vs {}", loo[i]);
            }
        }
    }

    #[test]
    fn wide_kernels_drop_dependent_prototypes() {
        let (x, y) = data(60);
        let p = NystromProblem::new(&x, 2, &y, x[..60].to_vec()).unwrap();
        let sol = p.solve(10.0, 1e3, DEFAULT_RANK_TOL, false).unwrap();
        assert!(sol.rank < 30, "rank {}", sol.rank);
        assert!(sol.train_predictions.iter().all(|v| v.is_finite()));
    }
}
