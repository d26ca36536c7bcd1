//! Fits of the effects made of events or of the value grid: bias jumps, spikes, quantisation.
//!
//! - **Bias jumps**: on 1 s means y, the difference of the means of the W blocks after and before
//!   each point, d\[i] = mean(y[i..i+W]) − mean(y[i−W..i]), W = 60 s (at most an eighth of the
//!   part). A jump of size s shows as a peak |d| ≈ |s|; the slow wander of the bias (flicker, rate
//!   random walk) does not. Peaks above [`JUMP_SIGMAS`] robust σ of d (1.4826·MAD), at least W
//!   apart, are the candidate jumps when they are steps' peaks:
//!   - the largest |d| within W on each side, with at least W/2 positions on each side;
//!   - *edge rule*: d a window before and after the peak, in its direction, at most half of it.
//!     A step's window difference is a triangle W wide on each side, down to the noise a window
//!     away; on a slope or a warm-up's flank it stays up, and a bump of the noise there is no step.
//!     A warm-up's decay makes |d| largest at the first position and falling from there: a
//!     transient whose start the detector cannot see, not a step it can place (and a step that
//!     close to the ends cannot be told from one);
//!   - *swing rule*: d does not reach the opposite sign at half the peak on both sides between W/2
//!     and 2W away. A slow bias oscillation's (a chirp's low end) alternates in sign every half
//!     period; a step's triangle stands alone;
//!   - *local level*: the peak stands above the threshold over the median of d within
//!     five windows on each side, not only over zero. On a warm-up's slow flank
//!     d sits at the slope's share everywhere, and a bump of the noise on top is no step (report
//!     case 775: a warm-up of τ 1,187 s on the quiet floor gave three such "steps").
//!
//!   Steps that come every few minutes inflate the MAD of d they are measured against, so the
//!   search runs in rounds: the steps found are removed, σ is measured again on what is left, and
//!   peaks a window away from the steps already found are added, until a round adds none (five at
//!   most). On noise alone a peak passes 3.5 σ about 0.3 times an hour, so the
//!   candidates make a step process only when there are at least k of them (the smallest k with
//!   P(Poisson(0.3·hours) ≥ k) ≤ 1 %); fewer, only those beyond
//!   [`LONE_STEP_SIGMAS`] count (the single-round threshold until the twenty-fifth session).
//!   Each step's size is the difference of the means after and before it, over a window at most
//!   and not past the neighbouring steps (a window difference at the peak would also hold a
//!   neighbour's share). The steps of the held-out part, found by the same detector on the whole
//!   recording, count towards the rate and size ([`fit_jumps`]).
//! - **Step kurtosis** ([`step_kurtosis`], a matched filter of the detector test, not a fit):
//!   many steps near the noise make the window differences heavy-tailed, which Gaussian noise of
//!   any spectrum does not; the geometric mean of their kurtosis over W of 20–120 s.
//! - **Spikes**: r\[k] = x\[k] − median(x[k−2..=k+2]); samples with |r| above [`SPIKE_SIGMAS`]
//!   robust σ of r (more on a part so long that white noise would pass that more than once:
//!   [`spike_threshold`]) that are the largest |r| within ±2 samples, when they are spread over the
//!   part as a Poisson process's events are. Outliers that crowd into some stretch of it (an
//!   index-of-dispersion test over ten segments at the 10⁻⁴ level) are the tails of noise that
//!   grew louder there, a burst, which is not in the catalogue: no spikes.
//! - **Quantisation**: the values sit on a grid when there are few distinct ones (at most a
//!   quarter of the samples) and at least 99.9 % of them are whole multiples of the smallest gap
//!   between distinct values (relative to the smallest value).

use super::params::{EffectParams, Fitted, FittedEffect};
use super::robust::{block_means, kurtosis, mad_sigma};
use crate::model::metrics::median;
use crate::model::normal::{chi2_upper, normal_quantile};

