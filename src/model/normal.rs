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

/// The two-sided normal threshold z with P(|Z| > z) = `alpha`: −Φ⁻¹(α/2), from the lower tail,
/// where α/2 is held exactly (1 − α/2 is not: at α = 1e-12 its rounding alone moves z by 3e-6
/// relative).
pub fn two_sided_z(alpha: f64) -> f64 {
    -normal_quantile(0.5 * alpha)
}

/// Upper quantile of χ²(k), k > 0: the value x exceeded with probability `alpha`,
/// Q(k/2, x/2) = `alpha` with Q the regularised upper incomplete gamma function
/// ([`regularized_gamma_q`]). Exact in closed form for k = 1 (x = z², z the two-sided normal
/// threshold) and k = 2 (x = −2 ln α); otherwise Newton's method on ln Q from the Wilson–Hilferty
/// cube-root approximation χ²_k ≈ k(1 − 2/(9k) + z√(2/(9k)))³ (Abramowitz & Stegun 26.4.17),
/// (within 1e-12 relative of scipy's `chi2.isf` for k from 1 to 199 and α from 1e-12 to 0.999;
/// test below). `alpha` near 1 gives the lower quantiles.
pub fn chi2_upper(k: f64, alpha: f64) -> f64 {
    assert!(k > 0.0 && alpha > 0.0 && alpha < 1.0, "chi2_upper needs k > 0 and 0 < alpha < 1, got {k}, {alpha}");
    if k == 1.0 {
        let z = two_sided_z(alpha);
        return z * z;
    }
    if k == 2.0 {
        return -2.0 * alpha.ln();
    }
    let a = 0.5 * k;
    let c = 2.0 / (9.0 * k);
    let mut x = k * (1.0 - c + normal_quantile(1.0 - alpha) * c.sqrt()).max(1e-3).powi(3);
    let target = alpha.ln();
    let ln_norm = libm::lgamma(a) + std::f64::consts::LN_2;
    for _ in 0..NEWTON_STEPS {
        // g(x) = ln Q(a, x/2) − ln α, g'(x) = −f(x)/Q with f the χ²_k density.
        let q = regularized_gamma_q(a, 0.5 * x);
        let ln_density = (a - 1.0) * (0.5 * x).ln() - 0.5 * x - ln_norm;
        let step = (q.ln() - target) * q / ln_density.exp();
        // A step that would take x to zero or below halves x instead.
        let next = if x + step > 0.0 { x + step } else { 0.5 * x };
        if (next - x).abs() <= 1e-15 * x {
            return next;
        }
        x = next;
    }
    x
}

/// Newton steps at most in [`chi2_upper`] (from the Wilson–Hilferty start it needs three to six).
const NEWTON_STEPS: usize = 60;

/// Q(a, x) = Γ(a, x)/Γ(a), the regularised upper incomplete gamma function, a > 0, x ≥ 0: the
/// series of P = 1 − Q for x < a + 1, the continued fraction of Q by the modified Lentz method
/// otherwise (Press et al., *Numerical Recipes*, 3rd ed., §6.2, eqs. 6.2.5 and 6.2.7), each to a
/// relative 1e-16, with `libm`'s ln Γ.
pub fn regularized_gamma_q(a: f64, x: f64) -> f64 {
    assert!(a > 0.0 && x >= 0.0, "regularized_gamma_q needs a > 0 and x >= 0, got {a}, {x}");
    if x == 0.0 {
        return 1.0;
    }
    let prefactor = (a * x.ln() - x - libm::lgamma(a)).exp();
    if x < a + 1.0 {
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..GAMMA_TERMS {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        1.0 - sum * prefactor
    } else {
        let tiny = f64::MIN_POSITIVE / f64::EPSILON;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..GAMMA_TERMS {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        prefactor * h
    }
}

/// Terms of the series or the continued fraction at most (both converge in O(√a) terms).
const GAMMA_TERMS: usize = 10_000;

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
    }

    /// scipy.stats.chi2.isf(alpha, k), printed with repr (tools/goldens/chi_square_goldens.py).
    const CHI2_ISF: [(f64, f64, f64); 21] = [
        (1.0, 1e-12, 50.844_127_911_818_155),
        (1.0, 0.025, 5.023_886_187_314_89),
        (1.0, 0.999, 1.570_797_149_262_492e-6),
        (2.0, 1e-6, 27.631_021_115_928_547),
        (2.0, 0.975, 0.050_635_615_968_579_795),
        (3.0, 1e-12, 58.919_755_683_202_155),
        (3.0, 0.5, 2.365_973_884_375_337_7),
        (3.0, 0.999, 0.024_297_585_815_692_75),
        (4.5, 1e-6, 34.653_059_219_192_25),
        (4.5, 0.975, 0.649_384_599_211_317_5),
        (9.0, 0.001, 27.877_164_871_256_575),
        (9.0, 0.999, 1.151_949_546_223_564_5),
        (19.0, 1e-12, 98.500_098_319_915_7),
        (19.0, 1e-6, 63.677_052_285_677_995),
        (19.0, 0.025, 32.852_326_861_729_715),
        (40.0, 0.5, 39.335_344_846_611_34),
        (40.0, 0.975, 24.433_039_170_807_89),
        (199.0, 1e-12, 373.147_056_933_857_87),
        (199.0, 0.001, 266.385_895_376_262_06),
        (199.0, 0.5, 198.333_731_838_416_84),
        (199.0, 0.999, 142.997_346_557_128_7),
    ];

    #[test]
    fn chi_square_quantiles_match_scipy() {
        for (k, alpha, x) in CHI2_ISF {
            let q = chi2_upper(k, alpha);
            assert!((q / x - 1.0).abs() < 1e-12, "k {k}, alpha {alpha}: {q:e} vs {x:e}");
            // And the tail probability at scipy's value is alpha back (the inverse's consistency).
            let back = regularized_gamma_q(0.5 * k, 0.5 * x);
            assert!((back / alpha - 1.0).abs() < 1e-10, "k {k}: Q = {back:e} vs {alpha:e}");
        }
        // The Wilson–Hilferty start alone is 1 % off at k = 3, α = 1e-12; the refined value is not.
        let wilson_hilferty = 3.0 * (1.0 - 2.0 / 27.0 + normal_quantile(1.0 - 1e-12) * (2.0f64 / 27.0).sqrt()).powi(3);
        assert!((wilson_hilferty / 58.919_755_683_202_155 - 1.0).abs() > 1e-3);
    }
}
