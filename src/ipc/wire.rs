//! Wire types exchanged over iceoryx2 (docs/design.md, "Wire types").
//!
//! Every type is `#[repr(C)]`, holds only plain numbers and carries an explicit iceoryx2 type name
//! (`#[type_name(...)]` on `#[derive(ZeroCopySend)]`, which implements
//! `ZeroCopySend::type_name`). iceoryx2 compares that name, the size and the alignment when a port
//! opens a service, so a peer in another language (the Python client's ctypes structures, whose
//! `type_name()` static method returns the same string) can talk to these services, and a peer with
//! a different layout is refused instead of misreading memory.

use iceoryx2::prelude::ZeroCopySend;

/// `RawSample::flags` bit 0 (the publisher says the vehicle is moving) and the
/// `CompSample::status` bits are the pipeline's own: one definition serves both.
pub use crate::stream::sample::{
    FLAG_MOVING as RAW_FLAG_MOVING, STATUS_GAP, STATUS_MOVING, STATUS_NO_MODEL, STATUS_REJECTED, STATUS_SENSOR_FAULT,
};

/// One raw gyro sample from the INS, on the `gyrocomp/raw` service (56 bytes).
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("gyrocomp::RawSample")]
#[repr(C)]
pub struct RawSample {
    /// Sequence number chosen by the publisher; the answer carries the same value.
    pub seq: u64,
    /// Sample time in nanoseconds (publisher's clock).
    pub t_ns: u64,
    /// Angular rate per axis (x, y, z) in deg/s.
    pub rate_dps: [f64; 3],
    /// Sensor temperature in °C; NaN when unknown.
    pub temp_c: f64,
    /// Bit field; bit 0 ([`RAW_FLAG_MOVING`]) = the publisher says "moving".
    pub flags: u32,
    /// Padding to a multiple of 8 bytes; write 0.
    pub _pad: u32,
}

impl RawSample {
    /// A sample with no temperature (NaN) and no flags.
    pub fn new(seq: u64, t_ns: u64, rate_dps: [f64; 3]) -> Self {
        Self { seq, t_ns, rate_dps, temp_c: f64::NAN, flags: 0, _pad: 0 }
    }

    /// Whether the publisher flagged this sample as moving.
    pub fn is_moving(&self) -> bool {
        self.flags & RAW_FLAG_MOVING != 0
    }

    /// The temperature, or `None` when it is NaN.
    pub fn temperature(&self) -> Option<f64> {
        (!self.temp_c.is_nan()).then_some(self.temp_c)
    }
}

/// One compensated sample, on the `gyrocomp/compensated` service (104 bytes).
/// Every [`RawSample`] yields exactly one, with the same `seq`.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("gyrocomp::CompSample.v2")]
#[repr(C)]
pub struct CompSample {
    /// `seq` of the raw sample this answers.
    pub seq: u64,
    /// `t_ns` of the raw sample this answers.
    pub t_ns: u64,
    /// Compensated angular rate per axis in deg/s (raw − drift).
    pub rate_dps: [f64; 3],
    /// Drift subtracted per axis in deg/s.
    pub drift_dps: [f64; 3],
    /// Version of the model that produced the drift (0 = none yet).
    pub model_version: u64,
    /// Bit field: [`STATUS_NO_MODEL`], [`STATUS_MOVING`], [`STATUS_REJECTED`], [`STATUS_GAP`],
    /// [`STATUS_SENSOR_FAULT`].
    pub status: u32,
    /// Padding to a multiple of 8 bytes; write 0.
    pub _pad: u32,
    /// Standard deviation of `drift_dps` as an estimate of the true drift, per axis, deg/s
    /// (+∞ while unknown): an INS can set its own gyro-bias noise from it.
    pub drift_std_dps: [f64; 3],
}

impl CompSample {
    /// The pass-through answer to `raw`: rate unchanged, zero drift, the given status bits.
    pub fn passthrough(raw: &RawSample, status: u32) -> Self {
        Self {
            seq: raw.seq,
            t_ns: raw.t_ns,
            rate_dps: raw.rate_dps,
            drift_dps: [0.0; 3],
            model_version: 0,
            status,
            _pad: 0,
            drift_std_dps: [f64::INFINITY; 3],
        }
    }
}

