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
//!    noise without the effect; with a given model, the model itself), on the whole gap and on
//!    their own detector ([`super::greedy`]). With a given model the detector test is what finds
//!    a slow line or a warm-up among ~50 statistics; before the fifteenth session it ran only with
//!    fitted terms, and a warm-up beside a small Gauss–Markov process or small steps was named
//!    after the small effect.
//! 5. Rank, accept and combine ([`super::greedy`]): **which**, and the gap **after** on the
//!    hold-out part.
//!
//! Its inputs are in [`super::inputs`], its results in [`super::outcome`], the models it builds in
//! [`super::builder`].

use super::SimgapError;
use super::baseline::{NoiseTerms, fit_noise_terms};
use super::builder::ModelBuilder;
use super::effects::{TrainingData, fit_candidates, fit_effect};
use super::ensemble::{Evaluation, Setup, evaluate};
use super::fit_events::{detect_grid, fit_jumps_at};
use super::fit_time::warmup_unbounded;
use super::greedy::{
    BASELINE_LEVEL, FitChoice, OWN_NULL_LEVEL, STEP_BENT, combine, detector_test, judge,
    outrank_all_but_best_candidate, own_evidence, ramp_before_unbounded_warmup, removes_most,
    reshape_first_beside_steps, stands_above_white_noise,
};
use super::model::SimModel;
use super::naming::naming_order;
use super::nested::{NestedTest, gauss_markov_test};
use super::nested_jumps::jumps_test;
use super::nested_ramp::ramp_test;
use super::nested_temperature::temperature_test;
use super::nested_warmup::warmup_test;
use super::params::{EffectKind, EffectParams, Fitted, FittedEffect};
use super::stats::StatLayout;
use super::uncertainty::bootstrap;

