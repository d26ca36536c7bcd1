//! Complex FFT of power-of-two lengths, the transform behind the Welch power spectral density
//! ([`crate::diag::psd`]) and the periodograms of the sim-to-real diagnosis.
//!
//! X\[k] = Σ_{j=0}^{n−1} x\[j]·e^(−2πi·jk/n) (the sign convention of `numpy.fft.fft`). The
//! transform itself is `rustfft`'s planned one (radix-4 and split-radix butterflies with SIMD
//! kernels where the processor has them): the diagnosis transforms every ensemble member's parts
//! several times, and the textbook radix-2 loop this module carried before (Cooley & Tukey 1965;
//! Press et al., *Numerical Recipes*, 3rd ed., §12.2) took an eighth of its run time. The tests
//! below check it against the definition, as they checked that loop.

use std::f64::consts::TAU;
use std::fmt;
use std::sync::Arc;

/// A complex number of the transforms' buffers (`rustfft`'s, i.e. `num_complex`'s).
pub use rustfft::num_complex::Complex64;

/// A planned FFT of one power-of-two length.
#[derive(Clone)]
pub struct Fft {
    n: usize,
    plan: Arc<dyn rustfft::Fft<f64>>,
}

impl fmt::Debug for Fft {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Fft").field("n", &self.n).finish_non_exhaustive()
    }
}

impl Fft {
    /// Plans a transform of length `n`; `None` unless `n` is a power of two (n = 1 included).
    pub fn new(n: usize) -> Option<Self> {
        if !n.is_power_of_two() {
            return None;
        }
        let plan = rustfft::FftPlanner::new().plan_fft_forward(n);
        Some(Self { n, plan })
    }

    /// The transform length.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Whether the length is zero (never: the smallest plan has length 1).
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Transforms `buffer` in place.
    ///
    /// # Panics
    /// If `buffer` has another length than [`len`](Self::len) (a programming error, not a data
    /// error).
    pub fn process(&self, buffer: &mut [Complex64]) {
        assert!(buffer.len() == self.n, "FFT buffer must have the planned length");
        self.plan.process(buffer);
    }

    /// The transform of the real series `x` zero-padded to the planned length.
    ///
    /// # Panics
    /// If `x` is longer than the plan (a programming error, not a data error).
    pub fn transform_real(&self, x: &[f64]) -> Vec<Complex64> {
        assert!(x.len() <= self.n, "series longer than the planned FFT");
        let mut z = vec![Complex64::new(0.0, 0.0); self.n];
        for (z, &v) in z.iter_mut().zip(x) {
            z.re = v;
        }
        self.process(&mut z);
        z
    }
}

/// A planned periodogram of real series: |X\[k]|² for k = 0..=n/2 of a series zero-padded to a
/// power-of-two length n ≥ 2, by one complex FFT of n/2 points on the even and odd samples packed
/// as real and imaginary parts, then the split step X\[k] = E\[k] + e^(−2πi·k/n)·O\[k] with
/// E\[k] = (Z\[k] + Z̄\[n/2−k])/2 and O\[k] = (Z\[k] − Z̄\[n/2−k])/(2i) (Press et al., *Numerical
/// Recipes*, 3rd ed., §12.3): half the work of the complex transform of the same length.
#[derive(Debug, Clone)]
pub struct RealPeriodogram {
    half: Fft,
    /// e^(−2πi·k/n) for k ≤ n/2, as (cos, sin).
    twiddles: Vec<(f64, f64)>,
}

impl RealPeriodogram {
    /// Plans the periodogram of length `n`; `None` unless `n` is a power of two of at least 2.
    pub fn new(n: usize) -> Option<Self> {
        if n < 2 {
            return None;
        }
        let half = Fft::new(n / 2).filter(|_| n.is_power_of_two())?;
        let twiddles = (0..=n / 2)
            .map(|k| {
                let angle = -TAU * k as f64 / n as f64;
                (angle.cos(), angle.sin())
            })
            .collect();
        Some(Self { half, twiddles })
    }

    /// The padded length n.
    pub fn len(&self) -> usize {
        2 * self.half.len()
    }

    /// Whether the length is zero (never: the smallest plan has length 2).
    pub fn is_empty(&self) -> bool {
        false
    }

