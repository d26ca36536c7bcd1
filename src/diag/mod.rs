//! Diagnostics of gyro noise: the overlapping Allan deviation ([`allan`]) and the IEEE Std 952
//! noise-term fit ([`noise_fit`]). Pure numerics: no files, no printing.

pub mod allan;
pub mod noise_fit;
pub mod noise_model;
pub mod pairwise;
