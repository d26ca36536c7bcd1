//! NumPy-compatible pairwise summation.
//!
//! `numpy.sum` of a contiguous `float64` array does not add left to right: it uses the pairwise
//! algorithm of `numpy/_core/src/umath/loops_utils.h.src` (`pairwise_sum`): blocks of at most 128
//! values are summed with 8 interleaved accumulators, longer runs are split in two halves (the
//! split point rounded down to a multiple of 8) and the halves summed recursively. Reproducing the
//! same order of additions makes [`crate::diag::allan`] agree with `allantools` bit for bit in the
//! usual case, and the rounding error grows as O(log n) instead of O(n).

/// Block length below which NumPy stops splitting (`PW_BLOCKSIZE`).
const BLOCK: usize = 128;

/// Sum of `f(i)` for `i` in `0..n`, added in NumPy's pairwise order (see the module docs).
///
/// `f` is called exactly once per index, so the terms need not be stored.
pub fn pairwise_sum_by(n: usize, f: &impl Fn(usize) -> f64) -> f64 {
    sum_range(0, n, f)
}

/// Sum of `values` in NumPy's pairwise order: equal to `numpy.sum(values)` for a contiguous array.
pub fn pairwise_sum(values: &[f64]) -> f64 {
    pairwise_sum_by(values.len(), &|i| values[i])
}

fn sum_range(start: usize, n: usize, f: &impl Fn(usize) -> f64) -> f64 {
    if n < 8 {
        let mut res = 0.0;
        for i in start..start + n {
            res += f(i);
        }
        res
    } else if n <= BLOCK {
        let mut r = [0.0f64; 8];
        for (j, acc) in r.iter_mut().enumerate() {
            *acc = f(start + j);
        }
        let whole = n - n % 8;
        let mut i = 8;
        while i < whole {
            for (j, acc) in r.iter_mut().enumerate() {
                *acc += f(start + i + j);
            }
            i += 8;
        }
        let mut res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
        for k in whole..n {
            res += f(start + k);
        }
        res
    } else {
        let mut n2 = n / 2;
        n2 -= n2 % 8;
        sum_range(start, n2, f) + sum_range(start + n2, n - n2, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_sums_are_exact() {
        assert_eq!(pairwise_sum(&[]), 0.0);
        assert_eq!(pairwise_sum(&[1.0, 2.0, 3.0]), 6.0);
        let v: Vec<f64> = (1..=1000).map(f64::from).collect();
        assert_eq!(pairwise_sum(&v), 500_500.0);
    }

    #[test]
    fn pairwise_beats_naive_on_a_long_sum() {
        // 0.1 is not representable; the naive sum of 10^6 copies drifts visibly, pairwise does not.
        let v = vec![0.1f64; 1_000_000];
        let naive: f64 = v.iter().sum();
        let pairwise = pairwise_sum(&v);
        assert!((pairwise - 100_000.0).abs() < (naive - 100_000.0).abs());
        assert!((pairwise - 100_000.0).abs() < 1e-9);
    }
}
