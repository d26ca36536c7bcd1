//! CSV writing: a header naming every column, then one row per sample, values written in the
//! shortest form that reads back to the same `f64` bit for bit.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

/// A buffered writer on the file `path`, created or truncated, or on standard output when `path`
/// is `-`.
pub fn create_output(path: &Path) -> io::Result<Box<dyn Write>> {
    Ok(if path.as_os_str() == "-" {
        Box::new(BufWriter::with_capacity(1 << 16, io::stdout().lock()))
    } else {
        Box::new(BufWriter::with_capacity(1 << 16, File::create(path)?))
    })
}

/// Writes equal-length columns of `f64` as CSV to a file or to standard output (`-`).
pub struct CsvColumnsWriter {
    out: Box<dyn Write>,
}

impl CsvColumnsWriter {
    /// Creates `path` (or uses standard output when `path` is `-`).
    pub fn create(path: &Path) -> io::Result<Self> {
        Ok(Self { out: create_output(path)? })
    }

    /// Writes the header and all rows; every column must be as long as the first.
    pub fn write(mut self, header: &[&str], columns: &[&[f64]]) -> io::Result<()> {
        assert_eq!(header.len(), columns.len(), "one header name per column");
        let rows = columns.first().map_or(0, |c| c.len());
        assert!(columns.iter().all(|c| c.len() == rows), "columns of equal length");
        writeln!(self.out, "{}", header.join(","))?;
        for r in 0..rows {
            for (k, column) in columns.iter().enumerate() {
                if k > 0 {
                    self.out.write_all(b",")?;
                }
                write!(self.out, "{}", column[r])?;
            }
            self.out.write_all(b"\n")?;
        }
        self.out.flush()
    }
}
