//! The paper's BP-ANN (§2.1, Eq. 1–3; §4.3): a 3-10-1 feed-forward network on the PSR rows
//! (Eq. 15–16, τ = 10, m = 3) with a logistic-sigmoid hidden layer, trained by back-propagation.
//!
//! Choices the paper leaves to MATLAB, made here as MATLAB's defaults:
//! - Output activation: linear, not the sigmoid the paper names (see [`OutputActivation`]).
//! - Optimiser: Levenberg–Marquardt (`trainlm`, the default trainer), μ = 0.001, μ_dec = 0.1,
//!   μ_inc = 10, μ_max = 1e10, at most 1000 epochs, min_grad = 1e-7, goal = 0 (see `lm`).
//! - Early stopping: 15 % of the training rows form a validation set (MATLAB `dividerand`'s
//!   validation share; no separate test share — the outer 80/20 split is the test), chosen at
//!   random by default; training stops after 6 epochs without validation improvement
//!   (`max_fail`) and keeps the best-validation weights.
//! - Initialisation: Nguyen–Widrow (`initnw`), seeded [`SplitMix64`]; fully deterministic per seed.
//!
//! Inputs and targets are expected in normalised units (Eq. 21); MATLAB's own `mapminmax`
//! pre-processing is not repeated.

mod lm;
mod net;

pub use net::OutputActivation;

use serde::{Deserialize, Serialize};

use super::baselines::check_series;
use super::baselines::linear_psr::check_embedding;
use super::{Fit, FitError, Predict};
use crate::model::embed::Embedding;
use crate::model::rng::SplitMix64;
use lm::{LmSettings, Rows};
use net::Layout;

/// How the validation rows are drawn from the training rows.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ValSplit {
    /// A seeded random subset (MATLAB `dividerand`, the default).
    #[default]
    Random,
    /// The last rows in time (MATLAB `divideblock`): no validation row lies between training rows.
    Tail,
}

/// BP-ANN configuration (paper §2.1, §4.3; MATLAB `feedforwardnet` + `trainlm` defaults).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct BpAnn {
    /// PSR delay and dimension; the input layer has m neurons. Default τ = 10, m = 3.
    pub embedding: Embedding,
    /// Hidden neurons H. Default 10 (paper §4.3).
    pub hidden: usize,
    /// Output activation. Default linear.
    pub output: OutputActivation,
    /// Maximum LM epochs. Default 1000.
    pub max_epochs: usize,
    /// Initial Marquardt μ. Default 0.001.
    pub mu: f64,
    /// μ factor after a successful step (0 < μ_dec < 1). Default 0.1.
    pub mu_dec: f64,
    /// μ factor after a failed step (> 1). Default 10.
    pub mu_inc: f64,
    /// Training stops when μ exceeds this. Default 1e10.
    pub mu_max: f64,
    /// Training stops when the MSE gradient norm falls below this. Default 1e-7.
    pub min_grad: f64,
    /// Training stops when the training MSE reaches this. Default 0.
    pub goal: f64,
    /// Share of training rows held out for early stopping, in [0, 0.5]. Default 0.15; 0 disables.
    pub val_fraction: f64,
    /// How validation rows are chosen. Default random.
    pub val_split: ValSplit,
    /// Consecutive epochs without validation improvement before stopping. Default 6.
    pub max_fail: usize,
    /// Seed of the initialisation and the random split.
    pub seed: u64,
}

impl Default for BpAnn {
    fn default() -> Self {
        Self {
            embedding: Embedding::PAPER,
            hidden: 10,
            output: OutputActivation::Linear,
            max_epochs: 1000,
            mu: 1e-3,
            mu_dec: 0.1,
            mu_inc: 10.0,
            mu_max: 1e10,
            min_grad: 1e-7,
            goal: 0.0,
            val_fraction: 0.15,
            val_split: ValSplit::Random,
            max_fail: 6,
            seed: 0x5EED,
        }
    }
}

/// Why LM training stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// `max_epochs` reached.
    MaxEpochs,
    /// Training MSE ≤ `goal`.
    Goal,
    /// Gradient norm below `min_grad`.
    MinGradient,
    /// μ exceeded `mu_max` without a successful step.
    MuMax,
    /// `max_fail` epochs without validation improvement.
    ValidationFailures,
}

