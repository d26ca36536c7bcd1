//! Wavelet thresholding: the universal threshold of Donoho & Johnstone (1994, "VisuShrink") with
//! the noise level estimated from the finest detail coefficients, and soft thresholding
//! (`pywt.threshold(d, T, 'soft')`).

/// Divisor turning the median absolute finest-detail coefficient into a Gaussian σ estimate
/// (≈ Φ⁻¹(3/4)), as in docs/design.md.
pub const MAD_TO_SIGMA: f64 = 0.6745;

/// Median of `|values|`, computed in `scratch` (resized as needed; no other allocation).
/// Even counts average the two middle values, as `numpy.median` does. Zero for an empty slice.
pub fn median_abs(values: &[f64], scratch: &mut Vec<f64>) -> f64 {
    scratch.clear();
    scratch.extend(values.iter().map(|v| v.abs()));
    let n = scratch.len();
    if n == 0 {
        return 0.0;
    }
    let mid = n / 2;
    let (lower, &mut upper, _) = scratch.select_nth_unstable_by(mid, f64::total_cmp);
    if n % 2 == 1 {
        upper
    } else {
        let below = lower.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        0.5 * (below + upper)
    }
}

/// Noise σ from the finest detail coefficients: `median(|cD1|) / 0.6745`.
pub fn noise_sigma(finest_detail: &[f64], scratch: &mut Vec<f64>) -> f64 {
    median_abs(finest_detail, scratch) / MAD_TO_SIGMA
}

/// Universal threshold `T = σ·√(2 ln n)` for a signal of `n` samples (zero for n ≤ 1).
pub fn universal_threshold(sigma: f64, n: usize) -> f64 {
    if n <= 1 { 0.0 } else { sigma * (2.0 * (n as f64).ln()).sqrt() }
}

/// Soft thresholding in place: `c ← sign(c)·max(|c| − T, 0)`.
pub fn soft_threshold(coeffs: &mut [f64], threshold: f64) {
    for c in coeffs {
        let magnitude = c.abs() - threshold;
        *c = if magnitude > 0.0 { magnitude.copysign(*c) } else { 0.0 };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_matches_numpy_for_odd_and_even_counts() {
        let mut scratch = Vec::new();
        assert_eq!(median_abs(&[3.0, -1.0, 2.0], &mut scratch), 2.0);
        assert_eq!(median_abs(&[-4.0, 1.0, 3.0, -2.0], &mut scratch), 2.5);
        assert_eq!(median_abs(&[], &mut scratch), 0.0);
    }

    #[test]
    fn soft_threshold_shrinks_towards_zero() {
        let mut c = [-3.0, -0.5, 0.0, 0.5, 2.0];
        soft_threshold(&mut c, 1.0);
        assert_eq!(c, [-2.0, 0.0, 0.0, 0.0, 1.0]);
    }

    #[test]
    fn universal_threshold_grows_with_log_n() {
        assert_eq!(universal_threshold(2.0, 1), 0.0);
        let t = universal_threshold(1.0, 1000);
        assert!((t - (2.0 * 1000f64.ln()).sqrt()).abs() < 1e-15);
    }
}
