//! The motion-injected protocol (docs/design.md "Evaluation protocols: motion-injected"): a known
//! motion profile is added to a static recording (`gyrocomp motion`), so the truth is the profile;
//! a compensator should remove the drift and leave the rotation. Pure numerics: it scores
//! compensated series and computes the two baselines that need no pipeline.
//!
//! Scores of one compensated series c against the truth m (per model):
//! - `rate_rmse_dps` = √(mean over the run of (c − m)²);
//! - the angle error of a span = |Σ (c_i − m_i)·Δt_i| over its samples, Δt_i = t_i − t_{i−1}
//!   (each rate is held over the interval that ends at its sample, as an INS integrates it; the
//!   first sample takes the first interval), in degrees;
//! - `angle_err_deg_median`, `angle_err_deg_p95`, `angle_err_deg_max` over the motion segments
//!   (maximal runs of `moving` = 1; quantiles interpolated as numpy's default), `None` without a
//!   segment; `angle_err_deg_run` over the whole run.
//!
//! Baselines computed here:
//! - **bias-hold**: raw minus the mean of the start-up window, the first `startup_s` seconds of
//!   the run but no further than the first motion (an INS aligns while it stands still);
//! - **highpass**: the causal first-order (RC) high-pass of the raw rate,
//!   `y_i = a_i·(y_{i−1} + x_i − x_{i−1})`, `a_i = RC/(RC + Δt_i)`, `RC = 1/(2π f_c)`, `y_0 = 0`
//!   (the backward-Euler discretisation of the RC filter; it starts at rest, i.e. it takes the
//!   first sample for bias). Its DC gain is 0, so it removes any constant bias — and gives back
//!   every net rotation after the motion ends.

use std::f64::consts::PI;
use std::fmt;
use std::ops::Range;

use serde::Serialize;

use crate::model::metrics::{quantile, rmse};

/// Why a motion run cannot be built or a baseline computed.
#[derive(Debug, Clone, PartialEq)]
pub enum MotionError {
    /// The series have different lengths.
    Lengths(String),
    /// Fewer than two samples.
    TooShort(usize),
    /// A value is NaN or infinite; the message names the series and the index.
    NonFinite(String),
    /// Time does not strictly increase at this index.
    Time(usize),
    /// A setting is out of range.
    Invalid(String),
}

impl fmt::Display for MotionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Lengths(m) | Self::NonFinite(m) | Self::Invalid(m) => f.write_str(m),
            Self::TooShort(n) => write!(f, "the motion protocol needs at least 2 samples, the run has {n}"),
            Self::Time(i) => write!(f, "time does not increase at sample {i}"),
        }
    }
}

impl std::error::Error for MotionError {}

/// A motion-injected run: time, raw rate (recording + profile), truth (the profile) and the
/// moving flags, with the integration steps and the motion segments derived from them.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionRun {
    t_s: Vec<f64>,
    raw: Vec<f64>,
    truth: Vec<f64>,
    dt: Vec<f64>,
    segments: Vec<Range<usize>>,
}

/// Scores of one model (module documentation).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MotionScores {
    /// RMS of compensated − truth over the run, deg/s.
    pub rate_rmse_dps: f64,
    /// Median over the motion segments of |∫(compensated − truth)dt|, deg.
    pub angle_err_deg_median: Option<f64>,
    /// 95th percentile of the same, deg.
    pub angle_err_deg_p95: Option<f64>,
    /// Largest of the same, deg.
    pub angle_err_deg_max: Option<f64>,
    /// |∫(compensated − truth)dt| over the whole run, deg.
    pub angle_err_deg_run: f64,
    /// |∫(compensated − truth)dt| of each motion segment, in order, deg (for pooling across
    /// recordings).
    pub angle_err_deg_segments: Vec<f64>,
}

/// The start-up bias-hold baseline of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct BiasHoldRun {
    /// raw − bias.
    pub compensated: Vec<f64>,
    /// The mean of the start-up window, deg/s.
    pub bias_dps: f64,
    /// Samples in the start-up window.
    pub samples: usize,
}

/// Maximal runs of `true`, as index ranges, in order.
pub fn segments(moving: &[bool]) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, &m) in moving.iter().enumerate() {
        match (m, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                out.push(s..i);
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push(s..moving.len());
    }
    out
}

