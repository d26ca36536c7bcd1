//! The one reader layer every command that reads a recording goes through (`allan`, `eval`,
//! `compensate`, `simgap`, `denoise`, `cc`, `replay`): a [`SampleSource`] yields samples (time,
//! the asked-for rate columns in deg/s, temperature) from a file of any registered
//! [`InputFormat`], chosen by the file's first bytes ([`FORMATS`], docs/inputs.md):
//!
//! - MCAP (a ROS 2 bag, `sensor_msgs/msg/Imu`, [`super::mcap_read`]): magic `\x89MCAP0\r\n`, or
//!   a `.mcap` name (so a damaged bag is reported as a damaged bag, not as bad CSV);
//! - CSV otherwise ([`super::csv_read`]): gyrocomp's layout or EuRoC / TUM-VI, told apart by
//!   the header ([`super::csv_dialect`]).
//!
//! [`InputOptions`] carry the user's `--topic` (MCAP) and `--units` (gyrocomp CSV: rad/s or
//! deg/s). Errors name the file and the line or message and the field, and no record is
//! skipped.

use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};

use super::csv_dialect::Dialect;
use super::csv_read::{CsvError, CsvErrorKind, ReadOptions, SampleReader, Table};
use super::mcap_read::{BagError, BagErrorKind, MCAP_MAGIC, McapSampleReader};

/// Degrees per radian.
const DEG_PER_RAD: f64 = 180.0 / std::f64::consts::PI;

/// The unit of the rate columns of a gyrocomp CSV (`--units`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RateUnit {
    /// Degrees per second (gyrocomp's own unit; the default).
    Dps,
    /// Radians per second (converted to deg/s as read).
    Rads,
}

impl std::str::FromStr for RateUnit {
    type Err = String;

    /// `dps` or `rads` (as `--units` takes them).
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "dps" => Ok(Self::Dps),
            "rads" => Ok(Self::Rads),
            other => Err(format!("`{other}` is not a rate unit: dps (deg/s) or rads (rad/s)")),
        }
    }
}

impl RateUnit {
    /// Factor from this unit to deg/s.
    pub fn to_dps(self) -> f64 {
        match self {
            Self::Dps => 1.0,
            Self::Rads => DEG_PER_RAD,
        }
    }
}

/// What the user says about an input besides its path.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct InputOptions {
    /// The MCAP topic to read (default: the only `sensor_msgs/msg/Imu` topic). An error for
    /// CSV input.
    pub topic: Option<String>,
    /// The unit of a gyrocomp CSV's rate columns (default deg/s). Formats whose unit is fixed
    /// (EuRoC, MCAP: rad/s) accept `rads` and refuse `dps`.
    pub units: Option<RateUnit>,
}

/// Why an input cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// A CSV problem, located by file, line and field.
    #[error(transparent)]
    Csv(#[from] CsvError),
    /// An MCAP problem, located by file, topic, message and field.
    #[error(transparent)]
    Bag(#[from] BagError),
    /// An option that does not fit the file.
    #[error("{}: {message}", path.display())]
    Options {
        /// The file.
        path: PathBuf,
        /// What does not fit.
        message: String,
    },
}

/// One sample, borrowed from its source.
#[derive(Debug, Clone, Copy)]
pub struct Sample<'a> {
    /// Where it is: the 1-based line of a CSV, the 1-based message number of an MCAP topic.
    pub record: u64,
    /// Time, seconds.
    pub t_s: f64,
    /// The exact timestamp, ns, when the format has one (MCAP header stamps); otherwise the
    /// caller derives it from `t_s` ([`super::t_ns_from_s`]).
    pub t_ns: Option<u64>,
    /// The asked-for columns, in order: rates in deg/s, then the extra columns as written.
    pub values: &'a [f64],
    /// Temperature, °C, when the format and the record have one.
    pub temp_c: Option<f64>,
}

