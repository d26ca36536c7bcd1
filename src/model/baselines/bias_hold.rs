//! Start-up bias-hold baseline: the mean of the first K training samples, held forever — what an
//! INS does when it averages the gyro while standing still at start-up (docs/design.md "Stage
//! definitions", *Compensation*; "Evaluation protocols", *honest*).

use serde::{Deserialize, Serialize};

use super::check_series;
use super::mean::mean_of;
use crate::model::{Fit, FitError, Predict};

/// Start-up bias-hold configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct BiasHold {
    /// K: samples averaged at the start of the training series (≥ 1). Default 600 (60 s at
    /// 10 Hz); see [`BiasHold::from_duration`].
    pub samples: usize,
}

impl Default for BiasHold {
    fn default() -> Self {
        Self { samples: 600 }
    }
}

impl BiasHold {
    /// K from a start-up duration and the series rate: `round(seconds · rate_hz)`, at least 1.
    pub fn from_duration(seconds: f64, rate_hz: f64) -> Self {
        let k = (seconds * rate_hz).round();
        let samples = if k.is_finite() && k >= 1.0 { k as usize } else { 1 };
        Self { samples }
    }
}

/// Fitted bias-hold model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BiasHoldModel {
    /// Mean of the first K training samples, the constant prediction.
    pub bias: f64,
}

impl Fit for BiasHold {
    type Model = BiasHoldModel;

    /// Needs K finite samples; only the first K are read (a later non-finite value is ignored,
    /// since an INS would not have seen it yet).
    fn fit(&self, train: &[f64]) -> Result<BiasHoldModel, FitError> {
        if self.samples == 0 {
            return Err(FitError::InvalidConfig("bias-hold needs at least 1 start-up sample".into()));
        }
        let k = self.samples;
        if train.len() < k {
            return Err(FitError::TooFewSamples { need: k, have: train.len() });
        }
        check_series(&train[..k], k)?;
        Ok(BiasHoldModel { bias: mean_of(&train[..k]) })
    }
}

impl Predict for BiasHoldModel {
    fn history_len(&self) -> usize {
        0
    }

    fn predict(&self, _history: &[f64]) -> f64 {
        self.bias
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn duration_to_samples() {
        assert_eq!(BiasHold::from_duration(60.0, 10.0).samples, 600);
        assert_eq!(BiasHold::from_duration(0.0, 10.0).samples, 1);
        assert_eq!(BiasHold::from_duration(f64::NAN, 10.0).samples, 1);
    }

    #[test]
    fn bad_config() {
        assert!(matches!(BiasHold { samples: 0 }.fit(&[1.0]), Err(FitError::InvalidConfig(_))));
    }
}
