//! IMU error simulator and motion profiles (issue 4).
//!
//! - [`config`]: the per-axis gyro error model and temperature trajectory (serde/TOML, units in the
//!   key names, unknown keys rejected).
//! - [`rng`]: seeded, reproducible random streams, one per term and axis.
//! - [`terms`]: the error terms as state machines (Gauss–Markov, flicker bank, random walk, jumps,
//!   spikes, quantiser, temperature bias with hysteresis, ramp/warm-up/sinusoids).
//! - [`temperature`]: the temperature trajectory written to `temp_c`.
//! - [`generator`]: the planned generator (config + seed → samples, in blocks).
//! - [`theory`]: exact Allan variance of the sampled terms, to check the generator against.
//! - [`presets`]: `paper`, `adis16405`, `mpu6050`.
//! - [`motion`]: known motion profiles added to static recordings (motion-injected evaluation).
//!
//! Pure numerics: nothing here reads or writes files.

pub mod config;
pub mod generator;
pub mod motion;
pub mod presets;
pub mod rng;
pub mod temperature;
pub mod terms;
pub mod theory;

pub use config::{
    AxisConfig, BiasInstability, ConfigError, Jumps, Quantization, QuantizationMode, SimConfig, Sinusoid, Spikes,
    TemperatureCoefficient, TemperatureConfig, TemperatureRamp, Warmup,
};
pub use generator::{AXIS_NAMES, AxisGenerator, AxisSeries, Generator, SimOutput};
pub use motion::{MotionKind, MotionPlan, MotionSegment};
pub use presets::Preset;
