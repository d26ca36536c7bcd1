//! LS-SVM regression (paper §2.2, Eq. 4–8; Suykens & Vandewalle 1999) in LS-SVMlab
//! conventions, for one-step-ahead prediction on PSR rows (Eq. 15–16):
//!
//! - [`kernel`]: the RBF kernel `exp(−‖x − y‖²/σ²)` (Eq. 8) and kernel matrices;
//! - [`dense`]: blocked Cholesky, triangular solves, diag(H⁻¹);
//! - [`exact`]: the bordered dual system (Eq. 7) via Cholesky of `Ω + I/γ`, closed-form LOO
//!   residuals (Cawley & Talbot 2004);
//! - [`expansion`]: the fitted [`LssvmModel`] (a [`KernelExpansion`]) and its [`Solver`], as
//!   plain data (what a model snapshot stores);
//! - [`model`]: [`LssvmModel`] as a `Predict` and [`LssvmConfig`] (`Fit`);
//! - [`prototypes`], [`nystrom`]: the large-window fixed-size LS-SVM (Suykens et al. 2002) with
//!   a Nyström feature map solved in the primal ([`NystromConfig`]);
//! - [`tune`]: [`CpsoLssvm`], (γ, σ²) tuned by CPSO (paper §2.2, Eq. 9–14) with a choice of
//!   fitness ([`Fitness`]), then the final fit.

pub mod dense;
pub mod exact;
pub mod expansion;
pub mod kernel;
pub mod model;
pub mod nystrom;
pub mod prototypes;
pub mod tune;
mod validate;

pub use exact::{ExactSolution, solve_exact};
pub use expansion::{KernelExpansion, LssvmModel, Solver};
pub use model::LssvmConfig;
pub use nystrom::{NystromConfig, NystromProblem, NystromSolution};
pub use prototypes::{PrototypeSelection, select_prototypes};
pub use tune::{CpsoLssvm, CpsoLssvmModel, Fitness};
