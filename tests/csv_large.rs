//! Large files through the CSV reader with bounded memory: a global allocator measures the peak
//! of live heap bytes on the reading thread.
//!
//! - A generated 12-column recording streamed through [`SampleReader`] holds a constant amount of
//!   memory however long it is (the text is never held).
//! - [`read_table`] keeps only the selected columns, as `f64`: its peak is set by the rows times
//!   the selected columns, not by the file size.
//! - Ignored (`cargo test --release --test csv_large -- --ignored --nocapture`): the same on a
//!   1 GB file written to the temp directory, with throughput figures.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::io::{BufWriter, Read, Write};
use std::path::Path;
use std::time::Instant;

use gyrocomp::io::{ReadOptions, SampleReader, read_table};

struct Peak;

thread_local! {
    static LIVE: Cell<i64> = const { Cell::new(0) };
    static PEAK: Cell<i64> = const { Cell::new(0) };
}

fn add(delta: i64) {
    // `try_with`: the allocator may run while thread-locals are being torn down.
    let _ = LIVE.try_with(|l| {
        let now = l.get() + delta;
        l.set(now);
        let _ = PEAK.try_with(|p| p.set(p.get().max(now)));
    });
}

unsafe impl GlobalAlloc for Peak {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        add(layout.size() as i64);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        add(-(layout.size() as i64));
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        add(new_size as i64 - layout.size() as i64);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Peak = Peak;

/// Runs `f` and returns its result and the peak of live heap bytes it added on this thread.
fn peak_of<T>(f: impl FnOnce() -> T) -> (T, u64) {
    let base = LIVE.with(Cell::get);
    PEAK.with(|p| p.set(base));
    let out = f();
    (out, (PEAK.with(Cell::get) - base).max(0) as u64)
}

/// A recording generated on the fly: `t_s,gx_dps,gy_dps,gz_dps,temp_c` and seven more columns,
/// row k at 1 kHz with values that depend on k (so a reader that mixes rows up is caught).
struct Recording {
    rows: u64,
    next: u64,
    line: Vec<u8>,
    at: usize,
}

const HEADER: &[u8] = b"t_s,gx_dps,gy_dps,gz_dps,temp_c,ax,ay,az,mx,my,mz,baro\n";

impl Recording {
    fn new(rows: u64) -> Self {
        Self { rows, next: 0, line: HEADER.to_vec(), at: 0 }
    }

    fn gx(k: u64) -> f64 {
        (k % 1000) as f64 * 1e-3 - 0.5
    }

    fn fill(&mut self) {
        let k = self.next;
        self.line.clear();
        writeln!(
            self.line,
            "{:.3},{},{:.6},-0.000125,21.5,0.0123,-0.0456,9.80665,0.21,-0.03,0.44,1013.25",
            k as f64 * 1e-3,
            Self::gx(k),
            (k % 7) as f64 * 1e-4
        )
        .unwrap();
        self.next += 1;
        self.at = 0;
    }
}

impl Read for Recording {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.at == self.line.len() {
            if self.next == self.rows {
                return Ok(0);
            }
            self.fill();
        }
        let n = buf.len().min(self.line.len() - self.at);
        buf[..n].copy_from_slice(&self.line[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

/// Streams `input` selecting `gx_dps`; returns (rows, sum of gx).
fn stream<R: Read>(input: R) -> (u64, f64) {
    let mut r = SampleReader::from_reader(input, Path::new("generated.csv"), &["gx_dps"], ReadOptions::default())
        .expect("header");
    let mut sum = 0.0;
    while let Some(row) = r.next_row().expect("valid row") {
        sum += row.values[0];
    }
    (r.rows_read(), sum)
}

fn expected_sum(rows: u64) -> f64 {
    (0..rows).map(Recording::gx).sum()
}

fn write_file(path: &Path, rows: u64) -> u64 {
    let mut out = BufWriter::with_capacity(1 << 20, std::fs::File::create(path).unwrap());
    std::io::copy(&mut Recording::new(rows), &mut out).unwrap();
    out.flush().unwrap();
    std::fs::metadata(path).unwrap().len()
}

#[test]
fn streaming_memory_does_not_grow_with_the_file() {
    let ((small_rows, _), small_peak) = peak_of(|| stream(Recording::new(1_000)));
    let rows = 300_000; // about 28 MB of text
    let ((n, sum), peak) = peak_of(|| stream(Recording::new(rows)));
    assert_eq!((small_rows, n), (1_000, rows));
    assert!((sum - expected_sum(rows)).abs() < 1e-6 * rows as f64);
    eprintln!("streaming: peak heap {small_peak} B for 1,000 rows, {peak} B for {rows} rows");
    // The 64 KiB read buffer and a few line-sized buffers, whatever the length.
    assert!(peak < 128 * 1024, "peak {peak} B");
    assert!(peak <= small_peak + 1024, "memory grew with the file: {small_peak} B -> {peak} B");
}

#[test]
fn read_table_keeps_only_the_selected_columns() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("wide.csv");
    let rows = 100_000u64;
    let size = write_file(&path, rows);
    let (table, peak) = peak_of(|| read_table(&path, &["gx_dps"], ReadOptions::default()).unwrap());
    assert_eq!(table.len() as u64, rows);
    let sum: f64 = table.columns[0].iter().sum();
    assert!((sum - expected_sum(rows)).abs() < 1e-6 * rows as f64);
    // t_s, gx_dps and temp_c as f64, each vector at most twice its length while growing.
    let held = 3 * rows * 8;
    eprintln!("read_table: file {size} B, peak heap {peak} B, selected data {held} B");
    assert!(peak <= 2 * held + 256 * 1024, "peak {peak} B for {held} B of selected data");
    assert!(peak < size / 2, "peak {peak} B against a {size}-byte file");
}

#[test]
#[ignore = "writes and reads a 1.2 GB file (about 20 s); run with --ignored --nocapture"]
fn one_gigabyte_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("one_gb.csv");
    let rows = 12_500_000u64;
    let t = Instant::now();
    let size = write_file(&path, rows);
    eprintln!("wrote {size} B ({rows} rows) in {:.1} s", t.elapsed().as_secs_f64());
    assert!(size >= 1_000_000_000);

    let t = Instant::now();
    let ((n, sum), peak) = peak_of(|| stream(std::fs::File::open(&path).unwrap()));
    let secs = t.elapsed().as_secs_f64();
    assert_eq!(n, rows);
    assert!((sum - expected_sum(rows)).abs() < 1e-6 * rows as f64);
    eprintln!("SampleReader: {n} rows in {secs:.1} s ({:.0} MB/s), peak heap {peak} B", size as f64 / secs / 1e6);
    assert!(peak < 128 * 1024);

    let t = Instant::now();
    let (table, peak) = peak_of(|| read_table(&path, &["gx_dps"], ReadOptions::default()).unwrap());
    let secs = t.elapsed().as_secs_f64();
    assert_eq!(table.len() as u64, rows);
    eprintln!(
        "read_table: {} rows in {secs:.1} s ({:.0} MB/s), peak heap {:.0} MB (selected data {:.0} MB)",
        table.len(),
        size as f64 / secs / 1e6,
        peak as f64 / 1e6,
        (3 * rows * 8) as f64 / 1e6
    );
    assert!(peak <= 2 * 3 * rows * 8 + 256 * 1024);
}
