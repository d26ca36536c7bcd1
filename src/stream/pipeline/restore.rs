//! The pipeline's warm state handed out for a snapshot and restored from one
//! ([`crate::stream::snapshot`]).

use super::{Pipeline, PipelineError};
use crate::stream::input_check::InputConfig;
use crate::stream::warm::{AxisWarm, StreamWarm};

impl Pipeline {
    /// Copies of each axis' buffers (denoiser window, static history) and running values (bias
    /// estimate and its variance, temperature term, self-calibration, held drift), for a
    /// snapshot: see [`crate::stream::snapshot`].
    pub fn warm_state(&self) -> [AxisWarm; 3] {
        std::array::from_fn(|k| {
            let a = &self.axes[k];
            let mut w = AxisWarm {
                drift: a.drift,
                comp: a.comp,
                from_model: a.from_model,
                drift_std: a.std,
                noise: self.noise[k].clone(),
                ..AxisWarm::default()
            };
            a.estimator.warm(&mut w);
            w
        })
    }

    /// A copy of the state shared by the axes (sample index, period, pending queue, detector,
    /// input checks), for a snapshot.
    pub fn stream_state(&self) -> StreamWarm {
        StreamWarm {
            index: self.first_index + self.stats.samples,
            period: self.period.clone(),
            horizon: self.horizon,
            pending: self.queue.state(),
            detector: self.detector.state(),
            input: self.check.state(),
        }
    }

    /// Restores what [`Pipeline::warm_state`] and [`Pipeline::stream_state`] copied into a
    /// pipeline that has processed no sample (models are installed separately with
    /// [`Pipeline::install_model`]): the next sample continues the stored sample index, so the
    /// restored pipeline gives the output the stored one would have given (the first sample
    /// after a restart is flagged as a gap when `seq` or time skipped while it was down).
    /// Refused when a value is not finite or the stored detector, period or windows do not
    /// fit this configuration; the checks that need the sized windows run part-way, so on an
    /// error the pipeline must be rebuilt ([`Snapshot::restore_into`](crate::stream::snapshot::Snapshot::restore_into)
    /// tries a scratch pipeline first and leaves its target unchanged).
    pub fn restore_state(&mut self, warm: &[AxisWarm; 3], stream: &StreamWarm) -> Result<(), PipelineError> {
        let bad = |m: String| Err(PipelineError::Config(m));
        if let Some(axis) = warm.iter().position(|w| !w.is_finite()) {
            return bad(format!("warm state of axis {axis} holds a non-finite value"));
        }
        if !stream.is_valid() {
            return bad("the stored pending samples, detector or input state hold a non-finite value".into());
        }
        if stream.detector.kind() != self.config.detector {
            return bad(format!(
                "motion.detector: the snapshot holds a {} detector's state, the pipeline runs {}",
                stream.detector.kind().name(),
                self.config.detector.name()
            ));
        }
        if self.stats.samples > 0 {
            return bad("a snapshot is restored before the first sample only".into());
        }
        match (self.period.period_s(), stream.period.period_s()) {
            (Some(now), Some(stored)) if now != stored => {
                return bad(format!("input.rate_hz: period {stored} s stored, {now} s running"));
            }
            (None, Some(t)) => {
                self.period = stream.period.clone();
                let period_ns = (t * 1e9).round() as u64;
                let input = InputConfig { period_ns, ..*self.check.config() };
                self.check.reconfigure(input);
                self.apply_period(t);
            }
            (None, None) => self.period = stream.period.clone(),
            _ => {}
        }
        self.detector.restore_state(&stream.detector).map_err(PipelineError::Config)?;
        self.queue.restore(&stream.pending).map_err(PipelineError::Config)?;
        for ((a, w), noise) in self.axes.iter_mut().zip(warm).zip(&mut self.noise) {
            a.estimator.restore(w);
            (a.drift, a.comp, a.from_model, a.std) = (w.drift, w.comp, w.from_model, w.drift_std);
            *noise = w.noise.clone();
        }
        self.check.restore(&stream.input);
        self.horizon = stream.horizon;
        self.first_index = stream.index;
        Ok(())
    }
}
