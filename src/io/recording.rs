//! A recording as the offline drivers see it (docs/design.md "One pipeline, three drivers"): the
//! file of `gyrocomp compensate`, of `replay` and of the motion-injected evaluation (any format of
//! the reader layer, [`super::source`]: CSV or a ROS 2 bag), loaded once with its streaming
//! reader (errors name the line or message and the field) and handed to the pipeline sample by
//! sample as [`InputSample`]s.
//!
//! - 1 to 3 chosen rate columns (deg/s) become the axes x, y, z in the order given; axes the
//!   recording does not have are 0.0.
//! - `temp_c` is carried when the file has it (NaN where absent or empty).
//! - An optional moving-flag column (values 0 or 1) sets [`FLAG_MOVING`], the publisher's "the
//!   platform is moving".
//! - Rates may be NaN or infinite (the pipeline rejects such samples itself, status bit 2); time
//!   must be finite, non-negative and strictly increasing.
//! - Time becomes the pipeline's `t_ns` by [`t_ns_from_s`], the one conversion every driver uses,
//!   unless the format has exact ns stamps (MCAP header stamps), which are taken as they are.

use std::path::{Path, PathBuf};

use super::csv_read::{CsvError, ReadOptions};
use super::source::{InputError, InputOptions, Request, open_samples};
use crate::stream::{FLAG_MOVING, InputSample};

/// Most rate columns a recording maps to axes (x, y, z).
pub const MAX_AXES: usize = 3;

/// Largest time [`t_ns_from_s`] accepts, exclusive: 2⁶⁴ ns, about 584 years.
const T_NS_LIMIT: f64 = 18_446_744_073_709_551_616.0;

/// The timestamp (ns) of a recording's time `t_s` (seconds): `round(t_s · 10⁹)`, rounded to the
/// nearest ns so that decimal times such as 0.1 s give 100,000,000 ns exactly. `None` when `t_s`
/// is negative, not finite, or at least 2⁶⁴ ns: such a time has no `u64` timestamp, and
/// [`Recording::load`] refuses it with the line named.
pub fn t_ns_from_s(t_s: f64) -> Option<u64> {
    if !t_s.is_finite() || t_s < 0.0 {
        return None;
    }
    let ns = (t_s * 1e9).round();
    (ns < T_NS_LIMIT).then_some(ns as u64)
}

/// Why a recording could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum RecordingError {
    /// A problem in a CSV file, located by file, line and field.
    #[error(transparent)]
    Csv(#[from] CsvError),
    /// A problem in another input (an MCAP bag: file, topic, message and field) or an option
    /// that does not fit the file.
    #[error(transparent)]
    Input(InputError),
    /// The columns asked for cannot make a recording (none, more than three, repeated).
    #[error("{0}")]
    Columns(String),
}

impl From<InputError> for RecordingError {
    fn from(e: InputError) -> Self {
        match e {
            InputError::Csv(e) => Self::Csv(e),
            other => Self::Input(other),
        }
    }
}

/// A gyro recording in memory: time, 1–3 rate columns, temperature and moving flags per row.
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    path: PathBuf,
    columns: Vec<String>,
    moving_column: Option<String>,
    t_s: Vec<f64>,
    t_ns: Vec<u64>,
    rates: Vec<Vec<f64>>,
    temp_c: Option<Vec<f64>>,
    moving: Option<Vec<bool>>,
}

impl Recording {
    /// Loads `columns` (1–3 rate columns, axes x, y, z in that order) of the CSV at `path`, and
    /// the 0/1 flags of `moving_column` when given: [`Recording::load_with`] with the default
    /// [`InputOptions`].
    pub fn load(path: &Path, columns: &[&str], moving_column: Option<&str>) -> Result<Self, RecordingError> {
        Self::load_with(path, columns, moving_column, &InputOptions::default())
    }

