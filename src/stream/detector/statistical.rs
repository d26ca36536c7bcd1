//! The statistical static detector (issue 13, item 3). Per axis it tests the residual
//! r = ω − b̂ (b̂: the drift estimate for the sample, of variance P) against the axis' own
//! noise ([`NoiseCalibration`]), with one knob: the false-alarm probability α of each test.
//!
//! - **Mean shift** over each window W (default 0.5, 2, 10, 30, 60 s): the mean r̄ of the last
//!   n = min(W/T, samples since the last alarm) samples fires when r̄² > z²·(v(n) + P), z the
//!   two-sided normal quantile of α and v(n) the calibrated variance of an n-sample mean (Allan
//!   variance, so bias instability and quantisation are accounted for). Short windows catch
//!   turns at once; long ones catch slow rotations of a few σ/√n. Windows never reach back past
//!   the last alarm, so a finished motion does not keep the long windows firing.
//! - **Variance** over the last `variance_window_s` (2 s): n·s²/σ² above the χ²(n − 1) quantile
//!   of α (vibration, oscillation with zero mean).
//!
//! A sample on which any test of any axis fires is an *alarm*. Moving = an alarm, the
//! publisher's flag, or fewer than `settle_s` seconds since the last alarm of the tests
//! (hysteresis: static again only after a clean stretch). No settle follows the publisher's
//! flag: the publisher knows when its motion ends, and a tail it left out fires the tests, whose
//! alarm then starts the settle.
//!
//! **Delayed commit and look-back.** When an alarm follows a static stretch, the motion began
//! before it was found. Its start is estimated as the span with the largest normalised mean
//! statistic — the GLR change-point estimate, searched on a geometric grid of spans up to the
//! longest window — extended over the next longer windows while the older segment is itself
//! significant at the relaxed level √α (a slowly building motion, found by its strongest recent
//! part); that span plus `guard_s` of the newest pending samples are discarded; the older ones
//! are committed. A static
//! sample is otherwise committed once `max window + guard_s` seconds have followed it, so no
//! sample that a later look-back could discard has reached the estimator.
//!
//! Before the axis' noise is known (fewer than 8 sample differences), or while an axis has no
//! drift estimate of finite variance, no test can run: the windows restart and the samples are
//! taken as static (there is nothing to compare them with).

use serde::{Deserialize, Serialize};

use super::{Decision, DetectorCounters, DetectorInput, DetectorState, MotionDetector};
use crate::model::normal::{MIN_PROBABILITY, chi2_upper};

/// Longest window, settle or guard span, samples (longer ones are cut to it: at 1 kHz 17 min).
pub const MAX_WINDOW_SAMPLES: usize = 1 << 20;
/// Ratio of the geometric grid the change point of an alarm is searched on.
pub const CHANGE_POINT_GRID: f64 = 1.15;
/// Commit delay (samples) while the windows are not sized yet.
pub const UNSIZED_DELAY: usize = 63;

/// Settings of the statistical detector (`[motion]` in the configuration); none is in deg/s.
#[derive(Debug, Clone, PartialEq)]
pub struct StatisticalConfig {
    /// False-alarm probability of each test on each sample.
    pub false_alarm: f64,
    /// Mean-shift windows, seconds, ascending.
    pub windows_s: Vec<f64>,
    /// Variance-test window, seconds.
    pub variance_window_s: f64,
    /// Hysteresis: seconds after the last alarm of the tests that are still moving (none after
    /// an alarm that carried the publisher's flag).
    pub settle_s: f64,
    /// Extra pending seconds discarded before a detected onset.
    pub guard_s: f64,
    /// Deadlock breaker: seconds of "moving" found by the detector alone (no publisher flag)
    /// over which the residual stayed the same (module documentation) before the drift estimate
    /// is relearnt; 0 = never.
    pub relearn_s: f64,
}

impl Default for StatisticalConfig {
    fn default() -> Self {
        Self {
            false_alarm: 1e-5,
            windows_s: vec![0.5, 2.0, 10.0, 30.0, 60.0],
            variance_window_s: 2.0,
            settle_s: 5.0,
            guard_s: 2.0,
            relearn_s: 300.0,
        }
    }
}