/// Kind of the event that produced a [`StatusSample`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum StatusEvent {
    /// Periodic counter report.
    Periodic = 0,
    /// The daemon started and opened its services.
    Started = 1,
    /// A retrained model was swapped in (`model_version` is the new one).
    ModelSwapped = 2,
    /// A retrain was skipped (not enough static data, or motion).
    RetrainSkipped = 3,
    /// A retrain failed (the previous model stays).
    RetrainFailed = 4,
    /// The daemon is shutting down.
    Stopping = 5,
}

impl StatusEvent {
    /// The event for a raw `event` field, `None` for an unknown value.
    pub fn from_u32(value: u32) -> Option<Self> {
        Some(match value {
            0 => Self::Periodic,
            1 => Self::Started,
            2 => Self::ModelSwapped,
            3 => Self::RetrainSkipped,
            4 => Self::RetrainFailed,
            5 => Self::Stopping,
            _ => return None,
        })
    }
}

/// Model events and counters, on the `gyrocomp/status` service (224 bytes).
/// Counters are totals since the daemon started.
#[derive(Debug, Clone, Copy, PartialEq, Default, ZeroCopySend)]
#[type_name("gyrocomp::StatusSample.v3")]
#[repr(C)]
pub struct StatusSample {
    /// Time of this report in nanoseconds (daemon's monotonic clock since start).
    pub t_ns: u64,
    /// Raw samples received.
    pub samples_in: u64,
    /// Compensated samples published.
    pub samples_out: u64,
    /// Raw samples rejected (answered with [`STATUS_REJECTED`]).
    pub rejected: u64,
    /// Samples treated as moving (answered with [`STATUS_MOVING`]).
    pub moving: u64,
    /// Gaps detected: skipped `seq`, timestamp jumps or steps back (answers flagged [`STATUS_GAP`]).
    pub gaps: u64,
    /// Retrains that produced a new model.
    pub retrains_done: u64,
    /// Retrains skipped (not enough static data).
    pub retrains_skipped: u64,
    /// Retrains that failed.
    pub retrains_failed: u64,
    /// Version of the model in use (0 = none yet).
    pub model_version: u64,
    /// `seq` of the last raw sample received.
    pub last_seq: u64,
    /// Duration of the last retrain in nanoseconds (0 = none yet).
    pub last_retrain_ns: u64,
    /// What produced this report, a [`StatusEvent`] as `u32`.
    pub event: u32,
    /// Padding to a multiple of 8 bytes; write 0.
    pub _pad: u32,
    /// Publisher-side send failures (e.g. a lossless subscriber that never drained).
    pub send_failures: u64,
    /// Rejected for a NaN, infinite or out-of-range rate (part of `rejected`).
    pub invalid: u64,
    /// Rejected as spikes by the robust outlier test (part of `rejected`).
    pub spikes: u64,
    /// Rejected for a repeated or decreasing `seq` (part of `rejected`).
    pub duplicates: u64,
    /// Rejected for a timestamp that did not advance (part of `rejected`, also gaps).
    pub time_backwards: u64,
    /// Sequence numbers missing between received samples (sum of the holes).
    pub seq_skipped: u64,
    /// Publisher restarts seen (`seq` back to 0 or far back: a new stream).
    pub restarts: u64,
    /// Static detector: static → moving transitions.
    pub detector_onsets: u64,
    /// Static detector: samples on which a test fired.
    pub detector_alarms: u64,
    /// Static samples committed to the drift estimators (delayed commit).
    pub committed: u64,
    /// Pending static samples discarded as the lead-in of a detected motion (or of a stuck run).
    pub discarded: u64,
    /// Rejected because an axis was stuck, one value repeated for `input.stuck_s` (part of
    /// `rejected`; status bit 4).
    pub stuck: u64,
    /// Rejected because an axis was saturated at `input.range_dps` (part of `rejected`; bit 4).
    pub saturated: u64,
    /// Temperatures ignored as ±∞ or implausible (the samples themselves were used).
    pub bad_temperature: u64,
    /// Static detector: times the drift estimate was relearnt after `[motion] relearn_s` of
    /// unexplained, unchanging "moving" (the deadlock breaker).
    pub relearns: u64,
}

// Layout checks: the byte counts are part of the wire contract (docs/design.md).
const _: () = {
    assert!(size_of::<RawSample>() == 56);
    assert!(align_of::<RawSample>() == 8);
    assert!(size_of::<CompSample>() == 104);
    assert!(align_of::<CompSample>() == 8);
    assert!(size_of::<StatusSample>() == 224);
    assert!(align_of::<StatusSample>() == 8);
};
