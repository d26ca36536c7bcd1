//! gyrocomp — modelling and compensation of MEMS gyroscope random drift.
//!
//! The method follows Sensors 2017, 17, 2335 ("MEMS gyroscope random drift modelling with wavelet
//! denoising, phase-space reconstruction and CPSO-LSSVM"): db4 wavelet denoising, phase-space
//! reconstruction (PSR, delay τ and dimension m chosen by the C-C method), then an LSSVM regression.
//!
//! Module map (pure numerics never touch files, threads or IPC):
//! - [`wavelet`]: Daubechies filters, PyWavelets-compatible `wavedec`/`waverec`, universal soft
//!   threshold, batch denoising.
//! - [`sim`]: seeded IMU error simulator (presets, TOML configs) and known motion profiles.
//! - [`stream`]: per-sample building blocks: ring buffer, causal wavelet denoiser, PSR embedding.
//! - [`model`]: the [-1, 1] scaler (Eq. 21) and the C-C method (Eq. 18–20).
//! - [`diag`]: Allan deviation and the IEEE Std 952 noise-term fit.
//! - [`eval`]: evaluation protocols (the paper's, beside honest baselines).
//! - [`config`]: the configuration file (`configs/default.toml`).
//! - [`io`]: CSV reading and writing (the edge where files live).
//! - [`cli`]: the `gyrocomp` command-line driver.
//! - [`daemon`]: `gyrocompd`, the iceoryx2 sidecar daemon (pipeline, retrainer, signals).

#![warn(missing_docs)]

pub mod cli;
pub mod config;
pub mod daemon;
pub mod diag;
pub mod eval;
pub mod io;
pub mod model;
pub mod sim;
pub mod stream;
pub mod wavelet;
