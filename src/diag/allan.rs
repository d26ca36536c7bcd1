//! Overlapping Allan deviation of a rate ("frequency") series.
//!
//! Definition (IEEE Std 952-1997 Annex C; NIST SP 1065 eq. 11, "OADEV"): with the sample interval
//! τ₀ = 1/f_s, the phase (integrated rate, i.e. angle) x₀ = 0, x_{k+1} = τ₀·Σ_{j≤k}(y_j − ȳ), and an
//! averaging factor m (τ = m·τ₀),
//!
//! σ²(τ) = Σ_{i=0}^{n−1} (x_{i+2m} − 2x_{i+m} + x_i)² / (2 τ² n),   n = N + 1 − 2m,
//!
//! where N is the number of rate samples. Each τ costs O(N) thanks to the cumulative sum.
//!
//! The computation reproduces `allantools.oadev(y, rate=f_s, data_type="freq", taus=...)`
//! (allantools 2024.06) operation for operation: `frequency2phase` (mean removed, `cumsum`, times
//! τ₀, a leading zero inserted so the phase has N + 1 points), `tau_generator` (the "octave" and
//! "all" lists, m = round(τ·f_s), m < N + 1, duplicates removed, sorted), `calc_adev_phase` with
//! stride 1 (the same sums, in NumPy's pairwise order, see [`crate::diag::pairwise`]) and
//! `remove_small_ns` (points with n ≤ 1 are dropped). The results agree with allantools to
//! rounding (the golden test holds them to 1e-9 relative).

use crate::diag::pairwise::{pairwise_sum, pairwise_sum_by};
use crate::model::normal::chi2_upper;

/// Which averaging times τ = m/f_s to evaluate (the `taus=` argument of allantools).
#[derive(Debug, Clone, PartialEq)]
pub enum Taus {
    /// m = 1, 2, 4, …, 2^⌊log₂(N+1)⌋ (allantools `"octave"`), then the points with n ≤ 1 dropped:
    /// about log₂ N values of τ, O(N log N) in all. The usual choice.
    Octave,
    /// Every m = 1, 2, …, N (allantools `"all"`), of which m ≤ (N − 1)/2 survive.
    ///
    /// Cost: about N/2 values of τ at O(N) each, i.e. ≈ N²/4 operations: instant for 10⁴ samples,
    /// ≈ 5 s for 10⁵ and, extrapolated, ≈ 10 min for 10⁶ (release build, one core).
    /// Cap it with [`oadev_with_max_m`] (≈ N·max_m operations).
    All,
    /// Explicit averaging factors m (sorted and de-duplicated; m = 0 and m > N ignored).
    Factors(Vec<usize>),
    /// Explicit averaging times in seconds, rounded to m = round(τ·f_s) (ties to even, as NumPy).
    Seconds(Vec<f64>),
}

/// Overlapping Allan deviation at a list of averaging times (NIST SP 1065 eq. 11).
#[derive(Debug, Clone, PartialEq)]
pub struct AllanDeviation {
    /// Averaging time τ = m/f_s of each point, seconds.
    pub tau_s: Vec<f64>,
    /// Averaging factor m of each point (τ in samples).
    pub m: Vec<usize>,
    /// Allan deviation σ(τ), in the unit of the input rate (deg/s for gyro data).
    pub adev: Vec<f64>,
    /// Simple error estimate σ(τ)/√n (allantools `ade`), same unit as `adev`.
    pub adev_err: Vec<f64>,
    /// Number of second differences n = N + 1 − 2m summed at each τ (allantools `ns`).
    pub n: Vec<usize>,
    /// Sample rate f_s, Hz.
    pub rate_hz: f64,
    /// Number N of rate samples in the input.
    pub samples: usize,
}

