//! The candidate unmodelled effects ([`EffectKind`]), their fitted parameters ([`EffectParams`])
//! and how those enter the simulated model ([`EffectParams::apply`]): plain data that the fits
//! ([`super::fit_time`], [`super::fit_spectral`], [`super::fit_events`]) return and the catalogue
//! ([`super::effects`]) dispatches to.

use serde::Serialize;

use super::model::SimModel;
use crate::sim::{Jumps, Quantization, QuantizationMode, Sinusoid, Spikes, Warmup};

/// A candidate unmodelled effect.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EffectKind {
    /// Exponential warm-up transient of the bias.
    Warmup,
    /// Bias proportional to the temperature (needs `temp_c`).
    Temperature,
    /// Linear rate ramp.
    Ramp,
    /// A sinusoidal disturbance.
    Sinusoid,
    /// Random steps of the bias.
    BiasJumps,
    /// Single-sample outliers.
    Spikes,
    /// Output quantisation to a grid.
    Quantization,
    /// Correlated (first-order Gauss–Markov) noise.
    GaussMarkov,
}

impl EffectKind {
    /// Every effect, in catalogue order.
    pub const ALL: [EffectKind; 8] = [
        EffectKind::Warmup,
        EffectKind::Temperature,
        EffectKind::Ramp,
        EffectKind::Sinusoid,
        EffectKind::BiasJumps,
        EffectKind::Spikes,
        EffectKind::Quantization,
        EffectKind::GaussMarkov,
    ];

    /// The name on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            EffectKind::Warmup => "warmup",
            EffectKind::Temperature => "temperature",
            EffectKind::Ramp => "ramp",
            EffectKind::Sinusoid => "sinusoid",
            EffectKind::BiasJumps => "bias_jumps",
            EffectKind::Spikes => "spikes",
            EffectKind::Quantization => "quantization",
            EffectKind::GaussMarkov => "gauss_markov",
        }
    }
}

/// The fitted parameters of an effect.
#[derive(Debug, Clone, PartialEq)]
pub enum EffectParams {
    /// `amplitude_dps · e^(−t/time_constant_s)`.
    Warmup {
        /// Offset at t = 0, deg/s.
        amplitude_dps: f64,
        /// Time constant, s.
        time_constant_s: f64,
    },
    /// `dps_per_c · (temp_c − reference_c)`.
    Temperature {
        /// deg/s per °C.
        dps_per_c: f64,
        /// °C (the training mean).
        reference_c: f64,
    },
    /// `dps_per_s · t`.
    Ramp {
        /// deg/s².
        dps_per_s: f64,
    },
    /// `amplitude_dps · sin(2π·frequency_hz·t + phase_deg)`.
    Sinusoid {
        /// deg/s.
        amplitude_dps: f64,
        /// Hz.
        frequency_hz: f64,
        /// Phase at t = 0 of the recording, degrees.
        phase_deg: f64,
    },
    /// Poisson bias jumps.
    BiasJumps {
        /// Jumps per hour, over the whole recording.
        rate_per_h: f64,
        /// RMS jump, deg/s.
        size_dps: f64,
        /// Jumps found on the whole recording (the training part's and the hold-out's;
        /// [`super::fit_events::fit_jumps`]).
        detected: usize,
    },
    /// Poisson spikes.
    Spikes {
        /// Spikes per hour.
        rate_per_h: f64,
        /// Mean spike magnitude, deg/s.
        size_dps: f64,
        /// Spikes found on the training part.
        detected: usize,
    },
    /// Rate-mode quantiser.
    Quantization {
        /// Step, deg/s.
        step_dps: f64,
    },
    /// First-order Gauss–Markov process.
    GaussMarkov {
        /// Stationary σ, deg/s.
        sigma_dps: f64,
        /// Correlation time, s.
        correlation_time_s: f64,
    },
}

