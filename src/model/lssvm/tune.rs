//! CPSO-LSSVM (paper §2.2, Fig. 4): (γ, σ²) tuned by CPSO ([`crate::model::cpso`], Eq. 9–14),
//! then the final model fitted on all training rows with the chosen values.
//!
//! The search runs over `(log10 γ, log10 σ²)`: both parameters act multiplicatively and span
//! several decades, so a linear search would spend almost all particles at the top decade.
//! Every fitness evaluation reuses σ²-independent work done once: the embedded rows, the
//! squared distances (and, for the large-window path, the prototypes).
//!
//! Solver: the exact LS-SVM ([`super::exact`]) up to `exact_max_rows` training rows, the
//! fixed-size LS-SVM ([`super::nystrom`]) above, for the search and for the final fit alike.

use nalgebra::DMatrix;

use super::exact::solve_with_system;
use super::expansion::{KernelExpansion, LssvmModel, Solver};
use super::kernel::{kernel_plus_ridge_from_sq_dist, sq_dist_matrix};
use super::model::embed_series;
use super::nystrom::{DEFAULT_RANK_TOL, NystromProblem};
use super::prototypes::{PrototypeSelection, select_prototypes};
use crate::model::cpso::{CpsoConfig, CpsoHistory, minimize};
use crate::model::embed::Embedding;
use crate::model::snapshot::{ModelState, TunedLssvm};
use crate::model::{Fit, FitError, Predict};

/// The objective CPSO minimises over (γ, σ²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fitness {
    /// Mean absolute error on the training rows (paper Eq. 13). It rewards over-fitting (large γ,
    /// small σ² drive it towards 0); kept to reproduce the paper.
    TrainMae,
    /// Root mean square of the closed-form leave-one-out residuals (Cawley & Talbot 2004 for
    /// the exact path; the ridge hat-matrix form for the fixed-size path). On a strongly
    /// autocorrelated series neighbouring rows nearly repeat each other, so LOO is optimistic.
    Loo,
    /// Fit on the first `1 − fraction` of the training rows, RMSE on the last `fraction`
    /// (time order: no target of the held-out part is used by the fit).
    Holdout {
        /// Share of the training rows held out, in (0, 1).
        fraction: f64,
    },
}

/// CPSO-LSSVM configuration (paper §2.2 and §4.3). The series given to [`Fit::fit`] must already
/// be normalised (Eq. 21).
#[derive(Debug, Clone, PartialEq)]
pub struct CpsoLssvm {
    /// PSR embedding (default τ = 10, m = 3).
    pub embedding: Embedding,
    /// CPSO settings (M, N, t_max, seed, threads, …).
    pub cpso: CpsoConfig,
    /// Search range of γ (searched in log10).
    pub gamma_bounds: (f64, f64),
    /// Search range of σ² (searched in log10).
    pub sigma2_bounds: (f64, f64),
    /// Objective of the search.
    pub fitness: Fitness,
    /// Largest number of training rows solved exactly; above it the fixed-size LS-SVM is used.
    pub exact_max_rows: usize,
    /// Prototypes m_p of the fixed-size path.
    pub prototypes: usize,
    /// Prototype selection of the fixed-size path.
    pub selection: PrototypeSelection,
    /// Pivoted-Cholesky tolerance of the fixed-size path.
    pub rank_tol: f64,
}

impl Default for CpsoLssvm {
    /// τ = 10, m = 3; γ ∈ [0.1, 10⁴], σ² ∈ [0.01, 10³]; held-out RMSE on the last 20 %; exact up to
    /// 1000 rows; 100 k-means++ prototypes above (within 0.2 % of the exact test RMSE on
    /// the real data down to σ² = 0.3, where 50 are 8 % off); [`CpsoConfig::default`].
    fn default() -> Self {
        Self {
            embedding: Embedding::PAPER,
            cpso: CpsoConfig::default(),
            gamma_bounds: (0.1, 1e4),
            sigma2_bounds: (0.01, 1e3),
            fitness: Fitness::Holdout { fraction: 0.2 },
            exact_max_rows: 1000,
            prototypes: 100,
            selection: PrototypeSelection::default(),
            rank_tol: DEFAULT_RANK_TOL,
        }
    }
}

/// A tuned and fitted CPSO-LSSVM.
#[derive(Debug, Clone, PartialEq)]
pub struct CpsoLssvmModel {
    /// The final model, fitted on all training rows.
    pub model: LssvmModel,
    /// Chosen γ.
    pub gamma: f64,
    /// Chosen σ².
    pub sigma2: f64,
    /// Best fitness found (in the units of [`CpsoLssvm::fitness`]).
    pub fitness: f64,
    /// Fitness evaluations made by CPSO.
    pub evaluations: usize,
    /// The CPSO run.
    pub history: CpsoHistory,
    /// Solver of the final model.
    pub solver: Solver,
}

