//! The statistics on which a simulation is compared with a recording (docs/design.md "Sim-to-real
//! diagnosis"). One [`StatLayout`] per part (training, hold-out) fixes which statistics there are,
//! so the real part and every simulated member give vectors of the same shape:
//!
//! - **Allan deviation** (overlapping, [`crate::diag::allan::oadev`]) at m = 1, 2, 4, … samples up
//!   to N/8, in three groups: short (τ < 1 s), mid (1–100 s), long (τ > 100 s); compared in log10.
//! - **PSD bands**: Welch density ([`crate::diag::psd`], Hann, segments of up to 4096 samples and at
//!   most N/4) averaged over octave bands of bins [2^k, 2^(k+1)); log10.
//! - **Spectral line**: the largest ratio of a Welch bin to the median of the 16 bins around it
//!   (a sinusoid stands out; broadband noise does not), and, where the part is long enough, the
//!   strongest line of its one full-length periodogram ([`super::fast_line`]: a stable line's
//!   whole evidence, which Welch's segment average divides); both as they are, scored under a
//!   Gumbel law ([`Scale::Maximum`]).
//! - **Distribution**: the kurtosis of increments over one sample and of the means of 1 s, 10 s and
//!   60 s blocks (where at least 40 blocks fit): spikes raise the first, bias jumps the others; and,
//!   when the recording sits on a grid of step Δ, the grid coherence |mean(e^(2πi·x/Δ))| (1 on the
//!   grid, ≈ N^(−1/2) off it); log10.
//! - **Compensation**: the project's cheapest honest compensation figure, the persistence
//!   predictor x̂[t+1] = d\[t] on the batch-denoised series d (db4, 3 levels): its RMSE against d
//!   and against the raw series (the residual a user would be left with); log10.
//! - **Bias trajectory**: the means of 10 equal blocks and of 5 blocks of growing length at the
//!   start ([0, N/64), [N/64, N/32), … [N/8, N/4)), each minus the part's mean, deg/s (linear):
//!   where in time the bias moves (warm-up, ramps, temperature steps); and the RMS residual of the
//!   10 block means about their least-squares line (log10): a deterministic trend is smooth, a
//!   random walk that reaches the same Allan deviation wanders about its line.
//! - **Effect detectors** — the fits of the effects, used as matched filters: the amplitude of the
//!   best warm-up exponential from the part's start ([`super::fit_time::warmup_fit`], deg/s), the
//!   change over the part of the least-squares line of the 1 s means
//!   ([`super::fit_time::ramp_change`], deg/s: the ramp's; a line through the bias trajectory,
//!   so in its own group [`Group::Derived`], outside the gap), the strongest spectral line of the
//!   1 s means against its neighbours (the full-length periodogram
//!   of [`super::fit_spectral::LineSearch`] with the neighbours' reach: from the 17th bin of the
//!   zero-padded periodogram, 9–17 cycles per part by its length; log10), the strongest step of
//!   the jump detector in robust σ ([`super::fit_events::StepScores`], log10), the step kurtosis
//!   ([`super::fit_events::step_kurtosis`], log10; in [`Group::Derived`], outside the gap, so that
//!   adding it moved no other diagnosis: the gap already holds the kurtosis of block increments)
//!   and, when the recording has a temperature, the slope of the rate on it
//!   ([`super::fit_time::temperature_slope`], deg/s/°C; every member sees the recorded
//!   temperature).

use serde::Serialize;

use super::SimgapError;
use super::fast_line::FastLinePlan;
use super::fit_events::{StepScores, step_kurtosis};
use super::fit_spectral::{LineSearch, Reach};
use super::fit_time::{WarmupPlan, ramp_change, temperature_slope};
use super::robust::{block_means, kurtosis, linear_fit};
use crate::diag::allan::{Taus, oadev};
use crate::diag::psd::welch;
use crate::model::baselines::Persistence;
use crate::model::metrics::median;
use crate::model::metrics::rmse;
use crate::model::{Fit, predict_from};
use crate::wavelet::{DenoiseConfig, denoise_batch};

