//! Storable forms of fitted models, for model snapshots (a warm restart of the daemon uses the
//! model of its last successful retrain; the file format is in [`crate::stream::snapshot`]).
//!
//! A fitted model hands out its state through [`Predict::state`](crate::model::Predict::state); the state is plain data
//! (serde) and is itself a [`Predict`](crate::model::Predict) whose predictions are bit-identical to the model it came
//! from: it evaluates the same [`LssvmModel`] (paper Eq. 4 in dual form, kernel Eq. 8, PSR input
//! Eq. 15) with the same `f64` values. Decoded states are untrusted input: [`ModelState::validate`]
//! checks every invariant `predict` relies on before one is used.

use serde::{Deserialize, Serialize};

use super::lssvm::{LssvmModel, Solver};
use crate::model::embed::Embedding;

/// Largest number of kernel centres a stored model may have (the exact path keeps every training
/// row; `retrain.window` is bounded well below this by the configuration).
pub const MAX_CENTRES: usize = 1 << 22;

/// A fitted model as storable data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum ModelState {
    /// An LS-SVM (exact or fixed-size) with the hyperparameters it was tuned to.
    Lssvm(TunedLssvm),
    /// A constant forecast (normalised units): the model the retrainer gives a constant training
    /// window, e.g. an axis the recording does not have.
    Constant {
        /// The forecast value.
        value: f64,
    },
}

/// A tuned LS-SVM: the regression function and how it was obtained (CPSO-LSSVM, paper §2.2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TunedLssvm {
    /// The fitted model (embedding and kernel expansion; σ² is `model.expansion.sigma2`).
    pub model: LssvmModel,
    /// Regularisation γ it was fitted with (Eq. 5).
    pub gamma: f64,
    /// Exact or fixed-size solver.
    pub solver: Solver,
}

/// Why a stored model state is unusable.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("stored model: {0}")]
pub struct InvalidModel(pub String);

impl ModelState {
    /// The PSR embedding the model reads its input with (`None`: it reads no history).
    pub fn embedding(&self) -> Option<Embedding> {
        match self {
            Self::Lssvm(t) => Some(t.model.embedding),
            Self::Constant { .. } => None,
        }
    }

    /// Checks the invariants `predict` relies on: a sane embedding, centres of the model's
    /// dimension, one coefficient per centre, finite values, σ² and γ positive.
    pub fn validate(&self) -> Result<(), InvalidModel> {
        let bad = |m: String| Err(InvalidModel(m));
        match self {
            Self::Lssvm(t) => {
                let (e, x) = (&t.model.embedding, &t.model.expansion);
                if e.tau == 0
                    || e.dim == 0
                    || e.dim.checked_sub(1).and_then(|d| d.checked_mul(e.tau)).and_then(|w| w.checked_add(1)).is_none()
                {
                    return bad(format!("embedding tau = {}, dim = {} is unusable", e.tau, e.dim));
                }
                if x.dim != e.dim {
                    return bad(format!("expansion dimension {} differs from the embedding's {}", x.dim, e.dim));
                }
                if x.coef.len() > MAX_CENTRES || x.centres.len() != x.coef.len() * x.dim {
                    return bad(format!(
                        "{} centre values for {} coefficients of dimension {}",
                        x.centres.len(),
                        x.coef.len(),
                        x.dim
                    ));
                }
                if !(x.sigma2 > 0.0 && x.sigma2.is_finite() && t.gamma > 0.0 && t.gamma.is_finite()) {
                    return bad(format!("gamma = {}, sigma2 = {} must be positive and finite", t.gamma, x.sigma2));
                }
                if !x.bias.is_finite() || x.centres.iter().chain(&x.coef).any(|v| !v.is_finite()) {
                    return bad("a centre, coefficient or the bias is not finite".into());
                }
                if let Solver::Nystrom { rank } = t.solver
                    && rank == 0
                {
                    return bad("fixed-size solver with rank 0".into());
                }
                Ok(())
            }
            Self::Constant { value } => {
                if value.is_finite() {
                    Ok(())
                } else {
                    bad(format!("constant forecast {value} is not finite"))
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Fit;
    use crate::model::Predict;
    use crate::model::cpso::CpsoConfig;
    use crate::model::lssvm::CpsoLssvm;

    fn fitted() -> (crate::model::lssvm::CpsoLssvmModel, Vec<f64>) {
        let x: Vec<f64> = (0..300).map(|i| (i as f64 * 0.07).sin() * 0.8 + (i as f64 * 0.31).cos() * 0.1).collect();
        let fit = CpsoLssvm {
            embedding: Embedding::new(3, 3).with_horizon(2),
            cpso: CpsoConfig { candidates: 4, particles: 2, iterations: 2, ..CpsoConfig::default() },
            exact_max_rows: 100,
            prototypes: 20,
            ..CpsoLssvm::default()
        };
        (fit.fit(&x[..250]).unwrap(), x)
    }

    #[test]
    fn the_state_predicts_exactly_like_the_model_and_validates() {
        let (model, x) = fitted();
        let state = model.state().expect("CPSO-LSSVM models are storable");
        state.validate().unwrap();
        assert_eq!(state.history_len(), model.history_len());
        for t in state.history_len()..x.len() {
            assert_eq!(state.predict(&x[..t]).to_bits(), model.predict(&x[..t]).to_bits());
        }
        assert_eq!(state.state().as_ref(), Some(&state));
    }

    #[test]
    fn broken_states_are_refused() {
        let (model, _) = fitted();
        let Some(ModelState::Lssvm(good)) = model.state() else { unreachable!() };
        let check = |f: &dyn Fn(&mut TunedLssvm)| {
            let mut t = good.clone();
            f(&mut t);
            ModelState::Lssvm(t).validate().unwrap_err()
        };
        check(&|t| t.model.embedding.tau = 0);
        check(&|t| t.model.embedding.tau = usize::MAX);
        check(&|t| t.model.expansion.dim = 2);
        check(&|t| {
            t.model.expansion.centres.pop();
        });
        check(&|t| t.model.expansion.coef[0] = f64::NAN);
        check(&|t| t.model.expansion.sigma2 = 0.0);
        check(&|t| t.gamma = f64::INFINITY);
        check(&|t| t.solver = Solver::Nystrom { rank: 0 });
    }
}
