//! `sensor_msgs/msg/Imu` (ROS 2 common_interfaces) decoded from CDR ([`super::cdr`]).
//!
//! Field order, as the message definition gives it (every field is read, so the offsets of
//! the ones that follow stay aligned, and a short message is found wherever it ends):
//! `header` (`std_msgs/Header`: `stamp` = `builtin_interfaces/Time` {int32 sec, uint32
//! nanosec}, `string frame_id`), `geometry_msgs/Quaternion orientation` (x, y, z, w),
//! `float64[9] orientation_covariance`, `geometry_msgs/Vector3 angular_velocity` (x, y, z,
//! rad/s), `float64[9] angular_velocity_covariance`, `geometry_msgs/Vector3 linear_acceleration`
//! (m/s²), `float64[9] linear_acceleration_covariance`.

use super::cdr::{CdrError, CdrErrorKind, CdrReader};

/// The ROS 2 type name of the message, as an MCAP schema names it.
pub const IMU_SCHEMA: &str = "sensor_msgs/msg/Imu";
/// Nanoseconds per second.
const NS_PER_S: u64 = 1_000_000_000;

/// The fields of one `sensor_msgs/msg/Imu` that gyrocomp uses or checks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuMessage<'a> {
    /// `header.stamp.sec`.
    pub stamp_sec: i32,
    /// `header.stamp.nanosec`, below 10⁹.
    pub stamp_nanosec: u32,
    /// `header.frame_id`.
    pub frame_id: &'a str,
    /// `orientation` x, y, z, w.
    pub orientation: [f64; 4],
    /// `angular_velocity` x, y, z, rad/s.
    pub angular_velocity: [f64; 3],
    /// `linear_acceleration` x, y, z, m/s².
    pub linear_acceleration: [f64; 3],
}

impl ImuMessage<'_> {
    /// The header stamp in ns since the epoch, `sec · 10⁹ + nanosec`; `None` before the epoch
    /// (negative `sec`), which has no `u64` timestamp.
    pub fn stamp_ns(&self) -> Option<u64> {
        u64::try_from(self.stamp_sec).ok().map(|s| s * NS_PER_S + u64::from(self.stamp_nanosec))
    }
}

/// Decodes one CDR-encoded `sensor_msgs/msg/Imu`; the error names the field where it fails.
pub fn decode_imu(data: &[u8]) -> Result<ImuMessage<'_>, CdrError> {
    let mut r = CdrReader::new(data)?;
    let stamp_sec = r.i32("header.stamp.sec")?;
    let at = r.position();
    let stamp_nanosec = r.u32("header.stamp.nanosec")?;
    if u64::from(stamp_nanosec) >= NS_PER_S {
        return Err(CdrError {
            field: "header.stamp.nanosec",
            offset: at,
            kind: CdrErrorKind::OutOfRange(format!("{stamp_nanosec} is not below 10⁹ ns")),
        });
    }
    let frame_id = r.string("header.frame_id")?;
    let orientation = r.f64_array::<4>("orientation")?;
    r.f64_array::<9>("orientation_covariance")?;
    let angular_velocity = [r.f64("angular_velocity.x")?, r.f64("angular_velocity.y")?, r.f64("angular_velocity.z")?];
    r.f64_array::<9>("angular_velocity_covariance")?;
    let linear_acceleration = r.f64_array::<3>("linear_acceleration")?;
    r.f64_array::<9>("linear_acceleration_covariance")?;
    r.finish()?;
    Ok(ImuMessage { stamp_sec, stamp_nanosec, frame_id, orientation, angular_velocity, linear_acceleration })
}
