//! The configuration file (`configs/default.toml` documents every key). Parsing rejects unknown
//! keys and bad values with a message naming the key; missing keys take the defaults below,
//! which equal `configs/default.toml` (a test holds them to it).

use std::fmt;
use std::path::PathBuf;
use std::time::Duration;

use serde::Deserialize;

use crate::model::cpso::{CpsoConfig, CpsoError};
use crate::model::lssvm::CpsoLssvm;
use crate::stream::ipc::{Delivery, IpcSettings, ServiceNames, WaitMode};
use crate::stream::{
    CausalConfig, DetectorKind, DriftConfig, Embedding, EstimatorKind, InputConfig, MotionConfig, PipelineConfig,
    RetrainMode, RetrainSchedule, StatisticalConfig,
};
use crate::wavelet::{DenoiseConfig, Wavelet};

/// Default causal window (samples): see the trade-off table in docs/evaluation.md ("Causal denoising").
pub const DEFAULT_DENOISE_WINDOW: usize = 256;
/// Default causal lag (samples): see the trade-off table in docs/evaluation.md ("Causal denoising").
pub const DEFAULT_DENOISE_LAG: usize = 5;
/// Largest `denoise.window`, `motion.window` and `ipc.subscriber_buffer` (samples).
pub const MAX_WINDOW: usize = 1 << 20;
/// Largest `retrain.window` (static samples per axis; the history of three axes is 48 MB).
pub const MAX_RETRAIN_WINDOW: usize = 1_000_000;
/// Largest `retrain.exact_max_rows`: the exact LS-SVM holds an n × n matrix (10,000 rows: 800 MB).
pub const MAX_EXACT_ROWS: usize = 10_000;
/// Largest embedding span `(embedding.dim − 1) · embedding.tau`, samples.
pub const MAX_EMBEDDING_SPAN: usize = 100_000;

/// The whole configuration.
#[derive(Debug, Clone, PartialEq, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// `[denoise]`: wavelet denoising, batch and causal.
    pub denoise: DenoiseSection,
    /// `[embedding]`: phase-space reconstruction.
    pub embedding: EmbeddingSection,
    /// `[pipeline]`: per-sample compensation.
    pub pipeline: PipelineSection,
    /// `[drift]`: the drift estimator.
    pub drift: DriftSection,
    /// `[motion]`: the static/moving detector.
    pub motion: MotionSection,
    /// `[input]`: input validation and gap detection.
    pub input: InputSection,
    /// `[retrain]`: background retraining and its model.
    pub retrain: RetrainSection,
    /// `[ipc]`: the daemon's iceoryx2 services and domain.
    pub ipc: IpcSection,
    /// `[log]`: the daemon's log output.
    pub log: LogSection,
    /// `[state]`: where the daemon keeps its model snapshot.
    pub state: StateSection,
}

/// `[state]` keys (used by `gyrocompd`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StateSection {
    /// Directory of the model snapshot (an absolute path; empty = no snapshots).
    pub dir: String,
    /// Seconds between periodic snapshots (0 = only after model swaps and at a clean stop).
    pub every_s: f64,
}

impl Default for StateSection {
    fn default() -> Self {
        Self { dir: String::new(), every_s: 30.0 }
    }
}

/// `[ipc]` keys (used by `gyrocompd`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct IpcSection {
    /// Services are `<service_prefix>/raw`, `/compensated` and `/status`.
    pub service_prefix: String,
    /// How the daemon waits for raw samples: `event` (sleep on the event service) or `spin`.
    pub wait: String,
    /// Subscriber buffer of the raw and compensated services, samples.
    pub subscriber_buffer: usize,
    /// Compensated publisher on a full subscriber buffer: `lossless` (wait) or `drop-newest`.
    pub delivery: String,
    /// `lossless`: longest wait for one full subscriber before the sample is dropped for it, ms
    /// (0 = wait as long as the subscriber exists).
    pub give_up_ms: u64,
    /// iceoryx2 `global.prefix` of a private domain (empty with `domain_root`: iceoryx2's own
    /// configuration lookup, `config/iceoryx2.toml` in the working directory first).
    pub domain_prefix: String,
    /// iceoryx2 `global.root_path` of a private domain, an absolute directory.
    pub domain_root: String,
}

