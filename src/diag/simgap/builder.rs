//! The models of a diagnosis: the baseline (fitted or given) plus fitted effects, with the noise
//! terms refitted once the effects' deterministic parts are removed ([`super::refit`]).

use super::SimgapError;
use super::baseline::NoiseTerms;
use super::effects::TrainingData;
use super::inputs::Baseline;
use super::model::SimModel;
use super::params::{EffectKind, FittedEffect};
use super::refit::refit_noise_terms;
use crate::sim::AxisConfig;

/// Builds the models of a diagnosis from its training data.
pub(super) struct ModelBuilder<'a> {
    pub(super) train: TrainingData<'a>,
    pub(super) baseline: &'a Baseline,
    pub(super) total_s: f64,
    pub(super) seed: u64,
}

/// The noise a model's effects are added to.
enum Noise<'a> {
    /// The given simulator axis (`--sim`), as it is.
    Given(&'a AxisConfig),
    /// The IEEE Std 952 terms refitted on the training part.
    Fitted(NoiseTerms),
}

impl ModelBuilder<'_> {
    /// The model of the baseline plus `effects`, and the noise terms refitted without the
    /// effects' deterministic parts ([`super::refit`]).
    pub(super) fn build(&self, effects: &[&FittedEffect]) -> Result<(SimModel, Option<NoiseTerms>), SimgapError> {
        let noise = self.noise(effects)?;
        let terms = match &noise {
            Noise::Fitted(terms) => Some(*terms),
            Noise::Given(_) => None,
        };
        Ok((self.model(&noise, effects), terms))
    }

    /// The model of the baseline plus `effect`, and the effect's own null ([`super::greedy`]):
    /// the same refitted noise terms simulated without the effect (one refit serves both).
    /// The null is `None` with a given baseline (nothing is refitted) and for effects without a
    /// deterministic part (their null is the baseline).
    pub(super) fn build_with_own_null(
        &self,
        effect: &FittedEffect,
    ) -> Result<(SimModel, Option<SimModel>), SimgapError> {
        let noise = self.noise(&[effect])?;
        let own_null =
            (matches!(noise, Noise::Fitted(_)) && effect.training_part.is_some()).then(|| self.model(&noise, &[]));
        Ok((self.model(&noise, &[effect]), own_null))
    }

    /// The noise of a model with `effects`: the given axis, or the terms refitted with the
    /// effects' deterministic parts removed ([`super::refit`]).
    fn noise(&self, effects: &[&FittedEffect]) -> Result<Noise<'_>, SimgapError> {
        match self.baseline {
            Baseline::Given(axis) => Ok(Noise::Given(axis)),
            Baseline::Fitted => {
                let with_gm = effects.iter().any(|e| e.params.kind() == EffectKind::GaussMarkov);
                let terms = refit_noise_terms(&self.train, effects, with_gm, self.total_s, self.seed)?;
                tracing::debug!("noise terms refitted with {} effect(s): {terms:?}", effects.len());
                Ok(Noise::Fitted(terms))
            }
        }
    }

    /// `noise` plus `effects` as a simulator model.
    fn model(&self, noise: &Noise<'_>, effects: &[&FittedEffect]) -> SimModel {
        let fs = self.train.rate_hz;
        match noise {
            Noise::Given(axis) => {
                let mut model = SimModel::from_axis(axis);
                for e in effects {
                    e.params.apply(&mut model);
                }
                model
            }
            Noise::Fitted(terms) => {
                // Under a quantiser the terms are already calibrated to what the rounding adds
                // ([`super::refit`]), so it is not simulated twice.
                let bias = self.train.x.iter().sum::<f64>() / self.train.x.len() as f64;
                let mut model = terms.to_model(fs, self.total_s, bias);
                for e in effects.iter().filter(|e| e.params.kind() != EffectKind::GaussMarkov) {
                    e.params.apply(&mut model);
                }
                model
            }
        }
    }
}
