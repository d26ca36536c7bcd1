//! Quantiles of the normal and χ² distributions, for tests that are set by a false-alarm
//! probability instead of a threshold in physical units.

/// The smallest tail probability a configured test may use: 1 − 1e-12 is still exactly
/// representable apart from 1, so the quantiles below stay finite (z ≈ 7.1).
pub const MIN_PROBABILITY: f64 = 1e-12;

/// Φ⁻¹(p), the standard normal quantile, for 0 < p < 1: P. J. Acklam's rational approximation
/// (relative error < 1.15e-9), refined by one Halley step on Φ(x) = erfc(−x/√2)/2 with `libm`'s
/// erfc (the FreeBSD msun port, within an ulp or two), which brings it to about machine precision
/// (within 1e-14 of scipy's `norm.ppf` from 1e-12 to 0.975; test below). The step needs an erfc
/// that accurate: with a single-precision one (Numerical Recipes' `erfcc`, relative error 1.2e-7)
/// it made the quantile thirty times *worse* than Acklam's alone.
pub fn normal_quantile(p: f64) -> f64 {
    assert!(p > 0.0 && p < 1.0, "normal_quantile needs 0 < p < 1, got {p}");
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] =
        [7.784_695_709_041_462e-3, 3.224_671_290_700_398e-1, 2.445_134_137_142_996, 3.754_408_661_907_416];
    let low = 0.024_25;
    let x = if p < low {
        let q = (-2.0 * p.ln()).sqrt();
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    } else if p <= 1.0 - low {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    } else {
        let q = (-2.0 * (1.0 - p).ln()).sqrt();
        -(((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    // Halley refinement: e = Φ(x) − p.
    let e = 0.5 * libm::erfc(-x / std::f64::consts::SQRT_2) - p;
    let u = e * (2.0 * std::f64::consts::PI).sqrt() * (x * x / 2.0).exp();
    x - u / (1.0 + x * u / 2.0)
}

/// The two-sided normal threshold z with P(|Z| > z) = `alpha`.
pub fn two_sided_z(alpha: f64) -> f64 {
    normal_quantile(1.0 - alpha / 2.0)
}

/// Upper quantile of χ²(k): the value exceeded with probability `alpha`, by the Wilson–Hilferty
/// cube-root approximation χ²_k ≈ k(1 − 2/(9k) + z√(2/(9k)))³ (relative error below 1 % for
/// k ≥ 3 at the tails used here; exact for k = 1 through z²).
pub fn chi2_upper(k: f64, alpha: f64) -> f64 {
    if k <= 1.0 {
        let z = two_sided_z(alpha);
        return z * z;
    }
    let z = normal_quantile(1.0 - alpha);
    let c = 2.0 / (9.0 * k);
    k * (1.0 - c + z * c.sqrt()).powi(3)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_match_reference_values() {
        // scipy.stats.norm.ppf and chi2.isf.
        for (p, z) in [
            (0.975, 1.959_963_984_540_054),
            (0.5, 0.0),
            (1e-5, -4.264_890_793_922_825),
            (0.999_995, 4.417_173_413_467_605),
        ] {
            assert!((normal_quantile(p) - z).abs() < 1e-6, "p {p}: {} vs {z}", normal_quantile(p));
        }
        // Machine precision after the Halley step (scipy.stats.norm.ppf, printed with repr); the
        // rational approximation alone is off by up to 1.15e-9 relative, and a refinement with a
        // single-precision erfc by up to 7e-8 (0.3: 6.7e-8).
        for (p, z) in [
            (1e-12, -7.034_483_825_301_131),
            (1e-3, -3.090_232_306_167_813),
            (0.1, -1.281_551_565_544_600_4),
            (0.3, -0.524_400_512_708_040_9),
            (0.5, 0.0),
            (0.975, 1.959_963_984_540_054),
        ] {
            let q = normal_quantile(p);
            assert!((q - z).abs() <= 1e-14 * z.abs().max(1.0), "p {p}: {q:e} vs {z:e}");
        }
        assert!((two_sided_z(1e-5) - 4.417_173_413_467_605).abs() < 1e-6);
        assert!((chi2_upper(1.0, 1e-6) - 23.928_126_976_934_827).abs() < 1e-4);
        // chi2.isf(1e-5, 19) = 57.3725…; Wilson–Hilferty within 1 %.
        assert!((chi2_upper(19.0, 1e-5) / 57.372_504 - 1.0).abs() < 0.01, "{}", chi2_upper(19.0, 1e-5));
    }
}
