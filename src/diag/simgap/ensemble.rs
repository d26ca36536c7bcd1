//! The seeded Monte-Carlo ensemble of a simulated model, compared with the recording on the
//! training and the hold-out part.
//!
//! Every member simulates the *whole* recording length from t = 0 and is cut where the recording
//! is cut, so effects that depend on absolute time (warm-up, ramp, temperature, the phase of a
//! sinusoid) are evaluated at the hold-out part's own time offset. Member j uses the seed
//! splitmix64(seed ⊕ splitmix64(j + 1)) ([`super::model::member_seed`]), the same for every model of a diagnosis: models that
//! differ by one effect are compared on common random numbers.
//!
//! With a fitted baseline each member also carries its own noise terms, the fitted ones changed by
//! a bootstrap draw of their uncertainty ([`super::uncertainty`]).
//!
//! Members are independent, so they may be spread over `threads` scoped threads; each result is
//! stored at its member's index, so the outcome does not depend on the thread count.

use serde::Serialize;

use super::SimgapError;
use super::gap::PartComparison;
use super::model::{SimModel, member_seed, simulate};
use super::stats::StatLayout;
use super::uncertainty::{Perturbation, perturbed};

/// The recording's side of a diagnosis: layouts and real statistics of both parts, and how to
/// build the ensemble.
#[derive(Debug, Clone)]
pub struct Setup<'a> {
    /// Sample rate, Hz.
    pub rate_hz: f64,
    /// Samples of the whole recording.
    pub len: usize,
    /// Samples of the training part (the hold-out part is the rest).
    pub n_train: usize,
    /// Recorded temperature of the whole recording, if any.
    pub temp_c: Option<&'a [f64]>,
    /// Statistics of the training part.
    pub layout_train: StatLayout,
    /// Statistics of the hold-out part.
    pub layout_hold: StatLayout,
    /// The real training part's statistics.
    pub real_train: Vec<f64>,
    /// The real hold-out part's statistics.
    pub real_hold: Vec<f64>,
    /// Ensemble size (≥ 4).
    pub members: usize,
    /// Seed of the ensemble.
    pub seed: u64,
    /// Worker threads (1 = none).
    pub threads: usize,
    /// Per-member changes of the noise terms ([`super::uncertainty`]); empty for none.
    pub perturbations: Vec<Perturbation>,
}

/// A simulated model compared with the recording on both parts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Evaluation {
    /// Training part.
    pub train: PartComparison,
    /// Hold-out part.
    pub hold: PartComparison,
}

impl Evaluation {
    /// Both parts tested at the stricter level `p` ([`PartComparison::at_level`]).
    pub fn at_level(&self, p: f64) -> Evaluation {
        Evaluation { train: self.train.at_level(p), hold: self.hold.at_level(p) }
    }

    /// Whether either part shows a significant gap.
    pub fn significant(&self) -> bool {
        self.train.significant || self.hold.significant
    }

    /// The mean of the training and hold-out gaps.
    pub fn mean_gap(&self) -> f64 {
        0.5 * (self.train.score.gap + self.hold.score.gap)
    }

    /// The ranking score of a model: the mean of the training and hold-out Dawid–Sebastiani
    /// scores ([`super::gap::GapScore::log_score`]), lower is better.
    pub fn mean_log_score(&self) -> f64 {
        0.5 * (self.train.score.log_score + self.hold.score.log_score)
    }
}

/// What one ensemble member gives: its statistics on the training part and on the hold-out part.
type MemberResult = Result<(Vec<f64>, Vec<f64>), SimgapError>;

fn member(setup: &Setup<'_>, model: &SimModel, j: usize) -> MemberResult {
    let own;
    let model = match setup.perturbations.get(j) {
        Some(delta) => {
            own = perturbed(model, delta);
            &own
        }
        None => model,
    };
    let x = simulate(model, setup.rate_hz, setup.len, setup.temp_c, member_seed(setup.seed, j))?;
    let (train, hold) = x.split_at(setup.n_train);
    let temp = setup.temp_c.map(|t| t.split_at(setup.n_train));
    Ok((setup.layout_train.compute(train, temp.map(|t| t.0))?, setup.layout_hold.compute(hold, temp.map(|t| t.1))?))
}

/// Runs the ensemble of `model` and compares it with the recording.
pub fn evaluate(setup: &Setup<'_>, model: &SimModel) -> Result<Evaluation, SimgapError> {
    let m = setup.members;
    let threads = setup.threads.clamp(1, m);
    let mut results: Vec<Option<MemberResult>> = (0..m).map(|_| None).collect();
    if threads == 1 {
        for (j, r) in results.iter_mut().enumerate() {
            *r = Some(member(setup, model, j));
        }
    } else {
        let chunk = m.div_ceil(threads);
        std::thread::scope(|s| {
            for (c, slots) in results.chunks_mut(chunk).enumerate() {
                s.spawn(move || {
                    for (i, r) in slots.iter_mut().enumerate() {
                        *r = Some(member(setup, model, c * chunk + i));
                    }
                });
            }
        });
    }
    let mut train = Vec::with_capacity(m);
    let mut hold = Vec::with_capacity(m);
    for r in results {
        let (a, b) = r.expect("every member ran")?;
        train.push(a);
        hold.push(b);
    }
    let evaluation = Evaluation {
        train: PartComparison::new(setup.layout_train.info(), setup.real_train.clone(), &train),
        hold: PartComparison::new(setup.layout_hold.info(), setup.real_hold.clone(), &hold),
    };
    for (name, part) in [("training", &evaluation.train), ("hold-out", &evaluation.hold)] {
        let groups: Vec<String> =
            part.score.groups.iter().map(|g| format!("{} {:.2}", g.group.name(), g.rms_z)).collect();
        tracing::debug!("{name}: gap {:.3}, RMS z by group: {}", part.score.gap, groups.join(", "));
    }
    Ok(evaluation)
}
