//! The C-C method (Kim, Eykholt & Salas, "Nonlinear dynamics, delay times, and embedding
//! windows", Physica D 127 (1999) 48–60) for choosing the phase-space reconstruction delay τ,
//! the delay window τw and the embedding dimension m: paper §3 Step 2, Eq. 18–20, and §4.2.
//!
//! Definitions used here (docs/design.md "Stage definitions", C-C method):
//! - Correlation integral with the sup-norm over pairs i < j (no self-pairs):
//!   `C(m, N, r, t) = 2/(M(M−1)) · #{i < j : ‖X_i − X_j‖∞ ≤ r}`, with
//!   `X_i = (x_i, x_{i+t}, …, x_{i+(m−1)t})` and `M = N − (m−1)t`; Θ(a) = 1 for a ≥ 0, so a
//!   distance equal to r counts.
//! - `S(m, r, t) = (1/t) Σ_{s=1..t} [C_s(m, N/t, r, t) − C_s(1, N/t, r, t)^m]`, where the s-th
//!   disjoint sub-series is `{x_s, x_{s+t}, x_{s+2t}, …}` truncated to ⌊N/t⌋ samples and `C_s` is
//!   the correlation integral of that sub-series embedded with delay 1 within it (delay t in the
//!   original series); `C_s(1, …)` uses all ⌊N/t⌋ points.
//! - m = 2..=5 and `r_j = j·σ/2`, j = 1..=4, with σ the population standard deviation (ddof = 0)
//!   of the whole analysed series.
//! - `ΔS(m, t) = max_j S(m, r_j, t) − min_j S(m, r_j, t)`, `S̄(t) = (1/16) Σ_m Σ_j S(m, r_j, t)`
//!   (Eq. 18), `ΔS̄(t) = (1/4) Σ_m ΔS(m, t)` (Eq. 19), `S_cor(t) = ΔS̄(t) + |S̄(t)|` (Eq. 20).
//! - τ is the first local minimum of ΔS̄(t), else the first zero of S̄(t), else the global minimum
//!   of ΔS̄(t) ([`TauRule`]); τw = argmin S_cor(t); m = round(τw/τ) + 1 (Eq. 17), at least 2.
//!
//! Cost: Σ_t N²/(2t) pair visits, each serving all 5 × 4 (dimension, radius) cells; the work is
//! spread over threads and counted in integers, so the result is bit-identical for any thread
//! count. The golden test (tests/cc.rs) compares against an independent brute-force reference,
//! tools/goldens/cc_reference.py.

mod pairs;

use serde::Serialize;

/// Smallest embedding dimension in the S sums (Eq. 18–19): m = 2.
pub const M_MIN: usize = 2;
/// Largest embedding dimension in the S sums (Eq. 18–19): m = 5.
pub const M_MAX: usize = 5;
/// Number of embedding dimensions m = 2..=5 in the S sums.
pub const DIMS: usize = M_MAX - M_MIN + 1;
/// Number of radii `r_j = j·σ/2`, j = 1..=4 (Eq. 18).
pub const RADII: usize = 4;

/// Settings of the C-C method. The dimensions (m = 2..=5) and radii (`r_j = j·σ/2`, j = 1..=4)
/// are fixed by the paper and Kim et al.: see [`M_MIN`], [`M_MAX`], [`RADII`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CcConfig {
    /// Largest delay t examined; t runs over 1..=t_max. The series needs ⌊N/t_max⌋ ≥ 6 samples
    /// per sub-series (so that dimension 5 still has two vectors).
    pub t_max: usize,
    /// Worker threads for the pair counting; 0 means the available parallelism. The result does
    /// not depend on it.
    pub threads: usize,
}

impl Default for CcConfig {
    /// t_max = 40 (the paper's τ = 10 and τw = 20 lie well inside), threads = 0 (all cores).
    fn default() -> Self {
        Self { t_max: 40, threads: 0 }
    }
}

