//! Per-sample building blocks of the streaming pipeline: a mirrored ring buffer, the causal
//! wavelet denoiser, the phase-space embedding, the input checks, the motion gate, the model
//! slot, the [`Pipeline`] that chains them for three axes and its background [`Trainer`] — all pure numerics, no I/O —
//! [`build_pipeline`], the construction every driver shares, [`offline`], the driver without
//! IPC, and, at the edge, [`ipc`]: the only module that knows iceoryx2.

pub mod build;
pub mod calibration;
pub mod causal_denoise;
pub mod detector;
pub mod drift;
pub mod embed;
pub mod input_check;
pub mod ipc;
pub mod model_slot;
pub mod motion_gate;
pub mod offline;
pub mod pending;
pub mod period;
pub mod pipeline;
pub mod retrain;
pub mod ring;
pub mod sample;
pub mod snapshot;

pub use build::{BuildError, build_pipeline};
pub use calibration::NoiseCalibration;
pub use causal_denoise::{CausalConfig, CausalConfigError, CausalDenoiser, denoise_causal};
pub use detector::{DetectorCounters, DetectorKind, MotionDetector, StatisticalConfig};
pub use drift::{DriftConfig, DriftEstimate, DriftEstimator, EstimatorKind, KalmanCounters};
pub use embed::{Embedded, Embedding};
pub use input_check::{InputCheck, InputConfig, InputCounters, Verdict};
pub use model_slot::{InstalledModel, ModelSlot, SharedModel};
pub use motion_gate::{MotionConfig, MotionGate};
pub use offline::{OfflineRun, compensate, compensate_recording, offline_config, run_pipeline};
pub use pipeline::{Pipeline, PipelineConfig, PipelineError, PipelineStats};
pub use retrain::{FittedAxis, RetrainMode, RetrainSchedule, TrainRequest, TrainResult, Trainer, TrainerError};
pub use ring::RingBuffer;
pub use sample::{FLAG_MOVING, InputSample, OutputSample, STATUS_GAP, STATUS_MOVING, STATUS_NO_MODEL, STATUS_REJECTED};
