//! No detector: every sample the publisher does not flag moving is static (`[motion] detector =
//! "none"`). What the ungated models of the motion protocol run behind (they see the whole
//! stream); commit delay 0, as the threshold gate.

use serde::{Deserialize, Serialize};

use super::{Decision, DetectorCounters, DetectorInput, DetectorState, MotionDetector};

/// No detector (module documentation): the publisher's moving flag is the only verdict.
#[derive(Debug, Clone, Default)]
pub struct NoDetector {
    counters: DetectorCounters,
    was_moving: bool,
}

/// The state of [`NoDetector`] in a snapshot: the last verdict (for counting onsets).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct NoDetectorState {
    was_moving: bool,
}

impl NoDetector {
    /// A detector that never flags motion itself.
    pub fn new() -> Self {
        Self::default()
    }
}

impl MotionDetector for NoDetector {
    fn name(&self) -> &'static str {
        "none"
    }

    /// Moving exactly when the publisher says so; onsets count the publisher's.
    fn push(&mut self, input: &DetectorInput<'_>) -> Decision {
        let moving = input.publisher_moving;
        if moving && !self.was_moving {
            self.counters.onsets += 1;
        }
        self.was_moving = moving;
        Decision { moving, ..Decision::default() }
    }

    fn commit_delay(&self) -> usize {
        0
    }

    fn set_period(&mut self, _period_s: f64) {}

    fn counters(&self) -> DetectorCounters {
        self.counters
    }

    fn state(&self) -> DetectorState {
        DetectorState::None(NoDetectorState { was_moving: self.was_moving })
    }

    fn restore_state(&mut self, state: &DetectorState) -> Result<(), String> {
        let DetectorState::None(s) = state else {
            return Err(format!("a {} detector's state, not the none detector's", state.kind().name()));
        };
        self.was_moving = s.was_moving;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::config::Config;
    use crate::model::baselines::PersistenceModel;
    use crate::model::rng::Rng;
    use crate::model::scaler::MinMaxScaler;
    use crate::stream::calibration::NoiseCalibration;
    use crate::stream::drift::DriftEstimate;
    use crate::stream::{DetectorKind, FLAG_MOVING, InputSample, MotionConfig, Pipeline};

    /// A seeded 100 Hz stream: bias 0.5 deg/s and noise, two turns of 30 and 90 deg/s, a stretch
    /// the publisher flags moving.
    fn stream() -> Vec<InputSample> {
        let mut rng = Rng::new(14);
        (0..6000u64)
            .map(|k| {
                let turn = match k {
                    2000..2300 => 30.0,
                    4000..4100 => -90.0,
                    _ => 0.0,
                };
                let r = [0, 1, 2].map(|a| 0.5 - 0.2 * a as f64 + turn + rng.uniform(-0.4, 0.4));
                let flags = if (3000..3050).contains(&k) { FLAG_MOVING } else { 0 };
                InputSample { flags, ..InputSample::new(k, k * 10_000_000, r) }
            })
            .collect()
    }

    #[test]
    fn it_never_flags_motion_and_the_publisher_flag_still_wins() {
        let mut d = NoDetector::new();
        let drift = [DriftEstimate { drift: 0.0, variance: 1e-6, from_model: false }; 3];
        let noise: [NoiseCalibration; 3] = Default::default();
        for (k, s) in stream().iter().enumerate() {
            let rate = [s.rate_dps[0] * 1e3, 1e6, -1e6];
            let publisher_moving = s.flags & FLAG_MOVING != 0;
            let input = DetectorInput { rate: &rate, drift: &drift, noise: &noise, publisher_moving };
            assert_eq!(d.push(&input), Decision { moving: publisher_moving, ..Decision::default() }, "sample {k}");
        }
        assert_eq!(d.counters(), DetectorCounters { onsets: 1, ..DetectorCounters::default() });
        assert_eq!((d.commit_delay(), d.longest_window()), (0, 1));
        let mut other = NoDetector::new();
        other.restore_state(&d.state()).unwrap();
        assert_eq!(other.state(), d.state());
        // Named "none" in the configuration file, and built by the registry.
        let config = Config::from_toml("[motion]\ndetector = \"none\"\n", "test").unwrap();
        assert_eq!(config.motion.detector, DetectorKind::None);
        let built = DetectorKind::None.build(&config.motion.statistical, config.motion.threshold);
        assert_eq!((built.name(), DetectorKind::None.name()), ("none", "none"));
    }

    /// What the ungated models of the motion protocol ran behind before this detector: the
    /// threshold gate with both thresholds at +∞.
    fn run(config: &Config, detector: DetectorKind, persistence: bool) -> Vec<String> {
        let mut settings = config.pipeline().unwrap();
        settings.detector = detector;
        if detector == DetectorKind::Threshold {
            settings.motion = MotionConfig { rate_dps: f64::INFINITY, variance_dps2: f64::INFINITY, ..settings.motion };
        }
        let mut p = Pipeline::new(settings).unwrap();
        if persistence {
            for axis in 0..3 {
                p.install_model(axis, Arc::new(PersistenceModel), MinMaxScaler { min: -1.0, max: 1.0 }, 1).unwrap();
            }
        }
        let mut out: Vec<String> = stream().iter().map(|s| format!("{:?}", p.process(s))).collect();
        out.push(format!("{:?}", p.stats()));
        out
    }

    #[test]
    fn a_pipeline_without_detector_matches_the_infinite_threshold_gate_bit_for_bit() {
        let mut kalman = Config::default();
        kalman.input.rate_hz = crate::config::RateSetting::Hz(100.0);
        for (config, persistence) in [(kalman, false), (Config::paper(), true)] {
            let none = run(&config, DetectorKind::None, persistence);
            let gate = run(&config, DetectorKind::Threshold, persistence);
            assert_eq!(none.len(), gate.len());
            for (k, (a, b)) in none.iter().zip(&gate).enumerate() {
                assert_eq!(a, b, "sample {k} ({:?})", config.drift.kind);
            }
            // Only the publisher's 50 flagged samples are moving.
            assert!(none.last().unwrap().contains(" moving: 50,"), "{}", none.last().unwrap());
        }
    }
}