/// Which rule chose the delay τ.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TauRule {
    /// The first local minimum of ΔS̄(t): the smallest t ≥ 2 with ΔS̄(t−1) > ΔS̄(t) ≤ ΔS̄(t+1)
    /// (Kim et al. and the paper, §4.2).
    FirstLocalMinimum,
    /// No local minimum: the first zero of S̄(t), i.e. the smallest t with S̄(t) = 0, or the
    /// smallest t ≥ 2 at which S̄ changes sign between t−1 and t (τ is the first t past the
    /// crossing).
    FirstZeroCrossing,
    /// Neither: the t of the smallest ΔS̄(t) (the first one on ties).
    ArgminDeltaS,
}

/// Result of [`cc_method`]; vectors are indexed by t − 1 for t = 1..=t_max.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CcResult {
    /// Delay τ in samples (see [`TauRule`]).
    pub tau: usize,
    /// Delay window τw = argmin_t S_cor(t), in samples (the first one on ties).
    pub tau_w: usize,
    /// Embedding dimension m = round(τw/τ) + 1 (Eq. 17, halves round up), at least 2.
    pub m: usize,
    /// The rule that chose τ.
    pub tau_rule: TauRule,
    /// Population standard deviation (ddof = 0) of the analysed series.
    pub sigma: f64,
    /// The radii `r_j = j·σ/2`, j = 1..=4.
    pub radii: [f64; RADII],
    /// The delays t = 1..=t_max.
    pub t: Vec<usize>,
    /// S̄(t), Eq. 18.
    pub s_mean: Vec<f64>,
    /// ΔS̄(t), Eq. 19.
    pub delta_s_mean: Vec<f64>,
    /// S_cor(t) = ΔS̄(t) + |S̄(t)|, Eq. 20.
    pub s_cor: Vec<f64>,
    /// S(m, r_j, t) as `s[t − 1][m − 2][j − 1]`.
    pub s: Vec<[[f64; RADII]; DIMS]>,
    /// ΔS(m, t) = max_j S(m, r_j, t) − min_j S(m, r_j, t) as `delta_s[t − 1][m − 2]`.
    pub delta_s: Vec<[f64; DIMS]>,
}

impl CcResult {
    /// S(m, r_j, t) for m in 2..=5, j in 1..=4, t in 1..=t_max; `None` outside those ranges.
    pub fn s_at(&self, m: usize, j: usize, t: usize) -> Option<f64> {
        let row = self.s.get(t.checked_sub(1)?)?;
        row.get(m.checked_sub(M_MIN)?)?.get(j.checked_sub(1)?).copied()
    }
}

/// Why [`cc_method`] refused a series.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CcError {
    /// t_max was zero.
    #[error("t_max must be at least 1")]
    ZeroTMax,
    /// The series is too short for t_max: every sub-series needs ⌊N/t_max⌋ ≥ 6 samples.
    #[error("series of {n} samples is too short for t_max = {t_max}: need at least {need}")]
    TooShort {
        /// Length of the series.
        n: usize,
        /// Requested largest delay.
        t_max: usize,
        /// Smallest length accepted for this t_max.
        need: usize,
    },
    /// A sample is NaN or infinite.
    #[error("sample {index} is not finite")]
    NonFinite {
        /// 0-based index of the first non-finite sample.
        index: usize,
    },
    /// The series is constant (σ = 0, so all radii are zero), or σ is not finite (samples so
    /// large that their squares overflow).
    #[error("the standard deviation of the series is 0 or not finite")]
    ZeroVariance,
}

/// Samples each sub-series needs: dimension 5 must keep M = ⌊N/t⌋ − 4 ≥ 2 vectors.
const MIN_SUB_LEN: usize = M_MAX + 1;

