//! Simulator configuration: the gyro error model per axis and the temperature trajectory, as plain
//! serde structs. The same structs are the TOML file format (`gyrocomp sim --config FILE.toml`):
//! every key names its unit, unknown keys are rejected, and an absent term is switched off.
//!
//! # Units
//! Rates are in deg/s throughout. The IEEE Std 952 coefficients keep the units that datasheets use,
//! and the key names say which:
//!
//! | key | term | unit | converted to |
//! |---|---|---|---|
//! | `arw_deg_rt_h` | angle random walk N | deg/√h | deg/√s = N/60; per-sample σ = N/60·√fs deg/s |
//! | `bias_instability.b_deg_h` | bias instability B | deg/h | deg/s = B/3600 |
//! | `rrw_deg_h_rt_h` | rate random walk K | deg/h/√h | deg/s/√s = K/216 000; per-sample step K·√dt |
//! | `ramp_deg_h2` | rate ramp R | deg/h² | deg/s² = R/3600² |
//! | `quantization.step_dps` | quantiser LSB Δ | deg/s | Allan Q = Δ/(fs·√12) deg (angle mode) |
//!
//! # Axes
//! `[axis]` holds the model shared by all three axes; `[x]`, `[y]` and `[z]` hold per-axis keys that
//! replace the same key of `[axis]` (a key whose value is a table, such as `[x.bias_instability]`,
//! replaces that whole table; `sinusoids` replaces the whole list). Each axis draws its own random
//! numbers, so sharing a model never shares a noise path.

use serde::{Deserialize, Serialize};

/// Seconds per hour.
const S_PER_H: f64 = 3600.0;

/// Angle random walk: deg/√h (the config's `arw_deg_rt_h`) per deg/√s (√3600).
pub const ARW_DEG_RT_H_PER_DEG_RT_S: f64 = 60.0;

/// Rate random walk: deg/h/√h (the config's `rrw_deg_h_rt_h`) per deg/s/√s (3600 · √3600).
pub const RRW_DEG_H_RT_H_PER_DPS_RT_S: f64 = S_PER_H * ARW_DEG_RT_H_PER_DEG_RT_S;

/// A configuration that cannot be simulated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConfigError {
    /// The TOML text does not parse, or names a key the simulator does not know.
    #[error("{0}")]
    Toml(String),
    /// A value is out of its range (the message names the key).
    #[error("{key}: {problem}")]
    Invalid {
        /// Dotted path of the key, e.g. `x.bias_instability.b_deg_h`.
        key: String,
        /// What is wrong with it.
        problem: String,
    },
}

/// The whole simulation: sample rate, length, temperature trajectory and the three axis models.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimConfig {
    /// Sample rate, Hz.
    pub rate_hz: f64,
    /// Length of the run, seconds (the CLI's `--duration` replaces it).
    pub duration_s: f64,
    /// Seed of the random streams; the CLI's `--seed` replaces it (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Temperature trajectory written to `temp_c` (constant 25 °C when absent).
    #[serde(default)]
    pub temperature: TemperatureConfig,
    /// Error model shared by all axes.
    #[serde(default)]
    pub axis: AxisConfig,
    /// Keys of axis x (`gx_dps`) that replace those of `[axis]`.
    #[serde(default, skip_serializing_if = "AxisConfig::is_empty")]
    pub x: AxisConfig,
    /// Keys of axis y (`gy_dps`) that replace those of `[axis]`.
    #[serde(default, skip_serializing_if = "AxisConfig::is_empty")]
    pub y: AxisConfig,
    /// Keys of axis z (`gz_dps`) that replace those of `[axis]`.
    #[serde(default, skip_serializing_if = "AxisConfig::is_empty")]
    pub z: AxisConfig,
}