/// A stream of samples from one file (module documentation).
pub trait SampleSource {
    /// The next sample; `Ok(None)` at the end.
    fn next_sample(&mut self) -> Result<Option<Sample<'_>>, InputError>;
    /// The file's label in error messages.
    fn path(&self) -> &Path;
    /// Whether samples may carry a temperature.
    fn has_temperature(&self) -> bool;
    /// Name of the time field (for errors about a time).
    fn time_field(&self) -> &str;
    /// The MCAP topic read, for formats that have topics (known after the first sample).
    fn topic(&self) -> Option<&str> {
        None
    }
    /// An error about `field` of the sample at `record` (a value the caller cannot use).
    fn invalid(&self, record: u64, field: &str, message: String) -> InputError;
    /// The error for a file without samples.
    fn no_data(&self) -> InputError;
}

/// What a command asks of an input.
#[derive(Debug, Clone, Copy)]
pub struct Request<'a> {
    /// Rate columns (deg/s after conversion).
    pub rates: &'a [&'a str],
    /// Further columns, read as written (flags, truths); none in an MCAP bag.
    pub extra: &'a [&'a str],
    /// Strictness.
    pub read: ReadOptions,
    /// The user's options.
    pub input: &'a InputOptions,
}

/// A file format the reader layer can open.
pub trait InputFormat: Sync {
    /// Its name in messages (`csv`, `mcap`).
    fn name(&self) -> &'static str;
    /// Whether a file that starts with `head` (up to 16 bytes) and is named `path` is of this
    /// format.
    fn detect(&self, head: &[u8], path: &Path) -> bool;
    /// Opens `path` for `request`.
    fn open(&self, path: &Path, request: &Request<'_>) -> Result<Box<dyn SampleSource>, InputError>;
}

/// The registered formats, tried in order; CSV, last, takes any file.
pub static FORMATS: &[&dyn InputFormat] = &[&McapFormat, &CsvFormat];

/// The format of the file at `path`, from its first bytes (and name).
pub fn detect_format(path: &Path) -> Result<&'static dyn InputFormat, InputError> {
    let mut head = [0u8; 16];
    let mut len = 0;
    let mut file = File::open(path).map_err(|e| CsvError {
        path: path.to_path_buf(),
        line: None,
        field: None,
        kind: CsvErrorKind::Io(e),
    })?;
    while len < head.len() {
        match file.read(&mut head[len..]) {
            Ok(0) => break,
            Ok(n) => len += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => {
                return Err(
                    CsvError { path: path.to_path_buf(), line: None, field: None, kind: CsvErrorKind::Io(e) }.into()
                );
            }
        }
    }
    Ok(*FORMATS.iter().find(|f| f.detect(&head[..len], path)).expect("CSV takes any file"))
}

/// Opens `path` with the format its first bytes show.
pub fn open_samples(path: &Path, request: &Request<'_>) -> Result<Box<dyn SampleSource>, InputError> {
    detect_format(path)?.open(path, request)
}

/// Reads the rate columns `rates` of `path` (any format) into a [`Table`]: time, the columns in
/// deg/s, temperature when the format has one (NaN where a record has none).
pub fn read_columns(path: &Path, rates: &[&str], read: ReadOptions, input: &InputOptions) -> Result<Table, InputError> {
    let mut source = open_samples(path, &Request { rates, extra: &[], read, input })?;
    let mut table = Table::with_columns(rates, source.has_temperature());
    while let Some(s) = source.next_sample()? {
        table.push(s.t_s, s.values, s.temp_c);
    }
    if table.is_empty() {
        return Err(source.no_data());
    }
    table.topic = source.topic().map(str::to_owned);
    Ok(table)
}

fn options_error(path: &Path, message: String) -> InputError {
    InputError::Options { path: path.to_path_buf(), message }
}

/// Refuses `--units dps` for a format whose rates are rad/s by definition.
fn fixed_rads(path: &Path, what: &str, units: Option<RateUnit>) -> Result<(), InputError> {
    match units {
        Some(RateUnit::Dps) => Err(options_error(path, format!("--units dps: {what} rates are rad/s by definition"))),
        _ => Ok(()),
    }
}

/// gyrocomp and EuRoC CSV ([`SampleReader`]).
struct CsvFormat;

