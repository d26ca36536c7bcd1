//! Fit of the IEEE Std 952-1997 (Annex C) noise model to a measured Allan deviation.
//!
//! Model ([`crate::diag::noise_model`]): σ²(τ) = 3Q²/τ² + N²/τ + (2 ln 2/π)B² + K²τ/3 + R²τ²/2,
//! linear in the five non-negative unknowns c = (Q², N², B², K², R²).
//!
//! Criterion: weighted least squares on the Allan **variance** with relative residuals,
//!
//! minimise Σᵢ wᵢ·(σ²_model(τᵢ) − σ²ᵢ)² / (σ²ᵢ)²   subject to c ≥ 0,
//!
//! where σ²ᵢ is the measured Allan variance and wᵢ a weight that grows with the number of terms
//! behind it: each τ counts by its relative misfit, whatever the magnitude of σ², and points from
//! fewer terms count less (least-squares Allan-variance fits as in IEEE Std 952-1997 Annex C and
//! El-Sheimy, Hou & Niu 2008, IEEE Trans. Instrum. Meas. 57(1)). See [`Weighting`] for the choice
//! of wᵢ: the default counts the *independent* terms n/m, because the overlapping count
//! n = N + 1 − 2m hardly changes over an octave grid and would let the few-sample long-τ points
//! weigh almost as much as the precise short-τ ones.
//!
//! Non-negativity: with only five unknowns the non-negative least-squares (NNLS) optimum is found by
//! enumeration. The NNLS solution is, by its KKT conditions, the unconstrained least-squares solution
//! on its set of free (positive) terms with the other terms at zero. So solving the unconstrained
//! problem on each of the 31 non-empty subsets of terms, discarding the solutions with a negative
//! coefficient, and keeping the feasible one with the lowest weighted residual gives exactly the NNLS
//! optimum. Each subset is solved by SVD of the column-scaled design matrix (columns of unit norm,
//! so the wide range of τ⁻² … τ² does not harm the conditioning); rank-deficient subsets are skipped.
//! Ties within rounding (weighted residual within 1e-12 of the total weight of the best one) go to
//! the subset with fewer terms, so a term that is absent from the data comes out as exactly zero.

use nalgebra::{DMatrix, DVector};

use crate::diag::allan::AllanDeviation;
use crate::diag::noise_model::{NoiseModel, TERMS, basis};

/// Relative singular-value threshold under which a subset's design matrix counts as rank-deficient.
const RANK_TOL: f64 = 1e-12;
/// Residuals within this fraction of the total weight of the best one are ties (see module docs).
const TIE_TOL: f64 = 1e-12;

/// Weight wᵢ of each Allan-variance point in the fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Weighting {
    /// wᵢ = nᵢ/mᵢ, the number of independent (non-overlapping) second differences at τᵢ = mᵢτ₀.
    /// The relative variance of an overlapping Allan-variance estimate falls roughly as m/N (its
    /// equivalent degrees of freedom grow as N/m, NIST SP 1065), so this is close to inverse-
    /// variance weighting of the relative residual. The default.
    #[default]
    IndependentTerms,
    /// wᵢ = nᵢ, the number of overlapping terms (allantools `ns`). On an octave grid n = N + 1 − 2m
    /// varies by at most a factor of two, so the noisy long-τ points weigh nearly as much as the
    /// short-τ ones; with pure white noise this lets long-τ scatter bias the fit: the ARW came out
    /// up to 20–38 % off (worst of 20 seeds, 2¹⁴–2²⁰ samples) against under 2 % with
    /// [`Weighting::IndependentTerms`] (`compare_weightings_on_white_noise` in tests/allan.rs).
    /// Kept for comparison.
    Terms,
}

impl Weighting {
    /// The weight of a point with `n` overlapping terms at averaging factor `m`.
    pub fn weight(self, n: usize, m: usize) -> f64 {
        match self {
            Self::IndependentTerms => n as f64 / m.max(1) as f64,
            Self::Terms => n as f64,
        }
    }
}