pub use super::inputs::{Baseline, Recording, Settings};
pub use super::outcome::{Diagnosis, EffectResult, Verdict};

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
    let data = TrainingData {
        x: train,
        rate_hz,
        temp_c: recording.temp_c.map(|t| &t[..n_train]),
        holdout: &recording.rate[n_train..],
    };
    let builder = ModelBuilder { train: data, baseline, total_s: len as f64 / rate_hz, seed: settings.seed };
    let (baseline_model, baseline_terms) = builder.build(&[])?;
    let given = matches!(baseline, Baseline::Given(_));
    let recording_terms = if given {
        fit_noise_terms(train, rate_hz, builder.total_s, false)
            .inspect_err(|e| {
                tracing::warn!("the recording's own IEEE terms could not be fitted beside the simulator's: {e}")
            })
            .ok()
    } else {
        None
    };
    // The recording's own noise terms: the fitted baseline's, or beside a given simulator its own
    // fit (the step process' test and the white-noise line of a Gauss–Markov process ask about
    // the recording, whatever the baseline).
    let own_terms = baseline_terms.as_ref().or(recording_terms.as_ref());
    let mut setup = setup;
    if let Some(terms) = &baseline_terms {
        setup.perturbations = bootstrap(terms, rate_hz, n_train, builder.total_s, settings.ensemble, settings.seed)?;
    }
    // Whether there is a gap at all: each part at 1 − 0.01/2, one false alarm in 100 over both.
    let before = evaluate(&setup, &baseline_model)?.at_level(BASELINE_LEVEL);
    // With a given simulator nothing is refitted: every effect's own null is the baseline itself,
    // and its detector is tested against that.
    let given_own_null = given.then(|| before.at_level(OWN_NULL_LEVEL));
    // Every model built, by its fits in the order added, so the final one is not refitted again.
    let mut built: Vec<(Vec<FitChoice>, SimModel)> = vec![(Vec::new(), baseline_model.clone())];
    let mut ensembles_run = 1;
    tracing::info!("baseline: gap {:.3} (training), {:.3} (hold-out)", before.train.score.gap, before.hold.score.gap);

    // The step process' test runs before the fits. Where it passes and its segmentation has more
    // change points than the window detector found steps (none, or some of a few sharp ones: a
    // step within a window of another is not resolved), the effect is also fitted from those
    // change points, and the fit that evaluates better is kept: from too few steps the jumps cover
    // less of the bias' motion and rank below an effect that covers it smoothly (a temperature
    // response, a warm-up); from a segmentation's spurious extra changes they can cover less of
    // a single step than the window detector's fit did. Its question (steps or a random walk?)
    // is the recording's, whatever the baseline: with a given simulator it runs on the
    // recording's own terms.
    let jumps = own_terms
        .map(|terms| jumps_test(recording.rate, rate_hz, terms, builder.total_s, settings.seed))
        .transpose()?;
    let step_changes = match &jumps {
        Some((test, Some(evidence))) if test.passed => Some(&evidence.changes),
        _ => None,
    };
    let mut candidates: Vec<(EffectKind, Vec<Fitted>)> = EffectKind::ALL
        .iter()
        .map(|&k| match (k, fit_candidates(k, &data), step_changes) {
            (EffectKind::BiasJumps, mut fits, Some(changes)) if window_steps(&fits[0]) < changes.len() => {
                fits.push(fit_jumps_at(data.x, data.holdout, rate_hz, changes));
                (k, fits)
            }
            (k, fits, _) => (k, fits),
        })
        .collect();
    add_step_corrected_fits(&mut candidates, &data);
    let mut effects = Vec::new();
    // Every candidate fit per effect and which scored best alone, for the combinations below.
    let mut fitted: Vec<(EffectKind, Vec<FittedEffect>, usize)> = Vec::new();
    for (kind, fits) in candidates {
        let best = best_fit(fits, |effect| {
            let (model, own_null_model) = builder.build_with_own_null(effect)?;
            let evaluation = evaluate(&setup, &model)?;
            ensembles_run += 1;
            Ok(((model, own_null_model), evaluation))
        })?;
        let result = match best {
            Ok(BestFit { found, best, built: (model, own_null_model), evaluation }) => {
                let effect = &found[best];
                built.push((vec![FitChoice { kind, fit: best }], model));
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
                    None if effect.training_part.is_some() => given_own_null.clone(),
                    None => None,
                };
                let own_null_judgement = own_null.as_ref().map(|n| judge(n, &evaluation, settings.min_share));
                let detector = own_null.as_ref().and_then(|n| {
                    detector_test(kind, setup.layout_train.info(), setup.layout_hold.info(), n, &evaluation)
                });
                let nested = match (&baseline_terms, &jumps) {
                    (_, Some((test, _))) if kind == EffectKind::BiasJumps => Some(log_nested(kind, test.clone())),
                    (Some(terms), _) => nested_test(kind, recording, terms, builder.total_s, settings.seed)?,
                    (None, _) => None,
                };
                if let Some(n) = &own_null {
                    tracing::info!(
                        "{} own null: gap {:.3} (training), {:.3} (hold-out), significant {}",
                        kind.name(),
                        n.train.score.gap,
                        n.hold.score.gap,
                        n.significant()
                    );
                }
                // Against the baseline only: with a given simulator the step process' test is the
                // recording's own question (above), not a comparison with the baseline.
                let evidence = own_evidence(baseline_terms.as_ref().and(nested.as_ref()), detector.as_ref());
                if !evidence {
                    tracing::info!(
                        "{}: no evidence of its own (nested test and detector), not a candidate",
                        kind.name()
                    );
                }
                let visible = own_terms.is_none_or(|t| stands_above_white_noise(&effect.params, t.n));
                if !visible {
                    tracing::info!("{}: below the white noise at its own time scale, not a candidate", kind.name());
                }
                let supported = evidence && visible;
                let params = Some(effect.params.clone());
                fitted.push((kind, found, best));
                EffectResult {
                    kind,
                    params,
                    note: None,
                    judgement: Some(judge(&before, &evaluation, settings.min_share)),
                    evaluation: Some(evaluation),
                    own_null,
                    own_null_judgement,
                    detector,
                    nested,
                    supported,
                }
            }
            Err(why) => EffectResult {
                kind,
                params: None,
                note: Some(why),
                evaluation: None,
                judgement: None,
                own_null: None,
                own_null_judgement: None,
                detector: None,
                nested: None,
                supported: false,
            },
        };
        effects.push(result);
    }
    let score = |e: &EffectResult| e.evaluation.as_ref().map_or(f64::INFINITY, Evaluation::mean_log_score);
    effects.sort_by(|a, b| score(a).total_cmp(&score(b)));
    // A warm-up whose fitted time constant the training part does not bound (greedy.rs).
    let unbounded_warmup = |params: &EffectParams| match *params {
        EffectParams::Warmup { time_constant_s, .. } => warmup_unbounded(time_constant_s, n_train, rate_hz),
        _ => false,
    };
    let unbounded = |e: &EffectResult| e.params.as_ref().is_some_and(unbounded_warmup);
    ramp_before_unbounded_warmup(&mut effects, |e| e.kind, unbounded, score);
    // The detector and nested routes count only for the best-ranked candidate (greedy.rs).
    outrank_all_but_best_candidate(
        &mut effects,
        |e| e.supported,
        |e| {
            if let Some(test) = &mut e.detector {
                test.outranked();
            }
            if let Some(test) = &mut e.nested {
                test.outranked = true;
            }
        },
    );
    let fits_of = |kind: EffectKind| fitted.iter().find(|(k, ..)| *k == kind);
    let best_choice = |kind: EffectKind| fits_of(kind).map(|&(kind, _, fit)| FitChoice { kind, fit });
    let ranked: Vec<(FitChoice, &Evaluation)> = effects
        .iter()
        .filter(|e| e.supported)
        .filter_map(|e| Some((best_choice(e.kind)?, e.evaluation.as_ref()?)))
        .collect();
    // The other candidate fits of the candidates, for the later steps (greedy.rs).
    let other_fits: Vec<FitChoice> = ranked
        .iter()
        .filter_map(|(choice, _)| fits_of(choice.kind))
        .flat_map(|(kind, found, best)| {
            (0..found.len()).filter(move |fit| fit != best).map(move |fit| FitChoice { kind: *kind, fit })
        })
        .collect();
    let found = |c: FitChoice| fits_of(c.kind).and_then(|(_, found, _)| found.get(c.fit));
    let own_null: Vec<EffectKind> = effects.iter().filter(|e| e.accepted_by_own_null()).map(|e| e.kind).collect();
    let mut evaluate_set = |set: &[FitChoice]| {
        let parts: Vec<&FittedEffect> = set.iter().filter_map(|&c| found(c)).collect();
        let (model, _) = builder.build(&parts)?;
        let evaluation = evaluate(&setup, &model);
        built.push((set.to_vec(), model));
        evaluation
    };
    let mut combination =
        combine(&before, &ranked, &other_fits, &own_null, settings.min_share, settings.max_effects, &mut evaluate_set)?;
    // Beside kept bias steps, the first effect's shape is chosen again with the steps in the
    // model (greedy.rs): every candidate fit of the slow bias motions, those on the step-corrected
    // part among them.
    let slow_fits: Vec<FitChoice> = ranked
        .iter()
        .map(|(choice, _)| *choice)
        .chain(other_fits.iter().copied())
        .filter(|c| STEP_BENT.contains(&c.kind))
        .collect();
    let unbounded_fit = |c: FitChoice| found(c).is_some_and(|e| unbounded_warmup(&e.params));
    reshape_first_beside_steps(&mut combination, &slow_fits, unbounded_fit, &mut evaluate_set)?;
    ensembles_run += combination.evaluations;
    let kept_fits = combination.chosen;
    let tried: Vec<EffectKind> = kept_fits.iter().map(|c| c.kind).collect();
    // The parameters of each kept effect as the final model holds them.
    let tried_params: Vec<EffectParams> =
        kept_fits.iter().filter_map(|&c| found(c)).map(|e| e.params.clone()).collect();
    // The first kept effect's own report: its own null and its evaluation alone.
    let first_tried = tried.first().and_then(|&k| effects.iter().find(|e| e.kind == k));
    // What the share of a partial explanation is measured from: the baseline when it shows a
    // significant gap, else the first kept effect's own null (the route it was accepted by).
    let reference = if before.significant() { Some(&before) } else { first_tried.and_then(|e| e.own_null.as_ref()) };
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
    // Named first: the cause of the drift part of the gap (naming.rs); `tried` keeps the order
    // the effects were added in.
    let chosen = if matches!(verdict, Verdict::Explained | Verdict::PartlyExplained) {
        let first_alone = first_tried.and_then(|e| e.evaluation.as_ref()).unwrap_or(&before);
        naming_order(&before, first_alone, &tried, |k| tried.iter().position(|&t| t == k).map(|i| &tried_params[i]))
    } else {
        Vec::new()
    };
    let after_model = match built.into_iter().find(|(set, _)| *set == kept_fits) {
        Some((_, model)) => model,
        None => builder.build(&kept_fits.iter().filter_map(|&c| found(c)).collect::<Vec<_>>())?.0,
    };
    let Setup { layout_train, layout_hold, .. } = setup;
    let located_train = layout_train.locate(train)?;
    let located_hold = layout_hold.locate(&recording.rate[n_train..])?;
    Ok(Diagnosis {
        rate_hz,
        samples: len,
        n_train,
        layout_train,
        layout_hold,
        located_train,
        located_hold,
        grid_step,
        baseline_terms,
        recording_terms,
        baseline_model,
        before,
        effects,
        chosen,
        tried,
        tried_params,
        after_model,
        after: combination.after,
        verdict,
        ensembles_run,
    })
}

