//! Per-sample building blocks of the streaming pipeline: a mirrored ring buffer, the causal
//! wavelet denoiser, the input checks, the motion gate, the model slot, the [`Pipeline`] that
//! chains them for three axes and its background [`Trainer`] — no I/O, no configuration file.
//! The layer above builds pipelines from the configuration and drives them (`crate::drive`);
//! the phase-space embedding is numerics (`crate::model::embed`); iceoryx2 is `crate::ipc`.

pub mod allan_cascade;
pub mod calibration;
pub mod causal_denoise;
pub mod detector;
pub mod drift;
pub mod input_check;
pub mod model_slot;
pub mod motion_gate;
pub mod pending;
pub mod period;
pub mod pipeline;
mod registry;
pub mod retrain;
pub mod ring;
pub mod sample;
pub mod snapshot;
pub mod warm;

pub use calibration::NoiseCalibration;
pub use causal_denoise::{CausalConfig, CausalConfigError, CausalDenoiser, denoise_causal};
pub use detector::{DetectorCounters, DetectorKind, MotionDetector, StatisticalConfig};
pub use drift::{DriftConfig, DriftEstimate, DriftEstimator, EstimatorKind, KalmanCounters};
pub use input_check::{InputCheck, InputConfig, InputCounters, Verdict};
pub use model_slot::{InstalledModel, ModelSlot, SharedModel};
pub use motion_gate::{MotionConfig, MotionGate};
pub use pipeline::{Pipeline, PipelineConfig, PipelineError, PipelineStats};
pub use retrain::{FittedAxis, RetrainMode, RetrainSchedule, TrainRequest, TrainResult, Trainer, TrainerError};
pub use ring::RingBuffer;
pub use sample::{FLAG_MOVING, InputSample, OutputSample, STATUS_GAP, STATUS_MOVING, STATUS_NO_MODEL, STATUS_REJECTED};
