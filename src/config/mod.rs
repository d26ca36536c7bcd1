//! The configuration file (`configs/default.toml` documents every key). Parsing rejects unknown
//! keys and bad values with a message naming the key; missing keys take the defaults below,
//! which equal `configs/default.toml` (a test holds them to it). One file per subsystem:
//! `pipeline` (`[denoise]` … `[retrain]`), `ipc` (`[ipc]`) and `daemon` (`[log]`, `[state]`); [`Config::load`] is the one way every driver reads a file.

use std::fmt;
use std::path::Path;

use serde::Deserialize;

use crate::stream::{DetectorKind, DriftConfig, EstimatorKind};

mod daemon;
mod ipc;
mod keys;
mod pipeline;

// The sections are the types of `Config`'s fields: they belong to its public face.
pub use daemon::{LogFormat, LogSection, StateSection};
pub use ipc::{DeliveryMode, DomainChoice, IpcSection};
pub use pipeline::{
    DenoiseSection, EmbeddingSection, InputSection, MotionSection, PipelineSection, RateSetting, RetrainSection,
};

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
    /// `[drift]`: the drift estimator (`estimator` is its `kind`).
    pub drift: DriftConfig,
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
        c.drift.kind = EstimatorKind::CpsoLssvm;
        c.motion.detector = DetectorKind::Threshold;
        c.input.rate_hz = RateSetting::Hz(100.0);
        c
    }

    /// Reads and validates the configuration file at `path`; `None` gives the built-in defaults.
    /// What `gyrocomp`, `gyrocompd` (at start and on SIGHUP) and `replay` all call.
    pub fn load(path: Option<&Path>) -> Result<Self, ConfigError> {
        let Some(path) = path else { return Ok(Self::default()) };
        let text =
            std::fs::read_to_string(path).map_err(|e| ConfigError(format!("{}: cannot read: {e}", path.display())))?;
        Self::from_toml(&text, &path.display().to_string())
    }

    /// Parses TOML text (`origin` names it in messages) and validates every value.
    pub fn from_toml(text: &str, origin: &str) -> Result<Self, ConfigError> {
        let config: Self = toml::from_str(text).map_err(|e| ConfigError(format!("{origin}: {e}")))?;
        config.validate().map_err(|ConfigError(msg)| ConfigError(format!("{origin}: {msg}")))?;
        Ok(config)
    }

    /// Checks values that the types alone do not: names, ranges, and window against lag.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.pipeline()?;
        self.ipc_settings()?;
        self.ipc_domain()?;
        self.log_format()?;
        self.state_dir()?;
        self.snapshot_every()?;
        Ok(())
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
            ("motion.window", self.motion.threshold.window, MAX_WINDOW),
            ("ipc.subscriber_buffer", self.ipc.subscriber_buffer, MAX_WINDOW),
            ("retrain.window", self.retrain.schedule.window, MAX_RETRAIN_WINDOW),
            ("retrain.exact_max_rows", self.retrain.fit.exact_max_rows, MAX_EXACT_ROWS),
        ] {
            if value > max {
                return Err(ConfigError(format!("{key}: {value} exceeds the limit {max}")));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::embed::Embedding;

    #[test]
    fn shipped_default_file_equals_the_built_in_defaults() {
        let text = include_str!("../../configs/default.toml");
        assert_eq!(Config::from_toml(text, "configs/default.toml").unwrap(), Config::default());
    }

    #[test]
    fn shipped_10hz_file_loads_and_changes_only_rate_and_gate() {
        let text = include_str!("../../configs/adis16405_10hz.toml");
        let c = Config::from_toml(text, "configs/adis16405_10hz.toml").unwrap();
        c.pipeline().unwrap();
        let m = &c.motion.threshold;
        assert_eq!((c.input.rate_hz, m.rate_dps, m.variance_dps2), (RateSetting::Hz(10.0), 1.0, 0.05));
        let mut expected = Config::default();
        let e = &mut expected.motion.threshold;
        (expected.input.rate_hz, e.rate_dps, e.variance_dps2) = (RateSetting::Hz(10.0), 1.0, 0.05);
        expected.motion.detector = DetectorKind::Threshold;
        expected.drift.kind = EstimatorKind::CpsoLssvm;
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
    fn load_names_an_unreadable_file_and_reads_a_good_one() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("missing.toml");
        let err = Config::load(Some(&missing)).unwrap_err();
        assert!(err.0.starts_with(&format!("{}: cannot read:", missing.display())), "{err}");
        let bad = dir.path().join("bad.toml");
        std::fs::write(&bad, "[denoise]\nwindw = 1\n").unwrap();
        let err = Config::load(Some(&bad)).unwrap_err();
        assert!(err.0.starts_with(&format!("{}:", bad.display())) && err.0.contains("windw"), "{err}");
        let good = dir.path().join("good.toml");
        std::fs::write(&good, "[denoise]\nwindow = 512\n").unwrap();
        assert_eq!(Config::load(Some(&good)).unwrap().denoise.window, 512);
        assert_eq!(Config::load(None).unwrap(), Config::default());
    }

    #[test]
    fn partial_files_keep_the_other_defaults() {
        let c = Config::from_toml("[denoise]\nwindow = 512\n", "x.toml").unwrap();
        assert_eq!(c.denoise.window, 512);
        assert_eq!(c.denoise.lag, DEFAULT_DENOISE_LAG);
        assert_eq!(c.embedding(), Embedding::PAPER);
    }
}