impl AllanDeviation {
    /// The deviation of a series of `samples` at `rate_hz` from its points (m, σ(τ), n): τ = m/f_s
    /// and the simple error σ/√n (allantools `ade`). An error when there is no point.
    pub fn from_points(
        rate_hz: f64,
        samples: usize,
        points: impl IntoIterator<Item = (usize, f64, usize)>,
    ) -> Result<AllanDeviation, AllanError> {
        let mut out = AllanDeviation {
            tau_s: Vec::new(),
            m: Vec::new(),
            adev: Vec::new(),
            adev_err: Vec::new(),
            n: Vec::new(),
            rate_hz,
            samples,
        };
        for (m, dev, n) in points {
            out.tau_s.push(m as f64 / rate_hz);
            out.m.push(m);
            out.adev.push(dev);
            out.adev_err.push(dev / (n as f64).sqrt());
            out.n.push(n);
        }
        if out.is_empty() {
            return Err(AllanError::TooFewSamples { samples });
        }
        Ok(out)
    }

    /// Number of τ points.
    pub fn len(&self) -> usize {
        self.tau_s.len()
    }

    /// Whether there are no τ points.
    pub fn is_empty(&self) -> bool {
        self.tau_s.is_empty()
    }

    /// Allan variance σ²(τ) of each point.
    pub fn avar(&self) -> Vec<f64> {
        self.adev.iter().map(|d| d * d).collect()
    }

    /// The points whose m is a power of two (the octave grid), e.g. to fit the noise model on
    /// evenly spaced log τ whatever list was computed.
    pub fn octave_points(&self) -> AllanDeviation {
        self.select(|m| m.is_power_of_two())
    }

    /// The points whose averaging factor m satisfies `keep`.
    pub fn select(&self, keep: impl Fn(usize) -> bool) -> AllanDeviation {
        let idx: Vec<usize> = (0..self.len()).filter(|&i| keep(self.m[i])).collect();
        AllanDeviation {
            tau_s: idx.iter().map(|&i| self.tau_s[i]).collect(),
            m: idx.iter().map(|&i| self.m[i]).collect(),
            adev: idx.iter().map(|&i| self.adev[i]).collect(),
            adev_err: idx.iter().map(|&i| self.adev_err[i]).collect(),
            n: idx.iter().map(|&i| self.n[i]).collect(),
            rate_hz: self.rate_hz,
            samples: self.samples,
        }
    }
}

impl AllanDeviation {
    /// Degrees of freedom ν of each point for its confidence interval: ν = ⌊N/m⌋ − 1 (at least
    /// 1), the number of non-overlapping clusters of m samples less one. This is the simple,
    /// noise-type-free count (IEEE Std 952-1997 Annex C, σ(δ)/σ = 1/√(2(K − 1))); the overlapping
    /// estimator has somewhat more degrees of freedom (NIST SP 1065 §5.3), so intervals from it
    /// are on the safe (wide) side.
    pub fn dof(&self) -> Vec<f64> {
        self.m.iter().map(|&m| ((self.samples / m.max(1)) as f64 - 1.0).max(1.0)).collect()
    }

    /// The two-sided `level` (e.g. 0.683 or 0.95) χ² confidence interval of each point's Allan
    /// deviation with ν = [`dof`](Self::dof): σ·√(ν/χ²_{(1+level)/2}(ν)) … σ·√(ν/χ²_{(1−level)/2}(ν)).
    pub fn confidence_band(&self, level: f64) -> Vec<(f64, f64)> {
        let (p_lo, p_hi) = ((1.0 - level) / 2.0, (1.0 + level) / 2.0);
        self.adev
            .iter()
            .zip(self.dof())
            .map(|(&d, nu)| {
                // The p_hi quantile is exceeded with probability p_lo, and the other way round.
                (d * (nu / chi2_upper(nu, p_lo)).sqrt(), d * (nu / chi2_upper(nu, p_hi)).sqrt())
            })
            .collect()
    }
}

