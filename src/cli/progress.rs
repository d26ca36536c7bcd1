//! A progress bar for long offline runs, drawn on stderr only when stderr is a terminal
//! ([`std::io::IsTerminal`]); with stderr redirected (a file, a pipe, a test) nothing is drawn.
//!
//! Hand-written rather than a crate (`indicatif` and the like): one line redrawn in place at
//! most ten times a second is all that is needed, and the bar has to cooperate with the
//! `tracing` log lines that share stderr: [`stderr_clearing_bar`] is the log writer of the
//! `gyrocomp` binary, and it erases a bar that is on screen before a log line is written, so the
//! log line starts at the left margin and the bar is redrawn below it on the next update.

use std::io::{self, IsTerminal, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Whether a bar is drawn on the current stderr line (set by a draw, cleared by the log writer).
static BAR_ON_SCREEN: AtomicBool = AtomicBool::new(false);
/// Least time between two redraws.
const REDRAW: Duration = Duration::from_millis(100);
/// Positions between two looks at the clock.
const CHECK_EVERY: u64 = 256;
/// Width of the bar itself, characters.
const BAR_WIDTH: usize = 30;
/// Erases the current terminal line: carriage return, then ANSI "erase to end of line".
const CLEAR_LINE: &str = "\r\x1b[K";

/// A progress bar over `total` steps; silent unless stderr is a terminal.
#[derive(Debug)]
pub struct Progress {
    label: String,
    total: u64,
    started: Instant,
    last_draw: Option<Instant>,
    next_check: u64,
    visible: bool,
}

impl Progress {
    /// A bar labelled `label` over `total` steps, drawn only when stderr is a terminal.
    pub fn new(label: &str, total: u64) -> Self {
        Self::with_visibility(label, total, io::stderr().is_terminal())
    }

    /// A bar that is drawn or not as told (tests; `new` decides by the terminal).
    pub fn with_visibility(label: &str, total: u64, visible: bool) -> Self {
        Self {
            label: label.to_owned(),
            total,
            started: Instant::now(),
            last_draw: None,
            next_check: 0,
            visible: visible && total > 0,
        }
    }

    /// Whether the bar draws anything.
    pub fn is_visible(&self) -> bool {
        self.visible
    }

    /// Records that `position` steps are done; redraws at most every 100 ms (cheap otherwise: the
    /// clock is read once every 256 positions).
    pub fn set(&mut self, position: u64) {
        if !self.visible || position < self.next_check {
            return;
        }
        self.next_check = position + CHECK_EVERY;
        let now = Instant::now();
        if self.last_draw.is_some_and(|t| now.duration_since(t) < REDRAW) {
            return;
        }
        self.last_draw = Some(now);
        let line = render(&self.label, position, self.total, now.duration_since(self.started).as_secs_f64());
        let mut err = io::stderr().lock();
        // A failed write to a terminal is not worth stopping a run for.
        let _ = write!(err, "{CLEAR_LINE}{line}").and_then(|()| err.flush());
        BAR_ON_SCREEN.store(true, Ordering::Relaxed);
    }

    /// Erases the bar (also done on drop).
    pub fn finish(&mut self) {
        if self.visible {
            clear_bar();
            self.visible = false;
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}

/// Erases a bar that is on screen.
fn clear_bar() {
    if BAR_ON_SCREEN.swap(false, Ordering::Relaxed) {
        let mut err = io::stderr().lock();
        let _ = write!(err, "{CLEAR_LINE}").and_then(|()| err.flush());
    }
}

/// One bar line: `label [#####·····]  45.0%  45000/100000  12.3 k/s  ETA 5 s`.
pub fn render(label: &str, position: u64, total: u64, elapsed_s: f64) -> String {
    let position = position.min(total);
    let fraction = if total == 0 { 1.0 } else { position as f64 / total as f64 };
    let filled = ((fraction * BAR_WIDTH as f64).round() as usize).min(BAR_WIDTH);
    let rate = if elapsed_s > 0.0 { position as f64 / elapsed_s } else { 0.0 };
    let eta = if rate > 0.0 { format!("ETA {:.0} s", (total - position) as f64 / rate) } else { "ETA ?".into() };
    format!(
        "{label} [{}{}] {:5.1}%  {position}/{total}  {}  {eta}",
        "#".repeat(filled),
        "·".repeat(BAR_WIDTH - filled),
        100.0 * fraction,
        per_second(rate),
    )
}

fn per_second(rate: f64) -> String {
    if rate >= 1e6 {
        format!("{:.1} M/s", rate / 1e6)
    } else if rate >= 1e3 {
        format!("{:.1} k/s", rate / 1e3)
    } else {
        format!("{rate:.0} /s")
    }
}

/// Standard error for log lines, erasing a progress bar that is on screen first.
#[derive(Debug)]
pub struct BarAwareStderr(io::Stderr);

impl Write for BarAwareStderr {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        clear_bar();
        self.0.write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.0.flush()
    }
}

/// The `tracing` writer of the `gyrocomp` binary: stderr, erasing a progress bar first.
pub fn stderr_clearing_bar() -> BarAwareStderr {
    BarAwareStderr(io::stderr())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bar_line_shows_fraction_rate_and_eta() {
        let line = render("compensate", 45_000, 100_000, 2.0);
        assert!(line.starts_with("compensate [##############"), "{line}");
        assert_eq!(line.matches('#').count(), 14, "{line}"); // 0.45 · 30 = 13.5 → 14
        assert!(line.contains(" 45.0%  45000/100000  22.5 k/s  ETA 2 s"), "{line}");
        let done = render("x", 10, 10, 0.0);
        assert!(done.contains("100.0%") && done.contains("ETA ?") && !done.contains('·'), "{done}");
        assert!(render("x", 0, 0, 1.0).contains("100.0%"));
    }

    #[test]
    fn a_hidden_bar_draws_nothing() {
        let mut p = Progress::with_visibility("x", 1000, false);
        p.set(500);
        assert!(!p.is_visible() && p.last_draw.is_none());
        assert!(!Progress::with_visibility("x", 0, true).is_visible());
    }
}