/// One effect's candidate fits that were found, and the one that scored best alone.
struct BestFit<T> {
    /// The fits found, in the order of the candidates.
    found: Vec<FittedEffect>,
    /// Index in `found` of the best one.
    best: usize,
    /// What `evaluate` returned beside the best one's evaluation.
    built: T,
    /// The best one's evaluation.
    evaluation: Evaluation,
}

/// Of `fits` (one effect's candidate fits), the one whose model `evaluate` scores best (the least
/// mean log score, the order effects are ranked in), with what `evaluate` returned beside its
/// evaluation, and every fit found; the first candidate's reason when none was found.
fn best_fit<T>(
    fits: Vec<Fitted>,
    mut evaluate: impl FnMut(&FittedEffect) -> Result<(T, Evaluation), SimgapError>,
) -> Result<Result<BestFit<T>, String>, SimgapError> {
    let mut found: Vec<FittedEffect> = Vec::new();
    let mut best: Option<(usize, T, Evaluation)> = None;
    let mut why = None;
    for fit in fits {
        match fit {
            Fitted::Found(effect) => {
                let (built, evaluation) = evaluate(&effect)?;
                if best.as_ref().is_none_or(|b| evaluation.mean_log_score() < b.2.mean_log_score()) {
                    best = Some((found.len(), built, evaluation));
                }
                found.push(effect);
            }
            Fitted::NotApplicable(reason) => {
                why.get_or_insert(reason);
            }
        }
    }
    Ok(best
        .map(|(best, built, evaluation)| BestFit { found, best, built, evaluation })
        .ok_or_else(|| why.unwrap_or_default()))
}

