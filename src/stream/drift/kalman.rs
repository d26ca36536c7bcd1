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
//! temperature T, the state is (b, c) with measurement z = b + c·(T − T₀) + v, T₀ the first
//! committed temperature, c constant (no process noise) with a weak prior (σ_c = 10·√R per °C,
//! i.e. ten per-sample σ per degree: the data decide within a degree or so of variation). The
//! drift of a sample at temperature T is b + c·(T − T₀), so a bias that follows the temperature
//! (a warm-up by self-heating) is followed while moving too, and the detector's reference
//! moves with it. A constant or absent temperature leaves the filter scalar (T − T₀ = 0); a
//! sample without a temperature in a stream that has them (NaN, or a reading the input check
//! threw out) is taken to be at the last finite one, so its drift does not jump.
//!
//! Innovation gate: a committed sample whose normalised innovation squared ν²/(P + R) exceeds
//! the χ²(1) quantile of the configured tail probability is not used (a spike or slow motion the
//! detector missed), and counted; the NIS sum over all commits is kept for consistency checks
//! (its mean is ≈ 1 when Q and R fit the data).

use super::{DriftEstimate, DriftEstimator, PendingMean};
use crate::model::normal::chi2_upper;
use crate::stream::calibration::NoiseCalibration;
use crate::stream::warm::AxisWarm;

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

/// Random-walk bias tracker of one axis (module documentation).
#[derive(Debug, Clone)]
pub struct KalmanBias {
    bias: f64,
    /// Variance of `bias`; +∞ before the first commit.
    variance: f64,
    /// Whether the temperature term is used.
    temperature: bool,
    /// Temperature coefficient c, deg/s per °C, its covariance with the bias and its variance.
    coef: f64,
    cov_bc: f64,
    var_c: f64,
    /// T₀, °C (`None` until a commit carried a temperature).
    reference_c: Option<f64>,
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
}

impl KalmanBias {
    /// A tracker with no data; `gate_probability` is the innovation gate's χ²(1) tail;
    /// `temperature` switches the temperature term on (module documentation).
    pub fn new(gate_probability: f64, temperature: bool) -> Self {
        Self {
            bias: 0.0,
            variance: f64::INFINITY,
            temperature,
            coef: 0.0,
            cov_bc: 0.0,
            var_c: 0.0,
            reference_c: None,
            temp_c: f64::NAN,
            last_temp_c: None,
            last_index: 0,
            q: 0.0,
            r: f64::NAN,
            calibration_version: u64::MAX,
            gate_nis: chi2_upper(1.0, gate_probability),
            counters: KalmanCounters::default(),
        }
    }

    /// Takes Q and R from the calibration when it changed.
    fn recalibrate(&mut self, noise: &NoiseCalibration) {
        if noise.version() == self.calibration_version {
            return;
        }
        self.calibration_version = noise.version();
        if let Some(r) = noise.white_variance() {
            // A constant input (an axis the recording lacks) has zero noise: keep R positive so
            // the gain stays defined.
            let r = r.max(f64::MIN_POSITIVE);
            self.r = r;
            self.q = noise.optimal_block().map_or(0.0, |m| 3.0 * r / (m * m));
        }
    }

    /// Process noise per sample and measurement noise, (deg/s)² (NaN R before calibration).
    pub fn noise(&self) -> (f64, f64) {
        (self.q, self.r)
    }

    /// The temperature coefficient c (deg/s per °C) and T₀, once a temperature was committed.
    pub fn temperature_coefficient(&self) -> Option<(f64, f64)> {
        self.reference_c.map(|t0| (self.coef, t0))
    }

    /// T − T₀ of the current sample: 0 without the term, a temperature or a reference.
    fn temperature_offset(&self) -> f64 {
        match self.reference_c {
            Some(t0) if self.temperature && self.temp_c.is_finite() => self.temp_c - t0,
            _ => 0.0,
        }
    }
}

