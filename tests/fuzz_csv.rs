//! Property tests ("fuzzing") of the CSV reader: arbitrary bytes, and valid recordings with
//! random byte-level mutations (deleted, inserted or replaced bytes from an alphabet of CSV
//! metacharacters, digits, BOM and invalid UTF-8). The reader must never panic; it returns either
//! a table whose columns all have one length per row (time finite and increasing, values finite
//! unless allowed otherwise), or an error whose message starts with the file name and, except
//! for a file without any non-blank line, names a line that exists in the input.
//!
//! Case counts: proptest's default (256 per property) or `PROPTEST_CASES`.

use std::io::Cursor;
use std::path::Path;

use gyrocomp::io::{CsvError, CsvErrorKind, ReadOptions, SampleReader, read_table_from};
use proptest::prelude::*;

const LABEL: &str = "fuzz.csv";

/// Lines a text editor shows for `bytes`.
fn line_count(bytes: &[u8]) -> u64 {
    let newlines = bytes.iter().filter(|&&b| b == b'\n').count() as u64;
    newlines + u64::from(bytes.last().is_some_and(|&b| b != b'\n'))
}

fn check_error(bytes: &[u8], err: &CsvError) -> Result<(), TestCaseError> {
    let msg = err.to_string();
    prop_assert!(msg.starts_with(LABEL), "message does not name the file: {msg}");
    match err.line {
        Some(line) => {
            prop_assert!(line >= 1 && line <= line_count(bytes).max(1), "line {line} not in the input: {msg}");
            prop_assert!(msg.starts_with(&format!("{LABEL}:{line}")), "{msg}");
        }
        None => {
            let blank = bytes.split(|&b| b == b'\n').all(|l| {
                let l = l.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(l);
                l.iter().all(|b| b.is_ascii_whitespace())
            });
            prop_assert!(matches!(err.kind, CsvErrorKind::Empty) && blank, "no line in: {msg}");
        }
    }
    Ok(())
}

fn check(bytes: &[u8], options: ReadOptions) -> Result<(), TestCaseError> {
    let columns = ["gx_dps", "gy_dps"];
    match read_table_from(Cursor::new(bytes), Path::new(LABEL), &columns, options) {
        Ok(t) => {
            prop_assert!(!t.is_empty());
            prop_assert!(t.columns.len() == 2 && t.columns.iter().all(|c| c.len() == t.len()));
            prop_assert!(t.temp_c.as_ref().is_none_or(|c| c.len() == t.len()));
            prop_assert!(t.t_s.iter().all(|v| v.is_finite()));
            if options.require_increasing_time {
                prop_assert!(t.t_s.windows(2).all(|w| w[1] > w[0]));
            }
            if !options.allow_non_finite {
                prop_assert!(t.columns.iter().flatten().all(|v| v.is_finite()));
            }
            prop_assert!(t.len() as u64 <= line_count(bytes));
        }
        Err(e) => check_error(bytes, &e)?,
    }
    // The streaming reader stops at the same place with the same kind of answer.
    let mut rows = 0u64;
    let streamed =
        SampleReader::from_reader(Cursor::new(bytes), Path::new(LABEL), &columns, options).and_then(|mut r| {
            while let Some(row) = r.next_row()? {
                rows += 1;
                assert!(row.line <= line_count(bytes));
            }
            Ok(())
        });
    if let Err(e) = streamed {
        check_error(bytes, &e)?;
    }
    Ok(())
}

fn options() -> impl Strategy<Value = ReadOptions> {
    (any::<bool>(), any::<bool>()).prop_map(|(allow_non_finite, require_increasing_time)| ReadOptions {
        allow_non_finite,
        require_increasing_time,
    })
}

