//! The Kalman bias tracker (issue 13, item 4): per axis, the drift is a random walk b_k =
//! b_{k−1} + w_k, w ~ N(0, Q) per sample, observed by committed static samples z_k = b_k + v_k,
//! v ~ N(0, R). Scalar Kalman filter (Kalman 1960; e.g. Groves, *Principles of GNSS, Inertial and
//! Multisensor Integrated Navigation*, 2nd ed., §3.2):
//! time update P ← P + Q·Δk; gain G = P/(P + R); b ← b + G(z − b); P ← (1 − G)P.
//!
//! Noise from the unit itself ([`NoiseCalibration`]): R = the white-noise variance per sample
//! (N² over the sample period, from the online Allan variance); Q = 3R/m\*² with m\* the
//! averaging time (samples) of the Allan minimum, i.e. the rate random walk K_eff = √3·N/τ\*
//! whose curve N²/τ + K²τ/3 has its minimum at the measured τ\*. So the filter averages for
//! about m\*/√3 samples: as long as the unit's own Allan curve says averaging still helps. Before
//! any Allan level is trusted Q = 0: a plain cumulative mean, i.e. start-up bias-hold.
//!
//! Delayed commit: the state is that of the last committed sample; [`KalmanBias::predict`]
//! propagates it to now. Pending samples (seen as static, not yet confirmed) are used only before
//! the first commit, as their plain mean (the start-up alignment). Fusing them later as well
//! was tried and dropped: a slow rotation that the detector has not yet found then pulls the
//! reference r = ω − b̂ along with it, so the detector never finds it (on ADIS run 1 with the
//! mixed profile the estimate absorbed a 1 deg/s rotation that way).
//!
//! Temperature term (issue 13, item 4, optional: `[drift] temperature`): when samples carry a
//! temperature T, a second filter runs beside the scalar one on the same commits, with state
//! (b, c) and measurement z = b + c·(T − T₀) + v, T₀ the first committed temperature, c constant
//! (no process noise) with a weak prior (σ_c = 10·√R per °C, i.e. ten per-sample σ per degree:
//! the data decide within a degree or so of variation). The drift of a sample at temperature T
//! is then b + c·(T − T₀), so a bias that follows the temperature (a warm-up by self-heating) is
//! followed while moving too, and the detector's reference moves with it. A sample without a
//! temperature in a stream that has them (NaN, or a reading the input check threw out) is taken
//! to be at the last finite one, so its drift does not jump.
//!
//! **Which filter is used is decided by the data**: a Bayesian comparison of the two models by
//! their sequential predictive likelihood (the product of the innovation densities
//! N(ν; 0, S) is each state-space model's marginal likelihood of the committed samples; e.g.
//! Harvey, *Forecasting, Structural Time Series Models and the Kalman Filter*, §3.4). The log
//! Bayes factor ln BF = Σ [ln N(ν_T; 0, S_T) − ln N(ν; 0, S)] over the commits that neither
//! filter's gate refuses is kept, and the temperature filter drives the output (drift, its
//! variance, the detector's reference) once ln BF exceeds [`TEMPERATURE_EVIDENCE`], until it
//! falls back below 0. Until then the scalar filter's output is used, as without the term. The
//! wide prior on c is paid for in this comparison (the Occam factor: after a temperature change
//! the two-state filter predicts with the larger S_T), so a temperature channel that the bias
//! does not follow costs nothing: before this comparison the term was always on, and on an
//! independently generated floor whose bias ignores the temperature its prior variance
//! d²·Var(c) raised the detector's thresholds after each temperature change, so that a slow
//! rotation leaked into the estimate, and c then learnt the leak.
//!
//! Innovation gate: a committed sample whose normalised innovation squared ν²/(P + R) exceeds
//! the χ²(1) quantile of the configured tail probability is not used (a spike or slow motion the
//! detector missed), and counted; the NIS sum over all commits is kept for consistency checks
//! (its mean is ≈ 1 when Q and R fit the data).

use super::{DriftEstimate, DriftEstimator, PendingMean};
use crate::model::normal::chi2_upper;
use crate::stream::calibration::NoiseCalibration;
use crate::stream::warm::{AxisWarm, TemperatureWarm};

