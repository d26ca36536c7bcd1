//! Prediction error indexes of paper §3 Step 5: MAE (Eq. 22), RMSE (Eq. 23), ARE (Eq. 24), the
//! standard deviation used for compensation (paper §4.3, Table 2; [`sample_std_dev`], n − 1) and
//! the population standard deviation ([`population_std_dev`], n), and quantiles and the median.
//!
//! ARE: the paper writes `(1/n) Σ |ŷ_i − y_i| / y_i`. Dividing by a signed `y_i` lets terms of
//! opposite sign cancel, so [`are`] divides by `|y_i|`. Even so ARE is ill-posed for a drift
//! series: after Eq. 21 the series sits around 0 in [−1, 1], so samples near zero dominate the
//! mean (one `y_i = 0` makes it infinite), and the value changes with the normalisation offset —
//! ARE in normalised units and in deg/s differ, unlike MAE/RMSE which only scale. Report it for
//! comparison with the paper, never to rank models.
//!
//! Unit conversion: MAE and RMSE scale linearly from normalised units to the original units by
//! the scaler's half-range ([`MinMaxScaler::inverse_scale`]); ARE does not, so
//! [`Metrics::in_original_units`] recomputes everything from inverse-transformed values.

use super::scaler::MinMaxScaler;

/// MAE, RMSE and ARE of one set of predictions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metrics {
    /// Number of predictions n.
    pub n: usize,
    /// Mean absolute error, Eq. 22.
    pub mae: f64,
    /// Root mean square error, Eq. 23.
    pub rmse: f64,
    /// Average relative error, Eq. 24 with `|y_i|` (a fraction, not percent; see module docs).
    pub are: f64,
}

impl Metrics {
    /// All three indexes of `pred` against `actual`; `None` when the lengths differ or are 0.
    pub fn new(pred: &[f64], actual: &[f64]) -> Option<Self> {
        Self::from_pairs(pred.len(), actual.len(), pred.iter().copied().zip(actual.iter().copied()))
    }

    /// The indexes in original units (e.g. deg/s) of normalised predictions and targets: both
    /// are mapped back with [`MinMaxScaler::inverse`] first. `None` as for [`Metrics::new`].
    pub fn in_original_units(pred: &[f64], actual: &[f64], scaler: &MinMaxScaler) -> Option<Self> {
        let pairs = pred.iter().zip(actual).map(|(&p, &a)| (scaler.inverse(p), scaler.inverse(a)));
        Self::from_pairs(pred.len(), actual.len(), pairs)
    }

    fn from_pairs(np: usize, na: usize, pairs: impl Iterator<Item = (f64, f64)>) -> Option<Self> {
        if np != na || np == 0 {
            return None;
        }
        let (mut abs, mut sq, mut rel) = (0.0, 0.0, 0.0);
        for (p, a) in pairs {
            let e = (p - a).abs();
            abs += e;
            sq += e * e;
            rel += e / a.abs();
        }
        let n = np as f64;
        Some(Self { n: np, mae: abs / n, rmse: (sq / n).sqrt(), are: rel / n })
    }
}

/// Mean absolute error, Eq. 22: `(1/n) Σ |ŷ_i − y_i|`. `None` when lengths differ or are 0.
pub fn mae(pred: &[f64], actual: &[f64]) -> Option<f64> {
    Metrics::new(pred, actual).map(|m| m.mae)
}

/// Root mean square error, Eq. 23: `√((1/n) Σ (ŷ_i − y_i)²)`. `None` when lengths differ or are 0.
pub fn rmse(pred: &[f64], actual: &[f64]) -> Option<f64> {
    Metrics::new(pred, actual).map(|m| m.rmse)
}

/// Average relative error, Eq. 24 with the denominator `|y_i|`: `(1/n) Σ |ŷ_i − y_i| / |y_i|`
/// (a fraction; `+∞` if some `y_i = 0`; see the module docs). `None` when lengths differ or are 0.
pub fn are(pred: &[f64], actual: &[f64]) -> Option<f64> {
    Metrics::new(pred, actual).map(|m| m.are)
}

