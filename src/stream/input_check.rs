//! Input checks of the [`Pipeline`](super::Pipeline) before a sample may touch any buffer: the
//! sequence number, the timestamp, the value range and a robust spike test (issue 7 "bad samples").
//!
//! Verdicts, in the order they are tested:
//! - **publisher restart** (`seq` = 0 after a non-zero `seq`, or more than [`RESTART_SEQ_BACK`]
//!   below the last one): a new stream — a restarted INS process or a new replay — whose clock may
//!   restart too. The sequence and time references are reset, the sample is flagged as a gap
//!   (bit 3) and checked like any other; counted in [`InputCounters::restarts`];
//! - **duplicate / out-of-order `seq`** (`seq` ≤ the last one, at most [`RESTART_SEQ_BACK`]
//!   below it): rejected (status bit 2), counted in [`InputCounters::duplicates`];
//! - **time going backwards** (`t_ns` ≤ the latest accepted `t_ns`): rejected and flagged as a gap
//!   (bits 2 and 3), counted in [`InputCounters::time_backwards`];
//! - **skipped `seq`** (`seq` > last + 1): the sample is good, flagged as a gap (bit 3), the missing
//!   count added to [`InputCounters::seq_skipped`];
//! - **gap in time** (step above `gap_factor` nominal periods): flagged (bit 3), the sample is good;
//! - **invalid rate** (NaN, ±∞, |rate| > `range_dps` on any axis): rejected (bit 2), counted in
//!   [`InputCounters::invalid`];
//! - **spike**: on any axis, `|x − level| > spike_z · 1.2533 · spread`, where `level` and `spread`
//!   are exponentially weighted means (over ~[`SPIKE_MEMORY`] samples) of the accepted static raw
//!   values and of their absolute deviations from `level` (1.2533 = √(π/2) turns a mean absolute
//!   deviation into σ for Gaussian noise). A recursive Hampel-type test: rejected samples never
//!   update the estimates, so a burst of outliers cannot widen its own acceptance band. At most
//!   `spike_max_run` consecutive outliers are rejected as spikes (bit 2, [`InputCounters::spikes`]);
//!   a longer run is a real change (motion or a bias step) and goes on to the motion gate. The
//!   test is skipped while the publisher flags motion and during the first [`SPIKE_MEMORY`] static
//!   samples (no estimate yet). `spike_z = 0` turns it off.
//!
//! - **saturated** (|rate| within [`SATURATION_TOLERANCE`] of `range_dps` on any axis: the
//!   sensor clips there, the true rate is unknown): rejected and flagged as a sensor fault
//!   (bits 2 and 4), counted in [`InputCounters::saturated`];
//! - **stuck** (one axis has repeated a bit-identical value for `stuck_s` seconds of timestamps
//!   or longer, after having varied since the stream began): rejected and flagged as a sensor
//!   fault (bits 2 and 4) until the value changes, counted in [`InputCounters::stuck`]. The
//!   verdict names the sample index where the run began ([`Verdict::stuck_since`]) so that the
//!   pipeline discards the run's pending samples: no part of a stuck run reaches the drift
//!   estimator as long as the detector's commit delay exceeds `stuck_s` (the statistical
//!   detector's does, 62 s by default; the threshold gate commits at once). An axis that has not
//!   changed since the first sample is taken as absent (a recording without that column), not
//!   stuck. The spike estimates, which the run's first seconds narrowed, start afresh. A real
//!   noisy MEMS gyro never repeats a value for seconds: the longest runs on the
//!   ADIS16405 recordings are a few samples (docs/design.md);
//!
//! A motion onset therefore shows as up to `spike_max_run` samples flagged "rejected" before the
//! gate flags "moving"; both hold the last static drift, so the compensated output is the same.

use serde::{Deserialize, Serialize};

use super::sample::{STATUS_GAP, STATUS_REJECTED, STATUS_SENSOR_FAULT};

/// A `seq` further than this below the last one starts a new stream (a publisher restart) rather
/// than being a late duplicate.
pub const RESTART_SEQ_BACK: u64 = 64;

/// Samples the spike test's level and spread average over (EWMA weight 1/32 after warm-up).
pub const SPIKE_MEMORY: u32 = 32;

/// A rate within this fraction of `range_dps` of the range is saturated (0.1 % of full scale:
/// a couple of LSB of a 12-bit sensor; a clipping sensor repeats its full-scale code).
pub const SATURATION_TOLERANCE: f64 = 1e-3;

