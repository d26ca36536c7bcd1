//! The streaming CSV reader: conventions of docs/design.md and clear errors naming file, line, field.

use std::io::Write;
use std::path::Path;

use gyrocomp::io::{CsvErrorKind, ReadOptions, SampleReader, read_table};

fn file_with(contents: &[u8]) -> tempfile::NamedTempFile {
    let mut f = tempfile::NamedTempFile::new().unwrap();
    f.write_all(contents).unwrap();
    f
}

fn read(contents: &str, column: &str) -> Result<gyrocomp::io::Table, gyrocomp::io::CsvError> {
    let f = file_with(contents.as_bytes());
    read_table(f.path(), &[column], ReadOptions::default())
}

#[test]
fn reads_selected_columns_and_temperature() {
    let t = read("t_s,gx_dps,gy_dps,temp_c\n0.0,1.5,2,20\n0.1,-1e-3,3,\n0.2,4,5,21.5\n", "gy_dps").unwrap();
    assert_eq!(t.t_s, vec![0.0, 0.1, 0.2]);
    assert_eq!(t.column("gy_dps").unwrap(), &[2.0, 3.0, 5.0]);
    let temp = t.temp_c.clone().unwrap();
    assert_eq!(temp[0], 20.0);
    assert!(temp[1].is_nan(), "an empty temperature field means none");
    assert_eq!(temp[2], 21.5);
    assert!((t.sample_rate_hz().unwrap() - 10.0).abs() < 1e-9);
}

/// A temperature column another logger wrote (`temperature`, `temp`, …) is read as the temperature;
/// with several, `temp_c` and then the order of `TEMP_COLUMN_NAMES` decides.
#[test]
fn reads_the_temperature_under_the_names_other_writers_use() {
    for name in ["temperature_c", "temperature", "temp"] {
        let f = file_with(format!("t_s,gx_dps,{name}\n0,1,20.5\n1,2,21\n").as_bytes());
        let reader = SampleReader::open(f.path(), &["gx_dps"], ReadOptions::default()).unwrap();
        assert_eq!(reader.temperature_column(), Some(name));
        let t = read_table(f.path(), &["gx_dps"], ReadOptions::default()).unwrap();
        assert_eq!(t.temp_c, Some(vec![20.5, 21.0]), "{name}");
    }
    let t = read("t_s,temp,gx_dps,temp_c,temperature\n0,1,2,30,40\n1,1,2,31,41\n", "gx_dps").unwrap();
    assert_eq!(t.temp_c, Some(vec![30.0, 31.0]), "temp_c first");
    let t = read("t_s,temp,gx_dps,temperature\n0,1,2,40\n1,1,2,41\n", "gx_dps").unwrap();
    assert_eq!(t.temp_c, Some(vec![40.0, 41.0]), "temperature before temp");
    let t = read("t_s,gx_dps,tempo\n0,1,2\n", "gx_dps").unwrap();
    assert_eq!(t.temp_c, None, "only the listed names");
}

#[test]
fn accepts_alternative_time_names_crlf_bom_quotes_and_spaces() {
    let t = read("\u{feff}time,\"gx_dps\"\r\n0, 1.0\r\n\r\n1,\"2.0\"\r\n", "gx_dps").unwrap();
    assert_eq!(t.t_s, vec![0.0, 1.0]);
    assert_eq!(t.columns[0], vec![1.0, 2.0]);
    let t = read("t,gx_dps\n0,1\n", "gx_dps").unwrap();
    assert_eq!(t.len(), 1);
}

#[test]
fn bad_number_names_file_line_and_field() {
    let f = file_with(b"t_s,gx_dps\n0.0,1\n0.1,abc\n");
    let err = read_table(f.path(), &["gx_dps"], ReadOptions::default()).unwrap_err();
    assert_eq!(err.line, Some(3));
    assert_eq!(err.field.as_deref(), Some("gx_dps"));
    assert!(matches!(err.kind, CsvErrorKind::BadNumber(ref s) if s == "abc"));
    let msg = err.to_string();
    assert!(msg.starts_with(&format!("{}:3: field `gx_dps`: not a number", f.path().display())), "{msg}");
}

#[test]
fn missing_column_lists_the_header() {
    let err = read("t_s,gy_dps\n0,1\n", "gx_dps").unwrap_err();
    assert_eq!(err.line, Some(1));
    let msg = err.to_string();
    assert!(msg.contains("column `gx_dps` not found") && msg.contains("t_s, gy_dps"), "{msg}");
    let err = read("seconds,gx_dps\n0,1\n", "gx_dps").unwrap_err();
    assert!(err.to_string().contains("`t_s` or `t` or `time`"), "{err}");
}