/// The error model of one axis. Every term is optional; an absent term contributes nothing.
///
/// The *drift* of an axis (its truth column `g?_drift_dps`) is the sum of every term except white
/// noise and quantisation: bias, bias instability, rate random walk, ramp, warm-up, temperature,
/// sinusoids, bias jumps and spikes. The raw output is `quantise(drift + white)`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisConfig {
    /// Constant bias, deg/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bias_dps: Option<f64>,
    /// Angle random walk N (white rate noise), deg/√h. Allan σ(τ) = N/√τ with N in deg/√s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub arw_deg_rt_h: Option<f64>,
    /// Bias instability B (flicker floor or Gauss–Markov).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bias_instability: Option<BiasInstability>,
    /// Rate random walk K, deg/h/√h. Allan σ(τ) = K·√(τ/3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rrw_deg_h_rt_h: Option<f64>,
    /// Rate ramp R, deg/h²: the drift grows by R·t. Allan σ(τ) = R·τ/√2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ramp_deg_h2: Option<f64>,
    /// Output quantiser.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quantization: Option<Quantization>,
    /// Exponential warm-up transient.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub warmup: Option<Warmup>,
    /// Bias sensitivity to the temperature trajectory.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub temperature_coefficient: Option<TemperatureCoefficient>,
    /// Sinusoidal disturbances (vibration, pick-up), summed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sinusoids: Option<Vec<Sinusoid>>,
    /// Random bias jumps (steps that persist).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub jumps: Option<Jumps>,
    /// Single-sample spikes (outliers).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spikes: Option<Spikes>,
}

/// Bias instability B, deg/h, with the process that realises it. In both models B is the level of
/// the Allan floor in the IEEE Std 952 sense: σ_floor = √(2 ln 2/π)·B ≈ 0.664·B.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "snake_case", deny_unknown_fields)]
pub enum BiasInstability {
    /// Flicker (1/f) noise with a flat Allan floor 0.664·B between `floor_from_s` and `floor_to_s`,
    /// made of first-order Gauss–Markov processes with correlation times spaced (at least) two per
    /// decade from `floor_from_s / 30` to `floor_to_s · 15` (one-sided PSD B²/(π f) in between; fast
    /// processes are output as interval means, so the floor holds down to τ = one sample). The
    /// floor is within ±2 % of 0.664·B over the span (at any sample rate); below it the deviation
    /// falls like √τ, above it like 1/√τ.
    Flicker {
        /// B, deg/h.
        b_deg_h: f64,
        /// Shortest averaging time of the flat floor, s.
        floor_from_s: f64,
        /// Longest averaging time of the flat floor, s.
        floor_to_s: f64,
    },
    /// One first-order Gauss–Markov process with correlation time T, its stationary σ chosen so that
    /// the Allan deviation peaks at 0.664·B (at τ ≈ 1.89·T): σ = 0.664·B / 0.6174.
    GaussMarkov {
        /// B, deg/h (the peak of the Allan deviation divided by 0.664).
        b_deg_h: f64,
        /// Correlation time T, s.
        correlation_time_s: f64,
    },
}

/// How the quantiser treats its rounding error.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum QuantizationMode {
    /// The rounding error is carried to the next sample, as in a sensor that integrates the rate
    /// and outputs angle increments: the error in angle stays bounded by Δ/(2 fs) and is white, so
    /// it shows as IEEE Std 952 angle quantisation, Allan σ²(τ) = 3Q²/τ² with Q = Δ/(fs·√12) deg
    /// (IEEE Std 952-1997 Annex C; El-Sheimy, Hou & Niu 2008, Table 1: Q = δθ/√12 with the angle
    /// step δθ = Δ/fs).
    #[default]
    Angle,
    /// Each sample is rounded on its own: the error is white rate noise of σ = Δ/√12, i.e. it adds
    /// N = Δ/√(12 fs) deg/√s to the angle random walk (Allan slope −1/2, not −1).
    Rate,
}

/// Output quantisation to a multiple of a step (the LSB).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Quantization {
    /// LSB of the rate output Δ, deg/s.
    pub step_dps: f64,
    /// `angle` (default, error carried: Allan Q) or `rate` (each sample rounded: white).
    #[serde(default)]
    pub mode: QuantizationMode,
}

/// Exponential warm-up transient: `amplitude_dps · exp(−t / time_constant_s)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Warmup {
    /// Offset at t = 0, deg/s.
    pub amplitude_dps: f64,
    /// Time constant, s.
    pub time_constant_s: f64,
}

