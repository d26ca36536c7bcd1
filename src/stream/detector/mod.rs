//! Static/moving detectors (issue 13, item 3): one trait, chosen by `[motion] detector` through
//! [`DetectorKind`]. A detector sees every accepted sample with the drift estimate made for it
//! and the axis' self-calibration, and returns a [`Decision`]: whether the sample is moving, and
//! how many of the newest *pending* samples (seen as static, not yet committed to the drift
//! estimator) must be thrown away because the motion it has just found had already begun.
//!
//! Delayed commit: a static sample waits in the pending queue of the
//! [`Pipeline`](super::Pipeline) for [`MotionDetector::commit_delay`] samples before the
//! estimator and the training window get it. A detector that can look back (the statistical
//! one) sets the delay above the longest span it may discard; the threshold gate and `none` set 0
//! (every static sample is committed at once, as before).
//!
//! | name | what it is |
//! |---|---|
//! | `statistical` | mean-shift tests on r = ω − b̂ over several windows and a variance test, set by one false-alarm probability, with hysteresis and delayed commit ([`StatisticalDetector`]) |
//! | `threshold` | fixed deg/s thresholds on |ω − b̂| and on a short-window variance ([`ThresholdDetector`]) |
//! | `none` | never flags motion itself: only the publisher's flag counts ([`NoDetector`]); for models that are to see the whole stream |
//!
//! The publisher's moving flag wins over every detector.

mod none;
mod statistical;
mod threshold;

use std::fmt;

use serde::{Deserialize, Serialize};

pub use none::{NoDetector, NoDetectorState};
pub use statistical::{StatisticalConfig, StatisticalDetector, StatisticalState};
pub use threshold::{ThresholdDetector, ThresholdState};

use super::calibration::NoiseCalibration;
use super::drift::DriftEstimate;

/// What a detector sees of one accepted sample.
#[derive(Debug, Clone, Copy)]
pub struct DetectorInput<'a> {
    /// Raw rates, deg/s.
    pub rate: &'a [f64; 3],
    /// The drift estimate of each axis for this sample.
    pub drift: &'a [DriftEstimate; 3],
    /// Each axis' self-calibration.
    pub noise: &'a [NoiseCalibration; 3],
    /// The publisher's moving flag.
    pub publisher_moving: bool,
}

/// A detector's verdict on one sample.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Decision {
    /// The sample is moving (status bit 1): it is neither committed nor pending.
    pub moving: bool,
    /// Newest pending samples to discard (the motion began before it was detected); the older
    /// pending samples are committed at once. 0 with `moving` false: nothing happens to them.
    pub discard: usize,
    /// Of `discard`, the span the motion is estimated to have lasted (the rest is the guard
    /// before it): what the pipeline discards instead while no reference is committed yet.
    pub onset: usize,
    /// Whether the pending queue is flushed (committed or discarded) on this sample.
    pub flush: bool,
    /// The drift estimate is wrong and must be relearnt: the detector has been "moving" on its
    /// own for long with a residual that does not change (a deadlock: a bias learnt from motion,
    /// or a bias step, makes every later sample look moving). The pending samples are
    /// discarded and the estimators start afresh.
    pub relearn: bool,
}

/// Counts of what a detector did (totals since start).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DetectorCounters {
    /// Static → moving transitions.
    pub onsets: u64,
    /// Samples on which a test fired (publisher flags not counted).
    pub alarms: u64,
    /// Samples flagged moving only by the hysteresis (settling after an alarm).
    pub settling: u64,
    /// Drift estimates relearnt after a deadlock ([`Decision::relearn`]).
    pub relearns: u64,
}

/// A static/moving detector for three axes (module documentation); allocates nothing per
/// sample once its windows are sized.
pub trait MotionDetector: fmt::Debug + Send {
    /// The detector's name in the configuration.
    fn name(&self) -> &'static str;

    /// Judges one accepted sample.
    fn push(&mut self, input: &DetectorInput<'_>) -> Decision;

    /// Samples a static sample stays pending before it is committed.
    fn commit_delay(&self) -> usize;

    /// Sizes time-based windows for the sample period (seconds); called once the period is
    /// known (configured, or measured from the first timestamps).
    fn set_period(&mut self, period_s: f64);

    /// Counters.
    fn counters(&self) -> DetectorCounters;

    /// The longest span (samples) over which the detector can still find a slow motion (1 for a
    /// detector without windows); drift estimators do not track faster than this.
    fn longest_window(&self) -> usize {
        1
    }

    /// New fixed thresholds from a reloaded configuration (only the threshold gate has any).
    fn reconfigure_thresholds(&mut self, _config: crate::stream::MotionConfig) {}

    /// A copy of the state the next decisions depend on (windows, hysteresis, deadlock watch),
    /// for a snapshot; the counters are not part of it.
    fn state(&self) -> DetectorState;

    /// Restores what [`MotionDetector::state`] copied, into a detector of the same kind whose
    /// windows are sized for the same period; refused (nothing changed) otherwise.
    fn restore_state(&mut self, state: &DetectorState) -> Result<(), String>;
}

/// A detector's state in a snapshot (one variant per detector kind).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum DetectorState {
    /// [`StatisticalDetector`].
    Statistical(Box<StatisticalState>),
    /// [`ThresholdDetector`].
    Threshold(ThresholdState),
    /// [`NoDetector`].
    None(NoDetectorState),
}

impl DetectorState {
    /// The detector kind the state belongs to.
    pub fn kind(&self) -> DetectorKind {
        match self {
            Self::Statistical(_) => DetectorKind::Statistical,
            Self::Threshold(_) => DetectorKind::Threshold,
            Self::None(_) => DetectorKind::None,
        }
    }

    /// Whether every stored number is finite.
    pub fn is_finite(&self) -> bool {
        match self {
            Self::Statistical(s) => s.is_finite(),
            Self::Threshold(s) => s.is_finite(),
            Self::None(_) => true,
        }
    }
}

/// The registry of detectors: `[motion] detector` in the configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DetectorKind {
    /// [`StatisticalDetector`] (the default).
    Statistical,
    /// [`ThresholdDetector`].
    Threshold,
    /// [`NoDetector`]: only the publisher's flag.
    None,
}

impl DetectorKind {
    /// The name in the configuration.
    pub fn name(self) -> &'static str {
        match self {
            Self::Statistical => "statistical",
            Self::Threshold => "threshold",
            Self::None => "none",
        }
    }
}
