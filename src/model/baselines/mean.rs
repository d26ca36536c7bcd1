//! Mean baseline: the training mean, held forever (docs/design.md "Stage definitions",
//! *Compensation*). On a zero-mean noise series it is the best constant predictor in RMSE.

use serde::{Deserialize, Serialize};

use super::check_series;
use crate::model::{Fit, FitError, Predict};

/// Mean baseline configuration: `x̂[t+1]` = the mean of the training series.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Mean;

/// Fitted mean model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeanModel {
    /// The training mean, the constant prediction.
    pub mean: f64,
}

/// Arithmetic mean of a non-empty slice.
pub(crate) fn mean_of(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

impl Fit for Mean {
    type Model = MeanModel;

    /// Needs one finite sample.
    fn fit(&self, train: &[f64]) -> Result<MeanModel, FitError> {
        check_series(train, 1)?;
        Ok(MeanModel { mean: mean_of(train) })
    }
}

impl Predict for MeanModel {
    fn history_len(&self) -> usize {
        0
    }

    fn predict(&self, _history: &[f64]) -> f64 {
        self.mean
    }

    /// Stored as a constant forecast (model snapshots).
    fn state(&self) -> Option<crate::model::snapshot::ModelState> {
        Some(crate::model::snapshot::ModelState::Constant { value: self.mean })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holds_the_training_mean() {
        let m = Mean.fit(&[1.0, 2.0, 6.0]).unwrap();
        assert_eq!(m.mean, 3.0);
        assert_eq!(m.predict(&[]), 3.0);
        assert_eq!(Mean.fit(&[]), Err(FitError::TooFewSamples { need: 1, have: 0 }));
        assert_eq!(Mean.fit(&[f64::INFINITY]), Err(FitError::NonFinite));
    }
}
