//! `gyrocompd` end to end: the built binary in a private iceoryx2 domain, fed a simulated stream
//! through the Rust client ports. One answer per raw sample, same `seq`, in order; deterministic
//! retraining raises `model_version` exactly where the schedule says; SIGHUP applies new motion
//! thresholds without losing a sample and reports a detector change as needing a restart (the
//! running detector stays); SIGTERM ends it with exit code 0 and a final status.

#[path = "common/python.rs"]
mod python;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use gyrocomp::ipc::{
    CompSample, CompSubscriber, Delivery, IpcDomain, IpcNode, IpcSettings, RawPublisher, RawSample, STATUS_MOVING,
    StatusEvent, StatusSample, StatusSubscriber, prime,
};
use gyrocomp::sim::{Generator, Preset};

const EVERY: u64 = 200;
const DELAY: u64 = 20;

/// The daemon process and its private domain; kills the process and removes the domain on drop
/// (printing the daemon's log when the test failed).
struct Daemon {
    child: Option<Child>,
    domain: IpcDomain,
    config: PathBuf,
    log: PathBuf,
    _dir: tempfile::TempDir,
}

impl Daemon {
    fn start(wait: &str) -> Self {
        let dir = tempfile::tempdir().expect("temp dir");
        let domain = IpcDomain::unique("daemon").expect("private domain");
        let config = dir.path().join("gyrocompd.toml");
        std::fs::write(&config, config_text(&domain, 1.0, wait)).unwrap();
        let log = dir.path().join("gyrocompd.log");
        let child = Command::new(env!("CARGO_BIN_EXE_gyrocompd"))
            .arg("--config")
            .arg(&config)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(std::fs::File::create(&log).unwrap())
            .spawn()
            .expect("start gyrocompd");
        Self { child: Some(child), domain, config, log, _dir: dir }
    }

    fn signal(&self, name: &str) {
        let pid = self.child.as_ref().unwrap().id().to_string();
        let ok = Command::new("kill").args([&format!("-{name}"), pid.as_str()]).status().unwrap().success();
        assert!(ok, "kill -{name} {pid}");
    }

