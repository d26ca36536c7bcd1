//! SIGHUP: applying a reloaded configuration to the running pipeline between two samples.
//!
//! Applied at once: the threshold gate's keys (`[motion] rate_dps`, `variance_dps2`, `window`),
//! the input checks (`[input]` but `rate_hz`) and the retrain schedule (`retrain.mode`, `window` —
//! up to the history allocated at start —, `every_samples`, `interval_s`, `apply_delay_samples`,
//! `min_samples`). Everything else needs a restart and keeps its running value in the effective
//! configuration; what changed is reported: whole sections (denoiser, embedding, bias, model, IPC,
//! log, state) by name, and the keys of the partly reloadable sections one by one — `[drift]`
//! (the estimators keep state built for their settings), `[motion] detector` and the statistical
//! detector's keys (its windows, hysteresis and pending queue are sized for them), `[input]
//! rate_hz` (the period the windows were sized for).

use crate::config::{Config, ConfigError};
use crate::stream::Pipeline;

/// The result of a reload.
#[derive(Debug, Clone, PartialEq)]
pub struct ReloadOutcome {
    /// The configuration now in effect: the running one with the applied keys replaced.
    pub effective: Config,
    /// What changed but takes effect only after a restart: sections (`denoise`, …) and single
    /// keys of the partly reloadable sections (`drift.estimator`, `motion.detector`, …).
    pub needs_restart: Vec<&'static str>,
}

/// The changed keys of `[drift]`, `[motion]` and `[input]` that a reload cannot apply.
fn restart_only_keys(running: &Config, new: &Config) -> Vec<&'static str> {
    let (d, nd) = (&running.drift, &new.drift);
    let (s, ns) = (&running.motion.statistical, &new.motion.statistical);
    let keys = [
        ("drift.estimator", d.kind != nd.kind),
        ("drift.innovation_gate", d.innovation_gate != nd.innovation_gate),
        ("drift.startup_s", d.startup_s != nd.startup_s),
        ("drift.temperature", d.temperature != nd.temperature),
        ("motion.detector", running.motion.detector != new.motion.detector),
        ("motion.false_alarm", s.false_alarm != ns.false_alarm),
        ("motion.windows_s", s.windows_s != ns.windows_s),
        ("motion.variance_window_s", s.variance_window_s != ns.variance_window_s),
        ("motion.settle_s", s.settle_s != ns.settle_s),
        ("motion.guard_s", s.guard_s != ns.guard_s),
        ("motion.relearn_s", s.relearn_s != ns.relearn_s),
        ("input.rate_hz", running.input.rate_hz != new.input.rate_hz),
    ];
    keys.into_iter().filter(|&(_, changed)| changed).map(|(key, _)| key).collect()
}

/// Applies the reloadable keys of `new` to `pipeline` (all or nothing). `running` is the
/// configuration in effect.
pub fn apply(pipeline: &mut Pipeline, running: &Config, new: &Config) -> Result<ReloadOutcome, ConfigError> {
    let pc = new.pipeline()?;
    pipeline.set_retrain_schedule(pc.retrain).map_err(|e| ConfigError(e.to_string()))?;
    pipeline.update_thresholds(pc.motion, pc.input);

    let mut effective = running.clone();
    effective.motion.threshold = new.motion.threshold;
    effective.input.check = new.input.check;
    effective.retrain.schedule = new.retrain.schedule;

    let mut needs_restart = restart_only_keys(running, new);
    let sections: [(&'static str, bool); 7] = [
        ("denoise", effective.denoise != new.denoise),
        ("embedding", effective.embedding != new.embedding),
        ("pipeline", effective.pipeline != new.pipeline),
        ("retrain (model keys)", effective.retrain != new.retrain),
        ("ipc", effective.ipc != new.ipc),
        ("log", effective.log != new.log),
        ("state", effective.state != new.state),
    ];
    for (name, changed) in sections {
        if changed {
            needs_restart.push(name);
        }
    }
    Ok(ReloadOutcome { effective, needs_restart })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reloadable_keys_apply_and_the_rest_is_reported() {
        let running = Config::paper();
        let mut pipeline = Pipeline::new(running.pipeline().unwrap()).unwrap();
        let mut new = running.clone();
        new.motion.threshold.rate_dps = 3.0;
        new.input.check.range_dps = 500.0;
        new.retrain.schedule.every_samples = 123;
        new.denoise.window = 128;
        new.retrain.fit.prototypes = 50;
        let out = apply(&mut pipeline, &running, &new).unwrap();
        assert_eq!(pipeline.config().motion.rate_dps, 3.0);
        assert_eq!(pipeline.config().input.range_dps, 500.0);
        assert_eq!(pipeline.config().retrain.every_samples, 123);
        assert_eq!(out.needs_restart, ["denoise", "retrain (model keys)"]);
        assert_eq!(out.effective.motion.threshold.rate_dps, 3.0);
        assert_eq!(out.effective.denoise, running.denoise);

        // A window beyond the allocated history is refused, and nothing is applied.
        let mut too_big = new.clone();
        too_big.retrain.schedule.window = 100_000;
        too_big.motion.threshold.rate_dps = 9.0;
        let err = apply(&mut pipeline, &out.effective, &too_big).unwrap_err();
        assert!(err.0.contains("retrain.window"), "{err}");
        assert_eq!(pipeline.config().motion.rate_dps, 3.0);
    }

    #[test]
    fn restart_only_keys_are_reported_and_keep_their_running_values() {
        let running = Config::default();
        let mut pipeline = Pipeline::new(running.pipeline().unwrap()).unwrap();
        let mut new = running.clone();
        new.motion.detector = crate::stream::DetectorKind::Threshold;
        new.motion.statistical.settle_s = 9.0;
        new.drift.kind = crate::stream::EstimatorKind::BiasHold;
        new.input.rate_hz = crate::config::RateSetting::Hz(50.0);
        // Reloadable keys beside them still apply.
        new.motion.threshold.variance_dps2 = 0.9;
        new.input.check.gap_factor = 5.0;
        let out = apply(&mut pipeline, &running, &new).unwrap();
        assert_eq!(out.needs_restart, ["drift.estimator", "motion.detector", "motion.settle_s", "input.rate_hz"]);
        assert_eq!(out.effective.motion.detector, running.motion.detector);
        assert_eq!(out.effective.motion.statistical, running.motion.statistical);
        assert_eq!(out.effective.drift, running.drift);
        assert_eq!(out.effective.input.rate_hz, running.input.rate_hz);
        assert_eq!(pipeline.config().detector, running.motion.detector);
        assert_eq!(pipeline.config().drift, running.drift);
        assert_eq!(pipeline.config().input.period_ns, running.pipeline().unwrap().input.period_ns);
        assert_eq!((out.effective.motion.threshold.variance_dps2, pipeline.config().motion.variance_dps2), (0.9, 0.9));
        assert_eq!((out.effective.input.check.gap_factor, pipeline.config().input.gap_factor), (5.0, 5.0));

        // Nothing to report when only reloadable keys change.
        let mut calm = out.effective.clone();
        calm.motion.threshold.rate_dps = 4.0;
        assert_eq!(apply(&mut pipeline, &out.effective, &calm).unwrap().needs_restart, Vec::<&str>::new());
    }
}