/// Fewest samples a part may have.
pub const MIN_PART_SAMPLES: usize = 512;
/// Longest Welch segment.
const MAX_SEGMENT: usize = 4096;
/// Shortest Welch segment.
const MIN_SEGMENT: usize = 64;
/// Bins on each side of a bin in the spectral-line background.
const LINE_HALF_WINDOW: usize = 8;
/// Lowest bin searched for a spectral line.
const LINE_MIN_BIN: usize = 4;
/// Block lengths (s) of the increment kurtosis beyond one sample.
const KURTOSIS_BLOCKS_S: [f64; 3] = [1.0, 10.0, 60.0];
/// Fewest blocks an increment kurtosis needs.
const KURTOSIS_MIN_BLOCKS: usize = 40;
/// Equal blocks of the bias trajectory.
const TRAJECTORY_BLOCKS: usize = 10;
/// Early blocks of growing length: [N/2^(k+1), N/2^k) for k from 6 down to 2, and [0, N/64).
const EARLY_BLOCKS: u32 = 6;
/// Boundaries of the Allan groups, s.
pub(super) const ALLAN_SHORT_BELOW_S: f64 = 1.0;
const ALLAN_LONG_ABOVE_S: f64 = 100.0;

/// The group of a statistic. The scalar gap averages |z| within each group, then over the groups,
/// so a group of many points (the Allan τ grid) weighs as much as a single-number group.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Group {
    /// Allan deviation, τ < 1 s.
    AllanShort,
    /// Allan deviation, 1 s ≤ τ ≤ 100 s.
    AllanMid,
    /// Allan deviation, τ > 100 s.
    AllanLong,
    /// Welch PSD in octave bands.
    Psd,
    /// Strongest spectral line.
    SpectralLine,
    /// Increment kurtosis and grid coherence.
    Distribution,
    /// Persistence compensation on the denoised series.
    Compensation,
    /// Means of 10 equal blocks in time, and their roughness about a line.
    Trajectory,
    /// Means of the blocks of growing length at the start.
    EarlyTrajectory,
    /// Effect detectors (warm-up amplitude, slow line, strongest step, temperature slope).
    Detectors,
    /// Matched filters that are functions of statistics already in the gap (the ramp's change, a
    /// line through the bias trajectory's block means), or close kin of them (the step kurtosis,
    /// of the increment kurtosis): in the vector for the detector test
    /// ([`super::greedy::detector_test`]) and the report's *where*, not in the gap or the score,
    /// which would count the same evidence twice.
    Derived,
}

impl Group {
    /// Every group the gap and the score average over, in report order ([`Group::Derived`] is not
    /// one of them).
    pub const ALL: [Group; 10] = [
        Group::AllanShort,
        Group::AllanMid,
        Group::AllanLong,
        Group::Psd,
        Group::SpectralLine,
        Group::Distribution,
        Group::Compensation,
        Group::Trajectory,
        Group::EarlyTrajectory,
        Group::Detectors,
    ];

    /// A short readable name.
    pub fn name(self) -> &'static str {
        match self {
            Group::AllanShort => "allan short (tau < 1 s)",
            Group::AllanMid => "allan mid (1-100 s)",
            Group::AllanLong => "allan long (tau > 100 s)",
            Group::Psd => "psd bands",
            Group::SpectralLine => "spectral line",
            Group::Distribution => "distribution",
            Group::Compensation => "compensation",
            Group::Trajectory => "bias trajectory",
            Group::EarlyTrajectory => "early bias trajectory",
            Group::Detectors => "effect detectors",
            Group::Derived => "derived matched filters (not in the gap)",
        }
    }
}

/// How a statistic is compared: its log10 (positive scale quantities), its value, or its value
/// under the law of a maximum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Scale {
    /// Compared as log10 of the value.
    Log10,
    /// Compared as is.
    Linear,
    /// A maximum over many bins or positions (the strongest spectral line), compared as is,
    /// above its median under a Gumbel law fitted to the members ([`super::band::Band::z_on`]):
    /// its long upper tail does not pass for an outlier, as it did on the log10 scale.
    Maximum,
}