    /// |X\[k]|² for k = 0..=n/2 of `x` zero-padded to n.
    ///
    /// # Panics
    /// If `x` is longer than n (a programming error, not a data error).
    pub fn power(&self, x: &[f64]) -> Vec<f64> {
        let m = self.half.len();
        assert!(x.len() <= 2 * m, "series longer than the planned periodogram");
        let mut z = vec![Complex64::new(0.0, 0.0); m];
        for (zj, pair) in z.iter_mut().zip(x.chunks(2)) {
            *zj = Complex64::new(pair[0], pair.get(1).copied().unwrap_or(0.0));
        }
        self.half.process(&mut z);
        (0..=m)
            .map(|k| {
                let (zr, zi) = (z[k % m].re, z[k % m].im);
                let (cr, ci) = (z[(m - k) % m].re, -z[(m - k) % m].im);
                let (er, ei) = (0.5 * (zr + cr), 0.5 * (zi + ci));
                // (Z − Z̄')/(2i) = (Im, −Re)/2 of the difference.
                let (or, oi) = (0.5 * (zi - ci), -0.5 * (zr - cr));
                let (wr, wi) = self.twiddles[k];
                let (xr, xi) = (er + wr * or - wi * oi, ei + wr * oi + wi * or);
                xr * xr + xi * xi
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The DFT by its definition, O(n²): the independent reference.
    fn naive_dft(x: &[f64]) -> Vec<(f64, f64)> {
        let n = x.len();
        (0..n)
            .map(|k| {
                x.iter().enumerate().fold((0.0, 0.0), |(r, i), (j, &v)| {
                    let angle = -TAU * (j * k % n) as f64 / n as f64;
                    (r + v * angle.cos(), i + v * angle.sin())
                })
            })
            .collect()
    }

    #[test]
    fn equals_the_definition() {
        for n in [1usize, 2, 4, 8, 64, 256] {
            let x: Vec<f64> = (0..n).map(|j| ((j * 7919) % 31) as f64 / 7.0 - 2.0 + (j as f64 * 0.3).sin()).collect();
            let fft = Fft::new(n).unwrap();
            let z = fft.transform_real(&x);
            for (k, (r, i)) in naive_dft(&x).into_iter().enumerate() {
                assert!((z[k].re - r).abs() < 1e-9 && (z[k].im - i).abs() < 1e-9, "n {n} bin {k}");
            }
        }
    }

    #[test]
    fn parseval_holds() {
        let n = 1024;
        let x: Vec<f64> = (0..n).map(|j| (j as f64 * 0.017).cos() + ((j * 31) % 17) as f64 * 0.1).collect();
        let fft = Fft::new(n).unwrap();
        let z = fft.transform_real(&x);
        let time: f64 = x.iter().map(|v| v * v).sum();
        let freq: f64 = z.iter().map(|z| z.re * z.re + z.im * z.im).sum::<f64>() / n as f64;
        assert!((time - freq).abs() < 1e-9 * time);
    }

    /// The packed real periodogram equals the complex transform's |X[k]|², zero padding
    /// included, for even and odd series lengths.
    #[test]
    fn the_real_periodogram_equals_the_complex_transform() {
        for (n, len) in [(2usize, 2usize), (4, 3), (16, 16), (64, 41), (1024, 1000)] {
            let x: Vec<f64> = (0..len).map(|j| (j as f64 * 0.37).sin() + ((j * 13) % 7) as f64 * 0.2).collect();
            let fft = Fft::new(n).unwrap();
            let z = fft.transform_real(&x);
            let power = RealPeriodogram::new(n).unwrap().power(&x);
            assert_eq!(power.len(), n / 2 + 1);
            let scale = z.iter().map(|z| z.re * z.re + z.im * z.im).fold(1.0, f64::max);
            for (k, p) in power.iter().enumerate() {
                let want = z[k].re * z[k].re + z[k].im * z[k].im;
                assert!((p - want).abs() < 1e-10 * scale, "n {n} bin {k}: {p} against {want}");
            }
        }
        assert!(RealPeriodogram::new(1).is_none() && RealPeriodogram::new(12).is_none());
    }

    #[test]
    fn refuses_other_lengths() {
        assert!(Fft::new(0).is_none());
        assert!(Fft::new(12).is_none());
    }
}