impl StatisticalConfig {
    /// Checks the values; the message names the key.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.false_alarm >= MIN_PROBABILITY && self.false_alarm < 0.5) {
            return Err(format!("motion.false_alarm: {} must lie in [1e-12, 0.5)", self.false_alarm));
        }
        if self.windows_s.is_empty() || self.windows_s.len() > 16 {
            return Err("motion.windows_s: give 1 to 16 windows".into());
        }
        if self.windows_s.iter().any(|w| !(w.is_finite() && *w > 0.0 && *w <= 3600.0))
            || self.windows_s.windows(2).any(|p| p[1] <= p[0])
        {
            return Err(format!("motion.windows_s: {:?} must be ascending, each in (0, 3600] s", self.windows_s));
        }
        for (key, v) in
            [("variance_window_s", self.variance_window_s), ("settle_s", self.settle_s), ("guard_s", self.guard_s)]
        {
            if !(v.is_finite() && (0.0..=3600.0).contains(&v)) {
                return Err(format!("motion.{key}: {v} must lie in [0, 3600] s"));
            }
        }
        let longest = self.windows_s.last().copied().unwrap_or(0.0);
        if !(self.relearn_s == 0.0
            || (self.relearn_s.is_finite() && self.relearn_s >= 2.0 * longest && self.relearn_s <= 86_400.0))
        {
            return Err(format!(
                "motion.relearn_s: {} must be 0 (never) or lie in [2 × the longest window ({longest} s), 86400] s",
                self.relearn_s
            ));
        }
        Ok(())
    }
}

/// Prefix sums of r and r² since the last reset, in a ring (the window means are differences).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
struct PrefixRing {
    sum: Vec<f64>,
    sum_sq: Vec<f64>,
    head: usize,
    s: f64,
    s2: f64,
}

impl PrefixRing {
    fn with_capacity(n: usize) -> Self {
        Self { sum: vec![0.0; n], sum_sq: vec![0.0; n], ..Self::default() }
    }

    fn reset(&mut self) {
        self.s = 0.0;
        self.s2 = 0.0;
    }

    fn push(&mut self, r: f64) {
        self.s += r;
        self.s2 += r * r;
        self.head = (self.head + 1) % self.sum.len();
        self.sum[self.head] = self.s;
        self.sum_sq[self.head] = self.s2;
    }

    /// Σr and Σr² over the newest `n` samples, `n` ≤ samples since the reset and < capacity
    /// (`n` equal to the samples since the reset reads the reset's zero).
    fn window(&self, n: usize, since_reset: usize) -> (f64, f64) {
        if n >= since_reset {
            return (self.s, self.s2);
        }
        let cap = self.sum.len();
        let i = (self.head + cap - n) % cap;
        (self.s - self.sum[i], self.s2 - self.sum_sq[i])
    }
}

/// The statistical detector (module documentation).
#[derive(Debug, Clone)]
pub struct StatisticalDetector {
    config: StatisticalConfig,
    z2: f64,
    /// z² at the relaxed level √α of the look-back extension.
    z2_relaxed: f64,
    /// Window lengths in samples (empty until the period is known).
    windows: Vec<usize>,
    variance_window: usize,
    /// χ²(n − 1) upper quantiles for n = 0 … variance_window (0 where undefined).
    chi2: Vec<f64>,
    settle: usize,
    guard: usize,
    delay: usize,
    /// The longest mean window, samples.
    longest: usize,
    rings: [PrefixRing; 3],
    /// Accepted samples since the last alarm (or since start).
    since_alarm: usize,
    moving: bool,
    /// Whether the last alarm carried the publisher's flag: the publisher knows when its motion
    /// ends, so no settle follows it (a tail the tests still see is an alarm of its own).
    flagged_last: bool,
    counters: DetectorCounters,
    /// Deadlock watch over the current detector-only moving run.
    stuck: StuckWatch,
    /// Relearn after this many stable blocks (0: never).
    relearn_blocks: usize,
}

/// The deadlock watch (module documentation): the residual of a moving run that only the
/// detector sees, in blocks of the longest window. It counts the run's blocks and the latest
/// consecutive blocks whose means agree (each axis within z·√(2·v(block)) of the previous one,
/// the variance test quiet in both).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
struct StuckWatch {
    sum: [f64; 3],
    filled: usize,
    previous: Option<[f64; 3]>,
    blocks: usize,
    steady: usize,
    variance_fired: bool,
}

