//! `replay`: feeds a recorded gyro CSV through `gyrocompd` over iceoryx2 and collects one
//! compensated sample per recorded sample (docs/design.md "One pipeline, three drivers", driver 2).
//!
//! - [`connect`]: the client ports in the configured iceoryx2 domain, and whether a daemon is
//!   already serving it.
//! - [`embedded`]: with no daemon running, one started in-process in a private domain (the same
//!   `gyrocomp::daemon::Daemon` the `gyrocompd` binary runs).
//! - [`stream`]: the lossless send/receive loop (`--max` or paced at the recording's rate × X).
//! - [`summary`]: what a replay reports (`--json`).
//! - [`main_job`]: the main job's report, its recordings pooled.
//!
//! The samples are the offline driver's ([`gyrocomp::io::Recording::input`]: `seq` = row index,
//! one t_s → t_ns conversion), sent as [`gyrocomp::daemon::convert::raw_from_input`], and the
//! answers are written with the same [`gyrocomp::io::CompensatedCsvWriter`] as `gyrocomp
//! compensate`, so with deterministic retraining the two files are equal byte for byte.

#![warn(missing_docs)]

pub mod connect;
pub mod embedded;
pub mod main_job;
pub mod stream;
pub mod summary;

pub use connect::{Client, ClientError};
pub use embedded::{EmbeddedDaemon, EmbeddedError};
pub use stream::{Pacing, ReplayError, ReplayOptions, ReplayResult, replay};
pub use summary::Summary;