/// Bias sensitivity to temperature: `dps_per_c · (T_eff − reference_c)`, where T_eff follows the
/// temperature trajectory through a play (backlash) operator of width `hysteresis_c`: T_eff moves
/// only when the temperature is more than `hysteresis_c / 2` away from it, so warming and cooling
/// through the same temperature give biases that differ by `dps_per_c · hysteresis_c`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TemperatureCoefficient {
    /// Coefficient, deg/s per °C.
    pub dps_per_c: f64,
    /// Temperature of zero temperature-induced bias, °C (default 25).
    #[serde(default = "default_reference_c")]
    pub reference_c: f64,
    /// Width of the hysteresis loop, °C (default 0: none).
    #[serde(default)]
    pub hysteresis_c: f64,
}

fn default_reference_c() -> f64 {
    25.0
}

/// A sinusoid `amplitude_dps · sin(2π·frequency_hz·t + phase_deg)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sinusoid {
    /// Amplitude, deg/s.
    pub amplitude_dps: f64,
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// Phase at t = 0, degrees (default 0).
    #[serde(default)]
    pub phase_deg: f64,
}

/// Bias jumps: a Poisson process of steps; each step is normal with standard deviation `size_dps`
/// and persists.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Jumps {
    /// Mean number of jumps per hour.
    pub rate_per_h: f64,
    /// Standard deviation of one jump, deg/s.
    pub size_dps: f64,
}

/// Spikes: a Poisson process of single-sample outliers of ±`size_dps` (random sign).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Spikes {
    /// Mean number of spikes per hour.
    pub rate_per_h: f64,
    /// Magnitude of one spike, deg/s.
    pub size_dps: f64,
}

/// The temperature trajectory (shared by the axes and written to `temp_c`): a start temperature,
/// an exponential warm-up rise (self-heating), linear ramps, and optional white noise on the reading.
///
/// `T(t) = start_c + warmup_rise_c·(1 − e^(−t/warmup_time_constant_s)) + Σ ramps(t)`; the bias
/// follows T(t), the `temp_c` column is T(t) plus the reading noise.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TemperatureConfig {
    /// Temperature at t = 0, °C (default 25).
    #[serde(default = "default_reference_c")]
    pub start_c: f64,
    /// Total rise of the exponential warm-up, °C (default 0: none).
    #[serde(default)]
    pub warmup_rise_c: f64,
    /// Time constant of the warm-up, s (default 600).
    #[serde(default = "default_warmup_tau")]
    pub warmup_time_constant_s: f64,
    /// Linear ramps: each changes the temperature by `delta_c` between `start_s` and
    /// `start_s + duration_s` and holds the change afterwards.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ramps: Vec<TemperatureRamp>,
    /// Standard deviation of white noise on the `temp_c` reading, °C (default 0).
    #[serde(default)]
    pub noise_c: f64,
}

fn default_warmup_tau() -> f64 {
    600.0
}

impl Default for TemperatureConfig {
    fn default() -> Self {
        Self { start_c: 25.0, warmup_rise_c: 0.0, warmup_time_constant_s: 600.0, ramps: Vec::new(), noise_c: 0.0 }
    }
}

/// One linear temperature ramp.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TemperatureRamp {
    /// Start of the ramp, s.
    pub start_s: f64,
    /// Length of the ramp, s (0 gives a step).
    pub duration_s: f64,
    /// Change of temperature over the ramp, °C.
    pub delta_c: f64,
}

