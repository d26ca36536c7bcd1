//! Streaming CSV reader for gyro recordings.
//!
//! A [`SampleReader`] walks the file one line at a time through reused buffers, so a
//! 1,000,000-row file is never held in memory as text: only the selected columns end up in memory,
//! once, as `f64`. Every problem is reported as a [`CsvError`] that names the file, the line and
//! the field.
//!
//! Accepted: a header line, comma-separated fields, LF or CRLF line ends, a UTF-8 byte-order mark,
//! blank lines (skipped, but counted), spaces around fields, and fields in double quotes (with `""`
//! for a quote). A quoted field may not span lines: recordings are numeric, and a line count that
//! is always right matters more here. (The `csv` crate was tried first; its record positions are
//! off by one after blank lines and on CRLF files, so error messages named the wrong line.)
//!
//! The header also decides the dialect ([`Dialect`]): gyrocomp's own, or EuRoC / TUM-VI (ns
//! timestamps, rad/s), whose values are converted to seconds and deg/s as they are read.

use std::fmt;
use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::ops::Range;
use std::path::{Path, PathBuf};

use super::csv_dialect::first_named;
pub use super::csv_dialect::{Dialect, TIME_COLUMN_NAMES};

/// Accepted names of the optional temperature column (°C), in order of preference: gyrocomp's own,
/// then what other writers call it (docs/design.md "CSV conventions"). A recording whose
/// temperature is named otherwise would lose the temperature response as a candidate effect
/// without a word, so the names a user's logger is likely to write are taken as they are.
pub const TEMP_COLUMN_NAMES: [&str; 4] = ["temp_c", "temperature_c", "temperature", "temp"];
/// Longest accepted line, bytes: a longer one (a binary file, a file without line ends) is an
/// error instead of a buffer that grows with the file.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// Reads one line (through `\n`) into `buf`, at most [`MAX_LINE_BYTES`] of it; `Err(None)` when
/// the line is longer.
fn read_line<B: BufRead>(reader: &mut B, buf: &mut Vec<u8>) -> Result<usize, Option<std::io::Error>> {
    let read = reader.take(MAX_LINE_BYTES as u64 + 1).read_until(b'\n', buf).map_err(Some)?;
    if buf.len() > MAX_LINE_BYTES && buf.last() != Some(&b'\n') {
        return Err(None);
    }
    Ok(read)
}

fn too_long() -> CsvErrorKind {
    CsvErrorKind::Malformed(format!("line longer than {MAX_LINE_BYTES} bytes (not a line-oriented text file?)"))
}

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
    /// A number that the reader of the file cannot use (e.g. a negative time, a flag that is not
    /// 0 or 1); the message says what was expected.
    Invalid(String),
}

impl fmt::Display for CsvErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(e) => write!(f, "cannot read: {e}"),
            Self::Empty => write!(f, "empty file: a header line is required"),
            Self::NoData => write!(f, "no data rows after the header"),
            Self::MissingColumn { wanted, available } => {
                write!(f, "column `{wanted}` not found; the header has: {}", available.join(", "))
            }
            Self::MissingField { found } => write!(f, "missing: the row has only {found} field(s)"),
            Self::BadNumber(text) => write!(f, "not a number: {text:?}"),
            Self::NonFinite(text) => write!(f, "not a finite number: {text:?}"),
            Self::TimeNotIncreasing { previous, current } => {
                write!(f, "time does not increase: {current} s follows {previous} s")
            }
            Self::Malformed(msg) => write!(f, "malformed CSV: {msg}"),
            Self::Invalid(msg) => f.write_str(msg),
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
    /// kept as NaN (docs/design.md: NaN = none).
    pub temp_c: Option<f64>,
}

