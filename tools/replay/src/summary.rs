//! The summary a replay prints (`--json`: one object, the keys of issue 6).

use serde::Serialize;

use gyrocomp::io::Recording;
use gyrocomp::model::Fit;
use gyrocomp::model::baselines::BiasHold;
use gyrocomp::model::metrics::{rmse, std_dev};
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
}

/// Start-up window of the bias-hold baseline, s.
const BIAS_HOLD_S: f64 = 60.0;

impl Summary {
    /// The summary of `result` for recording `rec`.
    pub fn new(rec: &Recording, result: &ReplayResult, daemon: &'static str) -> Self {
        let raw = rec.rate(0).unwrap_or(&[]);
        let kept: Vec<usize> = (0..result.outputs.len())
            .filter(|&i| result.outputs[i].status & (STATUS_REJECTED | STATUS_MOVING) == 0)
            .collect();
        let std = |x: Vec<f64>| std_dev(&x).unwrap_or(f64::NAN);
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
        }
    }

    /// Adds the drift errors against `truth` (the first axis' true drift, one value per row):
    /// ours and the start-up bias-hold baseline's, over the answered rows after its 60 s window.
    pub fn with_truth(mut self, rec: &Recording, result: &ReplayResult, truth: &[f64]) -> Self {
        let raw = rec.rate(0).unwrap_or(&[]);
        let hold = BiasHold::from_duration(BIAS_HOLD_S, rec.sample_rate_hz().unwrap_or(1.0));
        let n = result.outputs.len().min(truth.len());
        let Ok(model) = hold.fit(&raw[..n]) else { return self };
        let rows = hold.samples..n;
        let ours: Vec<f64> = rows.clone().map(|i| result.outputs[i].drift_dps[0]).collect();
        let held = vec![model.bias; rows.len()];
        self.drift_rmse_dps = rmse(&ours, &truth[rows.clone()]);
        self.drift_rmse_bias_hold_dps = rmse(&held, &truth[rows]);
        self
    }

    /// A few readable lines.
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
