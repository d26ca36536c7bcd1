//! Self-test of the diagnosis: "real" recordings made by the simulator with one known effect
//! added, diagnosed without being told which, and the confusion table of what was named.
//!
//! **Base model**: the x axis of the `adis16405` preset (N = 2.40 deg/√h, flicker B = 30 deg/h
//! from 1 to 5000 s, K = 20 deg/h/√h, bias 0.4017 deg/s) without its 0.005 deg/s quantiser
//! (quantisation is a candidate effect), at 10 Hz, 10,000 s by default (the length of the real
//! ADIS16405 runs). Every case records a temperature that moves like an air-conditioned room's:
//! from 24 °C, +3 °C of self-heating (time constant 900 s), then ramps of ±2.5 °C over 3 % of the
//! run at 1/6, 2/6, … 5/6 of it, alternately up and down (the last two inside the hold-out part),
//! read with 0.02 °C noise; only the `temperature` case makes the bias depend on it.
//!
//! **Injected effects** (magnitudes drawn per case, uniform in the ranges, times `scale`; for a
//! MEMS gyro whose white noise is 0.126 deg/s per 10 Hz sample and whose bias instability is
//! 0.008 deg/s, realistic and large enough to be seen in 10,000 s):
//!
//! | effect | magnitude |
//! |---|---|
//! | `warmup` | ±0.1–0.2 deg/s decaying with 120–360 s |
//! | `temperature` | ±0.01–0.02 deg/s/°C (the ADIS16405 data sheet's order is 0.01) |
//! | `ramp` | ±0.2–0.4 deg/s over the run |
//! | `sinusoid` | 0.01–0.03 deg/s at 0.002–0.5 Hz (log-uniform), any phase |
//! | `bias_jumps` | 2–6 per hour, each N(0, (0.04–0.08 deg/s)²) |
//! | `spikes` | 10–40 per hour of ±1–2 deg/s |
//! | `quantization` | a 0.02–0.05 deg/s rate quantiser |
//! | `gauss_markov` | σ 0.02–0.04 deg/s, correlation time 2–30 s (log-uniform) |
//!
//! **Controls**: no effect (must report no significant gap) and a linear chirp of 0.02–0.03 deg/s
//! sweeping 0.01 → 0.2 Hz over the run, which no effect of the catalogue describes (must report an
//! unexplained gap).

use std::f64::consts::TAU;

use serde::Serialize;

use super::SimgapError;
use super::diagnose::{Baseline, Recording, Settings, Verdict, diagnose};
use super::params::{EffectKind, EffectParams};
use crate::model::rng::Rng;
use crate::model::rng::splitmix64;
use crate::sim::{
    AxisConfig, BiasInstability, Generator, Jumps, Preset, Quantization, QuantizationMode, SimConfig, Sinusoid, Spikes,
    TemperatureCoefficient, TemperatureConfig, TemperatureRamp, Warmup,
};

/// Sample rate of the self-test recordings, Hz.
pub const RATE_HZ: f64 = 10.0;
/// Chirp sweep of the out-of-catalogue control, Hz.
pub const CHIRP_HZ: (f64, f64) = (0.01, 0.2);

/// What a self-test recording has on top of the base model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Injected {
    /// One effect of the catalogue.
    Effect(EffectKind),
    /// Nothing.
    Nothing,
    /// A chirp, outside the catalogue.
    OutOfCatalogue,
}

impl Injected {
    /// Every kind of case: the eight effects, then the two controls.
    pub fn all() -> Vec<Injected> {
        let mut v: Vec<Injected> = EffectKind::ALL.iter().map(|&k| Injected::Effect(k)).collect();
        v.push(Injected::Nothing);
        v.push(Injected::OutOfCatalogue);
        v
    }

    /// The kind of case named `name` (an effect name, `none` or `chirp`).
    pub fn from_name(name: &str) -> Option<Injected> {
        match name {
            "none" => Some(Injected::Nothing),
            "chirp" => Some(Injected::OutOfCatalogue),
            _ => EffectKind::ALL.iter().find(|k| k.name() == name).map(|&k| Injected::Effect(k)),
        }
    }

