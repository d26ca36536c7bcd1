//! Building the pipeline from a configuration: the one construction every driver uses
//! (docs/design.md "One pipeline, three drivers"): `gyrocompd`, `gyrocomp compensate` and, through
//! the daemon, `replay`.

use crate::config::{Config, ConfigError};
use crate::stream::pipeline::{Pipeline, PipelineError};
use crate::stream::retrain::Trainer;

/// Why a pipeline could not be built from a configuration.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// The configuration is invalid (the message names the key).
    #[error("{0}")]
    Config(#[from] ConfigError),
    /// The pipeline refused its settings.
    #[error("pipeline: {0}")]
    Pipeline(#[from] PipelineError),
    /// The retrain thread could not be started.
    #[error("cannot start the retrain thread: {0}")]
    Trainer(#[source] std::io::Error),
}

/// The pipeline of `config` ([`Config::pipeline`]); when its drift estimator takes models
/// (`cpso-lssvm`, `hybrid`), with the CPSO-LSSVM retrainer of `[retrain]` ([`Config::cpso_lssvm`], paper
/// §2.2) attached on its own thread.
pub fn build_pipeline(config: &Config) -> Result<Pipeline, BuildError> {
    let settings = config.pipeline()?;
    let uses_models = settings.drift.kind.uses_models();
    let mut pipeline = Pipeline::new(settings)?;
    if !uses_models {
        return Ok(pipeline);
    }
    // The trainer fits the horizon the estimator forecasts at (the denoiser's lag + 1 for
    // `cpso-lssvm`, one block for `hybrid`).
    let mut fit = config.cpso_lssvm()?;
    if let Some(estimator) = pipeline.estimator(0) {
        fit.embedding = fit.embedding.with_horizon(estimator.model_steps());
    }
    let trainer = Trainer::spawn_niced(fit, config.retrain.nice).map_err(BuildError::Trainer)?;
    pipeline.attach_trainer(trainer);
    Ok(pipeline)
}
