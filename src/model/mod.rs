//! Models and the numerics around them: the [-1, 1] scaler (paper Eq. 21) and the C-C method
//! for choosing the PSR delay and dimension (paper Eq. 18–20, Kim, Eykholt & Salas 1999).

pub mod cc;
pub mod cpso;
pub mod lssvm;
pub mod rng;
pub mod scaler;
pub mod traits;

pub use traits::{Fit, FitError, Predict, predict_from};
