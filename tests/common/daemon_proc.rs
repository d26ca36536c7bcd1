//! A `gyrocompd` process for the integration tests, and the client start-up they share.
//! The process is SIGKILLed on drop (its log printed when the test failed), so no test leaves a
//! daemon behind.

#![allow(dead_code)] // each test binary uses a part

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use gyrocomp::ipc::{CompSample, CompSubscriber, RawPublisher, RawSample, StatusSample, StatusSubscriber, prime};

/// A running (or exited) `gyrocompd` and its log file (its stderr).
pub struct DaemonProc {
    child: Option<Child>,
    pid: u32,
    log: PathBuf,
}

impl DaemonProc {
    /// Starts the built binary with `--config config`; stderr goes to `log`.
    pub fn start(config: &Path, log: PathBuf) -> Self {
        let child = Command::new(env!("CARGO_BIN_EXE_gyrocompd"))
            .arg("--config")
            .arg(config)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(std::fs::File::create(&log).unwrap())
            .spawn()
            .expect("start gyrocompd");
        Self { pid: child.id(), child: Some(child), log }
    }

    /// The process id.
    pub fn pid(&self) -> u32 {
        self.pid
    }

    /// Sends signal `name` (e.g. "TERM").
    pub fn signal(&self, name: &str) {
        let pid = self.pid.to_string();
        let ok = Command::new("kill").args([&format!("-{name}"), pid.as_str()]).status().unwrap().success();
        assert!(ok, "kill -{name} {pid}");
    }

    /// Whether the process is still running.
    pub fn alive(&mut self) -> bool {
        self.child.as_mut().is_some_and(|c| c.try_wait().unwrap().is_none())
    }

    /// SIGKILL, then reap.
    pub fn kill9(&mut self) {
        let mut c = self.child.take().expect("running daemon");
        c.kill().unwrap();
        c.wait().unwrap();
    }

    /// Waits for the process to exit; kills it and panics after `timeout`.
    pub fn wait_exit(&mut self, timeout: Duration) -> ExitStatus {
        let start = Instant::now();
        let child = self.child.as_mut().expect("running daemon");
        loop {
            if let Some(status) = child.try_wait().unwrap() {
                self.child = None;
                return status;
            }
            if start.elapsed() >= timeout {
                let _ = child.kill();
                let _ = child.wait();
                self.child = None;
                panic!("gyrocompd (pid {}) did not exit within {timeout:?}:\n{}", self.pid, self.log_text());
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Its log so far.
    pub fn log_text(&self) -> String {
        std::fs::read_to_string(&self.log).unwrap_or_default()
    }

    /// Waits until the log contains `needle`; returns the log.
    pub fn wait_log(&self, needle: &str, timeout: Duration) -> String {
        let start = Instant::now();
        loop {
            let text = self.log_text();
            if text.contains(needle) {
                return text;
            }
            assert!(start.elapsed() < timeout, "`{needle}` not logged within {timeout:?}:\n{text}");
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

impl Drop for DaemonProc {
    fn drop(&mut self) {
        if let Some(mut c) = self.child.take() {
            let _ = c.kill();
            let _ = c.wait();
        }
        if std::thread::panicking() {
            eprintln!("--- {} ---\n{}", self.log.display(), self.log_text());
        }
    }
}

/// A static sample at 100 Hz with a little variation, seq = `seq`.
pub fn sample(seq: u64) -> RawSample {
    let k = seq as f64;
    RawSample::new(seq, seq * 10_000_000, [0.02 + 0.002 * (k * 0.05).sin(), -0.01 + 0.001 * (k * 0.02).cos(), 0.005])
}

/// Primes again and again (100 ms each) until a (re)started daemon answers; returns the answer
/// and the next free seq.
pub fn prime_until(raw: &RawPublisher, comp: &CompSubscriber, mut seq: u64, timeout: Duration) -> (CompSample, u64) {
    let start = Instant::now();
    loop {
        assert!(start.elapsed() < timeout, "no answer within {timeout:?}");
        if !raw.wait_for_subscriber(Duration::from_millis(100)) {
            continue;
        }
        let got = prime(raw, comp, sample(seq), Duration::from_millis(100));
        seq += 1;
        if let Ok(a) = got {
            return (a, seq);
        }
    }
}

/// Sends `sample(seq)` and waits for its answer, which must be the next one to arrive.
pub fn round_trip(raw: &RawPublisher, comp: &CompSubscriber, seq: u64) -> CompSample {
    raw.send(sample(seq)).expect("send raw sample");
    let answer =
        comp.recv_timeout(Duration::from_secs(20)).unwrap().unwrap_or_else(|| panic!("no answer to seq {seq}"));
    assert_eq!(answer.seq, seq, "answers arrive once each, in order");
    answer
}

/// Reads status reports until one satisfies `pred`; panics after `timeout`.
pub fn wait_status(status: &StatusSubscriber, timeout: Duration, pred: impl Fn(&StatusSample) -> bool) -> StatusSample {
    let start = Instant::now();
    let mut last = None;
    loop {
        while let Some(s) = status.try_recv().unwrap() {
            if pred(&s) {
                return s;
            }
            last = Some(s);
        }
        assert!(start.elapsed() < timeout, "no status report as expected within {timeout:?}; last: {last:?}");
        let _ = status.wait(Duration::from_millis(50));
    }
}