/// Plausible temperatures, °C: outside (or ±∞) the temperature is ignored for that sample and
/// counted ([`InputCounters::bad_temperature`]); NaN means "none" and is not counted.
pub const TEMPERATURE_RANGE_C: (f64, f64) = (-100.0, 200.0);

/// √(π/2): σ per unit mean absolute deviation of Gaussian noise.
const MAD_MEAN_TO_SIGMA: f64 = 1.253_314_137_315_500_3;

/// Thresholds of the input checks (`[input]` in the configuration).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputConfig {
    /// Largest accepted |rate|, deg/s (the sensor's range).
    pub range_dps: f64,
    /// Nominal sample period, ns (0: not known yet, no gap test).
    pub period_ns: u64,
    /// A t_ns step above `gap_factor · period_ns` is a gap.
    pub gap_factor: f64,
    /// Spike threshold in σ of the recent static samples (0 = no spike test).
    pub spike_z: f64,
    /// Longest run of consecutive outliers rejected as spikes; a longer run is a real change.
    pub spike_max_run: u32,
    /// Seconds of bit-identical values on one axis after which it is stuck (0 = no test).
    pub stuck_s: f64,
}

impl Default for InputConfig {
    /// The configuration's defaults; the period not known yet.
    fn default() -> Self {
        Self { range_dps: 2000.0, period_ns: 0, gap_factor: 3.0, spike_z: 8.0, spike_max_run: 3, stuck_s: 2.0 }
    }
}

impl InputConfig {
    /// Checks the thresholds (not the period, which comes from `input.rate_hz` or is measured);
    /// the message names the key.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.range_dps > 0.0 && self.range_dps.is_finite()) {
            return Err(format!("input.range_dps: {} must be positive and finite", self.range_dps));
        }
        if !(self.gap_factor > 1.0 && self.gap_factor.is_finite()) {
            return Err(format!("input.gap_factor: {} must be finite and above 1", self.gap_factor));
        }
        if !(self.spike_z >= 0.0 && self.spike_z.is_finite()) || (self.spike_z > 0.0 && self.spike_z < 3.0) {
            return Err(format!("input.spike_z: {} must be 0 (off) or a finite value of at least 3", self.spike_z));
        }
        if !(self.stuck_s == 0.0 || (0.1..=3600.0).contains(&self.stuck_s)) {
            return Err(format!("input.stuck_s: {} must be 0 (off) or lie in [0.1, 3600] s", self.stuck_s));
        }
        Ok(())
    }
}

/// Counts of what the input checks found (totals since start).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct InputCounters {
    /// NaN, infinite or out-of-range rates.
    pub invalid: u64,
    /// Spikes rejected by the robust outlier test.
    pub spikes: u64,
    /// Samples whose `seq` repeated or went backwards.
    pub duplicates: u64,
    /// Samples whose timestamp did not advance.
    pub time_backwards: u64,
    /// Sequence numbers missing between accepted samples (sum of the holes).
    pub seq_skipped: u64,
    /// Gaps flagged (missing `seq`, timestamp jumps, timestamps going backwards, restarts).
    pub gaps: u64,
    /// Publisher restarts (a new stream: `seq` back to 0 or far back).
    pub restarts: u64,
    /// Samples rejected because an axis was stuck (repeating one value for `stuck_s`).
    pub stuck: u64,
    /// Samples rejected because an axis was saturated (at the range).
    pub saturated: u64,
    /// Temperatures ignored as ±∞ or implausible ([`TEMPERATURE_RANGE_C`]).
    pub bad_temperature: u64,
}

/// The recursive spike estimate of one axis.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
struct SpikeEstimate {
    level: f64,
    spread: f64,
    seen: u32,
    run: u32,
}

impl SpikeEstimate {
    fn is_outlier(&self, x: f64, z: f64) -> bool {
        self.seen >= SPIKE_MEMORY && (x - self.level).abs() > z * MAD_MEAN_TO_SIGMA * self.spread
    }

    /// Folds in an accepted static sample (cumulative means while warming up, then EWMA).
    fn update(&mut self, x: f64) {
        self.seen = (self.seen + 1).min(SPIKE_MEMORY);
        let w = 1.0 / f64::from(self.seen);
        let deviation = (x - self.level).abs();
        self.level += w * (x - self.level);
        if self.seen > 1 {
            self.spread += w * (deviation - self.spread);
        }
    }
}

/// The current run of bit-identical values of one axis.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
struct ValueRun {
    /// `f64::to_bits` of the value (meaningful once `seen`).
    bits: u64,
    /// Timestamp and sample index of the run's first sample.
    start_t_ns: u64,
    start_index: u64,
    seen: bool,
    /// The axis has changed value at least once (a never-changing axis is absent, not stuck).
    varied: bool,
}

