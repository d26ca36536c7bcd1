//! Plain per-sample input and output records of the [`Pipeline`](super::Pipeline).
//!
//! They carry the same fields as the iceoryx2 wire types of docs/design.md ("Wire types":
//! `gyrocomp::RawSample`, `gyrocomp::CompSample`) without the `#[repr(C)]` layout and padding;
//! the IPC layer converts field by field.

/// `flags` bit 0 of an [`InputSample`]: the publisher says the platform is moving.
pub const FLAG_MOVING: u32 = 1 << 0;

/// `status` bit 0: no model was used for this sample (none installed yet, or not enough static
/// history); the drift is the running static bias estimate.
pub const STATUS_NO_MODEL: u32 = 1 << 0;
/// `status` bit 1: the sample is moving; the drift is forecast from the last static state.
pub const STATUS_MOVING: u32 = 1 << 1;
/// `status` bit 2: the input was rejected (NaN/Inf or out of range); the output is a safe
/// substitute and the sample entered no buffer.
pub const STATUS_REJECTED: u32 = 1 << 2;
/// `status` bit 3: a time gap (or a backwards time step) precedes this sample.
pub const STATUS_GAP: u32 = 1 << 3;
/// `status` bit 4: a sensor fault — an axis is saturated (at `input.range_dps`) or stuck (one
/// value repeated for `input.stuck_s`); always with [`STATUS_REJECTED`]: the sample entered no
/// buffer and the stuck run's pending samples were discarded.
pub const STATUS_SENSOR_FAULT: u32 = 1 << 4;

/// One raw three-axis gyro sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputSample {
    /// Sequence number set by the publisher; echoed in the output.
    pub seq: u64,
    /// Timestamp, ns.
    pub t_ns: u64,
    /// Angular rates x, y, z, deg/s.
    pub rate_dps: [f64; 3],
    /// Temperature, °C (NaN = none): the Kalman tracker's temperature term uses it; ±∞ or an
    /// implausible value is ignored (taken as none) and counted.
    pub temp_c: f64,
    /// Publisher flags ([`FLAG_MOVING`]).
    pub flags: u32,
}

/// One compensated sample; exactly one per [`InputSample`], with the same `seq`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputSample {
    /// Sequence number of the input.
    pub seq: u64,
    /// Timestamp of the input, ns.
    pub t_ns: u64,
    /// Compensated rates, deg/s: raw − drift (never NaN).
    pub rate_dps: [f64; 3],
    /// Drift subtracted on each axis, deg/s.
    pub drift_dps: [f64; 3],
    /// Version of the newest installed model (0 = none yet).
    pub model_version: u64,
    /// Status bits ([`STATUS_NO_MODEL`], [`STATUS_MOVING`], [`STATUS_REJECTED`], [`STATUS_GAP`],
    /// [`STATUS_SENSOR_FAULT`]).
    pub status: u32,
    /// Standard deviation of the drift estimate per axis, deg/s (+∞ while unknown).
    pub drift_std_dps: [f64; 3],
}

impl InputSample {
    /// A sample with no temperature and no flags.
    pub fn new(seq: u64, t_ns: u64, rate_dps: [f64; 3]) -> Self {
        Self { seq, t_ns, rate_dps, temp_c: f64::NAN, flags: 0 }
    }
}
