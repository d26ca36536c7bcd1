//! One daemon per service prefix, one INS client per daemon (issue 15, items 1 and 2), each test
//! in its own private iceoryx2 domain, every process killed and the domain removed on drop:
//!
//! - a second `gyrocompd` binary is refused with exit code 3 and a message naming the running
//!   one, by each check on its own: the state directory lock (same `[state] dir`, another
//!   service prefix), the compensated service's single publisher (same prefix, another state
//!   directory), and both; the client then gets exactly one answer per sample; after a SIGKILL
//!   of the running daemon a restart with the same configuration serves again;
//! - a second in-process daemon is refused (`DaemonError::AlreadyRunning`) by both checks, and
//!   starts once the first one has stopped;
//! - a second INS client cannot publish on `raw` (`IpcError::PublisherTaken` naming the first
//!   client's node and pid; the Python client exits with code 3), and can once the first one
//!   has gone. (A *killed* client replaced by a new one: `tests/daemon_faults.rs`.)

#[path = "common/daemon_proc.rs"]
mod daemon_proc;
#[path = "common/python.rs"]
mod python;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use daemon_proc::{DaemonProc, prime_until, round_trip};
use gyrocomp::config::Config;
use gyrocomp::daemon::instance_lock::LOCK_FILE;
use gyrocomp::daemon::{Daemon, DaemonError, Signals};
use gyrocomp::ipc::{Delivery, IpcDomain, IpcError, IpcNode, IpcSettings};

/// Exit code of a refused second instance (src/bin/gyrocompd.rs).
const ALREADY_RUNNING: i32 = 3;

/// A private domain and a scratch directory; the domain's files are removed on drop.
struct Setup {
    domain: IpcDomain,
    dir: tempfile::TempDir,
}

impl Setup {
    fn new(tag: &str) -> Self {
        Self { domain: IpcDomain::unique(tag).expect("private domain"), dir: tempfile::tempdir().expect("temp dir") }
    }

    /// The daemon's configuration for `service_prefix` and state directory `state` (under the
    /// scratch directory).
    fn config_text(&self, service_prefix: &str, state: &str) -> String {
        format!(
            "[input]\nrate_hz = 100.0\ngap_factor = 1000.0\n\
             [ipc]\nservice_prefix = \"{service_prefix}\"\ndomain_prefix = \"{}\"\ndomain_root = \"{}\"\n\
             [state]\ndir = \"{}\"\n\
             [log]\nlevel = \"info\"\n",
            self.domain.prefix(),
            self.domain.root_path().trim_end_matches('/'),
            self.state(state).display(),
        )
    }

