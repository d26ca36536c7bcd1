//! Streaming reader of the `sensor_msgs/msg/Imu` messages of an MCAP file (a ROS 2 bag).
//!
//! The file is read front to back through the `mcap` crate's sans-io [`LinearReader`] in reads
//! of at most [`READ_BYTES`]: records come out borrowed from its buffer (zstd chunks are
//! decompressed as they stream), each message of the chosen topic is decoded in place by
//! [`decode_imu`] into the selected angular-velocity columns, and nothing else is kept, so a
//! bag of any length takes constant memory here; only the caller's columns grow.
//!
//! - The topic: the one named (`--topic`), or else the only topic whose schema is
//!   `sensor_msgs/msg/Imu`. Two Imu topics without a choice, none, or a named topic that is
//!   absent or not an Imu are errors that list the file's topics with their types.
//! - Time: the header stamp (`sec · 10⁹ + nanosec`, exact in [`McapSample::t_ns`]), not the
//!   MCAP log time; it must strictly increase (when asked) and not precede the epoch. In
//!   seconds it is `t_ns / 10⁹` correctly rounded below 2⁵³ ns (104 days; the same `f64` as
//!   parsing the decimal time), and within one ulp above.
//! - Rates: `angular_velocity` x, y, z (rad/s) → deg/s, asked for as `gx_dps`, `gy_dps`,
//!   `gz_dps` or `angular_velocity.x`, `.y`, `.z`. A bag has no temperature and no moving flag.
//! - Every message of the chosen topic becomes a sample or an error ([`BagError`]) that names
//!   the file, the message (its number on the topic and its log time) and the field: none is
//!   skipped. Chunk CRCs are checked; a truncated or corrupt file is an error naming the file.

use std::collections::{BTreeSet, HashMap};
use std::fmt;
use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};

use mcap::records::{Record, op};
use mcap::sans_io::{LinearReadEvent, LinearReader, LinearReaderOptions};

use super::cdr::CdrError;
use super::csv_read::ReadOptions;
use super::ros2_imu::{IMU_SCHEMA, decode_imu};

/// The magic bytes an MCAP file starts (and ends) with.
pub const MCAP_MAGIC: &[u8] = mcap::MAGIC;
/// Largest read handed to the MCAP parser at once, bytes.
pub const READ_BYTES: usize = 1 << 20;
/// Longest record (outside chunks) accepted, bytes: a corrupt length field is an error instead
/// of a buffer that grows with the file.
const MAX_RECORD_BYTES: usize = 1 << 30;
/// Bytes of a Message record before its payload.
const MESSAGE_HEADER_LEN: usize = 22;
/// The ROS 1 name of the IMU type (recognised to say why such a topic cannot be read).
const ROS1_IMU_SCHEMA: &str = "sensor_msgs/Imu";
/// The message encoding of ROS 2 bags.
const CDR: &str = "cdr";
/// Degrees per radian.
const DEG_PER_RAD: f64 = 180.0 / std::f64::consts::PI;
/// Column names of angular velocity x, y, z: gyrocomp's, then the message's.
const AXIS_NAMES: [[&str; 3]; 2] =
    [["gx_dps", "gy_dps", "gz_dps"], ["angular_velocity.x", "angular_velocity.y", "angular_velocity.z"]];

/// What is wrong with an MCAP input.
#[derive(Debug)]
pub enum BagErrorKind {
    /// The file could not be opened or read.
    Io(std::io::Error),
    /// The MCAP structure is broken (bad magic, truncated, CRC mismatch, unsupported compression).
    Format(mcap::McapError),
    /// No topic of type `sensor_msgs/msg/Imu`.
    NoImuTopic,
    /// Several Imu topics and no `--topic`.
    SeveralImuTopics,
    /// The named topic is not in the file.
    TopicNotFound(String),
    /// The named topic is not an Imu topic, or not CDR-encoded.
    Unsupported(String),
    /// A requested column is not a field a bag provides.
    MissingColumn {
        /// The column asked for.
        wanted: String,
    },
    /// The topic has no messages.
    NoData,
    /// One message cannot become a sample.
    Message {
        /// 1-based number of the message on its topic.
        number: u64,
        /// Its MCAP log time, ns (when the error is the reader's own).
        log_time: Option<u64>,
        /// The field at fault.
        field: String,
        /// What is wrong with it.
        detail: String,
    },
}

