//! The Monte-Carlo band of every statistic and where a value sits in it.
//!
//! For each statistic the ensemble of simulated members gives the median, the 2.5 % and 97.5 %
//! quantiles ([`crate::model::metrics::quantile_sorted`]; the band that "where" reports) and the standard
//! deviation s (n − 1 denominator). A value v is scored by its standard score
//!
//! z = (v − median) / s,
//!
//! which is far steadier than a score scaled by the band's edges: with a few dozen members the
//! 2.5 % and 97.5 % quantiles rest on the two most extreme members, the standard deviation on all.
//! The statistics are compared on scales where they are close to normal (log10 of Allan
//! deviations, PSD levels and kurtoses), so |z| > 1.96 is about the same as leaving the band. The
//! strongest spectral line is a maximum over many bins, whose upper tail no such scale makes
//! normal; above the median it is scored as the normal quantile of a Gumbel law fitted to the
//! members instead ([`Band::z_on`]).
//! Standard deviations below [`MIN_SD`] (a statistic all members share exactly, such as the grid
//! coherence of a quantised simulation) are raised to it.

use serde::Serialize;

use super::stats::Scale;
use crate::model::metrics::{quantile_sorted, sample_std_dev};
use crate::model::normal::normal_quantile;

/// Lower and upper quantile of the band.
pub const BAND: (f64, f64) = (0.025, 0.975);
/// Smallest standard deviation on the comparison scale (1e-6 decades, or 1e-6 deg/s).
pub const MIN_SD: f64 = 1e-6;

/// The ensemble band of one statistic, on the comparison scale.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Band {
    /// Ensemble median.
    pub median: f64,
    /// Ensemble mean.
    pub mean: f64,
    /// 2.5 % quantile.
    pub lo: f64,
    /// 97.5 % quantile.
    pub hi: f64,
    /// Standard deviation (n − 1).
    pub sd: f64,
}

impl Band {
    /// The band of `values` (not empty).
    pub fn of(values: &mut [f64]) -> Band {
        values.sort_unstable_by(f64::total_cmp);
        Band {
            median: quantile_sorted(values, 0.5),
            mean: values.iter().sum::<f64>() / values.len() as f64,
            lo: quantile_sorted(values, BAND.0),
            hi: quantile_sorted(values, BAND.1),
            sd: sample_std_dev(values).unwrap_or(0.0),
        }
    }

    /// The standard score of `v` (module docs).
    pub fn z(&self, v: f64) -> f64 {
        (v - self.median) / self.sd.max(MIN_SD)
    }

    /// The standard score of `v` for a statistic compared on `scale`: [`z`](Self::z), or for a
    /// maximum ([`Scale::Maximum`]) above the median of the members' Gumbel law the normal
    /// quantile of that law at `v`, z = Φ⁻¹(G(v)), G(v) = exp(−e^(−u)), u = (v − μ)/β
    /// ([`gumbel_parameters`]), and below it (v − law median)/s. A maximum over many bins
    /// has an exponential upper tail (Fisher–Tippett): scored by (v − median)/s on log10, one in
    /// 200 white-noise series reads z > 4 against 32 members, and one in 70 z > 3. Its lower tail
    /// is thin, so the Gumbel score would make a weaker strongest line far out (z −4.8 for −2.8).
    pub fn z_on(&self, scale: Scale, v: f64) -> f64 {
        if scale != Scale::Maximum || !v.is_finite() {
            return self.z(v);
        }
        let sd = self.sd.max(MIN_SD);
        let (mu, beta) = gumbel_parameters(self.mean, sd);
        let law_median = mu - beta * std::f64::consts::LN_2.ln();
        if v < law_median {
            // Below the law's median a maximum is scored as normal: a weaker strongest line is
            // no effect's signature, and the Gumbel law's thin lower tail would make it one.
            return (v - law_median) / sd;
        }
        // ln(1 − G) = ln(−expm1(−e^(−u))), which is −u − e^(−u)/2 + … far out (u > 0 here).
        let u = (v - mu) / beta;
        let x = (-u).exp();
        upper_tail_score(if x > 1e-8 { (-(-x).exp_m1()).ln() } else { -u - 0.5 * x })
    }

    /// Whether `v` lies outside [lo, hi].
    pub fn outside(&self, v: f64) -> bool {
        v < self.lo || v > self.hi
    }
}

/// The location μ and scale β of the Gumbel (maximum) law with this mean and standard deviation
/// (method of moments: β = sd·√6/π, μ = mean − γβ, γ Euler's constant).
pub fn gumbel_parameters(mean: f64, sd: f64) -> (f64, f64) {
    const EULER_GAMMA: f64 = 0.577_215_664_901_532_9;
    let beta = sd * 6f64.sqrt() / std::f64::consts::PI;
    (mean - EULER_GAMMA * beta, beta)
}