/// Innovation statistics of a [`KalmanBias`].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct KalmanCounters {
    /// Committed samples offered.
    pub commits: u64,
    /// Of those, refused by the innovation gate.
    pub gated: u64,
    /// Σ ν²/(P + R) over the offered commits after the first.
    pub nis_sum: f64,
    /// Terms in `nis_sum`.
    pub nis_count: u64,
}

impl KalmanCounters {
    /// Mean normalised innovation squared (≈ 1 for a consistent filter); `None` before any.
    pub fn mean_nis(&self) -> Option<f64> {
        (self.nis_count > 0).then(|| self.nis_sum / self.nis_count as f64)
    }
}

/// Prior variance of the temperature coefficient per R, per °C²: σ_c = 10·√R per °C.
const TEMPERATURE_PRIOR: f64 = 100.0;

/// Log Bayes factor (temperature filter against the scalar one) above which the temperature
/// filter drives the output (module documentation); it hands back below 0. ln 10, "substantial"
/// on Jeffreys' scale. Chosen on the tuning sets (simulated mpu6050, sim seeds 100–102, axes x
/// and y, whose bias follows the temperature at 0.02 and −0.015 deg/s/°C; independent floors of
/// `tools/simgap/independent_cases.py`, seeds 1400–1407, whose bias ignores a temperature that
/// varies by several °C; motion seeds 100–101; ln 100, ln 10 and e tried: median per motion
/// 1.26×, 1.28×, 1.26× the floor on the floors (always on: 1.39×), 5.73×, 5.73×, 5.83× on mpu6050
/// x (always on 4.94×, never 5.57×) and 5.08×, 4.73×, 4.64× on y (4.96×, 5.16×)), never on the
/// reported ones.
pub const TEMPERATURE_EVIDENCE: f64 = std::f64::consts::LN_10;

/// Random-walk bias tracker of one axis (module documentation).
#[derive(Debug, Clone)]
pub struct KalmanBias {
    /// The scalar filter: bias and its variance (+∞ before the first commit).
    bias: f64,
    variance: f64,
    /// Whether the temperature term is allowed (`[drift] temperature`).
    temperature: bool,
    /// The two-state filter run beside the scalar one, its evidence and whether it drives the
    /// output; `None` until a commit carried a temperature (the two are one filter until then).
    with_temp: Option<TemperatureWarm>,
    /// Temperature of the sample the next predict or commit refers to (NaN: none seen yet).
    temp_c: f64,
    /// The last finite temperature set: a sample without one (NaN mid-stream) is taken to be
    /// at it, so the drift does not jump by c·(T − T₀) for that sample.
    last_temp_c: Option<f64>,
    last_index: u64,
    q: f64,
    r: f64,
    calibration_version: u64,
    gate_nis: f64,
    counters: KalmanCounters,
    /// Innovation and its variance of the last commit the output's filter used.
    last_innovation: Option<(f64, f64)>,
}

impl KalmanBias {
    /// A tracker with no data; `gate_probability` is the innovation gate's χ²(1) tail;
    /// `temperature` switches the temperature term on (module documentation).
    pub fn new(gate_probability: f64, temperature: bool) -> Self {
        Self {
            bias: 0.0,
            variance: f64::INFINITY,
            temperature,
            with_temp: None,
            temp_c: f64::NAN,
            last_temp_c: None,
            last_index: 0,
            q: 0.0,
            r: f64::NAN,
            calibration_version: u64::MAX,
            gate_nis: chi2_upper(1.0, gate_probability),
            counters: KalmanCounters::default(),
            last_innovation: None,
        }
    }

    /// Takes Q and R from the calibration when it changed.
    fn recalibrate(&mut self, noise: &NoiseCalibration) {
        if noise.version() == self.calibration_version {
            return;
        }
        self.calibration_version = noise.version();
        if let Some((r, q)) = noise.random_walk_noise() {
            (self.r, self.q) = (r, q);
        }
    }

