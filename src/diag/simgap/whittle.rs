//! The Whittle likelihood of a rate series under the simulator's noise terms, fitted in the
//! frequency domain: the likelihood-ratio statistic of the nested-model tests ([`super::nested`],
//! and with a regressor's cross-periodogram [`super::nested_temperature`]).
//!
//! **Periodogram** (Percival & Walden 1993, *Spectral Analysis for Physical Applications*, §6):
//! the series is detrended (least-squares line) and tapered (a Tukey window over
//! [`TAPER_SHARE`] of it), I(ω) = |Σ wⱼxⱼe^(−iωj)|² / Σwⱼ², ω in radians per sample. The lowest
//! [`SINGLE_ORDINATES`] Fourier frequencies 2πk/n are kept one by one (a direct transform); above
//! them the periodogram of the series zero-padded to a power of two of at least 2n is averaged
//! over bins [`BIN_RATIO`] wide, each counting as the number of Fourier frequencies it spans.
//!
//! **Model** S(ω) = Σ cⱼ gⱼ(ω), cⱼ ≥ 0, the spectral densities (per-sample variance units) of the
//! processes the simulator adds ([`crate::sim::terms`], [`super::model`]):
//! white noise 1; angle quantisation (white angle noise, differenced) 4 sin²(ω/2); rate random walk
//! 1 / (4 sin²(ω/2)); the flicker bank ([`crate::sim::terms::flicker_poles`]) and an optional
//! Gauss–Markov process ([`gauss_markov_spectrum`]), exact for point samples (AR(1)) and for the
//! interval means the simulator outputs for short correlation times.
//!
//! **Fit**: the binned Whittle negative log-likelihood ℓ = Σ_b L_b (ln S_b + Ī_b / S_b)
//! (Whittle 1953; Percival & Walden §6.6) minimised by Fisher scoring, which for this gamma
//! likelihood with an identity link is iteratively reweighted non-negative least squares
//! (McCullagh & Nelder 1989, *Generalized Linear Models*, §8), with step halving so ℓ never rises.

use std::f64::consts::{PI, TAU};

use nalgebra::{DMatrix, DVector};

use super::SimgapError;
use super::baseline::NoiseTerms;
use super::robust::detrended;
use crate::diag::fft::{Complex64, Fft};
use crate::sim::terms::{flicker_poles, gauss_markov_averaged};

/// Share of the series tapered (half at each end).
pub const TAPER_SHARE: f64 = 0.1;
/// Lowest Fourier frequencies kept one by one.
pub const SINGLE_ORDINATES: usize = 32;
/// Ratio of a bin's upper to its lower edge above them.
pub const BIN_RATIO: f64 = 1.06;
/// Fisher-scoring iterations at most.
const MAX_ITERATIONS: usize = 40;
/// Relative change of ℓ below which the iteration stops.
const TOLERANCE: f64 = 1e-10;

/// The binned periodogram of a series (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Periodogram {
    /// Bin centres, radians per sample.
    pub omega: Vec<f64>,
    /// Mean periodogram over each bin.
    pub mean: Vec<f64>,
    /// Fourier frequencies each bin spans (its weight in the likelihood).
    pub weight: Vec<f64>,
}

impl Periodogram {
    /// The binned periodogram of `x` (module docs).
    pub fn of(x: &[f64]) -> Result<Periodogram, SimgapError> {
        let binned = Binned::of(&[&SpectralTransform::of(x)?])?;
        let mean = binned.products.into_iter().next().unwrap_or_default();
        Ok(Periodogram { omega: binned.omega, mean, weight: binned.weight })
    }
}

/// The binned periodograms of a series and of a regressor, and their cross-periodogram, on the
/// bins of [`Periodogram::of`] (both detrended and tapered alike): what the Whittle likelihood of
/// the series less a multiple of the regressor needs, for any multiple
/// (Percival & Walden 1993, §6 and §7: the cross-periodogram's real part).
#[derive(Debug, Clone, PartialEq)]
pub struct CrossPeriodogram {
    /// Bin centres, radians per sample.
    pub omega: Vec<f64>,
    /// Fourier frequencies each bin spans.
    pub weight: Vec<f64>,
    /// Mean |X|² of the series over each bin.
    pub xx: Vec<f64>,
    /// Mean Re(X·conj Z) of the series X and the regressor Z over each bin.
    pub xz: Vec<f64>,
    /// Mean |Z|² of the regressor over each bin.
    pub zz: Vec<f64>,
}

