//! The models an evaluation can run, by name, each fitted on the same training series and asked
//! for the same one-step predictions, so that the paper's models always stand beside the
//! baselines.

use std::fmt;
use std::str::FromStr;
use std::time::Instant;

use serde::Serialize;

use super::paper::Prepared;
use crate::model::baselines::{Ar, BiasHold, LinearPsr, Mean, Persistence};
use crate::model::bp_ann::BpAnn;
use crate::model::embed::Embedding;
use crate::model::lssvm::{CpsoLssvm, LssvmConfig};
use crate::model::{Fit, FitError, Predict, predict_from};

/// A model an evaluation can run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModelKind {
    /// The paper's model: LSSVM with (γ, σ²) tuned by CPSO.
    CpsoLssvm,
    /// LSSVM with fixed (γ, σ²) (default: the paper's γ = 29.358, σ² = 83.162), exact solve.
    Lssvm,
    /// The paper's BP-ANN (3-10-1, Levenberg–Marquardt).
    BpAnn,
    /// `x̂[t+1] = x[t]`.
    Persistence,
    /// AR(p), order by AIC.
    Ar,
    /// The training mean.
    Mean,
    /// The mean of the first samples of the run, held.
    BiasHold,
    /// Linear regression on the PSR lags.
    LinearPsr,
}

impl ModelKind {
    /// Every model, paper models first.
    pub const ALL: [Self; 8] = [
        Self::CpsoLssvm,
        Self::Lssvm,
        Self::BpAnn,
        Self::Persistence,
        Self::Ar,
        Self::Mean,
        Self::BiasHold,
        Self::LinearPsr,
    ];

    /// The name used on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Self::CpsoLssvm => "cpso-lssvm",
            Self::Lssvm => "lssvm",
            Self::BpAnn => "bp-ann",
            Self::Persistence => "persistence",
            Self::Ar => "ar",
            Self::Mean => "mean",
            Self::BiasHold => "bias-hold",
            Self::LinearPsr => "linear-psr",
        }
    }
}

impl fmt::Display for ModelKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ModelKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        find_by_name(&Self::ALL, Self::name, s, "model")
    }
}

/// The entry of `all` called `s` by `name`, or an error naming `s` (an unknown `what`) and
/// listing the known names.
pub(crate) fn find_by_name<T: Copy>(all: &[T], name: fn(T) -> &'static str, s: &str, what: &str) -> Result<T, String> {
    all.iter().copied().find(|&k| name(k) == s).ok_or_else(|| {
        let known: Vec<&str> = all.iter().map(|&k| name(k)).collect();
        format!("unknown {what} `{s}`; known: {}", known.join(", "))
    })
}

/// Settings shared by the models of one evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelOptions {
    /// Embedding of the PSR-based models.
    pub embedding: Embedding,
    /// Seed of the stochastic models.
    pub seed: u64,
    /// Samples averaged by the start-up bias-hold.
    pub bias_hold_samples: usize,
    /// γ of the fixed-parameter LSSVM.
    pub gamma: f64,
    /// σ² of the fixed-parameter LSSVM.
    pub sigma2: f64,
}

/// One model's test predictions and what its fit cost.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelRun {
    /// Which model.
    pub kind: ModelKind,
    /// Normalised one-step predictions of the test targets.
    pub predictions: Vec<f64>,
    /// Wall time of the fit, seconds.
    pub train_s: f64,
    /// LSSVM regularisation γ, when the model has one.
    pub gam: Option<f64>,
    /// LSSVM kernel width σ², when the model has one.
    pub sig2: Option<f64>,
    /// A short description of the fitted model (chosen order, stopping reason, …).
    pub detail: String,
}

/// Fits `config` on the training series and predicts every test target.
fn fit_and_predict<F: Fit>(config: &F, data: &Prepared) -> Result<(F::Model, Vec<f64>, f64), FitError> {
    let started = Instant::now();
    let model = config.fit(data.train())?;
    let train_s = started.elapsed().as_secs_f64();
    let predictions = predict_from(&model, &data.normalised, data.train_end);
    debug_assert!(model.history_len() <= data.train_end);
    Ok((model, predictions, train_s))
}

/// Runs one model on prepared data.
pub fn run_model(kind: ModelKind, data: &Prepared, options: &ModelOptions) -> Result<ModelRun, FitError> {
    let mut hyper = (None, None);
    let (predictions, train_s, detail) = match kind {
        ModelKind::CpsoLssvm => {
            let mut config = CpsoLssvm { embedding: options.embedding, ..CpsoLssvm::default() };
            config.cpso.seed = options.seed;
            let (model, p, s) = fit_and_predict(&config, data)?;
            hyper = (Some(model.gamma), Some(model.sigma2));
            (
                p,
                s,
                format!(
                    "{:?}, {} CPSO evaluations, held-out fitness {:.4}",
                    model.solver, model.evaluations, model.fitness
                ),
            )
        }
        ModelKind::Lssvm => {
            let config = LssvmConfig { gamma: options.gamma, sigma2: options.sigma2, embedding: options.embedding };
            let (_, p, s) = fit_and_predict(&config, data)?;
            hyper = (Some(options.gamma), Some(options.sigma2));
            (p, s, "exact".to_owned())
        }
        ModelKind::BpAnn => {
            let config = BpAnn { embedding: options.embedding, seed: options.seed, ..BpAnn::default() };
            let (model, p, s) = fit_and_predict(&config, data)?;
            let report = model.report();
            (p, s, format!("3-{}-1, {:?} after {} epochs", config.hidden, report.stop, report.epochs))
        }
        ModelKind::Persistence => {
            let (_, p, s) = fit_and_predict(&Persistence, data)?;
            (p, s, String::new())
        }
        ModelKind::Ar => {
            let (model, p, s) = fit_and_predict(&Ar::default(), data)?;
            (p, s, format!("order {} (AIC)", model.order()))
        }
        ModelKind::Mean => {
            let (_, p, s) = fit_and_predict(&Mean, data)?;
            (p, s, String::new())
        }
        ModelKind::BiasHold => {
            let (_, p, s) = fit_and_predict(&BiasHold { samples: options.bias_hold_samples }, data)?;
            (p, s, format!("first {} samples", options.bias_hold_samples))
        }
        ModelKind::LinearPsr => {
            let (_, p, s) = fit_and_predict(&LinearPsr { embedding: options.embedding }, data)?;
            (p, s, String::new())
        }
    };
    Ok(ModelRun { kind, predictions, train_s, gam: hyper.0, sig2: hyper.1, detail })
}
