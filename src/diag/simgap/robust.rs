//! Small order statistics and moments shared by the sim-to-real statistics and the effect fits:
//! the median absolute deviation (about [`crate::model::metrics::median`], NumPy's to the bit),
//! block means, the kurtosis and a least-squares line.

use crate::model::metrics::median;

/// Normal-consistency factor of the MAD: σ = 1.4826·MAD for Gaussian data (1/Φ⁻¹(3/4)).
pub const MAD_TO_SIGMA: f64 = 1.482_602_218_505_602;

/// Median absolute deviation about the median, scaled to a Gaussian σ ([`MAD_TO_SIGMA`]).
pub fn mad_sigma(x: &[f64]) -> f64 {
    let m = median(x);
    let dev: Vec<f64> = x.iter().map(|v| (v - m).abs()).collect();
    MAD_TO_SIGMA * median(&dev)
}

/// Means of consecutive non-overlapping blocks of `block` samples (a trailing partial block is
/// dropped).
pub fn block_means(x: &[f64], block: usize) -> Vec<f64> {
    let block = block.max(1);
    x.chunks_exact(block).map(|c| c.iter().sum::<f64>() / block as f64).collect()
}

/// Kurtosis E[(x − x̄)⁴]/E[(x − x̄)²]² (not the excess: 3 for Gaussian data, 1.8 for uniform);
/// NaN for fewer than two values or zero variance.
pub fn kurtosis(x: &[f64]) -> f64 {
    if x.len() < 2 {
        return f64::NAN;
    }
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let (mut m2, mut m4) = (0.0, 0.0);
    for v in x {
        let d = (v - mean) * (v - mean);
        m2 += d;
        m4 += d * d;
    }
    let (m2, m4) = (m2 / n, m4 / n);
    if m2 > 0.0 { m4 / (m2 * m2) } else { f64::NAN }
}

/// Slope and intercept of the least-squares line through (`t[i]`, `y[i]`); slope 0 when `t` is
/// constant.
pub fn linear_fit(t: &[f64], y: &[f64]) -> (f64, f64) {
    let n = t.len().min(y.len()) as f64;
    if n == 0.0 {
        return (0.0, 0.0);
    }
    let tm = t.iter().sum::<f64>() / n;
    let ym = y.iter().sum::<f64>() / n;
    let (mut sty, mut stt) = (0.0, 0.0);
    for (a, b) in t.iter().zip(y) {
        sty += (a - tm) * (b - ym);
        stt += (a - tm) * (a - tm);
    }
    let slope = if stt > 0.0 { sty / stt } else { 0.0 };
    (slope, ym - slope * tm)
}

/// `x` less its least-squares line ([`linear_fit`] against the sample index).
pub fn detrended(x: &[f64]) -> Vec<f64> {
    let index: Vec<f64> = (0..x.len()).map(|j| j as f64).collect();
    let (slope, offset) = linear_fit(&index, x);
    x.iter().zip(&index).map(|(v, j)| v - offset - slope * j).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moments_and_lines() {
        assert!((kurtosis(&[-1.0, 1.0, -1.0, 1.0]) - 1.0).abs() < 1e-12);
        assert!(kurtosis(&[2.0, 2.0]).is_nan());
        let t = [0.0, 1.0, 2.0, 3.0];
        let (s, c) = linear_fit(&t, &[1.0, 3.0, 5.0, 7.0]);
        assert!((s - 2.0).abs() < 1e-12 && (c - 1.0).abs() < 1e-12);
        assert_eq!(block_means(&[1.0, 3.0, 5.0, 7.0, 9.0], 2), vec![2.0, 6.0]);
        assert!((mad_sigma(&[1.0, 2.0, 3.0, 4.0, 100.0]) - MAD_TO_SIGMA).abs() < 1e-12);
    }
}
