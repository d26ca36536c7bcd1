//! The IEEE Std 952-1997 (Annex C) noise model of a gyro's Allan variance, and unit conversions.
//!
//! σ²(τ) = 3Q²/τ² + N²/τ + (2 ln 2/π)·B² + K²·τ/3 + R²·τ²/2
//!
//! (IEEE Std 952-1997, Annex C, eq. C.5, C.11, C.17, C.22, C.25 and Table C.1; El-Sheimy, Hou &
//! Niu 2008, "Analysis and modeling of inertial sensors using Allan variance", IEEE Trans. Instrum.
//! Meas. 57(1), Table I). With the rate in deg/s and τ in s the coefficients come out as:
//!
//! | term | symbol | unit here | customary unit |
//! |---|---|---|---|
//! | angle (rate) quantisation | Q | deg | deg |
//! | angle random walk (ARW) | N | deg/√s | deg/√h = N·60 |
//! | bias instability (flicker) | B | deg/s | deg/h = B·3600 |
//! | rate random walk (RRW) | K | deg/s/√s | deg/h/√h = K·3600·60 |
//! | rate ramp | R | deg/s² | deg/h² = R·3600² |
//!
//! The bias-instability term is the flicker-noise plateau of Annex C, valid for τ well above the
//! inverse of the flicker cut-off frequency.

use std::f64::consts::{LN_2, PI};

/// Number of terms of the model.
pub const TERMS: usize = 5;

/// Names of the terms, in the order used by [`basis`] and [`NoiseModel::squares`].
pub const TERM_NAMES: [&str; TERMS] =
    ["quantisation", "angle random walk", "bias instability", "rate random walk", "rate ramp"];

/// Contribution of each term to σ²(τ) per unit squared coefficient (IEEE Std 952-1997 Annex C):
/// `[3/τ², 1/τ, 2 ln 2/π, τ/3, τ²/2]`, so σ²(τ) = Σ basis(τ)ⱼ·cⱼ with c = (Q², N², B², K², R²).
pub fn basis(tau_s: f64) -> [f64; TERMS] {
    [3.0 / (tau_s * tau_s), 1.0 / tau_s, 2.0 * LN_2 / PI, tau_s / 3.0, tau_s * tau_s / 2.0]
}

/// Coefficients of the IEEE Std 952-1997 Annex C model, in units of a deg/s rate and seconds.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct NoiseModel {
    /// Angle quantisation noise Q, deg.
    pub q: f64,
    /// Angle random walk N, deg/√s.
    pub n: f64,
    /// Bias instability B, deg/s.
    pub b: f64,
    /// Rate random walk K, deg/s/√s.
    pub k: f64,
    /// Rate ramp R, deg/s².
    pub r: f64,
}

impl NoiseModel {
    /// Model from the squared coefficients `[Q², N², B², K², R²]` (negative values clamp to 0).
    pub fn from_squares(c: [f64; TERMS]) -> Self {
        let s = c.map(|v| v.max(0.0).sqrt());
        Self { q: s[0], n: s[1], b: s[2], k: s[3], r: s[4] }
    }

    /// The squared coefficients `[Q², N², B², K², R²]`, the linear unknowns of the fit.
    pub fn squares(&self) -> [f64; TERMS] {
        [self.q, self.n, self.b, self.k, self.r].map(|v| v * v)
    }

    /// Model Allan variance σ²(τ) (deg/s)², IEEE Std 952-1997 Annex C.
    pub fn allan_variance(&self, tau_s: f64) -> f64 {
        basis(tau_s).iter().zip(self.squares()).map(|(f, c)| f * c).sum()
    }

    /// Model Allan deviation σ(τ), deg/s.
    pub fn allan_deviation(&self, tau_s: f64) -> f64 {
        self.allan_variance(tau_s).sqrt()
    }

    /// The same coefficients in the customary units (deg/√h, deg/h, deg/h/√h, deg/h²).
    pub fn customary(&self) -> CustomaryNoise {
        CustomaryNoise {
            q_deg: self.q,
            n_deg_per_sqrt_h: arw_deg_per_sqrt_h(self.n),
            b_deg_per_h: bias_deg_per_h(self.b),
            k_deg_per_h_sqrt_h: rrw_deg_per_h_sqrt_h(self.k),
            r_deg_per_h2: ramp_deg_per_h2(self.r),
        }
    }
}

/// The model coefficients in the units customary in gyro data sheets (IEEE Std 952-1997 Annex C).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct CustomaryNoise {
    /// Angle quantisation Q, deg (unchanged).
    pub q_deg: f64,
    /// Angle random walk N, deg/√h.
    pub n_deg_per_sqrt_h: f64,
    /// Bias instability B, deg/h.
    pub b_deg_per_h: f64,
    /// Rate random walk K, deg/h/√h.
    pub k_deg_per_h_sqrt_h: f64,
    /// Rate ramp R, deg/h².
    pub r_deg_per_h2: f64,
}

/// Angle random walk from deg/√s to deg/√h: N·60 (√3600 s in √h).
pub fn arw_deg_per_sqrt_h(n_deg_per_sqrt_s: f64) -> f64 {
    n_deg_per_sqrt_s * 60.0
}

/// Bias instability from deg/s to deg/h: B·3600.
pub fn bias_deg_per_h(b_deg_per_s: f64) -> f64 {
    b_deg_per_s * 3600.0
}

/// Rate random walk from deg/s/√s to deg/h/√h: K·3600·60.
pub fn rrw_deg_per_h_sqrt_h(k_deg_per_s_sqrt_s: f64) -> f64 {
    k_deg_per_s_sqrt_s * 3600.0 * 60.0
}

/// Rate ramp from deg/s² to deg/h²: R·3600².
pub fn ramp_deg_per_h2(r_deg_per_s2: f64) -> f64 {
    r_deg_per_s2 * 3600.0 * 3600.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_terms_follow_their_slopes() {
        let white = NoiseModel { n: 0.01, ..NoiseModel::default() };
        assert!((white.allan_deviation(4.0) - 0.005).abs() < 1e-15);
        let ramp = NoiseModel { r: 2e-4, ..NoiseModel::default() };
        assert!((ramp.allan_deviation(10.0) - 2e-3 / 2f64.sqrt()).abs() < 1e-15);
        let bias = NoiseModel { b: 1.0, ..NoiseModel::default() };
        assert!((bias.allan_deviation(123.0) - 0.664_282_4).abs() < 1e-6);
        let q = NoiseModel { q: 1.0, ..NoiseModel::default() };
        assert!((q.allan_deviation(1.0) - 3f64.sqrt()).abs() < 1e-15);
        let k = NoiseModel { k: 1.0, ..NoiseModel::default() };
        assert!((k.allan_deviation(3.0) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn customary_units() {
        let m = NoiseModel { q: 1e-3, n: 0.01, b: 0.001, k: 1e-5, r: 1e-7 };
        let c = m.customary();
        assert_eq!(c.q_deg, 1e-3);
        assert!((c.n_deg_per_sqrt_h - 0.6).abs() < 1e-12);
        assert!((c.b_deg_per_h - 3.6).abs() < 1e-12);
        assert!((c.k_deg_per_h_sqrt_h - 2.16).abs() < 1e-12);
        assert!((c.r_deg_per_h2 - 1.296).abs() < 1e-12);
        assert_eq!(NoiseModel::from_squares(m.squares()).n, m.n);
    }
}
