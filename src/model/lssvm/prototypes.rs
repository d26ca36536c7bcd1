//! Prototype (landmark) selection for the fixed-size LS-SVM (Suykens et al. 2002, §6.4;
//! De Brabanter et al. 2010).
//!
//! Suykens et al. choose the m_p prototypes by maximising the quadratic Rényi entropy with random
//! swaps. That search is stochastic, costs O(m_p²) per swap and depends on σ², so it would have
//! to be redone for every candidate σ² of the tuner. Here the default is k-means++ seeding
//! (Arthur & Vassilvitskii 2007) followed by a few Lloyd iterations: Zhang, Tsang & Kwok
//! ("Improved Nyström low-rank approximation", ICML 2008) bound the Nyström error by the k-means
//! quantisation error, the result is σ²-independent (selected once per tuning run) and, with the
//! seeded generator, deterministic. Evenly spaced training rows are kept as a cheap alternative.
//!
//! When m_p ≥ n every training row becomes a prototype, in order, so the fixed-size model then
//! equals the exact LS-SVM (tests/lssvm.rs).

use super::kernel::sq_dist;
use crate::model::rng::Rng;

/// How the prototypes are chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PrototypeSelection {
    /// k-means++ seeding, then at most `iterations` Lloyd steps (stops early when the
    /// assignment no longer changes). Centres need not be training rows.
    KMeans {
        /// Lloyd iterations after seeding (0 = the k-means++ seeds themselves, training rows).
        iterations: usize,
        /// Seed of the k-means++ draws.
        seed: u64,
    },
    /// Rows `⌊k·n/m_p⌋`, k = 0..m_p: evenly spaced in time.
    EvenlySpaced,
}

impl Default for PrototypeSelection {
    /// k-means++ with 10 Lloyd iterations, seed 0.
    fn default() -> Self {
        Self::KMeans { iterations: 10, seed: 0 }
    }
}

/// Chooses `count` prototypes among the row-major `inputs` (`dim` columns); returns them
/// row-major. With `count ≥ n` all rows are returned, in order.
pub fn select_prototypes(inputs: &[f64], dim: usize, count: usize, method: PrototypeSelection) -> Vec<f64> {
    if dim == 0 {
        return Vec::new();
    }
    let n = inputs.len() / dim;
    if count >= n {
        return inputs[..n * dim].to_vec();
    }
    if count == 0 {
        return Vec::new();
    }
    match method {
        PrototypeSelection::EvenlySpaced => {
            (0..count).flat_map(|k| inputs[(k * n / count) * dim..(k * n / count + 1) * dim].iter().copied()).collect()
        }
        PrototypeSelection::KMeans { iterations, seed } => {
            let mut centres = kmeans_pp(inputs, dim, count, seed);
            lloyd(inputs, dim, &mut centres, iterations);
            centres
        }
    }
}

/// k-means++ seeding: the first centre uniformly, each next one with probability ∝ D(x)², the
/// squared distance to the nearest chosen centre.
fn kmeans_pp(inputs: &[f64], dim: usize, count: usize, seed: u64) -> Vec<f64> {
    let n = inputs.len() / dim;
    let row = |i: usize| &inputs[i * dim..(i + 1) * dim];
    let mut rng = Rng::new(seed);
    let first = ((rng.next_f64() * n as f64) as usize).min(n - 1);
    let mut centres = row(first).to_vec();
    let mut d2: Vec<f64> = (0..n).map(|i| sq_dist(row(i), row(first))).collect();
    while centres.len() < count * dim {
        let total: f64 = d2.iter().sum();
        let pick = if total > 0.0 {
            let target = rng.next_f64() * total;
            let mut acc = 0.0;
            let mut pick = n - 1;
            for (i, &d) in d2.iter().enumerate() {
                acc += d;
                if acc > target && d > 0.0 {
                    pick = i;
                    break;
                }
            }
            // Rounding can leave `pick` on an already chosen row: take the farthest instead.
            if d2[pick] == 0.0 {
                pick = (0..n).fold(0, |b, i| if d2[i] > d2[b] { i } else { b });
            }
            pick
        } else {
            // Fewer distinct rows than prototypes: repeat rows (they are pruned later by the
            // pivoted Cholesky of the prototype kernel matrix).
            (centres.len() / dim) % n
        };
        let c = row(pick).to_vec();
        for (i, d) in d2.iter_mut().enumerate() {
            *d = d.min(sq_dist(row(i), &c));
        }
        centres.extend_from_slice(&c);
    }
    centres
}

/// Lloyd iterations: assign each row to its nearest centre, move each centre to its mean (an
/// empty cluster keeps its centre).
fn lloyd(inputs: &[f64], dim: usize, centres: &mut [f64], iterations: usize) {
    let n = inputs.len() / dim;
    let k = centres.len() / dim;
    let mut assign = vec![usize::MAX; n];
    let mut sums = vec![0.0; k * dim];
    let mut counts = vec![0usize; k];
    for _ in 0..iterations {
        let mut changed = false;
        for (i, a) in assign.iter_mut().enumerate() {
            let x = &inputs[i * dim..(i + 1) * dim];
            let mut best = (f64::INFINITY, 0);
            for c in 0..k {
                let d = sq_dist(x, &centres[c * dim..(c + 1) * dim]);
                if d < best.0 {
                    best = (d, c);
                }
            }
            changed |= *a != best.1;
            *a = best.1;
        }
        if !changed {
            break;
        }
        sums.fill(0.0);
        counts.fill(0);
        for (i, &a) in assign.iter().enumerate() {
            counts[a] += 1;
            for j in 0..dim {
                sums[a * dim + j] += inputs[i * dim + j];
            }
        }
        for c in 0..k {
            if counts[c] > 0 {
                for j in 0..dim {
                    centres[c * dim + j] = sums[c * dim + j] / counts[c] as f64;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> Vec<f64> {
        (0..200).flat_map(|i| [(i % 20) as f64 / 10.0, (i / 20) as f64 / 5.0]).collect()
    }

    #[test]
    fn all_rows_when_asked_for_at_least_n() {
        let x = grid();
        assert_eq!(select_prototypes(&x, 2, 200, PrototypeSelection::default()), x);
        assert_eq!(select_prototypes(&x, 2, 500, PrototypeSelection::EvenlySpaced), x);
    }

    #[test]
    fn deterministic_distinct_and_spread() {
        let x = grid();
        let a = select_prototypes(&x, 2, 12, PrototypeSelection::default());
        assert_eq!(a, select_prototypes(&x, 2, 12, PrototypeSelection::default()));
        assert_ne!(a, select_prototypes(&x, 2, 12, PrototypeSelection::KMeans { iterations: 10, seed: 1 }));
        assert_eq!(a.len(), 24);
        // Every row of the grid lies within 0.6 of some centre (the grid spans 1.9 × 1.8).
        for r in x.chunks(2) {
            let near = a.chunks(2).map(|c| sq_dist(r, c)).fold(f64::INFINITY, f64::min);
            assert!(near < 0.36, "row {r:?} is {near} from the nearest centre");
        }
        let even = select_prototypes(&x, 2, 4, PrototypeSelection::EvenlySpaced);
        assert_eq!(even, vec![0.0, 0.0, 1.0, 0.4, 0.0, 1.0, 1.0, 1.4]);
    }

    #[test]
    fn copes_with_duplicate_rows() {
        let x = vec![1.0; 20];
        let p = select_prototypes(&x, 2, 4, PrototypeSelection::default());
        assert_eq!(p, vec![1.0; 8]);
    }
}