impl DriftEstimator for KalmanBias {
    fn name(&self) -> &'static str {
        "kalman"
    }

    fn predict(&mut self, now: u64, pending: PendingMean, noise: &NoiseCalibration) -> DriftEstimate {
        self.recalibrate(noise);
        if self.variance.is_finite() {
            let p = self.variance + self.q * now.saturating_sub(self.last_index) as f64;
            let d = self.temperature_offset();
            // Var(b + c·d) = P_bb + 2d·P_bc + d²·P_cc.
            let variance = (p + 2.0 * d * self.cov_bc + d * d * self.var_c).max(0.0);
            return DriftEstimate { drift: self.bias + self.coef * d, variance, from_model: true };
        }
        // Nothing committed yet (start-up): the mean of the pending samples.
        match pending.count {
            0 => DriftEstimate { drift: 0.0, variance: f64::INFINITY, from_model: false },
            n => {
                let variance = if self.r.is_finite() { self.r / n as f64 } else { f64::INFINITY };
                DriftEstimate { drift: pending.sum / n as f64, variance, from_model: false }
            }
        }
    }

    fn commit(&mut self, index: u64, raw: f64, noise: &NoiseCalibration) {
        self.recalibrate(noise);
        self.counters.commits += 1;
        if !self.r.is_finite() {
            // No noise figure yet (cannot happen after a commit fed the calibration first).
            return;
        }
        if !self.variance.is_finite() {
            self.bias = raw;
            self.variance = self.r;
            self.last_index = index;
            self.coef = 0.0;
            self.cov_bc = 0.0;
            self.var_c = TEMPERATURE_PRIOR * self.r;
            self.reference_c = (self.temperature && self.temp_c.is_finite()).then_some(self.temp_c);
            return;
        }
        if self.reference_c.is_none() && self.temperature && self.temp_c.is_finite() {
            // The first temperature seen: it becomes T₀ (the bias so far is at T₀).
            self.reference_c = Some(self.temp_c);
            self.var_c = TEMPERATURE_PRIOR * self.r;
        }
        let p = self.variance + self.q * index.saturating_sub(self.last_index) as f64;
        let d = self.temperature_offset();
        // h = [1, d]: P·hᵀ = (P_bb + d·P_bc, P_bc + d·P_cc), S = h·P·hᵀ + R.
        let ph = [p + d * self.cov_bc, self.cov_bc + d * self.var_c];
        let s = ph[0] + d * ph[1] + self.r;
        let nu = raw - self.bias - self.coef * d;
        let nis = nu * nu / s;
        self.counters.nis_sum += nis;
        self.counters.nis_count += 1;
        self.last_index = index;
        if nis > self.gate_nis {
            self.counters.gated += 1;
            self.variance = p;
            return;
        }
        // Gain K = P·hᵀ/S; P ← P − K·(P·hᵀ)ᵀ (for d = 0 the scalar filter, c untouched).
        let k = [ph[0] / s, ph[1] / s];
        self.bias += k[0] * nu;
        self.coef += k[1] * nu;
        self.variance = (p - k[0] * ph[0]).max(0.0);
        self.cov_bc -= k[0] * ph[1];
        self.var_c = (self.var_c - k[1] * ph[1]).max(0.0);
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
        warm.temperature = self.reference_c.map(|t0| [self.coef, self.cov_bc, self.var_c, t0]);
        warm.last_temp_c = self.last_temp_c;
        warm.bias_count = self.counters.commits;
        warm.last_commit = self.last_index;
    }

    fn restore(&mut self, warm: &AxisWarm) {
        self.bias = warm.bias;
        self.variance = warm.variance;
        match warm.temperature {
            Some([coef, cov_bc, var_c, t0]) => {
                (self.coef, self.cov_bc, self.var_c, self.reference_c) = (coef, cov_bc, var_c, Some(t0));
            }
            None => (self.coef, self.cov_bc, self.var_c, self.reference_c) = (0.0, 0.0, 0.0, None),
        }
        self.counters.commits = warm.bias_count;
        self.last_index = warm.last_commit;
        self.last_temp_c = warm.last_temp_c;
        self.temp_c = self.last_temp_c.unwrap_or(f64::NAN);
    }

    fn relearn(&mut self) {
        self.variance = f64::INFINITY;
        self.reference_c = None;
    }

    fn kalman_counters(&self) -> Option<KalmanCounters> {
        Some(self.counters)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
