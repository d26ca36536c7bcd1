//! Fits of the effects made of events or of the value grid: bias jumps, spikes, quantisation.
//!
//! - **Bias jumps**: on 1 s means y, the difference of the means of the W blocks after and before
//!   each point, d\[i] = mean(y[i..i+W]) − mean(y[i−W..i]), W = 60 s (at most an eighth of the
//!   part). A jump of size s shows as a peak |d| ≈ |s|; the slow wander of the bias (flicker, rate
//!   random walk) does not. Peaks above [`JUMP_SIGMAS`] robust σ of d (1.4826·MAD), at least W
//!   apart, are the jumps, when they are steps' peaks: the largest |d| within W on each side, with
//!   at least W/2 positions on each side. A warm-up's decay makes |d| largest at the first
//!   position and falling from there: a transient whose start the detector cannot see, not a step
//!   it can place (and a step that close to the ends cannot be told from one), and its flank is
//!   not a peak of its own (on a slow flank a bump of the noise still can be). The steps of the
//!   held-out part, found by the same detector on the whole recording, count towards the rate
//!   and size ([`fit_jumps`]).
//! - **Spikes**: r\[k] = x\[k] − median(x[k−2..=k+2]); samples with |r| above [`SPIKE_SIGMAS`]
//!   robust σ of r that are the largest |r| within ±2 samples, when they are spread over the
//!   part as a Poisson process's events are. Outliers that crowd into some stretch of it (an
//!   index-of-dispersion test over ten segments at the 10⁻⁴ level) are the tails of noise that
//!   grew louder there, a burst, which is not in the catalogue: no spikes.
//! - **Quantisation**: the values sit on a grid when there are few distinct ones (at most a
//!   quarter of the samples) and at least 99.9 % of them are whole multiples of the smallest gap
//!   between distinct values (relative to the smallest value).

use super::params::{EffectParams, Fitted, FittedEffect};
use super::robust::{block_means, mad_sigma};
use crate::diag::allan::chi_square_quantile;

/// Threshold of a jump, robust σ of the window difference.
pub const JUMP_SIGMAS: f64 = 4.5;
/// Window of the jump detector, s.
const JUMP_WINDOW_S: f64 = 60.0;
/// Threshold of a spike, robust σ of the residual from the 5-sample median.
pub const SPIKE_SIGMAS: f64 = 5.5;
/// Segments of the spikes' homogeneity test ([`time_dispersion`]).
const SPIKE_SEGMENTS: usize = 10;
/// Level of the spikes' homogeneity test: outliers that cluster in time beyond it are a change of
/// the noise level (a burst of noise), not a spike process.
const SPIKE_CLUSTER_LEVEL: f64 = 1e-4;
/// Largest share of distinct values on a grid.
const GRID_MAX_DISTINCT: f64 = 0.25;
/// Share of distinct values that must sit on the grid.
const GRID_MIN_ON: f64 = 0.999;

/// The window differences of the jump detector (module docs) of one series.
#[derive(Debug, Clone, PartialEq)]
pub struct StepScores {
    /// Samples per block (about one second).
    pub block: usize,
    /// Window, blocks.
    pub window: usize,
    /// Block index of each difference.
    pub positions: Vec<usize>,
    /// The differences d, deg/s.
    pub d: Vec<f64>,
    /// Robust σ of d (1.4826·MAD).
    pub sigma: f64,
}

impl StepScores {
    /// The window differences of `x`; `None` when fewer than 3 blocks fit in a window or `x` is
    /// constant.
    pub fn of(x: &[f64], rate_hz: f64) -> Option<StepScores> {
        let block = (rate_hz.round() as usize).max(1);
        let y = block_means(x, block);
        let w = ((JUMP_WINDOW_S * rate_hz / block as f64).round() as usize).min(y.len() / 8);
        if w < 3 {
            return None;
        }
        let mut prefix = vec![0.0; y.len() + 1];
        for (i, v) in y.iter().enumerate() {
            prefix[i + 1] = prefix[i] + v;
        }
        let positions: Vec<usize> = (w..=y.len() - w).collect();
        let d: Vec<f64> = positions
            .iter()
            .map(|&i| (prefix[i + w] - prefix[i]) / w as f64 - (prefix[i] - prefix[i - w]) / w as f64)
            .collect();
        let sigma = mad_sigma(&d);
        (sigma > 0.0).then_some(StepScores { block, window: w, positions, d, sigma })
    }

