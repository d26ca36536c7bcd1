//! Retraining, seen from the pipeline: attaching the trainer, the schedule of
//! [`RetrainSchedule`] (when a request is due, when its answer is applied), the training windows
//! and the installation of models.

use std::time::Instant;

use super::{Pending, Pipeline, PipelineError};
use crate::model::scaler::MinMaxScaler;
use crate::stream::model_slot::{InstalledModel, SharedModel};
use crate::stream::retrain::{RetrainMode, RetrainSchedule, TrainRequest, TrainResult, Trainer, TrainerError};

impl Pipeline {
    /// Attaches a background trainer; from now on retraining follows `config.retrain`.
    pub fn attach_trainer(&mut self, trainer: Trainer) {
        self.trainer = Some(trainer);
        self.pending = None;
        self.last_request = Instant::now();
    }

    /// Applies a new retrain schedule from the next sample on; a pending request keeps running.
    /// Refused when `schedule.window` exceeds the history allocated in [`Pipeline::new`].
    pub fn set_retrain_schedule(&mut self, schedule: RetrainSchedule) -> Result<(), PipelineError> {
        let kept = self.axes[0].estimator.max_model_history();
        if self.config.drift.kind.uses_models() && schedule.window > kept {
            return Err(PipelineError::Config(format!(
                "retrain.window: {} exceeds the {kept} samples of history kept since start",
                schedule.window
            )));
        }
        schedule.validate(self.config.embedding.history()).map_err(PipelineError::Config)?;
        self.config.retrain = schedule;
        Ok(())
    }

    /// Installs a model (normalised units) and the scaler of its training window on one axis.
    pub fn install_model(
        &mut self,
        axis: usize,
        model: SharedModel,
        scaler: MinMaxScaler,
        version: u64,
    ) -> Result<(), PipelineError> {
        let a = self.axes.get(axis).ok_or(PipelineError::NoSuchAxis(axis))?;
        let Some(slot) = a.estimator.model_slot() else {
            return Err(PipelineError::NoModels(a.estimator.name()));
        };
        let (need, kept) = (model.history_len(), a.estimator.max_model_history());
        if need > kept {
            return Err(PipelineError::HistoryTooLong { need, kept });
        }
        let (horizon, steps) = (model.horizon(), a.estimator.model_steps());
        if horizon != 1 && horizon != steps {
            return Err(PipelineError::HorizonMismatch { model: horizon, pipeline: steps });
        }
        slot.install(InstalledModel { model, scaler, version });
        self.next_version = self.next_version.max(version + 1);
        Ok(())
    }

    /// The training window of one axis: the last `retrain.window` static denoised samples
    /// (raw units, oldest first); empty for a bad axis index.
    pub fn training_window(&self, axis: usize) -> Vec<f64> {
        self.axes.get(axis).map_or_else(Vec::new, |a| {
            let h = a.estimator.training_history();
            h[h.len().saturating_sub(self.config.retrain.window)..].to_vec()
        })
    }

    /// The three training windows.
    pub fn training_windows(&self) -> [Vec<f64>; 3] {
        [self.training_window(0), self.training_window(1), self.training_window(2)]
    }

    /// Applies a finished retrain: deterministic mode at exactly `request + apply_delay`
    /// (waiting if needed), live mode whenever one has arrived.
    pub(super) fn poll_trainer(&mut self) {
        let (Some(trainer), Some(pending)) = (&self.trainer, self.pending) else { return };
        let result = match self.config.retrain.mode {
            RetrainMode::Deterministic => {
                if self.stats.samples < pending.request_index + self.config.retrain.apply_delay_samples {
                    return;
                }
                trainer.recv()
            }
            RetrainMode::Live => match trainer.try_recv() {
                Ok(Some(r)) => Some(r),
                Ok(None) => return,
                Err(_) => None,
            },
        };
        self.pending = None;
        match result {
            Some(r) => self.apply(r),
            None => {
                tracing::error!("retrain thread stopped; keeping the current models");
                self.trainer = None;
            }
        }
    }

    fn apply(&mut self, result: TrainResult) {
        match result.outcome {
            Ok(fitted) => {
                let version = self.next_version;
                for (axis, f) in fitted.into_iter().enumerate() {
                    if let Err(e) = self.install_model(axis, f.model, f.scaler, version) {
                        tracing::warn!(axis, error = %e, "retrained model refused; keeping the old one");
                    }
                }
                self.stats.models_installed += 1;
                tracing::info!(
                    version,
                    request_index = result.request_index,
                    at = self.stats.samples,
                    "model installed"
                );
            }
            Err(why) => {
                self.stats.retrain_failed += 1;
                tracing::warn!(request_index = result.request_index, %why, "retrain failed; keeping the old model");
            }
        }
    }

    pub(super) fn maybe_request(&mut self) {
        let Some(trainer) = &self.trainer else { return };
        let s = &self.config.retrain;
        let due = match s.mode {
            RetrainMode::Deterministic => s.every_samples > 0 && self.stats.samples.is_multiple_of(s.every_samples),
            RetrainMode::Live => self.last_request.elapsed().as_secs_f64() >= s.interval_s,
        };
        if !due {
            return;
        }
        self.last_request = Instant::now();
        if self.pending.is_some() {
            self.stats.retrain_skipped += 1;
            tracing::debug!(at = self.stats.samples, "retrain due while the previous one runs: skipped");
            return;
        }
        if self.axes.iter().any(|a| a.estimator.training_history().len().min(s.window) < s.min_samples) {
            self.stats.retrain_starved += 1;
            return;
        }
        let request = TrainRequest { request_index: self.stats.samples, windows: self.training_windows() };
        match trainer.try_send(request) {
            Ok(()) => {
                self.stats.retrain_requests += 1;
                self.pending = Some(Pending { request_index: self.stats.samples });
            }
            Err(TrainerError::Busy) => self.stats.retrain_skipped += 1,
            Err(TrainerError::Stopped) => {
                tracing::error!("retrain thread stopped; keeping the current models");
                self.trainer = None;
            }
        }
    }
}
