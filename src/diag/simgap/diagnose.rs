//! The diagnosis of one recording: baseline, gap, candidate effects, combination, verdict.
//!
//! 1. Split the recording: the first (1 − holdout) of it trains, the rest is held out.
//! 2. Baseline model: the IEEE Std 952 terms fitted to the training part ([`super::baseline`]),
//!    or a given simulator axis model.
//! 3. Run its ensemble (each member with its own draw of the noise terms' uncertainty,
//!    [`super::uncertainty`]) and compare both parts ([`super::ensemble`]): **where** and how far.
//! 4. Fit each candidate effect on the training part ([`super::effects`]); its model is the
//!    baseline refitted on the training part with the effect's deterministic part removed, plus the
//!    effect (with a given model: the given model plus the effect). Run its ensemble.
//!    Effects with a deterministic part are also evaluated against their own null (the refitted
//!    noise without the effect, [`super::greedy`]).
//! 5. Rank, accept and combine ([`super::greedy`]): **which**, and the gap **after** on the
//!    hold-out part.

use serde::Serialize;

use super::SimgapError;
use super::baseline::NoiseTerms;
use super::effects::{EffectKind, EffectParams, Fitted, FittedEffect, TrainingData, fit_effect};
use super::ensemble::{Evaluation, Setup, evaluate};
use super::fit_events::detect_grid;
use super::greedy::{Judgement, OWN_NULL_LEVEL, combine, judge, removes_most};
use super::model::SimModel;
use super::refit::refit_noise_terms;
use super::stats::StatLayout;
use super::uncertainty::bootstrap;
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

/// The verdict of a diagnosis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Neither part of the baseline shows a significant gap, and no effect is accepted against its
    /// own null ([`super::greedy`]).
    NoSignificantGap,
    /// The chosen effects leave no significant gap on either part.
    Explained,
    /// The chosen effects explain most of the gap but a significant residual remains: either no
    /// significant gap is left on the hold-out part but one is on the training part, or the
    /// effects remove at least [`super::greedy::PARTIAL_SHARE`] of the excess gap² on every
    /// significant part of the reference (the baseline, or the first effect's own null) and a
    /// significant gap is left (the residual's *where* is `where_after`). Issue 16, item 2: the
    /// dominant cause is named.
    PartlyExplained,
    /// No effect was kept, or the kept ones leave a significant gap on the hold-out part and do
    /// not remove most of it (then `chosen` is empty and `tried` lists them).
    Unexplained,
}

impl Verdict {
    /// A short readable form.
    pub fn text(self) -> &'static str {
        match self {
            Verdict::NoSignificantGap => "no significant gap",
            Verdict::Explained => "gap explained",
            Verdict::PartlyExplained => "gap partly explained: the chosen effects remove most of it; a significant residual remains",
            Verdict::Unexplained => "gap remains unexplained",
        }
    }
}

/// One candidate effect, fitted and evaluated.
#[derive(Debug, Clone)]
pub struct EffectResult {
    /// The effect.
    pub kind: EffectKind,
    /// Its fitted parameters (`None` when not applicable).
    pub params: Option<EffectParams>,
    /// Why it is not applicable.
    pub note: Option<String>,
    /// The evaluation of baseline + effect.
    pub evaluation: Option<Evaluation>,
    /// How it compares with the baseline.
    pub judgement: Option<Judgement>,
    /// Its own null ([`super::greedy`]): the refitted noise without the effect, evaluated and
    /// tested at [`OWN_NULL_LEVEL`] (`None` when the effect has no deterministic part or the
    /// baseline is given).
    pub own_null: Option<Evaluation>,
    /// How baseline-refit + effect compares with its own null.
    pub own_null_judgement: Option<Judgement>,
}

impl EffectResult {
    /// Whether adding the effect is accepted against the baseline or against its own null.
    pub fn accepted(&self) -> bool {
        self.judgement.is_some_and(|j| j.explains) || self.accepted_by_own_null()
    }

    /// Whether it is accepted against its own null ([`super::greedy`]).
    pub fn accepted_by_own_null(&self) -> bool {
        self.own_null_judgement.is_some_and(|j| j.explains)
    }
}

