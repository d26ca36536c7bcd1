//! The warm state of a pipeline: what each axis ([`AxisWarm`]) and the three together
//! ([`StreamWarm`]) hold besides the models, as the drift estimators, the detector and the
//! input checks hand it out and take it back ([`Pipeline::warm_state`](super::Pipeline::warm_state),
//! [`Pipeline::restore_state`](super::Pipeline::restore_state)); stored in snapshots
//! ([`super::snapshot`]).

mod axis;
mod bank;

use serde::{Deserialize, Serialize};

pub use axis::{AxisWarm, TemperatureWarm};
pub use bank::{BANK_GM, BANK_STATES, BankModel, BankWarm};

use super::detector::DetectorState;
use super::input_check::InputState;
use super::pending::PendingState;
use super::period::PeriodEstimate;

/// The state the three axes share: what the static detector and the input checks need to go
/// on deciding exactly as before the restart.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StreamWarm {
    /// Index of the next sample (samples processed so far): the restored pipeline continues it,
    /// so the pending samples, the estimators' last commit and the calibration's blocks keep
    /// their positions.
    pub index: u64,
    /// The sample period: configured, measured ("auto") or still being measured.
    pub period: PeriodEstimate,
    /// Samples since the last accepted static sample.
    pub horizon: u64,
    /// The pending (delayed-commit) queue.
    pub pending: PendingState,
    /// The static detector: residual windows, hysteresis, deadlock watch.
    pub detector: DetectorState,
    /// The input checks: `seq` and time references, spike estimates, stuck-value runs.
    pub input: InputState,
}

impl StreamWarm {
    /// Whether every stored value is usable (finite; temperatures finite or NaN).
    pub fn is_valid(&self) -> bool {
        self.pending.is_valid() && self.detector.is_finite() && self.input.is_finite()
    }
}