/// An MCAP problem, naming the file, the topic and, for one message, its number, log time and
/// field (boxed: errors travel far, samples often).
#[derive(Debug)]
pub struct BagError(Box<BagErrorData>);

/// The content of a [`BagError`].
#[derive(Debug)]
pub struct BagErrorData {
    /// The file being read.
    pub path: PathBuf,
    /// The topic being read, when one was chosen.
    pub topic: Option<String>,
    /// The file's topics and types, for the errors about choosing one (empty otherwise).
    pub topics: Vec<(String, String)>,
    /// What went wrong.
    pub kind: BagErrorKind,
}

impl BagError {
    /// An error about `path` (and `topic`, when known).
    pub fn new(path: &Path, topic: Option<&str>, kind: BagErrorKind) -> Self {
        Self(Box::new(BagErrorData {
            path: path.to_path_buf(),
            topic: topic.map(str::to_owned),
            topics: Vec::new(),
            kind,
        }))
    }

    /// The same error listing the file's `topics` (with their types).
    pub fn with_topics(mut self, topics: Vec<(String, String)>) -> Self {
        self.0.topics = topics;
        self
    }
}

impl std::ops::Deref for BagError {
    type Target = BagErrorData;

    fn deref(&self) -> &BagErrorData {
        &self.0
    }
}

impl fmt::Display for BagError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.path.display())?;
        let topic = self.topic.as_deref().unwrap_or("?");
        match &self.kind {
            BagErrorKind::Io(e) => write!(f, ": cannot read: {e}")?,
            BagErrorKind::Format(mcap::McapError::UnsupportedCompression(c)) => write!(
                f,
                ": chunks compressed with `{c}` cannot be read (zstd and uncompressed chunks can; re-encode the file, e.g. `mcap compress --compression zstd`)"
            )?,
            BagErrorKind::Format(e) => write!(f, ": not a readable MCAP file (truncated or corrupt?): {e}")?,
            BagErrorKind::NoImuTopic => write!(f, ": no sensor_msgs/msg/Imu topic")?,
            BagErrorKind::SeveralImuTopics => {
                write!(f, ": several sensor_msgs/msg/Imu topics: choose one with --topic")?
            }
            BagErrorKind::TopicNotFound(t) => write!(f, ": topic `{t}` not found")?,
            BagErrorKind::Unsupported(msg) => write!(f, ": topic `{topic}`: {msg}")?,
            BagErrorKind::MissingColumn { wanted } => write!(
                f,
                ": column `{wanted}` is not in a sensor_msgs/msg/Imu bag; it has: {}",
                AXIS_NAMES.concat().join(", ")
            )?,
            BagErrorKind::NoData => write!(f, ": topic `{topic}` has no messages")?,
            BagErrorKind::Message { number, log_time, field, detail } => {
                write!(f, ": {topic} message {number}")?;
                if let Some(t) = log_time {
                    write!(f, " (log time {t} ns)")?;
                }
                write!(f, ": field `{field}`: {detail}")?
            }
        }
        if !self.topics.is_empty() {
            let list: Vec<String> = self.topics.iter().map(|(t, s)| format!("{t} ({s})")).collect();
            write!(f, "; the file's topics: {}", list.join(", "))?;
        }
        Ok(())
    }
}

impl std::error::Error for BagError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.0.kind {
            BagErrorKind::Io(e) => Some(e),
            // The MCAP error's text is already part of this one's.
            _ => None,
        }
    }
}

