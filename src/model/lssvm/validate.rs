//! Input checks shared by the LS-SVM solvers: bad input is a [`FitError`], never a panic.

use crate::model::FitError;

/// γ (Eq. 5) and σ² (Eq. 8) must be positive and finite.
pub fn check_hyper(gamma: f64, sigma2: f64) -> Result<(), FitError> {
    if !(gamma > 0.0 && gamma.is_finite()) {
        return Err(FitError::InvalidConfig(format!("gamma must be positive and finite, got {gamma}")));
    }
    if !(sigma2 > 0.0 && sigma2.is_finite()) {
        return Err(FitError::InvalidConfig(format!("sigma2 must be positive and finite, got {sigma2}")));
    }
    Ok(())
}

/// `inputs` must hold `targets.len()` rows of `dim` finite values, at least `min_rows` of them.
pub fn check_rows(inputs: &[f64], dim: usize, targets: &[f64], min_rows: usize) -> Result<(), FitError> {
    if dim == 0 {
        return Err(FitError::InvalidConfig("input dimension must be at least 1".into()));
    }
    if inputs.len() != targets.len() * dim {
        return Err(FitError::InvalidConfig(format!(
            "{} input values do not form {} rows of dimension {dim}",
            inputs.len(),
            targets.len()
        )));
    }
    if targets.len() < min_rows {
        return Err(FitError::TooFewSamples { need: min_rows, have: targets.len() });
    }
    if inputs.iter().chain(targets).any(|v| !v.is_finite()) {
        return Err(FitError::NonFinite);
    }
    Ok(())
}
