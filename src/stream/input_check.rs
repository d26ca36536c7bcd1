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
//! A motion onset therefore shows as up to `spike_max_run` samples flagged "rejected" before the
//! gate flags "moving"; both hold the last static drift, so the compensated output is the same.

use super::sample::{STATUS_GAP, STATUS_REJECTED};

/// A `seq` further than this below the last one starts a new stream (a publisher restart) rather
/// than being a late duplicate.
pub const RESTART_SEQ_BACK: u64 = 64;

/// Samples the spike test's level and spread average over (EWMA weight 1/32 after warm-up).
pub const SPIKE_MEMORY: u32 = 32;

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
}

/// The recursive spike estimate of one axis.
#[derive(Debug, Clone, Copy, Default)]
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

/// What the checks decided for one sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Verdict {
    /// Status bits to set ([`STATUS_REJECTED`], [`STATUS_GAP`]).
    pub status: u32,
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
    counters: InputCounters,
}

impl InputCheck {
    /// Checks with the given thresholds and no history.
    pub fn new(config: InputConfig) -> Self {
        Self { config, last_seq: None, last_t_ns: None, spikes: Default::default(), counters: Default::default() }
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

    /// Checks one sample (`publisher_moving`: flags bit 0). A new `seq` advances the sequence
    /// reference (a sample that arrived is no hole, whatever else is wrong with it); only a
    /// timestamp that advances moves the time reference; the spike estimates move only in
    /// [`accept_static`](Self::accept_static).
    pub fn check(&mut self, seq: u64, t_ns: u64, rate: &[f64; 3], publisher_moving: bool) -> Verdict {
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
                return Verdict { status: STATUS_REJECTED };
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
                return Verdict { status: STATUS_REJECTED | STATUS_GAP };
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
            return Verdict { status: status | STATUS_REJECTED };
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
                    return Verdict { status: status | STATUS_REJECTED };
                }
            } else {
                for s in &mut self.spikes {
                    s.run = 0;
                }
            }
        }
        Verdict { status }
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
        InputConfig { range_dps: 100.0, period_ns: PERIOD, gap_factor: 3.0, spike_z: 8.0, spike_max_run: 3 }
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
        assert_eq!(c.check(next - 1, next * PERIOD, &[0.0; 3], false).status, STATUS_REJECTED);
        assert_eq!(c.check(next, (next - 1) * PERIOD, &[0.0; 3], false).status, STATUS_REJECTED | STATUS_GAP);
        // The time reference did not move, the sequence one did: the next regular sample is clean.
        assert_eq!(c.check(next + 1, (next + 1) * PERIOD, &[0.0; 3], false).status, 0);
        let n = c.counters();
        assert_eq!((n.duplicates, n.time_backwards, n.gaps), (1, 1, 1));
    }

    #[test]
    fn a_restarted_publisher_starts_a_new_stream() {
        let mut c = InputCheck::new(config());
        warm(&mut c, 200);
        // seq and clock back to 0: accepted as a new stream, flagged as a gap.
        assert_eq!(c.check(0, 0, &[noise(0); 3], false).status, STATUS_GAP);
        assert_eq!(c.check(1, PERIOD, &[noise(1); 3], false).status, 0);
        // A late repeat close behind is still a duplicate; far behind is another restart.
        assert!(c.check(1, 2 * PERIOD, &[0.0; 3], false).rejected());
        assert_eq!(c.check(2, 2 * PERIOD, &[noise(2); 3], false).status, 0);
        warm_from(&mut c, 3, 500);
        assert_eq!(c.check(10, 0, &[noise(10); 3], false).status, STATUS_GAP);
        let n = c.counters();
        assert_eq!((n.restarts, n.duplicates, n.time_backwards), (2, 1, 0));
    }

    /// Feeds static samples `from..to` (seq and time = index).
    fn warm_from(c: &mut InputCheck, from: u64, to: u64) {
        for k in from..to {
            let r = [noise(k); 3];
            assert_eq!(c.check(k, k * PERIOD, &r, false).status, 0, "sample {k}");
            c.accept_static(&r);
        }
    }

    #[test]
    fn skipped_seq_and_time_jumps_are_gaps_of_good_samples() {
        let mut c = InputCheck::new(config());
        let next = warm(&mut c, 10);
        assert_eq!(c.check(next + 4, (next + 4) * PERIOD, &[0.0; 3], false).status, STATUS_GAP);
        assert_eq!(c.check(next + 5, (next + 50) * PERIOD, &[0.0; 3], false).status, STATUS_GAP);
        let n = c.counters();
        assert_eq!((n.seq_skipped, n.gaps, n.duplicates), (4, 2, 0));
    }

    #[test]
    fn invalid_rates_are_rejected() {
        let mut c = InputCheck::new(config());
        for (k, bad) in [f64::NAN, f64::INFINITY, -101.0].into_iter().enumerate() {
            let v = c.check(k as u64, k as u64 * PERIOD, &[0.0, bad, 0.0], false);
            assert!(v.rejected());
        }
        assert_eq!(c.counters().invalid, 3);
    }

    #[test]
    fn isolated_spikes_are_rejected_and_long_runs_pass_as_real_changes() {
        let mut c = InputCheck::new(config());
        let mut k = warm(&mut c, 200);
        // An isolated 4 deg/s spike on one axis: rejected, estimates untouched.
        assert!(c.check(k, k * PERIOD, &[noise(k), 4.0, noise(k)], false).rejected());
        k += 1;
        assert_eq!(c.check(k, k * PERIOD, &[noise(k); 3], false).status, 0);
        c.accept_static(&[noise(k); 3]);
        k += 1;
        // A step of 3 deg/s that stays: the first spike_max_run samples are rejected, then it passes.
        let verdicts: Vec<bool> =
            (0..6).map(|j| c.check(k + j, (k + j) * PERIOD, &[3.0; 3], false).rejected()).collect();
        assert_eq!(verdicts, [true, true, true, false, false, false]);
        assert_eq!(c.counters().spikes, 4);
    }

    #[test]
    fn normal_noise_and_publisher_motion_are_never_spikes() {
        let mut c = InputCheck::new(config());
        let k = warm(&mut c, 5000);
        assert_eq!(c.counters().spikes, 0);
        assert!(!c.check(k, k * PERIOD, &[50.0; 3], true).rejected());
        let off = InputConfig { spike_z: 0.0, ..config() };
        let mut c = InputCheck::new(off);
        let k = warm(&mut c, 100);
        assert!(!c.check(k, k * PERIOD, &[50.0; 3], false).rejected());
    }
}