/// Why the Allan deviation could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AllanError {
    /// The sample rate is zero, negative or not finite.
    #[error("sample rate {0} Hz is not positive and finite")]
    BadRate(f64),
    /// A rate sample is NaN or infinite.
    #[error("sample {index} is not finite ({value})")]
    NonFinite {
        /// 0-based index of the sample.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// An explicit τ is NaN or infinite.
    #[error("averaging time {0} s is not finite")]
    BadTau(f64),
    /// The series is too short for the requested τ (at least 3 samples are needed for m = 1,
    /// and 2m + 1 for factor m).
    #[error(
        "too few samples for any requested tau: {samples} sample(s); the overlapping Allan \
         deviation at m samples needs at least 2m + 1 (3 for the shortest tau)"
    )]
    TooFewSamples {
        /// Number of samples given.
        samples: usize,
    },
}

/// Overlapping Allan deviation of the rate series `rate` sampled at `rate_hz`, at the averaging
/// times chosen by `taus` (allantools `oadev(rate, rate=rate_hz, data_type="freq", taus=...)`).
///
/// Points with fewer than two second differences (n ≤ 1) are dropped, as allantools does; an error
/// is returned when none remain, when the rate is not positive and finite, or when a sample is not
/// finite.
pub fn oadev(rate: &[f64], rate_hz: f64, taus: &Taus) -> Result<AllanDeviation, AllanError> {
    oadev_with_max_m(rate, rate_hz, taus, usize::MAX)
}

/// [`oadev`] with the averaging factor capped at `max_m` samples (allantools `maximum_m`), which
/// bounds the cost of [`Taus::All`] to ≈ N·max_m operations.
pub fn oadev_with_max_m(rate: &[f64], rate_hz: f64, taus: &Taus, max_m: usize) -> Result<AllanDeviation, AllanError> {
    let phase = checked_phase(rate, rate_hz)?;
    let factors = averaging_factors(rate.len(), rate_hz, taus, max_m)?;
    let points = factors.into_iter().filter_map(|m| oadev_phase_at(&phase, rate_hz, m).map(|(dev, n)| (m, dev, n)));
    AllanDeviation::from_points(rate_hz, rate.len(), points)
}

/// The phase ([`phase_from_rate`]) of a rate series after the checks every Allan estimator makes:
/// `rate_hz` positive and finite, every sample finite.
pub fn checked_phase(rate: &[f64], rate_hz: f64) -> Result<Vec<f64>, AllanError> {
    if !(rate_hz.is_finite() && rate_hz > 0.0) {
        return Err(AllanError::BadRate(rate_hz));
    }
    if let Some((index, &value)) = rate.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(AllanError::NonFinite { index, value });
    }
    Ok(phase_from_rate(rate, rate_hz))
}

/// Phase (angle) from a rate series, as allantools `frequency2phase`: the mean is removed, the
/// deviations are summed cumulatively and multiplied by τ₀ = 1/f_s, and a leading zero is inserted,
/// so the result has `rate.len() + 1` points. Empty input gives `[0.0]`.
pub fn phase_from_rate(rate: &[f64], rate_hz: f64) -> Vec<f64> {
    let dt = 1.0 / rate_hz;
    let mut phase = Vec::with_capacity(rate.len() + 1);
    phase.push(0.0);
    if rate.is_empty() {
        return phase;
    }
    let mean = pairwise_sum(rate) / rate.len() as f64;
    let mut acc = 0.0;
    for &y in rate {
        acc += y - mean;
        phase.push(acc * dt);
    }
    phase
}