    /// The largest |d| in robust σ: the strongest step of the series.
    pub fn strongest(&self) -> f64 {
        self.d.iter().fold(0.0, |m: f64, v| m.max(v.abs())) / self.sigma
    }
}

/// Bias jumps of a recording's training part `train`, their rate and size counted over the
/// held-out rest `holdout` too (module docs; `holdout` empty for a series with none): the
/// training part's steps are those the detector finds on it alone, the hold-out's those it finds
/// on the whole recording past the training part's end (so a step just past the split counts).
///
/// A jump process is a point process: where its steps fall cannot be predicted, only how often
/// and how large they are. A recording whose few steps all fall in the hold-out part would give a
/// rate of zero from the training part, and the hold-out's step would stay a gap no effect
/// explains. So the events of both parts are counted, as the nested tests judge presence on the
/// whole recording; the training part's steps alone are the deterministic part the noise is
/// refitted without. For this effect the hold-out is therefore not out of sample for the rate:
/// what it still checks is everything else (the steps' sizes, and that nothing else changed).
pub fn fit_jumps(train: &[f64], holdout: &[f64], rate_hz: f64) -> Fitted {
    let jumps = match detect_jumps(train, rate_hz) {
        Ok(jumps) => jumps,
        Err(why) => return Fitted::NotApplicable(why),
    };
    // The hold-out's steps as the whole recording shows them, so that a step just past the split,
    // too close to either part's end for that part's own detector, is counted too.
    let held: Vec<(usize, f64)> = if holdout.is_empty() {
        Vec::new()
    } else {
        let whole = [train, holdout].concat();
        detect_jumps(&whole, rate_hz).unwrap_or_default().into_iter().filter(|j| j.0 >= train.len()).collect()
    };
    if jumps.is_empty() && held.is_empty() {
        return Fitted::NotApplicable(format!("no step above {JUMP_SIGMAS} robust sigma"));
    }
    let hours = (train.len() + holdout.len()) as f64 / rate_hz / 3600.0;
    let all = jumps.len() + held.len();
    let size = (jumps.iter().chain(&held).map(|j| j.1 * j.1).sum::<f64>() / all as f64).sqrt();
    let training_part = (!jumps.is_empty()).then(|| {
        let mut part = vec![0.0; train.len()];
        let mut level = 0.0;
        let mut next = jumps.iter().peekable();
        for (k, p) in part.iter_mut().enumerate() {
            while next.peek().is_some_and(|j| j.0 <= k) {
                level += next.next().map_or(0.0, |j| j.1);
            }
            *p = level;
        }
        part
    });
    Fitted::Found(FittedEffect {
        params: EffectParams::BiasJumps { rate_per_h: all as f64 / hours, size_dps: size, detected: all },
        training_part,
    })
}

/// The steps of `x` (module docs), by sample index and size in time order; `Err` with the reason
/// when the series is too short for the detector or constant.
fn detect_jumps(x: &[f64], rate_hz: f64) -> Result<Vec<(usize, f64)>, String> {
    let Some(StepScores { block, window: w, positions, d, sigma }) = StepScores::of(x, rate_hz) else {
        return Err("training part too short for the jump detector, or constant".into());
    };
    let mut order: Vec<usize> =
        (0..d.len()).filter(|&j| d[j].abs() > JUMP_SIGMAS * sigma && is_step_peak(&d, j, w)).collect();
    order.sort_by(|&a, &b| d[b].abs().total_cmp(&d[a].abs()));
    let mut jumps: Vec<(usize, f64)> = Vec::new();
    for j in order {
        let i = positions[j];
        if jumps.iter().all(|&(k, _)| k.abs_diff(i * block) >= w * block) {
            jumps.push((i * block, d[j]));
        }
    }
    jumps.sort_by_key(|j| j.0);
    Ok(jumps)
}

/// Whether the window difference `d` has a step's peak at position `j` (module docs): |d\[j]|
/// is the largest within `w` positions on each side, and at least `w`/2 positions lie on each
/// side.
fn is_step_peak(d: &[f64], j: usize, w: usize) -> bool {
    let half = (w / 2).max(1);
    if j < half || j + half >= d.len() {
        return false;
    }
    is_largest_within(d, j, w)
}