impl ValueRun {
    /// Extends or restarts the run with `x`; true when it has lasted `stuck_ns` (> 0) or longer.
    fn push(&mut self, x: f64, t_ns: u64, index: u64, stuck_ns: u64) -> bool {
        let bits = x.to_bits();
        if !self.seen || bits != self.bits {
            self.varied |= self.seen;
            *self = Self { bits, start_t_ns: t_ns, start_index: index, seen: true, varied: self.varied };
            return false;
        }
        stuck_ns > 0 && self.varied && t_ns.saturating_sub(self.start_t_ns) >= stuck_ns
    }
}

/// The input checks' state in a snapshot: sequence and time references, spike estimates and
/// the value runs of the stuck test (counters and thresholds are not part of it).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct InputState {
    last_seq: Option<u64>,
    last_t_ns: Option<u64>,
    spikes: [SpikeEstimate; 3],
    runs: [ValueRun; 3],
}

impl InputState {
    /// Whether the spike estimates are finite.
    pub fn is_finite(&self) -> bool {
        self.spikes.iter().all(|s| s.level.is_finite() && s.spread.is_finite())
    }
}

/// What the checks decided for one sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Verdict {
    /// Status bits to set ([`STATUS_REJECTED`], [`STATUS_GAP`], [`STATUS_SENSOR_FAULT`]).
    pub status: u32,
    /// Stuck sensor: the index of the first sample of the stuck run (the earliest over the
    /// stuck axes); its pending samples must be discarded.
    pub stuck_since: Option<u64>,
}

impl Verdict {
    fn of(status: u32) -> Self {
        Self { status, stuck_since: None }
    }
}

impl Verdict {
    /// True when the sample must not enter any buffer.
    pub fn rejected(self) -> bool {
        self.status & STATUS_REJECTED != 0
    }
}

/// Stateful input checks for three axes; allocation-free.
#[derive(Debug, Clone)]
pub struct InputCheck {
    config: InputConfig,
    last_seq: Option<u64>,
    last_t_ns: Option<u64>,
    spikes: [SpikeEstimate; 3],
    runs: [ValueRun; 3],
    counters: InputCounters,
}

impl InputCheck {
    /// Checks with the given thresholds and no history.
    pub fn new(config: InputConfig) -> Self {
        Self {
            config,
            last_seq: None,
            last_t_ns: None,
            spikes: Default::default(),
            runs: Default::default(),
            counters: Default::default(),
        }
    }

    /// A copy of the state the next verdicts depend on, for a snapshot.
    pub fn state(&self) -> InputState {
        InputState { last_seq: self.last_seq, last_t_ns: self.last_t_ns, spikes: self.spikes, runs: self.runs }
    }

    /// Restores what [`InputCheck::state`] copied (thresholds and counters are kept).
    pub fn restore(&mut self, state: &InputState) {
        (self.last_seq, self.last_t_ns, self.spikes, self.runs) =
            (state.last_seq, state.last_t_ns, state.spikes, state.runs);
    }

    /// The temperature to use for an accepted sample: `temp_c` when it is NaN (none) or
    /// plausible ([`TEMPERATURE_RANGE_C`]); otherwise NaN, counted in
    /// [`InputCounters::bad_temperature`].
    pub fn temperature(&mut self, temp_c: f64) -> f64 {
        let (lo, hi) = TEMPERATURE_RANGE_C;
        if temp_c.is_nan() || (lo..=hi).contains(&temp_c) {
            return temp_c;
        }
        self.counters.bad_temperature += 1;
        f64::NAN
    }

    /// Applies new thresholds from the next sample on; the history is kept.
    pub fn reconfigure(&mut self, config: InputConfig) {
        self.config = config;
    }

    /// The thresholds.
    pub fn config(&self) -> &InputConfig {
        &self.config
    }

    /// Counters so far.
    pub fn counters(&self) -> InputCounters {
        self.counters
    }

    /// True when `rate` is finite and within the sensor range.
    pub fn in_range(&self, rate: f64) -> bool {
        rate.is_finite() && rate.abs() <= self.config.range_dps
    }

