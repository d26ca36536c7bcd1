//! `[log]` and `[state]`: the daemon's log output and model snapshot directory.

use std::path::PathBuf;

use serde::Deserialize;

use super::keys::by_name;
use super::{Config, ConfigError};

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

/// `[log]` keys (used by `gyrocompd`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LogSection {
    /// `text` (human-readable lines) or `json` (one JSON object per line).
    pub format: LogFormat,
    /// A `tracing` filter: a level (`error` … `trace`) or directives such as `info,iceoryx2=warn`.
    pub level: String,
}

impl Default for LogSection {
    fn default() -> Self {
        Self { format: LogFormat::Text, level: "info".into() }
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

impl<'de> Deserialize<'de> for LogFormat {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        by_name(d, "log.format", &[("text", Self::Text), ("json", Self::Json)])
    }
}

impl Config {
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

    /// The log format of `[log]`, after checking that `level` is a valid filter.
    pub fn log_format(&self) -> Result<LogFormat, ConfigError> {
        tracing_subscriber::EnvFilter::try_new(&self.log.level)
            .map_err(|e| ConfigError(format!("log.level: {:?}: {e}", self.log.level)))?;
        Ok(self.log.format)
    }
}