/// Whether |`v`\[k]| is the largest |v| within `reach` positions on each side (as far as `v` goes).
fn is_largest_within(v: &[f64], k: usize, reach: usize) -> bool {
    let peak = v[k].abs();
    v[k.saturating_sub(reach)..(k + reach + 1).min(v.len())].iter().all(|x| x.abs() <= peak)
}

/// Residual of each sample from the median of its 5-sample neighbourhood (0 at the two ends).
fn median5_residual(x: &[f64]) -> Vec<f64> {
    let mut r = vec![0.0; x.len()];
    for k in 2..x.len().saturating_sub(2) {
        let mut w = [x[k - 2], x[k - 1], x[k], x[k + 1], x[k + 2]];
        w.sort_unstable_by(f64::total_cmp);
        r[k] = x[k] - w[2];
    }
    r
}

/// The dispersion of event times `at` (sample indices of a series of `len` samples) over
/// [`SPIKE_SEGMENTS`] equal segments, Σ (cᵢ − c̄)² / c̄, and its limit for a homogeneous Poisson
/// process: the χ² quantile with [`SPIKE_SEGMENTS`] − 1 degrees of freedom at 1 −
/// [`SPIKE_CLUSTER_LEVEL`] (Fisher's index-of-dispersion test; Cox & Lewis 1966, §6.3).
fn time_dispersion(at: &[usize], len: usize) -> (f64, f64) {
    let mut counts = [0.0; SPIKE_SEGMENTS];
    for &k in at {
        counts[(k * SPIKE_SEGMENTS / len.max(1)).min(SPIKE_SEGMENTS - 1)] += 1.0;
    }
    let mean = at.len() as f64 / SPIKE_SEGMENTS as f64;
    let dispersion = counts.iter().map(|c| (c - mean) * (c - mean)).sum::<f64>() / mean;
    (dispersion, chi_square_quantile(1.0 - SPIKE_CLUSTER_LEVEL, (SPIKE_SEGMENTS - 1) as f64))
}

/// Spikes (module docs).
pub fn fit_spikes(x: &[f64], rate_hz: f64) -> Fitted {
    let r = median5_residual(x);
    let sigma = mad_sigma(&r);
    if sigma.is_nan() || sigma <= 0.0 {
        return Fitted::NotApplicable("constant series".into());
    }
    let limit = SPIKE_SIGMAS * sigma;
    let spikes: Vec<usize> =
        (2..x.len().saturating_sub(2)).filter(|&k| r[k].abs() > limit && is_largest_within(&r, k, 2)).collect();
    if spikes.is_empty() {
        return Fitted::NotApplicable(format!("no sample beyond {SPIKE_SIGMAS} robust sigma"));
    }
    let (dispersion, limit) = time_dispersion(&spikes, x.len());
    if dispersion > limit {
        return Fitted::NotApplicable(format!(
            "the {} outliers cluster in time (dispersion {dispersion:.0} over {SPIKE_SEGMENTS} segments, \
             above {limit:.1}): the noise level changes, these are not spikes",
            spikes.len()
        ));
    }
    let hours = x.len() as f64 / rate_hz / 3600.0;
    let size = spikes.iter().map(|&k| r[k].abs()).sum::<f64>() / spikes.len() as f64;
    let mut part = vec![0.0; x.len()];
    for &k in &spikes {
        part[k] = r[k];
    }
    Fitted::Found(FittedEffect {
        params: EffectParams::Spikes {
            rate_per_h: spikes.len() as f64 / hours,
            size_dps: size,
            detected: spikes.len(),
        },
        training_part: Some(part),
    })
}

/// The grid step of the values of `x`, when they sit on one (module docs).
pub fn detect_grid(x: &[f64]) -> Option<f64> {
    let scale = x.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
    if x.len() < 16 || scale.is_nan() || scale <= 0.0 {
        return None;
    }
    let tol = 1e-9 * scale;
    let mut sorted = x.to_vec();
    sorted.sort_unstable_by(f64::total_cmp);
    let mut distinct: Vec<f64> = Vec::new();
    for v in sorted {
        if distinct.last().is_none_or(|&last| v - last > tol) {
            distinct.push(v);
        }
    }
    if distinct.len() < 3 || distinct.len() as f64 > GRID_MAX_DISTINCT * x.len() as f64 {
        return None;
    }
    let smallest = distinct.windows(2).map(|w| w[1] - w[0]).fold(f64::INFINITY, f64::min);
    let span = distinct[distinct.len() - 1] - distinct[0];
    let step = span / (span / smallest).round();
    let on = distinct
        .iter()
        .filter(|&&v| {
            let k = (v - distinct[0]) / step;
            (k - k.round()).abs() < 1e-3
        })
        .count();
    (on as f64 >= GRID_MIN_ON * distinct.len() as f64).then_some(step)
}