/// Result of the IEEE Std 952-1997 Annex C noise-term fit.
#[derive(Debug, Clone, PartialEq)]
pub struct NoiseFit {
    /// The fitted coefficients Q, N, B, K, R (deg-based units, see [`NoiseModel`]).
    pub model: NoiseModel,
    /// Which terms are free (may be non-zero) in the chosen subset, in the order Q, N, B, K, R.
    pub active: [bool; TERMS],
    /// Weighted residual Σ wᵢ(σ²_model/σ²ᵢ − 1)², with the weights scaled so that max wᵢ = 1.
    pub weighted_rss: f64,
    /// Weighted RMS relative misfit of the Allan variance, √(weighted_rss / Σ wᵢ).
    pub rms_relative_residual: f64,
    /// Number of τ points used (points with σ = 0 or zero weight are left out).
    pub points: usize,
}

/// Why the noise-term fit could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NoiseFitError {
    /// The input slices have different lengths.
    #[error("tau, adev and weights have different lengths ({tau}, {adev}, {weights})")]
    LengthMismatch {
        /// Length of the τ slice.
        tau: usize,
        /// Length of the deviation slice.
        adev: usize,
        /// Length of the weight slice.
        weights: usize,
    },
    /// No point has a positive finite τ, σ and weight (e.g. the Allan deviation of a constant
    /// series is zero everywhere).
    #[error(
        "no usable Allan deviation point to fit (every point has a zero or non-finite deviation, \
         tau or weight; a constant series has zero Allan deviation)"
    )]
    NoUsablePoints,
    /// No subset of terms gave a usable non-negative solution (not expected with positive data).
    #[error("no non-negative least-squares solution found")]
    NoSolution,
}

/// Fits the noise model to every point of an Allan deviation result, weighted as `weighting` says
/// (see the module docs). To fit on octave-spaced τ only, pass `allan.octave_points()`.
pub fn fit_allan(allan: &AllanDeviation, weighting: Weighting) -> Result<NoiseFit, NoiseFitError> {
    let weights: Vec<f64> = allan.n.iter().zip(&allan.m).map(|(&n, &m)| weighting.weight(n, m)).collect();
    fit_noise_model(&allan.tau_s, &allan.adev, &weights)
}

/// Fits the IEEE Std 952-1997 Annex C model to Allan deviations `adev` (deg/s) at `tau_s`
/// (seconds) with point weights `weights` (e.g. from [`Weighting::weight`]): non-negative weighted
/// least squares on the relative Allan-variance residual, solved exactly by subset enumeration
/// (module docs).
///
/// Points with a zero or non-finite σ, a non-positive or non-finite τ, or a weight that is not
/// positive and finite are left out.
pub fn fit_noise_model(tau_s: &[f64], adev: &[f64], weights: &[f64]) -> Result<NoiseFit, NoiseFitError> {
    let fit = fit_terms(tau_s, adev, weights, |i| basis(tau_s[i]), [true; TERMS])?;
    Ok(NoiseFit {
        model: NoiseModel::from_squares(fit.squares),
        active: fit.active,
        weighted_rss: fit.weighted_rss,
        rms_relative_residual: fit.rms_relative_residual,
        points: fit.points,
    })
}

/// The result of [`fit_terms`]: non-negative coefficients of `K` Allan-variance basis functions.
#[derive(Debug, Clone, PartialEq)]
pub struct TermFit<const K: usize> {
    /// The coefficient of each basis function (for the IEEE basis: Q², N², B², K², R²); ≥ 0.
    pub squares: [f64; K],
    /// Which basis functions are free (may be non-zero) in the chosen subset.
    pub active: [bool; K],
    /// Weighted residual Σ wᵢ(σ²_model/σ²ᵢ − 1)², weights scaled so that max wᵢ = 1.
    pub weighted_rss: f64,
    /// √(weighted_rss / Σ wᵢ).
    pub rms_relative_residual: f64,
    /// Number of τ points used.
    pub points: usize,
}

