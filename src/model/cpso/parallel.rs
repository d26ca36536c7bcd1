//! Parallel fitness evaluation with deterministic results: worker threads
//! (`std::thread::scope`) take particles from a shared counter, every value is stored at its
//! particle's index, so the gathered vector is in particle order whatever the thread count or
//! scheduling. The fitness function must be a pure function of the position.

use std::sync::atomic::{AtomicUsize, Ordering};

use crate::model::lssvm::dense::resolve_threads;

/// `f` at every position, in order; NaN is mapped to +∞ (a failed evaluation never wins).
/// `threads`: 0 = all available cores.
pub fn evaluate_all<F>(f: &F, positions: &[Vec<f64>], threads: usize) -> Vec<f64>
where
    F: Fn(&[f64]) -> f64 + Sync,
{
    let clean = |v: f64| if v.is_nan() { f64::INFINITY } else { v };
    let threads = resolve_threads(threads).min(positions.len());
    if threads <= 1 {
        return positions.iter().map(|x| clean(f(x))).collect();
    }
    let next = AtomicUsize::new(0);
    let mut out = vec![f64::INFINITY; positions.len()];
    std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                let next = &next;
                s.spawn(move || {
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        if i >= positions.len() {
                            break mine;
                        }
                        mine.push((i, clean(f(&positions[i]))));
                    }
                })
            })
            .collect();
        for w in workers {
            // A panicking fitness function leaves +∞ for the particles that worker had taken.
            if let Ok(results) = w.join() {
                for (i, v) in results {
                    out[i] = v;
                }
            }
        }
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gathers_in_order_for_any_thread_count() {
        let pos: Vec<Vec<f64>> = (0..37).map(|i| vec![i as f64, 0.5]).collect();
        let f = |x: &[f64]| if x[0] == 3.0 { f64::NAN } else { x[0] * x[0] + x[1] };
        let one = evaluate_all(&f, &pos, 1);
        assert_eq!(one[3], f64::INFINITY);
        for t in [2, 3, 8, 64] {
            assert_eq!(evaluate_all(&f, &pos, t), one);
        }
    }
}