    /// Row name in the confusion table.
    pub fn name(self) -> &'static str {
        match self {
            Injected::Effect(k) => k.name(),
            Injected::Nothing => "none (control)",
            Injected::OutOfCatalogue => "chirp (control)",
        }
    }

    /// Whether a diagnosis outcome is the right one for this case.
    pub fn is_correct(self, verdict: Verdict, named: Option<EffectKind>) -> bool {
        match self {
            Injected::Effect(k) => matches!(verdict, Verdict::Explained | Verdict::PartlyExplained) && named == Some(k),
            Injected::Nothing => verdict == Verdict::NoSignificantGap,
            Injected::OutOfCatalogue => verdict == Verdict::Unexplained,
        }
    }
}

/// Settings of the self-test.
#[derive(Debug, Clone, PartialEq)]
pub struct SelftestSettings {
    /// Seeded cases per kind of case.
    pub cases: usize,
    /// Length of each recording, s.
    pub duration_s: f64,
    /// Factor on every injected magnitude (1 = the table in the module docs).
    pub scale: f64,
    /// Seed of everything.
    pub seed: u64,
    /// Settings of each diagnosis (its seed is derived per case).
    pub diagnosis: Settings,
}

/// One self-test case and what the diagnosis said.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CaseResult {
    /// What was injected.
    pub injected: Injected,
    /// Case number within its kind.
    pub case: usize,
    /// The injected magnitudes.
    pub magnitudes: String,
    /// The verdict.
    pub verdict: Verdict,
    /// The first effect chosen.
    pub named: Option<EffectKind>,
    /// Whether that is right.
    pub correct: bool,
    /// Gap before / after on the training part.
    pub gap_train: (f64, f64),
    /// Gap before / after on the hold-out part.
    pub gap_hold: (f64, f64),
    /// The fitted parameters of the named effect.
    pub named_params: Vec<(&'static str, f64)>,
}

/// The base axis model (module docs).
pub fn base_axis() -> AxisConfig {
    let mut axis = Preset::Adis16405.config().axis_model(0);
    axis.quantization = None;
    axis
}

/// The recorded temperature trajectory of a run of `duration_s` (module docs).
pub fn temperature_profile(duration_s: f64) -> TemperatureConfig {
    // Self-heating, then an air-conditioned room cycling by ±2.5 °C: a ramp of 3 % of the run
    // every 1/6 of it, alternately up and down (the last two inside the hold-out part).
    let ramps = (1..6)
        .map(|k| TemperatureRamp {
            start_s: k as f64 / 6.0 * duration_s,
            duration_s: 0.03 * duration_s,
            delta_c: if k % 2 == 1 { 2.5 } else { -2.5 },
        })
        .collect();
    TemperatureConfig { start_c: 24.0, warmup_rise_c: 3.0, warmup_time_constant_s: 900.0, ramps, noise_c: 0.02 }
}

/// The seed of case `case` of kind `injected`.
pub fn case_seed(seed: u64, injected: Injected, case: usize) -> u64 {
    let kind = Injected::all().iter().position(|&i| i == injected).unwrap_or(0) as u64;
    splitmix64(seed ^ splitmix64(kind * 1_000_003 + case as u64 + 1))
}