impl CrossPeriodogram {
    /// The binned spectra of `x` and the regressor `z` (the same length).
    pub fn of(x: &[f64], z: &[f64]) -> Result<CrossPeriodogram, SimgapError> {
        if z.len() != x.len() {
            return Err(SimgapError::BadSetting(format!(
                "the regressor has {} samples, the series {}",
                z.len(),
                x.len()
            )));
        }
        CrossPeriodogram::of_transforms(&SpectralTransform::of(x)?, &SpectralTransform::of(z)?)
    }

    /// The binned spectra of a series and a regressor from their transforms (of the same length).
    pub fn of_transforms(x: &SpectralTransform, z: &SpectralTransform) -> Result<CrossPeriodogram, SimgapError> {
        let binned = Binned::of(&[x, z])?;
        let mut products = binned.products.into_iter();
        let (xx, xz, zz) = (products.next(), products.next(), products.next());
        let (Some(xx), Some(xz), Some(zz)) = (xx, xz, zz) else {
            return Err(SimgapError::Numerical("cross-periodogram without its three products".into()));
        };
        Ok(CrossPeriodogram { omega: binned.omega, weight: binned.weight, xx, xz, zz })
    }

    /// The binned periodogram of x − c·z: mean |X − cZ|² = xx − 2c·xz + c²·zz per bin.
    pub fn residual(&self, c: f64) -> Periodogram {
        let mean = self.xx.iter().zip(&self.xz).zip(&self.zz).map(|((a, b), z)| a - 2.0 * c * b + c * c * z).collect();
        Periodogram { omega: self.omega.clone(), mean, weight: self.weight.clone() }
    }

    /// The c that minimises the binned Whittle likelihood of x − c·z under the spectral density
    /// `s` (one value per bin): the generalised least-squares estimate Σ L·xz/S / Σ L·zz/S (the
    /// likelihood is quadratic in c).
    pub fn gls_coefficient(&self, s: &[f64]) -> f64 {
        let (mut num, mut den) = (0.0, 0.0);
        for (((l, b), z), s) in self.weight.iter().zip(&self.xz).zip(&self.zz).zip(s) {
            num += l * b / s;
            den += l * z / s;
        }
        if den > 0.0 { num / den } else { 0.0 }
    }
}

/// The Fourier transform of one detrended, tapered series (module docs): its direct transform at
/// the lowest [`SINGLE_ORDINATES`] Fourier frequencies and the transform of it zero-padded to a
/// power of two of at least twice its length. Computed once per series, so a series tried against
/// many regressors (or a regressor against many series) is transformed once.
#[derive(Debug, Clone, PartialEq)]
pub struct SpectralTransform {
    len: usize,
    norm: f64,
    single: Vec<(f64, f64)>,
    padded: Vec<Complex64>,
}

impl SpectralTransform {
    /// The transform of `x` (at least 4·[`SINGLE_ORDINATES`] samples).
    pub fn of(x: &[f64]) -> Result<SpectralTransform, SimgapError> {
        let n = x.len();
        let need = 4 * SINGLE_ORDINATES;
        if n < need {
            return Err(SimgapError::TooShort { samples: n, need });
        }
        let residual = detrended(x);
        let window = taper(n);
        let norm: f64 = window.iter().map(|w| w * w).sum();
        let weighted: Vec<f64> = residual.iter().zip(&window).map(|(v, w)| v * w).collect();
        let single = lowest_ordinates(&weighted, SINGLE_ORDINATES);
        let padded = (2 * n).next_power_of_two();
        let fft = Fft::new(padded).ok_or_else(|| SimgapError::Numerical(format!("no FFT of length {padded}")))?;
        Ok(SpectralTransform { len: n, norm, single, padded: fft.transform_real(&weighted) })
    }
}

/// Binned spectral products of one or two series (module docs): for one series its periodogram;
/// for two (x, z) the bin means of |X|², Re(X·conj Z) and |Z|².
struct Binned {
    omega: Vec<f64>,
    weight: Vec<f64>,
    products: Vec<Vec<f64>>,
}

