//! Persistence (random-walk) baseline: `x̂[t+1] = x[t]` (docs/design.md "Stage definitions",
//! *Compensation*). It has no parameters; a model that cannot beat it has learnt nothing.

use serde::{Deserialize, Serialize};

use super::check_series;
use crate::model::{Fit, FitError, Predict};

/// Persistence baseline configuration: `x̂[t+1] = x[t]`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Persistence;

/// Fitted persistence model: predicts the last sample of the history.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PersistenceModel;

impl Fit for Persistence {
    type Model = PersistenceModel;

    /// Needs two finite samples (one target with one sample of history), for consistency with
    /// the other models; nothing is estimated.
    fn fit(&self, train: &[f64]) -> Result<PersistenceModel, FitError> {
        check_series(train, 2)?;
        Ok(PersistenceModel)
    }
}

impl Predict for PersistenceModel {
    fn history_len(&self) -> usize {
        1
    }

    fn predict(&self, history: &[f64]) -> f64 {
        history[history.len() - 1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeats_the_last_sample() {
        let m = Persistence.fit(&[1.0, 2.0]).unwrap();
        assert_eq!(m.predict(&[5.0, -3.0]), -3.0);
        assert_eq!(Persistence.fit(&[1.0]), Err(FitError::TooFewSamples { need: 2, have: 1 }));
        assert_eq!(Persistence.fit(&[1.0, f64::NAN]), Err(FitError::NonFinite));
    }
}
