//! The error terms of one axis as small state machines. Each `add_to` adds the term's next
//! `out.len()` samples to `out`, so a block is built term by term; the state carries over between
//! calls, and the result does not depend on how a run is cut into blocks.

use std::f64::consts::{LN_10, PI, TAU};

use super::rng::Stream;

/// √(2 ln 2 / π) ≈ 0.6643: Allan floor of flicker noise per unit B (IEEE Std 952).
pub const FLICKER_FLOOR: f64 = 0.664_282_470_267_960_1;
/// Peak Allan deviation of a first-order Gauss–Markov process per unit stationary σ (≈ 0.6174,
/// at τ ≈ 1.8926·T; maximum of √((2x − 3 + 4e^(−x) − e^(−2x))/x²)).
pub const GAUSS_MARKOV_PEAK: f64 = 0.617_364_283_144_440_7;
/// Correlation times of the flicker bank per decade.
pub const FLICKER_POLES_PER_DECADE: f64 = 2.0;
/// The flicker bank spans correlation times from `floor_from_s / FLICKER_LOW_MARGIN` …
pub const FLICKER_LOW_MARGIN: f64 = 30.0;
/// … to `floor_to_s · FLICKER_HIGH_MARGIN`.
pub const FLICKER_HIGH_MARGIN: f64 = 15.0;

/// Stationary σ of a Gauss–Markov process whose Allan deviation peaks at 0.664·`b` (same unit as `b`).
pub fn gauss_markov_sigma(b: f64) -> f64 {
    FLICKER_FLOOR * b / GAUSS_MARKOV_PEAK
}

/// (variance, correlation time in s) of the Gauss–Markov processes whose sum approximates flicker
/// noise of bias instability `b` (deg/s) with a flat Allan floor from `floor_from_s` to
/// `floor_to_s`, sampled every `dt` s.
///
/// Correlation times are log-spaced, at least [`FLICKER_POLES_PER_DECADE`] per decade, from
/// `floor_from_s / 30` to `floor_to_s · 15`. A sum of Lorentzians with weight w per unit of ln T has
/// one-sided PSD w/f; flicker with Allan floor √(2 ln 2/π)·B has one-sided PSD B²/(π f), so each
/// process gets variance B²·Δ/π, Δ the spacing in ln T. Processes with T below dt/1000 are left out
/// (averaged over a sample they are white noise of variance 2σ²T/dt, together under 1 % of the floor).
pub fn flicker_poles(b: f64, floor_from_s: f64, floor_to_s: f64, dt: f64) -> Vec<(f64, f64)> {
    let lo = floor_from_s / FLICKER_LOW_MARGIN;
    let hi = floor_to_s * FLICKER_HIGH_MARGIN;
    let span = (hi / lo).ln();
    let count = (span / LN_10 * FLICKER_POLES_PER_DECADE).ceil() as usize + 1;
    let step = span / (count - 1) as f64;
    let var = b * b * step / PI;
    (0..count)
        .map(|i| lo * (step * i as f64).exp())
        .filter(|&corr| corr >= dt / 1000.0)
        .map(|corr| (var, corr))
        .collect()
}

/// Gauss–Markov processes with a correlation time below this many sample intervals are output as
/// their mean over each sample interval (as a sensor that averages, or a decimation filter, does)
/// rather than as point samples; slower ones are point-sampled (the two differ by O(dt/T)).
pub const AVERAGE_BELOW_SAMPLES: f64 = 100.0;

/// Whether a Gauss–Markov process of correlation time `corr_s` sampled every `dt` s is output as
/// interval means (see [`AVERAGE_BELOW_SAMPLES`]).
pub fn gauss_markov_averaged(corr_s: f64, dt: f64) -> bool {
    corr_s < AVERAGE_BELOW_SAMPLES * dt
}

/// First-order Gauss–Markov process dx = −x/T·dt + √(2σ²/T)·dW, exactly discretised and started
/// from its stationary distribution.
///
/// Point-sampled: `x[k+1] = φ·x[k] + σ·√(1 − φ²)·w[k]`, φ = e^(−dt/T). Interval means (for T below
/// [`AVERAGE_BELOW_SAMPLES`] samples): the output of sample k is (1/dt)∫ x over the interval, drawn
/// jointly with the next state from their exact bivariate normal law given `x[k]` (two normal
/// deviates per sample), so the Allan variance at τ = m·dt is the continuous-time one exactly.
#[derive(Debug, Clone)]
pub struct GaussMarkov {
    phi: f64,
    drive: f64,
    /// Interval means: (weight of the state, weight of w1, weight of w2) in the output.
    mean: Option<(f64, f64, f64)>,
    x: f64,
    stream: Stream,
}

