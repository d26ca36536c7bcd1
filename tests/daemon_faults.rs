//! Fault tests of `gyrocompd` (issue 7, item 4), each in its own private iceoryx2 domain, every
//! process killed and the domain removed on drop even when an assertion fails:
//!
//! - (a) SIGKILL during a retrain after a snapshot exists; the restarted daemon compensates
//!   with the snapshot's model from its first answer, and `model_version` continues.
//! - (b) the publisher (a separate process) is killed and another one started: the daemon keeps
//!   serving without a restart.
//! - (c) the daemon is killed and restarted while the publisher runs. "The publisher keeps going"
//!   means: it stays alive, no send blocks longer than its give-up limit (200 ms), it keeps
//!   sending at its rate through the outage (samples sent while no daemon runs are lost, not
//!   answered), and once the daemon is back its new samples are answered again without the
//!   publisher reopening anything. The restarted daemon finds the killed one's node dead and
//!   cleans its stale resources (iceoryx2's dead-node cleanup) before it opens its ports.

#[path = "common/daemon_proc.rs"]
mod daemon_proc;
#[path = "common/ins_child.rs"]
mod ins_child;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use daemon_proc::{DaemonProc, prime_until, sample};
use gyrocomp::daemon::state::SNAPSHOT_FILE;
use gyrocomp::ipc::{CompSubscriber, Delivery, IpcDomain, IpcNode, IpcSettings, RawPublisher, STATUS_NO_MODEL};
use gyrocomp::stream::snapshot::Snapshot;
use ins_child::ChildProc;

/// Deterministic retrain schedule of these tests.
const EVERY: u64 = 300;
const DELAY: u64 = 30;

/// Not a test: the entry point of the child processes (see `tests/common/ins_child.rs`).
#[test]
#[ignore = "entry point of the child processes started by the other tests"]
fn ins_child_entry() {
    ins_child::entry();
}

/// A private domain, a state directory and the daemon's config file; removed on drop.
struct Setup {
    domain: IpcDomain,
    config: PathBuf,
    state: PathBuf,
    dir: tempfile::TempDir,
}

impl Setup {
    /// `retrain_heavy`: a CPSO search long enough (hundreds of ms) to kill the daemon inside it.
    fn new(tag: &str, retrain_heavy: bool) -> Self {
        let dir = tempfile::tempdir().expect("temp dir");
        let domain = IpcDomain::unique(tag).expect("private domain");
        let state = dir.path().join("state");
        let config = dir.path().join("gyrocompd.toml");
        let (window, candidates, particles, iterations) =
            if retrain_heavy { (250, 24, 12, 12) } else { (250, 2, 1, 1) };
        let text = format!(
            "[denoise]\nwindow = 64\n\
             [drift]\nestimator = \"cpso-lssvm\"\n[motion]\ndetector = \"threshold\"\n\
             [input]\nrate_hz = 100.0\ngap_factor = 1000.0\n\
             [retrain]\nmode = \"deterministic\"\nwindow = {window}\nmin_samples = 150\nevery_samples = {EVERY}\n\
             apply_delay_samples = {DELAY}\nexact_max_rows = 300\nprototypes = 20\n\
             cpso_candidates = {candidates}\ncpso_particles = {particles}\ncpso_iterations = {iterations}\n\
             [ipc]\ndomain_prefix = \"{}\"\ndomain_root = \"{}\"\n\
             [state]\ndir = \"{}\"\n\
             [log]\nlevel = \"info,gyrocomp=debug\"\n",
            domain.prefix(),
            domain.root_path().trim_end_matches('/'),
            state.display(),
        );
        std::fs::write(&config, text).unwrap();
        Self { domain, config, state, dir }
    }

