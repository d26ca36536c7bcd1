//! Pair counting for the C-C method: for every delay t and every disjoint sub-series
//! `{x_s, x_{s+t}, x_{s+2t}, …}` (length ⌊N/t⌋), the number of pairs i < j whose sup-norm distance
//! in dimensions m = 1..=5 is at most each of the four radii.
//!
//! Distances grow incrementally with the dimension, `d_m = max(d_{m−1}, |y_{i+m−1} − y_{j+m−1}|)`,
//! so one visit of a pair serves all (m, r) cells. Counts are integers, so the result does not
//! depend on how the work is split between threads.

use std::sync::atomic::{AtomicUsize, Ordering};

use super::{M_MAX, RADII};

/// Pair counts of one sub-series: `counts[m − 1][k] = #{i < j : d_m(i, j) ≤ r_k}` for
/// m = 1..=5, where pair (i, j) exists in dimension m when `j + m − 1` is inside the sub-series.
pub(super) type Counts = [[u64; RADII]; M_MAX];

/// Counts the pairs of every sub-series of every delay t = 1..=t_max, on up to `threads` threads.
/// Returns, for each t (index t − 1), the counts of its t sub-series in order s = 0..t.
pub(super) fn count_all(x: &[f64], t_max: usize, radii: &[f64; RADII], threads: usize) -> Vec<Vec<Counts>> {
    // Work units (t, s), largest first (cost ∝ (N/t)²), handed out through an atomic counter.
    let units: Vec<(usize, usize)> = (1..=t_max).flat_map(|t| (0..t).map(move |s| (t, s))).collect();
    let threads = threads.clamp(1, units.len().max(1));
    let next = AtomicUsize::new(0);
    let work = || {
        let mut done = Vec::new();
        let mut sub = Vec::with_capacity(x.len());
        loop {
            let u = next.fetch_add(1, Ordering::Relaxed);
            let Some(&(t, s)) = units.get(u) else { break };
            sub_series_into(x, t, s, &mut sub);
            done.push((u, count_pairs(&sub, radii)));
        }
        done
    };
    let finished: Vec<(usize, Counts)> = if threads == 1 {
        work()
    } else {
        std::thread::scope(|scope| {
            let handles: Vec<_> = (0..threads).map(|_| scope.spawn(work)).collect();
            let joined = handles.into_iter().map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)));
            joined.flatten().collect()
        })
    };
    let mut by_unit = vec![[[0u64; RADII]; M_MAX]; units.len()];
    for (u, counts) in finished {
        by_unit[u] = counts;
    }
    let mut by_unit = by_unit.into_iter();
    (1..=t_max).map(|t| by_unit.by_ref().take(t).collect()).collect()
}

/// Fills `out` with the s-th (0-based) sub-series of delay t, truncated to ⌊N/t⌋ samples.
fn sub_series_into(x: &[f64], t: usize, s: usize, out: &mut Vec<f64>) {
    let len = x.len() / t;
    out.clear();
    out.extend(x[s..].iter().step_by(t).take(len));
}

/// Larger of two finite numbers (one `maxsd`; the inputs are checked finite beforehand).
#[inline(always)]
fn max(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

/// Counts the pairs of one sub-series `y` (embedding delay 1 within it) against the radii.
pub(super) fn count_pairs(y: &[f64], radii: &[f64; RADII]) -> Counts {
    let len = y.len();
    let mut counts = [[0u64; RADII]; M_MAX];
    // Pairs (i, j) with j < full_end exist in all five dimensions.
    let full_end = len.saturating_sub(M_MAX - 1);
    for i in 0..len.saturating_sub(1) {
        if i + 1 < full_end {
            let head: [f64; M_MAX] = std::array::from_fn(|m| y[i + m]);
            count_full(&head, &y[i + 1..], full_end - (i + 1), radii, &mut counts);
        }
        // The last pairs reach the end of the sub-series in fewer than five dimensions.
        for j in (i + 1).max(full_end)..len {
            let mut d = 0.0;
            for m in 0..(len - j).min(M_MAX) {
                d = max(d, (y[i + m] - y[j + m]).abs());
                for (count, &r) in counts[m].iter_mut().zip(radii) {
                    *count += u64::from(d <= r);
                }
            }
        }
    }
    counts
}

/// Counts pairs (i, j) for `n` consecutive j whose windows `rest[q..q + 5]` all fit; `head` is
/// the window of i. Written as a flat loop over equal-length slices so that it vectorises.
#[inline(always)]
fn count_full(head: &[f64; M_MAX], rest: &[f64], n: usize, radii: &[f64; RADII], counts: &mut Counts) {
    let (y0, y1, y2, y3, y4) = (&rest[..n], &rest[1..n + 1], &rest[2..n + 2], &rest[3..n + 3], &rest[4..n + 4]);
    let [r0, r1, r2, r3] = *radii;
    let mut c = [[0u64; RADII]; M_MAX];
    for q in 0..n {
        let d1 = (head[0] - y0[q]).abs();
        let d2 = max(d1, (head[1] - y1[q]).abs());
        let d3 = max(d2, (head[2] - y2[q]).abs());
        let d4 = max(d3, (head[3] - y3[q]).abs());
        let d5 = max(d4, (head[4] - y4[q]).abs());
        for (cm, d) in c.iter_mut().zip([d1, d2, d3, d4, d5]) {
            cm[0] += u64::from(d <= r0);
            cm[1] += u64::from(d <= r1);
            cm[2] += u64::from(d <= r2);
            cm[3] += u64::from(d <= r3);
        }
    }
    for (total, part) in counts.iter_mut().zip(c) {
        for (a, b) in total.iter_mut().zip(part) {
            *a += b;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Plain double loop over pairs, one (m, r) cell at a time.
    fn brute(y: &[f64], radii: &[f64; RADII]) -> Counts {
        let mut counts = [[0u64; RADII]; M_MAX];
        for m in 1..=M_MAX {
            let vectors = y.len().saturating_sub(m - 1);
            for i in 0..vectors {
                for j in i + 1..vectors {
                    let d = (0..m).map(|k| (y[i + k] - y[j + k]).abs()).fold(0.0, f64::max);
                    for (k, &r) in radii.iter().enumerate() {
                        counts[m - 1][k] += u64::from(d <= r);
                    }
                }
            }
        }
        counts
    }

    #[test]
    fn incremental_counts_equal_the_brute_force() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let y: Vec<f64> = (0..97)
            .map(|i| {
                state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                ((state >> 40) % 7) as f64 * 0.5 + (i as f64 * 0.3).sin()
            })
            .collect();
        let radii = [0.25, 0.5, 0.75, 1.0];
        for len in [0, 1, 2, 4, 5, 6, 7, 11, 97] {
            assert_eq!(count_pairs(&y[..len], &radii), brute(&y[..len], &radii), "len {len}");
        }
    }

    #[test]
    fn thread_count_does_not_change_the_counts() {
        let x: Vec<f64> = (0..300).map(|i| ((i * 37 % 101) as f64).sqrt()).collect();
        let radii = [0.5, 1.0, 1.5, 2.0];
        let one = count_all(&x, 9, &radii, 1);
        assert_eq!(one.len(), 9);
        assert!(one.iter().enumerate().all(|(k, v)| v.len() == k + 1));
        assert_eq!(one, count_all(&x, 9, &radii, 2));
        assert_eq!(one, count_all(&x, 9, &radii, 5));
    }
}