    /// Waits until the daemon's log contains `needle` (a state, not a guessed delay).
    fn wait_log(&self, needle: &str, timeout: Duration) {
        let start = Instant::now();
        while !std::fs::read_to_string(&self.log).unwrap_or_default().contains(needle) {
            assert!(start.elapsed() < timeout, "no `{needle}` in the daemon's log within {timeout:?}");
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    fn wait(&mut self, timeout: Duration) -> ExitStatus {
        let start = Instant::now();
        let child = self.child.as_mut().unwrap();
        loop {
            if let Some(status) = child.try_wait().unwrap() {
                self.child = None;
                return status;
            }
            assert!(start.elapsed() < timeout, "gyrocompd did not exit within {timeout:?}");
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

impl Drop for Daemon {
    fn drop(&mut self) {
        if let Some(mut child) = self.child.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
        if std::thread::panicking() {
            eprintln!("--- gyrocompd log ---\n{}", std::fs::read_to_string(&self.log).unwrap_or_default());
        }
        let _ = self.domain.remove_private_files();
    }
}

/// A quick deterministic retrain schedule and a cheap CPSO-LSSVM, in the test's private domain.
fn config_text(domain: &IpcDomain, motion_rate_dps: f64, wait: &str) -> String {
    let root = domain.root_path();
    format!(
        "[denoise]\nwindow = 64\n\
         [drift]\nestimator = \"cpso-lssvm\"\n\
         [motion]\ndetector = \"threshold\"\nrate_dps = {motion_rate_dps:?}\n\
         [input]\nrate_hz = 10.0\n\
         [retrain]\nmode = \"deterministic\"\nwindow = 150\nmin_samples = 100\nevery_samples = {EVERY}\n\
         apply_delay_samples = {DELAY}\nexact_max_rows = 200\nprototypes = 20\n\
         cpso_candidates = 2\ncpso_particles = 1\ncpso_iterations = 1\n\
         [ipc]\nwait = \"{wait}\"\ndomain_prefix = \"{}\"\ndomain_root = \"{}\"\n\
         [log]\nlevel = \"info\"\n",
        domain.prefix(),
        root.trim_end_matches('/'),
    )
}

/// `n` simulated static samples of the paper preset (10 Hz), seq = index.
fn stream(n: usize) -> Vec<RawSample> {
    let mut sim = Preset::Paper.config();
    sim.duration_s = n as f64 / sim.rate_hz;
    let out = Generator::generate(&sim, 7).unwrap();
    (0..n)
        .map(|k| {
            let rate = [out.axes[0].raw[k], out.axes[1].raw[k], out.axes[2].raw[k]];
            RawSample { temp_c: out.temp_c[k], ..RawSample::new(k as u64, k as u64 * 100_000_000, rate) }
        })
        .collect()
}

/// Sends `samples` and returns the answers, checking one per sample, same `seq`, in order.
fn exchange(raw: &RawPublisher, comp: &CompSubscriber, samples: &[RawSample]) -> Vec<CompSample> {
    for s in samples {
        raw.send(*s).expect("send raw sample");
    }
    samples
        .iter()
        .map(|s| {
            let answer = comp.recv_timeout(Duration::from_secs(10)).unwrap().expect("an answer per sample");
            assert_eq!((answer.seq, answer.t_ns), (s.seq, s.t_ns));
            assert!(answer.rate_dps.iter().chain(&answer.drift_dps).all(|v| v.is_finite()));
            answer
        })
        .collect()
}

/// A lossless client node in the daemon's domain.
fn client(domain: &IpcDomain) -> IpcNode {
    let delivery = Delivery::Lossless { give_up_after: Some(Duration::from_secs(5)) };
    IpcNode::new(domain, "test_ins", IpcSettings { delivery, ..IpcSettings::default() }).unwrap()
}

fn reports(status: &StatusSubscriber) -> Vec<StatusSample> {
    let mut out = Vec::new();
    while let Some(s) = status.try_recv().unwrap() {
        out.push(s);
    }
    out
}

fn events(reports: &[StatusSample]) -> Vec<StatusEvent> {
    reports.iter().map(|s| StatusEvent::from_u32(s.event).expect("known status event")).collect()
}

fn write_config(path: &Path, text: &str) {
    std::fs::write(path, text).unwrap();
}

#[test]
fn daemon_answers_every_sample_retrains_reloads_and_stops_cleanly() {
    let mut daemon = Daemon::start("event");
    let node = client(&daemon.domain);
    let raw = node.raw_publisher().unwrap();
    let comp = node.comp_subscriber().unwrap();
    let status = node.status_subscriber().unwrap();

    let samples = stream(900);
    let first = prime(&raw, &comp, samples[0], Duration::from_secs(20)).expect("daemon answers the first sample");
    assert_eq!((first.seq, first.model_version), (0, 0));

    // Retraining: requests after 200, 400, 600 samples, each installed 20 samples later.
    let answers = exchange(&raw, &comp, &samples[1..700]);
    for a in &answers {
        // Installs happen right before seq k·EVERY + DELAY (seq 0 was the first sample).
        assert_eq!(a.model_version, a.seq.saturating_sub(DELAY) / EVERY, "seq {}", a.seq);
        assert_eq!(a.status & STATUS_MOVING, 0, "seq {}", a.seq);
    }
    assert_eq!(answers.last().unwrap().model_version, 3);

    // SIGHUP with a motion threshold below every rate: the next samples are all moving. The
    // detector also changes, to `none`, which a reload cannot apply: it is reported, and the
    // threshold gate goes on (with `none` nothing would be moving).
    let reloaded =
        config_text(&daemon.domain, 1e-9, "event").replace("detector = \"threshold\"", "detector = \"none\"");
    write_config(&daemon.config, &reloaded);
    daemon.signal("HUP");
    daemon.wait_log("SIGHUP: configuration reloaded", Duration::from_secs(20));
    daemon.wait_log("SIGHUP: motion.detector changed and needs a restart", Duration::from_secs(1));
    let moving = exchange(&raw, &comp, &samples[700..900]);
    assert!(moving.iter().all(|a| a.status & STATUS_MOVING != 0));

    let before_stop = reports(&status);
    let seen = events(&before_stop);
    assert!(seen.contains(&StatusEvent::ModelSwapped), "{seen:?}");
    let swap = before_stop.iter().rfind(|s| s.event == StatusEvent::ModelSwapped as u32).unwrap();
    assert!(
        swap.model_version >= 1 && swap.retrains_done == swap.model_version && swap.last_retrain_ns > 0,
        "{swap:?}"
    );

    daemon.signal("TERM");
    let exit = daemon.wait(Duration::from_secs(10));
    assert!(exit.success(), "gyrocompd exited with {exit}");
    let last = reports(&status);
    let stopping = last.last().expect("a final status");
    assert_eq!(StatusEvent::from_u32(stopping.event), Some(StatusEvent::Stopping), "{last:?}");
    assert_eq!((stopping.samples_in, stopping.samples_out, stopping.last_seq), (900, 900, 899));
    // Moving samples enter no buffer, but the static history is still there: the request after
    // 800 samples is served too.
    assert_eq!((stopping.model_version, stopping.send_failures), (4, 0));
    // The detector's counters travel on the status service (StatusSample.v2): the threshold gate
    // commits at once (700 static samples), and its one onset is the reload's motion.
    assert_eq!((stopping.committed, stopping.discarded, stopping.detector_onsets), (700, 0, 1), "{stopping:?}");
    assert_eq!(stopping.detector_alarms, 200, "{stopping:?}");
}

#[test]
fn spinning_daemon_answers_what_it_received_before_sigterm() {
    let mut daemon = Daemon::start("spin");
    let node = client(&daemon.domain);
    let raw = node.raw_publisher().unwrap();
    let comp = node.comp_subscriber().unwrap();
    let samples = stream(501);
    prime(&raw, &comp, samples[0], Duration::from_secs(20)).expect("daemon answers the first sample");
    // Lossless sends return once the samples sit in the daemon's buffer; SIGTERM right after
    // must still get every one of them answered.
    for s in &samples[1..] {
        raw.send(*s).unwrap();
    }
    daemon.signal("TERM");
    for s in &samples[1..] {
        let answer = comp.recv_timeout(Duration::from_secs(10)).unwrap().expect("an answer per sample");
        assert_eq!(answer.seq, s.seq);
    }
    let exit = daemon.wait(Duration::from_secs(10));
    assert!(exit.success(), "gyrocompd exited with {exit}");
}

#[test]
fn bad_config_is_refused_at_start_with_the_key_named() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("bad.toml");
    write_config(&config, "[ipc]\nwait = \"sometimes\"\n");
    let out = Command::new(env!("CARGO_BIN_EXE_gyrocompd")).arg("--config").arg(&config).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("ipc.wait"), "{stderr}");
}

#[test]
fn python_client_through_the_daemon() {
    if !python::iceoryx2_wheel_or_skip("python_client_through_the_daemon") {
        return;
    }
    let mut daemon = Daemon::start("event");
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/python/ins_publisher.py");
    let out = Command::new("python3")
        .args([script, "--count", "500", "--rate-hz", "0", "--quiet", "--timeout-s", "20"])
        .args(["--domain-prefix", &daemon.domain.prefix(), "--domain-root", &daemon.domain.root_path()])
        .output()
        .expect("run python3");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "python client failed\nstdout:\n{stdout}\nstderr:\n{stderr}");
    assert!(stdout.contains("received 500/500 compensated samples, in order: True"), "{stdout}");
    // The drift standard deviation (CompSample.v2) arrives: finite once the estimate exists.
    let finite: usize = stdout
        .lines()
        .find_map(|l| l.strip_prefix("drift std: ")?.split('/').next()?.parse().ok())
        .unwrap_or_else(|| panic!("no drift std line in {stdout}"));
    assert!(finite > 1400 && stdout.contains("none NaN or negative: True"), "{stdout}");
    daemon.signal("TERM");
    let exit = daemon.wait(Duration::from_secs(10));
    assert!(exit.success(), "gyrocompd exited with {exit}");
}
