//! Single- and multi-level discrete wavelet transforms with PyWavelets' `symmetric` boundary mode.
//!
//! Forward step (`pywt.dwt`, C routine `downsampling_convolution`): with the signal extended by
//! half-sample symmetric reflection (`x[-1] = x[0]`, `x[n] = x[n-1]`, repeated as often as the
//! filter needs), `c[o] = Σ_j h[j] · x[2o + 1 − j]` for `o < (n + F − 1) / 2`.
//!
//! Inverse step (`pywt.idwt`, C routine `upsampling_convolution_valid_sf`): for
//! `i = F/2 − 1 … len − 1`, `k = i − (F/2 − 1)`:
//! `y[2k] = Σ_{j<F/2} g[2j]·c[i − j]` and `y[2k+1] = Σ_{j<F/2} g[2j+1]·c[i − j]`, summed over the
//! approximation (g = rec_lo) and detail (g = rec_hi) branches; `y` has `2·len − F + 2` samples.

use super::filters::Wavelet;

/// Length of each coefficient array of a single-level DWT of `n` samples with `f` taps
/// (`pywt.dwt_coeff_len(n, f, 'symmetric')`).
pub fn dwt_len(n: usize, f: usize) -> usize {
    (n + f - 1) / 2
}

/// Length of the signal an inverse step rebuilds from `n_coeffs` coefficients with `f` taps
/// (`2·n_coeffs − f + 2`); zero when there are too few coefficients.
pub fn idwt_len(n_coeffs: usize, f: usize) -> usize {
    (2 * n_coeffs + 2).saturating_sub(f)
}

/// Deepest useful decomposition level for `n` samples and `f` taps (`pywt.dwt_max_level`):
/// `⌊log2(n / (f − 1))⌋`, or 0 when `n < f − 1`.
pub fn max_level(n: usize, f: usize) -> usize {
    if f < 2 || n < f - 1 {
        return 0;
    }
    (n / (f - 1)).ilog2() as usize
}

/// Index into `0..n` of position `i` of the half-sample symmetric extension (period `2n`).
#[inline]
fn reflect(i: isize, n: usize) -> usize {
    let period = 2 * n as isize;
    let r = i.rem_euclid(period) as usize;
    if r < n { r } else { 2 * n - 1 - r }
}

/// Calls `visit(j, x[2o + 1 − j])` for every tap `j < f` of output position `o`, reflecting
/// indices outside the signal (the convolution of [`dwt_point`]).
#[inline(always)]
fn for_each_tap(x: &[f64], f: usize, o: usize, mut visit: impl FnMut(usize, f64)) {
    let n = x.len();
    let i = 2 * o + 1;
    if i >= f - 1 && i < n {
        // Interior: every tap lands inside the signal.
        let window = &x[i + 1 - f..=i];
        for j in 0..f {
            visit(j, window[f - 1 - j]);
        }
    } else {
        for j in 0..f {
            visit(j, x[reflect(i as isize - j as isize, n)]);
        }
    }
}

/// Forward coefficients `(cA[o], cD[o])` of one output position `o` (the body of [`dwt_into`]).
#[inline]
pub(crate) fn dwt_point(x: &[f64], lo: &[f64], hi: &[f64], o: usize) -> (f64, f64) {
    let (mut a, mut d) = (0.0, 0.0);
    for_each_tap(x, lo.len(), o, |j, v| {
        a += lo[j] * v;
        d += hi[j] * v;
    });
    (a, d)
}

/// The detail coefficient `cD[o]` alone, bit-identical to [`dwt_point`]'s second value.
#[inline]
pub(crate) fn dwt_detail_point(x: &[f64], hi: &[f64], o: usize) -> f64 {
    let mut d = 0.0;
    for_each_tap(x, hi.len(), o, |j, v| d += hi[j] * v);
    d
}

/// The interior detail `Σ_j hi[j]·x[last − j]` of the `hi.len()` samples ending at `x[last]`
/// (needs `last ≥ hi.len() − 1`): bit-identical to the detail [`dwt_into`] computes at any position whose
/// taps end on that sample, so a streaming caller can compute it once per sample and reuse it
/// while the window slides.
#[inline]
pub fn interior_detail(x: &[f64], hi: &[f64], last: usize) -> f64 {
    let f = hi.len();
    let window = &x[last + 1 - f..=last];
    let mut d = 0.0;
    for j in 0..f {
        d += hi[j] * window[f - 1 - j];
    }
    d
}

/// One forward step: fills `ca` (low-pass) and `cd` (high-pass), each `dwt_len(x.len(), F)` long.
pub fn dwt_into(x: &[f64], wavelet: &Wavelet, ca: &mut [f64], cd: &mut [f64]) {
    let (lo, hi) = (wavelet.dec_lo(), wavelet.dec_hi());
    let len = dwt_len(x.len(), lo.len());
    assert!(!x.is_empty(), "dwt of an empty signal");
    assert!(ca.len() == len && cd.len() == len, "coefficient buffers must be dwt_len long");
    for o in 0..len {
        (ca[o], cd[o]) = dwt_point(x, lo, hi, o);
    }
}