impl AxisConfig {
    /// Whether no key is set (an empty `[x]` table).
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }

    /// This model with every key that `overrides` sets replaced by its value.
    pub fn merged_with(&self, overrides: &AxisConfig) -> AxisConfig {
        fn pick<T: Clone>(base: &Option<T>, over: &Option<T>) -> Option<T> {
            over.clone().or_else(|| base.clone())
        }
        AxisConfig {
            bias_dps: pick(&self.bias_dps, &overrides.bias_dps),
            arw_deg_rt_h: pick(&self.arw_deg_rt_h, &overrides.arw_deg_rt_h),
            bias_instability: pick(&self.bias_instability, &overrides.bias_instability),
            rrw_deg_h_rt_h: pick(&self.rrw_deg_h_rt_h, &overrides.rrw_deg_h_rt_h),
            ramp_deg_h2: pick(&self.ramp_deg_h2, &overrides.ramp_deg_h2),
            quantization: pick(&self.quantization, &overrides.quantization),
            warmup: pick(&self.warmup, &overrides.warmup),
            temperature_coefficient: pick(&self.temperature_coefficient, &overrides.temperature_coefficient),
            sinusoids: pick(&self.sinusoids, &overrides.sinusoids),
            jumps: pick(&self.jumps, &overrides.jumps),
            spikes: pick(&self.spikes, &overrides.spikes),
        }
    }

    /// ARW N in deg/√s (0 when absent).
    pub fn arw_deg_rt_s(&self) -> f64 {
        self.arw_deg_rt_h.unwrap_or(0.0) / ARW_DEG_RT_H_PER_DEG_RT_S
    }

    /// RRW K in deg/s/√s (0 when absent).
    pub fn rrw_dps_rt_s(&self) -> f64 {
        self.rrw_deg_h_rt_h.unwrap_or(0.0) / RRW_DEG_H_RT_H_PER_DPS_RT_S
    }

    /// Rate ramp R in deg/s² (0 when absent).
    pub fn ramp_dps2(&self) -> f64 {
        self.ramp_deg_h2.unwrap_or(0.0) / (S_PER_H * S_PER_H)
    }

    /// IEEE Std 952 angle quantisation Q in deg at sample rate `rate_hz`: Δ/(fs·√12) for an
    /// angle-mode quantiser, 0 otherwise (a rate-mode quantiser adds white noise instead).
    pub fn quantization_q_deg(&self, rate_hz: f64) -> f64 {
        match &self.quantization {
            Some(q) if q.mode == QuantizationMode::Angle => q.step_dps / (rate_hz * 12f64.sqrt()),
            _ => 0.0,
        }
    }

    fn validate(&self, name: &str) -> Result<(), ConfigError> {
        let bad = |key: &str, problem: &str| ConfigError::Invalid {
            key: format!("{name}.{key}"),
            problem: problem.to_owned(),
        };
        let finite = |key: &str, v: f64| if v.is_finite() { Ok(()) } else { Err(bad(key, "must be finite")) };
        let non_negative = |key: &str, v: f64| {
            if v.is_finite() && v >= 0.0 { Ok(()) } else { Err(bad(key, "must be finite and ≥ 0")) }
        };
        let positive =
            |key: &str, v: f64| if v.is_finite() && v > 0.0 { Ok(()) } else { Err(bad(key, "must be finite and > 0")) };
        if let Some(v) = self.bias_dps {
            finite("bias_dps", v)?;
        }
        if let Some(v) = self.arw_deg_rt_h {
            non_negative("arw_deg_rt_h", v)?;
        }
        if let Some(v) = self.rrw_deg_h_rt_h {
            non_negative("rrw_deg_h_rt_h", v)?;
        }
        if let Some(v) = self.ramp_deg_h2 {
            finite("ramp_deg_h2", v)?;
        }
        match &self.bias_instability {
            Some(BiasInstability::Flicker { b_deg_h, floor_from_s, floor_to_s }) => {
                non_negative("bias_instability.b_deg_h", *b_deg_h)?;
                positive("bias_instability.floor_from_s", *floor_from_s)?;
                positive("bias_instability.floor_to_s", *floor_to_s)?;
                if floor_to_s <= floor_from_s {
                    return Err(bad("bias_instability.floor_to_s", "must be greater than floor_from_s"));
                }
                if floor_to_s / floor_from_s > 1e12 {
                    return Err(bad("bias_instability.floor_to_s", "span over 12 decades"));
                }
            }
            Some(BiasInstability::GaussMarkov { b_deg_h, correlation_time_s }) => {
                non_negative("bias_instability.b_deg_h", *b_deg_h)?;
                positive("bias_instability.correlation_time_s", *correlation_time_s)?;
            }
            None => {}
        }
        if let Some(q) = &self.quantization {
            positive("quantization.step_dps", q.step_dps)?;
        }
        if let Some(w) = &self.warmup {
            finite("warmup.amplitude_dps", w.amplitude_dps)?;
            positive("warmup.time_constant_s", w.time_constant_s)?;
        }
        if let Some(c) = &self.temperature_coefficient {
            finite("temperature_coefficient.dps_per_c", c.dps_per_c)?;
            finite("temperature_coefficient.reference_c", c.reference_c)?;
            non_negative("temperature_coefficient.hysteresis_c", c.hysteresis_c)?;
        }
        for (i, s) in self.sinusoids.iter().flatten().enumerate() {
            finite(&format!("sinusoids[{i}].amplitude_dps"), s.amplitude_dps)?;
            non_negative(&format!("sinusoids[{i}].frequency_hz"), s.frequency_hz)?;
            finite(&format!("sinusoids[{i}].phase_deg"), s.phase_deg)?;
        }
        if let Some(j) = &self.jumps {
            non_negative("jumps.rate_per_h", j.rate_per_h)?;
            non_negative("jumps.size_dps", j.size_dps)?;
        }
        if let Some(s) = &self.spikes {
            non_negative("spikes.rate_per_h", s.rate_per_h)?;
            non_negative("spikes.size_dps", s.size_dps)?;
        }
        Ok(())
    }
}

