//! How a motion detector did on a motion-injected run (issue 13, item 3: "report detection delay,
//! leaked samples and false alarms on the motion protocol"). Pure numerics: the pipeline's
//! per-sample judgement (`STATUS_MOVING` of each output) against the run's true motion segments.
//!
//! Per run, with the segments S of the truth (maximal runs of `moving` = 1) and the judged flags j:
//! - a motion is **found** when some sample inside it is judged moving, **missed** otherwise;
//! - its **delay** is t(first sample of S judged moving) − t(first sample of S): 0 when the
//!   judgement was already "moving" as the motion began (an earlier alarm still settling);
//! - **leaked** samples are true-motion samples judged static (they may reach the drift estimate,
//!   unless the look-back discards them at the onset); the **leaked angle** of a motion is
//!   Σ |truth_i|·Δt_i over them, deg: the rotation that was passed on as static;
//! - a **false alarm** is a maximal run of judged-moving samples that overlaps no motion segment
//!   (a run that starts early, or settles after a motion, belongs to that motion); the hold-off
//!   after a motion (`settle_s`) is counted apart as static samples **held moving**.

use serde::Serialize;

use super::motion::{MotionError, MotionRun, segments};
use crate::model::metrics::quantile;

/// The detector's scores on one run (module documentation).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DetectionScores {
    /// Motion segments of the truth.
    pub motions: usize,
    /// Of them, those with no sample judged moving.
    pub missed: usize,
    /// Delay of each found motion, in order, s.
    pub delays_s: Vec<f64>,
    /// Median of `delays_s`, s (`None` when no motion was found).
    pub delay_s_median: Option<f64>,
    /// 95th percentile of `delays_s`, s.
    pub delay_s_p95: Option<f64>,
    /// Samples inside motions.
    pub moving_samples: usize,
    /// Of them, those judged static.
    pub leaked_samples: usize,
    /// Leaked angle of each motion, in order, deg.
    pub leaked_angle_deg_segments: Vec<f64>,
    /// Sum of `leaked_angle_deg_segments`, deg.
    pub leaked_angle_deg_total: f64,
    /// Runs of judged-moving samples that overlap no motion.
    pub false_alarms: usize,
    /// `false_alarms` per hour of the run.
    pub false_alarms_per_h: f64,
    /// Samples outside motions.
    pub static_samples: usize,
    /// Of them, those judged moving (false alarms and the hold-off after each motion).
    pub static_held_moving: usize,
}

/// Scores the judged flags `judged` (one per sample of `run`) against the run's motions.
pub fn detection_scores(run: &MotionRun, judged: &[bool]) -> Result<DetectionScores, MotionError> {
    if judged.len() != run.len() {
        return Err(MotionError::Lengths(format!("{} judged flags for a run of {} samples", judged.len(), run.len())));
    }
    let (t, dt, truth) = (run.t_s(), run.dt(), run.truth());
    let mut truly_moving = vec![false; run.len()];
    let mut delays_s = Vec::new();
    let mut leaked_angle_deg_segments = Vec::with_capacity(run.segments().len());
    let mut leaked_samples = 0;
    for s in run.segments() {
        truly_moving[s.clone()].iter_mut().for_each(|m| *m = true);
        if let Some(first) = s.clone().find(|&i| judged[i]) {
            delays_s.push(t[first] - t[s.start]);
        }
        let leaked: Vec<usize> = s.clone().filter(|&i| !judged[i]).collect();
        leaked_samples += leaked.len();
        // A fold from +0.0: an empty `sum()` of f64 is −0.0.
        leaked_angle_deg_segments.push(leaked.iter().fold(0.0, |a, &i| a + truth[i].abs() * dt[i]));
    }
    let false_alarms = segments(judged).into_iter().filter(|r| !truly_moving[r.clone()].contains(&true)).count();
    let moving_samples = run.moving_samples();
    let hours = (t[run.len() - 1] - t[0] + dt[0]) / 3600.0;
    Ok(DetectionScores {
        motions: run.segments().len(),
        missed: run.segments().len() - delays_s.len(),
        delay_s_median: quantile(&delays_s, 0.5),
        delay_s_p95: quantile(&delays_s, 0.95),
        delays_s,
        moving_samples,
        leaked_samples,
        leaked_angle_deg_total: leaked_angle_deg_segments.iter().fold(0.0, |a, b| a + b),
        leaked_angle_deg_segments,
        false_alarms,
        false_alarms_per_h: false_alarms as f64 / hours,
        static_samples: run.len() - moving_samples,
        static_held_moving: judged.iter().zip(&truly_moving).filter(|(j, m)| **j && !**m).count(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ten samples at 1 Hz (Δt = 1 s), two motions of 1 and 2 deg/s: [2, 5) and [7, 9).
    fn run() -> MotionRun {
        let truth = vec![0.0, 0.0, 1.0, 1.0, 1.0, 0.0, 0.0, 2.0, 2.0, 0.0];
        let moving: Vec<bool> = truth.iter().map(|&v| v != 0.0).collect();
        MotionRun::new((0..10).map(f64::from).collect(), truth.clone(), truth, &moving).unwrap()
    }

    fn flags(s: &str) -> Vec<bool> {
        s.chars().map(|c| c == '1').collect()
    }

    #[test]
    fn a_late_onset_a_miss_and_a_false_alarm_are_counted_by_hand() {
        // Samples:   0123456789
        // truth:     0011100220
        // judged:    1000110000  → a false alarm at 0, the first motion found 2 s late and held
        //                          one sample after it; the second motion missed.
        let s = detection_scores(&run(), &flags("1000110000")).unwrap();
        assert_eq!((s.motions, s.missed, s.false_alarms), (2, 1, 1));
        assert_eq!(s.delays_s, vec![2.0]);
        assert_eq!((s.moving_samples, s.leaked_samples), (5, 4));
        assert_eq!(s.leaked_angle_deg_segments, vec![2.0, 4.0]);
        assert_eq!(s.leaked_angle_deg_total, 6.0);
        assert_eq!((s.static_samples, s.static_held_moving), (5, 2));
        assert!((s.false_alarms_per_h - 360.0).abs() < 1e-9, "{}", s.false_alarms_per_h);
    }

    #[test]
    fn an_early_alarm_belongs_to_its_motion_and_a_perfect_detector_scores_zero() {
        // An alarm from sample 1 through the first motion: no false alarm, no delay.
        let early = detection_scores(&run(), &flags("0111100110")).unwrap();
        assert_eq!((early.missed, early.false_alarms, early.leaked_samples), (0, 0, 0));
        assert_eq!(early.delays_s, vec![0.0, 0.0]);
        assert_eq!(early.static_held_moving, 1);
        let truth: Vec<bool> = run().truth().iter().map(|&v| v != 0.0).collect();
        let perfect = detection_scores(&run(), &truth).unwrap();
        assert_eq!(
            (perfect.missed, perfect.false_alarms, perfect.leaked_samples, perfect.static_held_moving),
            (0, 0, 0, 0)
        );
        assert!(perfect.leaked_angle_deg_total == 0.0 && perfect.leaked_angle_deg_total.is_sign_positive());
        assert!(detection_scores(&run(), &truth[1..]).is_err());
    }
}