impl Predict for CpsoLssvmModel {
    fn history_len(&self) -> usize {
        self.model.history_len()
    }

    fn predict(&self, history: &[f64]) -> f64 {
        self.model.predict(history)
    }

    fn horizon(&self) -> usize {
        self.model.horizon()
    }

    /// The final model with its γ and solver (the search trace is not kept).
    fn state(&self) -> Option<ModelState> {
        Some(ModelState::Lssvm(TunedLssvm { model: self.model.clone(), gamma: self.gamma, solver: self.solver }))
    }
}

fn rmse(r: impl Iterator<Item = f64>) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    for v in r {
        s += v * v;
        n += 1;
    }
    (s / n as f64).sqrt()
}

fn mae(r: impl Iterator<Item = f64>) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    for v in r {
        s += v.abs();
        n += 1;
    }
    s / n as f64
}

/// The σ²-independent data of one search: rows split as the fitness needs, with distances.
enum Prepared<'a> {
    Exact {
        /// ‖x_i − x_j‖² among the fitted rows (lower triangle read).
        dist: DMatrix<f64>,
        fit_inputs: &'a [f64],
        fit_targets: &'a [f64],
        /// Held-out rows and targets (empty unless `Holdout`).
        hold_inputs: &'a [f64],
        hold_targets: &'a [f64],
    },
    Nystrom {
        problem: NystromProblem,
        hold_inputs: &'a [f64],
        hold_targets: &'a [f64],
    },
}

impl CpsoLssvm {
    fn validate(&self) -> Result<(), FitError> {
        let bad = |m: String| Err(FitError::InvalidConfig(m));
        for (name, (lo, hi)) in [("gamma", self.gamma_bounds), ("sigma2", self.sigma2_bounds)] {
            if !(lo > 0.0 && hi > lo && hi.is_finite()) {
                return bad(format!("{name} bounds must satisfy 0 < lo < hi < inf, got ({lo}, {hi})"));
            }
        }
        if let Fitness::Holdout { fraction } = self.fitness
            && !(fraction > 0.0 && fraction < 1.0)
        {
            return bad(format!("holdout fraction must lie in (0, 1), got {fraction}"));
        }
        if self.prototypes == 0 || !(self.rank_tol >= 0.0 && self.rank_tol < 1.0) {
            return bad(format!(
                "need prototypes >= 1 and 0 <= rank_tol < 1, got {} and {}",
                self.prototypes, self.rank_tol
            ));
        }
        Ok(())
    }

    /// Rows fitted during the search when `n` training rows are given (the rest are held out).
    fn fitted_rows(&self, n: usize) -> usize {
        match self.fitness {
            Fitness::Holdout { fraction } => n - ((fraction * n as f64).round() as usize).clamp(1, n),
            _ => n,
        }
    }

    /// Rows fitted during the search; at least two must remain.
    fn split(&self, n: usize) -> Result<usize, FitError> {
        let n_fit = self.fitted_rows(n);
        if n_fit < 2 {
            // The smallest row count that leaves two rows to fit (fraction < 1 bounds the search).
            let rows = (3..100_000).find(|&m| self.fitted_rows(m) >= 2).unwrap_or(3);
            return Err(FitError::TooFewSamples {
                need: self.embedding.samples_for_rows(rows),
                have: self.embedding.samples_for_rows(n),
            });
        }
        Ok(n_fit)
    }

    fn prepare<'a>(&self, inputs: &'a [f64], dim: usize, targets: &'a [f64]) -> Result<Prepared<'a>, FitError> {
        let n = targets.len();
        let n_fit = self.split(n)?;
        let (fit_inputs, hold_inputs) = inputs.split_at(n_fit * dim);
        let (fit_targets, hold_targets) = targets.split_at(n_fit);
        if n <= self.exact_max_rows {
            let dist = sq_dist_matrix(fit_inputs, fit_inputs, dim);
            Ok(Prepared::Exact { dist, fit_inputs, fit_targets, hold_inputs, hold_targets })
        } else {
            let protos = select_prototypes(fit_inputs, dim, self.prototypes, self.selection);
            let problem = NystromProblem::new(fit_inputs, dim, fit_targets, protos)?;
            Ok(Prepared::Nystrom { problem, hold_inputs, hold_targets })
        }
    }