/// Summary of one training run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrainReport {
    /// Epochs run (successful LM steps).
    pub epochs: usize,
    /// Epoch of the returned weights (best validation MSE, or the last epoch without validation).
    pub best_epoch: usize,
    /// Why training stopped.
    pub stop: StopReason,
    /// Training MSE of the returned weights (normalised units²).
    pub train_mse: f64,
    /// Validation MSE of the returned weights, if there was a validation set.
    pub val_mse: Option<f64>,
    /// Rows used for the LM steps.
    pub train_rows: usize,
    /// Rows held out for early stopping.
    pub val_rows: usize,
}

/// A fitted n₀–H–1 network (Eq. 1–3 plus the output neuron), independent of any embedding.
#[derive(Debug, Clone, PartialEq)]
pub struct Net {
    layout: Layout,
    params: Vec<f64>,
}

impl Net {
    /// Input neurons n₀.
    pub fn inputs(&self) -> usize {
        self.layout.inputs
    }

    /// Hidden neurons H.
    pub fn hidden(&self) -> usize {
        self.layout.hidden
    }

    /// All weights and thresholds, `[W (H × n₀, row-major) | b (H) | w2 (H) | b2]`.
    pub fn params(&self) -> &[f64] {
        &self.params
    }

    /// Output for one input vector (`x.len() == inputs()`; extra values are ignored).
    pub fn eval(&self, x: &[f64]) -> f64 {
        self.layout.forward(&self.params, |j| x[j])
    }
}

/// Fitted BP-ANN predictor: the network applied to the latest PSR row.
#[derive(Debug, Clone, PartialEq)]
pub struct BpAnnModel {
    embedding: Embedding,
    net: Net,
    report: TrainReport,
}

impl BpAnnModel {
    /// The embedding the model reads.
    pub fn embedding(&self) -> Embedding {
        self.embedding
    }

    /// The fitted network.
    pub fn net(&self) -> &Net {
        &self.net
    }

    /// How training went.
    pub fn report(&self) -> &TrainReport {
        &self.report
    }
}

impl BpAnn {
    fn validate(&self) -> Result<(), FitError> {
        let require = |ok: bool, msg: &str| {
            if ok { Ok(()) } else { Err(FitError::InvalidConfig(format!("BP-ANN: {msg}"))) }
        };
        check_embedding(self.embedding)?;
        require(self.hidden >= 1, "hidden must be at least 1")?;
        require(self.mu.is_finite() && self.mu > 0.0, "mu must be positive and finite")?;
        require(
            self.mu_dec > 0.0 && self.mu_dec < 1.0 && self.mu_inc > 1.0 && self.mu_inc.is_finite(),
            "need 0 < mu_dec < 1 < mu_inc",
        )?;
        require(self.mu_max > self.mu, "mu_max must exceed mu")?;
        require(self.max_epochs >= 1 && self.max_fail >= 1, "max_epochs and max_fail must be at least 1")?;
        require(self.min_grad >= 0.0 && self.goal >= 0.0, "min_grad and goal must be non-negative")?;
        require((0.0..=0.5).contains(&self.val_fraction), "val_fraction must lie in [0, 0.5]")
    }

    /// Validation rows out of `rows` (MATLAB rounds the share).
    fn val_rows(&self, rows: usize) -> usize {
        (self.val_fraction * rows as f64).round() as usize
    }

    /// Fewest rows that leave at least as many training rows as parameters (and one validation
    /// row when validation is on).
    fn min_rows(&self, inputs: usize) -> usize {
        let np = Layout { inputs, hidden: self.hidden, output: self.output }.n_params();
        (np..)
            .find(|&r| {
                let v = self.val_rows(r);
                r - v >= np && (self.val_fraction == 0.0 || v >= 1)
            })
            .unwrap_or(np)
    }

