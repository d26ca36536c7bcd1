//! Chaos initialisation of CPSO (paper §2.2, Step 1, Eq. 11–12): a random start vector
//! `z⁽⁰⁾ ∈ (0, 1)^D` is iterated through the logistic map `z ← μ z (1 − z)` (Eq. 11, μ = 4:
//! fully chaotic, ergodic on (0, 1)), and each iterate is mapped onto the bounds,
//! `x_ij = a_j + (b_j − a_j) z_ij` (Eq. 12).
//!
//! The points 0, 0.25, 0.5, 0.75 and 1 are fixed or reach a fixed point of the μ = 4 map in at
//! most two steps (0.5 → 1 → 0, 0.25 → 0.75 → 0.75), so a start or an iterate within
//! [`DEGENERATE_EPS`] of one of them is redrawn from the seeded generator.

use crate::model::rng::Rng;

/// Distance to a degenerate point of the logistic map below which a value is redrawn.
pub const DEGENERATE_EPS: f64 = 1e-9;

const DEGENERATE: [f64; 5] = [0.0, 0.25, 0.5, 0.75, 1.0];

fn degenerate(z: f64) -> bool {
    DEGENERATE.iter().any(|&p| (z - p).abs() < DEGENERATE_EPS)
}

/// A start value in (0, 1) away from the degenerate points.
fn draw(rng: &mut Rng) -> f64 {
    loop {
        let z = rng.next_f64();
        if !degenerate(z) {
            return z;
        }
    }
}

/// `count` candidate positions inside `bounds` (one `(lo, hi)` per dimension): the first `count`
/// logistic-map iterates (Eq. 11) of a random start, mapped by Eq. 12.
pub fn chaotic_candidates(bounds: &[(f64, f64)], count: usize, mu: f64, rng: &mut Rng) -> Vec<Vec<f64>> {
    let mut z: Vec<f64> = bounds.iter().map(|_| draw(rng)).collect();
    (0..count)
        .map(|_| {
            for zj in z.iter_mut() {
                *zj = mu * *zj * (1.0 - *zj);
                if degenerate(*zj) || !(*zj > 0.0 && *zj < 1.0) {
                    *zj = draw(rng);
                }
            }
            bounds.iter().zip(&z).map(|(&(a, b), &zj)| a + (b - a) * zj).collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn follows_the_logistic_map_inside_the_bounds() {
        let bounds = [(-2.0, 2.0), (10.0, 11.0)];
        let c = chaotic_candidates(&bounds, 50, 4.0, &mut Rng::new(3));
        assert_eq!(c.len(), 50);
        for w in c.windows(2) {
            for (j, &(a, b)) in bounds.iter().enumerate() {
                let (z0, z1) = ((w[0][j] - a) / (b - a), (w[1][j] - a) / (b - a));
                assert!(z1 > 0.0 && z1 < 1.0);
                assert!((z1 - 4.0 * z0 * (1.0 - z0)).abs() < 1e-9, "Eq. 11 step");
            }
        }
    }

    #[test]
    fn never_sticks_at_degenerate_points() {
        // Many seeds, long runs: no candidate may sit at a fixed point.
        for seed in 0..50 {
            let c = chaotic_candidates(&[(0.0, 1.0)], 500, 4.0, &mut Rng::new(seed));
            assert!(c.iter().all(|x| !degenerate(x[0])));
        }
    }
}
