//! The main job's report: one [`Summary`] per seeded recording and the figures pooled over them.
//!
//! Why several recordings: start-up bias-hold's error is one draw per recording (the mean of the
//! first seconds before the first turn), so a single recording's per-turn ratio against it says
//! more about that draw than about the tracker. On the main job's scenario, seeds 0–7, the
//! ratio went from 0.12× to 2.1× bias-hold per turn with the same binary; pooled over the
//! recordings' turns it is a measurement.

use serde::Serialize;

use crate::summary::{MotionFigures, PerMotion, Summary};

/// One recording of the main job: its seed (simulation and motion profile) and its summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SeededSummary {
    /// Seed of the simulated gyro and of its turns.
    pub seed: u64,
    /// The replay's summary, with the motion figures.
    #[serde(flatten)]
    pub summary: Summary,
}

/// The per-motion figures pooled over the recordings' turns (medians of all motions together;
/// whole-run errors summed over the recordings).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PooledFigures {
    /// Recordings pooled.
    pub recordings: usize,
    /// The pooled figures, with every motion of every recording in `per_motion`.
    #[serde(flatten)]
    pub figures: MotionFigures,
    /// Smallest and largest per-recording ratio of gyrocomp's per-motion median to bias-hold's.
    pub ratio_range: (f64, f64),
    /// Recordings on which gyrocomp's per-motion median is above bias-hold's.
    pub recordings_above_bias_hold: usize,
    /// RMS(drift − true drift) of the first column over the recordings (all of one length), deg/s:
    /// gyrocomp and, beside it, bias-hold.
    pub drift_rmse_dps: (f64, f64),
}

impl PooledFigures {
    /// The figures pooled over `runs`; `None` when a run has no motion figures or drift errors.
    pub fn of(runs: &[SeededSummary]) -> Option<Self> {
        let mut per_motion = PerMotion::default();
        let (mut motions, mut drift) = (Vec::with_capacity(runs.len()), Vec::with_capacity(runs.len()));
        for run in runs {
            let s = &run.summary;
            let m = s.motion.as_ref()?;
            per_motion.extend(&m.per_motion);
            motions.push(m);
            drift.push((s.drift_rmse_dps?, s.drift_rmse_bias_hold_dps?));
        }
        let ratios: Vec<f64> = motions.iter().map(|m| m.gyrocomp_median_deg / m.bias_hold_median_deg).collect();
        let rms = |v: Vec<f64>| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
        let sum = |pick: fn(&MotionFigures) -> f64| motions.iter().map(|m| pick(m)).sum();
        let run_deg = [sum(|m| m.gyrocomp_run_deg), sum(|m| m.bias_hold_run_deg), sum(|m| m.last_static_run_deg)];
        let figures = MotionFigures::of(per_motion, run_deg)?;
        Some(Self {
            recordings: runs.len(),
            figures,
            ratio_range: (
                ratios.iter().copied().fold(f64::INFINITY, f64::min),
                ratios.iter().copied().fold(0.0, f64::max),
            ),
            recordings_above_bias_hold: ratios.iter().filter(|&&r| r > 1.0).count(),
            drift_rmse_dps: (rms(drift.iter().map(|d| d.0).collect()), rms(drift.iter().map(|d| d.1).collect())),
        })
    }
}

/// The main job's report (module documentation).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MainJob {
    /// Each recording, in seed order.
    pub recordings: Vec<SeededSummary>,
    /// The figures pooled over them (`None` when a recording could not be scored).
    pub pooled: Option<PooledFigures>,
}

impl MainJob {
    /// The report of `recordings`.
    pub fn new(recordings: Vec<SeededSummary>) -> Self {
        let pooled = PooledFigures::of(&recordings);
        Self { recordings, pooled }
    }

    /// Whether every recording came back whole and, where checked, equal to the offline driver.
    pub fn succeeded(&self) -> bool {
        self.recordings.iter().all(|r| r.summary.dropped == 0 && r.summary.offline_equal != Some(false))
    }