    /// Innovation ν and its variance S (deg/s, (deg/s)²) of the last commit, of the filter that
    /// drives the output, when it used it (not the first commit, nor one the gate refused).
    pub fn last_innovation(&self) -> Option<(f64, f64)> {
        self.last_innovation
    }

    /// Process noise per sample and measurement noise, (deg/s)² (NaN R before calibration).
    pub fn noise(&self) -> (f64, f64) {
        (self.q, self.r)
    }

    /// The temperature coefficient c (deg/s per °C) and T₀ of the temperature filter, once a
    /// temperature was committed (whether or not that filter drives the output).
    pub fn temperature_coefficient(&self) -> Option<(f64, f64)> {
        self.with_temp.map(|f| (f.coef, f.reference_c))
    }

    /// Whether the temperature filter drives the output, and the log Bayes factor behind it.
    pub fn temperature_evidence(&self) -> (bool, f64) {
        self.with_temp.map_or((false, 0.0), |f| (f.in_use, f.evidence))
    }

    /// T − T₀ of the current sample: 0 without the term, a temperature or a reference.
    fn temperature_offset(&self) -> f64 {
        match self.with_temp {
            Some(f) if self.temperature && self.temp_c.is_finite() => self.temp_c - f.reference_c,
            _ => 0.0,
        }
    }

    /// The temperature filter's time update over `dk` samples and its commit of `raw` at
    /// T − T₀ = `d`: returns the innovation ν_T, its variance S_T and whether the gate refused
    /// it (the state is updated unless so).
    fn commit_with_temperature(&self, f: &mut TemperatureWarm, raw: f64, d: f64, dk: f64) -> (f64, f64, bool) {
        let p = f.variance + self.q * dk;
        // h = [1, d]: P·hᵀ = (P_bb + d·P_bc, P_bc + d·P_cc), S = h·P·hᵀ + R.
        let ph = [p + d * f.cov_bc, f.cov_bc + d * f.var_c];
        let s = ph[0] + d * ph[1] + self.r;
        let nu = raw - f.bias - f.coef * d;
        if nu * nu / s > self.gate_nis {
            f.variance = p;
            return (nu, s, true);
        }
        // Gain K = P·hᵀ/S; P ← P − K·(P·hᵀ)ᵀ.
        let k = [ph[0] / s, ph[1] / s];
        f.bias += k[0] * nu;
        f.coef += k[1] * nu;
        f.variance = (p - k[0] * ph[0]).max(0.0);
        f.cov_bc -= k[0] * ph[1];
        f.var_c = (f.var_c - k[1] * ph[1]).max(0.0);
        (nu, s, false)
    }
}

/// ln N(ν; 0, s) up to the constant −½ ln 2π (which cancels in a log Bayes factor).
pub(super) fn log_density(nu: f64, s: f64) -> f64 {
    -0.5 * (s.ln() + nu * nu / s)
}

