//! Per-sample building blocks of the streaming pipeline (pure numerics, no I/O):
//! a mirrored ring buffer, the causal wavelet denoiser and the phase-space embedding.

pub mod causal_denoise;
pub mod embed;
pub mod ipc;
pub mod ring;

pub use causal_denoise::{CausalConfig, CausalConfigError, CausalDenoiser, denoise_causal};
pub use embed::{Embedded, Embedding};
pub use ring::RingBuffer;
