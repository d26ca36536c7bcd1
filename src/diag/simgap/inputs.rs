//! What a diagnosis is given: its settings, the baseline model and the recording.

use crate::sim::AxisConfig;

/// Settings of a diagnosis.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// Share of the recording held out at its end (0 < holdout < 1).
    pub holdout: f64,
    /// Ensemble size (≥ 8).
    pub ensemble: usize,
    /// Seed of the ensemble.
    pub seed: u64,
    /// Share of the excess gap an effect must remove to explain it ([`super::greedy`]).
    pub min_share: f64,
    /// Most effects combined.
    pub max_effects: usize,
    /// Worker threads for the ensemble (1 = none).
    pub threads: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Self { holdout: 0.3, ensemble: 32, seed: 1, min_share: 0.25, max_effects: 3, threads: 1 }
    }
}

/// The model the gap is measured from.
#[derive(Debug, Clone, PartialEq)]
pub enum Baseline {
    /// The IEEE Std 952 terms fitted to the training part.
    Fitted,
    /// A given simulator axis model (`--sim FILE.toml`), boxed: it is far larger than `Fitted`.
    Given(Box<AxisConfig>),
}

/// The recording to diagnose: one rate column, uniformly sampled, with its temperature if any.
#[derive(Debug, Clone, Copy)]
pub struct Recording<'a> {
    /// Rate, deg/s.
    pub rate: &'a [f64],
    /// Sample rate, Hz.
    pub rate_hz: f64,
    /// Temperature, °C, one per sample.
    pub temp_c: Option<&'a [f64]>,
}