impl Scale {
    /// A natural value (deg/s, (deg/s)²/Hz, a ratio, …) on this comparison scale.
    pub fn of(self, natural: f64) -> f64 {
        match self {
            Scale::Log10 => log10(natural),
            Scale::Linear | Scale::Maximum => natural,
        }
    }
}

/// Comparison scale of the strongest spectral line (a maximum over the PSD's bins). The effect
/// detectors that are maxima too (the slow line, the strongest step) stay on log10: their
/// own-null tests were set on those scores, and scoring them as maxima gained nothing on tuning
/// seeds 1100–1209 (85 against 86 of 110).
const SPECTRAL_LINE_SCALE: Scale = Scale::Maximum;

/// What one entry of a statistics vector is.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StatInfo {
    /// Kind: `allan_deviation`, `psd`, `spectral_line`, `fast_line`, `kurtosis`, `quantisation`,
    /// `compensation`, `bias_trajectory`, `trajectory_roughness`, `warmup_amplitude`,
    /// `ramp_change`, `slow_line`, `strongest_step`, `step_kurtosis` or `temperature_slope`.
    pub statistic: &'static str,
    /// Which τ, frequency band, scale or time span.
    pub band: String,
    /// Group for the gap.
    pub group: Group,
    /// Comparison scale.
    pub scale: Scale,
    /// Unit of the natural value.
    pub unit: &'static str,
    /// Abscissa for plots: τ (s), band centre (Hz) or block centre (s); NaN for the others.
    pub x: f64,
}

impl StatInfo {
    /// The natural value (deg/s, (deg/s)²/Hz, …) of a value on the comparison scale.
    pub fn natural(&self, v: f64) -> f64 {
        match self.scale {
            Scale::Log10 => 10f64.powf(v),
            Scale::Linear | Scale::Maximum => v,
        }
    }
}

/// The statistics of one part of a series: which there are and how to compute them.
#[derive(Debug, Clone)]
pub struct StatLayout {
    info: Vec<StatInfo>,
    rate_hz: f64,
    len: usize,
    allan_m: Vec<usize>,
    psd_segment: usize,
    psd_bands: Vec<(usize, usize)>,
    /// The full-length line search, where the part is long enough for it
    /// ([`super::fast_line::reaches`]).
    fast_line: Option<FastLinePlan>,
    /// The warm-up fit's exponentials ([`WarmupPlan`]); `None` for a part under 10 s.
    warmup: Option<WarmupPlan>,
    kurtosis_scales: Vec<usize>,
    grid_step: Option<f64>,
    /// Sample ranges of the trajectory blocks (10 equal, then the early ones).
    trajectory: Vec<(usize, usize)>,
    temperature: bool,
    /// Start of the part in the recording, s (the trajectory labels, [`Located::Time`]).
    offset_s: f64,
}

fn log10(v: f64) -> f64 {
    v.max(1e-300).log10()
}

