//! The background retrainer (docs/design.md "Retrainer": a background thread retrains the model
//! on a sliding window).
//!
//! [`Trainer::spawn`] starts one thread that owns a [`Fit`] configuration (the paper's
//! [`CpsoLssvm`](crate::model::lssvm::CpsoLssvm) in production, anything cheap in tests). The
//! [`Pipeline`](super::Pipeline) sends it [`TrainRequest`]s — the last `retrain.window` static
//! denoised samples of each axis — over a bounded channel and polls the answers without
//! blocking. For each axis the thread fits the [-1, 1] scaler (paper Eq. 21) on the window,
//! fits the model on the normalised window and sends both back; the pipeline installs them.
//!
//! Scheduling (when a request is due, what happens to one that is still running, when the
//! answer is applied) lives in the pipeline; see [`RetrainSchedule`].

use std::sync::Arc;
use std::thread::JoinHandle;

use crossbeam_channel::{Receiver, Sender, TryRecvError, bounded};

use super::model_slot::SharedModel;
use crate::model::Fit;
use crate::model::baselines::MeanModel;
use crate::model::scaler::MinMaxScaler;

/// When retraining is requested and when its result is applied.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RetrainMode {
    /// Every `every_samples` input samples; the model is applied exactly `apply_delay_samples`
    /// samples after the request, the pipeline waiting for the trainer if it is not done yet.
    /// Two runs over the same input give identical outputs (replay, tests).
    Deterministic,
    /// Every `interval_s` seconds of wall time; the model is applied at the first sample after it
    /// arrives. The hot path never waits (the daemon).
    Live,
}

impl RetrainMode {
    /// The name in the configuration (`retrain.mode`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Deterministic => "deterministic",
            Self::Live => "live",
        }
    }
}

impl std::fmt::Display for RetrainMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The retrain schedule (`[retrain]` in the configuration).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RetrainSchedule {
    /// Deterministic or live.
    pub mode: RetrainMode,
    /// Static denoised samples per axis in a training window.
    pub window: usize,
    /// Deterministic mode: input samples between requests.
    pub every_samples: u64,
    /// Live mode: seconds of wall time between requests.
    pub interval_s: f64,
    /// Deterministic mode: samples between a request and the application of its model.
    pub apply_delay_samples: u64,
    /// Fewest static samples per axis for a request to be sent (fewer: the request is skipped).
    pub min_samples: usize,
}

impl Default for RetrainSchedule {
    fn default() -> Self {
        Self {
            mode: RetrainMode::Live,
            window: 4000,
            every_samples: 6000,
            interval_s: 60.0,
            apply_delay_samples: 1000,
            min_samples: 500,
        }
    }
}

impl RetrainSchedule {
    /// Checks the values against each other and against the `history` samples a model reads
    /// (the embedding's); the message names the key.
    pub fn validate(&self, history: usize) -> Result<(), String> {
        if self.window < history + 3 {
            return Err(format!(
                "retrain.window: {} is shorter than the embedding needs ({})",
                self.window,
                history + 3
            ));
        }
        if self.every_samples == 0 {
            return Err("retrain.every_samples must be at least 1".into());
        }
        if !(self.interval_s > 0.0 && self.interval_s.is_finite()) {
            return Err(format!("retrain.interval_s: {} must be positive and finite", self.interval_s));
        }
        if self.min_samples > self.window {
            return Err(format!("retrain.min_samples: {} exceeds retrain.window {}", self.min_samples, self.window));
        }
        Ok(())
    }
}

/// A training job: one window per axis (raw units, denoised, static samples only).
#[derive(Debug, Clone, PartialEq)]
pub struct TrainRequest {
    /// Index of the sample after which the request was made (samples processed so far).
    pub request_index: u64,
    /// Training windows x, y, z.
    pub windows: [Vec<f64>; 3],
}

/// One axis of a successful fit.
#[derive(Clone)]
pub struct FittedAxis {
    /// The model (normalised units).
    pub model: SharedModel,
    /// The scaler fitted on the window.
    pub scaler: MinMaxScaler,
}

/// The trainer's answer to a [`TrainRequest`].
#[derive(Clone)]
pub struct TrainResult {
    /// The request's index.
    pub request_index: u64,
    /// The three fitted axes, or why the fit failed (the old models stay).
    pub outcome: Result<[FittedAxis; 3], String>,
}

/// Fits the scaler and the model of one axis (paper Eq. 21, then `fit` on normalised data).
///
/// A constant window — an axis the recording does not have (0.0 throughout) or a stuck sensor —
/// gets the constant predictor instead ([`MeanModel`] of the normalised window, which maps back
/// to the constant): nothing can be fitted on a constant series (an AR design is singular), and
/// holding the constant is its exact forecast. Without this, one constant axis would fail the
/// fits of all three.
pub fn fit_axis<F>(fit: &F, window: &[f64]) -> Result<FittedAxis, String>
where
    F: Fit,
    F::Model: Send + Sync + 'static,
{
    let scaler = MinMaxScaler::fit(window).ok_or("training window is empty or holds a non-finite value")?;
    if scaler.min == scaler.max {
        return Ok(FittedAxis { model: Arc::new(MeanModel { mean: 0.0 }), scaler });
    }
    let scaled: Vec<f64> = window.iter().map(|&v| scaler.transform(v)).collect();
    let model = fit.fit(&scaled).map_err(|e| e.to_string())?;
    Ok(FittedAxis { model: Arc::new(model), scaler })
}

