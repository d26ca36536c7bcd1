//! The summary a replay prints (`--json`: one object, the keys of issue 6).

use serde::Serialize;

use gyrocomp::eval::MotionRun;
use gyrocomp::io::Recording;
use gyrocomp::model::Fit;
use gyrocomp::model::baselines::BiasHold;
use gyrocomp::model::metrics::{quantile, rmse, sample_std_dev};
use gyrocomp::stream::{STATUS_MOVING, STATUS_REJECTED};

use crate::stream::ReplayResult;

/// What one replay did.
///
/// `std_raw` and `std_compensated` are the sample standard deviations (deg/s, n − 1) of the first rate column,
/// raw and compensated, over the answered samples that were neither rejected nor moving: on a
/// static recording, how much of the signal the compensation took out.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// Samples published.
    pub sent: usize,
    /// Answers received (one per sample, in order).
    pub received: usize,
    /// Answers flagged "input rejected" (status bit 2).
    pub rejected: usize,
    /// Samples sent but never answered.
    pub dropped: usize,
    /// From the first send to the last answer, s.
    pub duration_s: f64,
    /// `received / duration_s`.
    pub samples_per_s: f64,
    /// Std of the raw first column over static accepted samples, deg/s.
    pub std_raw: f64,
    /// Std of the compensated first column over the same samples, deg/s.
    pub std_compensated: f64,
    /// Answers with an unexpected `seq` (another publisher on the same services), ignored.
    pub unexpected: usize,
    /// Model version of the last answer (0 = no model yet).
    pub model_version: u64,
    /// `"embedded"` (a daemon started in-process) or `"running"` (an existing daemon).
    pub daemon: &'static str,
    /// Whether the offline driver gave the same output bit for bit (checked by the embedded
    /// default run only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub offline_equal: Option<bool>,
    /// With a true-drift column (simulated recordings): RMS of (subtracted drift − true drift) of
    /// the first axis, deg/s, from the end of the start-up window on.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drift_rmse_dps: Option<f64>,
    /// The same for the start-up bias-hold baseline (mean of the first 60 s, held), beside it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drift_rmse_bias_hold_dps: Option<f64>,
    /// With injected motion (the embedded default): per-motion angle errors, see [`MotionFigures`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub motion: Option<MotionFigures>,
}

/// Angle errors |∫(compensated − truth)dt| of the first column per motion segment
/// ([`gyrocomp::eval::MotionRun`]): gyrocomp's answers beside start-up bias-hold, last-static
/// (the ZARU reference: it knows when the platform stops) and the white-noise floor 0.674·N·√T
/// of the same recording.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MotionFigures {
    /// Motion segments.
    pub motions: usize,
    /// Median per-motion angle error of the replayed output, deg.
    pub gyrocomp_median_deg: f64,
    /// The same for start-up bias-hold (mean of the first 60 s or up to the first motion).
    pub bias_hold_median_deg: f64,
    /// The same for last-static: each motion compensated by the mean of the last 60 s of
    /// samples the injected profile marks static (the daemon never sees those flags).
    pub last_static_median_deg: f64,
    /// Median white-noise floor of the motions, deg.
    pub floor_median_deg: f64,
    /// Angle error over the whole run, deg: gyrocomp and bias-hold.
    pub gyrocomp_run_deg: f64,
    /// The same for bias-hold.
    pub bias_hold_run_deg: f64,
    /// The same for last-static.
    pub last_static_run_deg: f64,
    /// Every motion's angle errors and floor, for pooling over recordings (not serialised).
    #[serde(skip)]
    pub per_motion: PerMotion,
}

/// The per-motion angle errors behind [`MotionFigures`], in the segments' order, deg.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PerMotion {
    /// gyrocomp's answers.
    pub gyrocomp: Vec<f64>,
    /// Start-up bias-hold.
    pub bias_hold: Vec<f64>,
    /// Last-static.
    pub last_static: Vec<f64>,
    /// The white-noise floor 0.674·N·√T.
    pub floor: Vec<f64>,
}

impl MotionFigures {
    /// The figures of `per_motion` (medians of each model's angle errors and of the floor) with
    /// the whole-run errors `run_deg` of gyrocomp, bias-hold and last-static; `None` without
    /// motions or floor.
    pub fn of(per_motion: PerMotion, run_deg: [f64; 3]) -> Option<Self> {
        let median = |v: &[f64]| quantile(v, 0.5);
        Some(Self {
            motions: per_motion.gyrocomp.len(),
            gyrocomp_median_deg: median(&per_motion.gyrocomp)?,
            bias_hold_median_deg: median(&per_motion.bias_hold)?,
            last_static_median_deg: median(&per_motion.last_static)?,
            floor_median_deg: median(&per_motion.floor)?,
            gyrocomp_run_deg: run_deg[0],
            bias_hold_run_deg: run_deg[1],
            last_static_run_deg: run_deg[2],
            per_motion,
        })
    }
}

impl PerMotion {
    /// Appends `other`'s motions (pooling recordings).
    pub fn extend(&mut self, other: &PerMotion) {
        self.gyrocomp.extend_from_slice(&other.gyrocomp);
        self.bias_hold.extend_from_slice(&other.bias_hold);
        self.last_static.extend_from_slice(&other.last_static);
        self.floor.extend_from_slice(&other.floor);
    }
}