/// Overlapping Allan deviation at averaging factor `m` of a phase series (allantools
/// `calc_adev_phase` with stride 1): returns `(σ(m/f_s), n)` with n = len − 2m second differences,
/// or `None` when n ≤ 1 (allantools drops such points) or m = 0.
pub fn oadev_phase_at(phase: &[f64], rate_hz: f64, m: usize) -> Option<(f64, usize)> {
    if m == 0 {
        return None;
    }
    let n = phase.len().checked_sub(m.checked_mul(2)?)?;
    if n <= 1 {
        return None;
    }
    let (d0, d1, d2) = (&phase[..n], &phase[m..m + n], &phase[2 * m..2 * m + n]);
    let s = pairwise_sum_by(n, &|i| {
        let v = d2[i] - 2.0 * d1[i] + d0[i];
        v * v
    });
    let dev = (s / (2.0 * n as f64)).sqrt() / m as f64 * rate_hz;
    Some((dev, n))
}

/// The sorted, de-duplicated averaging factors m of `taus` for `samples` rate samples, following
/// allantools `tau_generator` on the (samples + 1)-point phase: 0 < m < samples + 1 and m ≤ max_m.
pub fn averaging_factors(samples: usize, rate_hz: f64, taus: &Taus, max_m: usize) -> Result<Vec<usize>, AllanError> {
    let phase_len = samples + 1;
    let mut factors: Vec<usize> = match taus {
        // allantools: maxn = floor(log2(len(phase))); taus = 2^k/rate, k = 0..=maxn.
        Taus::Octave => (0..=phase_len.ilog2()).map(|k| 1usize << k).collect(),
        Taus::All => (1..=phase_len).collect(),
        Taus::Factors(ms) => ms.clone(),
        Taus::Seconds(ts) => {
            let mut ms = Vec::with_capacity(ts.len());
            for &t in ts {
                if !t.is_finite() {
                    return Err(AllanError::BadTau(t));
                }
                let m = (t * rate_hz).round_ties_even();
                if m > 0.0 && m < phase_len as f64 {
                    ms.push(m as usize);
                }
            }
            ms
        }
    };
    factors.retain(|&m| m > 0 && m < phase_len && m <= max_m);
    factors.sort_unstable();
    factors.dedup();
    Ok(factors)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_series_has_zero_deviation() {
        // 0.375 is exact in binary: the mean is exact and every deviation is exactly zero.
        let a = oadev(&[0.375; 1000], 10.0, &Taus::Octave).unwrap();
        assert!(!a.is_empty());
        assert!(a.adev.iter().all(|&d| d == 0.0), "{:?}", a.adev);
        // 0.37 is not: the computed mean differs from it by rounding, leaving ~1e-30 (allantools
        // gives the same values, 3.198e-30 at τ₀).
        let a = oadev(&[0.37; 1000], 10.0, &Taus::Octave).unwrap();
        assert!(a.adev.iter().all(|&d| d < 1e-14), "{:?}", a.adev);
    }

    #[test]
    fn linear_ramp_follows_r_tau_over_sqrt2() {
        // A rate ramp y = y0 + R t has σ(τ) = R τ / √2 exactly (IEEE Std 952 Annex C).
        let (fs, r) = (10.0, 0.003);
        let x: Vec<f64> = (0..4096).map(|k| 0.2 + r * k as f64 / fs).collect();
        let a = oadev(&x, fs, &Taus::Octave).unwrap();
        for (&tau, &dev) in a.tau_s.iter().zip(&a.adev) {
            let expected = r * tau / 2f64.sqrt();
            assert!((dev - expected).abs() <= 1e-9 * expected, "tau {tau}: {dev} vs {expected}");
        }
    }

    #[test]
    fn octave_factors_and_counts_follow_allantools() {
        // N = 37: phase has 38 points, maxn = 5, m = 1..32; n = 38 − 2m; n ≤ 1 dropped (m = 32).
        let x: Vec<f64> = (0..37).map(|k| ((k * 7919) % 13) as f64).collect();
        let a = oadev(&x, 7.0, &Taus::Octave).unwrap();
        assert_eq!(a.m, vec![1, 2, 4, 8, 16]);
        assert_eq!(a.n, vec![36, 34, 30, 22, 6]);
        assert_eq!(a.tau_s[2], 4.0 / 7.0);
        let all = oadev(&x, 7.0, &Taus::All).unwrap();
        assert_eq!(all.m, (1..=18).collect::<Vec<_>>());
        assert_eq!(all.octave_points().adev, a.adev);
    }

    #[test]
    fn explicit_taus_round_and_dedupe() {
        let x: Vec<f64> = (0..100).map(|k| (k as f64 * 0.7).sin()).collect();
        let by_s = oadev(&x, 10.0, &Taus::Seconds(vec![0.5, 0.1, 0.25, 0.1, 0.0, 99.0])).unwrap();
        assert_eq!(by_s.m, vec![1, 2, 5]); // 0.25 s · 10 Hz = 2.5 → 2 (ties to even)
        let by_m = oadev(&x, 10.0, &Taus::Factors(vec![5, 2, 1, 0, 1000])).unwrap();
        assert_eq!(by_m, by_s);
        let capped = oadev_with_max_m(&x, 10.0, &Taus::All, 3).unwrap();
        assert_eq!(capped.m, vec![1, 2, 3]);
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        assert_eq!(oadev(&[1.0, 2.0], 1.0, &Taus::Octave), Err(AllanError::TooFewSamples { samples: 2 }));
        assert_eq!(oadev(&[], 1.0, &Taus::All), Err(AllanError::TooFewSamples { samples: 0 }));
        assert!(oadev(&[1.0, 2.0, 3.0], 1.0, &Taus::Octave).is_ok());
        assert_eq!(oadev(&[1.0; 10], 0.0, &Taus::Octave), Err(AllanError::BadRate(0.0)));
        assert!(matches!(oadev(&[1.0; 10], f64::NAN, &Taus::Octave), Err(AllanError::BadRate(_))));
        assert!(matches!(
            oadev(&[1.0, f64::NAN, 2.0, 3.0], 1.0, &Taus::Octave),
            Err(AllanError::NonFinite { index: 1, .. })
        ));
        assert_eq!(oadev(&[1.0; 10], 1.0, &Taus::Seconds(vec![f64::INFINITY])), Err(AllanError::BadTau(f64::INFINITY)));
        assert!(matches!(oadev(&[1.0; 10], 1.0, &Taus::Factors(vec![])), Err(AllanError::TooFewSamples { .. })));
    }

    #[test]
    fn chi_square_quantiles_and_bands() {
        let x: Vec<f64> = (0..4096).map(|k| ((k * 7919) % 101) as f64).collect();
        let a = oadev(&x, 1.0, &Taus::Octave).unwrap();
        assert_eq!(a.dof()[0], 4095.0);
        let band = a.confidence_band(0.683);
        for ((lo, hi), d) in band.iter().zip(&a.adev) {
            assert!(lo < d && d < hi, "{lo} {d} {hi}");
        }
        // Relative width falls with ν: widest at the longest τ.
        let rel: Vec<f64> = band.iter().zip(&a.adev).map(|((lo, hi), d)| (hi - lo) / d).collect();
        assert!(rel.first() < rel.last());
        // m = 256: ν = 15; scipy.stats.chi2.isf(0.1585, 15) and chi2.isf(0.8415, 15).
        assert_eq!((a.m[8], a.dof()[8]), (256, 15.0));
        let (lo, hi) = band[8];
        assert!((lo / (a.adev[8] * (15.0 / 20.361_480_284_718_475f64).sqrt()) - 1.0).abs() < 1e-12);
        assert!((hi / (a.adev[8] * (15.0 / 9.644_267_220_957_815f64).sqrt()) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn phase_has_a_leading_zero_and_zero_mean_increments() {
        let p = phase_from_rate(&[1.0, 3.0, 2.0], 2.0);
        assert_eq!(p, vec![0.0, -0.5, 0.0, 0.0]);
        assert_eq!(phase_from_rate(&[], 1.0), vec![0.0]);
    }
}