impl Binned {
    fn of(series: &[&SpectralTransform]) -> Result<Binned, SimgapError> {
        let n = series[0].len;
        if series.iter().any(|t| t.len != n) {
            return Err(SimgapError::BadSetting("spectral transforms of different lengths".into()));
        }
        let norm = series[0].norm;
        let pairs: Vec<(usize, usize)> = if series.len() == 1 { vec![(0, 0)] } else { vec![(0, 0), (0, 1), (1, 1)] };
        let product = |a: (f64, f64), b: (f64, f64)| a.0 * b.0 + a.1 * b.1;
        let spacing = TAU / n as f64;
        let (mut omega, mut weight) = (Vec::new(), Vec::new());
        let mut products = vec![Vec::new(); pairs.len()];
        for k in 0..SINGLE_ORDINATES {
            omega.push(spacing * (k + 1) as f64);
            for (out, &(a, b)) in products.iter_mut().zip(&pairs) {
                out.push(product(series[a].single[k], series[b].single[k]) / norm);
            }
            weight.push(1.0);
        }
        let padded = series[0].padded.len();
        let at = |s: usize, p: usize| (series[s].padded[p].re, series[s].padded[p].im);
        let step = TAU / padded as f64;
        let mut lo = spacing * (SINGLE_ORDINATES as f64 + 0.5);
        while lo < PI {
            let hi = (lo * BIN_RATIO).max(lo + 2.0 * spacing).min(PI);
            let (first, last) = ((lo / step).ceil() as usize, ((hi / step).ceil() as usize).min(padded / 2));
            if last > first {
                omega.push(0.5 * (lo + hi));
                for (out, &(a, b)) in products.iter_mut().zip(&pairs) {
                    let sum: f64 = (first..last).map(|p| product(at(a, p), at(b, p)) / norm).sum();
                    out.push(sum / (last - first) as f64);
                }
                weight.push((hi - lo) / spacing);
            }
            lo = hi;
        }
        Ok(Binned { omega, weight, products })
    }
}

/// The DFT (cosine and sine sums) of `weighted` (the windowed residual) at its Fourier
/// frequencies k/n cycles per sample, k = 1 … `count` (the sums of `fit_spectral::dft_power`,
/// whose power is their squared modulus). The angles 2π(kj mod n)/n come from one table of the n
/// roots of unity, so the transform costs n sines and cosines rather than `count`·n, and each
/// angle is reduced exactly rather than from the rounded product 2πk/n·j.
fn lowest_ordinates(weighted: &[f64], count: usize) -> Vec<(f64, f64)> {
    let n = weighted.len();
    let roots: Vec<(f64, f64)> = (0..n).map(|m| (TAU * m as f64 / n as f64).sin_cos()).collect();
    (1..=count)
        .map(|k| {
            let step = k % n.max(1);
            let (mut m, mut sum) = (0, (0.0, 0.0));
            for &v in weighted {
                let (sin, cos) = roots[m];
                sum.0 += v * cos;
                sum.1 += v * sin;
                m += step;
                if m >= n {
                    m -= n;
                }
            }
            sum
        })
        .collect()
}

/// The Tukey window over `n` samples ([`TAPER_SHARE`] tapered).
fn taper(n: usize) -> Vec<f64> {
    let edge = ((TAPER_SHARE * 0.5 * n as f64).round() as usize).max(1);
    (0..n)
        .map(|j| {
            let from_end = j.min(n - 1 - j);
            if from_end >= edge { 1.0 } else { 0.5 * (1.0 - (PI * (from_end as f64 + 0.5) / edge as f64).cos()) }
        })
        .collect()
}