/// Threshold of a candidate jump, robust σ of the window difference (module docs).
pub const JUMP_SIGMAS: f64 = 3.5;
/// Threshold of a step that stands alone (fewer candidates than a step process needs, module
/// docs): robust σ of the window difference.
pub const LONE_STEP_SIGMAS: f64 = 4.5;
/// Reach of the local level of the window difference a candidate step must stand above, windows
/// on each side (module docs).
const LOCAL_LEVEL_WINDOWS: usize = 5;
/// Rate of false steps at [`JUMP_SIGMAS`] on noise alone, per hour: 10 candidates in the 32.6
/// hours of the independent generator's tuning controls (seeds 2380–2409, IEEE terms and
/// Gauss–Markov banks at three levels), where 2 in an hour was the most.
const FALSE_STEPS_PER_H: f64 = 0.3;
/// Chance that noise alone shows [`many_steps`] steps.
const MANY_STEPS_LEVEL: f64 = 0.01;
/// Largest share of a step's peak that the window difference may keep a window before and after
/// it (module docs): a step's difference falls to the noise there, a slope's or a warm-up's flank
/// does not.
const PEAK_EDGE_SHARE: f64 = 0.5;
/// Most detection rounds of the jump detector; each round measures the robust σ again on the
/// series with the steps found so far removed (module docs).
const JUMP_ROUNDS: usize = 5;
/// Window of the jump detector, s.
const JUMP_WINDOW_S: f64 = 60.0;
/// Windows of the step kurtosis, s ([`step_kurtosis`]).
pub const STEP_KURTOSIS_WINDOWS_S: [f64; 4] = [20.0, 40.0, 60.0, 120.0];
/// Threshold of a spike, robust σ of the residual from the 5-sample median, at least; on a longer
/// part it rises so that white noise passes it [`SPIKE_FALSE_PER_PART`] times ([`spike_threshold`]).
pub const SPIKE_SIGMAS: f64 = 5.5;
/// Samples of white noise expected beyond the spike threshold in a part ([`spike_threshold`]).
pub const SPIKE_FALSE_PER_PART: f64 = 1.0;
/// The residual from the 5-sample median of white noise, beyond 4.5 of its robust σ, is a normal
/// tail of this many robust σ (its MAD counts the fifth of the samples that are their own
/// median, r = 0; simulated on 1.6·10⁷ samples: 1.46 at 4.5, 1.49 at 5.5, 1.50 at 6–7).
pub const SPIKE_TAIL_SCALE: f64 = 1.5;
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
        let (block, y) = second_means(x, rate_hz);
        let w = window_blocks(JUMP_WINDOW_S, rate_hz, block, y.len());
        let (positions, d) = window_differences(&y, w)?;
        let sigma = mad_sigma(&d);
        (sigma > 0.0).then_some(StepScores { block, window: w, positions, d, sigma })
    }

    /// The largest |d| in robust σ: the strongest step of the series.
    pub fn strongest(&self) -> f64 {
        self.d.iter().fold(0.0, |m: f64, v| m.max(v.abs())) / self.sigma
    }
}

/// The means of `x` over blocks of about one second: samples per block, and the means.
pub(super) fn second_means(x: &[f64], rate_hz: f64) -> (usize, Vec<f64>) {
    let block = (rate_hz.round() as usize).max(1);
    (block, block_means(x, block))
}

/// A window of `window_s` seconds in blocks of `block` samples, at most an eighth of the `blocks`.
fn window_blocks(window_s: f64, rate_hz: f64, block: usize, blocks: usize) -> usize {
    ((window_s * rate_hz / block as f64).round() as usize).min(blocks / 8)
}

/// The window difference d\[i] = mean(y[i..i+w]) − mean(y[i−w..i]) of the block means `y` at
/// every position i from `w` to `y.len() − w`, with those positions; `None` when `w` < 3.
fn window_differences(y: &[f64], w: usize) -> Option<(Vec<usize>, Vec<f64>)> {
    if w < 3 || y.len() < 2 * w {
        return None;
    }
    let mut prefix = vec![0.0; y.len() + 1];
    for (i, v) in y.iter().enumerate() {
        prefix[i + 1] = prefix[i] + v;
    }
    let positions: Vec<usize> = (w..=y.len() - w).collect();
    let d = positions
        .iter()
        .map(|&i| (prefix[i + w] - prefix[i]) / w as f64 - (prefix[i] - prefix[i - w]) / w as f64)
        .collect();
    Some((positions, d))
}