#[test]
fn empty_file_and_header_only_are_errors() {
    let err = read("", "gx_dps").unwrap_err();
    assert!(matches!(err.kind, CsvErrorKind::Empty), "{err}");
    let err = read("t_s,gx_dps\n", "gx_dps").unwrap_err();
    assert!(matches!(err.kind, CsvErrorKind::NoData), "{err}");
}

#[test]
fn time_must_increase() {
    let err = read("t_s,gx_dps\n0.0,1\n0.2,1\n0.1,1\n", "gx_dps").unwrap_err();
    assert_eq!((err.line, err.field.as_deref()), (Some(4), Some("t_s")));
    assert!(
        matches!(err.kind, CsvErrorKind::TimeNotIncreasing { previous, current } if previous == 0.2 && current == 0.1)
    );
    let err = read("t_s,gx_dps\n0.0,1\n0.0,1\n", "gx_dps").unwrap_err();
    assert!(matches!(err.kind, CsvErrorKind::TimeNotIncreasing { .. }), "duplicate time: {err}");
}

#[test]
fn short_rows_and_non_finite_values() {
    let err = read("t_s,gx_dps\n0.0\n", "gx_dps").unwrap_err();
    assert_eq!((err.line, err.field.as_deref()), (Some(2), Some("gx_dps")));
    assert!(matches!(err.kind, CsvErrorKind::MissingField { found: 1 }));
    let err = read("t_s,gx_dps\n0.0,NaN\n", "gx_dps").unwrap_err();
    assert!(matches!(err.kind, CsvErrorKind::NonFinite(_)), "{err}");
    let err = read("t_s,gx_dps\n0.0,\n", "gx_dps").unwrap_err();
    assert!(matches!(err.kind, CsvErrorKind::BadNumber(_)), "an empty value is an error: {err}");
    // The streaming pipeline may take NaN and flag it itself; time must still be finite.
    let f = file_with(b"t_s,gx_dps\n0.0,nan\n0.1,inf\n");
    let opts = ReadOptions { allow_non_finite: true, ..ReadOptions::default() };
    let t = read_table(f.path(), &["gx_dps"], opts).unwrap();
    assert!(t.columns[0][0].is_nan() && t.columns[0][1].is_infinite());
    let f = file_with(b"t_s,gx_dps\nnan,1\n");
    assert!(read_table(f.path(), &["gx_dps"], opts).is_err());
}

#[test]
fn missing_file_is_an_io_error_naming_the_path() {
    let err = read_table(Path::new("/nonexistent/x.csv"), &["gx_dps"], ReadOptions::default()).unwrap_err();
    assert!(matches!(err.kind, CsvErrorKind::Io(_)));
    assert!(err.to_string().starts_with("/nonexistent/x.csv: cannot read"), "{err}");
}

#[test]
fn streaming_rows_carry_their_line_numbers() {
    let f = file_with(b"t_s,gx_dps,gy_dps\n0,1,2\n\n1,3,4\n");
    let mut r = SampleReader::open(f.path(), &["gy_dps", "gx_dps"], ReadOptions::default()).unwrap();
    let row = r.next_row().unwrap().unwrap();
    assert_eq!((row.line, row.t_s, row.values), (2, 0.0, &[2.0, 1.0][..]));
    let row = r.next_row().unwrap().unwrap();
    assert_eq!((row.line, row.values), (4, &[4.0, 3.0][..]));
    assert!(r.next_row().unwrap().is_none());
    assert_eq!(r.rows_read(), 2);
}

#[test]
fn line_numbers_stay_right_with_crlf_blank_lines_and_quotes() {
    // The csv crate reports line 1 for the first data row of a CRLF file and loses blank lines;
    // errors here must name the line a person sees in an editor.
    let err = read("t_s,gx_dps\r\n0,1\r\n\r\n\r\n1,x\r\n", "gx_dps").unwrap_err();
    assert_eq!(err.line, Some(5), "{err}");
    let err = read("note,t_s,gx_dps\n\"a, b\",0,1\n\"c \"\"q\"\"\",1,oops\n", "gx_dps").unwrap_err();
    assert_eq!((err.line, err.field.as_deref()), (Some(3), Some("gx_dps")), "{err}");
    let err = read("t_s,gx_dps\n0,1\n\"1,2\n", "gx_dps").unwrap_err();
    assert!(matches!(err.kind, CsvErrorKind::Malformed(_)) && err.line == Some(3), "{err}");
}