/// One sample of the chosen topic, borrowed from the reader.
#[derive(Debug, Clone, Copy)]
pub struct McapSample<'a> {
    /// 1-based number of the message on its topic.
    pub number: u64,
    /// The header stamp, ns since the epoch.
    pub t_ns: u64,
    /// The header stamp, seconds (module documentation).
    pub t_s: f64,
    /// The selected angular-velocity columns, deg/s, in the order asked for.
    pub values: &'a [f64],
}

/// A channel as the reader tracks it.
#[derive(Debug, Clone)]
struct ChannelInfo {
    topic: String,
    schema: String,
    encoding: String,
}

/// Streaming reader of one Imu topic of an MCAP file (module documentation).
pub struct McapSampleReader {
    path: PathBuf,
    file: File,
    reader: LinearReader,
    schemas: HashMap<u16, String>,
    channels: HashMap<u16, ChannelInfo>,
    wanted: Option<String>,
    /// The chosen topic, once its channel record is seen.
    topic: Option<String>,
    /// Channel ids of the chosen topic.
    ids: Vec<u16>,
    /// Angular-velocity component (0 = x) of each value column.
    axes: Vec<usize>,
    values: Vec<f64>,
    number: u64,
    previous_ns: Option<u64>,
    past_data_end: bool,
    options: ReadOptions,
}