impl GaussMarkov {
    /// A process of stationary standard deviation `sigma` and correlation time `corr_s`, sampled
    /// every `dt` s, drawing from `stream`.
    pub fn new(sigma: f64, corr_s: f64, dt: f64, mut stream: Stream) -> Self {
        let phi = (-dt / corr_s).exp();
        let one_minus_phi = -(-dt / corr_s).exp_m1();
        let one_minus_phi2 = -(-2.0 * dt / corr_s).exp_m1();
        let drive = sigma * one_minus_phi2.sqrt();
        let mean = gauss_markov_averaged(corr_s, dt).then(|| {
            let var = sigma * sigma;
            let t = corr_s;
            let v11 = var * one_minus_phi2;
            let v22 = 2.0 * var * t / (dt * dt) * (dt - 2.0 * t * one_minus_phi + 0.5 * t * one_minus_phi2);
            let v12 = var * t / dt * one_minus_phi * one_minus_phi;
            let a = if v11 > 0.0 { v12 / v11.sqrt() } else { 0.0 };
            let b = (v22 - a * a).max(0.0).sqrt();
            (t * one_minus_phi / dt, a, b)
        });
        let x = sigma * stream.normal();
        Self { phi, drive, mean, x, stream }
    }

    /// Adds the next `out.len()` samples.
    #[inline]
    pub fn add_to(&mut self, out: &mut [f64]) {
        let (phi, drive) = (self.phi, self.drive);
        let mut x = self.x;
        match self.mean {
            None => {
                for v in out {
                    *v += x;
                    x = phi * x + drive * self.stream.normal();
                }
            }
            Some((c, a, b)) => {
                for v in out {
                    let w1 = self.stream.normal();
                    let w2 = self.stream.normal();
                    *v += c * x + a * w1 + b * w2;
                    x = phi * x + drive * w1;
                }
            }
        }
        self.x = x;
    }
}

/// Random walk started at 0: `b[k+1] = b[k] + step·w[k]`.
#[derive(Debug, Clone)]
pub struct RandomWalk {
    step: f64,
    b: f64,
    stream: Stream,
}

impl RandomWalk {
    /// A walk with per-sample step standard deviation `step`.
    pub fn new(step: f64, stream: Stream) -> Self {
        Self { step, b: 0.0, stream }
    }

    /// Adds the next `out.len()` samples.
    #[inline]
    pub fn add_to(&mut self, out: &mut [f64]) {
        let mut b = self.b;
        for v in out {
            *v += b;
            b += self.step * self.stream.normal();
        }
        self.b = b;
    }
}

/// White Gaussian noise of a given per-sample standard deviation.
#[derive(Debug, Clone)]
pub struct White {
    sigma: f64,
    stream: Stream,
}

impl White {
    /// White noise of per-sample standard deviation `sigma`.
    pub fn new(sigma: f64, stream: Stream) -> Self {
        Self { sigma, stream }
    }

    /// Writes (not adds) the next `out.len()` samples.
    #[inline]
    pub fn fill(&mut self, out: &mut [f64]) {
        for v in out {
            *v = self.sigma * self.stream.normal();
        }
    }
}

/// Events of a Poisson process in continuous time, reported per sample.
#[derive(Debug, Clone)]
struct Poisson {
    mean_gap_s: f64,
    next_s: f64,
}

impl Poisson {
    fn new(rate_per_s: f64, stream: &mut Stream) -> Self {
        let mean_gap_s = if rate_per_s > 0.0 { 1.0 / rate_per_s } else { f64::INFINITY };
        Self { mean_gap_s, next_s: mean_gap_s * stream.exponential() }
    }

    /// Whether an event falls at or before `t_s`; consumes it.
    #[inline]
    fn take(&mut self, t_s: f64, stream: &mut Stream) -> bool {
        if self.next_s <= t_s {
            self.next_s += self.mean_gap_s * stream.exponential();
            true
        } else {
            false
        }
    }
}

/// Bias jumps: at each event of a Poisson process the bias steps by a normal amount and stays.
#[derive(Debug, Clone)]
pub struct Jumps {
    size: f64,
    level: f64,
    events: Poisson,
    stream: Stream,
}

impl Jumps {
    /// Jumps at `rate_per_s` events per second, each N(0, `size`²).
    pub fn new(rate_per_s: f64, size: f64, mut stream: Stream) -> Self {
        let events = Poisson::new(rate_per_s, &mut stream);
        Self { size, level: 0.0, events, stream }
    }

    /// Adds the samples at times `t_s` (one per sample of `out`).
    #[inline]
    pub fn add_to(&mut self, out: &mut [f64], t_s: &[f64]) {
        for (v, &t) in out.iter_mut().zip(t_s) {
            while self.events.take(t, &mut self.stream) {
                self.level += self.size * self.stream.normal();
            }
            *v += self.level;
        }
    }
}

/// Spikes: at each event of a Poisson process one sample gets ±size.
#[derive(Debug, Clone)]
pub struct Spikes {
    size: f64,
    events: Poisson,
    stream: Stream,
}

