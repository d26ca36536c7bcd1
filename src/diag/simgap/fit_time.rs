//! Fits of the effects that are functions of time or temperature: warm-up, ramp, temperature.
//! All work on the training part with t = k/f_s from its first sample.

use super::params::{EffectParams, Fitted, FittedEffect};
use super::robust::{block_means, linear_fit};

/// Time constants tried for the warm-up.
const WARMUP_GRID: usize = 56;
/// The warm-up grid spans duration/300 … the duration of the part: a warm-up of a quarter of an
/// hour or more in a one-hour part is an exponential with T near the part's length, which a grid
/// ending at duration/3 pinned to its edge and then lost to the ramp (issue 16, failure 4).
/// Whether such a slow exponential or a ramp describes the recording is left to the hold-out
/// part, where the two predictions differ (the ranking by both parts' gaps).
pub const WARMUP_RANGE: (f64, f64) = (1.0 / 300.0, 1.0);
/// Smallest temperature range (°C) over the training part for a temperature fit.
const MIN_TEMPERATURE_RANGE_C: f64 = 0.05;

/// Samples per block of about one second (at least one sample).
fn second_blocks(rate_hz: f64) -> usize {
    (rate_hz.round() as usize).max(1)
}

/// Centre time of each block of `block` samples, s.
fn block_times(blocks: usize, block: usize, rate_hz: f64) -> Vec<f64> {
    (0..blocks).map(|i| (i * block) as f64 / rate_hz + (block - 1) as f64 / (2.0 * rate_hz)).collect()
}

/// Warm-up `A·e^(−t/T)` (plus an offset): for each T of a log grid (duration/300 … duration),
/// A and the offset by least squares on 1 s means; the T with the smallest residual wins.
/// Returns (A deg/s, T s), or `None` for fewer than 10 s of data. ([`WarmupPlan`] for many parts
/// of one length.)
pub fn warmup_fit(x: &[f64], rate_hz: f64) -> Option<(f64, f64)> {
    WarmupPlan::new(x.len(), rate_hz)?.fit(x)
}

/// The warm-up fit ([`warmup_fit`]) planned for parts of one length: the grid's exponentials,
/// centred, and their sums of squares depend only on the part's length and rate, so every
/// ensemble member's part is fitted against the same ones, computed once (the same numbers, to
/// the bit, as computing them per part).
#[derive(Debug, Clone)]
pub struct WarmupPlan {
    len: usize,
    block: usize,
    /// (T, e^(−t/T) less its mean over the blocks, their sum of squares) per grid point.
    grid: Vec<(f64, Vec<f64>, f64)>,
}

impl WarmupPlan {
    /// The plan for parts of `len` samples at `rate_hz`; `None` for fewer than 10 s of data.
    pub fn new(len: usize, rate_hz: f64) -> Option<Self> {
        let block = second_blocks(rate_hz);
        let blocks = len / block;
        if blocks < 10 {
            return None;
        }
        let t = block_times(blocks, block, rate_hz);
        let duration = len as f64 / rate_hz;
        let (lo, hi) = (duration * WARMUP_RANGE.0, duration * WARMUP_RANGE.1);
        let grid = (0..WARMUP_GRID)
            .map(|g| {
                let tc = lo * (hi / lo).powf(g as f64 / (WARMUP_GRID - 1) as f64);
                let u: Vec<f64> = t.iter().map(|&s| (-s / tc).exp()).collect();
                let um = u.iter().sum::<f64>() / u.len() as f64;
                let centred: Vec<f64> = u.iter().map(|a| a - um).collect();
                let suu = centred.iter().fold(0.0, |acc, c| acc + c * c);
                (tc, centred, suu)
            })
            .collect();
        Some(Self { len, block, grid })
    }

    /// The fit of `x` (of the planned length; `None` otherwise): (A deg/s, T s).
    pub fn fit(&self, x: &[f64]) -> Option<(f64, f64)> {
        if x.len() != self.len {
            return None;
        }
        let y = block_means(x, self.block);
        let ym = y.iter().sum::<f64>() / y.len() as f64;
        let mut best = (f64::NEG_INFINITY, 0.0, self.grid[0].0);
        for (tc, centred, suu) in &self.grid {
            let suy = centred.iter().zip(&y).fold(0.0, |acc, (c, b)| acc + c * (b - ym));
            // Residual = Syy − Suy²/Suu: the largest explained part wins.
            if *suu > 0.0 && suy * suy / suu > best.0 {
                best = (suy * suy / suu, suy / suu, *tc);
            }
        }
        Some((best.1, best.2))
    }
}

/// Whether a fitted warm-up time constant is the grid's longest, the length of the part of
/// `part_samples` samples at `rate_hz` ([`warmup_fit`]): the data do not bound it, and over the
/// part the exponential is a ramp whose curvature the fit cannot pin (the ranking then prefers the
/// ramp, [`super::greedy::ramp_before_unbounded_warmup`]).
pub fn warmup_unbounded(time_constant_s: f64, part_samples: usize, rate_hz: f64) -> bool {
    let longest = part_samples as f64 / rate_hz * WARMUP_RANGE.1;
    time_constant_s >= longest * (1.0 - 1e-9)
}

/// Warm-up (see [`warmup_fit`]), with its shape on the training samples.
pub fn fit_warmup(x: &[f64], rate_hz: f64) -> Fitted {
    let Some((amplitude, tc)) = warmup_fit(x, rate_hz) else {
        return Fitted::NotApplicable("training part shorter than 10 s".into());
    };
    let part = (0..x.len()).map(|k| amplitude * (-(k as f64) / rate_hz / tc).exp()).collect();
    Fitted::Found(FittedEffect {
        params: EffectParams::Warmup { amplitude_dps: amplitude, time_constant_s: tc },
        training_part: Some(part),
    })
}

