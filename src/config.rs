//! The configuration file (`configs/default.toml` documents every key). Parsing rejects unknown
//! keys and bad values with a message naming the key; missing keys take the defaults below,
//! which equal `configs/default.toml` (a test holds them to it).

use std::fmt;

use serde::Deserialize;

use crate::stream::{CausalConfig, Embedding};
use crate::wavelet::{DenoiseConfig, Wavelet};

/// Default causal window (samples): see the trade-off table in the README.
pub const DEFAULT_DENOISE_WINDOW: usize = 256;
/// Default causal lag (samples): see the trade-off table in the README.
pub const DEFAULT_DENOISE_LAG: usize = 5;

/// The whole configuration.
#[derive(Debug, Clone, PartialEq, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// `[denoise]`: wavelet denoising, batch and causal.
    pub denoise: DenoiseSection,
    /// `[embedding]`: phase-space reconstruction.
    pub embedding: EmbeddingSection,
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
    /// Parses TOML text (`origin` names it in messages) and validates every value.
    pub fn from_toml(text: &str, origin: &str) -> Result<Self, ConfigError> {
        let config: Self = toml::from_str(text).map_err(|e| ConfigError(format!("{origin}: {e}")))?;
        config.validate().map_err(|ConfigError(msg)| ConfigError(format!("{origin}: {msg}")))?;
        Ok(config)
    }

    /// Checks values that the types alone do not: names, ranges, and window against lag.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.causal_denoise()?;
        if self.embedding.tau == 0 {
            return Err(ConfigError("embedding.tau must be at least 1".into()));
        }
        if self.embedding.dim == 0 {
            return Err(ConfigError("embedding.dim must be at least 1".into()));
        }
        Ok(())
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
        Embedding { tau: self.embedding.tau, dim: self.embedding.dim }
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
    }

    #[test]
    fn partial_files_keep_the_other_defaults() {
        let c = Config::from_toml("[denoise]\nwindow = 512\n", "x.toml").unwrap();
        assert_eq!(c.denoise.window, 512);
        assert_eq!(c.denoise.lag, DEFAULT_DENOISE_LAG);
        assert_eq!(c.embedding(), Embedding::PAPER);
    }
}