impl Spikes {
    /// Spikes at `rate_per_s` events per second, each ±`size`.
    pub fn new(rate_per_s: f64, size: f64, mut stream: Stream) -> Self {
        let events = Poisson::new(rate_per_s, &mut stream);
        Self { size, events, stream }
    }

    /// Adds the samples at times `t_s` (one per sample of `out`).
    #[inline]
    pub fn add_to(&mut self, out: &mut [f64], t_s: &[f64]) {
        for (v, &t) in out.iter_mut().zip(t_s) {
            while self.events.take(t, &mut self.stream) {
                *v += self.size * self.stream.sign();
            }
        }
    }
}

/// Quantiser to multiples of `step`, with or without carrying the rounding error.
#[derive(Debug, Clone)]
pub struct Quantiser {
    step: f64,
    inv: f64,
    /// When 1/step is a whole number of LSB per deg/s, outputs are `q / counts` (so 0.005 deg/s
    /// steps print as 0.345, not 0.34500000000000003); otherwise `q · step`.
    counts: Option<f64>,
    carry_error: bool,
    carry: f64,
}

impl Quantiser {
    /// A quantiser of LSB `step`; with `carry_error` the rounding error (in LSB) is added to the
    /// next sample, so the integrated output never strays more than half an angle LSB from the
    /// integrated input.
    pub fn new(step: f64, carry_error: bool) -> Self {
        let inv = 1.0 / step;
        let counts = ((inv - inv.round()).abs() <= 1e-9 * inv && inv.round() >= 1.0).then(|| inv.round());
        Self { step, inv: counts.unwrap_or(inv), counts, carry_error, carry: 0.0 }
    }

    #[inline]
    fn value(&self, q: f64) -> f64 {
        match self.counts {
            Some(c) => q / c,
            None => q * self.step,
        }
    }

    /// Quantises `x` into `out` (same length).
    #[inline]
    pub fn apply(&mut self, x: &[f64], out: &mut [f64]) {
        let inv = self.inv;
        if self.carry_error {
            let mut carry = self.carry;
            for (o, &v) in out.iter_mut().zip(x) {
                let u = v * inv + carry;
                let q = u.round();
                carry = u - q;
                *o = self.value(q);
            }
            self.carry = carry;
        } else {
            for (o, &v) in out.iter_mut().zip(x) {
                *o = self.value((v * inv).round());
            }
        }
    }
}

/// Bias proportional to temperature through a play (backlash) operator of width `hysteresis`.
#[derive(Debug, Clone)]
pub struct TemperatureBias {
    coefficient: f64,
    reference: f64,
    half_width: f64,
    effective: Option<f64>,
}

impl TemperatureBias {
    /// `coefficient` (deg/s/°C) · (T_eff − `reference`), T_eff lagging T by up to `hysteresis`/2.
    pub fn new(coefficient: f64, reference: f64, hysteresis: f64) -> Self {
        Self { coefficient, reference, half_width: hysteresis / 2.0, effective: None }
    }

    /// Adds the bias for the temperatures `temp` (one per sample).
    #[inline]
    pub fn add_to(&mut self, out: &mut [f64], temp: &[f64]) {
        let mut eff = self.effective.unwrap_or(temp.first().copied().unwrap_or(self.reference));
        for (v, &t) in out.iter_mut().zip(temp) {
            eff = eff.clamp(t - self.half_width, t + self.half_width);
            *v += self.coefficient * (eff - self.reference);
        }
        self.effective = Some(eff);
    }
}

/// Deterministic terms that are functions of time only: ramp, warm-up, sinusoids.
#[derive(Debug, Clone, Default)]
pub struct TimeTerms {
    /// Ramp slope, deg/s².
    pub ramp: f64,
    /// Warm-up (amplitude deg/s, time constant s).
    pub warmup: Option<(f64, f64)>,
    /// Sinusoids (amplitude deg/s, angular frequency rad/s, phase rad).
    pub sinusoids: Vec<(f64, f64, f64)>,
}

impl TimeTerms {
    /// Sinusoid parameters from amplitude, frequency in Hz and phase in degrees.
    pub fn sinusoid(amplitude: f64, frequency_hz: f64, phase_deg: f64) -> (f64, f64, f64) {
        (amplitude, TAU * frequency_hz, phase_deg.to_radians())
    }

    /// Whether every term is off.
    pub fn is_empty(&self) -> bool {
        self.ramp == 0.0 && self.warmup.is_none() && self.sinusoids.is_empty()
    }

    /// Adds the samples at times `t_s` (one per sample of `out`).
    pub fn add_to(&self, out: &mut [f64], t_s: &[f64]) {
        if self.is_empty() {
            return;
        }
        for (v, &t) in out.iter_mut().zip(t_s) {
            let mut s = self.ramp * t;
            if let Some((a, tc)) = self.warmup {
                s += a * (-t / tc).exp();
            }
            for &(a, w, p) in &self.sinusoids {
                s += a * (w * t + p).sin();
            }
            *v += s;
        }
    }
}
