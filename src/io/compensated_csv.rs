//! The output CSV of the offline drivers, shared by `gyrocomp compensate` and `replay` so that
//! their files can be compared byte for byte.
//!
//! Columns, one row per sample of the [`Recording`], in order:
//! - one rate column: `t_s,raw_dps,drift_dps,compensated_dps,status,model_version`;
//! - several: `t_s`, then per axis (in the recording's column order) `raw_dps_<a>`,
//!   `drift_dps_<a>`, `compensated_dps_<a>`, then `status,model_version`. `<a>` is the rate
//!   column's name without a trailing `_dps` (`gx_dps` → `gx`); when that would make two axes
//!   alike (`gx` and `gx_dps`), the full column names are used.
//!
//! `t_s` and `raw_dps` are the recording's values; `drift_dps`, `compensated_dps`, `status`
//! (the bits of [`crate::stream::sample`]) and `model_version` come from the [`OutputSample`].
//! Numbers are written with Rust's `{}` for `f64`, the shortest text that reads back to the same
//! bits, so equality of two runs survives the file (NaN and infinite raw values, which the
//! pipeline rejects, are written `NaN`, `inf`, `-inf`).

use std::io::{self, Write};
use std::path::Path;

use super::csv_write::create_output;
use super::recording::Recording;
use crate::stream::OutputSample;

/// The header of the output CSV for the recording's rate columns (module documentation).
pub fn compensated_header(columns: &[String]) -> Vec<String> {
    let mut header = vec!["t_s".to_owned()];
    let quantities = ["raw_dps", "drift_dps", "compensated_dps"];
    if columns.len() == 1 {
        header.extend(quantities.map(str::to_owned));
    } else {
        let short: Vec<&str> = columns.iter().map(|c| c.strip_suffix("_dps").unwrap_or(c)).collect();
        let distinct = short.iter().enumerate().all(|(k, s)| !short[..k].contains(s));
        for (k, column) in columns.iter().enumerate() {
            let label = if distinct { short[k] } else { column.as_str() };
            header.extend(quantities.map(|q| format!("{q}_{label}")));
        }
    }
    header.extend(["status".to_owned(), "model_version".to_owned()]);
    header
}

/// Writes the output CSV of one recording, row by row.
pub struct CompensatedCsvWriter<'a> {
    rec: &'a Recording,
    out: Box<dyn Write>,
}

impl<'a> CompensatedCsvWriter<'a> {
    /// Creates `path` (standard output for `-`) and writes the header for `rec`'s columns.
    pub fn create(path: &Path, rec: &'a Recording) -> io::Result<Self> {
        Self::new(create_output(path)?, rec)
    }

    /// Writes the header for `rec`'s columns to `out`.
    pub fn new(mut out: Box<dyn Write>, rec: &'a Recording) -> io::Result<Self> {
        writeln!(out, "{}", compensated_header(rec.columns()).join(","))?;
        Ok(Self { rec, out })
    }

    /// Writes the row of sample `index` of the recording, compensated as `out`. An index past the
    /// end of the recording is an `InvalidInput` error.
    pub fn write(&mut self, index: usize, sample: &OutputSample) -> io::Result<()> {
        let Some(&t_s) = self.rec.t_s().get(index) else {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("row {index} is past the end of the recording ({} rows)", self.rec.len()),
            ));
        };
        write!(self.out, "{t_s}")?;
        for axis in 0..self.rec.columns().len() {
            let raw = self.rec.rate(axis).map_or(f64::NAN, |r| r[index]);
            write!(self.out, ",{raw},{},{}", sample.drift_dps[axis], sample.rate_dps[axis])?;
        }
        writeln!(self.out, ",{},{}", sample.status, sample.model_version)
    }

    /// Flushes what is buffered; call it once at the end (dropping the writer flushes too, but
    /// hides errors).
    pub fn finish(mut self) -> io::Result<()> {
        self.out.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn headers_for_one_and_several_axes() {
        assert_eq!(
            compensated_header(&names(&["gx_dps"])).join(","),
            "t_s,raw_dps,drift_dps,compensated_dps,status,model_version"
        );
        assert_eq!(
            compensated_header(&names(&["gx_dps", "gz_dps"])).join(","),
            "t_s,raw_dps_gx,drift_dps_gx,compensated_dps_gx,raw_dps_gz,drift_dps_gz,compensated_dps_gz,status,model_version"
        );
        let alike = compensated_header(&names(&["gx", "gx_dps"]));
        assert_eq!(alike[1..4], names(&["raw_dps_gx", "drift_dps_gx", "compensated_dps_gx"]));
        assert_eq!(alike[4], "raw_dps_gx_dps");
    }
}