    /// Trains a network on explicit rows: `inputs` row-major, `targets.len()` rows of
    /// `dim` values each. Errors: [`FitError::TooFewSamples`] counts rows here.
    pub fn fit_rows(&self, dim: usize, inputs: &[f64], targets: &[f64]) -> Result<(Net, TrainReport), FitError> {
        self.validate()?;
        if dim == 0 || inputs.len() != dim * targets.len() {
            return Err(FitError::InvalidConfig(format!(
                "BP-ANN: {} input values do not form {} rows of {dim}",
                inputs.len(),
                targets.len()
            )));
        }
        let need = self.min_rows(dim);
        if targets.len() < need {
            return Err(FitError::TooFewSamples { need, have: targets.len() });
        }
        if inputs.iter().chain(targets).any(|v| !v.is_finite()) {
            return Err(FitError::NonFinite);
        }
        let layout = Layout { inputs: dim, hidden: self.hidden, output: self.output };
        let mut rng = SplitMix64::new(self.seed);
        let mut params = layout.init(&mut rng);

        // Split: a flag per row, then gather training and validation rows in time order.
        let rows = targets.len();
        let n_val = self.val_rows(rows);
        let mut is_val = vec![false; rows];
        match self.val_split {
            ValSplit::Tail => is_val[rows - n_val..].iter_mut().for_each(|f| *f = true),
            ValSplit::Random => {
                let mut order: Vec<usize> = (0..rows).collect();
                for i in (1..rows).rev() {
                    order.swap(i, rng.below(i + 1));
                }
                order[..n_val].iter().for_each(|&k| is_val[k] = true);
            }
        }
        let (mut tx, mut tt, mut vx, mut vt) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (k, &flag) in is_val.iter().enumerate() {
            let (x, t) = if flag { (&mut vx, &mut vt) } else { (&mut tx, &mut tt) };
            x.extend_from_slice(&inputs[k * dim..(k + 1) * dim]);
            t.push(targets[k]);
        }
        let settings = LmSettings {
            max_epochs: self.max_epochs,
            mu: self.mu,
            mu_dec: self.mu_dec,
            mu_inc: self.mu_inc,
            mu_max: self.mu_max,
            min_grad: self.min_grad,
            goal: self.goal,
            max_fail: self.max_fail,
        };
        let report = lm::train(&layout, &mut params, &Rows { x: &tx, t: &tt }, &Rows { x: &vx, t: &vt }, &settings);
        if params.iter().any(|v| !v.is_finite()) {
            return Err(FitError::Numerical("BP-ANN weights diverged".into()));
        }
        Ok((Net { layout, params }, report))
    }
}

impl Fit for BpAnn {
    type Model = BpAnnModel;

    /// Embeds `train` (Eq. 15–16) and trains on every row; needs `(m−1)τ + 1` samples of history
    /// plus enough rows for the parameters (51 for 3-10-1) and the validation share.
    fn fit(&self, train: &[f64]) -> Result<BpAnnModel, FitError> {
        self.validate()?;
        let e = self.embedding;
        check_series(train, e.samples_for_rows(self.min_rows(e.dim)))?;
        let rows = e.embed(train);
        let (net, report) = self.fit_rows(e.dim, &rows.inputs, &rows.targets)?;
        Ok(BpAnnModel { embedding: e, net, report })
    }
}

impl Predict for BpAnnModel {
    fn history_len(&self) -> usize {
        self.embedding.history()
    }

    /// Reads the latest PSR row of `history` in place (as `Embedding::latest_into`, no buffer).
    fn predict(&self, history: &[f64]) -> f64 {
        let first = history.len() - 1 - self.embedding.window();
        let tau = self.embedding.tau;
        self.net.layout.forward(&self.net.params, |j| history[first + j * tau])
    }

    fn horizon(&self) -> usize {
        self.embedding.horizon
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_config_and_input() {
        let bad = BpAnn { hidden: 0, ..BpAnn::default() };
        assert!(matches!(bad.fit(&[0.0; 500]), Err(FitError::InvalidConfig(_))));
        let bad = BpAnn { val_fraction: 0.9, ..BpAnn::default() };
        assert!(matches!(bad.fit(&[0.0; 500]), Err(FitError::InvalidConfig(_))));
        let bad = BpAnn { mu: f64::NAN, ..BpAnn::default() };
        assert!(matches!(bad.fit(&[0.0; 500]), Err(FitError::InvalidConfig(_))));
        // 51 parameters need 51 training rows; with 15 % validation that is 60 rows, 81 samples.
        assert_eq!(BpAnn::default().min_rows(3), 60);
        assert_eq!(BpAnn::default().fit(&[0.0; 80]), Err(FitError::TooFewSamples { need: 81, have: 80 }));
        let mut x = vec![0.1; 200];
        x[100] = f64::NAN;
        assert_eq!(BpAnn::default().fit(&x), Err(FitError::NonFinite));
        assert!(matches!(BpAnn::default().fit_rows(3, &[0.0; 10], &[0.0; 4]), Err(FitError::InvalidConfig(_))));
    }
}