/// Everything a diagnosis found.
#[derive(Debug, Clone)]
pub struct Diagnosis {
    /// Sample rate, Hz.
    pub rate_hz: f64,
    /// Samples of the recording.
    pub samples: usize,
    /// Samples of the training part.
    pub n_train: usize,
    /// Statistics of the training part.
    pub layout_train: StatLayout,
    /// Statistics of the hold-out part.
    pub layout_hold: StatLayout,
    /// Grid step of the recording's values, if any.
    pub grid_step: Option<f64>,
    /// The fitted noise terms (`None` with a given baseline).
    pub baseline_terms: Option<NoiseTerms>,
    /// The baseline model.
    pub baseline_model: SimModel,
    /// The baseline's evaluation (the gap before).
    pub before: Evaluation,
    /// The candidate effects, best first (not applicable ones last).
    pub effects: Vec<EffectResult>,
    /// The effects that explain the gap (empty unless the verdict is `Explained` or
    /// `PartlyExplained`).
    pub chosen: Vec<EffectKind>,
    /// The effects the greedy combination kept, whether or not they explain the gap.
    pub tried: Vec<EffectKind>,
    /// The model with the kept effects (`tried`).
    pub after_model: SimModel,
    /// Its evaluation (the gap after; the baseline's when none was kept).
    pub after: Evaluation,
    /// The verdict.
    pub verdict: Verdict,
    /// Ensembles run.
    pub ensembles_run: usize,
}