/// The fit of [`fit_noise_model`] for any basis of `K` functions (2^K − 1 subsets; meant for a
/// handful): σ²(τᵢ) ≈ Σⱼ cⱼ·`basis_at(i)`ⱼ with cⱼ ≥ 0, only the terms with `allowed[j]` free (the
/// others fixed at zero), by the same exact subset-enumeration NNLS on the weighted relative
/// Allan-variance residual (module docs). `basis_at` receives the index of a point in the input
/// slices, so a basis may depend on more than τ (e.g. the averaging factor of a sampled
/// Gauss–Markov process). `fit_noise_model` is this with the IEEE basis and every term allowed;
/// an exact flicker column or an extra Gauss–Markov column are other uses.
pub fn fit_terms<const K: usize>(
    tau_s: &[f64],
    adev: &[f64],
    weights: &[f64],
    basis_at: impl Fn(usize) -> [f64; K],
    allowed: [bool; K],
) -> Result<TermFit<K>, NoiseFitError> {
    if tau_s.len() != adev.len() || tau_s.len() != weights.len() {
        return Err(NoiseFitError::LengthMismatch { tau: tau_s.len(), adev: adev.len(), weights: weights.len() });
    }
    let keep: Vec<usize> = (0..tau_s.len())
        .filter(|&i| {
            let (t, d, w) = (tau_s[i], adev[i], weights[i]);
            t.is_finite() && t > 0.0 && d.is_finite() && (d * d) > 0.0 && w.is_finite() && w > 0.0
        })
        .collect();
    if keep.is_empty() {
        return Err(NoiseFitError::NoUsablePoints);
    }
    let w_max = keep.iter().map(|&i| weights[i]).fold(0.0, f64::max);
    let weights: Vec<f64> = keep.iter().map(|&i| weights[i] / w_max).collect();
    let total_weight: f64 = weights.iter().sum();
    // Row i: √wᵢ·basis(τᵢ)/σ²ᵢ · c ≈ √wᵢ.
    let rows = keep.len();
    let bases: Vec<[f64; K]> = keep.iter().map(|&i| basis_at(i)).collect();
    let design = DMatrix::from_fn(rows, K, |r, j| {
        let i = keep[r];
        weights[r].sqrt() * bases[r][j] / (adev[i] * adev[i])
    });
    let rhs = DVector::from_iterator(rows, weights.iter().map(|w| w.sqrt()));
    let allowed_mask: u32 = (0..K).filter(|&j| allowed[j]).map(|j| 1 << j).sum();

    let mut candidates: Vec<(f64, u32, [f64; K])> = Vec::new();
    for mask in 1u32..(1 << K) {
        if mask & !allowed_mask != 0 {
            continue;
        }
        if let Some(c) = solve_subset(&design, &rhs, mask) {
            let fitted = &design * DVector::from_column_slice(&c);
            let rss = (fitted - &rhs).norm_squared();
            candidates.push((rss, mask, c));
        }
    }
    let best_rss = candidates.iter().map(|c| c.0).fold(f64::INFINITY, f64::min);
    let (rss, mask, c) = candidates
        .into_iter()
        .filter(|c| c.0 <= best_rss + TIE_TOL * total_weight)
        .min_by(|a, b| a.1.count_ones().cmp(&b.1.count_ones()).then(a.0.total_cmp(&b.0)))
        .ok_or(NoiseFitError::NoSolution)?;
    Ok(TermFit {
        squares: c,
        active: std::array::from_fn(|j| mask & (1 << j) != 0),
        weighted_rss: rss,
        rms_relative_residual: (rss / total_weight).sqrt(),
        points: rows,
    })
}