    /// Loads `columns` (1–3 rate columns, axes x, y, z in that order) of the recording at `path`
    /// (any format of [`super::source`], read with `input`), and the 0/1 flags of
    /// `moving_column` when given. Every problem in the file is an error naming the file, the
    /// line or message and the field.
    pub fn load_with(
        path: &Path,
        columns: &[&str],
        moving_column: Option<&str>,
        input: &InputOptions,
    ) -> Result<Self, RecordingError> {
        if columns.is_empty() || columns.len() > MAX_AXES {
            return Err(RecordingError::Columns(format!(
                "{}: give 1 to {MAX_AXES} rate columns, not {}",
                path.display(),
                columns.len()
            )));
        }
        let mut wanted: Vec<&str> = columns.to_vec();
        wanted.extend(moving_column);
        for (k, name) in wanted.iter().enumerate() {
            if wanted[..k].contains(name) {
                return Err(RecordingError::Columns(format!("{}: column `{name}` is asked for twice", path.display())));
            }
        }
        let read = ReadOptions { allow_non_finite: true, require_increasing_time: true };
        let extra: Vec<&str> = moving_column.into_iter().collect();
        let mut source = open_samples(path, &Request { rates: columns, extra: &extra, read, input })?;
        let mut rec = Self {
            path: path.to_path_buf(),
            columns: columns.iter().map(|&c| c.to_owned()).collect(),
            moving_column: moving_column.map(str::to_owned),
            t_s: Vec::new(),
            t_ns: Vec::new(),
            rates: vec![Vec::new(); columns.len()],
            temp_c: source.has_temperature().then(Vec::new),
            moving: moving_column.map(|_| Vec::new()),
        };
        loop {
            let (record, t_s, t_ns, temp_c, flag) = match source.next_sample()? {
                None => break,
                Some(s) => {
                    for (column, &v) in rec.rates.iter_mut().zip(s.values) {
                        column.push(v);
                    }
                    (s.record, s.t_s, s.t_ns, s.temp_c, s.values.get(columns.len()).copied())
                }
            };
            let t_ns = t_ns.or_else(|| t_ns_from_s(t_s)).ok_or_else(|| {
                let field = source.time_field().to_owned();
                source.invalid(record, &field, format!("time {t_s} s has no ns timestamp: it must be ≥ 0"))
            })?;
            rec.t_s.push(t_s);
            rec.t_ns.push(t_ns);
            if let Some(temp) = rec.temp_c.as_mut() {
                temp.push(temp_c.unwrap_or(f64::NAN));
            }
            if let (Some(flags), Some(name), Some(v)) = (rec.moving.as_mut(), moving_column, flag) {
                if v != 0.0 && v != 1.0 {
                    return Err(source.invalid(record, name, format!("{v} is not a moving flag: 0 or 1")).into());
                }
                flags.push(v == 1.0);
            }
        }
        if rec.t_s.is_empty() {
            return Err(source.no_data().into());
        }
        Ok(rec)
    }

    /// The file it was loaded from.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Number of samples (data rows).
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    /// Whether there are no samples (never true for a loaded recording).
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    /// Names of the rate columns, axis x first.
    pub fn columns(&self) -> &[String] {
        &self.columns
    }

    /// Name of the moving-flag column, when one was loaded.
    pub fn moving_column(&self) -> Option<&str> {
        self.moving_column.as_deref()
    }

    /// Time of each sample as written in the file, seconds.
    pub fn t_s(&self) -> &[f64] {
        &self.t_s
    }

    /// The rates of one axis (index into [`Recording::columns`]), deg/s; `None` for an axis the
    /// recording does not have.
    pub fn rate(&self, axis: usize) -> Option<&[f64]> {
        self.rates.get(axis).map(Vec::as_slice)
    }

    /// The moving flags, when a moving column was loaded.
    pub fn moving(&self) -> Option<&[bool]> {
        self.moving.as_deref()
    }

    /// Removes the moving flags and returns them: [`Recording::input`] then sets no flag.
    pub fn take_moving(&mut self) -> Option<Vec<bool>> {
        self.moving_column = None;
        self.moving.take()
    }

    /// Mean sample rate, Hz, `(n − 1) / (t_last − t_first)`; `None` with a single sample.
    pub fn sample_rate_hz(&self) -> Option<f64> {
        let n = self.t_s.len();
        (n >= 2).then(|| (n - 1) as f64 / (self.t_s[n - 1] - self.t_s[0]))
    }

    /// Sample `i` as pipeline input: `seq = i`, `t_ns` = [`t_ns_from_s`] of its time, the rate
    /// columns on axes x, y, z (0.0 on the missing ones), `temp_c` (NaN without one) and
    /// [`FLAG_MOVING`] when its moving flag is 1. Panics when `i >= len()`.
    pub fn input(&self, i: usize) -> InputSample {
        let mut rate_dps = [0.0; MAX_AXES];
        for (r, column) in rate_dps.iter_mut().zip(&self.rates) {
            *r = column[i];
        }
        let moving = self.moving.as_ref().is_some_and(|m| m[i]);
        InputSample {
            seq: i as u64,
            t_ns: self.t_ns[i],
            rate_dps,
            temp_c: self.temp_c.as_ref().map_or(f64::NAN, |t| t[i]),
            flags: if moving { FLAG_MOVING } else { 0 },
        }
    }

    /// Every sample as pipeline input, in order ([`Recording::input`]).
    pub fn inputs(&self) -> impl ExactSizeIterator<Item = InputSample> + '_ {
        (0..self.len()).map(|i| self.input(i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_to_ns_rounds_and_refuses_what_has_no_timestamp() {
        assert_eq!(t_ns_from_s(0.0), Some(0));
        assert_eq!(t_ns_from_s(0.1), Some(100_000_000));
        assert_eq!(t_ns_from_s(0.3), Some(300_000_000)); // 0.3 · 1e9 = 299999999.99999994
        assert_eq!(t_ns_from_s(12345.6789), Some(12_345_678_900_000));
        assert_eq!(t_ns_from_s(1.5e-9), Some(2));
        assert_eq!(t_ns_from_s(-1e-3), None);
        assert_eq!(t_ns_from_s(f64::NAN), None);
        assert_eq!(t_ns_from_s(f64::INFINITY), None);
        assert_eq!(t_ns_from_s(2e10), None);
        assert_eq!(t_ns_from_s(1.8e10), Some(18_000_000_000_000_000_000));
    }
}
