//! The fixed-threshold gate as a [`MotionDetector`]: [`MotionGate`] with the drift estimate as
//! its rate reference (once every axis has one of finite variance), commit delay 0.

use serde::{Deserialize, Serialize};

use super::{Decision, DetectorCounters, DetectorInput, DetectorState, MotionDetector};
use crate::stream::motion_gate::{MotionConfig, MotionGate};

/// Threshold gate (module documentation).
#[derive(Debug, Clone)]
pub struct ThresholdDetector {
    gate: MotionGate,
    counters: DetectorCounters,
    was_moving: bool,
}

/// The threshold gate's state in a snapshot: the variance windows and the last verdict.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ThresholdState {
    windows: [Vec<f64>; 3],
    was_moving: bool,
}

impl ThresholdState {
    /// Whether every stored number is finite.
    pub fn is_finite(&self) -> bool {
        self.windows.iter().flatten().all(|v| v.is_finite())
    }
}

impl ThresholdDetector {
    /// A gate with these thresholds.
    pub fn new(config: MotionConfig) -> Self {
        Self { gate: MotionGate::new(config), counters: DetectorCounters::default(), was_moving: false }
    }
}

impl MotionDetector for ThresholdDetector {
    fn name(&self) -> &'static str {
        "threshold"
    }

    fn push(&mut self, input: &DetectorInput<'_>) -> Decision {
        let d = input.drift;
        let reference = d.iter().all(|e| e.variance.is_finite()).then(|| [d[0].drift, d[1].drift, d[2].drift]);
        let moving = self.gate.push(input.rate, reference.as_ref(), input.publisher_moving);
        if moving && !input.publisher_moving {
            self.counters.alarms += 1;
        }
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

    /// See [`MotionGate::reconfigure`].
    fn reconfigure_thresholds(&mut self, config: MotionConfig) {
        self.gate.reconfigure(config);
    }

    fn state(&self) -> DetectorState {
        DetectorState::Threshold(ThresholdState { windows: self.gate.windows(), was_moving: self.was_moving })
    }

    fn restore_state(&mut self, state: &DetectorState) -> Result<(), String> {
        let DetectorState::Threshold(s) = state else {
            return Err(format!("a {} detector's state, not a threshold gate's", state.kind().name()));
        };
        self.gate.refill(&s.windows)?;
        self.was_moving = s.was_moving;
        Ok(())
    }
}