impl Default for IpcSection {
    fn default() -> Self {
        Self {
            service_prefix: crate::stream::ipc::DEFAULT_PREFIX.into(),
            wait: "event".into(),
            subscriber_buffer: crate::stream::ipc::DEFAULT_SUBSCRIBER_BUFFER,
            delivery: "lossless".into(),
            give_up_ms: 1000,
            domain_prefix: String::new(),
            domain_root: String::new(),
        }
    }
}

/// `[log]` keys (used by `gyrocompd`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LogSection {
    /// `text` (human-readable lines) or `json` (one JSON object per line).
    pub format: String,
    /// A `tracing` filter: a level (`error` … `trace`) or directives such as `info,iceoryx2=warn`.
    pub level: String,
}

impl Default for LogSection {
    fn default() -> Self {
        Self { format: "text".into(), level: "info".into() }
    }
}

/// Log line format of `[log] format`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LogFormat {
    /// Human-readable lines.
    Text,
    /// One JSON object per line.
    Json,
}

/// The iceoryx2 domain of `[ipc] domain_prefix/domain_root`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DomainChoice {
    /// iceoryx2's own configuration lookup.
    Global,
    /// A private domain with this prefix and root path.
    Private {
        /// `global.prefix`.
        prefix: String,
        /// `global.root_path`.
        root: PathBuf,
    },
}

/// `[pipeline]` keys.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PipelineSection {
    /// Static samples averaged by the bias estimate used before the first model.
    pub bias_samples: u64,
}

impl Default for PipelineSection {
    fn default() -> Self {
        Self { bias_samples: 1000 }
    }
}

/// `[drift]` keys.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DriftSection {
    /// `kalman`, `cpso-lssvm` or `bias-hold`.
    pub estimator: EstimatorKind,
    /// Kalman innovation gate: χ²(1) tail probability.
    pub innovation_gate: f64,
    /// bias-hold: start-up seconds averaged.
    pub startup_s: f64,
    /// Kalman: learn a temperature coefficient when samples carry `temp_c`.
    pub temperature: bool,
}

impl Default for DriftSection {
    fn default() -> Self {
        let d = DriftConfig::default();
        Self { estimator: d.kind, innovation_gate: d.innovation_gate, startup_s: d.startup_s, temperature: d.temperature }
    }
}

/// `[motion]` keys.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MotionSection {
    /// `statistical` or `threshold`.
    pub detector: DetectorKind,
    /// statistical: false-alarm probability of each test.
    pub false_alarm: f64,
    /// statistical: mean-shift windows, s.
    pub windows_s: Vec<f64>,
    /// statistical: variance-test window, s.
    pub variance_window_s: f64,
    /// statistical: hysteresis after the last alarm, s.
    pub settle_s: f64,
    /// statistical: extra look-back discarded before an onset, s.
    pub guard_s: f64,
    /// statistical: seconds of unexplained, unchanging "moving" after which the drift estimate
    /// is relearnt (0: never).
    pub relearn_s: f64,
    /// threshold: |rate − drift| above which a sample is moving, deg/s.
    pub rate_dps: f64,
    /// threshold: short-window variance above which a sample is moving, (deg/s)².
    pub variance_dps2: f64,
    /// threshold: samples in the variance window.
    pub window: usize,
}

impl Default for MotionSection {
    fn default() -> Self {
        let s = StatisticalConfig::default();
        Self {
            detector: DetectorKind::Statistical,
            false_alarm: s.false_alarm,
            windows_s: s.windows_s,
            variance_window_s: s.variance_window_s,
            settle_s: s.settle_s,
            guard_s: s.guard_s,
            relearn_s: s.relearn_s,
            rate_dps: 2.0,
            variance_dps2: 0.6,
            window: 20,
        }
    }
}

/// `[input] rate_hz`: a nominal rate in Hz, or `"auto"` (measured from the first timestamps).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RateSetting {
    /// Measured: the median of the first timestamp steps.
    Auto,
    /// Given, Hz.
    Hz(f64),
}