impl StatLayout {
    /// The layout for parts of `len` samples at `rate_hz`, starting `offset_s` seconds into the
    /// recording (for the trajectory labels); `grid_step` adds the grid coherence at that step,
    /// `temperature` the temperature slope.
    pub fn new(
        len: usize,
        rate_hz: f64,
        offset_s: f64,
        grid_step: Option<f64>,
        temperature: bool,
    ) -> Result<Self, SimgapError> {
        if len < MIN_PART_SAMPLES {
            return Err(SimgapError::TooShort { samples: len, need: MIN_PART_SAMPLES });
        }
        let mut info = Vec::new();
        let mut allan_m = Vec::new();
        let mut m = 1;
        while m <= len / 8 {
            let tau = m as f64 / rate_hz;
            let group = if tau < ALLAN_SHORT_BELOW_S {
                Group::AllanShort
            } else if tau <= ALLAN_LONG_ABOVE_S {
                Group::AllanMid
            } else {
                Group::AllanLong
            };
            info.push(StatInfo {
                statistic: "allan_deviation",
                band: format!("tau = {} s", fmt_num(tau)),
                group,
                scale: Scale::Log10,
                unit: "deg/s",
                x: tau,
            });
            allan_m.push(m);
            m *= 2;
        }
        let psd_segment = (1usize << (len / 4).ilog2()).clamp(MIN_SEGMENT, MAX_SEGMENT);
        let half = psd_segment / 2;
        let df = rate_hz / psd_segment as f64;
        let mut psd_bands = Vec::new();
        let mut k = 2;
        while 2 * k <= half {
            let (f0, f1) = (k as f64 * df, 2.0 * k as f64 * df);
            info.push(StatInfo {
                statistic: "psd",
                band: format!("{}-{} Hz", fmt_num(f0), fmt_num(f1)),
                group: Group::Psd,
                scale: Scale::Log10,
                unit: "(deg/s)^2/Hz",
                x: (f0 * f1).sqrt(),
            });
            psd_bands.push((k, 2 * k));
            k *= 2;
        }
        info.push(StatInfo {
            statistic: "spectral_line",
            band: format!(
                "strongest bin / median of its 16 neighbours, {}-{} Hz",
                fmt_num(LINE_MIN_BIN as f64 * df),
                fmt_num((half - LINE_HALF_WINDOW) as f64 * df)
            ),
            group: Group::SpectralLine,
            scale: SPECTRAL_LINE_SCALE,
            unit: "ratio",
            x: f64::NAN,
        });
        let fast_line = FastLinePlan::new(len);
        if fast_line.is_some() {
            info.push(StatInfo {
                statistic: "fast_line",
                band: "strongest line of the whole part's periodogram / its background".into(),
                group: Group::SpectralLine,
                scale: SPECTRAL_LINE_SCALE,
                unit: "ratio",
                x: f64::NAN,
            });
        }
        let mut kurtosis_scales = vec![1];
        info.push(kurtosis_info("increments over 1 sample".into()));
        for s in KURTOSIS_BLOCKS_S {
            let m = (s * rate_hz).round() as usize;
            if m >= 2 && len / m >= KURTOSIS_MIN_BLOCKS && !kurtosis_scales.contains(&m) {
                kurtosis_scales.push(m);
                info.push(kurtosis_info(format!("increments of {} s means", fmt_num(s))));
            }
        }
        if let Some(step) = grid_step {
            info.push(StatInfo {
                statistic: "quantisation",
                band: format!("coherence with the {} deg/s grid", fmt_num(step)),
                group: Group::Distribution,
                scale: Scale::Log10,
                unit: "fraction",
                x: f64::NAN,
            });
        }
        for band in ["persistence RMSE on the denoised series", "raw residual after persistence on denoised"] {
            info.push(StatInfo {
                statistic: "compensation",
                band: band.into(),
                group: Group::Compensation,
                scale: Scale::Log10,
                unit: "deg/s",
                x: f64::NAN,
            });
        }
        let block = len / TRAJECTORY_BLOCKS;
        let mut trajectory: Vec<(usize, usize)> =
            (0..TRAJECTORY_BLOCKS).map(|b| (b * block, (b + 1) * block)).collect();
        trajectory.push((0, len >> EARLY_BLOCKS));
        trajectory.extend((2..=EARLY_BLOCKS).rev().map(|k| (len >> k, len >> (k - 1))));
        for (i, &(a, b)) in trajectory.iter().enumerate() {
            let (t0, t1) = (offset_s + a as f64 / rate_hz, offset_s + b as f64 / rate_hz);
            info.push(StatInfo {
                statistic: "bias_trajectory",
                band: format!("t = {}-{} s", fmt_num(t0), fmt_num(t1)),
                group: if i < TRAJECTORY_BLOCKS { Group::Trajectory } else { Group::EarlyTrajectory },
                scale: Scale::Linear,
                unit: "deg/s",
                x: 0.5 * (t0 + t1),
            });
        }
        info.push(StatInfo {
            statistic: "trajectory_roughness",
            band: "RMS of the 10 block means about their line".into(),
            group: Group::Trajectory,
            scale: Scale::Log10,
            unit: "deg/s",
            x: f64::NAN,
        });
        info.push(StatInfo {
            statistic: "warmup_amplitude",
            band: "best exponential from the part's start".into(),
            group: Group::Detectors,
            scale: Scale::Linear,
            unit: "deg/s",
            x: f64::NAN,
        });
        info.push(StatInfo {
            statistic: "ramp_change",
            band: "least-squares line of the 1 s means: its change over the part".into(),
            group: Group::Derived,
            scale: Scale::Linear,
            unit: "deg/s",
            x: f64::NAN,
        });
        info.push(StatInfo {
            statistic: "slow_line",
            band: "strongest line of the 1 s means / median of its 32 neighbours".into(),
            group: Group::Detectors,
            scale: Scale::Log10,
            unit: "ratio",
            x: f64::NAN,
        });
        info.push(StatInfo {
            statistic: "strongest_step",
            band: "largest difference of adjacent 60 s means".into(),
            group: Group::Detectors,
            scale: Scale::Log10,
            unit: "robust sigma",
            x: f64::NAN,
        });
        info.push(StatInfo {
            statistic: "step_kurtosis",
            band: "geometric mean kurtosis of the 20, 40, 60 and 120 s window differences".into(),
            group: Group::Derived,
            scale: Scale::Log10,
            unit: "ratio",
            x: f64::NAN,
        });
        if temperature {
            info.push(StatInfo {
                statistic: "temperature_slope",
                band: "1 s means of the rate on temp_c".into(),
                group: Group::Detectors,
                scale: Scale::Linear,
                unit: "deg/s/C",
                x: f64::NAN,
            });
        }
        Ok(Self {
            info,
            rate_hz,
            len,
            allan_m,
            psd_segment,
            psd_bands,
            fast_line,
            warmup: WarmupPlan::new(len, rate_hz),
            kurtosis_scales,
            grid_step,
            trajectory,
            temperature,
            offset_s,
        })
    }