/// Sum of squared deviations from the mean, `Σ (x_i − x̄)²` with `x̄ = (1/n) Σ x_i` (two passes),
/// the numerator of both standard deviations below.
fn sum_sq_dev(x: &[f64]) -> f64 {
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    x.iter().map(|v| (v - mean) * (v - mean)).sum()
}

/// Sample standard deviation with the `n − 1` denominator, `√(Σ (x_i − x̄)² / (n − 1))` (MATLAB's
/// `std` default), as in paper Table 2 (drift before/after compensation). `None` for fewer than 2
/// values.
pub fn sample_std_dev(x: &[f64]) -> Option<f64> {
    if x.len() < 2 {
        return None;
    }
    Some((sum_sq_dev(x) / (x.len() as f64 - 1.0)).sqrt())
}

/// Population standard deviation with the `n` denominator, `√(Σ (x_i − x̄)² / n)` (numpy's
/// `np.std` default), e.g. the spread of a simulated series (`gyrocomp sim`). `None` for an empty
/// slice.
pub fn population_std_dev(x: &[f64]) -> Option<f64> {
    if x.is_empty() {
        return None;
    }
    Some((sum_sq_dev(x) / x.len() as f64).sqrt())
}

/// The `q`-quantile of `x` (0 ≤ q ≤ 1), interpolating linearly between order statistics: with
/// the values sorted, position h = (n − 1)·q and `x[⌊h⌋] + (h − ⌊h⌋)·(x[⌊h⌋+1] − x[⌊h⌋])`
/// (Hyndman & Fan 1996 type 7, numpy's default `np.quantile`). `None` for an empty slice, a NaN
/// value or `q` outside [0, 1].
pub fn quantile(x: &[f64], q: f64) -> Option<f64> {
    if x.is_empty() || !(0.0..=1.0).contains(&q) || x.iter().any(|v| v.is_nan()) {
        return None;
    }
    let mut sorted = x.to_vec();
    sorted.sort_by(f64::total_cmp);
    Some(quantile_sorted(&sorted, q))
}

/// [`quantile`] of values already sorted ascending (not empty), for several quantiles of one
/// sort; `q` is clamped to [0, 1].
pub fn quantile_sorted(sorted: &[f64], q: f64) -> f64 {
    assert!(!sorted.is_empty(), "quantile of an empty sample");
    let h = (sorted.len() - 1) as f64 * q.clamp(0.0, 1.0);
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(sorted.len() - 1);
    sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
}

/// Median of `x` (the mean of the two middle values for an even count); NaN for an empty slice.
pub fn median(x: &[f64]) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    let mut v = x.to_vec();
    median_in_place(&mut v)
}

/// Median of `v` (non-empty), reordering it: the middle order statistics are selected rather
/// than the whole slice sorted, and combined as [`quantile_sorted`] combines them at q = 0.5, so
/// the value is the sorted slice's to the bit.
fn median_in_place(v: &mut [f64]) -> f64 {
    let (lo, odd) = ((v.len() - 1) / 2, v.len() % 2 == 1);
    let (_, &mut low, above) = v.select_nth_unstable_by(lo, f64::total_cmp);
    if odd {
        return quantile_sorted(&[low], 0.5);
    }
    let high = above.iter().copied().min_by(f64::total_cmp).unwrap_or(low);
    quantile_sorted(&[low, high], 0.5)
}