    /// The default drift path (Kalman tracker, statistical detector) with a snapshot a second.
    fn default_path(tag: &str) -> Self {
        let setup = Self::new(tag, false);
        let text = std::fs::read_to_string(&setup.config).unwrap();
        let text = text
            .replace("[drift]\nestimator = \"cpso-lssvm\"\n[motion]\ndetector = \"threshold\"\n", "")
            .replace("[state]\n", "[state]\nevery_s = 1.0\n");
        assert!(!text.contains("cpso-lssvm") && text.contains("every_s"), "{text}");
        std::fs::write(&setup.config, text).unwrap();
        setup
    }

    fn snapshot(&self) -> Option<Snapshot> {
        let bytes = std::fs::read(self.state.join(SNAPSHOT_FILE)).ok()?;
        Some(Snapshot::decode(&bytes).expect("a written snapshot decodes"))
    }
}

impl Drop for Setup {
    fn drop(&mut self) {
        let _ = self.domain.remove_private_files();
    }
}

/// Starts `gyrocompd` on the setup's configuration; its log is `gyrocompd-<n>.log`.
fn start_daemon(setup: &Setup, n: usize) -> DaemonProc {
    DaemonProc::start(&setup.config, setup.dir.path().join(format!("gyrocompd-{n}.log")))
}

fn client(domain: &IpcDomain) -> IpcNode {
    let delivery = Delivery::Lossless { give_up_after: Some(Duration::from_secs(5)) };
    IpcNode::new(domain, "fault_test", IpcSettings { delivery, ..IpcSettings::default() }).unwrap()
}

/// Sends `seqs` and checks one answer per sample, in order; returns the last answer's
/// (model_version, status).
fn exchange(raw: &RawPublisher, comp: &CompSubscriber, seqs: std::ops::Range<u64>) -> (u64, u32) {
    let mut last = (0, 0);
    for seq in seqs.clone() {
        raw.send(sample(seq)).expect("send");
    }
    for seq in seqs {
        let a = comp.recv_timeout(Duration::from_secs(20)).unwrap().expect("an answer per sample");
        assert_eq!(a.seq, seq);
        last = (a.model_version, a.status);
    }
    last
}

fn count(text: &str, needle: &str) -> usize {
    text.matches(needle).count()
}

