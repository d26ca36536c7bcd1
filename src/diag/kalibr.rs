//! Gyroscope noise parameters in the convention of Kalibr's `imu.yaml` (ethz-asl/kalibr wiki,
//! "IMU Noise Model"), also used by OpenVINS, VINS-Mono and `allan_variance_ros`.
//!
//! Kalibr models each gyro axis as ω̃ = ω + b + n with n continuous-time white noise of density
//! σ_g and b a random walk driven by white noise of density σ_bg:
//! - `gyroscope_noise_density` σ_g, rad/s/√Hz: the angle random walk **N** of the IEEE Std
//!   952-1997 model, the Allan deviation's −½-slope line read at τ = 1 s (σ²(τ) = N²/τ). Our N in
//!   deg/√s is the same quantity (rad/s/√Hz ≡ rad/√s) times π/180.
//! - `gyroscope_random_walk` σ_bg, rad/s²/√Hz: the rate random walk **K**, the +½-slope line read
//!   at τ = 3 s (σ²(τ) = K²τ/3). Our K in deg/s/√s times π/180.
//! - `update_rate`, Hz: the sample rate (Kalibr discretises σ_g·√rate and σ_bg/√rate itself),
//!   rounded to [`UPDATE_RATE_DIGITS`] significant digits: a rate estimated from the time column,
//!   (rows − 1)/(t_last − t_first), carries the rounding of the timestamps (a 100 Hz file gives
//!   99.99999999999997), which is not the rate of the sensor.
//!
//! Bias instability B (the flat floor) has no place in Kalibr's model; where the recording is too
//! short for K to show, the fit's K is 0 and Kalibr would trust the bias for ever. Then
//! [`KalibrGyro::random_walk_is_bound`] is set and the random walk is replaced by the smallest K
//! consistent with the measured floor — the +½ line through the Allan minimum,
//! K = σ_min·√(3/τ_min) — an upper bound users commonly take (and Kalibr's wiki suggests
//! inflating the values for real use anyway).

use super::allan::AllanDeviation;
use super::noise_model::NoiseModel;

/// Radians per degree.
const RAD_PER_DEG: f64 = std::f64::consts::PI / 180.0;

/// Significant digits of `update_rate` (module documentation): 6 keeps any real rate (e.g.
/// 199.608 Hz) and drops the ~1e-14 relative rounding of a rate computed from timestamps.
pub const UPDATE_RATE_DIGITS: i32 = 6;

/// `x` rounded to `digits` significant digits (0, NaN and infinities unchanged).
pub fn round_significant(x: f64, digits: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    // Through the decimal text, so the result is the double nearest the rounded decimal value
    // (100 exactly, not 100.00000000000001 from a scale-round-unscale in binary).
    format!("{:.*e}", (digits - 1).max(0) as usize, x).parse().unwrap_or(x)
}

/// The gyroscope keys of a Kalibr `imu.yaml` (module documentation).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct KalibrGyro {
    /// σ_g = N, rad/s/√Hz.
    pub gyroscope_noise_density: f64,
    /// σ_bg = K, rad/s²/√Hz.
    pub gyroscope_random_walk: f64,
    /// Sample rate, Hz, rounded to [`UPDATE_RATE_DIGITS`] significant digits.
    pub update_rate: f64,
    /// Whether `gyroscope_random_walk` is the bound through the Allan minimum (the fit found no
    /// rate random walk).
    pub random_walk_is_bound: bool,
}

impl KalibrGyro {
    /// Kalibr's parameters from a fitted IEEE noise model (deg units) and the Allan deviation it
    /// was fitted on (for the sample rate and, when the fit has no K, the bound through its
    /// minimum).
    pub fn from_fit(model: &NoiseModel, allan: &AllanDeviation) -> Self {
        let bound = || {
            allan
                .tau_s
                .iter()
                .zip(&allan.adev)
                .filter(|(t, a)| **t > 0.0 && a.is_finite() && **a > 0.0)
                .min_by(|x, y| x.1.total_cmp(y.1))
                .map_or(0.0, |(t, a)| a * (3.0 / t).sqrt())
        };
        let (k, random_walk_is_bound) = if model.k > 0.0 { (model.k, false) } else { (bound(), true) };
        Self {
            gyroscope_noise_density: model.n * RAD_PER_DEG,
            gyroscope_random_walk: k * RAD_PER_DEG,
            update_rate: round_significant(allan.rate_hz, UPDATE_RATE_DIGITS),
            random_walk_is_bound,
        }
    }

