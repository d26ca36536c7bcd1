//! Models and the numerics around them: the paper's LSSVM (Eq. 4–8) tuned by CPSO (§2.2), the
//! BP-ANN (Eq. 1–3), the honest baselines, the error metrics (Eq. 22–24), the [-1, 1] scaler
//! (Eq. 21) and the C-C method for choosing the PSR delay and dimension (Eq. 18–20, Kim, Eykholt
//! & Salas 1999) and the phase-space embedding they read ([`embed`]). Every model implements [`Fit`]
//! and [`Predict`].

pub mod baselines;
pub mod bp_ann;
pub mod cc;
pub mod cpso;
pub mod embed;
pub mod lssvm;
pub mod metrics;
pub mod normal;
pub mod rng;
pub mod scaler;
pub mod snapshot;
pub mod traits;

pub use traits::{Fit, FitError, Predict, predict_from};