/// Converts an error (MAE, RMSE, a standard deviation) from normalised units to original units:
/// multiplies by the scaler's half-range. Not valid for ARE.
pub fn error_to_units(error: f64, scaler: &MinMaxScaler) -> f64 {
    scaler.inverse_scale(error)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median(&[]).is_nan());
    }

    #[test]
    fn hand_computed_values() {
        let pred = [1.0, 2.0, 5.0, -1.0];
        let actual = [2.0, 2.0, 3.0, -2.0];
        // errors 1, 0, 2, 1
        let m = Metrics::new(&pred, &actual).unwrap();
        assert_eq!(m.n, 4);
        assert_eq!(m.mae, 1.0);
        assert!((m.rmse - (6.0f64 / 4.0).sqrt()).abs() < 1e-15);
        // |e|/|y|: 1/2, 0, 2/3, 1/2 → 5/3 / 4
        assert!((m.are - 5.0 / 12.0).abs() < 1e-15);
        assert_eq!(mae(&pred, &actual), Some(1.0));
        assert_eq!(rmse(&pred, &actual), Some(m.rmse));
        assert_eq!(are(&pred, &actual), Some(m.are));
        assert_eq!(are(&[1.0], &[0.0]), Some(f64::INFINITY));
    }

    #[test]
    fn sample_std_dev_uses_n_minus_one_and_population_std_dev_n() {
        // mean 5, squared deviations sum 32, n − 1 = 7, n = 8
        let x = [2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0];
        assert!((sample_std_dev(&x).unwrap() - (32.0f64 / 7.0).sqrt()).abs() < 1e-15);
        assert_eq!(sample_std_dev(&[1.0]), None);
        assert_eq!(population_std_dev(&x), Some(2.0));
        assert_eq!(population_std_dev(&[1.0]), Some(0.0));
        assert_eq!(population_std_dev(&[]), None);
    }

    #[test]
    fn sorted_quantiles_match_numpy_linear() {
        // numpy.quantile([1, 2, 4, 8], [0, 0.25, 0.5, 0.975, 1]) = [1, 1.75, 3, 7.7, 8]
        let s = [1.0, 2.0, 4.0, 8.0];
        for (p, want) in [(0.0, 1.0), (0.25, 1.75), (0.5, 3.0), (0.975, 7.7), (1.0, 8.0)] {
            assert!((quantile_sorted(&s, p) - want).abs() < 1e-12, "p {p}");
        }
    }

    #[test]
    fn quantiles_interpolate_like_numpy() {
        // np.quantile([3, 1, 4, 2], [0, 0.5, 0.95, 1]) = [1, 2.5, 3.85, 4]
        let x = [3.0, 1.0, 4.0, 2.0];
        assert_eq!(quantile(&x, 0.0), Some(1.0));
        assert_eq!(quantile(&x, 0.5), Some(2.5));
        assert!((quantile(&x, 0.95).unwrap() - 3.85).abs() < 1e-12);
        assert_eq!(quantile(&x, 1.0), Some(4.0));
        assert_eq!(quantile(&[7.0], 0.95), Some(7.0));
        assert_eq!(quantile(&[], 0.5), None);
        assert_eq!(quantile(&x, 1.5), None);
        assert_eq!(quantile(&[1.0, f64::NAN], 0.5), None);
    }

    #[test]
    fn bad_lengths() {
        assert_eq!(Metrics::new(&[], &[]), None);
        assert_eq!(Metrics::new(&[1.0], &[1.0, 2.0]), None);
        assert_eq!(mae(&[1.0, 2.0], &[1.0]), None);
    }

    #[test]
    fn original_units() {
        // [0, 4] ↦ [−1, 1]: half-range 2, centre 2.
        let s = MinMaxScaler { min: 0.0, max: 4.0 };
        let pred = [0.0, 0.5];
        let actual = [0.5, 0.0];
        let norm = Metrics::new(&pred, &actual).unwrap();
        let deg = Metrics::in_original_units(&pred, &actual, &s).unwrap();
        assert_eq!(deg.mae, error_to_units(norm.mae, &s));
        assert_eq!(deg.rmse, error_to_units(norm.rmse, &s));
        // Originals 2, 3 vs 3, 2: ARE = (1/3 + 1/2)/2, while normalised ARE is infinite.
        assert!((deg.are - 5.0 / 12.0).abs() < 1e-15);
        assert_eq!(norm.are, f64::INFINITY);
    }
}
