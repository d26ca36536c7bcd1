//! Diagnostics of gyro noise: Allan deviation and the IEEE Std 952 noise-term fit.

pub mod allan;
pub mod noise_fit;