impl<'de> Deserialize<'de> for RateSetting {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Raw {
            Number(f64),
            Word(String),
        }
        match Raw::deserialize(d)? {
            Raw::Number(hz) => Ok(Self::Hz(hz)),
            Raw::Word(w) if w == "auto" => Ok(Self::Auto),
            Raw::Word(w) => Err(serde::de::Error::custom(format!("input.rate_hz: {w:?} is neither a number nor \"auto\""))),
        }
    }
}

/// `[input]` keys.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct InputSection {
    /// Largest accepted |rate|, deg/s.
    pub range_dps: f64,
    /// Nominal sample rate, Hz, or measured.
    pub rate_hz: RateSetting,
    /// A timestamp step above this many nominal periods is a gap.
    pub gap_factor: f64,
    /// Spike threshold in σ of the recent static samples (0 = off).
    pub spike_z: f64,
    /// Longest run of outliers rejected as spikes (a longer run is a real change).
    pub spike_max_run: u32,
    /// Seconds of one bit-identical value on an axis after which the sensor is stuck (0 = off).
    pub stuck_s: f64,
}

impl Default for InputSection {
    fn default() -> Self {
        Self { range_dps: 2000.0, rate_hz: RateSetting::Auto, gap_factor: 3.0, spike_z: 8.0, spike_max_run: 3, stuck_s: 2.0 }
    }
}

/// `[retrain]` keys.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RetrainSection {
    /// `deterministic` (every `every_samples`, applied after `apply_delay_samples`) or `live`
    /// (every `interval_s` of wall time, applied when ready).
    pub mode: String,
    /// Static denoised samples per axis in a training window.
    pub window: usize,
    /// Deterministic mode: input samples between requests.
    pub every_samples: u64,
    /// Live mode: seconds between requests.
    pub interval_s: f64,
    /// Deterministic mode: samples between a request and its model's application.
    pub apply_delay_samples: u64,
    /// Fewest static samples per axis for a request.
    pub min_samples: usize,
    /// Largest number of training rows solved exactly; above, the fixed-size LS-SVM.
    pub exact_max_rows: usize,
    /// Prototypes m_p of the fixed-size LS-SVM.
    pub prototypes: usize,
    /// CPSO chaotic candidates M.
    pub cpso_candidates: usize,
    /// CPSO particles N.
    pub cpso_particles: usize,
    /// CPSO iterations t_max.
    pub cpso_iterations: usize,
    /// CPSO seed.
    pub seed: u64,
    /// Threads for the CPSO fitness evaluations (0 = all cores).
    pub threads: usize,
    /// Nice value of the retrain thread(s), 0 … 19 (higher = yields the CPU to the sample loop).
    pub nice: i32,
}

impl Default for RetrainSection {
    fn default() -> Self {
        let cpso = CpsoConfig::default();
        Self {
            mode: "live".into(),
            window: 4000,
            every_samples: 6000,
            interval_s: 60.0,
            apply_delay_samples: 1000,
            min_samples: 500,
            exact_max_rows: 1000,
            prototypes: 100,
            cpso_candidates: cpso.candidates,
            cpso_particles: cpso.particles,
            cpso_iterations: cpso.iterations,
            seed: 0,
            threads: 1,
            nice: 10,
        }
    }
}

/// `[denoise]` keys.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DenoiseSection {
    /// Mother wavelet, `db1` … `db10` (paper: db4).
    pub wavelet: String,
    /// Decomposition levels (paper: 3).
    pub level: usize,
    /// Causal mode: samples in the sliding window.
    pub window: usize,
    /// Causal mode: samples between the newest input and the emitted estimate.
    pub lag: usize,
}

impl Default for DenoiseSection {
    fn default() -> Self {
        Self { wavelet: "db4".into(), level: 3, window: DEFAULT_DENOISE_WINDOW, lag: DEFAULT_DENOISE_LAG }
    }
}

/// `[embedding]` keys.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct EmbeddingSection {
    /// Delay τ in samples (paper: 10).
    pub tau: usize,
    /// Embedding dimension m (paper: 3).
    pub dim: usize,
}

