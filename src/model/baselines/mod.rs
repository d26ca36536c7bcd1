//! Honest baselines (docs/design.md "Evaluation protocols", *honest*; "Stage definitions",
//! *Compensation*): the simple predictors every table lists next to the paper's models, on the
//! same split and through the same [`Fit`](super::Fit)/[`Predict`](super::Predict) interface.
//!
//! - [`Persistence`]: `x̂[t+1] = x[t]`.
//! - [`Mean`]: the training mean, held.
//! - [`BiasHold`]: the mean of the first K training samples, held (an INS start-up bias).
//! - [`Ar`]: AR(p) on consecutive lags with intercept, order by AIC or fixed.
//! - [`LinearPsr`]: linear regression on the PSR rows (paper Eq. 15–16), the linear counterpart
//!   of the paper's LSSVM.

pub mod ar;
pub mod bias_hold;
pub mod linear_psr;
mod lstsq;
pub mod mean;
pub mod persistence;

pub use ar::{Ar, ArModel, ArOrder};
pub use bias_hold::{BiasHold, BiasHoldModel};
pub use linear_psr::{LinearPsr, LinearPsrModel};
pub use mean::{Mean, MeanModel};
pub use persistence::{Persistence, PersistenceModel};

use super::FitError;

/// Checks a training series: at least `need` samples ([`FitError::TooFewSamples`]), all finite
/// ([`FitError::NonFinite`]).
pub(crate) fn check_series(train: &[f64], need: usize) -> Result<(), FitError> {
    if train.len() < need {
        return Err(FitError::TooFewSamples { need, have: train.len() });
    }
    if train.iter().any(|v| !v.is_finite()) {
        return Err(FitError::NonFinite);
    }
    Ok(())
}
