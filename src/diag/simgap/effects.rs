//! The catalogue of candidate unmodelled effects: what each is, how it is fitted on the training
//! part ([`fit_effect`]) and how it enters the simulated model ([`EffectParams::apply`]; the
//! effects and their fitted parameters are in [`super::params`]).
//!
//! | effect | fitted on the training part | in the simulation |
//! |---|---|---|
//! | `warmup` | A·e^(−t/T): T on a log grid (duration/300 … duration), A and an offset by least squares on 1 s means | `warmup` |
//! | `temperature` | slope of 1 s means of the rate on 1 s means of `temp_c` | bias ∝ recorded `temp_c` |
//! | `ramp` | least-squares slope | `ramp_deg_h2` |
//! | `sinusoid` | strongest line of the Hann periodogram against its local median, frequency refined, amplitude and phase by least squares; where the whole part's rectangular periodogram ([`super::fast_line`]) peaks elsewhere, a fit at that line too, the one that evaluates better kept | `sinusoids` |
//! | `bias_jumps` | steps where adjacent 60 s means differ by more than 4.5 robust σ, at a peak of that difference ([`super::fit_events`]), or, where the step process' nested test passes ([`super::nested_jumps`]) and its segmentation has more change points than those, its change points where that fit evaluates better; rate and size counted over the hold-out's steps too | Poisson jumps of the detected rate and RMS size |
//! | `spikes` | samples more than 5.5 robust σ from the median of their 5-sample neighbourhood, spread in time as a Poisson process's events | Poisson spikes of the detected rate and mean size |
//! | `quantization` | the grid step of the values (when they sit on one) | rate-mode quantiser |
//! | `gauss_markov` | a Gauss–Markov column in the Allan fit ([`super::baseline`]) | an extra Gauss–Markov process |
//!
//! The fits live in [`super::fit_time`], [`super::fit_spectral`] and [`super::fit_events`].

use super::baseline::fit_noise_terms;
use super::fit_events::{fit_jumps, fit_quantization, fit_spikes};
use super::fit_spectral::{fit_sinusoid, fit_sinusoid_candidates};
use super::fit_time::{fit_ramp, fit_temperature, fit_warmup};
use super::params::{EffectKind, EffectParams, Fitted, FittedEffect};

/// The training part of a recording: rate samples from t = 0 at `rate_hz`, with the temperature
/// when the recording has one.
#[derive(Debug, Clone, Copy)]
pub struct TrainingData<'a> {
    /// Rate, deg/s.
    pub x: &'a [f64],
    /// Sample rate, Hz.
    pub rate_hz: f64,
    /// Temperature, °C (same length as `x`).
    pub temp_c: Option<&'a [f64]>,
    /// The held-out rest of the recording, rate in deg/s: the bias jumps count their steps there
    /// too ([`super::fit_events::fit_jumps`]); empty when there is none (the
    /// refit's simulated training parts).
    pub holdout: &'a [f64],
}

/// The candidate fits of `kind` on the training part: one ([`fit_effect`]), except for the
/// sinusoid, whose two line searches may find different lines
/// ([`super::fit_spectral::fit_sinusoid_candidates`]); the diagnosis keeps the candidate whose
/// model evaluates better.
pub fn fit_candidates(kind: EffectKind, data: &TrainingData<'_>) -> Vec<Fitted> {
    match kind {
        EffectKind::Sinusoid => fit_sinusoid_candidates(data.x, data.rate_hz),
        _ => vec![fit_effect(kind, data)],
    }
}

/// Fits `kind` on the training part.
pub fn fit_effect(kind: EffectKind, data: &TrainingData<'_>) -> Fitted {
    match kind {
        EffectKind::Warmup => fit_warmup(data.x, data.rate_hz),
        EffectKind::Temperature => match data.temp_c {
            Some(temp) => fit_temperature(data.x, temp, data.rate_hz),
            None => Fitted::NotApplicable("the recording has no temperature column (temp_c)".into()),
        },
        EffectKind::Ramp => fit_ramp(data.x, data.rate_hz),
        EffectKind::Sinusoid => fit_sinusoid(data.x, data.rate_hz),
        EffectKind::BiasJumps => fit_jumps(data.x, data.holdout, data.rate_hz),
        EffectKind::Spikes => fit_spikes(data.x, data.rate_hz),
        EffectKind::Quantization => fit_quantization(data.x),
        EffectKind::GaussMarkov => {
            match fit_noise_terms(data.x, data.rate_hz, data.x.len() as f64 / data.rate_hz, true) {
                Ok(terms) => match terms.gauss_markov {
                    Some((sigma_dps, correlation_time_s)) if sigma_dps > 0.0 => Fitted::Found(FittedEffect {
                        params: EffectParams::GaussMarkov { sigma_dps, correlation_time_s },
                        training_part: None,
                    }),
                    _ => Fitted::NotApplicable("no Gauss–Markov term improves the Allan fit".into()),
                },
                Err(e) => Fitted::NotApplicable(format!("Allan fit failed: {e}")),
            }
        }
    }
}