/// Spectral density (per-sample variance units, ω radians per sample) of a first-order
/// Gauss–Markov process of unit variance and correlation time `corr_s` sampled every `dt` s as
/// the simulator outputs it ([`gauss_markov_averaged`]): point samples are an AR(1) sequence,
/// σ²(1 − φ²) / |1 − φe^(−iω)|², φ = e^(−dt/T); interval means have the autocovariances
/// γ₀ = 2σ²(a − 1 + φ)/a², γ_h = σ²(1 − φ)²φ^(h−1)/a² (a = dt/T), so
/// S = γ₀ + 2γ₁(cos ω − φ) / |1 − φe^(−iω)|².
pub fn gauss_markov_spectrum(corr_s: f64, dt: f64, omega: f64) -> f64 {
    let a = dt / corr_s;
    let phi = (-a).exp();
    let one_less = -(-a).exp_m1();
    let sin_half = (0.5 * omega).sin();
    let denominator = one_less * one_less + 4.0 * phi * sin_half * sin_half;
    if gauss_markov_averaged(corr_s, dt) {
        let gamma0 = 2.0 * (a + (-a).exp_m1()) / (a * a);
        let gamma1 = one_less * one_less / (a * a);
        gamma0 + 2.0 * gamma1 * (omega.cos() - phi) / denominator
    } else {
        one_less * (1.0 + phi) / denominator
    }
}

/// Columns of the model: quantisation, white, flicker, rate random walk, Gauss–Markov.
pub const COLUMNS: usize = 5;
/// The noise columns the nested tests fit: quantisation, white, flicker, rate random walk (no
/// Gauss–Markov column).
pub const NOISE_COLUMNS: [bool; COLUMNS] = [true, true, true, true, false];

/// The columns gⱼ(ω) at the bins of `periodogram` (module docs): the flicker bank with its floor
/// from `floor_from_s` to `floor_to_s` per unit B², and a zero Gauss–Markov column
/// ([`set_gauss_markov_column`] fills it).
pub fn columns(periodogram: &Periodogram, dt: f64, floor_from_s: f64, floor_to_s: f64) -> Vec<[f64; COLUMNS]> {
    let poles = flicker_poles(1.0, floor_from_s, floor_to_s, dt);
    periodogram
        .omega
        .iter()
        .map(|&w| {
            let s2 = 4.0 * (0.5 * w).sin().powi(2);
            let flicker: f64 = poles.iter().map(|&(v, c)| v * gauss_markov_spectrum(c, dt, w)).sum();
            [s2, 1.0, flicker, 1.0 / s2, 0.0]
        })
        .collect()
}

/// The coefficients of the columns (module docs) for the noise terms `terms` sampled every `dt`
/// s, with no Gauss–Markov process: where a fit starts.
pub fn coefficients_of(terms: &NoiseTerms, dt: f64) -> [f64; COLUMNS] {
    [(terms.q / dt).powi(2), terms.n * terms.n / dt, terms.b * terms.b, terms.k * terms.k * dt, 0.0]
}

/// The noise terms of the quantisation, white, flicker and random-walk coefficients `c` (the
/// inverse of [`coefficients_of`]); the flicker floor's start from `like`, no rate ramp and no
/// Gauss–Markov process.
pub fn terms_of(c: &[f64; COLUMNS], dt: f64, like: &NoiseTerms) -> NoiseTerms {
    NoiseTerms {
        q: c[0].sqrt() * dt,
        n: (c[1] * dt).sqrt(),
        b: c[2].sqrt(),
        k: (c[3] / dt).sqrt(),
        r: 0.0,
        gauss_markov: None,
        ..*like
    }
}

/// Sets the Gauss–Markov column of `cols` (from [`columns`]) to a unit-variance process of
/// correlation time `corr_s`; the other columns stay.
pub fn set_gauss_markov_column(cols: &mut [[f64; COLUMNS]], periodogram: &Periodogram, dt: f64, corr_s: f64) {
    for (g, &w) in cols.iter_mut().zip(&periodogram.omega) {
        g[COLUMNS - 1] = gauss_markov_spectrum(corr_s, dt, w);
    }
}

/// A Whittle fit: the coefficients and the negative log-likelihood.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WhittleFit {
    /// cⱼ of each column (module docs), ≥ 0.
    pub coefficients: [f64; COLUMNS],
    /// ℓ at them.
    pub neg_log_likelihood: f64,
}

/// S = Σ cⱼ gⱼ at each bin of `cols` (module docs).
pub fn spectral_density(cols: &[[f64; COLUMNS]], c: &[f64; COLUMNS]) -> Vec<f64> {
    cols.iter().map(|g| g.iter().zip(c).map(|(g, c)| g * c).sum()).collect()
}

