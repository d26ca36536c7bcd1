//! Discrete wavelet transforms and wavelet denoising, compatible with PyWavelets 1.x.
//!
//! - [`filters`]: the Daubechies family db1–db10 ([`Wavelet`]).
//! - [`dwt`]: single-level and multilevel transforms with PyWavelets' `symmetric` boundary mode
//!   (`pywt.dwt`, `pywt.idwt`, `pywt.wavedec`, `pywt.waverec`).
//! - [`threshold`]: the universal (VisuShrink) threshold and soft thresholding.
//! - [`denoise`]: the paper's denoising step (§3 Step 1, §4.2: db4, three levels, soft threshold)
//!   as a planned, allocation-free [`Denoiser`].

pub mod denoise;
pub mod dwt;
pub mod filters;
pub mod threshold;

pub use denoise::{DenoiseConfig, DenoiseReport, Denoiser, denoise_batch};
pub use filters::Wavelet;
