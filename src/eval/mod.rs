//! Evaluation protocols of docs/design.md ("Evaluation protocols"): the paper's protocol, with every
//! model scored beside the honest baselines on the same split, and the motion-injected protocol
//! (compensated rate and integrated angle against a known injected motion).

pub mod detection;
pub mod models;
pub mod motion;
pub mod motion_models;
pub mod paper;

pub use detection::{DetectionScores, detection_scores};
pub use motion::{MotionRun, MotionScores};
pub use motion_models::{BaselineSettings, MotionModel, run_motion_model};
pub use paper::{PaperProtocol, PaperScores, Prepared};
