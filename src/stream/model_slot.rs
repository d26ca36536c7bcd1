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
/// (paper Eq. 21, "stored with the model", docs/design.md) and its version.
#[derive(Clone)]
pub struct InstalledModel {
    /// Predictor of the normalised denoised series, one step ahead or directly
    /// [`Predict::horizon`] steps ahead.
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
    /// Predicts the sample `steps` (≥ 1) after the end of `history` (raw units). A model whose
    /// [`Predict::horizon`] is `steps` (direct multi-step, the retrainer's models) is evaluated
    /// once; a one-step model is iterated `steps` times on its own outputs. `scratch` must hold at
    /// least `model.history_len() + steps` values. Returns `None` when `history` is too short, the
    /// scratch too small, the model's horizon is neither 1 nor `steps`, or the model returns a
    /// non-finite value. Allocates nothing.
    pub fn predict_ahead(&self, history: &[f64], steps: usize, scratch: &mut [f64]) -> Option<f64> {
        let h = self.model.history_len();
        if steps == 0 || history.len() < h || scratch.len() < h + steps {
            return None;
        }
        let horizon = self.model.horizon();
        if horizon == steps && horizon > 1 {
            for (s, &v) in scratch.iter_mut().zip(&history[history.len() - h..]) {
                *s = self.scaler.transform(v);
            }
            let out = self.scaler.inverse(self.model.predict(&scratch[..h]));
            return out.is_finite().then_some(out);
        }
        if horizon != 1 {
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

    /// x̂[t+3] = x[t] + 3 in normalised units, fitted directly three steps ahead.
    struct PlusThree;
    impl Predict for PlusThree {
        fn history_len(&self) -> usize {
            1
        }
        fn predict(&self, history: &[f64]) -> f64 {
            history[history.len() - 1] + 3.0
        }
        fn horizon(&self) -> usize {
            3
        }
    }

    #[test]
    fn evaluates_a_direct_model_once_and_refuses_other_horizons() {
        let scaler = MinMaxScaler { min: 0.0, max: 2.0 };
        let m = InstalledModel { model: Arc::new(PlusThree), scaler, version: 1 };
        let mut scratch = [0.0; 4];
        // raw 1.5 → 0.5 (normalised) → 3.5 → raw 4.5; iterating would give 10.5 → raw 11.5.
        assert_eq!(m.predict_ahead(&[1.5], 3, &mut scratch), Some(4.5));
        assert_eq!(m.predict_ahead(&[1.5], 2, &mut scratch), None);
        assert_eq!(m.predict_ahead(&[1.5], 1, &mut scratch), None);
    }
}