/// Beside bias steps found in the training part (the bias-jump candidate with the most steps there),
/// adds to each slow bias motion of [`STEP_BENT`] a second candidate fit made on the training
/// part less those steps' fitted levels (one backfitting pass, Hastie & Tibshirani 1990,
/// *Generalized Additive Models*, §4.4): on the raw part a ramp with a few steps of its own size
/// beside it bends into a warm-up or a temperature response. Each fit is evaluated alone as the
/// others are; where bias steps are kept, the combination chooses the first effect's shape again
/// among all of them ([`reshape_first_beside_steps`]).
fn add_step_corrected_fits(candidates: &mut [(EffectKind, Vec<Fitted>)], data: &TrainingData<'_>) {
    let steps = candidates
        .iter()
        .filter(|(kind, _)| *kind == EffectKind::BiasJumps)
        .flat_map(|(_, fits)| fits.iter())
        .filter_map(|fit| match fit {
            Fitted::Found(FittedEffect { training_part: Some(part), .. }) => Some(part),
            _ => None,
        })
        .max_by_key(|part| part.windows(2).filter(|w| w[0] != w[1]).count());
    let Some(steps) = steps else { return };
    let corrected: Vec<f64> = data.x.iter().zip(steps).map(|(x, s)| x - s).collect();
    let corrected_data = TrainingData { x: &corrected, ..*data };
    for (kind, fits) in candidates.iter_mut().filter(|(kind, _)| STEP_BENT.contains(kind)) {
        if let fit @ Fitted::Found(_) = fit_effect(*kind, &corrected_data) {
            fits.push(fit);
        }
    }
}

/// How many steps the window detector's bias-jump fit `fit` holds (none where it found nothing).
fn window_steps(fit: &Fitted) -> usize {
    match fit {
        Fitted::Found(FittedEffect { params: EffectParams::BiasJumps { detected, .. }, .. }) => *detected,
        _ => 0,
    }
}

/// The nested-model test of `kind` against the fitted `terms`, where the effect has one: a test of
/// presence on the whole recording (a stationary process or a slow bias motion leaves more evidence
/// there than in the training part; each test has its own null at the same length), whose model
/// reaches `total_s`; `seed` seeds its null.
fn nested_test(
    kind: EffectKind,
    recording: &Recording<'_>,
    terms: &NoiseTerms,
    total_s: f64,
    seed: u64,
) -> Result<Option<NestedTest>, SimgapError> {
    let (x, rate_hz) = (recording.rate, recording.rate_hz);
    let test = match (kind, recording.temp_c) {
        (EffectKind::GaussMarkov, _) => gauss_markov_test(x, rate_hz, terms, total_s, seed)?,
        (EffectKind::Warmup, _) => warmup_test(x, rate_hz, terms, total_s, seed)?,
        (EffectKind::Ramp, _) => ramp_test(x, rate_hz, terms, total_s, seed)?,
        (EffectKind::Temperature, Some(temp)) => temperature_test(x, temp, rate_hz, terms, total_s, seed)?,
        _ => return Ok(None),
    };
    Ok(Some(log_nested(kind, test)))
}

/// `test`, logged as `kind`'s nested test.
fn log_nested(kind: EffectKind, test: NestedTest) -> NestedTest {
    tracing::info!(
        "{} nested test: S {:.4}, null zero share {:.2}, mean {:.4}, threshold {:.4}, passed {}",
        kind.name(),
        test.statistic,
        test.null_zero_share,
        test.null_mean,
        test.threshold,
        test.passed
    );
    test
}
