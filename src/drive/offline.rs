//! The offline driver (docs/design.md "One pipeline, three drivers", driver 3): a recording in, one
//! [`OutputSample`] per sample out, through the same [`Pipeline`] and retrainer as the daemon
//! ([`build_pipeline`]), with no IPC. `gyrocomp compensate` and the motion-injected evaluation
//! use it; `replay` sends the same [`InputSample`]s through `gyrocompd`.
//!
//! Offline runs retrain deterministically: [`offline_config`] sets `retrain.mode =
//! "deterministic"` (a request every `retrain.every_samples` samples, its model applied exactly
//! `retrain.apply_delay_samples` samples later, waiting for the fit if needed) whatever the file
//! says, and logs a note when it changes the mode. Live mode retrains by wall time, which offline
//! would make the output depend on the machine's speed; deterministic mode makes two runs — and
//! a replay through a daemon configured the same way — identical, bit for bit.

use super::build::{BuildError, build_pipeline};
use crate::config::Config;
use crate::io::Recording;
use crate::stream::pipeline::{Pipeline, PipelineStats};
use crate::stream::retrain::RetrainMode;
use crate::stream::sample::{InputSample, OutputSample};

/// What an offline run did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OfflineRun {
    /// The pipeline's counters at the end.
    pub stats: PipelineStats,
    /// Version of the newest model installed (0 = none).
    pub model_version: u64,
}

/// `config` as offline runs use it: `retrain.mode = "deterministic"` (module documentation);
/// logs a note when the mode was something else.
pub fn offline_config(config: &Config) -> Config {
    let mut config = config.clone();
    let schedule = &mut config.retrain.schedule;
    if schedule.mode != RetrainMode::Deterministic {
        tracing::info!(
            configured = %schedule.mode,
            every_samples = schedule.every_samples,
            apply_delay_samples = schedule.apply_delay_samples,
            "offline run: retrain.mode = \"deterministic\" (every_samples, apply_delay_samples) so that runs are reproducible"
        );
        schedule.mode = RetrainMode::Deterministic;
    }
    config
}

/// Feeds `inputs` to `pipeline` in order and calls `on_output(index, &output)` for each, index
/// counting from 0.
pub fn run_pipeline(
    pipeline: &mut Pipeline,
    inputs: impl IntoIterator<Item = InputSample>,
    mut on_output: impl FnMut(usize, &OutputSample),
) -> OfflineRun {
    for (index, input) in inputs.into_iter().enumerate() {
        let out = pipeline.process(&input);
        on_output(index, &out);
    }
    OfflineRun { stats: pipeline.stats(), model_version: pipeline.model_version() }
}

/// Compensates `inputs` offline with the pipeline of [`offline_config`]`(config)`.
pub fn compensate(
    config: &Config,
    inputs: impl IntoIterator<Item = InputSample>,
    on_output: impl FnMut(usize, &OutputSample),
) -> Result<OfflineRun, BuildError> {
    let mut pipeline = build_pipeline(&offline_config(config))?;
    Ok(run_pipeline(&mut pipeline, inputs, on_output))
}

/// Compensates every sample of `rec` ([`Recording::input`]); `on_output` receives the sample's
/// index in the recording, which is also its `seq`.
pub fn compensate_recording(
    config: &Config,
    rec: &Recording,
    on_output: impl FnMut(usize, &OutputSample),
) -> Result<OfflineRun, BuildError> {
    compensate(config, rec.inputs(), on_output)
}
