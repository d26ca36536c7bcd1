//! Theoretical Allan variance of the simulated terms, exact for the sampled processes the
//! generator produces (averaging m samples at rate fs, τ = m/fs). Used to check the generator and
//! to tabulate what a preset should look like; terms without a stationary Allan variance (warm-up,
//! temperature, jumps, spikes) are left out.

use super::config::{AxisConfig, BiasInstability, QuantizationMode};
use super::terms::{flicker_poles, gauss_markov_averaged};

/// Allan variance of a first-order Gauss–Markov process of stationary variance `var` and
/// correlation time `corr_s` as the generator samples it (every `dt` s, averaged over `m` samples):
/// the continuous-time formula for interval means ([`gauss_markov_averaged`]), the AR(1) one for
/// point samples.
pub fn gauss_markov_avar(var: f64, corr_s: f64, dt: f64, m: usize) -> f64 {
    if gauss_markov_averaged(corr_s, dt) {
        gauss_markov_avar_continuous(var, corr_s, m as f64 * dt)
    } else {
        gauss_markov_avar_sampled(var, corr_s, dt, m)
    }
}

/// Allan variance of a continuous first-order Gauss–Markov process:
/// σ²(τ) = var·(T/τ)²·(2τ/T − 3 + 4e^(−τ/T) − e^(−2τ/T)) (series for τ ≪ T).
pub fn gauss_markov_avar_continuous(var: f64, corr_s: f64, tau: f64) -> f64 {
    let x = tau / corr_s;
    let bracket = if x < 1e-3 {
        // 2x − 3 + 4e^(−x) − e^(−2x) = (2/3)x³ − (1/2)x⁴ + (7/30)x⁵ − …
        x * x * x * (2.0 / 3.0 - 0.5 * x + 7.0 / 30.0 * x * x)
    } else {
        2.0 * x - 3.0 + 4.0 * (-x).exp() - (-2.0 * x).exp()
    };
    (var * bracket / (x * x)).max(0.0)
}

/// Allan variance of a point-sampled Gauss–Markov (AR(1)) sequence, averaged over `m` samples:
/// σ²(m) = (4·S(m) − S(2m)) / (2m²), S(m) the variance of a sum of m consecutive samples.
pub fn gauss_markov_avar_sampled(var: f64, corr_s: f64, dt: f64, m: usize) -> f64 {
    let m_f = m as f64;
    let a = -(-dt / corr_s).exp_m1(); // 1 − φ
    let b = -(-m_f * dt / corr_s).exp_m1(); // 1 − φ^m
    let phi = 1.0 - a;
    let bracket = 2.0 * m_f + phi * (4.0 * m_f * a - 4.0 * b - 2.0 * b * b) / (a * a);
    (var * bracket / (2.0 * m_f * m_f)).max(0.0)
}

/// Allan variance of a sampled random walk with per-sample step variance `step_var`:
/// step_var·(2m² + 1)/(6m), which tends to K²τ/3.
pub fn random_walk_avar(step_var: f64, m: usize) -> f64 {
    let m_f = m as f64;
    step_var * (2.0 * m_f * m_f + 1.0) / (6.0 * m_f)
}

/// Theoretical Allan variance, (deg/s)², of one axis model at `rate_hz` for an average of `m`
/// samples (τ = m / rate_hz): quantisation, white noise, bias instability, rate random walk, ramp
/// and sinusoids (continuous-time formula for the latter).
pub fn axis_avar(axis: &AxisConfig, rate_hz: f64, m: usize) -> f64 {
    assert!(m >= 1, "m ≥ 1");
    let dt = 1.0 / rate_hz;
    let m_f = m as f64;
    let tau = m_f * dt;
    let mut avar = 0.0;
    // White: per-sample variance N²·fs averaged over m samples.
    let n = axis.arw_deg_rt_s();
    avar += n * n * rate_hz / m_f;
    if let Some(q) = &axis.quantization {
        avar += match q.mode {
            // Rounding error carried: rate error = (c[k−1] − c[k])·Δ with c uniform, σ² = Δ²/(4m²) = 3Q²/τ².
            QuantizationMode::Angle => q.step_dps * q.step_dps / (4.0 * m_f * m_f),
            // Independent rounding: white of variance Δ²/12 (assumes the input dithers the quantiser).
            QuantizationMode::Rate => q.step_dps * q.step_dps / 12.0 / m_f,
        };
    }
    match &axis.bias_instability {
        Some(BiasInstability::GaussMarkov { b_deg_h, correlation_time_s }) => {
            let sigma = super::terms::gauss_markov_sigma(b_deg_h / 3600.0);
            avar += gauss_markov_avar(sigma * sigma, *correlation_time_s, dt, m);
        }
        Some(BiasInstability::Flicker { b_deg_h, floor_from_s, floor_to_s }) => {
            for (var, corr) in flicker_poles(b_deg_h / 3600.0, *floor_from_s, *floor_to_s, dt) {
                avar += gauss_markov_avar(var, corr, dt, m);
            }
        }
        None => {}
    }
    let k = axis.rrw_dps_rt_s();
    avar += random_walk_avar(k * k * dt, m);
    let r = axis.ramp_dps2();
    avar += r * r * tau * tau / 2.0;
    for s in axis.sinusoids.iter().flatten() {
        let x = std::f64::consts::PI * s.frequency_hz * tau;
        if x > 0.0 {
            avar += s.amplitude_dps * s.amplitude_dps * x.sin().powi(4) / (x * x);
        }
    }
    avar
}

/// Theoretical Allan deviation, deg/s (square root of [`axis_avar`]).
pub fn axis_adev(axis: &AxisConfig, rate_hz: f64, m: usize) -> f64 {
    axis_avar(axis, rate_hz, m).sqrt()
}
