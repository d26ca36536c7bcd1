//! Per-sample building blocks of the streaming pipeline: a mirrored ring buffer, the causal
//! wavelet denoiser, the phase-space embedding, the motion gate, the model slot, the [`Pipeline`]
//! that chains them for three axes and its background [`Trainer`] — all pure numerics, no I/O —
//! and, at the edge, [`ipc`]: the only module that knows iceoryx2.

mod axis;
pub mod causal_denoise;
pub mod embed;
pub mod ipc;
pub mod model_slot;
pub mod motion_gate;
pub mod pipeline;
pub mod retrain;
pub mod ring;
pub mod sample;
pub mod snapshot;

pub use causal_denoise::{CausalConfig, CausalConfigError, CausalDenoiser, denoise_causal};
pub use embed::{Embedded, Embedding};
pub use model_slot::{InstalledModel, ModelSlot, SharedModel};
pub use motion_gate::{MotionConfig, MotionGate};
pub use pipeline::{InputConfig, Pipeline, PipelineConfig, PipelineError, PipelineStats};
pub use retrain::{FittedAxis, RetrainMode, RetrainSchedule, TrainRequest, TrainResult, Trainer, TrainerError};
pub use ring::RingBuffer;
pub use sample::{FLAG_MOVING, InputSample, OutputSample, STATUS_GAP, STATUS_MOVING, STATUS_NO_MODEL, STATUS_REJECTED};