impl SimConfig {
    /// A run of `duration_s` at `rate_hz` with the same error model `axis` on x, y and z (no
    /// per-axis overrides, no temperature profile, no fixed seed).
    pub fn with_axis(rate_hz: f64, duration_s: f64, axis: AxisConfig) -> Self {
        SimConfig {
            rate_hz,
            duration_s,
            seed: None,
            temperature: TemperatureConfig::default(),
            axis,
            x: AxisConfig::default(),
            y: AxisConfig::default(),
            z: AxisConfig::default(),
        }
    }

    /// Parses a TOML document (unknown keys are errors that name the key and its line).
    pub fn from_toml(text: &str) -> Result<Self, ConfigError> {
        let config: SimConfig =
            toml::from_str(text).map_err(|e| ConfigError::Toml(e.to_string().trim_end().to_owned()))?;
        config.validate()?;
        Ok(config)
    }

    /// The configuration as a TOML document that [`SimConfig::from_toml`] reads back to the same value.
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).expect("a SimConfig always serialises")
    }

    /// The effective model of axis `i` (0 = x, 1 = y, 2 = z): `[axis]` with the axis's keys replaced.
    pub fn axis_model(&self, i: usize) -> AxisConfig {
        let overrides = [&self.x, &self.y, &self.z][i];
        self.axis.merged_with(overrides)
    }

    /// Number of samples in the run: `round(duration_s · rate_hz)`.
    pub fn samples(&self) -> usize {
        (self.duration_s * self.rate_hz).round() as usize
    }

    /// Checks every value's range (sample rate, durations, time constants, sizes).
    pub fn validate(&self) -> Result<(), ConfigError> {
        let bad = |key: &str, problem: &str| ConfigError::Invalid { key: key.to_owned(), problem: problem.to_owned() };
        if !(self.rate_hz.is_finite() && self.rate_hz > 0.0) {
            return Err(bad("rate_hz", "must be finite and > 0"));
        }
        if !(self.duration_s.is_finite() && self.duration_s >= 0.0) {
            return Err(bad("duration_s", "must be finite and ≥ 0"));
        }
        if self.duration_s * self.rate_hz > 1e10 {
            return Err(bad("duration_s", "more than 10^10 samples"));
        }
        let t = &self.temperature;
        for (key, v) in [("temperature.start_c", t.start_c), ("temperature.warmup_rise_c", t.warmup_rise_c)] {
            if !v.is_finite() {
                return Err(bad(key, "must be finite"));
            }
        }
        if !(t.warmup_time_constant_s.is_finite() && t.warmup_time_constant_s > 0.0) {
            return Err(bad("temperature.warmup_time_constant_s", "must be finite and > 0"));
        }
        if !(t.noise_c.is_finite() && t.noise_c >= 0.0) {
            return Err(bad("temperature.noise_c", "must be finite and ≥ 0"));
        }
        for (i, r) in t.ramps.iter().enumerate() {
            if !(r.start_s.is_finite() && r.delta_c.is_finite() && r.duration_s.is_finite() && r.duration_s >= 0.0) {
                return Err(bad(
                    &format!("temperature.ramps[{i}]"),
                    "start_s, delta_c must be finite and duration_s ≥ 0",
                ));
            }
        }
        self.axis.validate("axis")?;
        for (name, axis) in [("x", &self.x), ("y", &self.y), ("z", &self.z)] {
            axis.validate(name)?;
        }
        Ok(())
    }
}