/// Unconstrained least squares on the terms in `mask` (others fixed at zero); `None` when the
/// subset is rank-deficient, has more terms than points, or any coefficient comes out negative.
fn solve_subset<const K: usize>(design: &DMatrix<f64>, rhs: &DVector<f64>, mask: u32) -> Option<[f64; K]> {
    let cols: Vec<usize> = (0..K).filter(|j| mask & (1 << j) != 0).collect();
    if cols.len() > design.nrows() {
        return None;
    }
    let norms: Vec<f64> = cols.iter().map(|&j| design.column(j).norm()).collect();
    if norms.iter().any(|&s| !(s.is_finite() && s > 0.0)) {
        return None;
    }
    let scaled = DMatrix::from_fn(design.nrows(), cols.len(), |r, k| design[(r, cols[k])] / norms[k]);
    let svd = scaled.svd(true, true);
    let (smax, smin) = (svd.singular_values.max(), svd.singular_values.min());
    // Non-finite singular values also count as rank-deficient.
    if !(smin.is_finite() && smax.is_finite()) || smin <= RANK_TOL * smax {
        return None;
    }
    let x = svd.solve(rhs, 0.0).ok()?;
    let mut c = [0.0; K];
    for (k, &j) in cols.iter().enumerate() {
        c[j] = x[k] / norms[k];
        if !(c[j].is_finite() && c[j] >= 0.0) {
            return None;
        }
    }
    Some(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(model: &NoiseModel, taus: &[f64]) -> Vec<f64> {
        taus.iter().map(|&t| model.allan_deviation(t)).collect()
    }

    #[test]
    fn single_white_term_is_recovered_alone() {
        let truth = NoiseModel { n: 0.02, ..NoiseModel::default() };
        let taus: Vec<f64> = (0..12).map(|k| 0.1 * 2f64.powi(k)).collect();
        let fit = fit_noise_model(&taus, &curve(&truth, &taus), &[1.0; 12]).unwrap();
        assert_eq!(fit.active, [false, true, false, false, false]);
        assert!((fit.model.n - 0.02).abs() < 1e-12);
        assert_eq!((fit.model.q, fit.model.b, fit.model.k, fit.model.r), (0.0, 0.0, 0.0, 0.0));
    }

    #[test]
    fn coefficients_are_never_negative() {
        // A curve that falls faster than any term allows pushes unconstrained LS negative.
        let taus = [1.0, 2.0, 4.0, 8.0, 16.0, 32.0];
        let adev = [1.0, 0.1, 0.01, 0.001, 1e-4, 1e-5];
        let fit = fit_noise_model(&taus, &adev, &[6.0, 5.0, 4.0, 3.0, 2.0, 1.0]).unwrap();
        let m = fit.model;
        assert!([m.q, m.n, m.b, m.k, m.r].iter().all(|&v| v >= 0.0 && v.is_finite()));
    }

    #[test]
    fn one_point_fits_one_term() {
        let fit = fit_noise_model(&[1.0], &[0.5], &[3.0]).unwrap();
        assert_eq!(fit.active.iter().filter(|&&a| a).count(), 1);
        assert!(fit.weighted_rss < 1e-20);
    }

    #[test]
    fn bad_input_is_an_error() {
        assert_eq!(fit_noise_model(&[], &[], &[]), Err(NoiseFitError::NoUsablePoints));
        assert_eq!(fit_noise_model(&[1.0, 2.0], &[0.0, 0.0], &[5.0, 3.0]), Err(NoiseFitError::NoUsablePoints));
        assert_eq!(fit_noise_model(&[1.0, 2.0], &[0.1, 0.1], &[0.0, f64::NAN]), Err(NoiseFitError::NoUsablePoints));
        assert!(matches!(fit_noise_model(&[1.0], &[1.0, 2.0], &[1.0]), Err(NoiseFitError::LengthMismatch { .. })));
        // Points with zero deviation are skipped, the rest still fit.
        assert!(fit_noise_model(&[1.0, 2.0], &[0.0, 0.5], &[5.0, 3.0]).is_ok());
    }
}