    fn state(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    /// Writes the configuration to a file named `name`; returns its path.
    fn config_file(&self, name: &str, service_prefix: &str, state: &str) -> PathBuf {
        let path = self.dir.path().join(name);
        std::fs::write(&path, self.config_text(service_prefix, state)).unwrap();
        path
    }

    fn daemon(&self, config: &Path, n: usize) -> DaemonProc {
        DaemonProc::start(config, self.dir.path().join(format!("gyrocompd-{n}.log")))
    }

    fn config(&self, service_prefix: &str, state: &str) -> Config {
        Config::from_toml(&self.config_text(service_prefix, state), "test config").unwrap()
    }
}

impl Drop for Setup {
    fn drop(&mut self) {
        let _ = self.domain.remove_private_files();
    }
}

fn client(domain: &IpcDomain, name: &str, service_prefix: &str) -> IpcNode {
    let delivery = Delivery::Lossless { give_up_after: Some(Duration::from_secs(5)) };
    let names = gyrocomp::ipc::ServiceNames::with_prefix(service_prefix);
    IpcNode::new(domain, name, IpcSettings { delivery, names, ..IpcSettings::default() }).unwrap()
}

/// Runs a second daemon to its end; it must be refused: exit code 3 and, on stderr, the
/// refusal and each of `names` (the running one's pid, node, …). Returns the stderr.
fn refused(setup: &Setup, config: &Path, n: usize, names: &[&str]) -> String {
    let mut second = setup.daemon(config, n);
    let exit = second.wait_exit(Duration::from_secs(20));
    let log = second.log_text();
    assert_eq!(exit.code(), Some(ALREADY_RUNNING), "second gyrocompd: {exit}\n{log}");
    assert!(log.contains("gyrocompd: error: gyrocompd is already running for service prefix"), "{log}");
    for name in names {
        assert!(log.contains(name), "`{name}` not named in:\n{log}");
    }
    log
}

#[test]
fn second_gyrocompd_is_refused_and_a_killed_one_does_not_block_a_restart() {
    let setup = Setup::new("single");
    let config = setup.config_file("a.toml", "gyrocomp", "state");
    let mut first = setup.daemon(&config, 1);
    let node = client(&setup.domain, "single_ins", "gyrocomp");
    let raw = node.raw_publisher().unwrap();
    let comp = node.comp_subscriber().unwrap();
    let (_, mut seq) = prime_until(&raw, &comp, 0, Duration::from_secs(30));
    let pid = format!("pid {}", first.pid());

    // The same configuration: both checks apply; the lock is taken first.
    refused(&setup, &config, 2, &[&pid, "state directory lock", LOCK_FILE]);
    // Another state directory, same service prefix: iceoryx2's single compensated publisher,
    // with the running daemon's node named from the node listing.
    let other_state = setup.config_file("b.toml", "gyrocomp", "state-b");
    let holder = "iceoryx2 node `gyrocompd` (id ";
    refused(&setup, &other_state, 3, &["`gyrocomp/compensated` already has its publisher", holder, &pid]);
    // Another service prefix, same state directory: the lock alone.
    let other_prefix = setup.config_file("c.toml", "other", "state");
    refused(&setup, &other_prefix, 4, &[&pid, "state directory lock", "service prefix gyrocomp"]);

    // Exactly one answer per sample (two daemons would answer each sample twice), in order.
    for _ in 0..200 {
        round_trip(&raw, &comp, seq);
        seq += 1;
    }
    assert!(comp.try_recv().unwrap().is_none(), "an answer too many");

    // SIGKILL: the kernel drops the lock, the restarted daemon cleans the dead node's ports.
    first.kill9();
    let mut restarted = setup.daemon(&config, 5);
    let (_, mut seq) = prime_until(&raw, &comp, seq, Duration::from_secs(30));
    let log = restarted.wait_log("stale iceoryx2 nodes cleaned", Duration::from_secs(10));
    let line = log.lines().find(|l| l.contains("stale iceoryx2 nodes cleaned")).unwrap();
    assert!(!line.contains("dead_before=0") && line.contains("dead_after=0"), "{line}");
    let record = std::fs::read_to_string(setup.state("state").join(LOCK_FILE)).unwrap();
    assert_eq!(record, format!("pid {}, service prefix gyrocomp\n", restarted.pid()));
    for _ in 0..50 {
        round_trip(&raw, &comp, seq);
        seq += 1;
    }
    restarted.signal("TERM");
    let exit = restarted.wait_exit(Duration::from_secs(10));
    assert!(exit.success(), "{exit}");
}

/// Runs a daemon on a thread until `signals` asks it to stop.
fn spawn_daemon(
    config: Config,
    signals: &Signals,
) -> std::thread::JoinHandle<Result<gyrocomp::daemon::RunSummary, String>> {
    let signals = signals.clone();
    std::thread::spawn(move || Daemon::new(config, None, signals).run().map_err(|e| e.to_string()))
}

/// A second in-process daemon on the same setup: refused, with `names` in the message.
fn refused_in_process(config: Config, names: &[&str]) {
    match Daemon::new(config, None, Signals::new()).run() {
        Err(e @ DaemonError::AlreadyRunning { .. }) => {
            let text = e.to_string();
            for name in names {
                assert!(text.contains(name), "`{name}` not named in: {text}");
            }
        }
        other => panic!("second in-process daemon not refused: {other:?}"),
    }
}

#[test]
fn second_in_process_daemon_is_refused_until_the_first_stops() {
    let setup = Setup::new("single_inproc");
    let signals = Signals::new();
    let first = spawn_daemon(setup.config("gyrocomp", "state"), &signals);
    let node = client(&setup.domain, "inproc_ins", "gyrocomp");
    let raw = node.raw_publisher().unwrap();
    let comp = node.comp_subscriber().unwrap();
    let (_, mut seq) = prime_until(&raw, &comp, 0, Duration::from_secs(30));

    let me = format!("pid {}", std::process::id());
    refused_in_process(setup.config("gyrocomp", "state"), &[&me, "state directory lock"]);
    refused_in_process(setup.config("gyrocomp", "state-b"), &["`gyrocomp/compensated` already has its publisher", &me]);
    refused_in_process(setup.config("other", "state"), &[&me, "state directory lock"]);
    round_trip(&raw, &comp, seq);
    seq += 1;

    signals.request_stop();
    let summary = first.join().unwrap().expect("first daemon ran");
    assert!(summary.samples_in >= 2, "{summary:?}");

    // Stopped cleanly: lock released, publisher port gone; a new daemon serves.
    let again = Signals::new();
    let second = spawn_daemon(setup.config("gyrocomp", "state"), &again);
    prime_until(&raw, &comp, seq, Duration::from_secs(30));
    again.request_stop();
    second.join().unwrap().expect("second daemon ran after the first stopped");
}

#[test]
fn second_ins_client_is_refused_on_raw_until_the_first_goes() {
    let setup = Setup::new("single_raw");
    let config = setup.config_file("a.toml", "gyrocomp", "state");
    let mut daemon = setup.daemon(&config, 1);
    let first = client(&setup.domain, "first_ins", "gyrocomp");
    let raw = first.raw_publisher().unwrap();
    let comp = first.comp_subscriber().unwrap();
    let (_, seq) = prime_until(&raw, &comp, 0, Duration::from_secs(30));

    let second = client(&setup.domain, "second_ins", "gyrocomp");
    let err = second.raw_publisher().err().expect("a second raw publisher must be refused");
    let text = err.to_string();
    assert!(matches!(err, IpcError::PublisherTaken { .. }), "{text}");
    let me = format!("pid {}", std::process::id());
    assert!(text.contains("`gyrocomp/raw` already has its publisher") && text.contains("`first_ins`"), "{text}");
    assert!(text.contains(&me), "{text}");
    // Subscribing is not publishing: a second client may still read the answers.
    let watcher = second.comp_subscriber().expect("a second compensated subscriber");

    if python::iceoryx2_wheel_or_skip("second_ins_client_is_refused_on_raw_until_the_first_goes") {
        let script = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/python/ins_publisher.py");
        let out = Command::new("python3")
            .args([script, "--count", "10", "--rate-hz", "0", "--quiet", "--timeout-s", "5"])
            .args(["--domain-prefix", &setup.domain.prefix(), "--domain-root", &setup.domain.root_path()])
            .output()
            .expect("run python3");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(3), "python client: {}\n{stderr}", out.status);
        assert!(stderr.contains("`gyrocomp/raw` already has its publisher"), "{stderr}");
    }

    // The first client's samples are still answered, to it and to the watcher, once each.
    let answer = round_trip(&raw, &comp, seq);
    let watched = watcher.recv_timeout(Duration::from_secs(10)).unwrap().expect("the watcher sees the answer");
    assert_eq!(watched.seq, answer.seq);

    // Once the first client's publisher is gone, the second one may publish.
    drop(raw);
    let raw2 = second.raw_publisher().expect("the raw publisher is free again");
    let comp2 = second.comp_subscriber().unwrap();
    prime_until(&raw2, &comp2, 1_000_000, Duration::from_secs(30));
    daemon.signal("TERM");
    assert!(daemon.wait_exit(Duration::from_secs(10)).success());
}