/// The step kurtosis of `x` (module docs): the geometric mean, over the windows of
/// [`STEP_KURTOSIS_WINDOWS_S`] (each at most an eighth of the 1 s means, and at least 3 of them),
/// of the kurtosis of the window difference. 3 (a Gaussian's) when no window fits.
pub fn step_kurtosis(x: &[f64], rate_hz: f64) -> f64 {
    let (block, y) = second_means(x, rate_hz);
    let mut windows: Vec<usize> =
        STEP_KURTOSIS_WINDOWS_S.iter().map(|&s| window_blocks(s, rate_hz, block, y.len())).collect();
    windows.dedup();
    let logs: Vec<f64> =
        windows.iter().filter_map(|&w| window_differences(&y, w)).map(|(_, d)| kurtosis(&d).log10()).collect();
    if logs.is_empty() { 3.0 } else { 10f64.powf(logs.iter().sum::<f64>() / logs.len() as f64) }
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
    let mut jumps = match candidate_steps(train, rate_hz) {
        Ok(jumps) => jumps,
        Err(why) => return Fitted::NotApplicable(why),
    };
    // The hold-out's steps as the whole recording shows them, so that a step just past the split,
    // too close to either part's end for that part's own detector, is counted too.
    let mut held: Vec<Step> = if holdout.is_empty() {
        Vec::new()
    } else {
        let whole = [train, holdout].concat();
        candidate_steps(&whole, rate_hz).unwrap_or_default().into_iter().filter(|j| j.at >= train.len()).collect()
    };
    let hours = (train.len() + holdout.len()) as f64 / rate_hz / 3600.0;
    keep_process(&mut [&mut jumps, &mut held], hours);
    if jumps.is_empty() && held.is_empty() {
        return Fitted::NotApplicable(format!(
            "no step above {LONE_STEP_SIGMAS} robust sigma, and fewer than {} above {JUMP_SIGMAS}",
            many_steps(hours)
        ));
    }
    found_jumps(&jumps, &held, train.len(), hours)
}

/// Bias jumps at the change points `changes` (sample indices of the whole recording, ascending)
/// of a step process found by the nested test's segmentation ([`super::nested_jumps`]), for a
/// recording whose training part is `train` and hold-out `holdout`: each step's size is the
/// difference of the means after and before it (as [`fit_jumps`]' sizes, over a window at most);
/// the training part's steps make its deterministic part, all count towards rate and size.
/// `NotApplicable` when there is none.
pub fn fit_jumps_at(train: &[f64], holdout: &[f64], rate_hz: f64, changes: &[usize]) -> Fitted {
    let whole = [train, holdout].concat();
    let at: Vec<usize> = changes.iter().copied().filter(|&c| c > 0 && c < whole.len()).collect();
    if at.is_empty() {
        return Fitted::NotApplicable("the segmentation has no change point".into());
    }
    let reach = (JUMP_WINDOW_S * rate_hz).round().max(1.0) as usize;
    let steps: Vec<Step> =
        at.iter().zip(step_sizes(&whole, &at, reach)).map(|(&at, size)| Step { at, size, sigmas: 0.0 }).collect();
    let (jumps, held): (Vec<Step>, Vec<Step>) = steps.into_iter().partition(|s| s.at < train.len());
    found_jumps(&jumps, &held, train.len(), whole.len() as f64 / rate_hz / 3600.0)
}

