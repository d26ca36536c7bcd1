//! Motion gate (docs/design.md "Stage definitions", motion gate): decides per sample whether the
//! platform is moving, so that moving samples are neither model input nor training data.
//!
//! A sample is moving when the publisher sets [`FLAG_MOVING`](super::sample::FLAG_MOVING), when
//! |rate − reference| on any axis exceeds `rate_dps`, or when the variance of the last `window`
//! accepted raw samples of any axis exceeds `variance_dps2`. The reference is the pipeline's
//! running static bias estimate, so the rate test looks at the rate net of the bias: a sensor with a bias of
//! several deg/s (common for MEMS) is not "moving" for ever; before any static sample there is no
//! reference and only the variance test applies. Both thresholds must sit above the sensor's
//! static noise at its sample rate (a few σ per sample; the variance of a `window`-sample window). The rate test reacts at once; the variance
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

impl Default for MotionConfig {
    fn default() -> Self {
        Self { rate_dps: 2.0, variance_dps2: 0.6, window: 20 }
    }
}

impl MotionConfig {
    /// Checks the values; the message names the key.
    pub fn validate(&self) -> Result<(), String> {
        for (key, v) in [("motion.rate_dps", self.rate_dps), ("motion.variance_dps2", self.variance_dps2)] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(format!("{key}: {v} must be positive and finite"));
            }
        }
        if self.window < 2 {
            return Err(format!("motion.window: {} must be at least 2", self.window));
        }
        Ok(())
    }
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

    /// The samples in each axis' variance window, oldest first (for a snapshot).
    pub fn windows(&self) -> [Vec<f64>; 3] {
        self.rings.each_ref().map(|r| r.as_slice().to_vec())
    }

    /// Refills the variance windows with what [`MotionGate::windows`] copied; refused (nothing
    /// changed) when a window holds more samples than `window`.
    pub fn refill(&mut self, windows: &[Vec<f64>; 3]) -> Result<(), String> {
        let cap = self.rings[0].capacity();
        if let Some(w) = windows.iter().find(|w| w.len() > cap) {
            return Err(format!("motion.window: {} samples stored, the window holds {cap}", w.len()));
        }
        for (ring, w) in self.rings.iter_mut().zip(windows) {
            ring.clear();
            w.iter().for_each(|&x| ring.push(x));
        }
        Ok(())
    }

    /// Adds an accepted (finite, in-range) sample and returns whether it is moving; the rate
    /// test compares `rate_dps − reference` (skipped without a reference).
    pub fn push(&mut self, rate_dps: &[f64; 3], reference: Option<&[f64; 3]>, flagged_moving: bool) -> bool {
        let mut moving = flagged_moving;
        for (k, (ring, &r)) in self.rings.iter_mut().zip(rate_dps).enumerate() {
            ring.push(r);
            if let Some(reference) = reference {
                moving |= (r - reference[k]).abs() > self.config.rate_dps;
            }
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
        let zero = Some(&[0.0; 3]);
        for _ in 0..4 {
            assert!(!g.push(&[0.1, 0.0, -0.1], zero, false));
        }
        assert!(g.push(&[0.1, 0.0, -0.1], zero, true));
        assert!(g.push(&[0.1, 6.0, -0.1], zero, false));
        // The 6.0 stays in the variance window for three more samples.
        for _ in 0..3 {
            assert!(g.push(&[0.1, 0.0, -0.1], zero, false));
        }
        assert!(!g.push(&[0.1, 0.0, -0.1], zero, false));
        // A 2 deg/s step: below the rate threshold, above the variance threshold.
        assert!(g.push(&[2.0, 0.0, 0.0], zero, false));
    }

    #[test]
    fn the_rate_test_is_relative_to_the_reference() {
        let mut g = gate();
        // A 20 deg/s bias is no motion once the reference (the drift estimate) has it …
        for _ in 0..6 {
            assert!(!g.push(&[20.0, 0.0, 0.0], Some(&[19.9, 0.0, 0.0]), false));
        }
        // … 6 deg/s above it is; without a reference only the variance test applies.
        assert!(g.push(&[26.0, 0.0, 0.0], Some(&[20.0, 0.0, 0.0]), false));
        let mut fresh = gate();
        assert!(!fresh.push(&[20.0, 0.0, 0.0], None, false));
    }
}
