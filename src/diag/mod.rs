//! Diagnostics of gyro noise: the overlapping Allan deviation ([`allan`]), the IEEE Std 952
//! noise-term fit ([`noise_fit`]) with its confidence intervals ([`fit_intervals`]) and its Kalibr `imu.yaml` form ([`kalibr`]), the Welch PSD ([`psd`], on the FFT of [`fft`]) and the
//! sim-to-real gap diagnosis ([`simgap`]). Pure numerics: no files, no printing.

pub mod allan;
pub mod fft;
pub mod fit_intervals;
pub mod kalibr;
pub mod noise_fit;
pub mod noise_model;
pub mod pairwise;
pub mod psd;
pub mod simgap;