/// Builds the models of a diagnosis from its training data.
struct ModelBuilder<'a> {
    train: TrainingData<'a>,
    baseline: &'a Baseline,
    total_s: f64,
    seed: u64,
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
    fn build(&self, effects: &[&FittedEffect]) -> Result<(SimModel, Option<NoiseTerms>), SimgapError> {
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
    fn build_with_own_null(&self, effect: &FittedEffect) -> Result<(SimModel, Option<SimModel>), SimgapError> {
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
                let mut terms = *terms;
                for e in effects {
                    if let EffectParams::Quantization { step_dps } = e.params {
                        // A rate quantiser adds white noise of variance Δ²/12, which the fitted N
                        // already holds: take it out so it is not simulated twice.
                        terms.n = (terms.n * terms.n - step_dps * step_dps / (12.0 * fs)).max(0.0).sqrt();
                    }
                }
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

/// Diagnoses `recording` (module docs).
pub fn diagnose(recording: &Recording<'_>, baseline: &Baseline, settings: &Settings) -> Result<Diagnosis, SimgapError> {
    if !(settings.holdout > 0.0 && settings.holdout < 1.0) {
        return Err(SimgapError::BadSetting(format!("holdout {} must lie strictly between 0 and 1", settings.holdout)));
    }
    if settings.ensemble < 8 {
        return Err(SimgapError::BadSetting(format!("ensemble {} is below 8 members", settings.ensemble)));
    }
    let rate_hz = recording.rate_hz;
    if !(rate_hz.is_finite() && rate_hz > 0.0) {
        return Err(SimgapError::BadSetting(format!("sample rate {rate_hz} Hz is not positive and finite")));
    }
    let len = recording.rate.len();
    if let Some(temp) = recording.temp_c {
        if temp.len() != len {
            return Err(SimgapError::BadSetting("temp_c has another length than the rate column".into()));
        }
        if let Some(i) = temp.iter().position(|v| !v.is_finite()) {
            return Err(SimgapError::BadSetting(format!("temp_c of sample {i} is not a finite number")));
        }
    }
    let n_train = ((1.0 - settings.holdout) * len as f64).round() as usize;
    let train = &recording.rate[..n_train.min(len)];
    let grid_step = detect_grid(train);
    let has_temp = recording.temp_c.is_some();
    let layout_train = StatLayout::new(n_train, rate_hz, 0.0, grid_step, has_temp)?;
    let layout_hold = StatLayout::new(len - n_train, rate_hz, n_train as f64 / rate_hz, grid_step, has_temp)?;
    let temp_parts = recording.temp_c.map(|t| t.split_at(n_train));
    let setup = Setup {
        rate_hz,
        len,
        n_train,
        temp_c: recording.temp_c,
        real_train: layout_train.compute(train, temp_parts.map(|t| t.0))?,
        real_hold: layout_hold.compute(&recording.rate[n_train..], temp_parts.map(|t| t.1))?,
        layout_train,
        layout_hold,
        members: settings.ensemble,
        seed: settings.seed,
        threads: settings.threads,
        perturbations: Vec::new(),
    };
    let data = TrainingData { x: train, rate_hz, temp_c: recording.temp_c.map(|t| &t[..n_train]) };
    let builder = ModelBuilder { train: data, baseline, total_s: len as f64 / rate_hz, seed: settings.seed };
    let (baseline_model, baseline_terms) = builder.build(&[])?;
    let mut setup = setup;
    if let Some(terms) = &baseline_terms {
        setup.perturbations = bootstrap(terms, rate_hz, n_train, builder.total_s, settings.ensemble, settings.seed)?;
    }
    let before = evaluate(&setup, &baseline_model)?;
    // Every model built, by its effects in the order added, so the final one is not refitted again.
    let mut built: Vec<(Vec<EffectKind>, SimModel)> = vec![(Vec::new(), baseline_model.clone())];
    let mut ensembles_run = 1;
    tracing::info!("baseline: gap {:.3} (training), {:.3} (hold-out)", before.train.score.gap, before.hold.score.gap);

    let fitted: Vec<(EffectKind, Fitted)> = EffectKind::ALL.iter().map(|&k| (k, fit_effect(k, &data))).collect();
    let mut effects = Vec::new();
    for (kind, fit) in &fitted {
        let result = match fit {
            Fitted::Found(effect) => {
                let (model, own_null_model) = builder.build_with_own_null(effect)?;
                let evaluation = evaluate(&setup, &model)?;
                built.push((vec![*kind], model));
                ensembles_run += 1;
                tracing::info!(
                    "{}: gap {:.3} (training), {:.3} (hold-out)",
                    kind.name(),
                    evaluation.train.score.gap,
                    evaluation.hold.score.gap
                );
                let own_null = match own_null_model {
                    Some(null_model) => {
                        ensembles_run += 1;
                        Some(evaluate(&setup, &null_model)?.at_level(OWN_NULL_LEVEL))
                    }
                    None => None,
                };
                let own_null_judgement = own_null.as_ref().map(|n| judge(n, &evaluation, settings.min_share));
                if let Some(n) = &own_null {
                    tracing::info!(
                        "{} own null: gap {:.3} (training), {:.3} (hold-out), significant {}",
                        kind.name(),
                        n.train.score.gap,
                        n.hold.score.gap,
                        n.significant()
                    );
                }
                EffectResult {
                    kind: *kind,
                    params: Some(effect.params.clone()),
                    note: None,
                    judgement: Some(judge(&before, &evaluation, settings.min_share)),
                    evaluation: Some(evaluation),
                    own_null,
                    own_null_judgement,
                }
            }
            Fitted::NotApplicable(why) => EffectResult {
                kind: *kind,
                params: None,
                note: Some(why.clone()),
                evaluation: None,
                judgement: None,
                own_null: None,
                own_null_judgement: None,
            },
        };
        effects.push(result);
    }
    effects.sort_by(|a, b| {
        let score = |e: &EffectResult| e.evaluation.as_ref().map_or(f64::INFINITY, Evaluation::mean_gap);
        score(a).total_cmp(&score(b))
    });
    let ranked: Vec<(EffectKind, &Evaluation)> =
        effects.iter().filter_map(|e| e.evaluation.as_ref().map(|ev| (e.kind, ev))).collect();
    let found = |kind: EffectKind| {
        fitted.iter().find_map(|(k, f)| match f {
            Fitted::Found(e) if *k == kind => Some(e),
            _ => None,
        })
    };
    let own_null: Vec<EffectKind> = effects.iter().filter(|e| e.accepted_by_own_null()).map(|e| e.kind).collect();
    let combination = combine(&before, &ranked, &own_null, settings.min_share, settings.max_effects, |set| {
        let parts: Vec<&FittedEffect> = set.iter().filter_map(|&k| found(k)).collect();
        let (model, _) = builder.build(&parts)?;
        let evaluation = evaluate(&setup, &model);
        built.push((set.to_vec(), model));
        evaluation
    })?;
    ensembles_run += combination.evaluations;
    let tried = combination.chosen;
    // What the share of a partial explanation is measured from: the baseline when it shows a
    // significant gap, else the first kept effect's own null (the route it was accepted by).
    let reference = if before.significant() {
        Some(&before)
    } else {
        tried.first().and_then(|&k| effects.iter().find(|e| e.kind == k)).and_then(|e| e.own_null.as_ref())
    };
    let verdict = if !before.significant() && own_null.is_empty() {
        Verdict::NoSignificantGap
    } else if tried.is_empty() {
        Verdict::Unexplained
    } else if !combination.after.significant() {
        Verdict::Explained
    } else if !combination.after.hold.significant || reference.is_some_and(|r| removes_most(r, &combination.after)) {
        Verdict::PartlyExplained
    } else {
        Verdict::Unexplained
    };
    let chosen =
        if matches!(verdict, Verdict::Explained | Verdict::PartlyExplained) { tried.clone() } else { Vec::new() };
    let after_model = match built.into_iter().find(|(set, _)| *set == tried) {
        Some((_, model)) => model,
        None => builder.build(&tried.iter().filter_map(|&k| found(k)).collect::<Vec<_>>())?.0,
    };
    let Setup { layout_train, layout_hold, .. } = setup;
    Ok(Diagnosis {
        rate_hz,
        samples: len,
        n_train,
        layout_train,
        layout_hold,
        grid_step,
        baseline_terms,
        baseline_model,
        before,
        effects,
        chosen,
        tried,
        after_model,
        after: combination.after,
        verdict,
        ensembles_run,
    })
}