impl Default for EmbeddingSection {
    fn default() -> Self {
        Self { tau: Embedding::PAPER.tau, dim: Embedding::PAPER.dim }
    }
}

/// A configuration that could not be parsed or is inconsistent; the message names the key.
#[derive(Debug, Clone, PartialEq)]
pub struct ConfigError(pub String);

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ConfigError {}

impl Config {
    /// The paper's method as the pipeline ran it before the drift-estimator seam: CPSO-LSSVM
    /// forecaster, fixed-threshold gate, 100 Hz nominal rate; everything else default. What the
    /// tests of the model machinery (retraining, snapshots, the one-pipeline property with models)
    /// run on.
    pub fn paper() -> Self {
        let mut c = Self::default();
        c.drift.estimator = EstimatorKind::CpsoLssvm;
        c.motion.detector = DetectorKind::Threshold;
        c.input.rate_hz = RateSetting::Hz(100.0);
        c
    }

    /// Parses TOML text (`origin` names it in messages) and validates every value.
    pub fn from_toml(text: &str, origin: &str) -> Result<Self, ConfigError> {
        let config: Self = toml::from_str(text).map_err(|e| ConfigError(format!("{origin}: {e}")))?;
        config.validate().map_err(|ConfigError(msg)| ConfigError(format!("{origin}: {msg}")))?;
        Ok(config)
    }