impl McapSampleReader {
    /// Opens `path`, selecting the angular-velocity `columns` (module documentation) of `topic`
    /// (or of the only Imu topic).
    pub fn open(path: &Path, columns: &[&str], topic: Option<&str>, options: ReadOptions) -> Result<Self, BagError> {
        let err = |kind| BagError::new(path, topic, kind);
        let axes = columns
            .iter()
            .map(|&c| {
                AXIS_NAMES
                    .iter()
                    .find_map(|names| names.iter().position(|&n| n == c))
                    .ok_or_else(|| err(BagErrorKind::MissingColumn { wanted: c.to_owned() }))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let file = File::open(path).map_err(|e| err(BagErrorKind::Io(e)))?;
        let reader = LinearReader::new_with_options(
            LinearReaderOptions::default().with_validate_chunk_crcs(true).with_record_length_limit(MAX_RECORD_BYTES),
        );
        Ok(Self {
            path: path.to_path_buf(),
            file,
            reader,
            schemas: HashMap::new(),
            channels: HashMap::new(),
            wanted: topic.map(str::to_owned),
            topic: None,
            ids: Vec::new(),
            values: vec![0.0; axes.len()],
            axes,
            number: 0,
            previous_ns: None,
            past_data_end: false,
            options,
        })
    }

    /// The file's label in error messages.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The topic being read, once known (after the first sample at the latest).
    pub fn topic(&self) -> Option<&str> {
        self.topic.as_deref()
    }

    /// Number of samples returned so far.
    pub fn samples_read(&self) -> u64 {
        self.number
    }

    fn error(&self, kind: BagErrorKind) -> BagError {
        BagError::new(&self.path, self.topic.as_deref().or(self.wanted.as_deref()), kind)
    }

    /// The file's topics and types seen so far, sorted.
    fn topic_list(&self) -> Vec<(String, String)> {
        let set: BTreeSet<(String, String)> =
            self.channels.values().map(|c| (c.topic.clone(), c.schema.clone())).collect();
        set.into_iter().collect()
    }

    /// Feeds the parser one read of the file.
    fn fill(&mut self, need: usize) -> Result<(), BagError> {
        let buf = self.reader.insert(need.clamp(1, READ_BYTES));
        let got = loop {
            match self.file.read(buf) {
                Ok(n) => break n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(BagError::new(&self.path, None, BagErrorKind::Io(e))),
            }
        };
        self.reader.notify_read(got);
        Ok(())
    }

    /// Records a channel; chooses the topic or finds the choice ambiguous or wrong.
    fn add_channel(&mut self, channel: mcap::records::Channel) -> Result<(), BagError> {
        let schema = self.schemas.get(&channel.schema_id).cloned().unwrap_or_else(|| "no schema".to_owned());
        let info = ChannelInfo { topic: channel.topic, schema, encoding: channel.message_encoding };
        let is_imu = info.schema == IMU_SCHEMA || info.schema == ROS1_IMU_SCHEMA;
        let chosen = match (&self.wanted, &self.topic) {
            (Some(w), _) => *w == info.topic,
            (None, None) => is_imu,
            (None, Some(t)) if *t == info.topic => true,
            (None, Some(_)) => {
                if is_imu {
                    self.channels.insert(channel.id, info);
                    return Err(self.ambiguous());
                }
                false
            }
        };
        if chosen && !self.ids.contains(&channel.id) {
            self.topic = Some(info.topic.clone());
            if !is_imu {
                return Err(
                    self.error(BagErrorKind::Unsupported(format!("its type is {}, not {IMU_SCHEMA}", info.schema)))
                );
            }
            if info.encoding != CDR {
                return Err(self.error(BagErrorKind::Unsupported(format!(
                    "message encoding `{}` is not supported (only ROS 2 `{CDR}`; a ROS 1 bag must be converted)",
                    info.encoding
                ))));
            }
            self.ids.push(channel.id);
        }
        self.channels.insert(channel.id, info);
        Ok(())
    }

    /// The error for a second Imu topic, with every topic of the file (read to its end).
    fn ambiguous(&mut self) -> BagError {
        self.topic = None;
        loop {
            let need = match self.reader.next_event() {
                Some(Ok(LinearReadEvent::ReadRequest(need))) => need,
                Some(Ok(LinearReadEvent::Record { opcode, data })) => {
                    if !self.past_data_end {
                        match mcap::parse_record(opcode, data) {
                            Ok(Record::Schema { header, .. }) => {
                                self.schemas.insert(header.id, header.name);
                            }
                            Ok(Record::Channel(c)) => {
                                let schema = self.schemas.get(&c.schema_id).cloned().unwrap_or_default();
                                self.channels
                                    .insert(c.id, ChannelInfo { topic: c.topic, schema, encoding: c.message_encoding });
                            }
                            Ok(Record::DataEnd(_)) => self.past_data_end = true,
                            _ => {}
                        }
                    }
                    continue;
                }
                // The listing is the best that can be said of a file that ends badly too.
                Some(Err(_)) | None => break,
            };
            if self.fill(need).is_err() {
                break;
            }
        }
        self.error(BagErrorKind::SeveralImuTopics).with_topics(self.topic_list())
    }

    /// Reads the next sample; `Ok(None)` at the end of the file.
    pub fn next_sample(&mut self) -> Result<Option<McapSample<'_>>, BagError> {
        loop {
            let event = match self.reader.next_event() {
                None => return self.end().map(|()| None),
                Some(Err(e)) => return Err(self.error(BagErrorKind::Format(e))),
                Some(Ok(event)) => event,
            };
            let (opcode, data) = match event {
                LinearReadEvent::ReadRequest(need) => {
                    self.fill(need)?;
                    continue;
                }
                LinearReadEvent::Record { opcode, data } => (opcode, data),
            };
            match opcode {
                op::DATA_END => self.past_data_end = true,
                op::SCHEMA | op::CHANNEL if !self.past_data_end => {
                    let record = mcap::parse_record(opcode, data);
                    match record {
                        Ok(Record::Schema { header, .. }) => {
                            self.schemas.insert(header.id, header.name);
                        }
                        Ok(Record::Channel(channel)) => self.add_channel(channel)?,
                        Ok(_) => {}
                        Err(e) => return Err(self.error(BagErrorKind::Format(e))),
                    }
                }
                op::MESSAGE => {
                    // Message record: channel id u16, sequence u32, log time u64, publish time
                    // u64, then the payload (MCAP specification, "Message (op=0x05)").
                    let Some(header) = data.get(..MESSAGE_HEADER_LEN) else {
                        return Err(self.error(BagErrorKind::Format(mcap::McapError::UnexpectedEoc)));
                    };
                    let id = u16::from_le_bytes([header[0], header[1]]);
                    if !self.ids.contains(&id) {
                        continue;
                    }
                    let log_time = u64::from_le_bytes(header[6..14].try_into().expect("8 bytes"));
                    let decoded = decode_imu(&data[MESSAGE_HEADER_LEN..])
                        .map(|m| (m.stamp_ns(), m.stamp_sec, m.stamp_nanosec, m.angular_velocity));
                    self.number += 1;
                    return self.sample(log_time, decoded).map(Some);
                }
                _ => {}
            }
        }
    }

    /// The sample of one decoded message (its stamp in ns, sec and nanosec, its angular
    /// velocity), checked.
    fn sample(
        &mut self,
        log_time: u64,
        decoded: Result<(Option<u64>, i32, u32, [f64; 3]), CdrError>,
    ) -> Result<McapSample<'_>, BagError> {
        let number = self.number;
        let fail = |field: &str, detail: String| BagErrorKind::Message {
            number,
            log_time: Some(log_time),
            field: field.to_owned(),
            detail,
        };
        let (t_ns, sec, nanosec, w) = match decoded {
            Ok(d) => d,
            Err(e) => return Err(self.error(fail(e.field, format!("{} (byte {} of the message)", e.kind, e.offset)))),
        };
        let Some(t_ns) = t_ns else {
            return Err(self.error(fail("header.stamp.sec", format!("{sec} s is before the epoch: no ns timestamp"))));
        };
        if self.options.require_increasing_time
            && let Some(previous) = self.previous_ns
            && t_ns <= previous
        {
            let detail = format!("time does not increase: {t_ns} ns follows {previous} ns");
            return Err(self.error(fail("header.stamp", detail)));
        }
        self.previous_ns = Some(t_ns);
        for (k, &axis) in self.axes.iter().enumerate() {
            if !w[axis].is_finite() && !self.options.allow_non_finite {
                let detail = format!("not a finite number: {}", w[axis]);
                return Err(self.error(fail(AXIS_NAMES[1][axis], detail)));
            }
            self.values[k] = w[axis] * DEG_PER_RAD;
        }
        Ok(McapSample { number, t_ns, t_s: seconds(t_ns, sec, nanosec), values: &self.values })
    }