/// A valid recording: a header (time name, the two rate columns, maybe `temp_c` and an extra
/// column, in some order) and rows with increasing time.
fn valid_file() -> impl Strategy<Value = Vec<u8>> {
    let time = prop::sample::select(vec!["t_s", "t", "time"]);
    let rows = prop::collection::vec((0.001f64..1.0, -500.0f64..500.0, -1e-3f64..1e-3, -40.0f64..85.0), 0..40);
    (time, any::<bool>(), any::<bool>(), any::<bool>(), rows).prop_map(|(time, temp, crlf, bom, rows)| {
        let eol = if crlf { "\r\n" } else { "\n" };
        let mut text = String::new();
        if bom {
            text.push('\u{feff}');
        }
        text.push_str(&format!("{time},gx_dps,extra,gy_dps{}{eol}", if temp { ",temp_c" } else { "" }));
        let mut t = 0.0;
        for (dt, a, b, c) in rows {
            t += dt;
            text.push_str(&format!("{t},{a},\"x\",{b:e}{}{eol}", if temp { format!(",{c}") } else { String::new() }));
        }
        text.into_bytes()
    })
}

/// A mutation: position (as a fraction of the length), operation, byte.
fn mutations() -> impl Strategy<Value = Vec<(f64, u8, u8)>> {
    let alphabet = prop::sample::select(b",\n\r\" \t.-+e0123456789naNiIf\xEF\xBB\xBF\xFF\x00;#".to_vec());
    prop::collection::vec((0.0f64..1.0, 0u8..3, alphabet), 1..8)
}

fn mutate(mut bytes: Vec<u8>, ops: &[(f64, u8, u8)]) -> Vec<u8> {
    for &(at, op, byte) in ops {
        let i = ((at * bytes.len() as f64) as usize).min(bytes.len());
        match op {
            0 if i < bytes.len() => {
                bytes.remove(i);
            }
            1 => bytes.insert(i, byte),
            _ if i < bytes.len() => bytes[i] = byte,
            _ => bytes.push(byte),
        }
    }
    bytes
}

proptest! {
    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..600), opts in options()) {
        check(&bytes, opts)?;
    }

    #[test]
    fn arbitrary_csv_like_text_never_panics(
        text in "(t_s|time|gx_dps|gy_dps|temp_c|[0-9.eE+-]{0,6}|nan|inf|\"|,|\r?\n| ){0,60}",
        opts in options(),
    ) {
        check(text.as_bytes(), opts)?;
    }

    #[test]
    fn valid_files_read_and_mutated_ones_fail_cleanly(file in valid_file(), ops in mutations(), opts in options()) {
        let rows = line_count(&file) - 1;
        match read_table_from(Cursor::new(&file), Path::new(LABEL), &["gx_dps", "gy_dps"], opts) {
            Ok(t) => prop_assert_eq!(t.len() as u64, rows),
            Err(e) => {
                prop_assert!(rows == 0 && matches!(e.kind, CsvErrorKind::NoData), "valid file refused: {}", e);
                prop_assert_eq!(e.line, Some(1));
            }
        }
        check(&mutate(file, &ops), opts)?;
    }
}

#[test]
fn an_overlong_line_is_refused_with_its_line_number() {
    let mut bytes = b"t_s,gx_dps,gy_dps\n0,1,2\n".to_vec();
    bytes.extend(std::iter::repeat_n(b'7', gyrocomp::io::csv_read::MAX_LINE_BYTES + 10));
    let err = read_table_from(Cursor::new(&bytes), Path::new(LABEL), &["gx_dps"], ReadOptions::default()).unwrap_err();
    assert_eq!(err.line, Some(3), "{err}");
    assert!(err.to_string().contains("line longer than"), "{err}");
    // Without a single line end the header itself is refused.
    let blob = vec![b'x'; gyrocomp::io::csv_read::MAX_LINE_BYTES * 2];
    let err = read_table_from(Cursor::new(&blob), Path::new(LABEL), &["gx_dps"], ReadOptions::default()).unwrap_err();
    assert_eq!(err.line, Some(1), "{err}");
}