/// The binned Whittle negative log-likelihood of `c` (module docs); infinite where S ≤ 0.
pub fn neg_log_likelihood(periodogram: &Periodogram, cols: &[[f64; COLUMNS]], c: &[f64; COLUMNS]) -> f64 {
    let mut total = 0.0;
    for ((g, &mean), &weight) in cols.iter().zip(&periodogram.mean).zip(&periodogram.weight) {
        let s: f64 = g.iter().zip(c).map(|(g, c)| g * c).sum();
        if s.is_nan() || s <= 0.0 {
            return f64::INFINITY;
        }
        total += weight * (s.ln() + mean / s);
    }
    total
}

/// Minimises ℓ over cⱼ ≥ 0 with the columns in `allowed` free (the others zero), from `start`
/// (module docs).
pub fn fit(
    periodogram: &Periodogram,
    cols: &[[f64; COLUMNS]],
    allowed: [bool; COLUMNS],
    start: [f64; COLUMNS],
) -> WhittleFit {
    fit_holding(periodogram, cols, allowed, start, None)
}

/// As [`fit`], with column `held.0` held at the coefficient `held.1` (and not free): a point of
/// the profile likelihood of that column's term.
pub fn fit_holding(
    periodogram: &Periodogram,
    cols: &[[f64; COLUMNS]],
    allowed: [bool; COLUMNS],
    start: [f64; COLUMNS],
    held: Option<(usize, f64)>,
) -> WhittleFit {
    let free: [bool; COLUMNS] = std::array::from_fn(|j| allowed[j] && held.is_none_or(|(h, _)| h != j));
    let hold = |c: &mut [f64; COLUMNS]| {
        if let Some((h, v)) = held {
            c[h] = v;
        }
    };
    let mut c: [f64; COLUMNS] = std::array::from_fn(|j| if free[j] { start[j] } else { 0.0 });
    hold(&mut c);
    let mut ell = neg_log_likelihood(periodogram, cols, &c);
    if !ell.is_finite() {
        // A start with S ≤ 0 somewhere: white noise at the periodogram's mean level.
        c = [0.0; COLUMNS];
        c[1] = periodogram.mean.iter().sum::<f64>() / periodogram.mean.len() as f64;
        hold(&mut c);
        ell = neg_log_likelihood(periodogram, cols, &c);
    }
    // What the free columns fit: the periodogram less the held term.
    let target: Vec<f64> = match held {
        Some((h, v)) => periodogram.mean.iter().zip(cols).map(|(m, g)| m - v * g[h]).collect(),
        None => periodogram.mean.clone(),
    };
    for _ in 0..MAX_ITERATIONS {
        let s = spectral_density(cols, &c);
        let weights: Vec<f64> = periodogram.weight.iter().zip(&s).map(|(l, s)| l / (s * s)).collect();
        let Some(mut proposal) = weighted_nnls(cols, &target, &weights, free) else { break };
        hold(&mut proposal);
        let mut step = 1.0;
        let mut improved = false;
        while step > 1e-6 {
            let trial: [f64; COLUMNS] = std::array::from_fn(|j| c[j] + step * (proposal[j] - c[j]));
            let value = neg_log_likelihood(periodogram, cols, &trial);
            if value < ell {
                let change = (ell - value) / ell.abs().max(1.0);
                c = trial;
                ell = value;
                improved = change > TOLERANCE;
                break;
            }
            step *= 0.5;
        }
        if !improved {
            break;
        }
    }
    WhittleFit { coefficients: c, neg_log_likelihood: ell }
}