/// Raises the calling thread's nice value by `nice` (Linux: `setpriority(PRIO_PROCESS, 0, …)`
/// acts on the calling thread only).
fn lower_priority(nice: i32) {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: setpriority takes plain integers and has no memory effects.
        let rc = unsafe { libc::setpriority(libc::PRIO_PROCESS, 0, nice) };
        if rc != 0 {
            tracing::warn!(nice, error = %std::io::Error::last_os_error(), "could not lower the retrain thread's priority");
        }
    }
    #[cfg(not(target_os = "linux"))]
    tracing::debug!(nice, "thread priorities are only lowered on Linux");
}

/// Handle of the trainer thread; dropping it closes the request channel and joins the thread.
pub struct Trainer {
    requests: Option<Sender<TrainRequest>>,
    results: Receiver<TrainResult>,
    thread: Option<JoinHandle<()>>,
}

/// Why the trainer could not take a request or give a result.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrainerError {
    /// A request is already queued.
    Busy,
    /// The trainer thread has stopped.
    Stopped,
}

impl Trainer {
    /// Starts the trainer thread with a fitting configuration, at the scheduling priority of
    /// the caller.
    pub fn spawn<F>(fit: F) -> std::io::Result<Self>
    where
        F: Fit + Send + 'static,
        F::Model: Send + Sync + 'static,
    {
        Self::spawn_niced(fit, 0)
    }

    /// [`Trainer::spawn`] with the trainer thread's nice value raised by `nice` (0 … 19; Linux
    /// keeps nice per thread, and the CPSO worker threads it starts inherit it), so that a fit
    /// yields the CPU to the sample loop. Elsewhere, or if the call fails, the thread keeps the
    /// caller's priority (logged).
    pub fn spawn_niced<F>(fit: F, nice: i32) -> std::io::Result<Self>
    where
        F: Fit + Send + 'static,
        F::Model: Send + Sync + 'static,
    {
        let (req_tx, req_rx) = bounded::<TrainRequest>(1);
        let (res_tx, res_rx) = bounded::<TrainResult>(1);
        let thread = std::thread::Builder::new().name("gyrocomp-retrain".into()).spawn(move || {
            if nice > 0 {
                lower_priority(nice);
            }
            for req in req_rx {
                let started = std::time::Instant::now();
                let fits: Result<Vec<FittedAxis>, String> = req
                    .windows
                    .iter()
                    .enumerate()
                    .map(|(axis, w)| fit_axis(&fit, w).map_err(|e| format!("axis {axis}: {e}")))
                    .collect();
                let outcome = fits.and_then(|v| <[FittedAxis; 3]>::try_from(v).map_err(|_| "axis count".to_string()));
                tracing::debug!(
                    request_index = req.request_index,
                    seconds = started.elapsed().as_secs_f64(),
                    ok = outcome.is_ok(),
                    "retrain finished"
                );
                if res_tx.send(TrainResult { request_index: req.request_index, outcome }).is_err() {
                    break;
                }
            }
        })?;
        Ok(Self { requests: Some(req_tx), results: res_rx, thread: Some(thread) })
    }

    /// Queues a request without blocking.
    pub fn try_send(&self, request: TrainRequest) -> Result<(), TrainerError> {
        let Some(tx) = &self.requests else { return Err(TrainerError::Stopped) };
        tx.try_send(request).map_err(|e| match e {
            crossbeam_channel::TrySendError::Full(_) => TrainerError::Busy,
            crossbeam_channel::TrySendError::Disconnected(_) => TrainerError::Stopped,
        })
    }

    /// A finished result, if any, without blocking; [`TrainerError::Stopped`] when the thread
    /// has stopped.
    pub fn try_recv(&self) -> Result<Option<TrainResult>, TrainerError> {
        match self.results.try_recv() {
            Ok(r) => Ok(Some(r)),
            Err(TryRecvError::Empty) => Ok(None),
            Err(TryRecvError::Disconnected) => Err(TrainerError::Stopped),
        }
    }

    /// Waits for the next result; `None` when the thread has stopped.
    pub fn recv(&self) -> Option<TrainResult> {
        self.results.recv().ok()
    }
}

impl Drop for Trainer {
    fn drop(&mut self) {
        self.requests.take();
        // Unblock a trainer waiting to send a result nobody will read.
        while self.results.try_recv().is_ok() {}
        if let Some(t) = self.thread.take() {
            // The thread finishes its current fit first; a panic inside it is reported, not rethrown.
            if t.join().is_err() {
                tracing::error!("retrain thread panicked");
            }
        }
    }
}

impl std::fmt::Debug for Trainer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Trainer").field("running", &self.thread.is_some()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::baselines::Ar;

    #[test]
    fn a_constant_window_gets_the_constant_and_others_the_model() {
        // AR cannot be fitted on a constant series; the axis still gets a model.
        let constant = fit_axis(&Ar::aic(3), &[0.25; 100]).unwrap();
        assert_eq!(constant.scaler.inverse(constant.model.predict(&[0.0; 4])), 0.25);
        assert_eq!(constant.model.history_len(), 0);
        let varying: Vec<f64> = (0..100).map(|i| (i as f64 * 0.3).sin() + 0.01 * (i % 7) as f64).collect();
        let fitted = fit_axis(&Ar::aic(3), &varying).unwrap();
        assert!((1..=3).contains(&fitted.model.history_len()));
        assert!(fit_axis(&Ar::aic(3), &[0.0, f64::NAN, 1.0]).is_err());
    }
}