/// Ramp: the least-squares slope of the rate against time.
pub fn fit_ramp(x: &[f64], rate_hz: f64) -> Fitted {
    let t: Vec<f64> = (0..x.len()).map(|k| k as f64 / rate_hz).collect();
    let (slope, _) = linear_fit(&t, x);
    Fitted::Found(FittedEffect {
        params: EffectParams::Ramp { dps_per_s: slope },
        training_part: Some(t.iter().map(|s| slope * s).collect()),
    })
}

/// The change (deg/s) of the least-squares line of the 1 s means of `x` over the part's duration:
/// the ramp's matched filter (the slope of [`fit_ramp`] on block means, times the duration), so its
/// scale does not depend on the part's length; 0 for fewer than two blocks.
pub fn ramp_change(x: &[f64], rate_hz: f64) -> f64 {
    let block = second_blocks(rate_hz);
    let y = block_means(x, block);
    if y.len() < 2 {
        return 0.0;
    }
    let t = block_times(y.len(), block, rate_hz);
    linear_fit(&t, &y).0 * x.len() as f64 / rate_hz
}

/// Least-squares slope (deg/s per °C) of 1 s means of `x` on 1 s means of `temp_c` (same length).
pub fn temperature_slope(x: &[f64], temp_c: &[f64], rate_hz: f64) -> f64 {
    let block = second_blocks(rate_hz);
    linear_fit(&block_means(temp_c, block), &block_means(x, block)).0
}

/// Temperature: the least-squares slope of 1 s rate means on 1 s temperature means, around the
/// training mean temperature.
pub fn fit_temperature(x: &[f64], temp_c: &[f64], rate_hz: f64) -> Fitted {
    let temp = &temp_c[..x.len().min(temp_c.len())];
    let (lo, hi) = temp.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
    if (hi - lo).is_nan() || hi - lo < MIN_TEMPERATURE_RANGE_C {
        return Fitted::NotApplicable(format!(
            "temp_c varies by {:.3} °C on the training part (less than {MIN_TEMPERATURE_RANGE_C} °C)",
            (hi - lo).max(0.0)
        ));
    }
    let slope = temperature_slope(&x[..temp.len()], temp, rate_hz);
    let reference = temp.iter().sum::<f64>() / temp.len() as f64;
    Fitted::Found(FittedEffect {
        params: EffectParams::Temperature { dps_per_c: slope, reference_c: reference },
        training_part: Some(temp.iter().map(|c| slope * (c - reference)).collect()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(f: Fitted) -> EffectParams {
        match f {
            Fitted::Found(e) => e.params,
            Fitted::NotApplicable(why) => panic!("not applicable: {why}"),
        }
    }

    #[test]
    fn recovers_a_clean_warmup_ramp_and_temperature() {
        let fs = 10.0;
        let n = 30_000;
        let t: Vec<f64> = (0..n).map(|k| k as f64 / fs).collect();
        let warm: Vec<f64> = t.iter().map(|s| 0.3 + 0.05 * (-s / 300.0).exp()).collect();
        let EffectParams::Warmup { amplitude_dps, time_constant_s } = params(fit_warmup(&warm, fs)) else { panic!() };
        assert!((amplitude_dps - 0.05).abs() < 2e-3 && (time_constant_s / 300.0 - 1.0).abs() < 0.05);

        let ramp: Vec<f64> = t.iter().map(|s| 0.1 + 2e-6 * s).collect();
        assert_eq!(params(fit_ramp(&ramp, fs)), EffectParams::Ramp { dps_per_s: params_slope(&ramp, fs) });

        let temp: Vec<f64> = t.iter().map(|s| 25.0 + (s / 500.0).sin()).collect();
        let rate: Vec<f64> = temp.iter().map(|c| 0.2 + 0.01 * (c - 25.0)).collect();
        let EffectParams::Temperature { dps_per_c, .. } = params(fit_temperature(&rate, &temp, fs)) else { panic!() };
        assert!((dps_per_c - 0.01).abs() < 1e-9);
        assert!(matches!(fit_temperature(&rate, &vec![25.0; n], fs), Fitted::NotApplicable(_)));
    }

    #[test]
    fn ramp_change_is_the_change_over_the_part_at_any_rate_and_length() {
        // A line of 0.02 deg/s over the part, at 10 Hz and 100 Hz and over two lengths: the
        // statistic is the line's change, not its slope, so it compares parts of any length.
        for (fs, seconds) in [(10.0, 3_000.0), (100.0, 600.0), (10.0, 777.7)] {
            let n = (fs * seconds) as usize;
            let x: Vec<f64> = (0..n).map(|k| -0.4 + 0.02 * k as f64 / n as f64).collect();
            let change = ramp_change(&x, fs);
            assert!((change - 0.02).abs() < 2e-4, "{fs} Hz, {seconds} s: {change}");
            let flat = vec![0.3; n];
            assert!(ramp_change(&flat, fs).abs() < 1e-12);
            let down: Vec<f64> = x.iter().map(|v| -v).collect();
            assert!((ramp_change(&down, fs) + change).abs() < 1e-12);
        }
        assert_eq!(ramp_change(&[0.1; 15], 10.0), 0.0, "one 1 s block has no line");
    }

    fn params_slope(x: &[f64], fs: f64) -> f64 {
        let EffectParams::Ramp { dps_per_s } = params(fit_ramp(x, fs)) else { panic!() };
        assert!((dps_per_s - 2e-6).abs() < 1e-12);
        dps_per_s
    }
}
