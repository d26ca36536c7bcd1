//! Driving the pipeline from the configuration file (docs/design.md "One pipeline, three
//! drivers"): [`build_pipeline`], the construction every driver shares, [`offline`], the
//! driver without IPC (a [`Recording`](crate::io::Recording) in, one output per sample out), and
//! what every binary shares ([`error_chain`]). Above `stream`, `io` and `ipc`; below the daemon,
//! the CLI and the binaries.

pub mod build;
pub mod errors;
pub mod offline;

pub use build::{BuildError, build_pipeline};
pub use errors::error_chain;
pub use offline::{OfflineRun, compensate, compensate_recording, offline_config, run_pipeline};
