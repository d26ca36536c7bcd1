//! Streaming CSV reader for gyro recordings.
//!
//! A [`SampleReader`] walks the file one record at a time through a reused buffer, so a
//! 1,000,000-row file is never held in memory as text: only the selected columns end up in memory,
//! once, as `f64`. Every problem is reported as a [`CsvError`] that names the file, the line and
//! the field.

use std::fmt;
use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};

/// Accepted names of the time column, in order of preference (design.md "CSV conventions").
pub const TIME_COLUMN_NAMES: [&str; 3] = ["t_s", "t", "time"];
/// Name of the optional temperature column.
pub const TEMP_COLUMN: &str = "temp_c";

/// What went wrong while reading a CSV file.
#[derive(Debug)]
pub enum CsvErrorKind {
    /// The file could not be opened or read.
    Io(std::io::Error),
    /// The file has no header line.
    Empty,
    /// The file has a header but no data rows.
    NoData,
    /// A requested column is not in the header.
    MissingColumn {
        /// The column asked for.
        wanted: String,
        /// The columns the header has.
        available: Vec<String>,
    },
    /// A row has fewer fields than the header requires.
    MissingField {
        /// Fields found in the row.
        found: usize,
    },
    /// A field is not a number.
    BadNumber(String),
    /// A field is NaN or infinite where a finite number is required.
    NonFinite(String),
    /// Time does not strictly increase from the previous row.
    TimeNotIncreasing {
        /// Time of the previous row, seconds.
        previous: f64,
        /// Time of this row, seconds.
        current: f64,
    },
    /// The CSV structure itself is broken (e.g. invalid UTF-8 in the header, unequal quoting).
    Malformed(String),
}

impl fmt::Display for CsvErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(e) => write!(f, "cannot read: {e}"),
            Self::Empty => write!(f, "empty file: a header line is required"),
            Self::NoData => write!(f, "no data rows after the header"),
            Self::MissingColumn { wanted, available } => write!(
                f,
                "column `{wanted}` not found; the header has: {}",
                available.join(", ")
            ),
            Self::MissingField { found } => write!(f, "missing: the row has only {found} field(s)"),
            Self::BadNumber(text) => write!(f, "not a number: {text:?}"),
            Self::NonFinite(text) => write!(f, "not a finite number: {text:?}"),
            Self::TimeNotIncreasing { previous, current } => write!(
                f,
                "time does not increase: {current} s follows {previous} s"
            ),
            Self::Malformed(msg) => write!(f, "malformed CSV: {msg}"),
        }
    }
}

/// A CSV problem, located by file, line (1-based, the header is line 1) and field name.
#[derive(Debug)]
pub struct CsvError {
    /// The file being read (or a label such as `<stdin>`).
    pub path: PathBuf,
    /// 1-based line number, when the problem sits on a line.
    pub line: Option<u64>,
    /// The column name of the offending field, when one field is at fault.
    pub field: Option<String>,
    /// What went wrong.
    pub kind: CsvErrorKind,
}

impl fmt::Display for CsvError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.path.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        if let Some(field) = &self.field {
            write!(f, ": field `{field}`")?;
        }
        write!(f, ": {}", self.kind)
    }
}

impl std::error::Error for CsvError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.kind {
            CsvErrorKind::Io(e) => Some(e),
            _ => None,
        }
    }
}

/// How strict the reader is.
#[derive(Debug, Clone, Copy)]
pub struct ReadOptions {
    /// Accept `NaN`/`inf` in value columns (the streaming pipeline flags such samples itself);
    /// when false they are errors. Time must always be finite.
    pub allow_non_finite: bool,
    /// Require time to strictly increase from row to row.
    pub require_increasing_time: bool,
}

impl Default for ReadOptions {
    fn default() -> Self {
        Self { allow_non_finite: false, require_increasing_time: true }
    }
}

/// One parsed data row, borrowed from the reader's buffers.
#[derive(Debug, Clone, Copy)]
pub struct Row<'a> {
    /// 1-based line number of the row in the file.
    pub line: u64,
    /// Time, seconds.
    pub t_s: f64,
    /// The selected value columns, in the order they were asked for.
    pub values: &'a [f64],
    /// Temperature in °C when the file has a `temp_c` column and the field is not empty; NaN is
    /// kept as NaN (design.md: NaN = none).
    pub temp_c: Option<f64>,
}