    /// Checks one sample (`index`: the pipeline's sample index, `publisher_moving`: flags bit
    /// 0). A new `seq` advances the sequence reference (a sample that arrived is no hole,
    /// whatever else is wrong with it); only a timestamp that advances moves the time reference;
    /// the spike estimates move only in [`accept_static`](Self::accept_static).
    pub fn check(&mut self, index: u64, seq: u64, t_ns: u64, rate: &[f64; 3], publisher_moving: bool) -> Verdict {
        let mut status = 0;
        if let Some(last) = self.last_seq
            && ((seq == 0 && last > 0) || seq + RESTART_SEQ_BACK < last)
        {
            self.counters.restarts += 1;
            self.last_seq = None;
            self.last_t_ns = None;
            status |= STATUS_GAP;
        }
        if let Some(last) = self.last_seq {
            if seq <= last {
                self.counters.duplicates += 1;
                return Verdict::of(STATUS_REJECTED);
            }
            if seq > last + 1 {
                self.counters.seq_skipped += seq - last - 1;
                status |= STATUS_GAP;
            }
        }
        self.last_seq = Some(seq);
        if let Some(prev) = self.last_t_ns {
            if t_ns <= prev {
                self.counters.time_backwards += 1;
                self.counters.gaps += 1;
                return Verdict::of(STATUS_REJECTED | STATUS_GAP);
            }
            // Period 0: not known yet ("auto" before the first steps are measured).
            let limit = self.config.gap_factor * self.config.period_ns as f64;
            if self.config.period_ns > 0 && (t_ns - prev) as f64 > limit {
                status |= STATUS_GAP;
            }
        }
        self.last_t_ns = Some(t_ns);
        if status & STATUS_GAP != 0 {
            self.counters.gaps += 1;
        }
        if !rate.iter().all(|&r| self.in_range(r)) {
            self.counters.invalid += 1;
            return Verdict::of(status | STATUS_REJECTED);
        }
        let stuck_ns = (self.config.stuck_s * 1e9) as u64;
        let mut stuck_since: Option<u64> = None;
        for (run, &r) in self.runs.iter_mut().zip(rate) {
            if run.push(r, t_ns, index, stuck_ns) {
                stuck_since = Some(stuck_since.map_or(run.start_index, |s| s.min(run.start_index)));
            }
        }
        let full_scale = self.config.range_dps * (1.0 - SATURATION_TOLERANCE);
        if rate.iter().any(|r| r.abs() >= full_scale) {
            self.counters.saturated += 1;
            return Verdict { status: status | STATUS_REJECTED | STATUS_SENSOR_FAULT, stuck_since };
        }
        if stuck_since.is_some() {
            self.counters.stuck += 1;
            // The run's first stuck_s seconds narrowed the spike estimates: they start afresh.
            self.spikes = Default::default();
            return Verdict { status: status | STATUS_REJECTED | STATUS_SENSOR_FAULT, stuck_since };
        }
        if self.config.spike_z > 0.0 && !publisher_moving {
            let z = self.config.spike_z;
            let outlier = self.spikes.iter().zip(rate).any(|(s, &r)| s.is_outlier(r, z));
            if outlier {
                let run = self.spikes[0].run + 1;
                for s in &mut self.spikes {
                    s.run = run;
                }
                if run <= self.config.spike_max_run {
                    self.counters.spikes += 1;
                    return Verdict::of(status | STATUS_REJECTED);
                }
            } else {
                for s in &mut self.spikes {
                    s.run = 0;
                }
            }
        }
        Verdict::of(status)
    }