/// A self-test recording: (rate deg/s, temperature °C, magnitudes).
pub fn synthesize(
    injected: Injected,
    duration_s: f64,
    scale: f64,
    seed: u64,
) -> Result<(Vec<f64>, Vec<f64>, String), SimgapError> {
    let mut draw = Rng::new(seed);
    let sign = |r: &mut Rng| if r.next_u64() >> 63 == 0 { 1.0 } else { -1.0 };
    let mut axis = base_axis();
    let mut extra = None;
    let magnitudes = match injected {
        Injected::Effect(EffectKind::Warmup) => {
            let (a, t) = (sign(&mut draw) * scale * draw.uniform(0.1, 0.2), draw.uniform(120.0, 360.0));
            axis.warmup = Some(Warmup { amplitude_dps: a, time_constant_s: t });
            format!("amplitude {a:.4} deg/s, time constant {t:.0} s")
        }
        Injected::Effect(EffectKind::Temperature) => {
            let c = sign(&mut draw) * scale * draw.uniform(0.01, 0.02);
            axis.temperature_coefficient =
                Some(TemperatureCoefficient { dps_per_c: c, reference_c: 25.0, hysteresis_c: 0.0 });
            format!("{c:.4} deg/s/°C")
        }
        Injected::Effect(EffectKind::Ramp) => {
            let total = sign(&mut draw) * scale * draw.uniform(0.2, 0.4);
            axis.ramp_deg_h2 = Some(total / duration_s * 3600.0 * 3600.0);
            format!("{total:.4} deg/s over the run")
        }
        Injected::Effect(EffectKind::Sinusoid) => {
            let (a, f, p) = (
                scale * draw.uniform(0.01, 0.03),
                0.002 * 250f64.powf(draw.uniform(0.0, 1.0)),
                draw.uniform(0.0, 360.0),
            );
            axis.sinusoids = Some(vec![Sinusoid { amplitude_dps: a, frequency_hz: f, phase_deg: p }]);
            format!("amplitude {a:.4} deg/s at {f:.4} Hz")
        }
        Injected::Effect(EffectKind::BiasJumps) => {
            let (r, s) = (draw.uniform(2.0, 6.0), scale * draw.uniform(0.04, 0.08));
            axis.jumps = Some(Jumps { rate_per_h: r, size_dps: s });
            format!("{r:.1} per hour, size sd {s:.3} deg/s")
        }
        Injected::Effect(EffectKind::Spikes) => {
            let (r, s) = (draw.uniform(10.0, 40.0), scale * draw.uniform(1.0, 2.0));
            axis.spikes = Some(Spikes { rate_per_h: r, size_dps: s });
            format!("{r:.0} per hour of ±{s:.2} deg/s")
        }
        Injected::Effect(EffectKind::Quantization) => {
            let s = scale * draw.uniform(0.02, 0.05);
            axis.quantization = Some(Quantization { step_dps: s, mode: QuantizationMode::Rate });
            format!("step {s:.4} deg/s")
        }
        Injected::Effect(EffectKind::GaussMarkov) => {
            let (sigma, t) = (scale * draw.uniform(0.02, 0.04), 2.0 * 15f64.powf(draw.uniform(0.0, 1.0)));
            // The simulator's Gauss–Markov slot is the bias instability; keep the flicker floor and
            // add the process by a second axis model.
            extra = Some(Extra::GaussMarkov(sigma, t));
            format!("sigma {sigma:.4} deg/s, correlation time {t:.1} s")
        }
        Injected::Nothing => "none".into(),
        Injected::OutOfCatalogue => {
            let a = scale * draw.uniform(0.02, 0.03);
            extra = Some(Extra::Chirp(a));
            format!("chirp {a:.4} deg/s, {} to {} Hz", CHIRP_HZ.0, CHIRP_HZ.1)
        }
    };
    let config = SimConfig {
        rate_hz: RATE_HZ,
        duration_s,
        seed: None,
        temperature: temperature_profile(duration_s),
        axis: AxisConfig::default(),
        x: axis,
        y: AxisConfig::default(),
        z: extra_axis(extra),
    };
    let out = Generator::generate(&config, seed)?;
    let crate::sim::SimOutput { t_s, temp_c, axes: [x, _, z] } = out;
    let mut rate = x.raw;
    match extra {
        Some(Extra::Chirp(a)) => {
            let sweep = (CHIRP_HZ.1 - CHIRP_HZ.0) / duration_s;
            for (v, t) in rate.iter_mut().zip(&t_s) {
                *v += a * (TAU * (CHIRP_HZ.0 * t + 0.5 * sweep * t * t)).sin();
            }
        }
        Some(Extra::GaussMarkov(..)) => {
            for (v, g) in rate.iter_mut().zip(&z.raw) {
                *v += g;
            }
        }
        None => {}
    }
    Ok((rate, temp_c, magnitudes))
}

