//! Evaluation protocols of design.md ("Evaluation protocols"): the paper's protocol, with every
//! model scored beside the honest baselines on the same split.

pub mod models;
pub mod paper;

pub use paper::{PaperProtocol, PaperScores, Prepared};
