//! The multi-scale tracker's state ([`BankWarm`], `stream::drift::multiscale`): the filter, its
//! fitted noise model and the Allan variance it is fitted to, as plain data a snapshot stores
//! (the logic lives with the estimator; this file imports nothing of it).

use serde::{Deserialize, Serialize};

use crate::stream::allan_cascade::AllanCascade;

/// Gauss–Markov states of the bank (correlation times `stream::drift::BANK_TAUS_S`).
pub const BANK_GM: usize = 6;
/// Filter states: the random-walk bias, then the Gauss–Markov states.
pub const BANK_STATES: usize = 1 + BANK_GM;
/// The noise model of the bank, per sample: white variance R, the bias' random-walk step
/// variance and each Gauss–Markov state's stationary variance, (deg/s)².
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct BankModel {
    /// Measurement (white) noise variance per sample.
    pub white: f64,
    /// Random-walk step variance of the bias per sample.
    pub walk: f64,
    /// Stationary variance of each Gauss–Markov state.
    pub markov: [f64; BANK_GM],
    /// Whether the model comes from a fit (false: the scalar tracker's rule from τ\*).
    pub fitted: bool,
}

/// The multi-scale tracker of one axis as a snapshot stores it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BankWarm {
    /// Whether a committed sample backs the state (false at start-up and after a relearn).
    pub started: bool,
    /// State at the last commit: bias, then the Gauss–Markov states, deg/s.
    pub state: [f64; BANK_STATES],
    /// Its covariance, (deg/s)².
    pub covariance: [[f64; BANK_STATES]; BANK_STATES],
    /// Sample index of the last commit.
    pub last_commit: u64,
    /// The noise model in use.
    pub model: BankModel,
    /// Allan variance of the committed samples, concatenated across gaps.
    pub allan: AllanCascade,
    /// Commits since the model was last fitted.
    pub since_fit: u64,
    /// Committed samples offered to the filter (its counter; written by a snapshot only).
    pub commits: u64,
}

impl Default for BankWarm {
    fn default() -> Self {
        Self {
            started: false,
            state: [0.0; BANK_STATES],
            covariance: [[0.0; BANK_STATES]; BANK_STATES],
            last_commit: 0,
            model: BankModel::default(),
            allan: AllanCascade::new(),
            since_fit: 0,
            commits: 0,
        }
    }
}

impl BankWarm {
    /// Whether every value is usable: finite, variances non-negative.
    pub fn is_valid(&self) -> bool {
        let m = &self.model;
        let finite_nonneg = |v: f64| v.is_finite() && v >= 0.0;
        self.state.iter().chain(self.covariance.iter().flatten()).all(|v| v.is_finite())
            && (0..BANK_STATES).all(|i| self.covariance[i][i] >= 0.0)
            && [m.white, m.walk].iter().chain(&m.markov).all(|&v| finite_nonneg(v))
            && self.allan.is_valid()
    }
}
