//! A stand-in INS as a separate process, for the fault and permission tests: the test binary
//! runs itself again (`--exact ins_child_entry`) with `GC_CHILD` set, so the child can be
//! killed, restarted or run under another uid without any extra program.
//!
//! Modes (`GC_CHILD`):
//! - `publisher`: primes the stream, then publishes static samples at `GC_RATE_HZ` (lossless,
//!   giving up on a full subscriber after 200 ms) and counts the answers; prints a progress line
//!   every 50 ms; with `GC_COUNT` it stops after that many samples, waits up to 5 s for the
//!   missing answers and prints `done …`.
//! - `probe`: creates a node, then tries each port of an existing daemon's services (raw
//!   publisher, compensated and status subscribers) and, when both stream ports opened, one
//!   round trip; prints `probe node=… raw_publisher=ok|refused … answered=ok|refused errors=…`.
//! - `stalled`: a client that stops reading: subscribes to the compensated service (buffer
//!   `GC_BUFFER`, default 2048), prints `subscribed`, receives until it got an answer and none is
//!   waiting (so it is attached and its buffer is empty), prints `stalled received=… last_seq=…`
//!   and then never receives again, alive until killed.
//!
//! Every line the child says starts with [`MARK`] and a keyword and holds `key=value` fields,
//! parsed by [`Progress`] (the test harness prints its own text before the first one).

#![allow(dead_code)] // each test binary uses a part

use std::collections::HashMap;
use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Child, ChildStdout, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use gyrocomp::ipc::{
    CompSubscriber, Delivery, IpcDomain, IpcNode, IpcSettings, RawPublisher, RawSample, STATUS_NO_MODEL, prime,
};

/// Name of the test function that is the child's entry point.
pub const ENTRY: &str = "ins_child_entry";
/// Marks the child's own output lines.
pub const MARK: &str = "@@ ";

/// One line of the child's output: the keyword and its fields.
#[derive(Debug, Clone, Default)]
pub struct Progress {
    /// `progress`, `done`, `primed`, `probe`, …
    pub kind: String,
    /// `key=value` fields.
    pub fields: HashMap<String, String>,
    /// The whole line.
    pub line: String,
}

impl Progress {
    fn parse(line: &str) -> Option<Self> {
        let line = &line[line.find(MARK)? + MARK.len()..];
        let mut words = line.split_whitespace();
        let kind = words.next().unwrap_or_default().to_owned();
        let fields = words.filter_map(|w| w.split_once('=')).map(|(k, v)| (k.to_owned(), v.to_owned())).collect();
        Some(Self { kind, fields, line: line.to_owned() })
    }

    /// A numeric field (0 when absent).
    pub fn get(&self, key: &str) -> u64 {
        self.fields.get(key).and_then(|v| v.parse().ok()).unwrap_or(0)
    }
}

/// A child process and the lines it printed so far; killed (SIGKILL) on drop.
pub struct ChildProc {
    child: Option<Child>,
    lines: Arc<Mutex<Vec<Progress>>>,
    reader: Option<std::thread::JoinHandle<()>>,
    stderr: std::path::PathBuf,
    _dir: tempfile::TempDir,
}

impl ChildProc {
    /// Starts the test binary itself in child mode `mode` for `domain`, with extra environment
    /// variables, optionally through a wrapper (e.g. `setpriv --reuid …`).
    pub fn start(mode: &str, domain: &IpcDomain, env: &[(&str, String)], wrapper: &[&str]) -> Self {
        let exe = std::env::current_exe().expect("test binary path");
        let dir = tempfile::tempdir().expect("temp dir");
        let stderr = dir.path().join("child.stderr");
        let mut cmd = match wrapper.split_first() {
            Some((program, args)) => {
                let mut c = Command::new(program);
                c.args(args).arg(&exe);
                c
            }
            None => Command::new(&exe),
        };
        cmd.args(["--exact", ENTRY, "--nocapture", "--ignored", "--test-threads=1"])
            .env("GC_CHILD", mode)
            .env("GC_PREFIX", domain.prefix())
            .env("GC_ROOT", domain.root_path())
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(std::fs::File::create(&stderr).unwrap());
        for (k, v) in env {
            cmd.env(k, v);
        }
        let mut child = cmd.spawn().expect("start the child process");
        let lines = Arc::new(Mutex::new(Vec::new()));
        let reader = Some(spawn_reader(child.stdout.take().unwrap(), Arc::clone(&lines)));
        Self { child: Some(child), lines, reader, stderr, _dir: dir }
    }

    /// The lines printed so far that start with `kind`.
    pub fn lines(&self, kind: &str) -> Vec<Progress> {
        self.lines.lock().unwrap().iter().filter(|p| p.kind == kind).cloned().collect()
    }

