//! The strongest narrow spectral line of a whole part, searched coherently: one rectangular-window
//! periodogram over the part's full length.
//!
//! A stable sinusoid of likelihood-ratio evidence Λ (Λ = n·A²/(2σ²) in white noise of variance
//! σ² per sample) raises its ordinate of the full-length periodogram, in units of the local
//! noise level, to about 1 + Λ/2, while the noise ordinates stay Exp(1) (Brockwell & Davis 1991,
//! §10.2; Priestley 1981, §6.1.4, Fisher's test). The other two line statistics give some of that
//! away: the Welch line ([`super::stats`]) averages K segments, which divides the line's excess by
//! K; the slow line ([`super::fit_spectral::LineSearch`] on 1 s means) uses a Hann window, whose
//! coherent gain² of 1/4 against its noise gain of 3/8 costs a third of it, and reaches only
//! 0.5 Hz. This search keeps all of it, at lines of at least [`MIN_CYCLES`] cycles in the part,
//! where a red floor's leakage through the rectangular window's sidelobes is smooth.
//!
//! 1. Means of m samples, m = ⌈n / [`MAX_SAMPLES`]⌉ (a long or fast part is searched up to the
//!    means' Nyquist frequency, rate/(2m), so the cost stays bounded), less their least-squares
//!    line.
//! 2. The periodogram |X\[k]|² zero-padded to the power of two at least twice the means' count
//!    (a line between two natural bins loses at most 0.9 dB, against 3.9 dB unpadded).
//! 3. The background of each ordinate: the median of the ordinates in blocks of [`BLOCK_BINS`]
//!    natural bins, interpolated log-linearly between block centres (a red floor is locally a
//!    power law; a line is a few of a block's ordinates and hardly moves its median).
//! 4. The statistic: the largest ordinate over its background from [`MIN_CYCLES`] natural bins on,
//!    times ln 2 (the median of Exp(1)), so that a white floor's ordinates are Exp(1) and the
//!    largest of M independent ones lies near ln M. It is compared with the ensemble's, so the
//!    padding's correlated ordinates and the median's own scatter need no closed form.

use super::robust::{block_means, detrended};
use crate::diag::fft::RealPeriodogram;

/// Most means searched: a longer part is searched on means of several samples.
pub const MAX_SAMPLES: usize = 1 << 16;
/// Natural bins (1 / the part's duration apart) per background block.
pub const BLOCK_BINS: usize = 64;
/// Fewest cycles in the part for a candidate line: one background block up from zero.
pub const MIN_CYCLES: usize = BLOCK_BINS;

/// The strongest line of a part (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FastLine {
    /// Its ordinate over the background, × ln 2.
    pub ratio: f64,
    /// Its frequency, Hz (of the padded bin, within a quarter of a natural bin of the peak).
    pub frequency_hz: f64,
    /// Half the width of a natural bin, Hz: the bracket a refinement of the frequency searches.
    pub half_bin_hz: f64,
}

/// Samples averaged per mean for a part of `len` samples (module docs, step 1).
fn block_len(len: usize) -> usize {
    len.div_ceil(MAX_SAMPLES).max(1)
}

/// Whether a part of `len` samples is long enough for the search: at least two background blocks
/// above [`MIN_CYCLES`].
pub fn reaches(len: usize) -> bool {
    len / block_len(len) / 2 >= MIN_CYCLES + 2 * BLOCK_BINS
}

/// The search planned for parts of one length (the periodogram's plan made once, as every
/// ensemble member's part has the same length).
#[derive(Debug, Clone)]
pub struct FastLinePlan {
    /// Samples per mean.
    block_len: usize,
    /// Means per part.
    means: usize,
    periodogram: RealPeriodogram,
}

impl FastLinePlan {
    /// The plan for parts of `len` samples; `None` for a part too short ([`reaches`]).
    pub fn new(len: usize) -> Option<Self> {
        if !reaches(len) {
            return None;
        }
        let block_len = block_len(len);
        let means = len / block_len;
        let periodogram = RealPeriodogram::new((2 * means).next_power_of_two())?;
        Some(Self { block_len, means, periodogram })
    }

    /// Searches `x` (of the planned length) sampled at `rate_hz` (module docs); `None` for a part
    /// of another length or without variation.
    pub fn search(&self, x: &[f64], rate_hz: f64) -> Option<FastLine> {
        if x.len() / self.block_len != self.means {
            return None;
        }
        let y = detrended(&block_means(x, self.block_len));
        let n = y.len();
        let fs = rate_hz / self.block_len as f64;
        let power = self.periodogram.power(&y);
        let nfft = self.periodogram.len();
        let padding = nfft as f64 / n as f64;
        let block = ((BLOCK_BINS as f64 * padding).round() as usize).max(1);
        // Block medians at their centres, in logs (an empty or silent block has none).
        let mut centres = Vec::new();
        let mut levels = Vec::new();
        let mut scratch = Vec::with_capacity(block);
        for (b, chunk) in power.chunks(block).enumerate() {
            if chunk.len() < block / 2 {
                break;
            }
            scratch.clear();
            scratch.extend_from_slice(chunk);
            let mid = scratch.len() / 2;
            let (_, median, _) = scratch.select_nth_unstable_by(mid, f64::total_cmp);
            if *median > 0.0 {
                centres.push(b as f64 * block as f64 + 0.5 * (chunk.len() as f64 - 1.0));
                levels.push(median.ln());
            }
        }
        if centres.len() < 2 {
            return None;
        }
        let k_min = (MIN_CYCLES as f64 * padding).ceil() as usize;
        let mut best = (0.0, 0);
        let mut seg = 0;
        for (k, &p) in power.iter().enumerate().skip(k_min) {
            let kf = k as f64;
            while seg + 2 < centres.len() && centres[seg + 1] <= kf {
                seg += 1;
            }
            let (c0, c1) = (centres[seg], centres[seg + 1]);
            let w = ((kf - c0) / (c1 - c0)).clamp(0.0, 1.0);
            let background = ((1.0 - w) * levels[seg] + w * levels[seg + 1]).exp();
            let ratio = p / background;
            if ratio > best.0 {
                best = (ratio, k);
            }
        }
        if best.0 <= 0.0 {
            return None;
        }
        let df = fs / nfft as f64;
        Some(FastLine {
            ratio: best.0 * std::f64::consts::LN_2,
            frequency_hz: best.1 as f64 * df,
            half_bin_hz: 0.5 * fs / n as f64,
        })
    }
}

