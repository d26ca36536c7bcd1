//! Loading one rate column of a recording for the offline commands.

use std::path::Path;

use crate::io::{ReadOptions, Table, read_table};

use super::CliError;

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
}

/// Reads `column` of the CSV at `path`; the sample rate comes from `rate_override` or the time
/// column, and must be positive and finite.
pub fn load_series(path: &Path, column: &str, rate_override: Option<f64>) -> Result<Series, CliError> {
    let Table { t_s, mut columns, temp_c, .. } = read_table(path, &[column], ReadOptions::default())?;
    let values = columns.pop().expect("one column was asked for");
    let rate_hz = match rate_override {
        Some(r) => r,
        None if t_s.len() >= 2 => (t_s.len() - 1) as f64 / (t_s[t_s.len() - 1] - t_s[0]),
        None => {
            return Err(
                format!("{}: one sample is not enough to know the sample rate; pass --rate", path.display()).into()
            );
        }
    };
    if !(rate_hz.is_finite() && rate_hz > 0.0) {
        return Err(format!("{}: sample rate {rate_hz} Hz is not positive and finite", path.display()).into());
    }
    Ok(Series { t_s, values, rate_hz, temp_c })
}