    /// The newest line starting with `kind`.
    pub fn last(&self, kind: &str) -> Option<Progress> {
        self.lines.lock().unwrap().iter().rev().find(|p| p.kind == kind).cloned()
    }

    /// Waits until a line starting with `kind` satisfies `pred`; panics after `timeout`.
    pub fn wait_for(&self, kind: &str, timeout: Duration, pred: impl Fn(&Progress) -> bool) -> Progress {
        let start = Instant::now();
        loop {
            if let Some(p) = self.lines.lock().unwrap().iter().rev().find(|p| p.kind == kind && pred(p)) {
                return p.clone();
            }
            assert!(
                start.elapsed() < timeout,
                "child: no `{kind}` line as expected within {timeout:?}; last lines: {:?}\nstderr:\n{}",
                self.lines.lock().unwrap().iter().rev().take(3).map(|p| p.line.clone()).collect::<Vec<_>>(),
                self.stderr_text()
            );
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Waits for the child to exit; returns its exit code.
    pub fn wait_exit(&mut self, timeout: Duration) -> Option<i32> {
        let start = Instant::now();
        let child = self.child.as_mut().expect("running child");
        loop {
            if let Some(status) = child.try_wait().unwrap() {
                self.child = None;
                if let Some(r) = self.reader.take() {
                    let _ = r.join();
                }
                return status.code();
            }
            assert!(start.elapsed() < timeout, "child did not exit within {timeout:?}\n{}", self.stderr_text());
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// SIGKILL, then reap.
    pub fn kill(&mut self) {
        if let Some(mut c) = self.child.take() {
            let _ = c.kill();
            let _ = c.wait();
        }
        if let Some(r) = self.reader.take() {
            let _ = r.join();
        }
    }

    /// What the child wrote on stderr.
    pub fn stderr_text(&self) -> String {
        std::fs::read_to_string(&self.stderr).unwrap_or_default()
    }
}

impl Drop for ChildProc {
    fn drop(&mut self) {
        self.kill();
        if std::thread::panicking() {
            eprintln!("--- child stderr ---\n{}", self.stderr_text());
        }
    }
}

fn spawn_reader(out: ChildStdout, lines: Arc<Mutex<Vec<Progress>>>) -> std::thread::JoinHandle<()> {
    std::thread::spawn(move || {
        for line in BufReader::new(out).lines().map_while(Result::ok) {
            if let Some(p) = Progress::parse(&line) {
                lines.lock().unwrap().push(p);
            }
        }
    })
}

/// The child's entry point: does nothing unless `GC_CHILD` is set (then it is the child).
pub fn entry() {
    let Ok(mode) = std::env::var("GC_CHILD") else { return };
    let var = |k: &str| std::env::var(k).unwrap_or_else(|_| panic!("child: {k} not set"));
    let domain = IpcDomain::private(&var("GC_PREFIX"), Path::new(&var("GC_ROOT"))).expect("child domain");
    match mode.as_str() {
        "publisher" => publisher(&domain),
        "probe" => probe(&domain),
        "stalled" => stalled(&domain),
        other => panic!("child: unknown mode {other}"),
    }
}

fn say(line: &str) {
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "{MARK}{line}");
    let _ = out.flush();
}

fn client_node(domain: &IpcDomain, name: &str) -> Result<IpcNode, String> {
    let delivery = Delivery::Lossless { give_up_after: Some(Duration::from_millis(200)) };
    IpcNode::new(domain, name, IpcSettings { delivery, ..IpcSettings::default() }).map_err(|e| e.to_string())
}

fn sample(seq: u64) -> RawSample {
    let k = seq as f64;
    RawSample::new(seq, seq * 10_000_000, [0.02 + 0.001 * (k * 0.1).sin(), -0.01, 0.005])
}

/// Primes until an answer comes (the daemon may still be starting); returns the next seq.
fn prime_until(raw: &RawPublisher, comp: &CompSubscriber, mut seq: u64, timeout: Duration) -> u64 {
    let start = Instant::now();
    loop {
        let ok = prime(raw, comp, sample(seq), Duration::from_millis(100)).is_ok();
        seq += 1;
        if ok {
            return seq;
        }
        assert!(start.elapsed() < timeout, "child: the daemon did not answer within {timeout:?}");
    }
}

fn publisher(domain: &IpcDomain) {
    let env_u64 = |k: &str, d: u64| std::env::var(k).ok().and_then(|v| v.parse().ok()).unwrap_or(d);
    let first = env_u64("GC_SEQ_START", 0);
    let count = std::env::var("GC_COUNT").ok().and_then(|v| v.parse::<u64>().ok());
    let period = Duration::from_secs_f64(1.0 / env_u64("GC_RATE_HZ", 200) as f64);
    let node = client_node(domain, "fault_ins").expect("child node");
    let raw = node.raw_publisher().expect("raw publisher");
    let comp = node.comp_subscriber().expect("compensated subscriber");
    let mut seq = prime_until(&raw, &comp, first, Duration::from_secs(30));
    let streamed_from = seq;
    say(&format!("primed seq={seq}"));
    let (mut sent, mut send_errors, mut answered, mut last_seq, mut version, mut no_model) =
        (0u64, 0u64, 0u64, 0, 0, 0);
    let mut max_send_us = 0u64;
    let started = Instant::now();
    let mut last_print = Instant::now();
    let mut next = Instant::now();
    let drain = |answered: &mut u64, last_seq: &mut u64, version: &mut u64, no_model: &mut u64| {
        while let Ok(Some(a)) = comp.try_recv() {
            if a.seq >= streamed_from {
                *answered += 1;
            }
            *last_seq = a.seq;
            *version = a.model_version;
            if a.status & STATUS_NO_MODEL != 0 {
                *no_model += 1;
            }
        }
    };
    loop {
        if count.is_some_and(|c| sent >= c) || started.elapsed() > Duration::from_secs(120) {
            break;
        }
        let t = Instant::now();
        match raw.send(sample(seq)) {
            Ok(()) => {}
            Err(_) => send_errors += 1,
        }
        max_send_us = max_send_us.max(t.elapsed().as_micros() as u64);
        seq += 1;
        sent += 1;
        drain(&mut answered, &mut last_seq, &mut version, &mut no_model);
        if last_print.elapsed() >= Duration::from_millis(50) {
            last_print = Instant::now();
            say(&format!(
                "progress sent={sent} send_errors={send_errors} answered={answered} last_answer_seq={last_seq} \
                 next_seq={seq} model_version={version} no_model={no_model} max_send_us={max_send_us}"
            ));
        }
        next += period;
        if let Some(wait) = next.checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        } else {
            next = Instant::now();
        }
    }
    let deadline = Instant::now() + Duration::from_secs(5);
    while answered < sent && Instant::now() < deadline {
        let _ = comp.wait(Duration::from_millis(20));
        drain(&mut answered, &mut last_seq, &mut version, &mut no_model);
    }
    say(&format!(
        "done sent={sent} send_errors={send_errors} answered={answered} last_answer_seq={last_seq} \
         model_version={version} no_model={no_model} max_send_us={max_send_us}"
    ));
}

fn probe(domain: &IpcDomain) {
    let word = |ok: bool| if ok { "ok" } else { "refused" };
    let node = match client_node(domain, "probe_ins") {
        Ok(n) => n,
        Err(e) => {
            say(&format!("probe node=refused error={}", e.replace(char::is_whitespace, "_")));
            return;
        }
    };
    let raw = node.raw_publisher();
    let comp = node.comp_subscriber();
    let status = node.status_subscriber();
    let errors: Vec<String> = [raw.as_ref().err(), comp.as_ref().err(), status.as_ref().err()]
        .into_iter()
        .flatten()
        .map(|e| e.to_string().replace(char::is_whitespace, "_"))
        .collect();
    let answered = match (&raw, &comp) {
        (Ok(r), Ok(c)) => prime(r, c, sample(0), Duration::from_secs(10)).is_ok(),
        _ => false,
    };
    say(&format!(
        "probe node=ok raw_publisher={} comp_subscriber={} status_subscriber={} answered={} errors={}",
        word(raw.is_ok()),
        word(comp.is_ok()),
        word(status.is_ok()),
        word(answered),
        errors.join("|")
    ));
}

fn stalled(domain: &IpcDomain) {
    let buffer = std::env::var("GC_BUFFER").ok().and_then(|v| v.parse().ok()).unwrap_or(2048);
    let settings = IpcSettings { subscriber_buffer: buffer, ..IpcSettings::default() };
    let node = IpcNode::new(domain, "stalled_reader", settings).expect("child node");
    let comp = node.comp_subscriber().expect("compensated subscriber");
    say("subscribed");
    let (mut received, mut last_seq) = (0u64, 0u64);
    loop {
        match comp.recv_timeout(Duration::from_millis(10)).expect("receive") {
            Some(a) => {
                received += 1;
                last_seq = a.seq;
            }
            None if received > 0 => break,
            None => {}
        }
    }
    say(&format!("stalled received={received} last_seq={last_seq}"));
    loop {
        std::thread::sleep(Duration::from_secs(1));
    }
}