    /// The keys as Kalibr YAML, with a comment header naming the source; `topic` fills
    /// `rostopic` when given. Only the gyroscope keys are written: the accelerometer's come from
    /// its own recording.
    pub fn to_yaml(&self, source: &str, topic: Option<&str>) -> String {
        let mut y = String::new();
        y.push_str("# Kalibr imu.yaml gyroscope keys (gyrocomp allan --format kalibr)\n");
        y.push_str(&format!("# from: {source}\n"));
        y.push_str("# IEEE Std 952-1997 Allan fit: noise density = N (ARW), random walk = K (RRW), rad units.\n");
        y.push_str("# accelerometer_noise_density / accelerometer_random_walk: not measured here (gyro only).\n");
        if self.random_walk_is_bound {
            y.push_str("# gyroscope_random_walk: the fit found no rate random walk (record too short);\n");
            y.push_str("#   the value is the +1/2-slope bound through the Allan minimum.\n");
        }
        if let Some(t) = topic {
            y.push_str(&format!("rostopic: {t}\n"));
        }
        y.push_str(&format!("update_rate: {}\n", self.update_rate));
        y.push_str(&format!("gyroscope_noise_density: {:e}\n", self.gyroscope_noise_density));
        y.push_str(&format!("gyroscope_random_walk: {:e}\n", self.gyroscope_random_walk));
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn allan(tau: &[f64], adev: &[f64]) -> AllanDeviation {
        let len = tau.len();
        AllanDeviation {
            tau_s: tau.to_vec(),
            adev: adev.to_vec(),
            adev_err: vec![0.0; len],
            n: vec![100; len],
            m: (0..len).map(|j| 1 << j).collect(),
            rate_hz: 10.0,
            samples: 10_000,
        }
    }

    #[test]
    fn converts_n_and_k_to_radians_and_bounds_a_missing_random_walk() {
        let a = allan(&[0.1, 1.0, 10.0, 100.0], &[0.1, 0.03, 0.01, 0.02]);
        let model = NoiseModel { q: 0.0, n: 0.03, b: 0.0, k: 0.002, r: 0.0 };
        let k = KalibrGyro::from_fit(&model, &a);
        assert!((k.gyroscope_noise_density - 0.03 * RAD_PER_DEG).abs() < 1e-15);
        assert!((k.gyroscope_random_walk - 0.002 * RAD_PER_DEG).abs() < 1e-15);
        assert_eq!((k.update_rate, k.random_walk_is_bound), (10.0, false));
        // No K: the +½ line through the minimum (τ = 10 s, 0.01 deg/s) read at τ = 3 s.
        let k = KalibrGyro::from_fit(&NoiseModel { k: 0.0, ..model }, &a);
        assert!(k.random_walk_is_bound);
        assert!((k.gyroscope_random_walk - 0.01 * (0.3f64).sqrt() * RAD_PER_DEG).abs() < 1e-15);
        let yaml = k.to_yaml("x.csv", Some("/imu0"));
        assert!(yaml.contains("rostopic: /imu0\nupdate_rate: 10\n"), "{yaml}");
        assert!(yaml.contains("the +1/2-slope bound"), "{yaml}");
    }

    #[test]
    fn update_rate_drops_the_rounding_of_timestamps() {
        // 1000 rows at 100 Hz: (n − 1)/span with span = 9.99 s in floating point.
        let t_last = 999.0 / 100.0;
        let estimated = 999.0 / (t_last - 0.0);
        let mut a = allan(&[0.01, 0.02], &[0.1, 0.07]);
        for (rate, printed) in [(99.99999999999997, "100"), (estimated, "100"), (199.608, "199.608"), (0.5, "0.5")] {
            a.rate_hz = rate;
            let k = KalibrGyro::from_fit(&NoiseModel { n: 0.01, k: 0.001, ..NoiseModel::default() }, &a);
            assert!(
                k.to_yaml("x", None).contains(&format!("\nupdate_rate: {printed}\n")),
                "{rate}: {}",
                k.to_yaml("x", None)
            );
        }
        assert_eq!(round_significant(99.99999999999997, 6), 100.0);
        assert_eq!(round_significant(123_456_789.0, 6), 123_457_000.0);
        assert_eq!(round_significant(0.0, 6), 0.0);
    }
}