    /// One line per recording, then the pooled figures.
    pub fn text(&self) -> String {
        let mut text = String::new();
        for r in &self.recordings {
            let s = &r.summary;
            let motion = s.motion.as_ref().map_or_else(String::new, |m| {
                format!(
                    "; per turn ({}) gyrocomp {:.3} deg = {:.2}× bias-hold's {:.3}, last-static {:.3}; whole run {:.2} / {:.2} deg",
                    m.motions,
                    m.gyrocomp_median_deg,
                    m.gyrocomp_median_deg / m.bias_hold_median_deg,
                    m.bias_hold_median_deg,
                    m.last_static_median_deg,
                    m.gyrocomp_run_deg,
                    m.bias_hold_run_deg
                )
            });
            let offline = match s.offline_equal {
                Some(true) => "; offline driver identical",
                Some(false) => "; offline driver DIFFERENT",
                None => "",
            };
            text += &format!(
                "seed {}: sent {}, received {}, rejected {}, dropped {} in {:.2} s ({:.0} samples/s){motion}{offline}\n",
                r.seed, s.sent, s.received, s.rejected, s.dropped, s.duration_s, s.samples_per_s
            );
        }
        if let Some(pooled) = &self.pooled {
            let p = &pooled.figures;
            text += &format!(
                "pooled over {} recordings, {} turns (first column):\n\
                 angle error per turn, median: gyrocomp {:.3} deg = {:.2}× start-up bias-hold's {:.3} deg \
                 ({:.2}–{:.2}× per recording, above it on {} of {}); last-static, which knows when the platform stops, {:.3} deg; \
                 white-noise floor 0.674·N·√T {:.3} deg\n\
                 angle error over the whole runs, summed: gyrocomp {:.1} deg, bias-hold {:.1} deg, last-static {:.1} deg\n\
                 RMS(drift − true drift): gyrocomp {:.4e} deg/s, start-up bias-hold {:.4e} deg/s",
                pooled.recordings,
                p.motions,
                p.gyrocomp_median_deg,
                p.gyrocomp_median_deg / p.bias_hold_median_deg,
                p.bias_hold_median_deg,
                pooled.ratio_range.0,
                pooled.ratio_range.1,
                pooled.recordings_above_bias_hold,
                pooled.recordings,
                p.last_static_median_deg,
                p.floor_median_deg,
                p.gyrocomp_run_deg,
                p.bias_hold_run_deg,
                p.last_static_run_deg,
                pooled.drift_rmse_dps.0,
                pooled.drift_rmse_dps.1
            );
        }
        text.trim_end().to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(seed: u64, ours: Vec<f64>, hold: Vec<f64>, drift: (f64, f64)) -> SeededSummary {
        let n = ours.len();
        let per_motion = PerMotion { floor: vec![0.5; n], last_static: vec![1.0; n], gyrocomp: ours, bias_hold: hold };
        let motion = MotionFigures::of(per_motion, [2.0, 3.0, 1.0]).unwrap();
        let summary = Summary {
            sent: 10,
            received: 10,
            rejected: 0,
            dropped: 0,
            duration_s: 1.0,
            samples_per_s: 10.0,
            std_raw: 1.0,
            std_compensated: 1.0,
            unexpected: 0,
            model_version: 0,
            daemon: "embedded",
            offline_equal: Some(true),
            drift_rmse_dps: Some(drift.0),
            drift_rmse_bias_hold_dps: Some(drift.1),
            motion: Some(motion),
        };
        SeededSummary { seed, summary }
    }

    #[test]
    fn pooling_takes_the_median_of_all_motions_not_the_median_of_medians() {
        // Medians per recording: 1 and 10 (ours), 2 and 2 (bias-hold); all six motions pooled:
        // ours {0, 1, 2, 9, 10, 11} → 5.5, bias-hold {1, 2, 3, 1, 2, 3} → 2.
        let job = MainJob::new(vec![
            run(0, vec![0.0, 1.0, 2.0], vec![1.0, 2.0, 3.0], (3.0, 4.0)),
            run(1, vec![9.0, 10.0, 11.0], vec![1.0, 2.0, 3.0], (4.0, 3.0)),
        ]);
        let p = job.pooled.as_ref().unwrap();
        assert_eq!((p.recordings, p.figures.motions), (2, 6));
        assert_eq!((p.figures.gyrocomp_median_deg, p.figures.bias_hold_median_deg), (5.5, 2.0));
        assert_eq!(p.ratio_range, (0.5, 5.0));
        assert_eq!(p.recordings_above_bias_hold, 1);
        assert_eq!((p.figures.gyrocomp_run_deg, p.figures.bias_hold_run_deg), (4.0, 6.0));
        // RMS over equal-length recordings: √((9 + 16)/2) both ways.
        let rms = (12.5f64).sqrt();
        assert!((p.drift_rmse_dps.0 - rms).abs() < 1e-12 && (p.drift_rmse_dps.1 - rms).abs() < 1e-12);
        assert!(job.succeeded());
        assert!(job.text().contains("pooled over 2 recordings, 6 turns"), "{}", job.text());
    }

    #[test]
    fn a_recording_that_could_not_be_scored_leaves_nothing_pooled_and_a_loss_fails_the_job() {
        let mut unscored = run(1, vec![1.0], vec![1.0], (1.0, 1.0));
        unscored.summary.motion = None;
        unscored.summary.dropped = 1;
        let job = MainJob::new(vec![run(0, vec![1.0], vec![2.0], (1.0, 1.0)), unscored]);
        assert!(job.pooled.is_none());
        assert!(!job.succeeded());
    }
}