    /// The fitness of (γ, σ²) on prepared data; +∞ when the fit fails.
    fn fitness_of(&self, p: &Prepared, dim: usize, gamma: f64, sigma2: f64) -> f64 {
        let loo = self.fitness == Fitness::Loo;
        let score = |exp: &KernelExpansion,
                     train_res: &mut dyn Iterator<Item = f64>,
                     loo_res: Option<&[f64]>,
                     hi: &[f64],
                     ht: &[f64]| match self.fitness {
            Fitness::TrainMae => mae(train_res),
            Fitness::Loo => loo_res.map_or(f64::INFINITY, |r| rmse(r.iter().copied())),
            Fitness::Holdout { .. } => rmse(hi.chunks_exact(dim).zip(ht).map(|(x, y)| y - exp.eval(x))),
        };
        let value = match p {
            Prepared::Exact { dist, fit_inputs, fit_targets, hold_inputs, hold_targets } => {
                let h = kernel_plus_ridge_from_sq_dist(dist, sigma2, gamma);
                match solve_with_system(h, fit_targets, loo, 1) {
                    Ok(sol) => {
                        // Training residual of the dual solution: y_i − f(x_i) = α_i / γ.
                        let mut train = sol.alpha.iter().map(|a| a / gamma);
                        let exp = KernelExpansion {
                            dim,
                            centres: fit_inputs.to_vec(),
                            coef: sol.alpha.clone(),
                            bias: sol.bias,
                            sigma2,
                        };
                        score(&exp, &mut train, sol.loo_residuals.as_deref(), hold_inputs, hold_targets)
                    }
                    Err(_) => f64::INFINITY,
                }
            }
            Prepared::Nystrom { problem, hold_inputs, hold_targets } => {
                match problem.solve(gamma, sigma2, self.rank_tol, loo) {
                    Ok(sol) => {
                        let mut train = problem.targets().iter().zip(&sol.train_predictions).map(|(y, f)| y - f);
                        score(&sol.expansion, &mut train, sol.loo_residuals.as_deref(), hold_inputs, hold_targets)
                    }
                    Err(_) => f64::INFINITY,
                }
            }
        };
        if value.is_finite() { value } else { f64::INFINITY }
    }

    /// Tunes and fits on explicit row-major `inputs` (`targets.len()` rows of `dim` values).
    pub fn fit_rows(
        &self,
        inputs: &[f64],
        dim: usize,
        targets: &[f64],
    ) -> Result<(KernelExpansion, TuneReport), FitError> {
        self.validate()?;
        super::validate::check_rows(inputs, dim, targets, 3)?;
        let prepared = self.prepare(inputs, dim, targets)?;
        let bounds = [
            (self.gamma_bounds.0.log10(), self.gamma_bounds.1.log10()),
            (self.sigma2_bounds.0.log10(), self.sigma2_bounds.1.log10()),
        ];
        let f = |z: &[f64]| self.fitness_of(&prepared, dim, 10f64.powf(z[0]), 10f64.powf(z[1]));
        let (best, best_f, history) =
            minimize(f, &bounds, &self.cpso).map_err(|e| FitError::InvalidConfig(e.to_string()))?;
        drop(prepared);
        if !best_f.is_finite() {
            return Err(FitError::Numerical("every CPSO candidate failed to fit".into()));
        }
        let (gamma, sigma2) = (10f64.powf(best[0]), 10f64.powf(best[1]));
        let (expansion, solver) = if targets.len() <= self.exact_max_rows {
            let sol = super::exact::solve_exact(inputs, dim, targets, gamma, sigma2, false, self.cpso.threads)?;
            (KernelExpansion { dim, centres: inputs.to_vec(), coef: sol.alpha, bias: sol.bias, sigma2 }, Solver::Exact)
        } else {
            let protos = select_prototypes(inputs, dim, self.prototypes, self.selection);
            let sol = NystromProblem::new(inputs, dim, targets, protos)?.solve(gamma, sigma2, self.rank_tol, false)?;
            let rank = sol.rank;
            (sol.expansion, Solver::Nystrom { rank })
        };
        Ok((expansion, TuneReport { gamma, sigma2, fitness: best_f, history, solver }))
    }
}

/// What the tuning chose (see [`CpsoLssvmModel`]).
#[derive(Debug, Clone, PartialEq)]
pub struct TuneReport {
    /// Chosen γ.
    pub gamma: f64,
    /// Chosen σ².
    pub sigma2: f64,
    /// Best fitness.
    pub fitness: f64,
    /// The CPSO run.
    pub history: CpsoHistory,
    /// Solver of the final fit.
    pub solver: Solver,
}

impl Fit for CpsoLssvm {
    type Model = CpsoLssvmModel;

    fn fit(&self, train: &[f64]) -> Result<CpsoLssvmModel, FitError> {
        self.validate()?;
        let e = embed_series(&self.embedding, train, 3)?;
        let (expansion, r) = self.fit_rows(&e.inputs, e.dim, &e.targets)?;
        Ok(CpsoLssvmModel {
            model: LssvmModel { embedding: self.embedding, expansion },
            gamma: r.gamma,
            sigma2: r.sigma2,
            fitness: r.fitness,
            evaluations: r.history.evaluations,
            history: r.history,
            solver: r.solver,
        })
    }
}
