//! The temperature trajectory: exponential warm-up plus linear ramps, with optional reading noise.

use super::config::TemperatureConfig;
use super::rng::{Stream, StreamId};
use super::terms::White;

/// Axis index of the temperature stream (after the three gyro axes).
const TEMPERATURE_AXIS: u64 = 3;

/// Generates the temperature (true and as read) at given times.
#[derive(Debug, Clone)]
pub struct TemperatureTrajectory {
    config: TemperatureConfig,
    noise: Option<White>,
}

impl TemperatureTrajectory {
    /// The trajectory of `config`, its reading noise drawn from the temperature stream of `seed`.
    pub fn new(config: &TemperatureConfig, seed: u64) -> Self {
        let noise = (config.noise_c > 0.0)
            .then(|| White::new(config.noise_c, Stream::new(seed, TEMPERATURE_AXIS, StreamId::TemperatureNoise)));
        Self { config: config.clone(), noise }
    }

    /// The true temperature at `t_s` seconds, °C.
    pub fn at(&self, t_s: f64) -> f64 {
        let c = &self.config;
        let mut temp = c.start_c;
        if c.warmup_rise_c != 0.0 {
            temp -= c.warmup_rise_c * (-t_s / c.warmup_time_constant_s).exp_m1();
        }
        for r in &c.ramps {
            let progress = if t_s < r.start_s {
                0.0
            } else if t_s >= r.start_s + r.duration_s {
                1.0
            } else {
                (t_s - r.start_s) / r.duration_s
            };
            temp += r.delta_c * progress;
        }
        temp
    }

    /// Writes the true temperature at each time of `t_s` into `truth`, and the reading (truth plus
    /// noise) into `reading`.
    pub fn fill(&mut self, t_s: &[f64], truth: &mut [f64], reading: &mut [f64]) {
        for (v, &t) in truth.iter_mut().zip(t_s) {
            *v = self.at(t);
        }
        match &mut self.noise {
            Some(noise) => {
                noise.fill(reading);
                for (r, &v) in reading.iter_mut().zip(truth.iter()) {
                    *r += v;
                }
            }
            None => reading.copy_from_slice(truth),
        }
    }
}
