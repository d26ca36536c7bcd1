//! The per-axis model slot: a fitted drift predictor and its scaler behind an atomic swap.
//!
//! The background trainer (or any thread holding an [`Arc<ModelSlot>`]) installs a new model with
//! [`ModelSlot::install`]; the hot path reads it with [`ModelSlot::load`], which is lock-free and
//! does not allocate (arc-swap's `ArcSwapOption::load`; only a thread's very first load registers
//! a reusable debt node). A reader keeps the model it loaded alive until its guard is dropped.

use std::sync::Arc;

use arc_swap::ArcSwapOption;

use crate::model::Predict;
use crate::model::scaler::MinMaxScaler;

/// A fitted model shareable between the trainer thread and the hot path.
pub type SharedModel = Arc<dyn Predict + Send + Sync>;

/// A model as installed: the predictor (normalised units), the scaler of its training window
/// (paper Eq. 21, "stored with the model", design.md) and its version.
#[derive(Clone)]
pub struct InstalledModel {
    /// One-step-ahead predictor of the normalised denoised series.
    pub model: SharedModel,
    /// The scaler fitted on the model's training window.
    pub scaler: MinMaxScaler,
    /// Version number given at installation.
    pub version: u64,
}

impl std::fmt::Debug for InstalledModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("InstalledModel")
            .field("history_len", &self.model.history_len())
            .field("scaler", &self.scaler)
            .field("version", &self.version)
            .finish()
    }
}

impl InstalledModel {
    /// Predicts `steps` (≥ 1) samples beyond the end of `history` (raw units) by iterating the
    /// one-step model on its own outputs; `scratch` must hold at least
    /// `model.history_len() + steps` values. Returns `None` when `history` is too short, the
    /// scratch too small, or the model returns a non-finite value. Allocates nothing.
    pub fn predict_ahead(&self, history: &[f64], steps: usize, scratch: &mut [f64]) -> Option<f64> {
        let h = self.model.history_len();
        if steps == 0 || history.len() < h || scratch.len() < h + steps {
            return None;
        }
        for (s, &v) in scratch.iter_mut().zip(&history[history.len() - h..]) {
            *s = self.scaler.transform(v);
        }
        let mut last = f64::NAN;
        for k in 0..steps {
            last = self.model.predict(&scratch[..h + k]);
            if !last.is_finite() {
                return None;
            }
            scratch[h + k] = last;
        }
        let out = self.scaler.inverse(last);
        out.is_finite().then_some(out)
    }
}

/// An atomically swappable, initially empty model slot.
#[derive(Debug, Default)]
pub struct ModelSlot {
    current: ArcSwapOption<InstalledModel>,
}

impl ModelSlot {
    /// An empty slot.
    pub fn new() -> Self {
        Self::default()
    }

    /// Replaces the model (readers holding the old one keep it until they drop their guard).
    pub fn install(&self, model: InstalledModel) {
        self.current.store(Some(Arc::new(model)));
    }

    /// The current model, if any (lock-free, allocation-free).
    #[inline]
    pub fn load(&self) -> arc_swap::Guard<Option<Arc<InstalledModel>>> {
        self.current.load()
    }

    /// Version of the installed model (0 when empty).
    pub fn version(&self) -> u64 {
        self.current.load().as_ref().map_or(0, |m| m.version)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// x̂[t+1] = 0.5·x[t] in normalised units.
    struct Half;
    impl Predict for Half {
        fn history_len(&self) -> usize {
            1
        }
        fn predict(&self, history: &[f64]) -> f64 {
            0.5 * history[history.len() - 1]
        }
    }

    #[test]
    fn iterates_the_one_step_model_in_normalised_units() {
        let slot = ModelSlot::new();
        assert!(slot.load().is_none());
        let scaler = MinMaxScaler { min: 0.0, max: 2.0 }; // centre 1, half-range 1
        slot.install(InstalledModel { model: Arc::new(Half), scaler, version: 7 });
        assert_eq!(slot.version(), 7);
        let guard = slot.load();
        let m = guard.as_ref().unwrap();
        let mut scratch = [0.0; 4];
        // 3.0 → 2.0 (normalised) → 1.0 → 0.5 → 0.25 → raw 1.25.
        assert_eq!(m.predict_ahead(&[0.0, 3.0], 3, &mut scratch), Some(1.25));
        assert_eq!(m.predict_ahead(&[], 1, &mut scratch), None);
        assert_eq!(m.predict_ahead(&[3.0], 4, &mut scratch), None);
    }
}