    /// Folds an accepted static sample into the spike estimates (call only for samples that
    /// passed [`check`](Self::check) and the motion gate).
    pub fn accept_static(&mut self, rate: &[f64; 3]) {
        for (s, &r) in self.spikes.iter_mut().zip(rate) {
            s.update(r);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const PERIOD: u64 = 10_000_000;

    fn config() -> InputConfig {
        InputConfig {
            range_dps: 100.0,
            period_ns: PERIOD,
            gap_factor: 3.0,
            spike_z: 8.0,
            spike_max_run: 3,
            stuck_s: 2.0,
        }
    }

    /// Deterministic noise with σ ≈ 0.1: a sum of three incommensurate sines.
    fn noise(k: u64) -> f64 {
        let t = k as f64;
        0.08 * (t * 1.7).sin() + 0.06 * (t * 2.9 + 1.0).sin() + 0.05 * (t * 0.37 + 2.0).sin()
    }

    /// Feeds `n` static samples (seq and time = index from 0) and returns the next seq.
    fn warm(c: &mut InputCheck, n: u64) -> u64 {
        warm_from(c, 0, n);
        n
    }

    #[test]
    fn duplicates_and_backward_time_are_rejected_without_moving_the_references() {
        let mut c = InputCheck::new(config());
        let next = warm(&mut c, 10);
        assert_eq!(c.check(0, next - 1, next * PERIOD, &[0.0; 3], false).status, STATUS_REJECTED);
        assert_eq!(c.check(0, next, (next - 1) * PERIOD, &[0.0; 3], false).status, STATUS_REJECTED | STATUS_GAP);
        // The time reference did not move, the sequence one did: the next regular sample is clean.
        assert_eq!(c.check(0, next + 1, (next + 1) * PERIOD, &[0.0; 3], false).status, 0);
        let n = c.counters();
        assert_eq!((n.duplicates, n.time_backwards, n.gaps), (1, 1, 1));
    }

    #[test]
    fn a_restarted_publisher_starts_a_new_stream() {
        let mut c = InputCheck::new(config());
        warm(&mut c, 200);
        // seq and clock back to 0: accepted as a new stream, flagged as a gap.
        assert_eq!(c.check(0, 0, 0, &[noise(0); 3], false).status, STATUS_GAP);
        assert_eq!(c.check(0, 1, PERIOD, &[noise(1); 3], false).status, 0);
        // A late repeat close behind is still a duplicate; far behind is another restart.
        assert!(c.check(0, 1, 2 * PERIOD, &[0.0; 3], false).rejected());
        assert_eq!(c.check(0, 2, 2 * PERIOD, &[noise(2); 3], false).status, 0);
        warm_from(&mut c, 3, 500);
        assert_eq!(c.check(0, 10, 0, &[noise(10); 3], false).status, STATUS_GAP);
        let n = c.counters();
        assert_eq!((n.restarts, n.duplicates, n.time_backwards), (2, 1, 0));
    }

    /// Feeds static samples `from..to` (seq and time = index).
    fn warm_from(c: &mut InputCheck, from: u64, to: u64) {
        for k in from..to {
            let r = [noise(k); 3];
            assert_eq!(c.check(0, k, k * PERIOD, &r, false).status, 0, "sample {k}");
            c.accept_static(&r);
        }
    }

    #[test]
    fn skipped_seq_and_time_jumps_are_gaps_of_good_samples() {
        let mut c = InputCheck::new(config());
        let next = warm(&mut c, 10);
        assert_eq!(c.check(0, next + 4, (next + 4) * PERIOD, &[0.0; 3], false).status, STATUS_GAP);
        assert_eq!(c.check(0, next + 5, (next + 50) * PERIOD, &[0.0; 3], false).status, STATUS_GAP);
        let n = c.counters();
        assert_eq!((n.seq_skipped, n.gaps, n.duplicates), (4, 2, 0));
    }

    #[test]
    fn invalid_rates_are_rejected() {
        let mut c = InputCheck::new(config());
        for (k, bad) in [f64::NAN, f64::INFINITY, -101.0].into_iter().enumerate() {
            let v = c.check(0, k as u64, k as u64 * PERIOD, &[0.0, bad, 0.0], false);
            assert!(v.rejected());
        }
        assert_eq!(c.counters().invalid, 3);
    }

    #[test]
    fn isolated_spikes_are_rejected_and_long_runs_pass_as_real_changes() {
        let mut c = InputCheck::new(config());
        let mut k = warm(&mut c, 200);
        // An isolated 4 deg/s spike on one axis: rejected, estimates untouched.
        assert!(c.check(0, k, k * PERIOD, &[noise(k), 4.0, noise(k)], false).rejected());
        k += 1;
        assert_eq!(c.check(0, k, k * PERIOD, &[noise(k); 3], false).status, 0);
        c.accept_static(&[noise(k); 3]);
        k += 1;
        // A step of 3 deg/s that stays: the first spike_max_run samples are rejected, then it passes.
        let verdicts: Vec<bool> =
            (0..6).map(|j| c.check(0, k + j, (k + j) * PERIOD, &[3.0; 3], false).rejected()).collect();
        assert_eq!(verdicts, [true, true, true, false, false, false]);
        assert_eq!(c.counters().spikes, 4);
    }

    #[test]
    fn normal_noise_and_publisher_motion_are_never_spikes() {
        let mut c = InputCheck::new(config());
        let k = warm(&mut c, 5000);
        assert_eq!(c.counters().spikes, 0);
        assert!(!c.check(0, k, k * PERIOD, &[50.0; 3], true).rejected());
        let off = InputConfig { spike_z: 0.0, ..config() };
        let mut c = InputCheck::new(off);
        let k = warm(&mut c, 100);
        assert!(!c.check(0, k, k * PERIOD, &[50.0; 3], false).rejected());
    }
}