    /// What each entry of a statistics vector is.
    pub fn info(&self) -> &[StatInfo] {
        &self.info
    }

    /// Length of the parts this layout is for.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the layout is for empty parts (never: see [`MIN_PART_SAMPLES`]).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The statistics of `x` (exactly [`len`](Self::len) samples), on the comparison scale;
    /// `temp_c` is the part's temperature (required when the layout has the temperature slope).
    pub fn compute(&self, x: &[f64], temp_c: Option<&[f64]>) -> Result<Vec<f64>, SimgapError> {
        if x.len() != self.len {
            return Err(SimgapError::TooShort { samples: x.len(), need: self.len });
        }
        let mut out = Vec::with_capacity(self.info.len());
        let allan = oadev(x, self.rate_hz, &Taus::Factors(self.allan_m.clone()))?;
        out.extend(allan.adev.iter().map(|&d| log10(d)));
        let psd = welch(x, self.rate_hz, self.psd_segment)?;
        for &(k0, k1) in &self.psd_bands {
            out.push(log10(psd.density[k0..k1].iter().sum::<f64>() / (k1 - k0) as f64));
        }
        out.push(SPECTRAL_LINE_SCALE.of(line_ratio(&psd.density)));
        if let Some(plan) = &self.fast_line {
            out.push(SPECTRAL_LINE_SCALE.of(plan.search(x, self.rate_hz).map_or(0.0, |l| l.ratio)));
        }
        for &m in &self.kurtosis_scales {
            let means = block_means(x, m);
            let inc: Vec<f64> = means.windows(2).map(|w| w[1] - w[0]).collect();
            out.push(log10(kurtosis(&inc)));
        }
        if let Some(step) = self.grid_step {
            out.push(log10(grid_coherence(x, step)));
        }
        let (denoised, _) = denoise_batch(x, &DenoiseConfig::paper());
        let persistence = Persistence.fit(&denoised).map_err(|e| SimgapError::Numerical(e.to_string()))?;
        let pred = predict_from(&persistence, &denoised, 1);
        out.push(log10(rmse(&pred, &denoised[1..]).unwrap_or(f64::NAN)));
        out.push(log10(rmse(&pred, &x[1..]).unwrap_or(f64::NAN)));
        let mean = x[..self.trajectory[TRAJECTORY_BLOCKS - 1].1].iter().sum::<f64>()
            / self.trajectory[TRAJECTORY_BLOCKS - 1].1 as f64;
        let blocks: Vec<f64> =
            self.trajectory.iter().map(|&(a, b)| x[a..b].iter().sum::<f64>() / (b - a) as f64 - mean).collect();
        out.extend_from_slice(&blocks);
        let centres: Vec<f64> = (0..TRAJECTORY_BLOCKS).map(|b| b as f64).collect();
        let (slope, intercept) = linear_fit(&centres, &blocks[..TRAJECTORY_BLOCKS]);
        let rough = centres.iter().zip(&blocks).map(|(c, b)| (b - intercept - slope * c).powi(2)).sum::<f64>();
        out.push(log10((rough / TRAJECTORY_BLOCKS as f64).sqrt()));
        out.push(self.warmup.as_ref().and_then(|plan| plan.fit(x)).map_or(0.0, |(amplitude, _)| amplitude));
        out.push(ramp_change(x, self.rate_hz));
        out.push(log10(self.slow_line(x).map_or(0.0, |(l, _)| l.ratio)));
        out.push(log10(StepScores::of(x, self.rate_hz).map_or(0.0, |s| s.strongest())));
        out.push(log10(step_kurtosis(x, self.rate_hz)));
        if self.temperature {
            let temp = temp_c.filter(|t| t.len() == x.len()).ok_or(SimgapError::NoTemperature)?;
            out.push(temperature_slope(x, temp, self.rate_hz));
        }
        debug_assert_eq!(out.len(), self.info.len());
        Ok(out)
    }

