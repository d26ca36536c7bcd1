//! The models of the motion-injected protocol ([`super::motion`]), each producing one
//! compensated value per sample of the same stream.
//!
//! Every drift predictor runs through the streaming [`Pipeline`] on the same samples, with the
//! configuration's denoiser, retrain schedule and start-up bias estimate, retraining
//! deterministically ([`offline_config`]); they differ in the model and in the motion gate:
//!
//! | name | model | motion gate |
//! |---|---|---|
//! | `gyrocomp` | the configured `[drift]` estimator ([`build_pipeline`], the daemon's; default Kalman) | the configured `[motion]` detector (default statistical) |
//! | `gyrocomp-flagged` | the same | the same, plus the file's `moving` column as the publisher's flag (an oracle: it says what the detector has to guess) |
//! | `cpso-lssvm` | the paper's CPSO-LSSVM forecaster | the configured detector |
//! | `hybrid` | the Kalman tracker, plus a CPSO-LSSVM forecast of its 10 s block means while moving | the configured detector |
//! | `multiscale` | the multi-scale tracker (random-walk bias plus a fitted Gauss–Markov bank) | the configured detector |
//! | `persistence` | x̃\[t] = the newest denoised sample | none (the `none` detector): it sees the whole stream |
//! | `ar` | AR(p), order by AIC ≤ 20, refitted on the retrain schedule | none (the `none` detector) |
//! | `persistence-gated`, `ar-gated` | the same models | the configured detector, as gyrocomp (what the detector alone is worth) |
//!
//! `bias-hold`, `last-static` and `highpass` need no pipeline: start-up mean; the mean of the last
//! 60 s of samples the file flags static (a zero-rate-update reference that knows when it stops);
//! a causal high-pass.
//!
//! `persistence` and `ar` are one-step predictors of the drift run causally on the stream as it
//! comes: nothing tells them when the platform moves, so a rotation enters their input like
//! drift — exactly their weakness, and what the gate is for. Persistence needs no fit: it is
//! installed before the first sample (until the causal denoiser's first output, the pipeline's
//! running bias estimate stands in, as it does for every model before its first fit). `bias-hold`
//! and `highpass` need no pipeline ([`MotionRun::bias_hold`], [`MotionRun::highpass`]).
//!
//! The recording's rate column is axis x; axes y and z carry 0.0 (a constant axis gets the
//! constant predictor, [`crate::stream::retrain::fit_axis`]).

use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

use serde::Serialize;

use super::models::find_by_name;
use super::motion::{MotionError, MotionRun};
use crate::config::Config;
use crate::drive::{BuildError, build_pipeline, offline_config, run_pipeline};
use crate::model::baselines::{Ar, PersistenceModel};
use crate::model::scaler::MinMaxScaler;
use crate::stream::sample::STATUS_MOVING;
use crate::stream::{DetectorKind, EstimatorKind, FLAG_MOVING, InputSample, Pipeline, Trainer};

/// A model of the motion-injected protocol (module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MotionModel {
    /// The gyrocomp pipeline with its CPSO-LSSVM retrainer and motion gate.
    Gyrocomp,
    /// The same with the file's moving flags given as the publisher's flag (oracle).
    GyrocompFlagged,
    /// Raw minus the mean of the start-up window.
    BiasHold,
    /// Raw minus the mean of the last 60 s of static samples, with the file's flags (ZARU).
    LastStatic,
    /// The pipeline with the `cpso-lssvm` estimator (the paper's method) behind the configured
    /// detector.
    CpsoLssvm,
    /// The pipeline with the `hybrid` estimator (the Kalman tracker plus the paper's model as a
    /// forecaster of the bias trajectory while moving) behind the configured detector.
    Hybrid,
    /// The pipeline with the `multiscale` estimator behind the configured detector.
    Multiscale,
    /// Persistence of the denoised stream, no gate.
    Persistence,
    /// AR(p) on the denoised stream, no gate.
    Ar,
    /// Causal first-order high-pass of the raw rate.
    Highpass,
    /// Persistence behind the motion gate.
    PersistenceGated,
    /// AR(p) behind the motion gate.
    ArGated,
}

impl MotionModel {
    /// Every model, in table order.
    pub const ALL: [Self; 12] = [
        Self::Gyrocomp,
        Self::GyrocompFlagged,
        Self::BiasHold,
        Self::LastStatic,
        Self::CpsoLssvm,
        Self::Hybrid,
        Self::Multiscale,
        Self::Persistence,
        Self::Ar,
        Self::Highpass,
        Self::PersistenceGated,
        Self::ArGated,
    ];

    /// The name on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Self::Gyrocomp => "gyrocomp",
            Self::GyrocompFlagged => "gyrocomp-flagged",
            Self::BiasHold => "bias-hold",
            Self::LastStatic => "last-static",
            Self::CpsoLssvm => "cpso-lssvm",
            Self::Hybrid => "hybrid",
            Self::Multiscale => "multiscale",
            Self::Persistence => "persistence",
            Self::Ar => "ar",
            Self::Highpass => "highpass",
            Self::PersistenceGated => "persistence-gated",
            Self::ArGated => "ar-gated",
        }
    }

    /// Whether the model runs through the pipeline (and so takes a while on long runs).
    pub fn uses_pipeline(self) -> bool {
        !matches!(self, Self::BiasHold | Self::Highpass | Self::LastStatic)
    }
}

