//! Known motion profiles for the motion-injected evaluation (docs/design.md): a seeded sequence of
//! rotations about the sensed axis, separated by static stretches, that is added to the rate
//! columns of a static recording. The profile is the truth; a compensator should remove the drift
//! and leave the profile.
//!
//! Segment shapes (rate against time within a segment of length d, u = (t − start)/d):
//! - **turn**: `peak · sin²(π u)` — smooth start and stop, peak |rate| log-uniform in 1 … 90 deg/s,
//!   d uniform in 2 … 60 s, angle = peak·d/2;
//! - **slow**: a Tukey window, cosine ramps over the first and last 20 % and a plateau between —
//!   peak |rate| log-uniform in 0.05 … 1 deg/s (the size of the drift itself), d uniform in
//!   20 … 300 s, angle = 0.8·peak·d.
//!
//! Signs are random. Motions are drawn until their total length would exceed (1 − F)·duration, F
//! the static fraction (a last motion is shortened to fit when at least its minimum length is
//! left); the remaining time is split into static stretches before, between and after the
//! motions, in proportions drawn from an exponential distribution. So at least a fraction F of the
//! run is static.

use std::f64::consts::PI;

use super::rng::{Stream, StreamId};

/// Axis index of the motion stream (after the gyro axes and the temperature).
const MOTION_AXIS: u64 = 4;
/// Fraction of a slow segment taken by each cosine ramp.
const SLOW_TAPER: f64 = 0.2;

/// Which motions a profile contains.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionKind {
    /// Smooth turns, 1 … 90 deg/s, 2 … 60 s.
    Turns,
    /// Slow rotations, 0.05 … 1 deg/s, 20 … 300 s.
    Slow,
    /// Turns and slow rotations, each motion one or the other with equal probability.
    Mixed,
}

/// Shape of one motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SegmentShape {
    /// `peak · sin²(π u)`.
    Turn,
    /// Tukey window with 20 % cosine ramps.
    Slow,
}

impl SegmentShape {
    fn duration_range(self) -> (f64, f64) {
        match self {
            SegmentShape::Turn => (2.0, 60.0),
            SegmentShape::Slow => (20.0, 300.0),
        }
    }

    fn peak_range(self) -> (f64, f64) {
        match self {
            SegmentShape::Turn => (1.0, 90.0),
            SegmentShape::Slow => (0.05, 1.0),
        }
    }

    /// Rate at fraction `u` ∈ [0, 1] of the segment per unit of peak.
    fn profile(self, u: f64) -> f64 {
        match self {
            SegmentShape::Turn => {
                let s = (PI * u).sin();
                s * s
            }
            SegmentShape::Slow => {
                let edge = u.min(1.0 - u);
                if edge >= SLOW_TAPER { 1.0 } else { 0.5 * (1.0 - (PI * edge / SLOW_TAPER).cos()) }
            }
        }
    }

    /// Integral of [`SegmentShape::profile`] over the segment per unit of peak and length.
    fn area(self) -> f64 {
        match self {
            SegmentShape::Turn => 0.5,
            SegmentShape::Slow => 1.0 - SLOW_TAPER,
        }
    }
}

/// One motion of a profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionSegment {
    /// Start, s from the start of the recording.
    pub start_s: f64,
    /// Length, s.
    pub duration_s: f64,
    /// Signed peak rate, deg/s.
    pub peak_dps: f64,
    /// Shape.
    pub shape: SegmentShape,
}

impl MotionSegment {
    /// The rotation angle of the whole segment, deg (signed).
    pub fn angle_deg(&self) -> f64 {
        self.peak_dps * self.duration_s * self.shape.area()
    }

    /// Rate at time `t_s` (0 outside the segment), deg/s.
    pub fn rate_at(&self, t_s: f64) -> f64 {
        let u = (t_s - self.start_s) / self.duration_s;
        if (0.0..1.0).contains(&u) { self.peak_dps * self.shape.profile(u) } else { 0.0 }
    }

    /// Whether `t_s` lies within the segment, `[start, start + duration)`.
    pub fn contains(&self, t_s: f64) -> bool {
        t_s >= self.start_s && t_s < self.start_s + self.duration_s
    }
}

/// A planned motion profile over a recording.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionPlan {
    /// The motions in time order, not overlapping.
    pub segments: Vec<MotionSegment>,
    /// Length of the recording the plan covers, s.
    pub duration_s: f64,
}

impl MotionPlan {
    /// Plans motions of `kind` over `duration_s` seconds with at least `static_fraction` ∈ [0, 1]
    /// of the time static, from `seed`.
    pub fn plan(kind: MotionKind, seed: u64, duration_s: f64, static_fraction: f64) -> Result<Self, String> {
        if !(0.0..=1.0).contains(&static_fraction) {
            return Err(format!("static fraction {static_fraction} is outside [0, 1]"));
        }
        if !(duration_s.is_finite() && duration_s >= 0.0) {
            return Err(format!("duration {duration_s} s is not finite and ≥ 0"));
        }
        let mut rng = Stream::new(seed, MOTION_AXIS, StreamId::Motion);
        let budget = (1.0 - static_fraction) * duration_s;
        let mut drawn: Vec<(f64, f64, SegmentShape)> = Vec::new();
        let mut used = 0.0;
        loop {
            let shape = match kind {
                MotionKind::Turns => SegmentShape::Turn,
                MotionKind::Slow => SegmentShape::Slow,
                MotionKind::Mixed => {
                    if rng.uniform() < 0.5 {
                        SegmentShape::Turn
                    } else {
                        SegmentShape::Slow
                    }
                }
            };
            let (d_lo, d_hi) = shape.duration_range();
            let (p_lo, p_hi) = shape.peak_range();
            let duration = rng.uniform_in(d_lo, d_hi);
            let peak = rng.log_uniform(p_lo, p_hi) * rng.sign();
            let left = budget - used;
            if left < d_lo {
                break;
            }
            let duration = duration.min(left);
            used += duration;
            drawn.push((duration, peak, shape));
        }
        let static_total = duration_s - used;
        let weights: Vec<f64> = (0..=drawn.len()).map(|_| rng.exponential()).collect();
        let weight_sum: f64 = weights.iter().sum();
        let mut t = 0.0;
        let mut segments = Vec::with_capacity(drawn.len());
        for (i, &(duration_s, peak_dps, shape)) in drawn.iter().enumerate() {
            t += static_total * weights[i] / weight_sum;
            segments.push(MotionSegment { start_s: t, duration_s, peak_dps, shape });
            t += duration_s;
        }
        Ok(Self { segments, duration_s })
    }

    /// Fraction of the planned time that is static.
    pub fn static_fraction(&self) -> f64 {
        if self.duration_s <= 0.0 {
            return 1.0;
        }
        1.0 - self.segments.iter().map(|s| s.duration_s).sum::<f64>() / self.duration_s
    }

    /// Truth rate (deg/s) and moving flag (0/1) at each time of `t_rel_s` (seconds from the start
    /// of the recording, increasing).
    pub fn render(&self, t_rel_s: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let mut truth = Vec::with_capacity(t_rel_s.len());
        let mut moving = Vec::with_capacity(t_rel_s.len());
        let mut next = 0;
        for &t in t_rel_s {
            while next < self.segments.len() && self.segments[next].start_s + self.segments[next].duration_s <= t {
                next += 1;
            }
            match self.segments.get(next) {
                Some(s) if s.contains(t) => {
                    truth.push(s.rate_at(t));
                    moving.push(1.0);
                }
                _ => {
                    truth.push(0.0);
                    moving.push(0.0);
                }
            }
        }
        (truth, moving)
    }
}
