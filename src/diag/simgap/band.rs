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
//! deviations, PSD levels and kurtoses), so |z| > 1.96 is about the same as leaving the band.
//! Standard deviations below [`MIN_SD`] (a statistic all members share exactly, such as the grid
//! coherence of a quantised simulation) are raised to it.

use serde::Serialize;

use crate::model::metrics::{quantile_sorted, sample_std_dev};

/// Lower and upper quantile of the band.
pub const BAND: (f64, f64) = (0.025, 0.975);
/// Smallest standard deviation on the comparison scale (1e-6 decades, or 1e-6 deg/s).
pub const MIN_SD: f64 = 1e-6;

/// The ensemble band of one statistic, on the comparison scale.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Band {
    /// Ensemble median.
    pub median: f64,
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
            lo: quantile_sorted(values, BAND.0),
            hi: quantile_sorted(values, BAND.1),
            sd: sample_std_dev(values).unwrap_or(0.0),
        }
    }

    /// The standard score of `v` (module docs).
    pub fn z(&self, v: f64) -> f64 {
        (v - self.median) / self.sd.max(MIN_SD)
    }

    /// Whether `v` lies outside [lo, hi].
    pub fn outside(&self, v: f64) -> bool {
        v < self.lo || v > self.hi
    }
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
}