/// Runs the C-C method (Kim et al. 1999; paper Eq. 18–20) on `x` for t = 1..=`config.t_max`.
///
/// Errors when t_max is 0, when `x.len() < 6·t_max`, when a sample is not finite or when the
/// series is constant.
pub fn cc_method(x: &[f64], config: &CcConfig) -> Result<CcResult, CcError> {
    let t_max = config.t_max;
    if t_max == 0 {
        return Err(CcError::ZeroTMax);
    }
    let need = MIN_SUB_LEN.saturating_mul(t_max);
    if x.len() < need {
        return Err(CcError::TooShort { n: x.len(), t_max, need });
    }
    if let Some(index) = x.iter().position(|v| !v.is_finite()) {
        return Err(CcError::NonFinite { index });
    }
    let sigma = population_std(x);
    if sigma <= 0.0 || !sigma.is_finite() {
        return Err(CcError::ZeroVariance);
    }
    let radii: [f64; RADII] = std::array::from_fn(|k| (k + 1) as f64 * sigma / 2.0);
    let threads = match config.threads {
        0 => std::thread::available_parallelism().map_or(1, usize::from),
        n => n,
    };
    let counts = pairs::count_all(x, t_max, &radii, threads);

    let mut result = CcResult {
        tau: 0,
        tau_w: 0,
        m: 0,
        tau_rule: TauRule::FirstLocalMinimum,
        sigma,
        radii,
        t: (1..=t_max).collect(),
        s_mean: Vec::with_capacity(t_max),
        delta_s_mean: Vec::with_capacity(t_max),
        s_cor: Vec::with_capacity(t_max),
        s: Vec::with_capacity(t_max),
        delta_s: Vec::with_capacity(t_max),
    };
    for (t, subs) in (1..=t_max).zip(&counts) {
        let s = s_table(subs, x.len() / t, t);
        let mut sum = 0.0;
        let mut delta_sum = 0.0;
        let mut delta = [0.0; DIMS];
        for (row, d) in s.iter().zip(&mut delta) {
            let (lo, hi) = row.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| (lo.min(v), hi.max(v)));
            for &v in row {
                sum += v;
            }
            *d = hi - lo;
            delta_sum += *d;
        }
        let s_mean = sum / (DIMS * RADII) as f64;
        let delta_s_mean = delta_sum / DIMS as f64;
        result.s_mean.push(s_mean);
        result.delta_s_mean.push(delta_s_mean);
        result.s_cor.push(delta_s_mean + s_mean.abs());
        result.s.push(s);
        result.delta_s.push(delta);
    }
    let (tau, rule) = choose_tau(&result.delta_s_mean, &result.s_mean);
    result.tau = tau;
    result.tau_rule = rule;
    result.tau_w = argmin(&result.s_cor) + 1;
    result.m = ((2 * result.tau_w + tau) / (2 * tau) + 1).max(2);
    Ok(result)
}

/// Population standard deviation (ddof = 0): sequential sums for the mean and the squared
/// deviations (the reference script sums in the same order).
fn population_std(x: &[f64]) -> f64 {
    let n = x.len() as f64;
    let mut sum = 0.0;
    for &v in x {
        sum += v;
    }
    let mean = sum / n;
    let mut sq = 0.0;
    for &v in x {
        let d = v - mean;
        sq += d * d;
    }
    (sq / n).sqrt()
}

/// Correlation integral from a pair count: `2·count / (M(M−1))` for M vectors.
fn correlation(count: u64, vectors: usize) -> f64 {
    2.0 * count as f64 / (vectors as f64 * (vectors - 1) as f64)
}

/// S(m, r_j, t) for m = 2..=5, j = 1..=4 from the pair counts of the t sub-series of length
/// `sub_len` = ⌊N/t⌋: `(1/t) Σ_s [C_s(m, r_j) − C_s(1, r_j)^m]`.
fn s_table(subs: &[pairs::Counts], sub_len: usize, t: usize) -> [[f64; RADII]; DIMS] {
    let mut s = [[0.0; RADII]; DIMS];
    for (row, m) in s.iter_mut().zip(M_MIN..=M_MAX) {
        for (k, cell) in row.iter_mut().enumerate() {
            let mut sum = 0.0;
            for counts in subs {
                let c1 = correlation(counts[0][k], sub_len);
                let cm = correlation(counts[m - 1][k], sub_len - (m - 1));
                let mut power = c1;
                for _ in 1..m {
                    power *= c1;
                }
                sum += cm - power;
            }
            *cell = sum / t as f64;
        }
    }
    s
}

/// Index of the smallest value (the first one on ties).
fn argmin(v: &[f64]) -> usize {
    let mut best = 0;
    for (i, &x) in v.iter().enumerate() {
        if x < v[best] {
            best = i;
        }
    }
    best
}

