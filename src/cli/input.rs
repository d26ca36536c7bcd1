//! Loading a recording for the offline commands: the input options every command that reads a
//! recording takes (`--topic`, `--units`, docs/inputs.md) and one rate column with its time
//! stamps.

use std::path::Path;

use crate::io::sampling::GAP_FACTOR;
use crate::io::{InputOptions, RateUnit, ReadOptions, Sampling, Table, read_columns, sampling};

use super::CliError;

/// The options of the input file, shared by every command that reads a recording.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct InputArgs {
    /// MCAP input (ROS 2 bag): the sensor_msgs/msg/Imu topic to read (default: the only one).
    #[arg(long)]
    pub topic: Option<String>,
    /// Unit of the rate columns of a gyrocomp CSV: dps (deg/s, the default) or rads (rad/s,
    /// converted to deg/s). EuRoC CSV and MCAP bags are rad/s by definition.
    #[arg(long, value_name = "dps|rads")]
    pub units: Option<RateUnit>,
}

impl InputArgs {
    /// The reader layer's options.
    pub fn options(&self) -> InputOptions {
        InputOptions { topic: self.topic.clone(), units: self.units }
    }
}

/// One column of a recording with its time stamps.
#[derive(Debug, Clone)]
pub struct Series {
    /// Time of each sample, seconds.
    pub t_s: Vec<f64>,
    /// The rate values, deg/s.
    pub values: Vec<f64>,
    /// Sample rate, Hz, from the time column (or the `--rate` override).
    pub rate_hz: f64,
    /// The `temp_c` column when the file has one (NaN where a row leaves it empty).
    pub temp_c: Option<Vec<f64>>,
    /// The MCAP topic read (`None` for CSV).
    pub topic: Option<String>,
}

/// Reads `column` of the recording at `path` (CSV or MCAP, read with `input`); the sample rate
/// comes from `rate_override` or the time stamps ([`sampling()`]: not lowered by dropouts), and must
/// be positive and finite. Dropouts and irregular stamps are logged as warnings
/// ([`warn_uneven`]): the analyses take the samples as equally spaced.
pub fn load_series(
    path: &Path,
    column: &str,
    rate_override: Option<f64>,
    input: &InputOptions,
) -> Result<Series, CliError> {
    let Table { t_s, mut columns, temp_c, topic, .. } = read_columns(path, &[column], ReadOptions::default(), input)?;
    let values = columns.pop().expect("one column was asked for");
    let measured = sampling(&t_s);
    if let Some(s) = &measured {
        warn_uneven(path, s);
    }
    let rate_hz = match (rate_override, measured) {
        (Some(r), _) => r,
        (None, Some(s)) => s.rate_hz,
        (None, None) => {
            return Err(
                format!("{}: one sample is not enough to know the sample rate; pass --rate", path.display()).into()
            );
        }
    };
    if !(rate_hz.is_finite() && rate_hz > 0.0) {
        return Err(format!("{}: sample rate {rate_hz} Hz is not positive and finite", path.display()).into());
    }
    Ok(Series { t_s, values, rate_hz, temp_c, topic })
}

/// Logs a warning when the time stamps of `path` are not equally spaced ([`Sampling`]): where the
/// first dropouts lie (sample index and time) and how many samples are missing in all, or how
/// many intervals are irregular. The offline analyses join the samples on either side of a
/// dropout as if they were consecutive.
pub fn warn_uneven(path: &Path, s: &Sampling) {
    const SHOWN: usize = 3;
    if s.irregular > 0 {
        tracing::warn!(
            "{}: irregular time stamps ({} intervals over {} median intervals); the samples are taken as equally spaced at the mean rate {:.6} Hz",
            path.display(),
            s.irregular,
            GAP_FACTOR,
            s.rate_hz
        );
    }
    if s.gaps.is_empty() {
        return;
    }
    let listed: Vec<String> = s
        .gaps
        .iter()
        .take(SHOWN)
        .map(|g| format!("after sample {} (t = {:.3} s, {:.3} s to the next)", g.index, g.from_s, g.to_s - g.from_s))
        .collect();
    let more = if s.gaps.len() > SHOWN { format!(" and {} more", s.gaps.len() - SHOWN) } else { String::new() };
    tracing::warn!(
        "{}: {} dropout(s), {} samples missing in all: {}{}; the samples either side are joined as if consecutive, at {:.6} Hz",
        path.display(),
        s.gaps.len(),
        s.missing(),
        listed.join(", "),
        more,
        s.rate_hz
    );
}