/// Quantisation: the grid step of the values, when there is one.
pub fn fit_quantization(x: &[f64]) -> Fitted {
    match detect_grid(x) {
        Some(step_dps) => {
            Fitted::Found(FittedEffect { params: EffectParams::Quantization { step_dps }, training_part: None })
        }
        None => Fitted::NotApplicable("the values are not on a grid".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn noise(n: usize, seed: u64, amplitude: f64) -> Vec<f64> {
        let mut state = seed;
        (0..n)
            .map(|_| {
                state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                amplitude * ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5)
            })
            .collect()
    }

    #[test]
    fn finds_jumps_and_their_sizes() {
        let mut x = noise(36_000, 1, 0.4);
        for (k, v) in x.iter_mut().enumerate() {
            *v += if k >= 10_000 { 0.08 } else { 0.0 } + if k >= 25_000 { -0.05 } else { 0.0 };
        }
        let Fitted::Found(e) = fit_jumps(&x, &[], 10.0) else { panic!() };
        let EffectParams::BiasJumps { detected, size_dps, .. } = e.params else { panic!() };
        assert_eq!(detected, 2);
        assert!((size_dps - ((0.08f64.powi(2) + 0.05f64.powi(2)) / 2.0).sqrt()).abs() < 0.01);
        let part = e.training_part.unwrap();
        assert!(part[5_000].abs() < 1e-12 && (part[20_000] - 0.08).abs() < 0.01);
        assert!(matches!(fit_jumps(&noise(36_000, 2, 0.4), &[], 10.0), Fitted::NotApplicable(_)));
    }

    #[test]
    fn a_warm_up_is_not_a_jump_but_a_step_near_the_start_is() {
        // A 100 s warm-up moves |d| well past the threshold at the first positions, but |d| is
        // largest at the first one and falls from there: no step's peak, and none on its flank
        // (dominant report cases 767 and 777 were named bias_jumps for such a "step"). On a slower
        // flank (200 s here) a bump of the noise can still make a peak of its own: a limit.
        for time_constant_s in [60.0, 100.0] {
            let warm: Vec<f64> = noise(36_000, 11, 0.4)
                .iter()
                .enumerate()
                .map(|(k, v)| v + 0.3 * (-(k as f64) / 10.0 / time_constant_s).exp())
                .collect();
            let scores = StepScores::of(&warm, 10.0).unwrap();
            assert!(scores.strongest() > 1.5 * JUMP_SIGMAS, "{}", scores.strongest());
            let found = fit_jumps(&warm, &[], 10.0);
            assert!(matches!(found, Fitted::NotApplicable(_)), "{time_constant_s} s: {found:?}");
        }
        // A step 100 s in (40 window positions, past half a window) is still placed.
        let mut step = noise(36_000, 12, 0.4);
        for v in step.iter_mut().skip(1_000) {
            *v += 0.08;
        }
        let Fitted::Found(e) = fit_jumps(&step, &[], 10.0) else { panic!() };
        assert!(matches!(e.params, EffectParams::BiasJumps { detected: 1, .. }), "{:?}", e.params);
        let part = e.training_part.unwrap();
        assert!(part[900].abs() < 1e-12 && (part[1_100] - 0.08).abs() < 0.01);
    }

    #[test]
    fn a_step_in_the_holdout_counts_towards_the_rate_but_not_the_training_part() {
        let train = noise(36_000, 13, 0.4);
        let mut holdout = noise(15_000, 14, 0.4);
        for v in holdout.iter_mut().skip(6_000) {
            *v += 0.08;
        }
        assert!(matches!(fit_jumps(&train, &[], 10.0), Fitted::NotApplicable(_)));
        let Fitted::Found(e) = fit_jumps(&train, &holdout, 10.0) else { panic!() };
        let EffectParams::BiasJumps { detected, size_dps, rate_per_h } = e.params else { panic!() };
        assert_eq!(detected, 1);
        assert!((size_dps - 0.08).abs() < 0.01, "{size_dps}");
        // One step in 5,100 s.
        assert!((rate_per_h - 3600.0 / 5_100.0).abs() < 1e-9, "{rate_per_h}");
        // No step of the training part to refit the noise without.
        assert!(e.training_part.is_none());
        // A training step is the training part's, whatever the hold-out holds.
        let mut stepped = [train.as_slice(), holdout.as_slice()].concat();
        for v in stepped.iter_mut().skip(20_000) {
            *v -= 0.08;
        }
        let (stepped, holdout) = stepped.split_at(train.len());
        let Fitted::Found(e) = fit_jumps(stepped, holdout, 10.0) else { panic!() };
        assert!(matches!(e.params, EffectParams::BiasJumps { detected: 2, .. }), "{:?}", e.params);
        let part = e.training_part.unwrap();
        assert_eq!(part.len(), stepped.len());
        assert!(part[19_000].abs() < 1e-12 && (part[21_000] + 0.08).abs() < 0.01);
        // A step just past the split, too close to both parts' ends for their own detectors, is
        // counted from the whole recording.
        let mut early = noise(15_000, 17, 0.4);
        for v in early.iter_mut().skip(300) {
            *v += 0.08;
        }
        assert!(matches!(fit_jumps(&early, &[], 10.0), Fitted::NotApplicable(_)));
        let Fitted::Found(e) = fit_jumps(&train, &early, 10.0) else { panic!() };
        assert!(matches!(e.params, EffectParams::BiasJumps { detected: 1, .. }), "{:?}", e.params);
        // A hold-out with no step adds nothing.
        assert!(matches!(fit_jumps(&train, &early[..200], 10.0), Fitted::NotApplicable(_)));
    }

    #[test]
    fn outliers_crowded_into_a_burst_of_noise_are_not_spikes() {
        // Four times the noise over a fifth of the series: its tails pass the spike threshold by
        // the hundred, all inside the burst.
        let mut burst = noise(40_000, 15, 0.4);
        for v in &mut burst[10_000..18_000] {
            *v *= 4.0;
        }
        let found = fit_spikes(&burst, 10.0);
        assert!(matches!(&found, Fitted::NotApplicable(why) if why.contains("cluster")), "{found:?}");
        // Spikes as many, spread over the series, are spikes.
        let mut spread = noise(40_000, 16, 0.4);
        for k in (0..200).map(|i| 100 + i * 199) {
            spread[k] += 2.0;
        }
        let Fitted::Found(e) = fit_spikes(&spread, 10.0) else { panic!() };
        assert!(matches!(e.params, EffectParams::Spikes { detected: 200, .. }), "{:?}", e.params);
    }

    #[test]
    fn the_dispersion_limit_is_the_chi_square_quantile_and_an_even_spread_has_none() {
        let even: Vec<usize> = (0..100).map(|i| i * 10).collect();
        let (dispersion, limit) = time_dispersion(&even, 1_000);
        assert!(dispersion.abs() < 1e-12);
        // χ²₉ at 1 − 10⁻⁴ is 33.72 (scipy.stats.chi2.ppf); Wilson–Hilferty gives 34.15 this far
        // out in the tail, 1.3 % above: a slightly stricter test.
        assert!((limit - 33.72).abs() < 0.03 * 33.72 && limit >= 33.72, "{limit}");
        // All in one segment: (n − n/10)²/(n/10) + 9 (n/10) = 9 n.
        let (dispersion, _) = time_dispersion(&[5; 20], 1_000);
        assert!((dispersion - 180.0).abs() < 1e-9, "{dispersion}");
    }

    #[test]
    fn finds_spikes() {
        let mut x = noise(20_000, 3, 0.4);
        for k in [100, 5000, 12345] {
            x[k] += 2.0;
        }
        let Fitted::Found(e) = fit_spikes(&x, 10.0) else { panic!() };
        assert!(matches!(e.params, EffectParams::Spikes { detected: 3, .. }), "{:?}", e.params);
        assert!(matches!(fit_spikes(&noise(20_000, 4, 0.4), 10.0), Fitted::NotApplicable(_)));
    }

    #[test]
    fn finds_a_grid_and_only_a_grid() {
        let x: Vec<f64> = noise(5000, 5, 1.0).iter().map(|v| (v / 0.005).round() * 0.005 + 0.4).collect();
        let step = detect_grid(&x).unwrap();
        assert!((step - 0.005).abs() < 1e-12, "{step}");
        assert_eq!(detect_grid(&noise(5000, 6, 1.0)), None);
    }
}
