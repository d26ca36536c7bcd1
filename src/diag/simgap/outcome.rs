//! What a diagnosis finds: the verdict, each candidate effect's result, the whole diagnosis.

use serde::Serialize;

use super::baseline::NoiseTerms;
use super::ensemble::Evaluation;
use super::greedy::{DetectorTest, Judgement};
use super::model::SimModel;
use super::nested::NestedTest;
use super::params::{EffectKind, EffectParams};
use super::stats::{Locations, StatLayout};

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
            Verdict::PartlyExplained => {
                "gap partly explained: the chosen effects remove most of it; a significant residual remains"
            }
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
    /// tested at [`super::greedy::OWN_NULL_LEVEL`]; with a given baseline, which is not refitted,
    /// the baseline itself (`None` when the effect has no deterministic part).
    pub own_null: Option<Evaluation>,
    /// How baseline-refit + effect compares with its own null.
    pub own_null_judgement: Option<Judgement>,
    /// The test on the effect's own detector against its own null ([`super::greedy`]).
    pub detector: Option<DetectorTest>,
    /// The nested-model test of the effect against the baseline: a Gauss–Markov process
    /// ([`super::nested`]), a temperature response ([`super::nested_temperature`]), a warm-up
    /// ([`super::nested_warmup`]) or a ramp ([`super::nested_ramp`]).
    pub nested: Option<NestedTest>,
    /// Whether the effect's own tests leave it a candidate ([`super::greedy::own_evidence`]): false
    /// when its model comparison against the baseline finds no more of it than a recording
    /// without it typically shows and its matched filter does not stand out either, and false for
    /// an effect that is not applicable. An effect without that support is never kept, however
    /// much its simulation narrows the gap.
    pub supported: bool,
}

impl EffectResult {
    /// Whether adding the effect is accepted against the baseline or against its own null.
    pub fn accepted(&self) -> bool {
        self.supported && (self.judgement.is_some_and(|j| j.explains) || self.accepted_by_own_null())
    }

    /// Whether it is accepted against its own null ([`super::greedy`]).
    pub fn accepted_by_own_null(&self) -> bool {
        self.supported
            && (self.own_null_judgement.is_some_and(|j| j.explains)
                || self.detector.as_ref().is_some_and(|d| d.passed)
                || self.nested.as_ref().is_some_and(|t| t.passed && !t.outranked))
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
    /// Where the real training part's strongest lines and steps lie.
    pub located_train: Locations,
    /// Where the real hold-out part's strongest lines and steps lie.
    pub located_hold: Locations,
    /// Grid step of the recording's values, if any.
    pub grid_step: Option<f64>,
    /// The fitted noise terms (`None` with a given baseline).
    pub baseline_terms: Option<NoiseTerms>,
    /// With a given simulator: the IEEE Std 952 terms fitted to the training part, to set beside
    /// the simulator's own (a gap at short τ is then read off as "the simulator's N is low");
    /// `None` with a fitted baseline, whose terms these are, or when the fit fails.
    pub recording_terms: Option<NoiseTerms>,
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
    /// The fitted parameters of each effect of `tried`, as the final model holds them: for an
    /// effect with several candidate fits (a sinusoid's two line detectors, the bias jumps' window
    /// and segmentation fits) the combination may keep another fit than the one that scored best
    /// alone, whose parameters `effects` lists ([`super::greedy::combine`]).
    pub tried_params: Vec<EffectParams>,
    /// The model with the kept effects (`tried`).
    pub after_model: SimModel,
    /// Its evaluation (the gap after; the baseline's when none was kept).
    pub after: Evaluation,
    /// The verdict.
    pub verdict: Verdict,
    /// Ensembles run.
    pub ensembles_run: usize,
}

impl Diagnosis {
    /// The kept effects whose final model holds another of their candidate fits than the one
    /// `effects` lists (the one that scored best alone), with the parameters kept.
    pub fn kept_with_other_fit(&self) -> impl Iterator<Item = (EffectKind, &EffectParams)> {
        self.tried.iter().zip(&self.tried_params).filter_map(|(&kind, params)| {
            self.effects.iter().any(|e| e.kind == kind && e.params.as_ref() != Some(params)).then_some((kind, params))
        })
    }
}