    /// The `slow_line` statistic's search: the strongest line of the part's 1 s means, and their
    /// rate, Hz.
    fn slow_line(&self, x: &[f64]) -> Option<(LineSearch, f64)> {
        let second = (self.rate_hz.round() as usize).max(1);
        let slow_rate = self.rate_hz / second as f64;
        LineSearch::of(&block_means(x, second), slow_rate, Reach::Neighbours).map(|l| (l, slow_rate))
    }

    /// Where the real part's value of each line or step statistic comes from: the frequency of
    /// the bin or line that `spectral_line` (Welch), `fast_line` and `slow_line` score, and the
    /// time of the largest window difference that `strongest_step` scores, so that a residual's
    /// *where* can say at which frequency a line or at which time a step stands out. `x` is a real
    /// part of [`len`](Self::len) samples.
    pub fn locate(&self, x: &[f64]) -> Result<Locations, SimgapError> {
        if x.len() != self.len {
            return Err(SimgapError::TooShort { samples: x.len(), need: self.len });
        }
        let index = |name: &str| self.info.iter().position(|i| i.statistic == name);
        let mut found = Vec::new();
        let psd = welch(x, self.rate_hz, self.psd_segment)?;
        let (ratio, bin) = line_peak(&psd.density);
        if let (Some(i), true) = (index("spectral_line"), ratio > 0.0) {
            found.push((i, Located::Frequency(psd.freq_hz[bin])));
        }
        if let (Some(i), Some(line)) =
            (index("fast_line"), self.fast_line.as_ref().and_then(|p| p.search(x, self.rate_hz)))
        {
            found.push((i, Located::Frequency(line.frequency_hz)));
        }
        if let (Some(i), Some((search, slow_rate))) = (index("slow_line"), self.slow_line(x)) {
            found.push((i, Located::Frequency(search.bin as f64 * slow_rate / search.nfft as f64)));
        }
        if let (Some(i), Some(steps)) = (index("strongest_step"), StepScores::of(x, self.rate_hz)) {
            let largest = steps.d.iter().enumerate().max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()));
            if let Some((j, _)) = largest {
                let t = self.offset_s + (steps.positions[j] * steps.block) as f64 / self.rate_hz;
                found.push((i, Located::Time(t)));
            }
        }
        Ok(Locations(found))
    }
}