/// Start-up window of the bias-hold baseline, s.
const BIAS_HOLD_S: f64 = 60.0;
/// Window of the last-static reference, s (as `gyrocomp eval --protocol motion`'s).
const LAST_STATIC_S: f64 = 60.0;

impl Summary {
    /// The summary of `result` for recording `rec`.
    pub fn new(rec: &Recording, result: &ReplayResult, daemon: &'static str) -> Self {
        let raw = rec.rate(0).unwrap_or(&[]);
        let kept: Vec<usize> = (0..result.outputs.len())
            .filter(|&i| result.outputs[i].status & (STATUS_REJECTED | STATUS_MOVING) == 0)
            .collect();
        let std = |x: Vec<f64>| sample_std_dev(&x).unwrap_or(f64::NAN);
        let std_raw = std(kept.iter().map(|&i| raw[i]).collect());
        let std_compensated = std(kept.iter().map(|&i| result.outputs[i].rate_dps[0]).collect());
        let duration_s = result.duration.as_secs_f64();
        let received = result.outputs.len();
        Self {
            sent: result.sent,
            received,
            rejected: result.outputs.iter().filter(|o| o.status & STATUS_REJECTED != 0).count(),
            dropped: result.dropped(),
            duration_s,
            samples_per_s: if duration_s > 0.0 { received as f64 / duration_s } else { 0.0 },
            std_raw,
            std_compensated,
            unexpected: result.unexpected,
            model_version: result.outputs.last().map_or(0, |o| o.model_version),
            daemon,
            offline_equal: None,
            drift_rmse_dps: None,
            drift_rmse_bias_hold_dps: None,
            motion: None,
        }
    }

    /// Adds the per-motion angle errors against the injected `truth` profile (`moving`: its
    /// segments); left out when the run cannot be scored (no static start, too short).
    pub fn with_motion(mut self, rec: &Recording, result: &ReplayResult, truth: Vec<f64>, moving: &[bool]) -> Self {
        let raw = rec.rate(0).unwrap_or(&[]).to_vec();
        let Ok(run) = MotionRun::new(rec.t_s().to_vec(), raw, truth, moving) else { return self };
        let ours: Vec<f64> = result.outputs.iter().map(|o| o.rate_dps[0]).collect();
        let (Ok(g), Ok(hold), Ok(last)) =
            (run.score(&ours), run.bias_hold(BIAS_HOLD_S), run.last_static(moving, LAST_STATIC_S))
        else {
            return self;
        };
        let (Ok(b), Ok(l)) = (run.score(&hold.compensated), run.score(&last)) else { return self };
        let floor = run.sensor_arw().map(|n| run.white_noise_floor(n)).unwrap_or_default();
        let per_motion = PerMotion {
            gyrocomp: g.angle_err_deg_segments,
            bias_hold: b.angle_err_deg_segments,
            last_static: l.angle_err_deg_segments,
            floor,
        };
        self.motion = MotionFigures::of(per_motion, [g.angle_err_deg_run, b.angle_err_deg_run, l.angle_err_deg_run]);
        self
    }

    /// Adds the drift errors against `truth` (the first axis' true drift, one value per row):
    /// ours and the start-up bias-hold baseline's, over the answered rows after its 60 s window
    /// (which ends at the first sample of `first_motion`, when motion was injected).
    pub fn with_truth(
        mut self,
        rec: &Recording,
        result: &ReplayResult,
        truth: &[f64],
        first_motion: Option<usize>,
    ) -> Self {
        let raw = rec.rate(0).unwrap_or(&[]);
        let mut hold = BiasHold::from_duration(BIAS_HOLD_S, rec.sample_rate_hz().unwrap_or(1.0));
        hold.samples = hold.samples.min(first_motion.unwrap_or(usize::MAX)).max(1);
        let n = result.outputs.len().min(truth.len());
        let Ok(model) = hold.fit(&raw[..n]) else { return self };
        let rows = hold.samples..n;
        let ours: Vec<f64> = rows.clone().map(|i| result.outputs[i].drift_dps[0]).collect();
        let held = vec![model.bias; rows.len()];
        self.drift_rmse_dps = rmse(&ours, &truth[rows.clone()]);
        self.drift_rmse_bias_hold_dps = rmse(&held, &truth[rows]);
        self
    }

    /// A few readable lines (the main job prints its motion figures itself, [`crate::main_job::MainJob::text`]).
    pub fn text(&self) -> String {
        let check = match self.offline_equal {
            Some(true) => {
                "\noffline driver (gyrocomp compensate's pipeline) on the same recording: identical, bit for bit"
            }
            Some(false) => "\noffline driver (gyrocomp compensate's pipeline) on the same recording: DIFFERENT",
            None => "",
        };
        let text = format!(
            "replay ({} daemon): sent {}, received {}, rejected {}, dropped {} in {:.2} s ({:.0} samples/s)\n\
             std of the first column over static samples: raw {:.4e} deg/s, compensated {:.4e} deg/s; model version {}",
            self.daemon,
            self.sent,
            self.received,
            self.rejected,
            self.dropped,
            self.duration_s,
            self.samples_per_s,
            self.std_raw,
            self.std_compensated,
            self.model_version
        );
        let truth = match (self.drift_rmse_dps, self.drift_rmse_bias_hold_dps) {
            (Some(ours), Some(hold)) => format!(
                "\nRMS(drift − true drift), first column: gyrocomp {ours:.4e} deg/s, start-up bias-hold {hold:.4e} deg/s"
            ),
            _ => String::new(),
        };
        text + &truth + check
    }
}