/// One reconstructed sample `y[out]` of the inverse step (the body of [`idwt_into`]); `ca` and
/// `cd` need only be valid at indices `out/2 … out/2 + F/2 − 1`.
#[inline]
pub(crate) fn idwt_point(ca: &[f64], cd: &[f64], lo: &[f64], hi: &[f64], out: usize) -> f64 {
    let half = lo.len() / 2;
    let (k, parity) = (out / 2, out % 2);
    let i = k + half - 1;
    let mut sum = 0.0;
    for j in 0..half {
        sum += lo[2 * j + parity] * ca[i - j] + hi[2 * j + parity] * cd[i - j];
    }
    sum
}

/// One inverse step: rebuilds `out` (`idwt_len(ca.len(), F)` long) from equal-length `ca`, `cd`.
pub fn idwt_into(ca: &[f64], cd: &[f64], wavelet: &Wavelet, out: &mut [f64]) {
    let (lo, hi) = (wavelet.rec_lo(), wavelet.rec_hi());
    assert_eq!(ca.len(), cd.len(), "approximation and detail must have equal length");
    assert_eq!(out.len(), idwt_len(ca.len(), lo.len()), "output buffer must be idwt_len long");
    for (o, y) in out.iter_mut().enumerate() {
        *y = idwt_point(ca, cd, lo, hi, o);
    }
}

/// Multilevel decomposition, `pywt.wavedec(x, wavelet, mode='symmetric', level=level)`:
/// returns `[cA_level, cD_level, …, cD_1]`.
pub fn wavedec(x: &[f64], wavelet: &Wavelet, level: usize) -> Vec<Vec<f64>> {
    let f = wavelet.filter_len();
    let mut details = Vec::with_capacity(level);
    let mut approx = x.to_vec();
    for _ in 0..level {
        let len = dwt_len(approx.len(), f);
        let (mut ca, mut cd) = (vec![0.0; len], vec![0.0; len]);
        dwt_into(&approx, wavelet, &mut ca, &mut cd);
        details.push(cd);
        approx = ca;
    }
    let mut coeffs = Vec::with_capacity(level + 1);
    coeffs.push(approx);
    coeffs.extend(details.into_iter().rev());
    coeffs
}

/// Multilevel reconstruction, `pywt.waverec(coeffs, wavelet, mode='symmetric')`, from
/// `[cA_level, cD_level, …, cD_1]`. Like PyWavelets, an approximation one longer than the next
/// detail is trimmed by its last sample; the result may be one sample longer than the original
/// signal (odd lengths), exactly as PyWavelets returns it.
pub fn waverec(coeffs: &[Vec<f64>], wavelet: &Wavelet) -> Vec<f64> {
    let f = wavelet.filter_len();
    let (first, details) = coeffs.split_first().expect("at least the approximation");
    let mut approx = first.clone();
    for cd in details {
        if approx.len() == cd.len() + 1 {
            approx.pop();
        }
        let mut out = vec![0.0; idwt_len(cd.len(), f)];
        idwt_into(&approx, cd, wavelet, &mut out);
        approx = out;
    }
    approx
}

#[cfg(test)]
mod tests {
    use super::*;

    fn signal(n: usize) -> Vec<f64> {
        (0..n).map(|i| ((i * 7919) % 113) as f64 * 0.01 + (i as f64 * 0.05).sin()).collect()
    }

    #[test]
    fn reflection_repeats_with_period_two_n() {
        let n = 3;
        let got: Vec<usize> = (-7..10).map(|i| reflect(i, n)).collect();
        // … x2 x1 x0 | x0 x1 x2 | x2 x1 x0 | x0 …
        assert_eq!(got, vec![0, 0, 1, 2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0, 1, 2, 2]);
    }

    #[test]
    fn perfect_reconstruction_for_every_length_and_level() {
        for order in [1, 2, 4, 7] {
            let w = Wavelet::daubechies(order).unwrap();
            for n in [1, 2, 5, 8, 13, 64, 101, 1000] {
                let x = signal(n);
                for level in 1..=4 {
                    let rec = waverec(&wavedec(&x, &w, level), &w);
                    assert!(rec.len() == n || rec.len() == n + 1);
                    let err = x.iter().zip(&rec).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                    assert!(err < 1e-10, "db{order} n={n} level={level}: error {err}");
                }
            }
        }
    }

    #[test]
    fn orthogonal_transform_keeps_energy_away_from_the_edges() {
        // Haar on an even length has no boundary coefficients beyond the signal: Parseval holds.
        let w = Wavelet::daubechies(1).unwrap();
        let x = signal(64);
        let (mut a, mut d) = (vec![0.0; 32], vec![0.0; 32]);
        dwt_into(&x, &w, &mut a, &mut d);
        let ex: f64 = x.iter().map(|v| v * v).sum();
        let ec: f64 = a.iter().chain(&d).map(|v| v * v).sum();
        assert!((ex - ec).abs() < 1e-9 * ex);
    }

    #[test]
    fn levels_match_pywavelets_rule() {
        assert_eq!(max_level(6, 8), 0);
        assert_eq!(max_level(7, 8), 0);
        assert_eq!(max_level(14, 8), 1);
        assert_eq!(max_level(56, 8), 3);
        assert_eq!(max_level(55, 8), 2);
        assert_eq!(dwt_len(100, 8), 53);
        assert_eq!(idwt_len(53, 8), 100);
    }
}