/// Non-negative weighted least squares min Σ wᵢ(yᵢ − Σⱼ cⱼ gᵢⱼ)² over the columns in `allowed`, by
/// exact enumeration of the active subsets (each solved by its normal equations on unit-scaled
/// columns); `None` when no subset has a solution.
fn weighted_nnls(cols: &[[f64; COLUMNS]], y: &[f64], w: &[f64], allowed: [bool; COLUMNS]) -> Option<[f64; COLUMNS]> {
    let mut gram = [[0.0; COLUMNS]; COLUMNS];
    let mut rhs = [0.0; COLUMNS];
    let mut yy = 0.0;
    for ((g, &y), &w) in cols.iter().zip(y).zip(w) {
        for a in 0..COLUMNS {
            rhs[a] += w * g[a] * y;
            for b in a..COLUMNS {
                gram[a][b] += w * g[a] * g[b];
            }
        }
        yy += w * y * y;
    }
    let scale: [f64; COLUMNS] = std::array::from_fn(|j| gram[j][j].sqrt());
    let mut best: Option<(f64, [f64; COLUMNS])> = None;
    for mask in 1u32..(1 << COLUMNS) {
        let active: Vec<usize> = (0..COLUMNS).filter(|&j| mask & (1 << j) != 0).collect();
        if active.iter().any(|&j| !(allowed[j] && scale[j] > 0.0 && scale[j].is_finite())) {
            continue;
        }
        let k = active.len();
        let g = DMatrix::from_fn(k, k, |r, s| {
            let (a, b) = (active[r].min(active[s]), active[r].max(active[s]));
            gram[a][b] / (scale[active[r]] * scale[active[s]])
        });
        let r = DVector::from_iterator(k, active.iter().map(|&j| rhs[j] / scale[j]));
        let Some(chol) = g.cholesky() else { continue };
        let x = chol.solve(&r);
        if x.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
            continue;
        }
        // Σw(y − Gc)² = yᵀWy − 2cᵀGᵀWy + cᵀGᵀWGc, on the scaled columns = yy − xᵀr (at the optimum).
        let rss = yy - x.dot(&r);
        if best.as_ref().is_none_or(|(b, _)| rss < *b) {
            let mut c = [0.0; COLUMNS];
            for (i, &j) in active.iter().enumerate() {
                c[j] = x[i] / scale[j];
            }
            best = Some((rss, c));
        }
    }
    best.map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::simgap::model::{SimModel, simulate};
    use crate::sim::AxisConfig;
    use crate::sim::config::{ARW_DEG_RT_H_PER_DEG_RT_S, RRW_DEG_H_RT_H_PER_DPS_RT_S};

    /// The table-driven transform at the lowest Fourier frequencies equals the direct sums
    /// Σ vⱼ·(cos, sin)(2πkj/n) to rounding, on a length that is not a power of two.
    #[test]
    fn the_lowest_ordinates_are_the_direct_transform() {
        let n = 1_001;
        let v: Vec<f64> =
            (0..n).map(|j| ((j * 7919) % 1_000) as f64 / 500.0 - 1.0 + (j as f64 * 0.013).sin()).collect();
        let table = lowest_ordinates(&v, 40);
        for (k, &(c, s)) in (1..=40).zip(&table) {
            let mut direct = (0.0, 0.0);
            for (j, x) in v.iter().enumerate() {
                let (sin, cos) = (TAU * (k * j) as f64 / n as f64).sin_cos();
                direct.0 += x * cos;
                direct.1 += x * sin;
            }
            assert!((c - direct.0).abs() < 1e-10 && (s - direct.1).abs() < 1e-10, "k {k}: {c} {s} against {direct:?}");
        }
        assert!(table.iter().any(|&(c, s)| c.abs() + s.abs() > 1.0));
    }

    /// Both Gauss–Markov forms integrate to the unit variance over (−π, π] (the spectrum's
    /// definition), and the interval-mean form tends to white noise of variance 2T/dt for T ≪ dt.
    #[test]
    fn the_gauss_markov_spectrum_has_unit_variance() {
        let dt = 0.1;
        for corr in [0.5, 3.0, 40.0] {
            let n = 200_000;
            let integral: f64 =
                (0..n).map(|i| gauss_markov_spectrum(corr, dt, PI * (i as f64 + 0.5) / n as f64)).sum::<f64>()
                    / n as f64;
            let averaged = gauss_markov_averaged(corr, dt);
            // Interval means have less variance than the process: (2/a²)(a − 1 + e^(−a)).
            let want = if averaged {
                let a = dt / corr;
                2.0 * (a - 1.0 + (-a).exp()) / (a * a)
            } else {
                1.0
            };
            assert!((integral / want - 1.0).abs() < 1e-3, "T {corr}: {integral} vs {want}");
        }
        let (corr, w) = (0.001, 1.0);
        assert!((gauss_markov_spectrum(corr, dt, w) / (2.0 * corr / dt) - 1.0).abs() < 0.02);
    }

    /// The cross-periodogram is the periodogram of x − c·z for every c (|X − cZ|² expanded; the
    /// detrending and the taper are linear), and its least-squares coefficient of x = 3z + a
    /// line is 3 under any spectral density.
    #[test]
    fn the_cross_periodogram_expands_the_residuals_periodogram() {
        let n = 3000;
        let z: Vec<f64> = (0..n).map(|i| (i as f64 * 0.013).sin() + 0.3 * (i as f64 * 0.21).cos()).collect();
        let noise: Vec<f64> = (0..n).map(|i| ((i * 7919 % 1000) as f64 / 1000.0 - 0.5) * 0.4).collect();
        let x: Vec<f64> = z.iter().zip(&noise).map(|(z, e)| 2.0 * z + e).collect();
        let cross = CrossPeriodogram::of(&x, &z).unwrap();
        for c in [0.0, 1.5, 2.0, -3.0] {
            let direct = Periodogram::of(&x.iter().zip(&z).map(|(x, z)| x - c * z).collect::<Vec<_>>()).unwrap();
            let expanded = cross.residual(c);
            assert_eq!(direct.omega, expanded.omega);
            assert_eq!(direct.weight, expanded.weight);
            let scale = direct.mean.iter().cloned().fold(0.0, f64::max);
            for (a, b) in direct.mean.iter().zip(&expanded.mean) {
                assert!((a - b).abs() <= 1e-9 * scale, "c {c}: {a} vs {b}");
            }
        }
        assert_eq!(Periodogram::of(&x).unwrap().mean, cross.xx);
        let exact: Vec<f64> = z.iter().enumerate().map(|(i, z)| 3.0 * z + 0.01 * i as f64 - 1.0).collect();
        let cross = CrossPeriodogram::of(&exact, &z).unwrap();
        for s in [vec![1.0; cross.omega.len()], cross.omega.iter().map(|w| 1.0 / (w * w)).collect()] {
            assert!((cross.gls_coefficient(&s) - 3.0).abs() < 1e-9);
        }
    }

    /// On a simulated series of white noise plus rate random walk the fit recovers both terms
    /// (per-sample white variance N²/dt; K² dt per step) within their sampling error, and the
    /// flicker and Gauss–Markov columns add nothing significant.
    #[test]
    fn recovers_white_noise_and_rate_random_walk() {
        let (fs, len) = (10.0, 40_000);
        let (n, k) = (0.03, 4e-4);
        let model = SimModel {
            axis: AxisConfig {
                arw_deg_rt_h: Some(n * ARW_DEG_RT_H_PER_DEG_RT_S),
                rrw_deg_h_rt_h: Some(k * RRW_DEG_H_RT_H_PER_DPS_RT_S),
                ..AxisConfig::default()
            },
            ..SimModel::default()
        };
        let x = simulate(&model, fs, len, None, 3).unwrap();
        let p = Periodogram::of(&x).unwrap();
        let cols = columns(&p, 1.0 / fs, 1.0, len as f64 / fs);
        let f = fit(&p, &cols, [true, true, false, true, false], [0.0, 1.0, 0.0, 1.0, 0.0]);
        let white = n * n * fs;
        assert!((f.coefficients[1] / white - 1.0).abs() < 0.03, "{:?} vs {white}", f.coefficients);
        let step = k * k / fs;
        assert!((f.coefficients[3] / step - 1.0).abs() < 0.5, "{:?} vs {step}", f.coefficients);
        // The profile likelihood: held at its estimate the random walk gives the fit back; held
        // 4× higher or lower, ℓ rises (the others refitted, the held value kept exactly).
        let allowed = [true, true, false, true, false];
        let at = |c3: f64| fit_holding(&p, &cols, allowed, f.coefficients, Some((3, c3)));
        let same = at(f.coefficients[3]);
        assert!((same.neg_log_likelihood - f.neg_log_likelihood).abs() < 1e-6 * f.neg_log_likelihood.abs());
        for factor in [0.25, 4.0] {
            let held = at(factor * f.coefficients[3]);
            assert_eq!(held.coefficients[3], factor * f.coefficients[3]);
            assert!(held.neg_log_likelihood > f.neg_log_likelihood + 1.0, "{factor}: {held:?} vs {f:?}");
        }
    }
}