/// Where a statistic's real value comes from ([`StatLayout::locate`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Located {
    /// A frequency, Hz.
    Frequency(f64),
    /// A time in the recording, s.
    Time(f64),
}

impl Located {
    /// A short readable form: "0.54 Hz", "t = 1234 s".
    pub fn text(self) -> String {
        match self {
            Located::Frequency(f) => format!("{} Hz", fmt_num(f)),
            Located::Time(t) => format!("t = {} s", fmt_num(t.round())),
        }
    }
}

/// Where a real part's line and step statistics come from, by statistic index
/// ([`StatLayout::locate`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Locations(Vec<(usize, Located)>);

impl Locations {
    /// Where statistic `i`'s real value comes from; `None` for statistics without a location.
    pub fn at(&self, i: usize) -> Option<Located> {
        self.0.iter().find(|&&(j, _)| j == i).map(|&(_, l)| l)
    }
}

fn kurtosis_info(band: String) -> StatInfo {
    StatInfo {
        statistic: "kurtosis",
        band,
        group: Group::Distribution,
        scale: Scale::Log10,
        unit: "ratio",
        x: f64::NAN,
    }
}

/// Largest ratio of a PSD bin to the median of the [`LINE_HALF_WINDOW`] bins on each side.
fn line_ratio(density: &[f64]) -> f64 {
    line_peak(density).0
}

/// The strongest bin's ratio to the median of its neighbours (as [`line_ratio`]) and the bin.
fn line_peak(density: &[f64]) -> (f64, usize) {
    let half = density.len() - 1;
    let mut best: (f64, usize) = (0.0, 0);
    let mut window = Vec::with_capacity(2 * LINE_HALF_WINDOW);
    for k in LINE_MIN_BIN.max(LINE_HALF_WINDOW)..=half.saturating_sub(LINE_HALF_WINDOW) {
        window.clear();
        window.extend_from_slice(&density[k - LINE_HALF_WINDOW..k]);
        window.extend_from_slice(&density[k + 1..=k + LINE_HALF_WINDOW]);
        let background = median(&window);
        if background > 0.0 && density[k] / background > best.0 {
            best = (density[k] / background, k);
        }
    }
    best
}

/// |mean of e^(2πi·x/step)|: 1 when every sample is a multiple of `step` (plus a common offset),
/// about N^(−1/2) for values spread over many steps.
pub fn grid_coherence(x: &[f64], step: f64) -> f64 {
    let (mut c, mut s) = (0.0, 0.0);
    for v in x {
        let phase = std::f64::consts::TAU * (v / step).fract();
        c += phase.cos();
        s += phase.sin();
    }
    (c * c + s * s).sqrt() / x.len().max(1) as f64
}

