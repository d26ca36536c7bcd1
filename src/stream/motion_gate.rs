//! Motion gate (design.md "Stage definitions", motion gate): decides per sample whether the
//! platform is moving, so that moving samples are neither model input nor training data.
//!
//! A sample is moving when the publisher sets [`FLAG_MOVING`](super::sample::FLAG_MOVING), when
//! |rate| on any axis exceeds `rate_dps`, or when the variance of the last `window` accepted raw
//! samples of any axis exceeds `variance_dps2`. The rate test reacts at once; the variance
//! window keeps the gate closed for up to `window` samples after a manoeuvre ends (a natural
//! hold-off). The three axes are gated together: the platform moves as a whole.

use super::ring::RingBuffer;

/// Thresholds of the motion gate (`[motion]` in the configuration).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionConfig {
    /// |rate| above which a sample is moving, deg/s.
    pub rate_dps: f64,
    /// Short-window variance above which a sample is moving, (deg/s)².
    pub variance_dps2: f64,
    /// Samples in the variance window (≥ 2).
    pub window: usize,
}

/// Per-sample motion detector for three axes; allocates only in [`MotionGate::new`].
#[derive(Debug, Clone)]
pub struct MotionGate {
    config: MotionConfig,
    rings: [RingBuffer; 3],
}

impl MotionGate {
    /// A gate with empty windows (`window` is raised to 2 if smaller).
    pub fn new(config: MotionConfig) -> Self {
        let w = config.window.max(2);
        Self { config, rings: [RingBuffer::new(w), RingBuffer::new(w), RingBuffer::new(w)] }
    }

    /// The thresholds.
    pub fn config(&self) -> &MotionConfig {
        &self.config
    }

    /// Changes the thresholds; the variance windows are kept when `window` is unchanged and
    /// restart empty otherwise (only the rate test applies until they refill).
    pub fn reconfigure(&mut self, config: MotionConfig) {
        if config.window.max(2) == self.config.window.max(2) {
            self.config = config;
        } else {
            *self = Self::new(config);
        }
    }

    /// Adds an accepted (finite, in-range) sample and returns whether it is moving.
    pub fn push(&mut self, rate_dps: &[f64; 3], flagged_moving: bool) -> bool {
        let mut moving = flagged_moving;
        for (ring, &r) in self.rings.iter_mut().zip(rate_dps) {
            ring.push(r);
            moving |= r.abs() > self.config.rate_dps;
            // The variance test needs a full window; before that only the rate test applies.
            if ring.is_full() && variance(ring.as_slice()) > self.config.variance_dps2 {
                moving = true;
            }
        }
        moving
    }
}

/// Population variance of a short slice (two passes: exact enough for a few dozen samples).
fn variance(x: &[f64]) -> f64 {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gate() -> MotionGate {
        MotionGate::new(MotionConfig { rate_dps: 5.0, variance_dps2: 0.5, window: 4 })
    }

    #[test]
    fn flag_rate_and_variance_each_mark_motion() {
        let mut g = gate();
        for _ in 0..4 {
            assert!(!g.push(&[0.1, 0.0, -0.1], false));
        }
        assert!(g.push(&[0.1, 0.0, -0.1], true));
        assert!(g.push(&[0.1, 6.0, -0.1], false));
        // The 6.0 stays in the variance window for three more samples.
        for _ in 0..3 {
            assert!(g.push(&[0.1, 0.0, -0.1], false));
        }
        assert!(!g.push(&[0.1, 0.0, -0.1], false));
        // A 2 deg/s step: below the rate threshold, above the variance threshold.
        assert!(g.push(&[2.0, 0.0, 0.0], false));
    }
}
