//! The `--json` document of `gyrocomp simgap` and the `where` entries it shares with the text
//! and HTML reports.

use serde::Serialize;
use serde_json::{Map, Value};

use super::simgap_args::SimgapArgs;
use crate::diag::simgap::baseline::NoiseTerms;
use crate::diag::simgap::gap::PartComparison;
use crate::diag::simgap::stats::{Locations, StatInfo};
use crate::diag::simgap::{Diagnosis, Verdict};

/// One entry of `where`.
#[derive(Debug, Serialize)]
pub struct WhereEntry {
    /// Kind of statistic.
    pub statistic: &'static str,
    /// τ, band, scale or time span.
    pub band: String,
    /// Real value (natural unit).
    pub real: f64,
    /// Ensemble 2.5 % quantile.
    pub sim_lo: f64,
    /// Ensemble 97.5 % quantile.
    pub sim_hi: f64,
    /// Ensemble median.
    pub sim_median: f64,
    /// Standard score of the real value in the band.
    pub z: f64,
    /// Unit of the values.
    pub unit: &'static str,
}

/// The statistics of `part` outside their band, largest |z| first; a line or step statistic's
/// band says at which frequency or time the real part's line or step lies (`located`).
pub fn where_entries(info: &[StatInfo], part: &PartComparison, located: &Locations) -> Vec<WhereEntry> {
    part.outside_by_size()
        .into_iter()
        .map(|i| {
            let (s, b) = (&info[i], &part.bands[i]);
            WhereEntry {
                statistic: s.statistic,
                band: match located.at(i) {
                    Some(at) => format!("{}; the real part's at {}", s.band, at.text()),
                    None => s.band.clone(),
                },
                real: s.natural(part.real[i]),
                sim_lo: s.natural(b.lo),
                sim_hi: s.natural(b.hi),
                sim_median: s.natural(b.median),
                z: part.z[i],
                unit: s.unit,
            }
        })
        .collect()
}

fn params_map(params: &[(&'static str, f64)]) -> Map<String, Value> {
    params.iter().map(|&(k, v)| (k.to_owned(), Value::from(v))).collect()
}

pub(super) fn json_report<'a>(args: &'a SimgapArgs, d: &Diagnosis) -> JsonReport<'a> {
    let effects: Vec<Value> = d
        .effects
        .iter()
        .map(|e| {
            let mut m = Map::new();
            m.insert("name".into(), e.kind.name().into());
            m.insert(
                "params".into(),
                Value::Object(params_map(&e.params.as_ref().map_or_else(Vec::new, |p| p.named()))),
            );
            m.insert("gap".into(), e.evaluation.as_ref().map(|v| v.train.score.gap).into());
            m.insert("gap_holdout".into(), e.evaluation.as_ref().map(|v| v.hold.score.gap).into());
            m.insert("explains".into(), e.accepted().into());
            m.insert("share_train".into(), e.judgement.and_then(|j| j.share_train).into());
            m.insert("share_holdout".into(), e.judgement.and_then(|j| j.share_hold).into());
            m.insert("explains_against_own_null".into(), e.accepted_by_own_null().into());
            m.insert("gap_own_null".into(), e.own_null.as_ref().map(|v| v.train.score.gap).into());
            m.insert("gap_holdout_own_null".into(), e.own_null.as_ref().map(|v| v.hold.score.gap).into());
            m.insert("detector".into(), serde_json::to_value(&e.detector).unwrap_or(Value::Null));
            m.insert("nested".into(), serde_json::to_value(&e.nested).unwrap_or(Value::Null));
            m.insert("supported".into(), e.supported.into());
            m.insert("log_score".into(), e.evaluation.as_ref().map(|v| v.mean_log_score()).into());
            m.insert("log_score_holdout".into(), e.evaluation.as_ref().map(|v| v.hold.score.log_score).into());
            m.insert("note".into(), e.note.clone().into());
            Value::Object(m)
        })
        .collect();
    let part = |p: &PartComparison| {
        serde_json::json!({
            "gap": p.score.gap,
            "significant": p.significant,
            "gap_threshold": p.null.gap_threshold(),
            "max_abs_z": p.score.max_abs_z,
            "t": p.t,
            "t_threshold": p.null.threshold,
            "t_members": p.null.t,
            "flag": p.flag,
            "null_median": p.null.median,
            "outside": p.score.outside,
            "allan_decades": p.score.allan_decades,
            "groups": p.score.groups,
        })
    };
    JsonReport {
        gap_before: d.before.hold.score.gap,
        gap_after: d.after.hold.score.gap,
        r#where: where_entries(d.layout_hold.info(), &d.before.hold, &d.located_hold),
        effects,
        chosen: d.chosen.iter().map(|k| k.name()).collect(),
        tried: d.tried.iter().map(|k| k.name()).collect(),
        tried_params: d.tried_params.iter().map(|p| Value::Object(params_map(&p.named()))).collect(),
        verdict: d.verdict,
        gap_before_train: d.before.train.score.gap,
        gap_after_train: d.after.train.score.gap,
        before: serde_json::json!({"train": part(&d.before.train), "holdout": part(&d.before.hold)}),
        after: serde_json::json!({"train": part(&d.after.train), "holdout": part(&d.after.hold)}),
        where_train: where_entries(d.layout_train.info(), &d.before.train, &d.located_train),
        where_after: where_entries(d.layout_hold.info(), &d.after.hold, &d.located_hold),
        baseline_terms: d.baseline_terms,
        recording_terms: d.recording_terms,
        grid_step_dps: d.grid_step,
        column: &args.column,
        samples: d.samples,
        rate_hz: d.rate_hz,
        train_samples: d.n_train,
        holdout: args.holdout,
        ensemble: args.ensemble,
        seed: args.seed,
        min_share: args.min_share,
        ensembles_run: d.ensembles_run,
        gap_definition: "root of the mean over statistic groups of the mean z^2 in the group; z = (real - ensemble median) / ensemble sd",
    }
}

/// The JSON document of `--json`; the first five keys are the interface of issue 8, in order.
#[derive(Serialize)]
pub(super) struct JsonReport<'a> {
    gap_before: f64,
    gap_after: f64,
    r#where: Vec<WhereEntry>,
    effects: Vec<Value>,
    chosen: Vec<&'static str>,
    tried: Vec<&'static str>,
    /// The parameters of each kept effect as the final model holds them (another candidate fit
    /// than the one `effects` lists, where the combination kept another).
    tried_params: Vec<Value>,
    verdict: Verdict,
    gap_before_train: f64,
    gap_after_train: f64,
    before: Value,
    after: Value,
    where_train: Vec<WhereEntry>,
    where_after: Vec<WhereEntry>,
    baseline_terms: Option<NoiseTerms>,
    recording_terms: Option<NoiseTerms>,
    grid_step_dps: Option<f64>,
    column: &'a str,
    samples: usize,
    rate_hz: f64,
    train_samples: usize,
    holdout: f64,
    ensemble: usize,
    seed: u64,
    min_share: f64,
    ensembles_run: usize,
    gap_definition: &'static str,
}