/// The bias-jump effect of the training part's steps `jumps` and the hold-out's `held` (not both
/// empty) over a recording of `hours` whose training part has `train_len` samples.
fn found_jumps(jumps: &[Step], held: &[Step], train_len: usize, hours: f64) -> Fitted {
    let all = jumps.len() + held.len();
    let size = (jumps.iter().chain(held).map(|j| j.size * j.size).sum::<f64>() / all as f64).sqrt();
    let training_part = (!jumps.is_empty()).then(|| {
        let mut part = vec![0.0; train_len];
        let mut level = 0.0;
        let mut next = jumps.iter().peekable();
        for (k, p) in part.iter_mut().enumerate() {
            while next.peek().is_some_and(|j| j.at <= k) {
                level += next.next().map_or(0.0, |j| j.size);
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

/// A candidate step of the jump detector.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Step {
    /// Sample index.
    at: usize,
    /// Size, deg/s.
    size: f64,
    /// |d| at its peak, robust σ of the round it was found in.
    sigmas: f64,
}

/// The candidate steps of `x` above [`JUMP_SIGMAS`], found in rounds (module docs), in time
/// order; `Err` with the reason when the series is too short for the detector or constant.
fn candidate_steps(x: &[f64], rate_hz: f64) -> Result<Vec<Step>, String> {
    let Some(first) = StepScores::of(x, rate_hz) else {
        return Err("training part too short for the jump detector, or constant".into());
    };
    let (block, w) = (first.block, first.window);
    let mut found: Vec<(usize, f64)> = Vec::new();
    let mut scores = first;
    for round in 0..JUMP_ROUNDS {
        let known: Vec<usize> = found.iter().map(|f| f.0).collect();
        let new = peaks(&scores, JUMP_SIGMAS, &known);
        if new.is_empty() {
            break;
        }
        found.extend(new);
        found.sort_unstable_by_key(|f| f.0);
        if round + 1 == JUMP_ROUNDS {
            break;
        }
        let at: Vec<usize> = found.iter().map(|f| f.0).collect();
        let mut cleaned = x.to_vec();
        for (&k, s) in at.iter().zip(step_sizes(x, &at, w * block)) {
            for v in &mut cleaned[k..] {
                *v -= s;
            }
        }
        match StepScores::of(&cleaned, rate_hz) {
            Some(next) => scores = next,
            None => break,
        }
    }
    let at: Vec<usize> = found.iter().map(|f| f.0).collect();
    let sizes = step_sizes(x, &at, w * block);
    Ok(found.iter().zip(sizes).map(|(&(at, sigmas), size)| Step { at, size, sigmas }).collect())
}

/// Keeps the candidates of `parts` (the parts of one recording of `hours`) that make a step
/// process (module docs): all of them when there are at least [`many_steps`] in all, else those
/// beyond [`LONE_STEP_SIGMAS`].
fn keep_process(parts: &mut [&mut Vec<Step>], hours: f64) {
    if parts.iter().map(|p| p.len()).sum::<usize>() < many_steps(hours) {
        for part in parts.iter_mut() {
            part.retain(|s| s.sigmas > LONE_STEP_SIGMAS);
        }
    }
}

/// The fewest steps at [`JUMP_SIGMAS`] that count as a step process over `hours` of noise: the
/// smallest k with P(Poisson(λ) ≥ k) ≤ [`MANY_STEPS_LEVEL`], λ = [`FALSE_STEPS_PER_H`] · hours.
fn many_steps(hours: f64) -> usize {
    let lambda = FALSE_STEPS_PER_H * hours;
    let (mut k, mut term, mut below) = (0usize, (-lambda).exp(), 0.0);
    while 1.0 - below - term > MANY_STEPS_LEVEL {
        below += term;
        k += 1;
        term *= lambda / k as f64;
    }
    k + 1
}

/// Peaks of `scores` above `sigmas` robust σ that are steps' peaks, at least a window apart from
/// each other and from the steps `known` (sample indices), largest first: sample index and
/// |d| in robust σ.
fn peaks(scores: &StepScores, sigmas: f64, known: &[usize]) -> Vec<(usize, f64)> {
    let StepScores { block, window: w, positions, d, sigma } = scores;
    let above_local_level = |j: usize| {
        let reach = LOCAL_LEVEL_WINDOWS * w;
        let level = median(&d[j.saturating_sub(reach)..(j + reach + 1).min(d.len())]);
        (d[j] - level).abs() > sigmas * sigma
    };
    let mut order: Vec<usize> = (0..d.len())
        .filter(|&j| d[j].abs() > sigmas * sigma && is_step_peak(d, j, *w) && above_local_level(j))
        .collect();
    order.sort_by(|&a, &b| d[b].abs().total_cmp(&d[a].abs()));
    let mut found: Vec<(usize, f64)> = Vec::new();
    for j in order {
        let i = positions[j] * block;
        if found.iter().map(|f| &f.0).chain(known).all(|&k| k.abs_diff(i) >= w * block) {
            found.push((i, d[j].abs() / sigma));
        }
    }
    found
}

/// Size of each step at `at` (sample indices, ascending): the mean of `x` after it less the mean
/// before it, each over at most `reach` samples and not past the neighbouring steps.
fn step_sizes(x: &[f64], at: &[usize], reach: usize) -> Vec<f64> {
    let mean = |s: &[f64]| s.iter().sum::<f64>() / s.len().max(1) as f64;
    (0..at.len())
        .map(|i| {
            let lo = at[i].saturating_sub(reach).max(if i > 0 { at[i - 1] } else { 0 });
            let hi = (at[i] + reach).min(at.get(i + 1).copied().unwrap_or(x.len()));
            mean(&x[at[i]..hi]) - mean(&x[lo..at[i]])
        })
        .collect()
}

/// Whether the window difference `d` has a step's peak at position `j` (module docs): |d\[j]|
/// is the largest within `w` positions on each side, at least `w`/2 positions lie on each side,
/// and the differences a window away on either side, in the peak's direction, are at most
/// [`PEAK_EDGE_SHARE`] of it.
fn is_step_peak(d: &[f64], j: usize, w: usize) -> bool {
    let half = (w / 2).max(1);
    if j < half || j + half >= d.len() {
        return false;
    }
    let edge = PEAK_EDGE_SHARE * d[j].abs();
    let outward = |k: Option<usize>| k.and_then(|k| d.get(k)).is_none_or(|v| v * d[j].signum() <= edge);
    is_largest_within(d, j, w) && outward(j.checked_sub(w)) && outward(Some(j + w)) && !swings(d, j, w)
}

/// Whether the peak of `d` at `j` is a swing of an oscillation rather than a step (module docs):
/// on both sides, between half a window and two windows away, `d` reaches the opposite sign at
/// [`PEAK_EDGE_SHARE`] of the peak or beyond. A step's window difference is a lone triangle; a
/// slow bias oscillation's alternates in sign every half period.
fn swings(d: &[f64], j: usize, w: usize) -> bool {
    let against = -PEAK_EDGE_SHARE * d[j].abs();
    let opposite = |range: std::ops::Range<usize>| {
        d[range.start.min(d.len())..range.end.min(d.len())].iter().any(|v| v * d[j].signum() <= against)
    };
    let half = (w / 2).max(1);
    opposite(j.saturating_sub(2 * w)..j.saturating_sub(half)) && opposite(j + half + 1..j + 2 * w + 1)
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
    (dispersion, chi2_upper((SPIKE_SEGMENTS - 1) as f64, SPIKE_CLUSTER_LEVEL))
}

/// The spike threshold for a part of `n` samples, robust σ of the median residual (module docs):
/// [`SPIKE_SIGMAS`], or where white noise would pass that more than [`SPIKE_FALSE_PER_PART`] times
/// (a long or fast part: 22 per 100,000 samples at 5.5), the level it passes that often,
/// [`SPIKE_TAIL_SCALE`]·Φ⁻¹(1 − F/(2n)).
pub fn spike_threshold(n: usize) -> f64 {
    let tail = SPIKE_FALSE_PER_PART / (2.0 * n.max(1) as f64);
    SPIKE_SIGMAS.max(SPIKE_TAIL_SCALE * normal_quantile(1.0 - tail))
}

/// The spike candidates of a median residual `r` (module docs): the samples beyond `limit` that
/// are the largest |r| within ±2 samples.
fn spike_candidates(r: &[f64], limit: f64) -> Vec<usize> {
    (2..r.len().saturating_sub(2)).filter(|&k| r[k].abs() > limit && is_largest_within(r, k, 2)).collect()
}

/// Spikes (module docs).
pub fn fit_spikes(x: &[f64], rate_hz: f64) -> Fitted {
    let r = median5_residual(x);
    let sigma = mad_sigma(&r);
    if sigma.is_nan() || sigma <= 0.0 {
        return Fitted::NotApplicable("constant series".into());
    }
    let spikes = spike_candidates(&r, spike_threshold(x.len()) * sigma);
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
    use std::f64::consts::TAU;

    /// The steps of `x` alone as a recording (no hold-out), by sample index and size.
    fn detect_jumps(x: &[f64], rate_hz: f64) -> Result<Vec<(usize, f64)>, String> {
        let mut steps = candidate_steps(x, rate_hz)?;
        keep_process(&mut [&mut steps], x.len() as f64 / rate_hz / 3600.0);
        Ok(steps.into_iter().map(|s| (s.at, s.size)).collect())
    }

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
    fn pure_noise_rarely_shows_a_step() {
        // At 3.5 robust σ a false step is a matter of chance, about 0.3 an hour; a step process
        // needs several (three in an hour) or one beyond 4.5 σ. None in these 40 hours; at most
        // one hour in 100 may show a step process, and a lone step beyond 4.5 σ is rarer still.
        let found: Vec<usize> =
            (100..140).map(|seed| detect_jumps(&noise(36_000, seed, 0.4), 10.0).unwrap().len()).collect();
        assert!(found.iter().filter(|&&n| n > 0).count() <= 1, "{found:?}");
    }

    #[test]
    fn steps_every_few_minutes_of_a_third_of_the_noise_are_found_with_their_sizes() {
        // Eleven steps of 0.03 (a quarter of the per-sample σ 0.115, about 4.5 σ of the 60 s
        // window difference), 300 s apart, in alternating directions on 3,600 s at 10 Hz.
        let mut x = noise(36_000, 21, 0.4);
        let at: Vec<usize> = (1..=11).map(|k| k * 3_000).collect();
        let size = |k: usize| if k.is_multiple_of(2) { 0.03 } else { -0.03 };
        for (k, &i) in at.iter().enumerate() {
            for v in &mut x[i..] {
                *v += size(k);
            }
        }
        let jumps = detect_jumps(&x, 10.0).unwrap();
        assert!(jumps.len() >= 9 && jumps.len() <= 11, "{jumps:?}");
        for (i, s) in &jumps {
            let k = at.iter().position(|a| a.abs_diff(*i) <= 300).unwrap_or_else(|| panic!("{i} is no step"));
            assert!((s - size(k)).abs() < 0.012, "step {k} at {i}: {s}");
        }
        // The same noise without the steps has none.
        assert!(detect_jumps(&noise(36_000, 21, 0.4), 10.0).unwrap().is_empty());
    }

    /// The fewest steps that make a step process: P(Poisson(0.3·hours) ≥ k) ≤ 0.01.
    #[test]
    fn many_steps_is_the_poisson_tail_quantile() {
        // λ = 0.3: P(≥ 2) = 0.037, P(≥ 3) = 0.0036; λ = 0.9: P(≥ 4) = 0.013, P(≥ 5) = 0.0023.
        assert_eq!(many_steps(1.0), 3);
        assert_eq!(many_steps(3.0), 5);
        assert_eq!(many_steps(0.0), 1);
    }

    /// The step kurtosis is a Gaussian's for noise of any spectrum (white and a slow random walk
    /// here), higher with a dozen steps an hour of a third of the per-sample noise at irregular
    /// times — too small for the detector at 4.5 σ one by one — and lower for a sinusoid, whose
    /// window differences sit near its two extremes.
    #[test]
    fn the_step_kurtosis_sees_many_small_steps_and_not_coloured_noise() {
        let n = 36_000;
        let walk = noise(n, 21, 0.0008).into_iter().scan(0.0, |w, v| {
            *w += v;
            Some(*w)
        });
        let gaussian: Vec<f64> = noise(n, 22, 0.4).iter().zip(walk).map(|(v, w)| v + w).collect();
        let plain = step_kurtosis(&gaussian, 10.0);
        for plain in [plain, step_kurtosis(&noise(n, 23, 0.4), 10.0), step_kurtosis(&noise(n, 24, 0.4), 10.0)] {
            assert!((2.6..3.0).contains(&plain), "{plain}");
        }
        let at = [1_900, 4_100, 7_800, 8_900, 12_300, 15_700, 19_800, 21_000, 24_600, 29_100, 30_400, 33_500];
        let stepped: Vec<f64> = gaussian
            .iter()
            .enumerate()
            .map(|(k, v)| {
                v + at
                    .iter()
                    .enumerate()
                    .filter(|&(_, &a)| k >= a)
                    .map(|(i, _)| if i % 3 == 1 { -0.04 } else { 0.04 })
                    .sum::<f64>()
            })
            .collect();
        let with_steps = step_kurtosis(&stepped, 10.0);
        assert!(with_steps > 3.3, "{with_steps}");
        let sine: Vec<f64> =
            gaussian.iter().enumerate().map(|(k, v)| v + 0.05 * (k as f64 / 10.0 / 240.0 * TAU).sin()).collect();
        let line = step_kurtosis(&sine, 10.0);
        assert!(line < 2.0, "{line}");
    }

    /// On a warm-up's slow flank (τ 1,200 s) the window difference sits at the slope's share
    /// (about 1.5 σ here) for the first half hour, and bumps of the noise on top pass 3.5 σ (two
    /// of these ten hours, at 227 s and 1,192 s, measured against zero); over their local level
    /// they are no steps (the local-level rule).
    #[test]
    fn bumps_on_a_slow_flank_are_no_steps() {
        for seed in 11..21 {
            let warm: Vec<f64> = noise(36_000, seed, 0.4)
                .iter()
                .enumerate()
                .map(|(k, v)| v + 0.2 * (-(k as f64) / 10.0 / 1_200.0).exp())
                .collect();
            let on_flank: Vec<Step> =
                candidate_steps(&warm, 10.0).unwrap().into_iter().filter(|s| s.at < 18_000).collect();
            assert!(on_flank.is_empty(), "seed {seed}: {on_flank:?}");
        }
    }

    #[test]
    fn a_warm_up_is_not_a_jump_but_a_step_near_the_start_is() {
        // A warm-up moves |d| past the threshold at the first positions, but |d| is largest at
        // the first one and falls from there: no step's peak, and none on its flank (dominant
        // report cases 767 and 777 were named bias_jumps for such a "step"). On a slower flank
        // (200 s) a bump of the noise can make a local peak, but the difference a window away
        // stays above half of it, so it is no step's (the edge rule).
        for time_constant_s in [60.0, 100.0, 200.0] {
            let warm: Vec<f64> = noise(36_000, 11, 0.4)
                .iter()
                .enumerate()
                .map(|(k, v)| v + 0.3 * (-(k as f64) / 10.0 / time_constant_s).exp())
                .collect();
            let scores = StepScores::of(&warm, 10.0).unwrap();
            assert!(scores.strongest() > LONE_STEP_SIGMAS, "{}", scores.strongest());
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
        // χ²₉ exceeded with probability 10⁻⁴ (scipy.stats.chi2.isf(1e-4, 9)).
        assert!((limit / 33.719_948_438_964_636 - 1.0).abs() < 1e-12, "{limit}");
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

    /// On Gaussian white noise the threshold keeps the false spikes to about one per part, where
    /// 5.5 robust σ lets through 22 per 100,000 samples; spikes of 8 σ are all found.
    #[test]
    fn spikes_in_a_long_part_are_not_outnumbered_by_the_noise_tails() {
        use crate::sim::rng::{Stream, StreamId};
        let n = 400_000;
        let mut rng = Stream::new(17, 0, StreamId::White);
        let mut x: Vec<f64> = (0..n).map(|_| rng.normal()).collect();
        let count = |x: &[f64], sigmas: f64| {
            let r = median5_residual(x);
            spike_candidates(&r, sigmas * mad_sigma(&r)).len()
        };
        assert!(count(&x, SPIKE_SIGMAS) > 40, "the fixed threshold's false spikes: {}", count(&x, SPIKE_SIGMAS));
        assert!(count(&x, spike_threshold(n)) <= 4, "{}", count(&x, spike_threshold(n)));
        for k in 0..40 {
            x[5_000 + k * 9_871] += if k % 2 == 0 { 8.0 } else { -8.0 };
        }
        let Fitted::Found(e) = fit_spikes(&x, 100.0) else { panic!() };
        let EffectParams::Spikes { detected, size_dps, .. } = e.params else { panic!() };
        assert!((40..=44).contains(&detected), "{detected}");
        assert!((size_dps - 8.0).abs() < 1.0, "{size_dps}");
        // The threshold rises with the part's length, and never below SPIKE_SIGMAS.
        assert_eq!(spike_threshold(1_000), SPIKE_SIGMAS);
        assert!(
            spike_threshold(10_000) < spike_threshold(100_000) && spike_threshold(100_000) < spike_threshold(1_000_000)
        );
    }

    #[test]
    fn finds_a_grid_and_only_a_grid() {
        let x: Vec<f64> = noise(5000, 5, 1.0).iter().map(|v| (v / 0.005).round() * 0.005 + 0.4).collect();
        let step = detect_grid(&x).unwrap();
        assert!((step - 0.005).abs() < 1e-12, "{step}");
        assert_eq!(detect_grid(&noise(5000, 6, 1.0)), None);
    }
}