/// Streaming reader of the selected columns of a gyro CSV file.
pub struct SampleReader<R: Read> {
    path: PathBuf,
    reader: csv::Reader<R>,
    record: csv::ByteRecord,
    names: Vec<String>,
    time_name: String,
    time_idx: usize,
    value_idx: Vec<usize>,
    temp_idx: Option<usize>,
    values: Vec<f64>,
    previous_t: Option<f64>,
    rows: u64,
    options: ReadOptions,
}

impl SampleReader<File> {
    /// Opens `path` and selects the value `columns` (plus time and, if present, `temp_c`).
    pub fn open(path: &Path, columns: &[&str], options: ReadOptions) -> Result<Self, CsvError> {
        let file = File::open(path).map_err(|e| CsvError {
            path: path.to_path_buf(),
            line: None,
            field: None,
            kind: CsvErrorKind::Io(e),
        })?;
        Self::from_reader(file, path, columns, options)
    }
}

impl<R: Read> SampleReader<R> {
    /// Wraps any reader; `label` names it in error messages.
    pub fn from_reader(
        input: R,
        label: &Path,
        columns: &[&str],
        options: ReadOptions,
    ) -> Result<Self, CsvError> {
        let path = label.to_path_buf();
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(true)
            .flexible(true)
            .trim(csv::Trim::All)
            .buffer_capacity(1 << 16)
            .from_reader(input);
        let header_err = |kind| CsvError { path: path.clone(), line: Some(1), field: None, kind };
        let headers = reader
            .headers()
            .map_err(|e| header_err(malformed_or_io(e)))?
            .clone();
        if headers.is_empty() || (headers.len() == 1 && headers[0].is_empty()) {
            return Err(CsvError { path, line: None, field: None, kind: CsvErrorKind::Empty });
        }
        let names: Vec<String> = headers.iter().map(str::to_owned).collect();
        let find = |wanted: &str| names.iter().position(|n| n == wanted);
        let (time_idx, time_name) = TIME_COLUMN_NAMES
            .iter()
            .find_map(|&n| find(n).map(|i| (i, n.to_owned())))
            .ok_or_else(|| {
                header_err(CsvErrorKind::MissingColumn {
                    wanted: TIME_COLUMN_NAMES.join("` or `"),
                    available: names.clone(),
                })
            })?;
        let value_idx = columns
            .iter()
            .map(|&c| {
                find(c).ok_or_else(|| {
                    header_err(CsvErrorKind::MissingColumn {
                        wanted: c.to_owned(),
                        available: names.clone(),
                    })
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let temp_idx = find(TEMP_COLUMN);
        Ok(Self {
            path,
            reader,
            record: csv::ByteRecord::new(),
            values: vec![0.0; value_idx.len()],
            names,
            time_name,
            time_idx,
            value_idx,
            temp_idx,
            previous_t: None,
            rows: 0,
            options,
        })
    }

    /// Names of all columns in the header.
    pub fn header(&self) -> &[String] {
        &self.names
    }

    /// Whether the file has a `temp_c` column.
    pub fn has_temperature(&self) -> bool {
        self.temp_idx.is_some()
    }

    /// Number of data rows returned so far.
    pub fn rows_read(&self) -> u64 {
        self.rows
    }

    /// Reads the next row; `Ok(None)` at the end of the file. Blank lines are skipped.
    pub fn next_row(&mut self) -> Result<Option<Row<'_>>, CsvError> {
        let more = self.reader.read_byte_record(&mut self.record).map_err(|e| CsvError {
            path: self.path.clone(),
            line: e.position().map(|p| p.line()),
            field: None,
            kind: malformed_or_io(e),
        })?;
        if !more {
            return Ok(None);
        }
        let line = self.record.position().map_or(0, |p| p.line());
        let t_s = self.field(line, self.time_idx, false)?;
        if self.options.require_increasing_time
            && let Some(previous) = self.previous_t
            && t_s <= previous
        {
            return Err(self.error(
                line,
                self.time_idx,
                CsvErrorKind::TimeNotIncreasing { previous, current: t_s },
            ));
        }
        self.previous_t = Some(t_s);
        for k in 0..self.value_idx.len() {
            self.values[k] = self.field(line, self.value_idx[k], self.options.allow_non_finite)?;
        }
        let temp_c = match self.temp_idx {
            Some(i) if self.record.get(i).is_some_and(|f| !f.is_empty()) => {
                Some(self.field(line, i, true)?)
            }
            _ => None,
        };
        self.rows += 1;
        Ok(Some(Row { line, t_s, values: &self.values, temp_c }))
    }

    fn field(&self, line: u64, idx: usize, allow_non_finite: bool) -> Result<f64, CsvError> {
        let Some(bytes) = self.record.get(idx) else {
            return Err(self.error(line, idx, CsvErrorKind::MissingField { found: self.record.len() }));
        };
        let text = String::from_utf8_lossy(bytes);
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() || allow_non_finite => Ok(v),
            Ok(_) => Err(self.error(line, idx, CsvErrorKind::NonFinite(text.into_owned()))),
            Err(_) => Err(self.error(line, idx, CsvErrorKind::BadNumber(text.into_owned()))),
        }
    }

    fn error(&self, line: u64, idx: usize, kind: CsvErrorKind) -> CsvError {
        let field = if idx == self.time_idx { self.time_name.clone() } else { self.names[idx].clone() };
        CsvError { path: self.path.clone(), line: Some(line), field: Some(field), kind }
    }
}

fn malformed_or_io(e: csv::Error) -> CsvErrorKind {
    let msg = e.to_string();
    match e.into_kind() {
        csv::ErrorKind::Io(io) => CsvErrorKind::Io(io),
        _ => CsvErrorKind::Malformed(msg),
    }
}

/// Selected columns of a recording, held in memory as `f64` (one copy, no text).
#[derive(Debug, Clone, Default)]
pub struct Table {
    /// Time of each row, seconds.
    pub t_s: Vec<f64>,
    /// Names of the value columns, in the order asked for.
    pub names: Vec<String>,
    /// One vector per value column, each `t_s.len()` long.
    pub columns: Vec<Vec<f64>>,
    /// Temperature per row (NaN where absent) when the file has a `temp_c` column.
    pub temp_c: Option<Vec<f64>>,
}

impl Table {
    /// Number of rows.
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    /// Whether the table has no rows.
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    /// The values of the column called `name`, if selected.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.names.iter().position(|n| n == name).map(|i| self.columns[i].as_slice())
    }

    /// Mean sample rate in Hz, `(n − 1) / (t_last − t_first)`; `None` with fewer than two rows.
    pub fn sample_rate_hz(&self) -> Option<f64> {
        let n = self.t_s.len();
        (n >= 2).then(|| (n - 1) as f64 / (self.t_s[n - 1] - self.t_s[0]))
    }
}

/// Reads the selected `columns` of the CSV file at `path` into a [`Table`], streaming.
///
/// Fails on an empty file, a header without data rows, a missing column, a field that is not a
/// finite number, or time that does not strictly increase.
pub fn read_table(path: &Path, columns: &[&str], options: ReadOptions) -> Result<Table, CsvError> {
    let mut reader = SampleReader::open(path, columns, options)?;
    let mut table = Table {
        names: columns.iter().map(|&c| c.to_owned()).collect(),
        columns: vec![Vec::new(); columns.len()],
        temp_c: reader.has_temperature().then(Vec::new),
        ..Table::default()
    };
    while let Some(row) = reader.next_row()? {
        table.t_s.push(row.t_s);
        for (column, &v) in table.columns.iter_mut().zip(row.values) {
            column.push(v);
        }
        if let Some(temp) = table.temp_c.as_mut() {
            temp.push(row.temp_c.unwrap_or(f64::NAN));
        }
    }
    if table.is_empty() {
        return Err(CsvError { path: path.to_path_buf(), line: None, field: None, kind: CsvErrorKind::NoData });
    }
    Ok(table)
}