#[test]
fn sigkill_during_a_retrain_then_restart_resumes_from_the_snapshot() {
    let setup = Setup::new("faulta", true);
    let mut daemon = start_daemon(&setup, 1);
    let node = client(&setup.domain);
    let raw = node.raw_publisher().unwrap();
    let comp = node.comp_subscriber().unwrap();

    // First model: request after EVERY samples, installed DELAY samples later, then snapshot.
    let (_, mut seq) = prime_until(&raw, &comp, 0, Duration::from_secs(30));
    let (version, status) = exchange(&raw, &comp, seq..EVERY + DELAY + 10);
    seq = EVERY + DELAY + 10;
    assert_eq!((version, status & STATUS_NO_MODEL), (1, 0));
    daemon.wait_log("snapshot written", Duration::from_secs(20));
    let stored = setup.snapshot().expect("a snapshot after the first retrain");
    assert_eq!(stored.model_version(), 1);

    // The sample that completes 2·EVERY makes the second request; kill right after its answer,
    // while the heavy CPSO search runs.
    exchange(&raw, &comp, seq..2 * EVERY);
    daemon.kill9();
    let log = daemon.log_text();
    assert_eq!(count(&log, "retrain finished"), 1, "the second retrain must still have been running:\n{log}");
    assert_eq!(setup.snapshot().unwrap().model_version(), 1);

    // Restart: the very first answer already uses the snapshot's model.
    let restarted_at = Instant::now();
    let daemon = start_daemon(&setup, 2);
    let (first, seq) = prime_until(&raw, &comp, 2 * EVERY + 100, Duration::from_secs(30));
    let resume = restarted_at.elapsed();
    eprintln!("restart to first compensated answer: {:.0} ms", resume.as_secs_f64() * 1e3);
    assert_eq!(first.model_version, 1, "{first:?}");
    assert_eq!(first.status & STATUS_NO_MODEL, 0, "no warm-up after a snapshot: {first:?}");
    let log = daemon.wait_log("model snapshot loaded", Duration::from_secs(5));
    assert!(!log.contains("snapshot ignored"), "{log}");

    // The restarted daemon retrains on its own schedule (it counts its own samples, some of the
    // priming ones may have gone to the dead daemon); versions continue from the snapshot's.
    let (version, status) = exchange(&raw, &comp, seq..seq + EVERY + DELAY + 50);
    assert_eq!((version, status & STATUS_NO_MODEL), (2, 0));
    daemon.wait_log("snapshot written", Duration::from_secs(20));
    let start = Instant::now();
    while setup.snapshot().unwrap().model_version() < 2 {
        assert!(start.elapsed() < Duration::from_secs(10), "snapshot of version 2 not written");
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn the_default_kalman_daemon_writes_snapshots_and_a_restart_after_kill_9_uses_one() {
    let setup = Setup::default_path("faultk");
    let mut daemon = start_daemon(&setup, 1);
    let node = client(&setup.domain);
    let raw = node.raw_publisher().unwrap();
    let comp = node.comp_subscriber().unwrap();
    let (first, mut seq) = prime_until(&raw, &comp, 0, Duration::from_secs(30));
    // A cold start: nothing to subtract for the first sample.
    assert_eq!(first.drift_dps, [0.0; 3]);
    exchange(&raw, &comp, seq..seq + 400);
    seq += 400;
    // No model on this path, yet the periodic snapshot is written, with the pending samples.
    let start = Instant::now();
    let stored = loop {
        if let Some(s) = setup.snapshot().filter(|s| s.stream.index >= seq) {
            break s;
        }
        assert!(start.elapsed() < Duration::from_secs(20), "no snapshot of the Kalman path:\n{}", daemon.log_text());
        std::thread::sleep(Duration::from_millis(20));
    };
    assert_eq!(stored.model_version(), 0);
    assert!(stored.axes.iter().all(|a| a.model.is_none()));
    assert!(!daemon.log_text().contains("snapshot not written"));
    daemon.kill9();

    // The restarted daemon resumes from it: its first answer is what a pipeline restored from
    // the stored snapshot gives, not what a cold one gives.
    let daemon = start_daemon(&setup, 2);
    let (a, _) = prime_until(&raw, &comp, seq + 10, Duration::from_secs(30));
    daemon.wait_log("model snapshot loaded", Duration::from_secs(5));
    let config = gyrocomp::config::Config::from_toml(&std::fs::read_to_string(&setup.config).unwrap(), "test").unwrap();
    let mut p = gyrocomp::stream::Pipeline::new(config.pipeline().unwrap()).unwrap();
    stored.restore_into(&mut p).unwrap();
    let r = sample(a.seq);
    let input = gyrocomp::stream::InputSample {
        seq: r.seq,
        t_ns: r.t_ns,
        rate_dps: r.rate_dps,
        temp_c: r.temp_c,
        flags: r.flags,
    };
    let want = p.process(&input);
    // The restored state decides (here: the detector's verdict held from before the kill).
    let cold = gyrocomp::stream::Pipeline::new(config.pipeline().unwrap()).unwrap().process(&input);
    assert_ne!((cold.status, cold.drift_dps), (want.status, want.drift_dps), "{cold:?} {want:?}");
    if a.seq == seq + 10 {
        // The first priming sample reached it: exactly the restored pipeline's answer, flagged
        // as a gap (the samples the dead daemon never saw).
        assert_eq!((a.drift_dps, a.status), (want.drift_dps, want.status));
        assert!(a.status & gyrocomp::stream::STATUS_GAP != 0, "{a:?}");
    }
}

#[test]
fn corrupt_snapshot_is_reported_and_ignored() {
    let setup = Setup::new("faultc", false);
    std::fs::create_dir_all(&setup.state).unwrap();
    std::fs::write(setup.state.join(SNAPSHOT_FILE), b"GYROSNAP\x01\0\0\0garbage").unwrap();
    let daemon = start_daemon(&setup, 1);
    let node = client(&setup.domain);
    let raw = node.raw_publisher().unwrap();
    let comp = node.comp_subscriber().unwrap();
    let (first, _) = prime_until(&raw, &comp, 0, Duration::from_secs(30));
    assert_eq!(first.model_version, 0);
    assert!(first.status & STATUS_NO_MODEL != 0);
    let log = daemon.wait_log("snapshot ignored", Duration::from_secs(5));
    assert!(log.contains(SNAPSHOT_FILE) && log.contains("truncated"), "{log}");
}

#[test]
fn killed_publisher_is_replaced_while_the_daemon_keeps_serving() {
    let setup = Setup::new("faultb", false);
    let mut daemon = start_daemon(&setup, 1);
    let mut first = ChildProc::start("publisher", &setup.domain, &[], &[]);
    first.wait_for("progress", Duration::from_secs(30), |p| p.get("answered") >= 200);
    first.kill();

    let second = ChildProc::start(
        "publisher",
        &setup.domain,
        &[("GC_SEQ_START", "1000000".into()), ("GC_COUNT", "600".into())],
        &[],
    );
    let done = second.wait_for("done", Duration::from_secs(60), |_| true);
    assert_eq!(done.get("sent"), 600, "{}", done.line);
    assert_eq!(done.get("answered"), 600, "every sample of the new publisher answered: {}", done.line);
    assert_eq!(done.get("send_errors"), 0, "{}", done.line);
    assert!(daemon.alive(), "the daemon kept running");
    // The daemon retrained across both publishers (its schedule counts every sample it served).
    assert!(done.get("model_version") >= 1, "{}", done.line);
}

#[test]
fn daemon_restart_while_the_publisher_keeps_going_and_stale_nodes_are_cleaned() {
    let setup = Setup::new("faultd", false);
    let mut daemon = start_daemon(&setup, 1);
    let publisher = ChildProc::start("publisher", &setup.domain, &[], &[]);
    publisher.wait_for("progress", Duration::from_secs(30), |p| p.get("answered") >= 200);

    daemon.kill9();
    let killed_at = publisher.last("progress").unwrap();
    let census = IpcNode::dead_nodes(&setup.domain).unwrap();
    assert!(census.dead >= 1, "the killed daemon's node is detected as dead: {census:?}");

    // While no daemon runs the publisher keeps sending at its rate (its samples go unanswered).
    let sent_at_kill = killed_at.get("sent");
    let during = publisher.wait_for("progress", Duration::from_secs(30), |p| p.get("sent") >= sent_at_kill + 100);
    assert!(during.get("sent") >= killed_at.get("sent") + 100, "{} -> {}", killed_at.line, during.line);

    let mut daemon = start_daemon(&setup, 2);
    let log = daemon.wait_log("stale iceoryx2 nodes cleaned", Duration::from_secs(20));
    let line = log.lines().find(|l| l.contains("stale iceoryx2 nodes cleaned")).unwrap();
    assert!(line.contains("dead_after=0") && !line.contains("dead_before=0"), "{line}");
    assert_eq!(IpcNode::dead_nodes(&setup.domain).unwrap().dead, 0);

    // The publisher, never restarted, is answered again.
    let resumed_from = publisher.last("progress").unwrap().get("next_seq");
    let after =
        publisher.wait_for("progress", Duration::from_secs(30), |p| p.get("last_answer_seq") > resumed_from + 100);
    assert!(daemon.alive());
    let worst = after.get("max_send_us");
    eprintln!("publisher: longest send {worst} µs across the restart; {}", after.line);
    assert!(worst < 1_000_000, "a send blocked beyond its 200 ms give-up limit: {worst} µs");
}