    /// At the end of the file: the errors for a topic never found or never written.
    fn end(&self) -> Result<(), BagError> {
        let kind = match (&self.wanted, &self.topic) {
            (_, Some(_)) if self.number > 0 => return Ok(()),
            (_, Some(_)) => BagErrorKind::NoData,
            (Some(w), None) => BagErrorKind::TopicNotFound(w.clone()),
            (None, None) => BagErrorKind::NoImuTopic,
        };
        let e = self.error(kind);
        Err(if self.topic.is_none() { e.with_topics(self.topic_list()) } else { e })
    }
}

/// `t_ns` in seconds (module documentation): `t_ns / 10⁹` correctly rounded where `t_ns` is
/// exact in an `f64`, else the sum of the seconds and the fraction.
fn seconds(t_ns: u64, sec: i32, nanosec: u32) -> f64 {
    const EXACT: u64 = 1 << 53;
    if t_ns < EXACT { t_ns as f64 / 1e9 } else { f64::from(sec) + f64::from(nanosec) / 1e9 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seconds_round_like_the_decimal_time() {
        for t_ns in [0u64, 1, 999_999_999, 1_000_000_000, 1_234_567_890_123, (1 << 53) - 1] {
            let text = format!("{}.{:09}", t_ns / 1_000_000_000, t_ns % 1_000_000_000);
            let sec = (t_ns / 1_000_000_000) as i32;
            let nanosec = (t_ns % 1_000_000_000) as u32;
            assert_eq!(seconds(t_ns, sec, nanosec), text.parse::<f64>().unwrap(), "{text}");
        }
        let epoch = seconds(1_700_000_000_123_456_789, 1_700_000_000, 123_456_789);
        let exact: f64 = "1700000000.123456789".parse().unwrap();
        assert!((epoch - exact).abs() <= 2.4e-7, "within one ulp");
    }
}
