//! Chaotic particle swarm optimisation (CPSO), paper §2.2 (Eq. 9–14), as a generic minimiser.
//!
//! 1. Chaos initialisation ([`chaos`], Eq. 11–12): M candidates from logistic-map iterates
//!    (μ = 4) of a seeded random start, mapped onto the bounds; their fitness is evaluated and
//!    the best N become the swarm (ties: lower candidate index). Initial velocities are uniform
//!    in `[−v_max, v_max]`, `v_max = velocity_fraction · (hi − lo)` per dimension.
//! 2. Velocity and position updates (Eq. 9–10) with `c1 = c2 = 2`, fresh `r1, r2 ∈ [0, 1)`
//!    per particle and dimension, inertia falling linearly from ω_max = 0.9 to ω_min = 0.1
//!    (Eq. 14, `ω(t) = ω_max − t (ω_max − ω_min)/(t_max − 1)` for t = 0, …, t_max − 1, so both
//!    ends are reached). Velocities are clamped to `±v_max`; positions are clamped to the bounds
//!    and the velocity component that left them is zeroed.
//! 3. Personal and global bests are updated after each (synchronous) iteration, in particle
//!    order, on strict improvement.
//! 4. Stop after t_max iterations, or earlier when the global best has not improved for
//!    `stall_iterations` iterations (0 = never).
//!
//! Determinism: every random number is drawn on the calling thread from the seeded [`Rng`], in a
//! fixed order; only fitness evaluations run in parallel ([`parallel`]) and are gathered in
//! particle order, so the result is bit-identical for a given seed whatever the thread count.

pub mod chaos;
pub mod parallel;

use std::fmt;

use crate::model::rng::Rng;
use chaos::chaotic_candidates;
use parallel::evaluate_all;

/// CPSO settings (paper §2.2). The paper gives c1, c2, ω_max, ω_min and μ; M, N and t_max
/// are ours.
#[derive(Debug, Clone, PartialEq)]
pub struct CpsoConfig {
    /// M: chaotic candidates evaluated at initialisation (Eq. 11–12), at least N.
    pub candidates: usize,
    /// N: swarm size kept from the candidates.
    pub particles: usize,
    /// t_max: maximum number of update iterations (Eq. 14).
    pub iterations: usize,
    /// c1, cognitive learning factor (Eq. 9), 2 in the paper.
    pub c1: f64,
    /// c2, social learning factor (Eq. 9), 2 in the paper.
    pub c2: f64,
    /// ω_max, initial inertia weight (Eq. 14), 0.9 in the paper.
    pub w_max: f64,
    /// ω_min, final inertia weight (Eq. 14), 0.1 in the paper.
    pub w_min: f64,
    /// Logistic-map parameter μ (Eq. 11), 4 (fully chaotic).
    pub mu: f64,
    /// Velocity clamp as a fraction of each dimension's range.
    pub velocity_fraction: f64,
    /// Stop when the global best has not improved for this many iterations (0 = never).
    pub stall_iterations: usize,
    /// Seed of every random draw (start vector, velocities, r1, r2).
    pub seed: u64,
    /// Threads for the fitness evaluations (0 = all available cores). Does not change results.
    pub threads: usize,
}

impl Default for CpsoConfig {
    /// M = 24, N = 12, t_max = 12, c1 = c2 = 2, ω 0.9 → 0.1, μ = 4, v_max = 20 % of the range,
    /// stall stop after 5 iterations without improvement, seed 0, all cores.
    fn default() -> Self {
        Self {
            candidates: 24,
            particles: 12,
            iterations: 12,
            c1: 2.0,
            c2: 2.0,
            w_max: 0.9,
            w_min: 0.1,
            mu: 4.0,
            velocity_fraction: 0.2,
            stall_iterations: 5,
            seed: 0,
            threads: 0,
        }
    }
}

/// What a CPSO run went through.
#[derive(Debug, Clone, PartialEq)]
pub struct CpsoHistory {
    /// Global best fitness after initialisation, then after each iteration.
    pub best_f: Vec<f64>,
    /// Fitness evaluations made (M + N · iterations run).
    pub evaluations: usize,
    /// Update iterations run (≤ t_max).
    pub iterations: usize,
    /// True when the run stopped on stall before t_max.
    pub stalled: bool,
}

/// Why CPSO could not run.
#[derive(Debug, Clone, PartialEq)]
pub enum CpsoError {
    /// A bound is not finite or has `lo ≥ hi`, or there are no dimensions.
    Bounds(String),
    /// A configuration value is out of range.
    Config(String),
}

impl fmt::Display for CpsoError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Bounds(m) => write!(f, "invalid CPSO bounds: {m}"),
            Self::Config(m) => write!(f, "invalid CPSO configuration: {m}"),
        }
    }
}

impl std::error::Error for CpsoError {}