/// An addition that is not a key of the x axis model.
#[derive(Debug, Clone, Copy)]
enum Extra {
    /// Chirp amplitude, deg/s.
    Chirp(f64),
    /// Gauss–Markov σ (deg/s) and correlation time (s), simulated on the z axis and added.
    GaussMarkov(f64, f64),
}

fn extra_axis(extra: Option<Extra>) -> AxisConfig {
    match extra {
        Some(Extra::GaussMarkov(sigma, t)) => AxisConfig {
            bias_instability: Some(BiasInstability::GaussMarkov {
                b_deg_h: sigma * crate::sim::terms::GAUSS_MARKOV_PEAK / crate::sim::terms::FLICKER_FLOOR * 3600.0,
                correlation_time_s: t,
            }),
            ..AxisConfig::default()
        },
        _ => AxisConfig::default(),
    }
}

/// Runs case `case` of kind `injected`.
pub fn run_case(injected: Injected, case: usize, settings: &SelftestSettings) -> Result<CaseResult, SimgapError> {
    let seed = case_seed(settings.seed, injected, case);
    let (rate, temp, magnitudes) = synthesize(injected, settings.duration_s, settings.scale, seed)?;
    let recording = Recording { rate: &rate, rate_hz: RATE_HZ, temp_c: Some(&temp) };
    let diagnosis_settings = Settings { seed: splitmix64(seed ^ 0x5137_6a70), ..settings.diagnosis.clone() };
    let d = diagnose(&recording, &Baseline::Fitted, &diagnosis_settings)?;
    let named = d.chosen.first().copied();
    let named_params = named
        .and_then(|k| d.effects.iter().find(|e| e.kind == k))
        .and_then(|e| e.params.as_ref())
        .map_or_else(Vec::new, EffectParams::named);
    Ok(CaseResult {
        injected,
        case,
        magnitudes,
        verdict: d.verdict,
        named,
        correct: injected.is_correct(d.verdict, named),
        gap_train: (d.before.train.score.gap, d.after.train.score.gap),
        gap_hold: (d.before.hold.score.gap, d.after.hold.score.gap),
        named_params,
    })
}

/// Runs every case (`settings.cases` of each kind in `kinds`), calling `progress` after each.
pub fn run_selftest(
    settings: &SelftestSettings,
    kinds: &[Injected],
    mut progress: impl FnMut(&CaseResult),
) -> Result<Vec<CaseResult>, SimgapError> {
    let mut results = Vec::new();
    for &injected in kinds {
        for case in 0..settings.cases {
            let r = run_case(injected, case, settings)?;
            progress(&r);
            results.push(r);
        }
    }
    Ok(results)
}

/// Columns of the confusion table: the eight effects, "no gap", "unexplained".
pub const CONFUSION_COLUMNS: usize = EffectKind::ALL.len() + 2;

/// The column of an outcome in the confusion table.
pub fn confusion_column(verdict: Verdict, named: Option<EffectKind>) -> usize {
    match (verdict, named) {
        (Verdict::Explained | Verdict::PartlyExplained, Some(k)) => {
            EffectKind::ALL.iter().position(|&e| e == k).unwrap_or(0)
        }
        (Verdict::NoSignificantGap, _) => EffectKind::ALL.len(),
        _ => EffectKind::ALL.len() + 1,
    }
}

/// The confusion table: one row per kind of case (in [`Injected::all`] order) with the count of
/// each outcome column.
pub fn confusion(results: &[CaseResult]) -> Vec<(Injected, [usize; CONFUSION_COLUMNS])> {
    Injected::all()
        .into_iter()
        .map(|injected| {
            let mut row = [0; CONFUSION_COLUMNS];
            for r in results.iter().filter(|r| r.injected == injected) {
                row[confusion_column(r.verdict, r.named)] += 1;
            }
            (injected, row)
        })
        .filter(|(_, row)| row.iter().sum::<usize>() > 0)
        .collect()
}
