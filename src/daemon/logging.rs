//! The daemon's log output: `tracing` events on stderr, as text or JSON lines (`[log]`).

use tracing_subscriber::EnvFilter;

use crate::config::{Config, ConfigError, LogFormat};

/// Installs the global `tracing` subscriber of `[log]`. Fails on a bad `[log]` section or when
/// a subscriber is already installed.
pub fn init(config: &Config) -> Result<(), ConfigError> {
    let format = config.log_format()?;
    let filter = EnvFilter::try_new(&config.log.level).map_err(|e| ConfigError(format!("log.level: {e}")))?;
    // Colours only on a terminal: a file or the journal would get the escape codes as text.
    let ansi = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let builder = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .with_target(false)
        .with_ansi(ansi);
    let installed = match format {
        LogFormat::Text => builder.try_init(),
        LogFormat::Json => builder.json().try_init(),
    };
    installed.map_err(|e| ConfigError(format!("log: {e}")))
}