impl InputFormat for CsvFormat {
    fn name(&self) -> &'static str {
        "csv"
    }

    fn detect(&self, _head: &[u8], _path: &Path) -> bool {
        true
    }

    fn open(&self, path: &Path, request: &Request<'_>) -> Result<Box<dyn SampleSource>, InputError> {
        if let Some(topic) = &request.input.topic {
            return Err(options_error(path, format!("--topic {topic}: topics are for MCAP input; this is a CSV file")));
        }
        let mut columns: Vec<&str> = request.rates.to_vec();
        columns.extend(request.extra);
        let mut reader = SampleReader::open(path, &columns, request.read)?;
        match reader.dialect() {
            Dialect::Euroc => fixed_rads(path, "EuRoC CSV", request.input.units)?,
            Dialect::Gyrocomp => {
                let factor = request.input.units.unwrap_or(RateUnit::Dps).to_dps();
                for k in 0..request.rates.len() {
                    reader.scale_column(k, factor);
                }
            }
        }
        Ok(Box::new(reader))
    }
}

impl<R: Read> SampleSource for SampleReader<R> {
    fn next_sample(&mut self) -> Result<Option<Sample<'_>>, InputError> {
        Ok(self.next_row()?.map(|row| Sample {
            record: row.line,
            t_s: row.t_s,
            t_ns: None,
            values: row.values,
            temp_c: row.temp_c,
        }))
    }

    fn path(&self) -> &Path {
        SampleReader::path(self)
    }

    fn has_temperature(&self) -> bool {
        SampleReader::has_temperature(self)
    }

    fn time_field(&self) -> &str {
        self.time_column()
    }

    fn invalid(&self, record: u64, field: &str, message: String) -> InputError {
        let path = SampleReader::path(self).to_path_buf();
        CsvError { path, line: Some(record), field: Some(field.to_owned()), kind: CsvErrorKind::Invalid(message) }
            .into()
    }

    fn no_data(&self) -> InputError {
        let path = SampleReader::path(self).to_path_buf();
        CsvError { path, line: Some(self.header_line()), field: None, kind: CsvErrorKind::NoData }.into()
    }
}

/// MCAP bags with a `sensor_msgs/msg/Imu` topic ([`McapSampleReader`]).
struct McapFormat;

impl InputFormat for McapFormat {
    fn name(&self) -> &'static str {
        "mcap"
    }

    fn detect(&self, head: &[u8], path: &Path) -> bool {
        head.starts_with(MCAP_MAGIC) || path.extension().is_some_and(|e| e.eq_ignore_ascii_case("mcap"))
    }

    fn open(&self, path: &Path, request: &Request<'_>) -> Result<Box<dyn SampleSource>, InputError> {
        fixed_rads(path, "sensor_msgs/msg/Imu", request.input.units)?;
        let mut columns: Vec<&str> = request.rates.to_vec();
        columns.extend(request.extra);
        Ok(Box::new(McapSampleReader::open(path, &columns, request.input.topic.as_deref(), request.read)?))
    }
}

impl SampleSource for McapSampleReader {
    fn next_sample(&mut self) -> Result<Option<Sample<'_>>, InputError> {
        Ok(McapSampleReader::next_sample(self)?.map(|s| Sample {
            record: s.number,
            t_s: s.t_s,
            t_ns: Some(s.t_ns),
            values: s.values,
            temp_c: None,
        }))
    }

    fn path(&self) -> &Path {
        McapSampleReader::path(self)
    }

    fn has_temperature(&self) -> bool {
        false
    }

    fn time_field(&self) -> &str {
        "header.stamp"
    }

    fn topic(&self) -> Option<&str> {
        McapSampleReader::topic(self)
    }

    fn invalid(&self, record: u64, field: &str, message: String) -> InputError {
        let kind = BagErrorKind::Message { number: record, log_time: None, field: field.to_owned(), detail: message };
        BagError::new(McapSampleReader::path(self), McapSampleReader::topic(self), kind).into()
    }

    fn no_data(&self) -> InputError {
        BagError::new(McapSampleReader::path(self), McapSampleReader::topic(self), BagErrorKind::NoData).into()
    }
}