impl CpsoConfig {
    /// Checks the settings [`minimize`] needs: 1 ≤ N ≤ M (the swarm is the best N of the M chaotic
    /// candidates, Eq. 11–12), 0 < μ ≤ 4 (the logistic map of Eq. 11 stays in [0, 1]), a positive
    /// velocity clamp and finite c1, c2, ω_max, ω_min (Eq. 9, 14). The one CPSO parameter check:
    /// [`minimize`] runs it, and so does the configuration file's `[retrain]` section
    /// ([`crate::config::Config::cpso_lssvm`]).
    pub fn validate(&self) -> Result<(), CpsoError> {
        if self.particles == 0 || self.candidates < self.particles {
            return Err(CpsoError::Config(format!(
                "need 1 <= particles <= candidates, got {} and {}",
                self.particles, self.candidates
            )));
        }
        let finite =
            [self.c1, self.c2, self.w_max, self.w_min, self.mu, self.velocity_fraction].iter().all(|v| v.is_finite());
        if !finite || self.velocity_fraction <= 0.0 || !(self.mu > 0.0 && self.mu <= 4.0) {
            return Err(CpsoError::Config(format!(
                "need 0 < mu <= 4, velocity_fraction > 0 and finite factors; got {self:?}"
            )));
        }
        Ok(())
    }
}

/// Checks the search box: at least one dimension, each with finite `lo < hi`.
fn validate_bounds(bounds: &[(f64, f64)]) -> Result<(), CpsoError> {
    if bounds.is_empty() {
        return Err(CpsoError::Bounds("no dimensions".into()));
    }
    for (d, &(lo, hi)) in bounds.iter().enumerate() {
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(CpsoError::Bounds(format!("dimension {d}: [{lo}, {hi}]")));
        }
    }
    Ok(())
}

/// Minimises `f` over the box `bounds` (one `(lo, hi)` per dimension) with CPSO (paper §2.2).
/// Returns the best position, its fitness and the run's history. `f` may run on several threads
/// at once; NaN fitness counts as +∞.
pub fn minimize<F>(f: F, bounds: &[(f64, f64)], config: &CpsoConfig) -> Result<(Vec<f64>, f64, CpsoHistory), CpsoError>
where
    F: Fn(&[f64]) -> f64 + Sync,
{
    validate_bounds(bounds)?;
    config.validate()?;
    let mut rng = Rng::new(config.seed);
    let dims = bounds.len();
    let vmax: Vec<f64> = bounds.iter().map(|&(lo, hi)| config.velocity_fraction * (hi - lo)).collect();

    // Step 1: chaos initialisation, keep the best N of M.
    let candidates = chaotic_candidates(bounds, config.candidates, config.mu, &mut rng);
    let cand_f = evaluate_all(&f, &candidates, config.threads);
    let mut order: Vec<usize> = (0..candidates.len()).collect();
    order.sort_by(|&a, &b| cand_f[a].total_cmp(&cand_f[b]).then(a.cmp(&b)));
    order.truncate(config.particles);
    let mut x: Vec<Vec<f64>> = order.iter().map(|&i| candidates[i].clone()).collect();
    let mut v: Vec<Vec<f64>> = (0..x.len()).map(|_| vmax.iter().map(|&m| rng.uniform(-m, m)).collect()).collect();
    let mut pbest = x.clone();
    let mut pbest_f: Vec<f64> = order.iter().map(|&i| cand_f[i]).collect();
    let mut g = 0;
    for i in 1..pbest_f.len() {
        if pbest_f[i] < pbest_f[g] {
            g = i;
        }
    }
    let mut gbest = pbest[g].clone();
    let mut gbest_f = pbest_f[g];
    let mut history =
        CpsoHistory { best_f: vec![gbest_f], evaluations: candidates.len(), iterations: 0, stalled: false };

    let mut since_improved = 0;
    for t in 0..config.iterations {
        // Eq. 14 with t = 0 … t_max − 1.
        let w = if config.iterations > 1 {
            config.w_max - t as f64 * (config.w_max - config.w_min) / (config.iterations - 1) as f64
        } else {
            config.w_max
        };
        // Step 2: Eq. 9–10, random numbers drawn in particle, then dimension, order.
        for (i, (xi, vi)) in x.iter_mut().zip(v.iter_mut()).enumerate() {
            for d in 0..dims {
                let (r1, r2) = (rng.next_f64(), rng.next_f64());
                let vel = w * vi[d] + config.c1 * r1 * (pbest[i][d] - xi[d]) + config.c2 * r2 * (gbest[d] - xi[d]);
                vi[d] = vel.clamp(-vmax[d], vmax[d]);
                xi[d] += vi[d];
                let (lo, hi) = bounds[d];
                if xi[d] < lo || xi[d] > hi {
                    xi[d] = xi[d].clamp(lo, hi);
                    vi[d] = 0.0;
                }
            }
        }
        // Step 3: evaluate, update personal and global bests.
        let fx = evaluate_all(&f, &x, config.threads);
        history.evaluations += x.len();
        let before = gbest_f;
        for (i, &fi) in fx.iter().enumerate() {
            if fi < pbest_f[i] {
                pbest_f[i] = fi;
                pbest[i].clone_from(&x[i]);
                if fi < gbest_f {
                    gbest_f = fi;
                    gbest.clone_from(&x[i]);
                }
            }
        }
        history.best_f.push(gbest_f);
        history.iterations = t + 1;
        // Step 4: stopping criteria.
        since_improved = if gbest_f < before { 0 } else { since_improved + 1 };
        if config.stall_iterations > 0 && since_improved >= config.stall_iterations && t + 1 < config.iterations {
            history.stalled = true;
            break;
        }
    }
    Ok((gbest, gbest_f, history))
}