impl DriftEstimator for KalmanBias {
    fn name(&self) -> &'static str {
        "kalman"
    }

    fn predict(&mut self, now: u64, pending: PendingMean, noise: &NoiseCalibration) -> DriftEstimate {
        self.recalibrate(noise);
        if self.variance.is_finite() {
            let dk = now.saturating_sub(self.last_index) as f64;
            if let Some(f) = self.with_temp.filter(|f| f.in_use) {
                let p = f.variance + self.q * dk;
                let d = self.temperature_offset();
                // Var(b + c·d) = P_bb + 2d·P_bc + d²·P_cc.
                let variance = (p + 2.0 * d * f.cov_bc + d * d * f.var_c).max(0.0);
                return DriftEstimate { drift: f.bias + f.coef * d, variance, from_model: true };
            }
            return DriftEstimate { drift: self.bias, variance: self.variance + self.q * dk, from_model: true };
        }
        // Nothing committed yet (start-up); R is NaN before the calibration knows a σ.
        pending.startup_estimate(self.r)
    }

    fn commit(&mut self, index: u64, raw: f64, noise: &NoiseCalibration) {
        self.recalibrate(noise);
        self.counters.commits += 1;
        self.last_innovation = None;
        if !self.r.is_finite() {
            // No noise figure yet (cannot happen after a commit fed the calibration first).
            return;
        }
        let first = !self.variance.is_finite();
        if first {
            self.bias = raw;
            self.variance = self.r;
            self.last_index = index;
            self.with_temp = None;
        }
        if self.with_temp.is_none() && self.temperature && self.temp_c.is_finite() {
            // The first temperature seen: it becomes T₀ (the bias so far is at T₀), and the
            // temperature filter starts from the scalar one's state (until now it would have been
            // the same filter: T − T₀ = 0), with the prior on c.
            self.with_temp = Some(TemperatureWarm {
                bias: self.bias,
                variance: self.variance,
                coef: 0.0,
                cov_bc: 0.0,
                var_c: TEMPERATURE_PRIOR * self.r,
                reference_c: self.temp_c,
                evidence: 0.0,
                in_use: false,
            });
        }
        if first {
            return;
        }
        let dk = index.saturating_sub(self.last_index) as f64;
        self.last_index = index;
        let p = self.variance + self.q * dk;
        let s = p + self.r;
        let nu = raw - self.bias;
        let gated = nu * nu / s > self.gate_nis;
        // Without a temperature so far the two filters are one: the second is not run.
        let (mut nu_out, mut s_out, mut gated_out) = (nu, s, gated);
        if let Some(mut f) = self.with_temp {
            let d = self.temperature_offset();
            let (nu_t, s_t, gated_t) = self.commit_with_temperature(&mut f, raw, d, dk);
            if !gated && !gated_t {
                f.evidence += log_density(nu_t, s_t) - log_density(nu, s);
                if !f.in_use && f.evidence > TEMPERATURE_EVIDENCE {
                    f.in_use = true;
                    tracing::debug!(evidence = f.evidence, index, "the temperature term now drives the drift");
                } else if f.in_use && f.evidence < 0.0 {
                    f.in_use = false;
                    tracing::debug!(evidence = f.evidence, index, "the temperature term no longer drives the drift");
                }
            }
            if f.in_use {
                // The counters follow the filter that drives the output.
                (nu_out, s_out, gated_out) = (nu_t, s_t, gated_t);
            }
            self.with_temp = Some(f);
        }
        self.counters.nis_sum += nu_out * nu_out / s_out;
        self.counters.nis_count += 1;
        if gated_out {
            self.counters.gated += 1;
        } else {
            self.last_innovation = Some((nu_out, s_out));
        }
        if gated {
            self.variance = p;
            return;
        }
        let k = p / s;
        self.bias += k * nu;
        self.variance = (p - k * p).max(0.0);
    }

    /// A sample without a temperature (NaN) is taken to be at the last finite one.
    fn set_temperature(&mut self, temp_c: f64) {
        if temp_c.is_finite() {
            self.last_temp_c = Some(temp_c);
        }
        self.temp_c = self.last_temp_c.unwrap_or(f64::NAN);
    }

    fn warm(&self, warm: &mut AxisWarm) {
        warm.bias = self.bias;
        warm.variance = self.variance;
        warm.temperature = self.with_temp;
        warm.last_temp_c = self.last_temp_c;
        warm.bias_count = self.counters.commits;
        warm.last_commit = self.last_index;
    }

    /// Without a stored temperature filter (none had a T₀ yet) it starts afresh from the scalar
    /// one at the first commit that carries a temperature.
    fn restore(&mut self, warm: &AxisWarm) {
        self.bias = warm.bias;
        self.variance = warm.variance;
        self.with_temp = warm.temperature;
        self.counters.commits = warm.bias_count;
        self.last_index = warm.last_commit;
        self.last_temp_c = warm.last_temp_c;
        self.temp_c = self.last_temp_c.unwrap_or(f64::NAN);
    }

    fn has_reference(&self) -> bool {
        self.variance.is_finite()
    }

    fn relearn(&mut self) {
        self.variance = f64::INFINITY;
        self.with_temp = None;
    }

    fn kalman_counters(&self) -> Option<KalmanCounters> {
        Some(self.counters)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// Commits 20,000 samples of white noise (σ 0.1 deg/s) on a bias of 0.3 deg/s plus
    /// `coefficient` · (T − 20 °C), the temperature swinging 20 … 26 °C and back, to a tracker
    /// with the temperature term and to one without; returns both and the calibration.
    fn trackers_after_a_temperature_swing(coefficient: f64) -> (KalmanBias, KalmanBias, NoiseCalibration) {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
        let mut noise = NoiseCalibration::new();
        let (mut with, mut without) = (KalmanBias::new(1e-6, true), KalmanBias::new(1e-6, false));
        for i in 0..20_000u64 {
            let t = 23.0 - 3.0 * (2.0 * std::f64::consts::PI * i as f64 / 20_000.0).cos();
            let e: f64 = StandardNormal.sample(&mut rng);
            let raw = 0.3 + coefficient * (t - 20.0) + 0.1 * e;
            noise.observe(raw);
            noise.commit(i, raw);
            with.set_temperature(t);
            with.commit(i, raw, &noise);
            without.commit(i, raw, &noise);
        }
        (with, without, noise)
    }

    #[test]
    fn the_temperature_filter_drives_the_output_only_when_the_bias_follows_the_temperature() {
        let pending = PendingMean::default();
        // A bias that ignores the temperature: the output is the scalar tracker's, bit for bit,
        // also far from T₀, where the two-state filter's Var(c)·(T − T₀)² would widen it.
        let (mut with, mut without, noise) = trackers_after_a_temperature_swing(0.0);
        let (in_use, evidence) = with.temperature_evidence();
        assert!(!in_use && evidence < TEMPERATURE_EVIDENCE, "evidence {evidence}");
        with.set_temperature(30.0);
        let scalar = without.predict(25_000, pending, &noise);
        assert_eq!(with.predict(25_000, pending, &noise), scalar);
        let (c, t0) = with.temperature_coefficient().unwrap();
        assert!(c.abs() < 0.01 && (t0 - 20.0).abs() < 0.01, "c {c}, T₀ {t0}");
        // A bias of 0.02 deg/s per °C (0.12 deg/s over the swing): the temperature filter takes
        // over and predicts the bias at 30 °C, 0.1 deg/s above what the scalar tracker holds.
        let (mut with, mut without, noise) = trackers_after_a_temperature_swing(0.02);
        let (in_use, evidence) = with.temperature_evidence();
        assert!(in_use && evidence > 10.0 * TEMPERATURE_EVIDENCE, "evidence {evidence}");
        with.set_temperature(30.0);
        let at_30 = with.predict(25_000, pending, &noise);
        assert!((at_30.drift - 0.5).abs() < 0.02, "{at_30:?}");
        let held = without.predict(25_000, pending, &noise);
        assert!((held.drift - 0.3).abs() < 0.03, "{held:?}");
    }

    #[test]
    fn a_sample_without_temperature_is_taken_at_the_last_one() {
        let mut noise = NoiseCalibration::new();
        for i in 0..200u64 {
            let x = if i % 2 == 0 { 0.01 } else { -0.01 };
            noise.observe(x);
            noise.commit(i, x);
        }
        let mut k = KalmanBias::new(1e-6, true);
        // A bias of 0.1 deg/s per °C over 20 … 30 °C: c is learnt.
        for i in 0..2000u64 {
            let t = 20.0 + 10.0 * (i as f64 / 2000.0);
            k.set_temperature(t);
            k.commit(i, 0.1 * (t - 20.0), &noise);
        }
        let pending = PendingMean::default();
        k.set_temperature(30.0);
        let at_30 = k.predict(2000, pending, &noise);
        k.set_temperature(f64::NAN);
        let missing = k.predict(2000, pending, &noise);
        assert_eq!(missing, at_30, "NaN is the last finite temperature, not T0");
        let mut warm = AxisWarm::default();
        k.warm(&mut warm);
        assert_eq!(warm.last_temp_c, Some(30.0));
        let mut restored = KalmanBias::new(1e-6, true);
        restored.restore(&warm);
        restored.set_temperature(f64::NAN);
        assert_eq!(restored.predict(2000, pending, &noise), at_30);
        assert!((at_30.drift - 1.0).abs() < 0.01, "{at_30:?}");
    }
}
