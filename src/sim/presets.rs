//! Built-in simulator presets. Each is also written out as `configs/sim/<name>.toml` (a test keeps
//! the two equal), so a preset is a starting point for a config file.

use super::config::{
    AxisConfig, BiasInstability, Quantization, QuantizationMode, SimConfig, TemperatureCoefficient, TemperatureConfig,
    Warmup,
};

/// A named simulator configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Preset {
    /// Resembles the data of the seed paper (Sensors 2017, 17, 2335, §4.1): x-axis random drift of a
    /// preheated laboratory MEMS IMU, 10 Hz, 1500 s, standard deviation ≈ 0.0035 deg/s (Table 2:
    /// 0.00354, 0.00412, 0.00328 deg/s), correlated over about a second (the C-C method gives τ = 10
    /// samples). The paper gives no noise coefficients; these are chosen to match those figures:
    ///
    /// - white noise N = 0.02 deg/√h (σ = 0.00105 deg/s per 10 Hz sample);
    /// - bias instability B = 11 deg/h as a Gauss–Markov process with T = 2 s (stationary
    ///   σ = 0.664·B/0.6174 = 11.8 deg/h = 0.0033 deg/s);
    /// - rate random walk K = 20 deg/h/√h (the slow wander, ≈ 0.0012 deg/s within 1500 s);
    /// - no bias, no quantisation, constant 25 °C (deterministic errors were removed in the paper).
    ///
    /// Over 1500 s (mean of 20 seeds) the truth drift has std 0.0035 deg/s (±0.0003 between seeds)
    /// and the raw output 0.0037 deg/s. The three axes share the model (independent noise).
    Paper,
    /// Resembles the static ADIS16405 recording `adis16405_run1_10hz.csv` (shared data, University of
    /// Calgary via SMAC-Group/imudata): 10 Hz block means, 10,000 s. Fitted per axis to the overlapping
    /// Allan deviation of run 1 (gx → x, gy → y, gz → z; weighted least squares over τ = 0.1 … 2500 s
    /// of N², B², K² for a grid of flicker spans):
    ///
    /// | axis | N deg/√h | B deg/h (flicker floor span) | K deg/h/√h | bias deg/s |
    /// |---|---|---|---|---|
    /// | x | 2.40 | 30 (1 … 5000 s) | 20 | 0.4017 |
    /// | y | 2.52 | 36 (1 … 20 s) | 140 | −0.4158 |
    /// | z | 2.28 | 28 (1 … 5000 s) | 170 | −0.2935 |
    ///
    /// Quantisation: each sample rounded to 0.005 deg/s (rate mode), the grid of the 10 Hz file
    /// (means of ten 0.05 deg/s LSB samples). No temperature channel in the recording: constant 25 °C.
    Adis16405,
    /// A consumer InvenSense MPU-6050 at ±250 deg/s, from datasheet-typical figures (not fitted to a
    /// recording): 100 Hz, 1800 s.
    ///
    /// - white noise 0.005 deg/s/√Hz → N = 0.30 deg/√h;
    /// - bias instability B = 12 deg/h, flicker with a flat floor from 2 s to 500 s;
    /// - rate random walk K = 8 deg/h/√h;
    /// - LSB 1/131 deg/s, angle mode;
    /// - zero-rate offsets x 1.2, y −0.8, z 0.45 deg/s;
    /// - warm-up transient 0.08 deg/s decaying with 120 s (x; other axes scaled);
    /// - temperature: self-heating from 22 °C by +8 °C with a 400 s time constant; bias coefficient
    ///   0.02 (x), −0.015 (y), 0.01 (z) deg/s/°C around 25 °C with 0.4 °C hysteresis; reading noise
    ///   0.02 °C.
    Mpu6050,
}

impl Preset {
    /// All presets.
    pub const ALL: [Preset; 3] = [Preset::Paper, Preset::Adis16405, Preset::Mpu6050];

    /// The preset's name (as on the command line and in `configs/sim/`).
    pub fn name(self) -> &'static str {
        match self {
            Preset::Paper => "paper",
            Preset::Adis16405 => "adis16405",
            Preset::Mpu6050 => "mpu6050",
        }
    }

    /// The preset of that name.
    pub fn from_name(name: &str) -> Option<Preset> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    /// The configuration.
    pub fn config(self) -> SimConfig {
        match self {
            Preset::Paper => paper(),
            Preset::Adis16405 => adis16405(),
            Preset::Mpu6050 => mpu6050(),
        }
    }
}

fn paper() -> SimConfig {
    SimConfig {
        rate_hz: 10.0,
        duration_s: 1500.0,
        seed: None,
        temperature: TemperatureConfig::default(),
        axis: AxisConfig {
            arw_deg_rt_h: Some(0.02),
            bias_instability: Some(BiasInstability::GaussMarkov { b_deg_h: 11.0, correlation_time_s: 2.0 }),
            rrw_deg_h_rt_h: Some(20.0),
            ..AxisConfig::default()
        },
        x: AxisConfig::default(),
        y: AxisConfig::default(),
        z: AxisConfig::default(),
    }
}

fn adis16405() -> SimConfig {
    let axis = |bias: f64, n: f64, b: f64, floor_to_s: f64, k: f64| AxisConfig {
        bias_dps: Some(bias),
        arw_deg_rt_h: Some(n),
        bias_instability: Some(BiasInstability::Flicker { b_deg_h: b, floor_from_s: 1.0, floor_to_s }),
        rrw_deg_h_rt_h: Some(k),
        ..AxisConfig::default()
    };
    SimConfig {
        rate_hz: 10.0,
        duration_s: 10_000.0,
        seed: None,
        temperature: TemperatureConfig::default(),
        axis: AxisConfig {
            quantization: Some(Quantization { step_dps: 0.005, mode: QuantizationMode::Rate }),
            ..AxisConfig::default()
        },
        x: axis(0.4017, 2.40, 30.0, 5000.0, 20.0),
        y: axis(-0.4158, 2.52, 36.0, 20.0, 140.0),
        z: axis(-0.2935, 2.28, 28.0, 5000.0, 170.0),
    }
}

fn mpu6050() -> SimConfig {
    let axis = |bias: f64, warmup: f64, coefficient: f64| AxisConfig {
        bias_dps: Some(bias),
        warmup: Some(Warmup { amplitude_dps: warmup, time_constant_s: 120.0 }),
        temperature_coefficient: Some(TemperatureCoefficient {
            dps_per_c: coefficient,
            reference_c: 25.0,
            hysteresis_c: 0.4,
        }),
        ..AxisConfig::default()
    };
    SimConfig {
        rate_hz: 100.0,
        duration_s: 1800.0,
        seed: None,
        temperature: TemperatureConfig {
            start_c: 22.0,
            warmup_rise_c: 8.0,
            warmup_time_constant_s: 400.0,
            ramps: Vec::new(),
            noise_c: 0.02,
        },
        axis: AxisConfig {
            arw_deg_rt_h: Some(0.30),
            bias_instability: Some(BiasInstability::Flicker { b_deg_h: 12.0, floor_from_s: 2.0, floor_to_s: 500.0 }),
            rrw_deg_h_rt_h: Some(8.0),
            quantization: Some(Quantization { step_dps: 1.0 / 131.0, mode: QuantizationMode::Angle }),
            ..AxisConfig::default()
        },
        x: axis(1.2, 0.08, 0.02),
        y: axis(-0.8, -0.05, -0.015),
        z: axis(0.45, 0.03, 0.01),
    }
}