    /// Checks values that the types alone do not: names, ranges, and window against lag.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.causal_denoise()?;
        self.pipeline()?;
        self.ipc_settings()?;
        self.ipc_domain()?;
        self.log_format()?;
        self.state_dir()?;
        self.snapshot_every()?;
        Ok(())
    }

    /// The snapshot directory of `[state] dir`: `None` when empty (snapshots off), else an
    /// absolute path.
    pub fn state_dir(&self) -> Result<Option<PathBuf>, ConfigError> {
        if self.state.dir.is_empty() {
            return Ok(None);
        }
        let dir = PathBuf::from(&self.state.dir);
        if !dir.is_absolute() {
            return Err(ConfigError(format!("state.dir: {} is not an absolute path", dir.display())));
        }
        Ok(Some(dir))
    }

    /// The period of `[state] every_s` (`None`: 0, no periodic snapshots); 0 or 1 to 86400 s.
    pub fn snapshot_every(&self) -> Result<Option<std::time::Duration>, ConfigError> {
        match self.state.every_s {
            0.0 => Ok(None),
            s if (1.0..=86_400.0).contains(&s) => Ok(Some(std::time::Duration::from_secs_f64(s))),
            s => Err(ConfigError(format!("state.every_s: {s} must be 0 (off) or lie in [1, 86400] s"))),
        }
    }

    /// The embedding and the sizes that set memory use, against their limits (checked before
    /// anything is computed from them).
    fn limits(&self) -> Result<(), ConfigError> {
        if self.embedding.tau == 0 {
            return Err(ConfigError("embedding.tau must be at least 1".into()));
        }
        if self.embedding.dim == 0 {
            return Err(ConfigError("embedding.dim must be at least 1".into()));
        }
        let span = (self.embedding.dim - 1).checked_mul(self.embedding.tau);
        if span.is_none_or(|s| s > MAX_EMBEDDING_SPAN) {
            return Err(ConfigError(format!(
                "embedding.tau/embedding.dim: (dim − 1)·tau must not exceed {MAX_EMBEDDING_SPAN}, got tau = {}, dim = {}",
                self.embedding.tau, self.embedding.dim
            )));
        }
        for (key, value, max) in [
            ("denoise.window", self.denoise.window, MAX_WINDOW),
            ("motion.window", self.motion.window, MAX_WINDOW),
            ("ipc.subscriber_buffer", self.ipc.subscriber_buffer, MAX_WINDOW),
            ("retrain.window", self.retrain.window, MAX_RETRAIN_WINDOW),
            ("retrain.exact_max_rows", self.retrain.exact_max_rows, MAX_EXACT_ROWS),
        ] {
            if value > max {
                return Err(ConfigError(format!("{key}: {value} exceeds the limit {max}")));
            }
        }
        Ok(())
    }

    /// The iceoryx2 port settings of `[ipc]`, validated.
    pub fn ipc_settings(&self) -> Result<IpcSettings, ConfigError> {
        let i = &self.ipc;
        let prefix = i.service_prefix.trim_end_matches('/');
        if prefix.is_empty() {
            return Err(ConfigError("ipc.service_prefix must not be empty".into()));
        }
        let wait_mode = match i.wait.as_str() {
            "event" => WaitMode::Event,
            "spin" => WaitMode::Spin,
            other => return Err(ConfigError(format!("ipc.wait: {other:?} is neither \"event\" nor \"spin\""))),
        };
        if i.subscriber_buffer == 0 {
            return Err(ConfigError("ipc.subscriber_buffer must be at least 1".into()));
        }
        let delivery = match i.delivery.as_str() {
            "lossless" => {
                Delivery::Lossless { give_up_after: (i.give_up_ms > 0).then(|| Duration::from_millis(i.give_up_ms)) }
            }
            "drop-newest" => Delivery::DropNewest,
            other => {
                return Err(ConfigError(format!(
                    "ipc.delivery: {other:?} is neither \"lossless\" nor \"drop-newest\""
                )));
            }
        };
        Ok(IpcSettings {
            names: ServiceNames::with_prefix(prefix),
            subscriber_buffer: i.subscriber_buffer,
            wait_mode,
            delivery,
            notify: true,
        })
    }

    /// The iceoryx2 domain of `[ipc]`: both `domain_prefix` and `domain_root` set (root
    /// absolute), or neither.
    pub fn ipc_domain(&self) -> Result<DomainChoice, ConfigError> {
        let (prefix, root) = (&self.ipc.domain_prefix, &self.ipc.domain_root);
        match (prefix.is_empty(), root.is_empty()) {
            (true, true) => Ok(DomainChoice::Global),
            (false, false) => {
                let root = PathBuf::from(root);
                if !root.is_absolute() {
                    return Err(ConfigError(format!("ipc.domain_root: {} is not an absolute path", root.display())));
                }
                Ok(DomainChoice::Private { prefix: prefix.clone(), root })
            }
            _ => Err(ConfigError("ipc.domain_prefix/ipc.domain_root: give both or neither".into())),
        }
    }

    /// The log format of `[log]`, after checking that `level` is a valid filter.
    pub fn log_format(&self) -> Result<LogFormat, ConfigError> {
        tracing_subscriber::EnvFilter::try_new(&self.log.level)
            .map_err(|e| ConfigError(format!("log.level: {:?}: {e}", self.log.level)))?;
        match self.log.format.as_str() {
            "text" => Ok(LogFormat::Text),
            "json" => Ok(LogFormat::Json),
            other => Err(ConfigError(format!("log.format: {other:?} is neither \"text\" nor \"json\""))),
        }
    }

    /// The pipeline settings of `[denoise]`, `[embedding]`, `[pipeline]`, `[motion]`, `[input]`
    /// and `[retrain]`, validated.
    pub fn pipeline(&self) -> Result<PipelineConfig, ConfigError> {
        fn err<T>(m: String) -> Result<T, ConfigError> {
            Err(ConfigError(m))
        }
        let positive = |key: &str, v: f64| {
            if v > 0.0 && v.is_finite() { Ok(()) } else { err(format!("{key}: {v} must be positive and finite")) }
        };
        self.limits()?;
        if self.pipeline.bias_samples == 0 {
            return err("pipeline.bias_samples must be at least 1".into());
        }
        let m = &self.motion;
        let statistical = StatisticalConfig {
            false_alarm: m.false_alarm,
            windows_s: m.windows_s.clone(),
            variance_window_s: m.variance_window_s,
            settle_s: m.settle_s,
            guard_s: m.guard_s,
            relearn_s: m.relearn_s,
        };
        statistical.validate().map_err(ConfigError)?;
        let d = &self.drift;
        if !(d.innovation_gate >= crate::model::normal::MIN_PROBABILITY && d.innovation_gate < 0.5) {
            return err(format!("drift.innovation_gate: {} must lie in [1e-12, 0.5)", d.innovation_gate));
        }
        positive("drift.startup_s", d.startup_s)?;
        positive("motion.rate_dps", m.rate_dps)?;
        positive("motion.variance_dps2", m.variance_dps2)?;
        if m.window < 2 {
            return err(format!("motion.window: {} must be at least 2", m.window));
        }
        let i = &self.input;
        positive("input.range_dps", i.range_dps)?;
        let period_ns = match i.rate_hz {
            RateSetting::Auto => 0,
            RateSetting::Hz(hz) => {
                positive("input.rate_hz", hz)?;
                (1e9 / hz).round().max(1.0) as u64
            }
        };
        if !(i.gap_factor > 1.0 && i.gap_factor.is_finite()) {
            return err(format!("input.gap_factor: {} must be finite and above 1", i.gap_factor));
        }
        if !(i.spike_z >= 0.0 && i.spike_z.is_finite()) || (i.spike_z > 0.0 && i.spike_z < 3.0) {
            return err(format!("input.spike_z: {} must be 0 (off) or a finite value of at least 3", i.spike_z));
        }
        if !(i.stuck_s == 0.0 || (0.1..=3600.0).contains(&i.stuck_s)) {
            return err(format!("input.stuck_s: {} must be 0 (off) or lie in [0.1, 3600] s", i.stuck_s));
        }
        let r = &self.retrain;
        if !(0..=19).contains(&r.nice) {
            return err(format!("retrain.nice: {} is outside 0..=19", r.nice));
        }
        let mode = match r.mode.as_str() {
            "deterministic" => RetrainMode::Deterministic,
            "live" => RetrainMode::Live,
            other => return err(format!("retrain.mode: {other:?} is neither \"deterministic\" nor \"live\"")),
        };
        let embedding = self.embedding();
        if r.window < embedding.history() + 3 {
            return err(format!(
                "retrain.window: {} is shorter than the embedding needs ({})",
                r.window,
                embedding.history() + 3
            ));
        }
        if r.every_samples == 0 {
            return err("retrain.every_samples must be at least 1".into());
        }
        positive("retrain.interval_s", r.interval_s)?;
        if r.min_samples > r.window {
            return err(format!("retrain.min_samples: {} exceeds retrain.window {}", r.min_samples, r.window));
        }
        self.cpso_lssvm()?;
        Ok(PipelineConfig {
            causal: self.causal_denoise()?,
            embedding,
            bias_samples: self.pipeline.bias_samples,
            motion: MotionConfig { rate_dps: m.rate_dps, variance_dps2: m.variance_dps2, window: m.window },
            detector: m.detector,
            statistical,
            drift: DriftConfig {
                kind: d.estimator,
                innovation_gate: d.innovation_gate,
                startup_s: d.startup_s,
                temperature: d.temperature,
            },
            input: InputConfig {
                range_dps: i.range_dps,
                period_ns,
                gap_factor: i.gap_factor,
                spike_z: i.spike_z,
                spike_max_run: i.spike_max_run,
                stuck_s: i.stuck_s,
            },
            retrain: RetrainSchedule {
                mode,
                window: r.window,
                every_samples: r.every_samples,
                interval_s: r.interval_s,
                apply_delay_samples: r.apply_delay_samples,
                min_samples: r.min_samples,
            },
        })
    }

    /// The retrainer's CPSO-LSSVM (paper §2.2) from `[retrain]` and `[embedding]`; the other
    /// settings are [`CpsoLssvm::default`]. Its targets lie `denoise.lag + 1` samples ahead
    /// (direct multi-step forecasting, [`Embedding::horizon`]): the pipeline's newest denoised
    /// value is L samples old when a sample arrives, and one model evaluation then reaches that
    /// sample — instead of iterating a one-step model L + 1 times, which costs L + 1 evaluations
    /// per sample and compounds its error; CPSO also tunes γ, σ² on the forecast actually used.
    pub fn cpso_lssvm(&self) -> Result<CpsoLssvm, ConfigError> {
        let r = &self.retrain;
        if r.prototypes == 0 {
            return Err(ConfigError("retrain.prototypes must be at least 1".into()));
        }
        let cpso = CpsoConfig {
            candidates: r.cpso_candidates,
            particles: r.cpso_particles,
            iterations: r.cpso_iterations,
            seed: r.seed,
            threads: r.threads,
            ..CpsoConfig::default()
        };
        cpso.validate().map_err(|(CpsoError::Config(m) | CpsoError::Bounds(m))| {
            ConfigError(format!("retrain.cpso_particles/retrain.cpso_candidates: {m}"))
        })?;
        if r.cpso_iterations == 0 {
            return Err(ConfigError("retrain.cpso_iterations must be at least 1".into()));
        }
        Ok(CpsoLssvm {
            embedding: self.embedding().with_horizon(self.denoise.lag + 1),
            cpso,
            exact_max_rows: r.exact_max_rows,
            prototypes: r.prototypes,
            ..CpsoLssvm::default()
        })
    }

    /// The batch denoiser settings of `[denoise]`.
    pub fn denoise(&self) -> Result<DenoiseConfig, ConfigError> {
        let wavelet =
            Wavelet::from_name(&self.denoise.wavelet).map_err(|e| ConfigError(format!("denoise.wavelet: {e}")))?;
        if !(1..=32).contains(&self.denoise.level) {
            return Err(ConfigError(format!("denoise.level: {} is outside 1..=32", self.denoise.level)));
        }
        Ok(DenoiseConfig { wavelet, level: self.denoise.level })
    }

    /// The causal denoiser settings of `[denoise]`.
    pub fn causal_denoise(&self) -> Result<CausalConfig, ConfigError> {
        let causal = CausalConfig { denoise: self.denoise()?, window: self.denoise.window, lag: self.denoise.lag };
        causal.validate().map_err(|e| ConfigError(format!("denoise.window/denoise.lag: {e}")))?;
        Ok(causal)
    }

    /// The embedding of `[embedding]`.
    pub fn embedding(&self) -> Embedding {
        Embedding::new(self.embedding.tau, self.embedding.dim)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shipped_default_file_equals_the_built_in_defaults() {
        let text = include_str!("../configs/default.toml");
        assert_eq!(Config::from_toml(text, "configs/default.toml").unwrap(), Config::default());
    }

    #[test]
    fn shipped_10hz_file_loads_and_changes_only_rate_and_gate() {
        let text = include_str!("../configs/adis16405_10hz.toml");
        let c = Config::from_toml(text, "configs/adis16405_10hz.toml").unwrap();
        c.pipeline().unwrap();
        assert_eq!((c.input.rate_hz, c.motion.rate_dps, c.motion.variance_dps2), (RateSetting::Hz(10.0), 1.0, 0.05));
        let mut expected = Config::default();
        (expected.input.rate_hz, expected.motion.rate_dps, expected.motion.variance_dps2) =
            (RateSetting::Hz(10.0), 1.0, 0.05);
        expected.motion.detector = DetectorKind::Threshold;
        expected.drift.estimator = EstimatorKind::CpsoLssvm;
        assert_eq!(c, expected);
    }

    #[test]
    fn unknown_keys_and_bad_values_name_the_key() {
        let err = Config::from_toml("[denoise]\nwindw = 100\n", "x.toml").unwrap_err();
        assert!(err.0.starts_with("x.toml:") && err.0.contains("windw"), "{err}");
        let err = Config::from_toml("[denoize]\n", "x.toml").unwrap_err();
        assert!(err.0.contains("denoize"), "{err}");
        let err = Config::from_toml("[denoise]\nwindow = -3\n", "x.toml").unwrap_err();
        assert!(err.0.contains("window"), "{err}");
        let err = Config::from_toml("[denoise]\nwavelet = \"sym4\"\n", "x.toml").unwrap_err();
        assert!(err.0.contains("denoise.wavelet"), "{err}");
        let err = Config::from_toml("[denoise]\nwindow = 64\nlag = 64\n", "x.toml").unwrap_err();
        assert!(err.0.contains("denoise.window/denoise.lag"), "{err}");
        let err = Config::from_toml("[embedding]\ntau = 0\n", "x.toml").unwrap_err();
        assert!(err.0.contains("embedding.tau"), "{err}");
        for (text, key) in [
            ("[retrain]\nmode = \"sometimes\"\n", "retrain.mode"),
            ("[retrain]\nwindow = 10\n", "retrain.window"),
            ("[retrain]\nevery_samples = 0\n", "retrain.every_samples"),
            ("[retrain]\nmin_samples = 5000\n", "retrain.min_samples"),
            ("[retrain]\ncpso_particles = 0\n", "retrain.cpso_particles"),
            ("[retrain]\nprototypes = 0\n", "retrain.prototypes"),
            ("[retrain]\ninterval_s = 0.0\n", "retrain.interval_s"),
            ("[motion]\nwindow = 1\n", "motion.window"),
            ("[motion]\nrate_dps = -1.0\n", "motion.rate_dps"),
            ("[input]\ngap_factor = 0.5\n", "input.gap_factor"),
            ("[input]\nspike_z = 1.5\n", "input.spike_z"),
            ("[input]\nrate_hz = 0.0\n", "input.rate_hz"),
            ("[input]\nrate_hz = \"fast\"\n", "input.rate_hz"),
            ("[drift]\nestimator = \"lstm\"\n", "estimator"),
            ("[drift]\ninnovation_gate = 0.0\n", "drift.innovation_gate"),
            ("[motion]\ndetector = \"magic\"\n", "detector"),
            ("[motion]\nfalse_alarm = 0.9\n", "motion.false_alarm"),
            ("[motion]\nfalse_alarm = 1e-300\n", "motion.false_alarm"),
            ("[drift]\ninnovation_gate = 1e-300\n", "drift.innovation_gate"),
            ("[motion]\nwindows_s = [2.0, 1.0]\n", "motion.windows_s"),
            ("[motion]\nsettle_s = -1.0\n", "motion.settle_s"),
            ("[pipeline]\nbias_samples = 0\n", "pipeline.bias_samples"),
            ("[retrain]\nwindw = 4000\n", "windw"),
            ("[ipc]\nwait = \"sleep\"\n", "ipc.wait"),
            ("[ipc]\ndelivery = \"overwrite\"\n", "ipc.delivery"),
            ("[ipc]\nsubscriber_buffer = 0\n", "ipc.subscriber_buffer"),
            ("[ipc]\nservice_prefix = \"\"\n", "ipc.service_prefix"),
            ("[ipc]\ndomain_prefix = \"x_\"\n", "ipc.domain_prefix"),
            ("[ipc]\ndomain_prefix = \"x_\"\ndomain_root = \"rel\"\n", "ipc.domain_root"),
            ("[ipc]\nbuffer = 10\n", "buffer"),
            ("[log]\nformat = \"xml\"\n", "log.format"),
            ("[log]\nlevel = \"info,[\"\n", "log.level"),
            ("[log]\ncolour = true\n", "colour"),
            ("[motion]\nthreshold = 1.0\n", "threshold"),
            ("[state]\ndir = \"relative/dir\"\n", "state.dir"),
            ("[state]\npath = \"/x\"\n", "path"),
            ("[embedding]\ntau = 9223372036854775807\n", "embedding.tau"),
            ("[retrain]\nwindow = 5000000\n", "retrain.window"),
            ("[retrain]\nexact_max_rows = 100000\n", "retrain.exact_max_rows"),
            ("[denoise]\nwindow = 100000000\n", "denoise.window"),
        ] {
            let err = Config::from_toml(text, "x.toml").unwrap_err();
            assert!(err.0.contains(key), "{text}: {err}");
        }
    }

    #[test]
    fn partial_files_keep_the_other_defaults() {
        let c = Config::from_toml("[denoise]\nwindow = 512\n", "x.toml").unwrap();
        assert_eq!(c.denoise.window, 512);
        assert_eq!(c.denoise.lag, DEFAULT_DENOISE_LAG);
        assert_eq!(c.embedding(), Embedding::PAPER);
    }
}