/// A number in at most 4 significant digits without trailing zeros.
pub fn fmt_num(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = (3 - v.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_owned() } else { s }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_and_values_line_up() {
        let n = 6000;
        let x: Vec<f64> =
            (0..n).map(|i| ((((i * 7919) % 101) as f64 + (i as f64 * 0.05).sin() * 20.0).round()) * 0.01).collect();
        let layout = StatLayout::new(n, 10.0, 100.0, Some(0.01), true).unwrap();
        let temp: Vec<f64> = (0..n).map(|i| 20.0 + i as f64 * 1e-3).collect();
        let v = layout.compute(&x, Some(&temp)).unwrap();
        assert_eq!(v.len(), layout.info().len());
        assert!(v.iter().all(|x| x.is_finite()));
        // On the 0.01 grid the coherence is 1 (log10 = 0) up to rounding.
        let q = layout.info().iter().position(|s| s.statistic == "quantisation").unwrap();
        assert!(v[q].abs() < 1e-6, "{}", v[q]);
        // The trajectory is labelled in recording time.
        let t = layout.info().iter().find(|s| s.statistic == "bias_trajectory").unwrap();
        assert_eq!(t.band, "t = 100-160 s");
        assert!(matches!(layout.compute(&x, None), Err(SimgapError::NoTemperature)));
        assert!(StatLayout::new(100, 10.0, 0.0, None, false).is_err());
    }

    /// `n` uniform deviates in [−0.5, 0.5) from a seeded linear congruential generator.
    fn uniform_noise(n: usize, seed: u64) -> Vec<f64> {
        let mut state = seed;
        (0..n)
            .map(|_| {
                state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            })
            .collect()
    }

    #[test]
    fn a_sinusoid_is_a_spectral_line() {
        let n = 8192;
        let noise = uniform_noise(n, 7);
        let with_line: Vec<f64> = noise.iter().enumerate().map(|(i, v)| v + 0.2 * (i as f64 * 0.9).sin()).collect();
        let psd = |x: &[f64]| welch(x, 10.0, 1024).unwrap().density;
        assert!(line_ratio(&psd(&with_line)) > 5.0 * line_ratio(&psd(&noise)));
    }

    /// Each line statistic reports the frequency of the line it scores: a 1.2 Hz sinusoid for the
    /// Welch and full-length searches, a 0.05 Hz one for the search on 1 s means.
    #[test]
    fn line_statistics_say_where_their_line_is() {
        let (fs, n) = (10.0, 40_000);
        let x: Vec<f64> = uniform_noise(n, 11)
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let t = i as f64 / fs;
                v + 0.1 * (std::f64::consts::TAU * 1.2 * t).sin() + 0.05 * (std::f64::consts::TAU * 0.05 * t).sin()
            })
            .collect();
        let layout = StatLayout::new(n, fs, 0.0, None, false).unwrap();
        let lines = layout.locate(&x).unwrap();
        let at = |name: &str| match lines.at(layout.info().iter().position(|s| s.statistic == name).unwrap()) {
            Some(Located::Frequency(f)) => f,
            other => panic!("{name}: {other:?}"),
        };
        assert!((at("spectral_line") - 1.2).abs() <= fs / layout.psd_segment as f64, "{}", at("spectral_line"));
        assert!((at("fast_line") - 1.2).abs() < 1e-3, "{}", at("fast_line"));
        assert!((at("slow_line") - 0.05).abs() < 1e-3, "{}", at("slow_line"));
        let allan = layout.info().iter().position(|s| s.statistic == "allan_deviation").unwrap();
        assert_eq!(lines.at(allan), None);
        assert!(layout.locate(&x[1..]).is_err());
    }

    /// The strongest step is placed at its time in the recording (the part starting 100 s in).
    #[test]
    fn the_strongest_step_is_located_in_time() {
        let (fs, n) = (10.0, 40_000);
        let x: Vec<f64> =
            uniform_noise(n, 3).iter().enumerate().map(|(i, v)| v + if i >= 15_000 { 0.2 } else { 0.0 }).collect();
        let layout = StatLayout::new(n, fs, 100.0, None, false).unwrap();
        let step = layout.info().iter().position(|s| s.statistic == "strongest_step").unwrap();
        match layout.locate(&x).unwrap().at(step) {
            Some(Located::Time(t)) => assert!((t - 1600.0).abs() <= 2.0, "{t}"),
            other => panic!("{other:?}"),
        }
        assert_eq!(Located::Time(1600.4).text(), "t = 1600 s");
        assert_eq!(Located::Frequency(0.54).text(), "0.54 Hz");
    }

    #[test]
    fn numbers_print_short() {
        assert_eq!(fmt_num(0.1), "0.1");
        assert_eq!(fmt_num(409.6), "409.6");
        assert_eq!(fmt_num(0.0048828125), "0.004883");
        assert_eq!(fmt_num(12800.0), "12800");
    }
}