impl EffectParams {
    /// Which effect these parameters belong to.
    pub fn kind(&self) -> EffectKind {
        match self {
            EffectParams::Warmup { .. } => EffectKind::Warmup,
            EffectParams::Temperature { .. } => EffectKind::Temperature,
            EffectParams::Ramp { .. } => EffectKind::Ramp,
            EffectParams::Sinusoid { .. } => EffectKind::Sinusoid,
            EffectParams::BiasJumps { .. } => EffectKind::BiasJumps,
            EffectParams::Spikes { .. } => EffectKind::Spikes,
            EffectParams::Quantization { .. } => EffectKind::Quantization,
            EffectParams::GaussMarkov { .. } => EffectKind::GaussMarkov,
        }
    }

    /// The parameters as (name with unit, value) pairs, for JSON and the text report.
    pub fn named(&self) -> Vec<(&'static str, f64)> {
        match *self {
            EffectParams::Warmup { amplitude_dps, time_constant_s } => {
                vec![("amplitude_dps", amplitude_dps), ("time_constant_s", time_constant_s)]
            }
            EffectParams::Temperature { dps_per_c, reference_c } => {
                vec![("dps_per_c", dps_per_c), ("reference_c", reference_c)]
            }
            EffectParams::Ramp { dps_per_s } => vec![("dps_per_s", dps_per_s), ("deg_h2", dps_per_s * 3600.0 * 3600.0)],
            EffectParams::Sinusoid { amplitude_dps, frequency_hz, phase_deg } => {
                vec![("amplitude_dps", amplitude_dps), ("frequency_hz", frequency_hz), ("phase_deg", phase_deg)]
            }
            EffectParams::BiasJumps { rate_per_h, size_dps, detected } => {
                vec![("rate_per_h", rate_per_h), ("size_dps", size_dps), ("detected", detected as f64)]
            }
            EffectParams::Spikes { rate_per_h, size_dps, detected } => {
                vec![("rate_per_h", rate_per_h), ("size_dps", size_dps), ("detected", detected as f64)]
            }
            EffectParams::Quantization { step_dps } => vec![("step_dps", step_dps)],
            EffectParams::GaussMarkov { sigma_dps, correlation_time_s } => {
                vec![("sigma_dps", sigma_dps), ("correlation_time_s", correlation_time_s)]
            }
        }
    }

    /// Adds the effect to `model` (replacing the same term if the model has it).
    pub fn apply(&self, model: &mut SimModel) {
        let axis = &mut model.axis;
        match *self {
            EffectParams::Warmup { amplitude_dps, time_constant_s } => {
                axis.warmup = Some(Warmup { amplitude_dps, time_constant_s });
            }
            EffectParams::Temperature { dps_per_c, reference_c } => model.temperature = Some((dps_per_c, reference_c)),
            EffectParams::Ramp { dps_per_s } => axis.ramp_deg_h2 = Some(dps_per_s * 3600.0 * 3600.0),
            EffectParams::Sinusoid { amplitude_dps, frequency_hz, phase_deg } => {
                axis.sinusoids.get_or_insert_with(Vec::new).push(Sinusoid { amplitude_dps, frequency_hz, phase_deg });
            }
            EffectParams::BiasJumps { rate_per_h, size_dps, .. } => axis.jumps = Some(Jumps { rate_per_h, size_dps }),
            EffectParams::Spikes { rate_per_h, size_dps, .. } => axis.spikes = Some(Spikes { rate_per_h, size_dps }),
            EffectParams::Quantization { step_dps } => {
                model.quantization = Some(Quantization { step_dps, mode: QuantizationMode::Rate });
            }
            EffectParams::GaussMarkov { sigma_dps, correlation_time_s } => {
                model.extra_gauss_markov = Some((sigma_dps, correlation_time_s));
            }
        }
    }
}

/// An effect fitted on the training part.
#[derive(Debug, Clone, PartialEq)]
pub struct FittedEffect {
    /// Its parameters.
    pub params: EffectParams,
    /// Its deterministic part on the training samples, subtracted before the noise terms are
    /// refitted (so the baseline terms do not absorb the effect twice); `None` for an effect with
    /// nothing to subtract (quantisation, Gauss–Markov noise).
    pub training_part: Option<Vec<f64>>,
}

/// The outcome of fitting one effect.
#[derive(Debug, Clone, PartialEq)]
pub enum Fitted {
    /// Fitted.
    Found(FittedEffect),
    /// Not a candidate for this recording, and why (no `temp_c`, no grid, nothing detected).
    NotApplicable(String),
}