/// Chooses τ (1-based) from ΔS̄ and S̄ following [`TauRule`].
fn choose_tau(delta_s_mean: &[f64], s_mean: &[f64]) -> (usize, TauRule) {
    // t = k + 1 for 0-based k; a local minimum needs t ≥ 2 and t + 1 ≤ t_max.
    let local = (1..delta_s_mean.len().saturating_sub(1))
        .find(|&k| delta_s_mean[k - 1] > delta_s_mean[k] && delta_s_mean[k] <= delta_s_mean[k + 1]);
    if let Some(k) = local {
        return (k + 1, TauRule::FirstLocalMinimum);
    }
    let zero = (0..s_mean.len()).find(|&k| s_mean[k] == 0.0 || (k >= 1 && (s_mean[k - 1] < 0.0) != (s_mean[k] < 0.0)));
    if let Some(k) = zero {
        return (k + 1, TauRule::FirstZeroCrossing);
    }
    (argmin(delta_s_mean) + 1, TauRule::ArgminDeltaS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tau_rules_and_their_fallbacks() {
        let (tau, rule) = choose_tau(&[3.0, 2.0, 2.0, 1.0], &[1.0; 4]);
        assert_eq!((tau, rule), (2, TauRule::FirstLocalMinimum), "plateau: ΔS̄(t) ≤ ΔS̄(t+1)");
        let (tau, rule) = choose_tau(&[1.0, 2.0, 3.0, 4.0], &[0.5, 0.2, -0.1, -0.3]);
        assert_eq!((tau, rule), (3, TauRule::FirstZeroCrossing));
        let (tau, rule) = choose_tau(&[1.0, 2.0, 3.0], &[0.5, 0.0, 0.2]);
        assert_eq!((tau, rule), (2, TauRule::FirstZeroCrossing));
        let (tau, rule) = choose_tau(&[4.0, 3.0, 2.0, 1.0], &[0.5, 0.4, 0.3, 0.2]);
        assert_eq!((tau, rule), (4, TauRule::ArgminDeltaS));
        // A local minimum at the last t is not recognised (ΔS̄(t+1) is unknown).
        let (tau, rule) = choose_tau(&[2.0, 1.0], &[0.1, 0.1]);
        assert_eq!((tau, rule), (2, TauRule::ArgminDeltaS));
    }

    #[test]
    fn bad_input_is_refused() {
        let config = CcConfig { t_max: 4, threads: 1 };
        assert_eq!(cc_method(&[1.0; 23], &config), Err(CcError::TooShort { n: 23, t_max: 4, need: 24 }));
        assert_eq!(cc_method(&[1.0; 24], &config), Err(CcError::ZeroVariance));
        let mut x: Vec<f64> = (0..24).map(|i| i as f64).collect();
        assert!(cc_method(&x, &config).is_ok());
        x[5] = f64::NAN;
        assert_eq!(cc_method(&x, &config), Err(CcError::NonFinite { index: 5 }));
        assert_eq!(cc_method(&x, &CcConfig { t_max: 0, threads: 1 }), Err(CcError::ZeroTMax));
    }

    #[test]
    fn dimension_rounds_half_up_and_is_at_least_two() {
        let x: Vec<f64> = (0..600).map(|i| (i as f64 * 0.2).sin() + 0.1 * ((i * 7919 % 13) as f64)).collect();
        let r = cc_method(&x, &CcConfig { t_max: 12, threads: 2 }).unwrap();
        let want = ((r.tau_w as f64 / r.tau as f64 + 0.5).floor() as usize + 1).max(2);
        assert_eq!(r.m, want);
        assert_eq!(r.s_at(2, 1, 1), Some(r.s[0][0][0]));
        assert_eq!(r.s_at(5, 4, 12), Some(r.s[11][3][3]));
        assert_eq!(r.s_at(1, 1, 1), None);
        assert_eq!(r.s_at(2, 5, 1), None);
        assert_eq!(r.s_at(2, 1, 13), None);
        assert_eq!(r.s_at(2, 1, 0), None);
    }
}