/// Streaming reader of the selected columns of a gyro CSV file.
pub struct SampleReader<R: Read> {
    path: PathBuf,
    reader: BufReader<R>,
    line_buf: Vec<u8>,
    line_no: u64,
    fields: Fields,
    names: Vec<String>,
    time_name: String,
    time_idx: usize,
    /// Factor from the time column's unit to seconds.
    time_scale: f64,
    value_idx: Vec<usize>,
    /// Factor from each value column's unit to gyrocomp's (deg/s).
    value_scale: Vec<f64>,
    temp_idx: Option<usize>,
    values: Vec<f64>,
    previous_t: Option<f64>,
    rows: u64,
    options: ReadOptions,
    /// Line number of the header.
    header_line: u64,
    dialect: Dialect,
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
    pub fn from_reader(input: R, label: &Path, columns: &[&str], options: ReadOptions) -> Result<Self, CsvError> {
        let path = label.to_path_buf();
        let mut reader = BufReader::with_capacity(1 << 16, input);
        let mut line_buf = Vec::with_capacity(256);
        let mut line_no = 0;
        let mut fields = Fields::default();
        let io_err =
            |path: &Path, line, e| CsvError { path: path.to_path_buf(), line, field: None, kind: CsvErrorKind::Io(e) };
        // The header is the first non-blank line.
        loop {
            line_buf.clear();
            let read = read_line(&mut reader, &mut line_buf).map_err(|e| match e {
                Some(e) => io_err(&path, None, e),
                None => CsvError { path: path.clone(), line: Some(line_no + 1), field: None, kind: too_long() },
            })?;
            if read == 0 {
                return Err(CsvError { path, line: None, field: None, kind: CsvErrorKind::Empty });
            }
            line_no += 1;
            if line_no == 1 && line_buf.starts_with(b"\xEF\xBB\xBF") {
                line_buf.drain(..3);
            }
            if !is_blank(&line_buf) {
                break;
            }
        }
        let header_line = line_no;
        let header_err = |kind| CsvError { path: path.clone(), line: Some(header_line), field: None, kind };
        fields.split(&line_buf).map_err(|msg| header_err(CsvErrorKind::Malformed(msg.to_owned())))?;
        let names: Vec<String> = (0..fields.len())
            .map(|i| String::from_utf8_lossy(fields.get(i).unwrap_or_default()).into_owned())
            .collect();
        let dialect = Dialect::of(&names);
        let (time, time_name) = dialect.time(&names).ok_or_else(|| {
            header_err(CsvErrorKind::MissingColumn { wanted: dialect.time_names(), available: names.clone() })
        })?;
        let resolved = columns
            .iter()
            .map(|&c| {
                dialect.column(&names, c).ok_or_else(|| {
                    header_err(CsvErrorKind::MissingColumn { wanted: c.to_owned(), available: names.clone() })
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let temp_idx = first_named(&names, &TEMP_COLUMN_NAMES);
        Ok(Self {
            path,
            reader,
            line_buf,
            line_no,
            fields,
            values: vec![0.0; resolved.len()],
            names,
            time_name,
            time_idx: time.index,
            time_scale: time.scale,
            value_idx: resolved.iter().map(|r| r.index).collect(),
            value_scale: resolved.iter().map(|r| r.scale).collect(),
            temp_idx,
            previous_t: None,
            rows: 0,
            header_line,
            options,
            dialect,
        })
    }

    /// The dialect the header shows.
    pub fn dialect(&self) -> Dialect {
        self.dialect
    }

    /// Line number of the header.
    pub fn header_line(&self) -> u64 {
        self.header_line
    }

    /// Multiplies the values of the `k`-th selected column by `factor` as they are read (a unit
    /// conversion, e.g. rad/s → deg/s for `--units rads`). Panics when `k` is not a selected
    /// column.
    pub fn scale_column(&mut self, k: usize, factor: f64) {
        self.value_scale[k] *= factor;
    }

    /// Names of all columns in the header.
    pub fn header(&self) -> &[String] {
        &self.names
    }

    /// Name of the time column found in the header (one of [`TIME_COLUMN_NAMES`]).
    pub fn time_column(&self) -> &str {
        &self.time_name
    }

    /// The file's label in error messages.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whether the file has a temperature column (one of [`TEMP_COLUMN_NAMES`]).
    pub fn has_temperature(&self) -> bool {
        self.temp_idx.is_some()
    }

    /// Name of the temperature column found in the header (the first of [`TEMP_COLUMN_NAMES`]
    /// that it has), if any.
    pub fn temperature_column(&self) -> Option<&str> {
        self.temp_idx.map(|i| self.names[i].as_str())
    }

    /// Number of data rows returned so far.
    pub fn rows_read(&self) -> u64 {
        self.rows
    }

    /// Reads the next row; `Ok(None)` at the end of the file. Blank lines are skipped.
    pub fn next_row(&mut self) -> Result<Option<Row<'_>>, CsvError> {
        loop {
            self.line_buf.clear();
            let read = read_line(&mut self.reader, &mut self.line_buf).map_err(|e| CsvError {
                path: self.path.clone(),
                line: Some(self.line_no + 1),
                field: None,
                kind: e.map_or_else(too_long, CsvErrorKind::Io),
            })?;
            if read == 0 {
                return Ok(None);
            }
            self.line_no += 1;
            if !is_blank(&self.line_buf) {
                break;
            }
        }
        let line = self.line_no;
        self.fields.split(&self.line_buf).map_err(|msg| CsvError {
            path: self.path.clone(),
            line: Some(line),
            field: None,
            kind: CsvErrorKind::Malformed(msg.to_owned()),
        })?;
        let t_s = self.field(line, self.time_idx, false)? * self.time_scale;
        if self.options.require_increasing_time
            && let Some(previous) = self.previous_t
            && t_s <= previous
        {
            return Err(self.error(line, self.time_idx, CsvErrorKind::TimeNotIncreasing { previous, current: t_s }));
        }
        self.previous_t = Some(t_s);
        for k in 0..self.value_idx.len() {
            self.values[k] = self.field(line, self.value_idx[k], self.options.allow_non_finite)? * self.value_scale[k];
        }
        let temp_c = match self.temp_idx {
            Some(i) if self.fields.get(i).is_some_and(|f| !f.is_empty()) => Some(self.field(line, i, true)?),
            _ => None,
        };
        self.rows += 1;
        Ok(Some(Row { line, t_s, values: &self.values, temp_c }))
    }

    fn field(&self, line: u64, idx: usize, allow_non_finite: bool) -> Result<f64, CsvError> {
        let Some(bytes) = self.fields.get(idx) else {
            return Err(self.error(line, idx, CsvErrorKind::MissingField { found: self.fields.len() }));
        };
        let parsed = std::str::from_utf8(bytes).ok().and_then(|t| t.parse::<f64>().ok());
        match parsed {
            Some(v) if v.is_finite() || allow_non_finite => Ok(v),
            Some(_) => Err(self.error(line, idx, CsvErrorKind::NonFinite(lossy(bytes)))),
            None => Err(self.error(line, idx, CsvErrorKind::BadNumber(lossy(bytes)))),
        }
    }

    fn error(&self, line: u64, idx: usize, kind: CsvErrorKind) -> CsvError {
        let field = if idx == self.time_idx { self.time_name.clone() } else { self.names[idx].clone() };
        CsvError { path: self.path.clone(), line: Some(line), field: Some(field), kind }
    }
}

fn lossy(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn is_blank(line: &[u8]) -> bool {
    line.iter().all(|b| b.is_ascii_whitespace())
}

/// The fields of one line: unquoted, trimmed bytes packed in one buffer, with their ranges.
#[derive(Debug, Default)]
struct Fields {
    bytes: Vec<u8>,
    ranges: Vec<Range<usize>>,
}

impl Fields {
    fn len(&self) -> usize {
        self.ranges.len()
    }

    fn get(&self, i: usize) -> Option<&[u8]> {
        self.ranges.get(i).map(|r| &self.bytes[r.clone()])
    }

    /// Splits one line (its `\n` or `\r\n` included or not) into fields.
    fn split(&mut self, line: &[u8]) -> Result<(), &'static str> {
        let line = line.strip_suffix(b"\n").unwrap_or(line);
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        self.bytes.clear();
        self.ranges.clear();
        let mut i = 0;
        loop {
            while i < line.len() && (line[i] == b' ' || line[i] == b'\t') {
                i += 1;
            }
            let start = self.bytes.len();
            if i < line.len() && line[i] == b'"' {
                i += 1;
                loop {
                    match line.get(i) {
                        None => return Err("a quoted field is not closed on its line"),
                        Some(b'"') if line.get(i + 1) == Some(&b'"') => {
                            self.bytes.push(b'"');
                            i += 2;
                        }
                        Some(b'"') => {
                            i += 1;
                            break;
                        }
                        Some(&b) => {
                            self.bytes.push(b);
                            i += 1;
                        }
                    }
                }
                while i < line.len() && line[i] != b',' {
                    if !line[i].is_ascii_whitespace() {
                        return Err("text after a closing quote");
                    }
                    i += 1;
                }
            } else {
                while i < line.len() && line[i] != b',' {
                    self.bytes.push(line[i]);
                    i += 1;
                }
                while self.bytes.len() > start && self.bytes.last().is_some_and(u8::is_ascii_whitespace) {
                    self.bytes.pop();
                }
            }
            self.ranges.push(start..self.bytes.len());
            if i >= line.len() {
                return Ok(());
            }
            i += 1; // the comma
        }
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
    /// The MCAP topic the rows come from (`None` for CSV).
    pub topic: Option<String>,
}

impl Table {
    /// An empty table of the value `columns`, with a temperature column when `temperature`.
    pub fn with_columns(columns: &[&str], temperature: bool) -> Self {
        Self {
            names: columns.iter().map(|&c| c.to_owned()).collect(),
            columns: vec![Vec::new(); columns.len()],
            temp_c: temperature.then(Vec::new),
            ..Self::default()
        }
    }

    /// Appends one row: its time, its values (one per column) and its temperature (NaN in the
    /// temperature column when `None`; ignored without one).
    pub fn push(&mut self, t_s: f64, values: &[f64], temp_c: Option<f64>) {
        self.t_s.push(t_s);
        for (column, &v) in self.columns.iter_mut().zip(values) {
            column.push(v);
        }
        if let Some(temp) = self.temp_c.as_mut() {
            temp.push(temp_c.unwrap_or(f64::NAN));
        }
    }

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
    collect_table(SampleReader::open(path, columns, options)?, columns)
}

/// As [`read_table`], from any reader; `label` names it in error messages.
pub fn read_table_from<R: Read>(
    input: R,
    label: &Path,
    columns: &[&str],
    options: ReadOptions,
) -> Result<Table, CsvError> {
    collect_table(SampleReader::from_reader(input, label, columns, options)?, columns)
}

fn collect_table<R: Read>(mut reader: SampleReader<R>, columns: &[&str]) -> Result<Table, CsvError> {
    let mut table = Table::with_columns(columns, reader.has_temperature());
    while let Some(row) = reader.next_row()? {
        table.push(row.t_s, row.values, row.temp_c);
    }
    if table.is_empty() {
        let (path, line) = (reader.path.clone(), reader.header_line);
        return Err(CsvError { path, line: Some(line), field: None, kind: CsvErrorKind::NoData });
    }
    Ok(table)
}