/// Agreeing consecutive block pairs the deadlock watch needs at the end of a long run (three
/// blocks of the longest window: 3 min by default).
pub const STEADY_BLOCKS: usize = 2;

impl StuckWatch {
    fn reset(&mut self) {
        *self = Self::default();
    }
}

/// The statistical detector's state in a snapshot: the residual windows (prefix-sum rings),
/// samples since the last alarm, the hysteresis verdict and the deadlock watch. What the
/// configuration and the period determine (window lengths, quantiles) is not stored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StatisticalState {
    rings: [PrefixRing; 3],
    since_alarm: usize,
    moving: bool,
    flagged_last: bool,
    stuck: StuckWatch,
}

impl StatisticalState {
    /// Whether every stored number is finite.
    pub fn is_finite(&self) -> bool {
        let ring = |r: &PrefixRing| r.sum.iter().chain(&r.sum_sq).chain([&r.s, &r.s2]).all(|v| v.is_finite());
        self.rings.iter().all(ring)
            && self.stuck.sum.iter().chain(self.stuck.previous.iter().flatten()).all(|v| v.is_finite())
    }
}

impl StatisticalDetector {
    /// A detector whose windows are sized once [`MotionDetector::set_period`] is called.
    pub fn new(config: StatisticalConfig) -> Self {
        Self {
            z2: chi2_upper(1.0, config.false_alarm),
            z2_relaxed: chi2_upper(1.0, config.false_alarm.sqrt()),
            config,
            windows: Vec::new(),
            variance_window: 0,
            chi2: Vec::new(),
            settle: 0,
            guard: 0,
            delay: 0,
            longest: 0,
            rings: Default::default(),
            since_alarm: 0,
            moving: false,
            flagged_last: false,
            counters: DetectorCounters::default(),
            stuck: StuckWatch::default(),
            relearn_blocks: 0,
        }
    }

    /// The settings.
    pub fn config(&self) -> &StatisticalConfig {
        &self.config
    }

    /// Whether a test fires on this sample and, if so, how far back the motion began: among all
    /// mean windows (and the whole stretch since the last alarm) of every axis, the length n with
    /// the largest normalised statistic r̄²/(v(n) + P) — the generalised-likelihood-ratio estimate
    /// of the change point, evaluated at the window lengths (a fast turn peaks at the shortest
    /// window, a slow ramp at the span it has lasted); the variance window when only the
    /// variance test fires. `n` is truncated at the last alarm.
    fn fired(&mut self, input: &DetectorInput<'_>) -> Option<usize> {
        let since = self.since_alarm;
        let mut best: Option<(f64, usize)> = None;
        let mut variance_fired = false;
        for k in 0..3 {
            let noise = &input.noise[k];
            let p = input.drift[k].variance;
            if !p.is_finite() {
                continue;
            }
            let ring = &self.rings[k];
            for n in self.windows.iter().map(|&w| w.min(since)).chain(std::iter::once(since.min(self.longest))) {
                if n == 0 {
                    continue;
                }
                let Some(v) = noise.mean_variance(n) else { continue };
                let (s, _) = ring.window(n, since);
                let mean = s / n as f64;
                let t = mean * mean / (v + p);
                if best.is_none_or(|(b, _)| t > b) {
                    best = Some((t, n));
                }
            }
            let n = self.variance_window.min(since);
            if n >= 2
                && let Some(s2) = noise.sample_variance()
            {
                let (s, ss) = ring.window(n, since);
                let scatter = ss - s * s / n as f64;
                variance_fired |= scatter / s2 > self.chi2[n];
            }
        }
        self.stuck.variance_fired |= variance_fired;
        let onset = match best {
            Some((t, _)) if t > self.z2 => {
                let n = self.change_point(input);
                if variance_fired { n.max(self.variance_window.min(since)) } else { n }
            }
            _ if variance_fired => self.variance_window.min(since),
            _ => return None,
        };
        Some(self.extend_back(input, onset))
    }

