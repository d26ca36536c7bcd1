//! SIGHUP: applying a reloaded configuration to the running pipeline between two samples.
//!
//! Applied at once: `[motion]`, `[input]` and the retrain schedule (`retrain.mode`, `window` — up
//! to the history allocated at start —, `every_samples`, `interval_s`, `apply_delay_samples`,
//! `min_samples`). Every other key (denoiser, embedding, bias, model, IPC, log) needs a restart;
//! the sections that changed are reported.

use crate::config::{Config, ConfigError};
use crate::stream::Pipeline;

/// The result of a reload.
#[derive(Debug, Clone, PartialEq)]
pub struct ReloadOutcome {
    /// The configuration now in effect: the running one with the applied keys replaced.
    pub effective: Config,
    /// Sections with changed keys that take effect only after a restart.
    pub needs_restart: Vec<&'static str>,
}

/// Applies the reloadable keys of `new` to `pipeline` (all or nothing). `running` is the
/// configuration in effect.
pub fn apply(pipeline: &mut Pipeline, running: &Config, new: &Config) -> Result<ReloadOutcome, ConfigError> {
    let pc = new.pipeline()?;
    pipeline.set_retrain_schedule(pc.retrain).map_err(|e| ConfigError(e.to_string()))?;
    pipeline.update_thresholds(pc.motion, pc.input);

    let mut effective = running.clone();
    effective.motion = new.motion.clone();
    effective.input = new.input.clone();
    effective.retrain.schedule = new.retrain.schedule;

    let mut needs_restart = Vec::new();
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
}