impl MotionRun {
    /// A run from equal-length series; time must be finite and strictly increasing, raw and truth
    /// finite.
    pub fn new(t_s: Vec<f64>, raw: Vec<f64>, truth: Vec<f64>, moving: &[bool]) -> Result<Self, MotionError> {
        let n = t_s.len();
        if raw.len() != n || truth.len() != n || moving.len() != n {
            return Err(MotionError::Lengths(format!(
                "series of unequal length: time {n}, raw {}, truth {}, moving {}",
                raw.len(),
                truth.len(),
                moving.len()
            )));
        }
        if n < 2 {
            return Err(MotionError::TooShort(n));
        }
        for (name, series) in [("time", &t_s), ("raw", &raw), ("truth", &truth)] {
            if let Some(i) = series.iter().position(|v| !v.is_finite()) {
                return Err(MotionError::NonFinite(format!("{name} is not finite at sample {i}")));
            }
        }
        if let Some(i) = (1..n).find(|&i| t_s[i] <= t_s[i - 1]) {
            return Err(MotionError::Time(i));
        }
        let dt = (0..n).map(|i| if i == 0 { t_s[1] - t_s[0] } else { t_s[i] - t_s[i - 1] }).collect();
        Ok(Self { segments: segments(moving), t_s, raw, truth, dt })
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    /// Whether the run is empty (never: a run has at least two samples).
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    /// Time of each sample, s.
    pub fn t_s(&self) -> &[f64] {
        &self.t_s
    }

    /// Integration step of each sample, Δt_i = t_i − t_{i−1} (the first takes the first interval), s.
    pub fn dt(&self) -> &[f64] {
        &self.dt
    }

    /// The raw rate, deg/s.
    pub fn raw(&self) -> &[f64] {
        &self.raw
    }

    /// The truth (the injected profile), deg/s.
    pub fn truth(&self) -> &[f64] {
        &self.truth
    }

    /// The motion segments (index ranges).
    pub fn segments(&self) -> &[Range<usize>] {
        &self.segments
    }

    /// Samples inside motion segments.
    pub fn moving_samples(&self) -> usize {
        self.segments.iter().map(|s| s.len()).sum()
    }

    /// Mean sample rate, Hz.
    pub fn rate_hz(&self) -> f64 {
        (self.len() - 1) as f64 / (self.t_s[self.len() - 1] - self.t_s[0])
    }

    /// ∫(compensated − truth)dt over `span`, signed, deg.
    fn angle_error(&self, compensated: &[f64], span: Range<usize>) -> f64 {
        span.map(|i| (compensated[i] - self.truth[i]) * self.dt[i]).sum()
    }

    /// Scores a compensated series (one value per sample, deg/s).
    pub fn score(&self, compensated: &[f64]) -> Result<MotionScores, MotionError> {
        if compensated.len() != self.len() {
            return Err(MotionError::Lengths(format!(
                "{} compensated values for a run of {} samples",
                compensated.len(),
                self.len()
            )));
        }
        let per_segment: Vec<f64> =
            self.segments.iter().map(|s| self.angle_error(compensated, s.clone()).abs()).collect();
        Ok(MotionScores {
            rate_rmse_dps: rmse(compensated, &self.truth).unwrap_or(f64::NAN),
            angle_err_deg_median: quantile(&per_segment, 0.5),
            angle_err_deg_p95: quantile(&per_segment, 0.95),
            angle_err_deg_max: per_segment.iter().copied().reduce(f64::max),
            angle_err_deg_run: self.angle_error(compensated, 0..self.len()).abs(),
            angle_err_deg_segments: per_segment,
        })
    }

    /// Length of each motion segment, s (Σ Δt over its samples).
    pub fn segment_durations(&self) -> Vec<f64> {
        self.segments.iter().map(|s| self.dt[s.clone()].iter().sum()).collect()
    }

    /// The sensor's own static series, raw − truth (the recording before the motion was added).
    pub fn sensor_error(&self) -> Vec<f64> {
        self.raw.iter().zip(&self.truth).map(|(r, m)| r - m).collect()
    }

    /// N of the sensor's own static series (raw − truth), deg/√s: the IEEE Std 952 fit of its
    /// octave Allan deviation (`crate::diag`); `None` when the fit fails (a constant series).
    pub fn sensor_arw(&self) -> Option<f64> {
        use crate::diag::allan::{Taus, oadev_with_max_m};
        use crate::diag::noise_fit::{Weighting, fit_allan};
        let allan = oadev_with_max_m(&self.sensor_error(), self.rate_hz(), &Taus::Octave, usize::MAX).ok()?;
        let fit = fit_allan(&allan.octave_points(), Weighting::default()).ok()?;
        (fit.model.n > 0.0).then_some(fit.model.n)
    }

    /// The white-noise floor of each motion segment, deg: the median of |∫ white noise dt| over a
    /// segment of length T is 0.674·N·√T (0.674 = Φ⁻¹(0.75), the median of |Z|), N the angle
    /// random walk in deg/√s. No drift model can remove it.
    pub fn white_noise_floor(&self, n_deg_rt_s: f64) -> Vec<f64> {
        const MEDIAN_ABS_NORMAL: f64 = 0.674_489_750_196_081_7;
        self.segment_durations().iter().map(|&t| MEDIAN_ABS_NORMAL * n_deg_rt_s * t.sqrt()).collect()
    }

    /// The `last-static` (zero-rate update) reference: each sample minus the mean of the last
    /// `window_s` seconds' worth of samples (round(window_s · rate) samples) flagged static before
    /// it, with the file's flags — what an INS does that stops, knows it, and re-levels its gyro
    /// bias. Before the first static sample nothing is subtracted.
    pub fn last_static(&self, moving: &[bool], window_s: f64) -> Result<Vec<f64>, MotionError> {
        if !(window_s > 0.0 && window_s.is_finite()) {
            return Err(MotionError::Invalid(format!("last-static window {window_s} s must be positive and finite")));
        }
        if moving.len() != self.len() {
            return Err(MotionError::Lengths(format!("{} flags for a run of {} samples", moving.len(), self.len())));
        }
        let w = ((window_s * self.rate_hz()).round() as usize).max(1);
        let mut window = std::collections::VecDeque::with_capacity(w + 1);
        let mut sum = 0.0;
        let mut out = Vec::with_capacity(self.len());
        for (i, &raw) in self.raw.iter().enumerate() {
            let bias = if window.is_empty() { 0.0 } else { sum / window.len() as f64 };
            out.push(raw - bias);
            if !moving[i] {
                window.push_back(raw);
                sum += raw;
                if window.len() > w {
                    sum -= window.pop_front().unwrap_or(0.0);
                }
            }
        }
        Ok(out)
    }

    /// The start-up bias-hold baseline: raw minus the mean of the samples less than `startup_s`
    /// after the first one and before the first motion.
    pub fn bias_hold(&self, startup_s: f64) -> Result<BiasHoldRun, MotionError> {
        if !(startup_s > 0.0 && startup_s.is_finite()) {
            return Err(MotionError::Invalid(format!("start-up window {startup_s} s must be positive and finite")));
        }
        let first_motion = self.segments.first().map_or(self.len(), |s| s.start);
        let samples = self.t_s[..first_motion].iter().take_while(|&&t| t - self.t_s[0] < startup_s).count();
        if samples == 0 {
            return Err(MotionError::Invalid(
                "bias-hold: the run moves from its first sample, so there is no static start-up window".into(),
            ));
        }
        let bias_dps = self.raw[..samples].iter().sum::<f64>() / samples as f64;
        Ok(BiasHoldRun { compensated: self.raw.iter().map(|r| r - bias_dps).collect(), bias_dps, samples })
    }

    /// The causal first-order high-pass of the raw rate with cutoff `cutoff_hz` (module
    /// documentation).
    pub fn highpass(&self, cutoff_hz: f64) -> Result<Vec<f64>, MotionError> {
        if !(cutoff_hz > 0.0 && cutoff_hz.is_finite()) {
            return Err(MotionError::Invalid(format!("high-pass cutoff {cutoff_hz} Hz must be positive and finite")));
        }
        let rc = 1.0 / (2.0 * PI * cutoff_hz);
        let mut y = Vec::with_capacity(self.len());
        y.push(0.0);
        for i in 1..self.len() {
            let a = rc / (rc + self.dt[i]);
            y.push(a * (y[i - 1] + self.raw[i] - self.raw[i - 1]));
        }
        Ok(y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(raw: Vec<f64>, truth: Vec<f64>, moving: &[bool]) -> MotionRun {
        let t = (0..raw.len()).map(|i| 0.5 * i as f64).collect();
        MotionRun::new(t, raw, truth, moving).unwrap()
    }

    #[test]
    fn segments_are_maximal_runs_of_motion() {
        let m = [true, true, false, false, true, false, true];
        assert_eq!(segments(&m), vec![0..2, 4..5, 6..7]);
        assert!(segments(&[false, false]).is_empty());
        assert_eq!(segments(&[true; 3]), vec![0..3]);
    }

    #[test]
    fn angle_errors_integrate_with_the_sample_interval() {
        let moving = [false, true, true, false, true, false];
        let truth = vec![0.0, 2.0, 2.0, 0.0, 4.0, 0.0];
        let comp = vec![0.1, 2.0, 3.0, 0.1, 2.0, 0.1];
        let r = run(vec![0.0; 6], truth.clone(), &moving);
        let s = r.score(&comp).unwrap();
        // Segments: (0 + 1)·0.5 = 0.5 and |−2|·0.5 = 1; run: (0.1 + 1 + 0.1 − 2 + 0.1)·0.5 = −0.35.
        assert!((s.angle_err_deg_median.unwrap() - 0.75).abs() < 1e-12);
        assert!((s.angle_err_deg_p95.unwrap() - 0.975).abs() < 1e-12);
        assert_eq!(s.angle_err_deg_max, Some(1.0));
        assert!((s.angle_err_deg_run - 0.35).abs() < 1e-12);
        let e2 = [0.01, 0.0, 1.0, 0.01, 4.0, 0.01];
        assert!((s.rate_rmse_dps - (e2.iter().sum::<f64>() / 6.0).sqrt()).abs() < 1e-12);
        let perfect = r.score(&truth).unwrap();
        assert_eq!(
            (perfect.rate_rmse_dps, perfect.angle_err_deg_run, perfect.angle_err_deg_max),
            (0.0, 0.0, Some(0.0))
        );
        assert!(r.score(&comp[1..]).is_err());
    }

    #[test]
    fn bias_hold_stops_at_the_startup_window_or_the_first_motion() {
        // 0.5 s steps: a 1.2 s window holds samples 0, 1, 2.
        let raw = vec![1.0, 2.0, 3.0, 10.0, 10.0, 10.0];
        let b = run(raw.clone(), vec![0.0; 6], &[false; 6]).bias_hold(1.2).unwrap();
        assert_eq!((b.samples, b.bias_dps), (3, 2.0));
        assert_eq!(b.compensated, vec![-1.0, 0.0, 1.0, 8.0, 8.0, 8.0]);
        let early = run(raw.clone(), vec![0.0; 6], &[false, false, true, true, false, false]);
        assert_eq!(early.bias_hold(60.0).unwrap().samples, 2);
        assert!(run(raw, vec![0.0; 6], &[true; 6]).bias_hold(60.0).is_err());
    }

    #[test]
    fn last_static_subtracts_the_mean_of_the_last_static_window_and_the_floor_grows_as_sqrt_t() {
        // 0.5 s steps (2 Hz): a 1 s window holds the last two static samples.
        let raw = vec![1.0, 3.0, 10.0, 10.0, 5.0, 7.0];
        let moving = [false, false, true, true, false, false];
        let r = run(raw, vec![0.0; 6], &moving);
        let c = r.last_static(&moving, 1.0).unwrap();
        assert_eq!(c, vec![1.0, 2.0, 8.0, 8.0, 3.0, 3.0]);
        assert!(r.last_static(&moving, 0.0).is_err());
        // One segment of two samples: T = 1 s.
        let floor = r.white_noise_floor(2.0);
        assert_eq!(floor.len(), 1);
        assert!((floor[0] - 0.674_489_750_196_081_7 * 2.0).abs() < 1e-12);
    }

    #[test]
    fn highpass_removes_a_constant_and_decays_a_step() {
        let r = run(vec![3.0; 50], vec![0.0; 50], &[false; 50]);
        assert!(r.highpass(0.01).unwrap().iter().all(|&v| v == 0.0));
        let mut raw = vec![0.0; 50];
        raw[10..].fill(1.0);
        let y = run(raw, vec![0.0; 50], &[false; 50]).highpass(0.1).unwrap();
        let rc = 1.0 / (2.0 * PI * 0.1);
        let a = rc / (rc + 0.5);
        for (k, &v) in y[10..].iter().enumerate() {
            assert!((v - a.powi(k as i32 + 1)).abs() < 1e-12, "step response at {k}");
        }
        assert!(r.highpass(0.0).is_err() && r.highpass(f64::NAN).is_err());
    }

    #[test]
    fn bad_runs_are_refused() {
        let ok = vec![0.0, 1.0];
        assert!(matches!(MotionRun::new(ok.clone(), ok.clone(), vec![0.0], &[false; 2]), Err(MotionError::Lengths(_))));
        assert!(matches!(MotionRun::new(vec![0.0], vec![0.0], vec![0.0], &[false]), Err(MotionError::TooShort(1))));
        assert!(matches!(
            MotionRun::new(ok.clone(), vec![0.0, f64::NAN], ok.clone(), &[false; 2]),
            Err(MotionError::NonFinite(_))
        ));
        assert!(matches!(MotionRun::new(vec![1.0, 1.0], ok.clone(), ok, &[false; 2]), Err(MotionError::Time(1))));
    }
}