    /// The change-point estimate of an alarm: the span n (samples, on a geometric grid of ratio
    /// [`CHANGE_POINT_GRID`] from one sample to the longest window, truncated at the last alarm)
    /// that maximises the normalised mean statistic r̄²/(v(n) + P) over the axes — the GLR
    /// estimate of where a mean shift began. Run only on an alarm.
    fn change_point(&self, input: &DetectorInput<'_>) -> usize {
        let since = self.since_alarm;
        let top = since.min(self.longest).max(1);
        let mut best = (f64::NEG_INFINITY, top);
        let mut n = 1usize;
        loop {
            for k in 0..3 {
                let p = input.drift[k].variance;
                let Some(v) = input.noise[k].mean_variance(n) else { continue };
                if !p.is_finite() {
                    continue;
                }
                let mean = self.rings[k].window(n, since).0 / n as f64;
                let t = mean * mean / (v + p);
                if t > best.0 {
                    best = (t, n);
                }
            }
            if n >= top {
                break;
            }
            n = ((n as f64 * CHANGE_POINT_GRID).ceil() as usize).min(top);
        }
        best.1
    }

    /// Feeds the deadlock watch with this sample's residual; true when the drift estimate must
    /// be relearnt. Only samples that the detector alone calls moving count; samples the
    /// publisher flags are skipped (the run goes on across them), a static one ends the run.
    fn watch_for_deadlock(&mut self, input: &DetectorInput<'_>) -> bool {
        if input.publisher_moving {
            // The publisher says the platform moves: its samples say nothing about the
            // reference. The watch pauses (a deadlock persists across flagged motions).
            return false;
        }
        if self.relearn_blocks == 0 {
            return false;
        }
        if !self.moving {
            // The run ends with a clean stretch of settle_s; static samples right after the
            // publisher's flag (no settle follows it) only pause the watch, as the flag does.
            if self.since_alarm >= self.settle {
                self.stuck.reset();
            }
            return false;
        }
        for k in 0..3 {
            self.stuck.sum[k] += input.rate[k] - input.drift[k].drift;
        }
        self.stuck.filled += 1;
        if self.stuck.filled < self.longest {
            return false;
        }
        let n = self.longest as f64;
        let mean: [f64; 3] = std::array::from_fn(|k| self.stuck.sum[k] / n);
        let same = self.stuck.previous.is_some_and(|prev| {
            (0..3).all(|k| {
                input.noise[k].mean_variance(self.longest).is_some_and(|v| {
                    let d = mean[k] - prev[k];
                    d * d <= self.z2 * 2.0 * v
                })
            })
        });
        self.stuck.steady = if same && !self.stuck.variance_fired { self.stuck.steady + 1 } else { 0 };
        self.stuck.blocks += 1;
        self.stuck.previous = if self.stuck.variance_fired { None } else { Some(mean) };
        self.stuck.sum = [0.0; 3];
        self.stuck.filled = 0;
        self.stuck.variance_fired = false;
        if self.stuck.blocks < self.relearn_blocks || self.stuck.steady < STEADY_BLOCKS {
            return false;
        }
        self.counters.relearns += 1;
        self.stuck.reset();
        true
    }

    /// Extends a look-back span of `n` samples over the older windows while the segment between
    /// them is itself significant at the relaxed level √α: a motion that builds up slowly (a
    /// ramp) is found by its recent, strongest part, but began well before it; a turn after a
    /// static stretch stops at once (the older segment is static).
    fn extend_back(&self, input: &DetectorInput<'_>, mut n: usize) -> usize {
        let since = self.since_alarm;
        for &w in &self.windows {
            let w = w.min(since);
            if w <= n {
                continue;
            }
            let significant = (0..3).any(|k| {
                let p = input.drift[k].variance;
                let Some(v) = input.noise[k].mean_variance(w - n) else { return false };
                if !p.is_finite() {
                    return false;
                }
                let ring = &self.rings[k];
                let mean = (ring.window(w, since).0 - ring.window(n, since).0) / (w - n) as f64;
                mean * mean > self.z2_relaxed * (v + p)
            });
            if !significant {
                break;
            }
            n = w;
        }
        n
    }
}

