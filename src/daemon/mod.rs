//! `gyrocompd`, the sidecar daemon (docs/design.md "One pipeline, three drivers", driver 1): raw gyro
//! samples in over iceoryx2, one compensated sample out per raw sample (same `seq`), model events
//! and counters on the status service, a background retrainer, and signal handling.
//!
//! - [`convert`]: wire types ⇄ pipeline records, pipeline counters → `StatusSample`.
//! - [`signals`]: SIGTERM/SIGINT (stop) and SIGHUP (reload) as atomic flags.
//! - [`logging`]: the `[log]` section → a `tracing` subscriber.
//! - [`reload`]: applying a reloaded configuration to a running pipeline.
//! - [`instance_lock`]: the state directory's lock (one daemon per state directory).
//! - [`state`]: the model snapshot file (atomic writes on a writer thread, loading at start).
//! - [`errors`]: why the daemon could not start.
//! - [`run`]: the loop; `startup.rs` builds what it runs on, `worker.rs` answers each sample.

pub mod convert;
pub mod errors;
pub mod instance_lock;
pub mod logging;
pub mod reload;
pub mod run;
pub mod signals;
mod startup;
pub mod state;
mod worker;

pub use errors::DaemonError;
pub use run::{Daemon, RunSummary};
pub use signals::Signals;
