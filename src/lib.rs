//! gyrocomp — modelling and compensation of MEMS gyroscope random drift.
//!
//! The method follows Sensors 2017, 17, 2335 ("MEMS gyroscope random drift modelling with wavelet
//! denoising, phase-space reconstruction and CPSO-LSSVM"): db4 wavelet denoising, phase-space
//! reconstruction (PSR, delay τ and dimension m chosen by the C-C method), then an LSSVM regression.
//!
//! Module map, by layer (docs/design.md "Layers"; each imports only those above it in this list,
//! `tests/architecture.rs` checks it):
//! - numerics, never touching files, threads or IPC: [`wavelet`] (Daubechies filters,
//!   PyWavelets-compatible `wavedec`/`waverec`, universal soft threshold, batch denoising),
//!   [`model`] (the models behind `Fit`/`Predict`, the phase-space embedding, the C-C method,
//!   scaler, metrics), [`sim`] (seeded IMU error simulator and motion profiles), [`diag`] (Allan
//!   deviation, the IEEE Std 952 noise-term fit, the sim-to-real diagnosis);
//! - [`stream`]: the per-sample [`Pipeline`](stream::Pipeline) and its stages, the retrainer,
//!   snapshot encoding — no I/O, no configuration file;
//! - [`io`] (CSV reading and writing, the edge where files live) and [`ipc`] (iceoryx2);
//! - [`config`] (the configuration file, `configs/default.toml`, [`Config::load`](config::Config::load)),
//!   [`drive`] (pipelines built from it, the offline driver, what the binaries share), [`eval`]
//!   (evaluation protocols, the paper's beside honest baselines), [`daemon`] (`gyrocompd`);
//! - [`cli`]: the `gyrocomp` command-line driver.

#![warn(missing_docs)]

pub mod cli;
pub mod config;
pub mod daemon;
pub mod diag;
pub mod drive;
pub mod eval;
pub mod io;
pub mod ipc;
pub mod model;
pub mod sim;
pub mod stream;
pub mod wavelet;
