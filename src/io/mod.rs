//! File I/O at the edge of the library: one reader layer for recordings ([`source`]: gyrocomp or
//! EuRoC CSV, ROS 2 bags in MCAP) and CSV writing, following the CSV conventions of
//! docs/design.md (header line, time column `t_s`/`t`/`time` in seconds, rate columns in deg/s,
//! optional `temp_c`) and docs/inputs.md. Numerics never see a file: they receive slices.

pub mod cdr;
pub mod compensated_csv;
pub mod csv_dialect;
pub mod csv_read;
pub mod csv_write;
pub mod mcap_read;
pub mod recording;
pub mod ros2_imu;
pub mod sampling;
pub mod sim_csv;
pub mod source;

pub use compensated_csv::{CompensatedCsvWriter, compensated_header};
pub use csv_read::{CsvError, CsvErrorKind, ReadOptions, Row, SampleReader, Table, read_table, read_table_from};
pub use csv_write::{CsvColumnsWriter, create_output};
pub use recording::{Recording, RecordingError, t_ns_from_s};
pub use sampling::{Sampling, TimeGap, sampling};
pub use sim_csv::write_sim_csv;
pub use source::{
    InputError, InputOptions, RateUnit, Request, Sample, SampleSource, detect_format, open_samples, read_columns,
};