impl FastLine {
    /// Searches `x` sampled at `rate_hz` (module docs; [`FastLinePlan`] for many parts of one
    /// length); `None` for a part too short ([`reaches`]) or without variation.
    pub fn of(x: &[f64], rate_hz: f64) -> Option<FastLine> {
        FastLinePlan::new(x.len())?.search(x, rate_hz)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::rng::{Stream, StreamId};
    use std::f64::consts::TAU;

    fn white(n: usize, sigma: f64, seed: u64) -> Vec<f64> {
        let mut rng = Stream::new(seed, 0, StreamId::White);
        (0..n).map(|_| sigma * rng.normal()).collect()
    }

    /// On white noise the statistic behaves as the largest of M ≈ n/2 Exp(1) ordinates (Fisher's
    /// g-test): its mean over 40 series lies within ±3 of ln M + γ (the Gumbel mean; the padding's
    /// extra, correlated ordinates and the median's scatter raise it a little, not by a factor).
    #[test]
    fn on_white_noise_it_is_the_largest_of_exponential_ordinates() {
        let n = 20_000;
        let mean = (0..40).map(|s| FastLine::of(&white(n, 1.0, 100 + s), 10.0).unwrap().ratio).sum::<f64>() / 40.0;
        let gumbel = ((n / 2 - MIN_CYCLES) as f64).ln() + 0.5772;
        assert!((mean - gumbel).abs() < 3.0, "{mean} against {gumbel}");
    }

    /// A line of evidence Λ = n·A²/(2σ²) = 60 at 0.55 Hz (beyond the 1 s means' reach) stands at
    /// about 1 + Λ/2 = 31 (within the 0.9 dB scalloping and the noise: 18–45), and its frequency is
    /// found within a natural bin; the same series without it stays below 20.
    #[test]
    fn a_line_stands_at_half_its_evidence() {
        let (n, fs, f) = (24_000, 10.0, 0.5536);
        let amplitude = (2.0 * 60.0 / n as f64).sqrt();
        let noise = white(n, 1.0, 7);
        let x: Vec<f64> =
            noise.iter().enumerate().map(|(k, v)| v + amplitude * (TAU * f * k as f64 / fs + 0.3).sin()).collect();
        let line = FastLine::of(&x, fs).unwrap();
        assert!((18.0..45.0).contains(&line.ratio), "{}", line.ratio);
        assert!((line.frequency_hz - f).abs() < 2.0 * line.half_bin_hz, "{}", line.frequency_hz);
        assert!(FastLine::of(&noise, fs).unwrap().ratio < 20.0);
    }

    /// Under a red floor (white noise plus a rate random walk 100× the white level at the lowest
    /// frequencies) the background follows the slope: the statistic of the floor alone stays
    /// within the white-noise range, and a line on it is still found.
    #[test]
    fn a_red_floor_does_not_make_lines() {
        let (n, fs) = (30_000, 10.0);
        let mut rng = Stream::new(3, 0, StreamId::White);
        let mut walk = 0.0;
        let floor: Vec<f64> = (0..n)
            .map(|_| {
                walk += 0.02 * rng.normal();
                walk + rng.normal()
            })
            .collect();
        let alone = FastLine::of(&floor, fs).unwrap();
        assert!(alone.ratio < 20.0, "{}", alone.ratio);
        let f = 0.2;
        let amplitude = (2.0 * 80.0 / n as f64).sqrt();
        let x: Vec<f64> =
            floor.iter().enumerate().map(|(k, v)| v + amplitude * (TAU * f * k as f64 / fs).sin()).collect();
        let line = FastLine::of(&x, fs).unwrap();
        assert!(line.ratio > 25.0 && (line.frequency_hz - f).abs() < 2.0 * line.half_bin_hz, "{line:?}");
    }

    /// A part longer than [`MAX_SAMPLES`] is searched on means: a 100 Hz part of 200,000 samples
    /// on means of 4 (12.5 Hz Nyquist) still finds a 3 Hz line.
    #[test]
    fn a_long_part_is_searched_on_means() {
        let (n, fs, f) = (200_000, 100.0, 3.0);
        assert_eq!(block_len(n), 4);
        let amplitude = (2.0 * 100.0 / n as f64).sqrt();
        let x: Vec<f64> = white(n, 1.0, 11)
            .iter()
            .enumerate()
            .map(|(k, v)| v + amplitude * (TAU * f * k as f64 / fs).sin())
            .collect();
        let line = FastLine::of(&x, fs).unwrap();
        assert!((line.frequency_hz - f).abs() < 2.0 * line.half_bin_hz, "{line:?}");
    }

    #[test]
    fn a_short_part_is_not_searched() {
        assert!(!reaches(300));
        assert!(FastLine::of(&white(300, 1.0, 1), 10.0).is_none());
        assert!(reaches(400));
    }
}
