//! How a recording was sampled, from its time stamps: the sample rate the offline analyses assume
//! (they take the samples as equally spaced) and the dropouts — stretches with no samples — that a
//! rate from the first and last time stamp would hide. A dropout is an interval longer than
//! [`GAP_FACTOR`] times the median interval; each counts `round(interval / median) − 1` missing
//! samples. The rate is (n − 1 + missing) / (t_last − t_first): the mean rate over the whole span
//! (jitter averages out) when nothing is missing, and not lowered by what is. Where such long
//! intervals are more than [`IRREGULAR_SHARE`] of all, the stamps are irregular (batched arrival
//! times, a clock that stalls) rather than a few dropouts, and the rate stays the mean over the
//! span. (The stream's input check, [`crate::stream::input_check`], flags a live sample after a
//! step of `gap_factor` configured periods, 3 by default, against a rate it is told; this is the
//! offline estimate of that rate, and one missing sample, an interval of 2, already counts.)

use crate::model::metrics::median;

/// An interval longer than this many median intervals is a dropout.
pub const GAP_FACTOR: f64 = 1.5;

/// Above this share of long intervals the stamps count as irregular, not as dropouts.
pub const IRREGULAR_SHARE: f64 = 0.01;

/// A stretch of the recording with no samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeGap {
    /// Index of the last sample before the gap (the next one is `index + 1`).
    pub index: usize,
    /// Time of that sample, s.
    pub from_s: f64,
    /// Time of the next sample, s.
    pub to_s: f64,
    /// Samples missing at the median interval.
    pub missing: usize,
}

/// What the time stamps say about the sampling ([`sampling`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Sampling {
    /// Sample rate, Hz (module docs).
    pub rate_hz: f64,
    /// The dropouts, in time order; empty when the stamps are irregular.
    pub gaps: Vec<TimeGap>,
    /// Intervals longer than [`GAP_FACTOR`] median intervals when they are more than
    /// [`IRREGULAR_SHARE`] of all (irregular stamps, module docs); 0 otherwise.
    pub irregular: usize,
}

impl Sampling {
    /// Samples missing in all the dropouts.
    pub fn missing(&self) -> usize {
        self.gaps.iter().map(|g| g.missing).sum()
    }
}

/// The sampling of time stamps `t_s` (strictly increasing, as the readers guarantee); `None` with
/// fewer than two.
pub fn sampling(t_s: &[f64]) -> Option<Sampling> {
    let n = t_s.len();
    if n < 2 {
        return None;
    }
    let span = t_s[n - 1] - t_s[0];
    let intervals: Vec<f64> = t_s.windows(2).map(|w| w[1] - w[0]).collect();
    let median = median(&intervals);
    let long: Vec<usize> = (0..intervals.len()).filter(|&i| intervals[i] > GAP_FACTOR * median).collect();
    if long.len() as f64 > IRREGULAR_SHARE * intervals.len() as f64 {
        return Some(Sampling { rate_hz: (n - 1) as f64 / span, gaps: Vec::new(), irregular: long.len() });
    }
    let gaps: Vec<TimeGap> = long
        .iter()
        .map(|&i| TimeGap {
            index: i,
            from_s: t_s[i],
            to_s: t_s[i + 1],
            missing: ((intervals[i] / median).round() as usize).saturating_sub(1),
        })
        .collect();
    let missing: usize = gaps.iter().map(|g| g.missing).sum();
    Some(Sampling { rate_hz: (n - 1 + missing) as f64 / span, gaps, irregular: 0 })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn uniform(n: usize, rate_hz: f64) -> Vec<f64> {
        (0..n).map(|i| 3.0 + i as f64 / rate_hz).collect()
    }

    #[test]
    fn equally_spaced_stamps_have_no_gap_and_the_mean_rate() {
        let t = uniform(10_001, 100.0);
        let s = sampling(&t).unwrap();
        assert!(s.gaps.is_empty() && s.irregular == 0);
        assert_eq!(s.rate_hz, 10_000.0 / (t[10_000] - t[0]));
        assert!((s.rate_hz - 100.0).abs() < 1e-9);
    }

    #[test]
    fn a_dropout_is_found_and_does_not_lower_the_rate() {
        // 10 Hz, samples 1,000..1,100 missing (100 samples, 10.1 s between two stamps).
        let t: Vec<f64> = uniform(5_000, 10.0)
            .into_iter()
            .enumerate()
            .filter(|(i, _)| !(1_000..1_100).contains(i))
            .map(|(_, t)| t)
            .collect();
        let s = sampling(&t).unwrap();
        assert_eq!(s.gaps.len(), 1);
        let gap = s.gaps[0];
        assert_eq!((gap.index, gap.missing), (999, 100));
        assert!((gap.from_s - 102.9).abs() < 1e-9 && (gap.to_s - 113.0).abs() < 1e-9, "{gap:?}");
        assert!((s.rate_hz - 10.0).abs() < 1e-9, "{}", s.rate_hz);
        // What the span alone gives: 4,899 intervals over 499.9 s.
        assert!(((t.len() - 1) as f64 / (t[t.len() - 1] - t[0]) - 9.8).abs() < 0.01);
    }

    #[test]
    fn jitter_is_not_a_dropout() {
        // Each stamp off by up to ±20 % of an interval (deterministic): intervals of 0.6–1.4 times
        // the nominal one.
        let t: Vec<f64> =
            (0..20_000).map(|i| i as f64 * 0.01 + 0.002 * ((i * 7_919 % 101) as f64 / 50.0 - 1.0)).collect();
        let s = sampling(&t).unwrap();
        assert!(s.gaps.is_empty() && s.irregular == 0, "{s:?}");
        assert!((s.rate_hz - 100.0).abs() < 0.01);
    }

    #[test]
    fn batched_stamps_are_irregular_not_a_thousand_dropouts() {
        // Pairs of samples 1 ms apart every 20 ms (a driver that stamps on arrival): half of the
        // intervals are 19 times the median.
        let t: Vec<f64> = (0..4_000).map(|i| (i / 2) as f64 * 0.02 + (i % 2) as f64 * 0.001).collect();
        let s = sampling(&t).unwrap();
        assert!(s.gaps.is_empty());
        assert_eq!(s.irregular, 1_999);
        assert_eq!(s.rate_hz, 3_999.0 / (t[3_999] - t[0]));
    }

    #[test]
    fn one_stamp_has_no_sampling() {
        assert_eq!(sampling(&[1.0]), None);
    }
}