/// The standard normal score z with P(Z > z) = e^`ln_p`, for ln p ≤ ln ½: Φ⁻¹ where e^ln_p is
/// a normal double, else the tail's asymptotic inverse (p ≈ φ(z)/z, so z² = 2L − 2 ln z − ln 2π
/// with L = −ln p, one fixed-point step from z = √(2L); relative error below 1e-4 there, z > 37).
fn upper_tail_score(ln_p: f64) -> f64 {
    if ln_p > -700.0 {
        return -normal_quantile(ln_p.exp());
    }
    let two_l = -2.0 * ln_p;
    (two_l - two_l.sqrt().ln() * 2.0 - (2.0 * std::f64::consts::PI).ln()).sqrt()
}

/// The band of every statistic from `members` (one statistics vector each), leaving member
/// `skip` out when it is `Some` (the leave-one-out bands of the null distribution).
pub fn bands(members: &[Vec<f64>], skip: Option<usize>) -> Vec<Band> {
    let stats = members.first().map_or(0, Vec::len);
    let mut column = Vec::with_capacity(members.len());
    (0..stats)
        .map(|s| {
            column.clear();
            column.extend(members.iter().enumerate().filter(|(j, _)| Some(*j) != skip).map(|(_, m)| m[s]));
            Band::of(&mut column)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn band_quantiles_and_standard_score() {
        let mut v: Vec<f64> = (0..=40).map(|i| i as f64).collect();
        let b = Band::of(&mut v);
        assert_eq!((b.median, b.lo, b.hi), (20.0, 1.0, 39.0));
        // sd of 0..=40 with n − 1: √(41·42/12) = 11.979…
        assert!((b.sd - (41.0f64 * 42.0 / 12.0).sqrt()).abs() < 1e-12);
        assert!((b.z(20.0 + 2.0 * b.sd) - 2.0).abs() < 1e-12);
        assert!(b.outside(39.5) && !b.outside(38.0));
    }

    #[test]
    fn leave_one_out_drops_the_member() {
        let members = vec![vec![0.0], vec![1.0], vec![100.0]];
        assert_eq!(bands(&members, Some(2))[0].median, 0.5);
        assert_eq!(bands(&members, None)[0].median, 1.0);
    }

    #[test]
    fn zero_width_bands_do_not_divide_by_zero() {
        let b = Band::of(&mut [0.0, 0.0, 0.0]);
        assert_eq!(b.z(0.0), 0.0);
        assert!(b.z(1.0).is_finite() && b.z(1.0) > 1e5);
    }

    /// Members at the quantiles of a Gumbel law (μ 2, β 0.5): a value at the law's p quantile,
    /// μ − β·ln(−ln p), above its median scores Φ⁻¹(p) as a maximum, below it a normal score;
    /// scored as normal, the upper tail reads far out (p = 0.9999, z 3.72: (v − median)/s is
    /// 6.9). Far tails stay finite and ordered, and the other scales score as before.
    #[test]
    fn a_maximum_is_scored_under_its_gumbel_law() {
        let (mu, beta) = (2.0, 0.5);
        let quantile = |p: f64| mu - beta * (-p.ln()).ln();
        let mut members: Vec<f64> = (0..4000).map(|i| quantile((i as f64 + 0.5) / 4000.0)).collect();
        let b = Band::of(&mut members);
        for (p, z) in [(0.5, 0.0), (0.9, 1.281_551_6), (0.99, 2.326_347_9), (0.9999, 3.719_016_5)] {
            let got = b.z_on(Scale::Maximum, quantile(p));
            assert!((got - z).abs() < 0.03, "p {p}: z {got}, want {z}");
        }
        // Below the median, a normal score: (q(0.01) − q(0.5))/s = (1.237 − 2.183)/0.641.
        let low = b.z_on(Scale::Maximum, quantile(0.01));
        assert!((low + 1.475).abs() < 0.01, "{low}");
        assert!(b.z_on(Scale::Linear, quantile(0.9999)) > 6.5);
        let (far_up, farther_up) = (b.z_on(Scale::Maximum, 400.0), b.z_on(Scale::Maximum, 800.0));
        assert!(far_up.is_finite() && farther_up.is_finite() && farther_up > far_up && far_up > 5.0);
        let far_down = b.z_on(Scale::Maximum, -40.0);
        assert!(far_down.is_finite() && far_down < -7.0);
        assert!(b.z_on(Scale::Maximum, f64::NAN).is_nan());
        for scale in [Scale::Linear, Scale::Log10] {
            assert_eq!(b.z_on(scale, 3.0), b.z(3.0));
        }
    }
}