impl MotionDetector for StatisticalDetector {
    fn name(&self) -> &'static str {
        "statistical"
    }

    fn push(&mut self, input: &DetectorInput<'_>) -> Decision {
        if self.windows.is_empty() {
            // Period not known yet: nothing to size the windows with.
            return Decision { moving: input.publisher_moving, flush: input.publisher_moving, ..Decision::default() };
        }
        if input.drift.iter().any(|d| !d.variance.is_finite()) {
            // No drift estimate to test against yet: a residual against an unknown bias would
            // stay in the windows and fire once one exists. Start the windows afresh instead.
            for ring in &mut self.rings {
                ring.reset();
            }
            self.since_alarm = 0;
            let flush = input.publisher_moving && !self.moving;
            self.moving = input.publisher_moving;
            return Decision { moving: self.moving, flush, ..Decision::default() };
        }
        for k in 0..3 {
            self.rings[k].push(input.rate[k] - input.drift[k].drift);
        }
        self.since_alarm += 1;
        let fired = self.fired(input);
        let was_moving = self.moving;
        let alarm = fired.is_some() || input.publisher_moving;
        if fired.is_some() {
            self.counters.alarms += 1;
        }
        let mut decision = Decision::default();
        if alarm {
            if !was_moving {
                self.counters.onsets += 1;
                // Look back: discard the span the motion is estimated to have lasted (the
                // publisher knows its own onsets: nothing to discard for a flag alone).
                if let Some(n) = fired {
                    (decision.onset, decision.discard) = (n, n + self.guard);
                }
            }
            decision.flush = !was_moving;
            for ring in &mut self.rings {
                ring.reset();
            }
            self.since_alarm = 0;
            self.moving = true;
            self.flagged_last = input.publisher_moving;
        } else if self.moving && (self.flagged_last || self.since_alarm >= self.settle) {
            self.moving = false;
        } else if self.moving {
            self.counters.settling += 1;
        }
        decision.moving = self.moving;
        decision.relearn = self.watch_for_deadlock(input);
        decision
    }

    /// Before the period is known the samples wait too (a start-up hold of
    /// `UNSIZED_DELAY` (63) samples; the period is measured within the first ten).
    fn commit_delay(&self) -> usize {
        if self.windows.is_empty() { UNSIZED_DELAY } else { self.delay }
    }

    fn set_period(&mut self, period_s: f64) {
        let samples = |s: f64| ((s / period_s).round().min(MAX_WINDOW_SAMPLES as f64) as usize).max(1);
        self.windows = self.config.windows_s.iter().map(|&w| samples(w)).collect();
        self.windows.dedup();
        self.variance_window =
            if self.config.variance_window_s > 0.0 { samples(self.config.variance_window_s).max(2) } else { 0 };
        self.chi2 = (0..=self.variance_window)
            .map(|n| if n >= 2 { chi2_upper((n - 1) as f64, self.config.false_alarm) } else { 0.0 })
            .collect();
        let span = |s: f64| (s / period_s).round().min(MAX_WINDOW_SAMPLES as f64) as usize;
        self.settle = span(self.config.settle_s);
        self.guard = span(self.config.guard_s);
        self.longest = self.windows.iter().copied().max().unwrap_or(1);
        let longest = self.longest.max(self.variance_window);
        self.delay = longest + self.guard;
        // The run's length in whole blocks of the longest window.
        self.relearn_blocks =
            if self.config.relearn_s > 0.0 { (span(self.config.relearn_s) / self.longest).max(1) } else { 0 };
        self.stuck.reset();
        self.rings = std::array::from_fn(|_| PrefixRing::with_capacity(longest + 1));
        self.since_alarm = 0;
    }

    fn counters(&self) -> DetectorCounters {
        self.counters
    }

    fn longest_window(&self) -> usize {
        self.windows.iter().copied().max().unwrap_or(1)
    }

    fn state(&self) -> DetectorState {
        DetectorState::Statistical(Box::new(StatisticalState {
            rings: self.rings.clone(),
            since_alarm: self.since_alarm,
            moving: self.moving,
            flagged_last: self.flagged_last,
            stuck: self.stuck.clone(),
        }))
    }

    fn restore_state(&mut self, state: &DetectorState) -> Result<(), String> {
        let DetectorState::Statistical(s) = state else {
            return Err(format!("a {} detector's state, not a statistical one's", state.kind().name()));
        };
        let cap = self.rings[0].sum.len();
        let fits = |r: &PrefixRing| r.sum.len() == cap && r.sum_sq.len() == cap && (cap == 0 || r.head < cap);
        if !s.rings.iter().all(fits) {
            return Err(format!(
                "motion windows: the stored residual windows hold {} samples, these settings {cap}",
                s.rings[0].sum.len()
            ));
        }
        if s.stuck.filled > self.longest {
            return Err("motion: the stored deadlock watch is longer than the longest window".into());
        }
        self.rings = s.rings.clone();
        self.since_alarm = s.since_alarm;
        self.moving = s.moving;
        self.flagged_last = s.flagged_last;
        self.stuck = s.stuck.clone();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stream::calibration::NoiseCalibration;
    use crate::stream::drift::DriftEstimate;
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};
    use rand_xoshiro::Xoshiro256PlusPlus;

    const SIGMA: f64 = 0.1;

    fn normal(rng: &mut Xoshiro256PlusPlus) -> f64 {
        StandardNormal.sample(rng)
    }

    /// A detector at 10 Hz and calibrations fed with 20,000 white samples of σ = 0.1.
    fn setup() -> (StatisticalDetector, [NoiseCalibration; 3], Xoshiro256PlusPlus) {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(42);
        let mut noise: [NoiseCalibration; 3] = Default::default();
        for i in 0..20_000 {
            for n in &mut noise {
                let x = SIGMA * normal(&mut rng);
                n.observe(x);
                n.commit(i, x);
            }
        }
        let mut d = StatisticalDetector::new(StatisticalConfig::default());
        d.set_period(0.1);
        (d, noise, rng)
    }

    fn push(d: &mut StatisticalDetector, noise: &[NoiseCalibration; 3], rate: [f64; 3], flag: bool) -> Decision {
        // A well-known bias of 0 (variance of a 10,000-sample mean).
        let e = DriftEstimate { drift: 0.0, variance: SIGMA * SIGMA / 1e4, from_model: true };
        d.push(&DetectorInput { rate: &rate, drift: &[e; 3], noise, publisher_moving: flag })
    }

    /// 70 s of white noise, every sample judged static (the windows fill).
    fn still_for_70_s(d: &mut StatisticalDetector, noise: &[NoiseCalibration; 3], rng: &mut Xoshiro256PlusPlus) {
        for _ in 0..700 {
            let r: [f64; 3] = std::array::from_fn(|_| SIGMA * normal(rng));
            assert!(!push(d, noise, r, false).moving);
        }
    }

    #[test]
    fn white_noise_raises_few_alarms_and_the_windows_are_sized_in_seconds() {
        let (mut d, noise, mut rng) = setup();
        assert_eq!(d.windows, vec![5, 20, 100, 300, 600]);
        assert_eq!((d.commit_delay(), d.longest_window()), (620, 600));
        let mut alarms = 0;
        for _ in 0..20_000 {
            let r: [f64; 3] = std::array::from_fn(|_| SIGMA * normal(&mut rng));
            alarms += push(&mut d, &noise, r, false).flush as u32;
        }
        // 18 tests a sample at α = 1e-5 (correlated): a handful over 20,000 samples at most.
        assert!(alarms <= 5, "{alarms} onsets on white noise");
    }

    #[test]
    fn a_slow_shift_is_found_and_its_span_discarded_and_a_flag_discards_nothing() {
        let (mut d, noise, mut rng) = setup();
        still_for_70_s(&mut d, &noise, &mut rng);
        // 0.05 deg/s = σ/2 per sample: invisible to one sample, clear to a 10 s mean (5σ/√100·10).
        let mut found = None;
        for i in 0..300 {
            let mut r: [f64; 3] = std::array::from_fn(|_| SIGMA * normal(&mut rng));
            r[1] += 0.05;
            let dec = push(&mut d, &noise, r, false);
            if dec.flush {
                found = Some((i, dec.discard));
                break;
            }
        }
        let (after, discard) = found.expect("the shift is found within 30 s");
        assert!(after < 200, "found after {after} samples");
        // The look-back reaches back to the shift's start (plus the 2 s guard).
        assert!(discard > after && discard <= after.max(100) * 3 + 20, "discard {discard} for a shift {after} old");
        // Hysteresis: moving until settle_s (5 s) pass without an alarm.
        let mut quiet = 0;
        while push(&mut d, &noise, [0.0; 3], false).moving {
            quiet += 1;
        }
        assert_eq!(quiet, 49);
        // The publisher's flag: moving at once, nothing discarded.
        let dec = push(&mut d, &noise, [0.0; 3], true);
        assert!(dec.moving && dec.flush && dec.discard == 0, "{dec:?}");
    }

    #[test]
    fn no_settle_follows_the_publishers_flag_but_one_follows_a_tail_it_left_out() {
        let (mut d, noise, mut rng) = setup();
        still_for_70_s(&mut d, &noise, &mut rng);
        // A flagged turn of 20 deg/s for 10 s, then still: static with the first unflagged sample.
        for _ in 0..100 {
            assert!(push(&mut d, &noise, [20.0, 0.0, 0.0], true).moving);
        }
        let r: [f64; 3] = std::array::from_fn(|_| SIGMA * normal(&mut rng));
        assert!(!push(&mut d, &noise, r, false).moving, "the publisher said the motion ended");
        // A flagged turn whose flag drops 0.5 s early: the tail fires, and the settle (5 s) runs
        // from the tail's last alarm.
        for _ in 0..100 {
            push(&mut d, &noise, [20.0, 0.0, 0.0], true);
        }
        for _ in 0..5 {
            assert!(push(&mut d, &noise, [20.0, 0.0, 0.0], false).moving);
        }
        let mut quiet = 0;
        while push(&mut d, &noise, [0.0; 3], false).moving {
            quiet += 1;
        }
        assert_eq!(quiet, 49);
    }

    #[test]
    fn a_steady_offset_for_relearn_s_relearns_once_but_a_changing_or_flagged_one_never() {
        // A wrong reference: every sample is 0.3 deg/s (3σ) off, for 15 min. The detector says
        // moving throughout; after relearn_s (300 s) with the last three 60 s blocks agreeing, it
        // asks for a relearn, then the watch starts over (here nothing relearns the reference, so
        // it asks again 300 s later).
        let (mut d, noise, mut rng) = setup();
        let mut relearnt = Vec::new();
        for i in 0..9_000 {
            let r: [f64; 3] = std::array::from_fn(|k| SIGMA * normal(&mut rng) + if k == 0 { 0.3 } else { 0.0 });
            let dec = push(&mut d, &noise, r, false);
            assert!(dec.moving || i < 5, "sample {i} static against a 3σ offset");
            if dec.relearn {
                relearnt.push(i);
            }
        }
        assert!(
            relearnt.len() == 2 && (2_990..3_010).contains(&relearnt[0]) && (5_990..6_010).contains(&relearnt[1]),
            "a relearn after each 300 s (5 blocks): {relearnt:?}"
        );
        assert_eq!(d.counters().relearns, 2);
        // A flagged motion within the run pauses the watch, it does not end the run: the relearn
        // comes 10 s later.
        let (mut d, noise, mut rng) = setup();
        let mut relearnt = Vec::new();
        for i in 0..9_000 {
            let r: [f64; 3] = std::array::from_fn(|k| SIGMA * normal(&mut rng) + if k == 0 { 0.3 } else { 0.0 });
            if push(&mut d, &noise, r, (1_000..1_100).contains(&i)).relearn {
                relearnt.push(i);
            }
        }
        assert!(
            relearnt.len() == 2 && (3_090..3_110).contains(&relearnt[0]) && (6_090..6_110).contains(&relearnt[1]),
            "{relearnt:?}"
        );
        // The same offset, but the publisher says moving throughout: never relearn.
        let (mut d, noise, mut rng) = setup();
        for _ in 0..9_000 {
            let r: [f64; 3] = std::array::from_fn(|k| SIGMA * normal(&mut rng) + if k == 0 { 0.3 } else { 0.0 });
            assert!(!push(&mut d, &noise, r, true).relearn);
        }
        // A residual that changes from block to block (a long motion: 0.3 deg/s ± 0.1 alternating
        // every minute, 20σ of a block mean) is motion, not a wrong reference.
        let (mut d, noise, mut rng) = setup();
        for i in 0..18_000 {
            let step = if (i / 600) % 2 == 0 { 0.1 } else { -0.1 };
            let r: [f64; 3] = std::array::from_fn(|k| SIGMA * normal(&mut rng) + if k == 0 { 0.3 + step } else { 0.0 });
            let dec = push(&mut d, &noise, r, false);
            assert!(dec.moving && !dec.relearn || i < 5, "sample {i}: {dec:?}");
        }
    }
}