impl fmt::Display for MotionModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for MotionModel {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        find_by_name(&Self::ALL, Self::name, s, "motion-protocol model")
    }
}

/// Window of `last-static`, s (the ZARU reference of issue 13).
pub const LAST_STATIC_S: f64 = 60.0;

/// Settings of the baselines that need no pipeline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BaselineSettings {
    /// Start-up window of `bias-hold`, s.
    pub startup_s: f64,
    /// Cutoff of `highpass`, Hz.
    pub highpass_hz: f64,
}

/// One model's compensated series and a short description of what ran.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelOutput {
    /// Compensated rate of the rate column, one per sample, deg/s.
    pub compensated: Vec<f64>,
    /// What ran (models installed, samples gated, …).
    pub detail: String,
    /// The pipeline's judgement of each sample (`STATUS_MOVING` of its output: detector alarm,
    /// publisher flag or hold-off), for the models that run the pipeline; `None` for the
    /// baselines computed without it.
    pub judged_moving: Option<Vec<bool>>,
}

/// Why a model could not run.
#[derive(Debug, thiserror::Error)]
pub enum MotionModelError {
    /// The pipeline could not be built.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// A baseline's settings or the run are unusable.
    #[error(transparent)]
    Motion(#[from] MotionError),
}

/// The pipeline of a pipeline model, from the offline configuration.
fn pipeline(model: MotionModel, config: &Config) -> Result<Pipeline, BuildError> {
    let mut settings = config.pipeline()?;
    // The baseline predictors forecast the denoised stream: the model forecaster's machinery.
    settings.drift.kind = EstimatorKind::CpsoLssvm;
    if matches!(model, MotionModel::Persistence | MotionModel::Ar) {
        // No gate: the model sees the whole stream (no file flags are given to these models).
        settings.detector = DetectorKind::None;
    }
    let mut p = match model {
        MotionModel::Gyrocomp | MotionModel::GyrocompFlagged => return build_pipeline(config),
        MotionModel::CpsoLssvm | MotionModel::Hybrid | MotionModel::Multiscale => {
            let mut c = config.clone();
            c.drift.kind = match model {
                MotionModel::Hybrid => EstimatorKind::Hybrid,
                MotionModel::Multiscale => EstimatorKind::Multiscale,
                _ => EstimatorKind::CpsoLssvm,
            };
            return build_pipeline(&c);
        }
        _ => Pipeline::new(settings)?,
    };
    if matches!(model, MotionModel::Persistence | MotionModel::PersistenceGated) {
        // Persistence is scale-free: any scaler gives the same forecast.
        let identity = MinMaxScaler { min: -1.0, max: 1.0 };
        for axis in 0..3 {
            p.install_model(axis, Arc::new(PersistenceModel), identity, 1)?;
        }
    } else {
        p.attach_trainer(Trainer::spawn(Ar::default()).map_err(BuildError::Trainer)?);
    }
    Ok(p)
}

/// Runs `model` on the stream `inputs` (the rate column on axis x, no flags; `moving` gives the
/// file's flags for `gyrocomp-flagged`), calling `progress(samples_done)` as it goes.
pub fn run_motion_model(
    model: MotionModel,
    config: &Config,
    run: &MotionRun,
    inputs: &[InputSample],
    moving: &[bool],
    baselines: BaselineSettings,
    progress: &mut dyn FnMut(usize),
) -> Result<ModelOutput, MotionModelError> {
    match model {
        MotionModel::BiasHold => {
            let b = run.bias_hold(baselines.startup_s)?;
            let detail = format!("mean of the first {} samples: {:.6} deg/s", b.samples, b.bias_dps);
            return Ok(ModelOutput { compensated: b.compensated, detail, judged_moving: None });
        }
        MotionModel::LastStatic => {
            let detail = format!("mean of the last {LAST_STATIC_S} s of samples flagged static");
            return Ok(ModelOutput {
                compensated: run.last_static(moving, LAST_STATIC_S)?,
                detail,
                judged_moving: None,
            });
        }
        MotionModel::Highpass => {
            let detail = format!("first-order RC, cutoff {} Hz", baselines.highpass_hz);
            return Ok(ModelOutput { compensated: run.highpass(baselines.highpass_hz)?, detail, judged_moving: None });
        }
        _ => {}
    }
    let config = offline_config(config);
    let mut p = pipeline(model, &config)?;
    let flagged = model == MotionModel::GyrocompFlagged;
    let stream = inputs.iter().enumerate().map(|(i, s)| {
        let flags = if flagged && moving.get(i).copied().unwrap_or(false) { FLAG_MOVING } else { 0 };
        InputSample { flags, ..*s }
    });
    let mut compensated = Vec::with_capacity(inputs.len());
    let mut judged_moving = Vec::with_capacity(inputs.len());
    let done = run_pipeline(&mut p, stream, |i, out| {
        compensated.push(out.rate_dps[0]);
        judged_moving.push(out.status & STATUS_MOVING != 0);
        progress(i + 1);
    });
    let s = done.stats;
    let gate = if matches!(model, MotionModel::Persistence | MotionModel::Ar) { "no gate" } else { "gate" };
    let detail = format!(
        "{gate}, {} samples held as moving, {} models installed, {} fits failed",
        s.moving, s.models_installed, s.retrain_failed
    );
    Ok(ModelOutput { compensated, detail, judged_moving: Some(judged_moving) })
}
