//! The simulated model of one axis as the diagnosis builds it, and one seeded member of its
//! ensemble.
//!
//! Most terms are the simulator's own ([`crate::sim::AxisConfig`], run through
//! [`crate::sim::Generator`]); three are added to its output with the simulator's term types,
//! because `AxisConfig` has no slot for them:
//! - IEEE Std 952 angle quantisation Q as white *angle* noise: the rate error u\[k] − u[k−1] with u
//!   white of σ = Q·f_s has Allan variance 3σ²/m² = 3Q²/τ² (Annex C), without putting the output
//!   on a grid (the simulator's angle-mode quantiser would);
//! - a Gauss–Markov process beside the flicker bias instability ([`crate::sim::terms::GaussMarkov`]);
//! - the bias caused by the *recorded* temperature ([`crate::sim::terms::TemperatureBias`]): the
//!   temperature is an observed input, so the simulation uses the one the recording saw.
//!
//! The output quantiser ([`crate::sim::terms::Quantiser`]) comes last, after every term. Each extra
//! term draws from its own stream, so switching a term on leaves the other noise paths unchanged
//! (the effects are common-random-number comparisons, as in the simulator).

use serde::Serialize;

use super::SimgapError;
use crate::model::rng::splitmix64;
use crate::sim::rng::{Stream, StreamId};
use crate::sim::terms::{GaussMarkov, Quantiser, TemperatureBias};
use crate::sim::{AxisConfig, Generator, Quantization, QuantizationMode, SimConfig};

/// Index of the extra Gauss–Markov stream among the bias-instability streams (the flicker bank
/// uses the first few dozen).
const EXTRA_GM_STREAM: u64 = 1000;
/// Index of the angle-noise stream among the white streams (0 is the ARW).
const ANGLE_NOISE_STREAM: u64 = 1;

/// The simulated model of one axis.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct SimModel {
    /// The simulator's axis model, without quantisation (see [`SimModel::quantization`]).
    pub axis: AxisConfig,
    /// IEEE Std 952 angle quantisation Q, deg, as white angle noise (module docs).
    pub angle_noise_q_deg: f64,
    /// An extra first-order Gauss–Markov process: (stationary σ deg/s, correlation time s).
    pub extra_gauss_markov: Option<(f64, f64)>,
    /// Bias sensitivity to the recorded temperature: (deg/s per °C, reference °C).
    pub temperature: Option<(f64, f64)>,
    /// Output quantiser, applied last.
    pub quantization: Option<Quantization>,
}

impl SimModel {
    /// The model of a simulator axis configuration (its quantiser moved to the end of the chain).
    pub fn from_axis(axis: &AxisConfig) -> Self {
        let mut axis = axis.clone();
        let quantization = axis.quantization.take();
        Self { axis, quantization, ..Self::default() }
    }
}

/// Seed of member `j` of an ensemble seeded with `seed` (what [`simulate`] is given).
pub fn member_seed(seed: u64, j: usize) -> u64 {
    splitmix64(seed ^ splitmix64(j as u64 + 1))
}

/// One seeded member: `len` samples at `rate_hz` from t = 0; `temp_c` (when the model has a
/// temperature coefficient) is the recorded temperature, at least `len` long.
pub fn simulate(
    model: &SimModel,
    rate_hz: f64,
    len: usize,
    temp_c: Option<&[f64]>,
    seed: u64,
) -> Result<Vec<f64>, SimgapError> {
    let config = SimConfig {
        rate_hz,
        duration_s: len as f64 / rate_hz,
        seed: None,
        temperature: Default::default(),
        axis: AxisConfig::default(),
        x: model.axis.clone(),
        y: AxisConfig::default(),
        z: AxisConfig::default(),
    };
    let mut rate = Vec::new();
    Generator::new(&config, seed)?.into_axis(0).fill(len, &mut rate);
    if model.angle_noise_q_deg > 0.0 {
        let sigma = model.angle_noise_q_deg * rate_hz;
        let mut stream = Stream::indexed(seed, 0, StreamId::White, ANGLE_NOISE_STREAM);
        let mut previous = sigma * stream.normal();
        for v in &mut rate {
            let u = sigma * stream.normal();
            *v += u - previous;
            previous = u;
        }
    }
    if let Some((sigma, corr)) = model.extra_gauss_markov {
        let stream = Stream::indexed(seed, 0, StreamId::BiasInstability, EXTRA_GM_STREAM);
        GaussMarkov::new(sigma, corr, 1.0 / rate_hz, stream).add_to(&mut rate);
    }
    if let Some((coefficient, reference)) = model.temperature {
        let temp = temp_c.filter(|t| t.len() >= len).ok_or(SimgapError::NoTemperature)?;
        TemperatureBias::new(coefficient, reference, 0.0).add_to(&mut rate, &temp[..len]);
    }
    if let Some(q) = &model.quantization {
        rate = quantise(q, &rate);
    }
    Ok(rate)
}

/// `rate` through the output quantiser `q` ([`crate::sim::terms::Quantiser`]), the last step of
/// [`simulate`].
pub fn quantise(q: &Quantization, rate: &[f64]) -> Vec<f64> {
    let mut quantised = vec![0.0; rate.len()];
    Quantiser::new(q.step_dps, q.mode == QuantizationMode::Angle).apply(rate, &mut quantised);
    quantised
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::allan::{Taus, oadev};

    #[test]
    fn angle_noise_has_the_ieee_quantisation_slope() {
        let q = 1e-3;
        let model = SimModel { angle_noise_q_deg: q, ..SimModel::default() };
        let x = simulate(&model, 10.0, 200_000, None, 3).unwrap();
        let allan = oadev(&x, 10.0, &Taus::Factors(vec![4, 16, 64])).unwrap();
        for (tau, adev) in allan.tau_s.iter().zip(&allan.adev) {
            let want = 3f64.sqrt() * q / tau;
            assert!((adev / want - 1.0).abs() < 0.05, "tau {tau}: {adev} vs {want}");
        }
    }

    #[test]
    fn quantiser_comes_last_and_seeds_repeat() {
        let model = SimModel {
            axis: AxisConfig { arw_deg_rt_h: Some(2.0), ..AxisConfig::default() },
            extra_gauss_markov: Some((0.01, 5.0)),
            temperature: Some((0.01, 25.0)),
            quantization: Some(Quantization { step_dps: 0.01, mode: QuantizationMode::Rate }),
            ..SimModel::default()
        };
        let temp: Vec<f64> = (0..5000).map(|i| 25.0 + i as f64 * 1e-3).collect();
        let a = simulate(&model, 10.0, 5000, Some(&temp), 9).unwrap();
        assert_eq!(a, simulate(&model, 10.0, 5000, Some(&temp), 9).unwrap());
        assert_ne!(a, simulate(&model, 10.0, 5000, Some(&temp), 10).unwrap());
        assert!(a.iter().all(|v| ((v / 0.01).round() * 0.01 - v).abs() < 1e-12));
        assert!(matches!(simulate(&model, 10.0, 5000, None, 9), Err(SimgapError::NoTemperature)));
    }
}
