//! The iceoryx2 layer: wire layout, round trips, backpressure, domain isolation, the Python client.
//! Every test runs in its own private iceoryx2 domain (unique prefix and root path) and removes it.

#[path = "common/python.rs"]
mod python;

use std::mem::offset_of;
use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Barrier};
use std::thread;
use std::time::{Duration, Instant};

use gyrocomp::ipc::{
    CompSample, Delivery, IpcDomain, IpcNode, IpcSettings, RawSample, STATUS_NO_MODEL, StatusEvent, StatusSample,
    WaitMode, prime, run_echo,
};
use iceoryx2::prelude::ZeroCopySend;

/// A private domain, removed (root directory, shared memory) when dropped.
struct Domain(IpcDomain);

impl Domain {
    fn new(tag: &str) -> Self {
        Self(IpcDomain::unique(tag).expect("private domain"))
    }
}

impl Drop for Domain {
    fn drop(&mut self) {
        let _ = self.0.remove_private_files();
    }
}

/// Shared-memory objects of `domain` still in /dev/shm, apart from iceoryx2's per-process
/// management object (kept until the process ends).
fn shm_leftovers(domain: &IpcDomain) -> Vec<String> {
    let prefix = domain.prefix();
    std::fs::read_dir("/dev/shm")
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.starts_with(&prefix) && !n.ends_with(".global_mgmt"))
                .collect()
        })
        .unwrap_or_default()
}

/// A raw sample with a temperature (NaN would make `==` fail).
/// Publisher side of a start-up handshake: returns once the subscriber (on another thread) has
/// attached to this publisher's connection (see `gyrocomp::ipc::client`).
fn publisher_attached(publisher: &gyrocomp::ipc::RawPublisher, barrier: &Barrier) {
    assert!(publisher.wait_for_subscriber(Duration::from_secs(5)));
    publisher.update_connections().unwrap();
    barrier.wait();
    barrier.wait();
}

/// Subscriber side of the handshake: attaches (looking for samples does it) between the two waits.
fn subscriber_attached(subscriber: &gyrocomp::ipc::RawSubscriber, barrier: &Barrier) {
    barrier.wait();
    assert!(!subscriber.has_samples().unwrap());
    barrier.wait();
}

fn raw(seq: u64) -> RawSample {
    RawSample { temp_c: 25.0, ..RawSample::new(seq, seq * 1_000_000, [0.01 * seq as f64, -1.0, 2.5]) }
}

/// Runs the echo on its own thread until stopped; waits until its ports exist.
struct Echo {
    stop: Arc<AtomicBool>,
    handle: Option<thread::JoinHandle<u64>>,
}

impl Echo {
    fn start(domain: &IpcDomain, settings: &IpcSettings) -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let ready = Arc::new(AtomicBool::new(false));
        let (d, s, st, rd) = (domain.clone(), settings.clone(), stop.clone(), ready.clone());
        let handle = thread::spawn(move || run_echo(&d, &s, &st, &rd, None).expect("echo"));
        let start = Instant::now();
        while !ready.load(Ordering::Acquire) {
            assert!(start.elapsed() < Duration::from_secs(10), "echo did not start");
            thread::sleep(Duration::from_millis(1));
        }
        Self { stop, handle: Some(handle) }
    }

    fn stop(mut self) -> u64 {
        self.stop.store(true, Ordering::Release);
        self.handle.take().unwrap().join().unwrap()
    }
}

#[test]
fn wire_layout_matches_design() {
    assert_eq!(size_of::<RawSample>(), 56);
    assert_eq!(
        [
            offset_of!(RawSample, seq),
            offset_of!(RawSample, t_ns),
            offset_of!(RawSample, rate_dps),
            offset_of!(RawSample, temp_c),
            offset_of!(RawSample, flags),
            offset_of!(RawSample, _pad)
        ],
        [0, 8, 16, 40, 48, 52]
    );
    assert_eq!(size_of::<CompSample>(), 104);
    assert_eq!(
        [
            offset_of!(CompSample, seq),
            offset_of!(CompSample, t_ns),
            offset_of!(CompSample, rate_dps),
            offset_of!(CompSample, drift_dps),
            offset_of!(CompSample, model_version),
            offset_of!(CompSample, status),
            offset_of!(CompSample, _pad),
            offset_of!(CompSample, drift_std_dps)
        ],
        [0, 8, 16, 40, 64, 72, 76, 80]
    );
    assert_eq!(size_of::<StatusSample>(), 224);
    // SAFETY: type_name only returns a string constant.
    unsafe {
        assert_eq!(<RawSample as ZeroCopySend>::type_name(), "gyrocomp::RawSample");
        assert_eq!(<CompSample as ZeroCopySend>::type_name(), "gyrocomp::CompSample.v2");
        assert_eq!(<StatusSample as ZeroCopySend>::type_name(), "gyrocomp::StatusSample.v3");
    }
    let r = RawSample::new(3, 0, [0.0; 3]);
    assert!(r.temperature().is_none() && !r.is_moving());
}

fn round_trip(mode: WaitMode, n: u64) {
    let domain = Domain::new("rt");
    let settings = IpcSettings { wait_mode: mode, notify: mode == WaitMode::Event, ..IpcSettings::default() };
    {
        let node = IpcNode::new(&domain.0, "test_sub", settings.clone()).unwrap();
        let sub = node.raw_subscriber().unwrap();
        let (d, s) = (domain.0.clone(), settings.clone());
        let barrier = Arc::new(Barrier::new(2));
        let b = barrier.clone();
        let producer = thread::spawn(move || {
            let node = IpcNode::new(&d, "test_pub", s).unwrap();
            let publisher = node.raw_publisher().unwrap();
            publisher_attached(&publisher, &b);
            for seq in 0..n {
                publisher.send(raw(seq)).unwrap();
            }
        });
        subscriber_attached(&sub, &barrier);
        let mut got = Vec::new();
        while (got.len() as u64) < n {
            match sub.recv_timeout(Duration::from_secs(5)).unwrap() {
                Some(s) => got.push(s),
                None => panic!("timed out after {} of {n} samples", got.len()),
            }
        }
        producer.join().unwrap();
        assert!(got.iter().enumerate().all(|(i, s)| *s == raw(i as u64)), "lost, reordered or altered samples");
        assert!(sub.try_recv().unwrap().is_none());
    }
    assert_eq!(shm_leftovers(&domain.0), Vec::<String>::new());
}

#[test]
fn round_trip_with_event_wakeups_loses_nothing() {
    round_trip(WaitMode::Event, 5000);
}

#[test]
fn round_trip_spinning_loses_nothing() {
    round_trip(WaitMode::Spin, 5000);
}

#[test]
fn lossless_publisher_waits_for_a_slow_subscriber() {
    let domain = Domain::new("bp");
    let settings = IpcSettings {
        subscriber_buffer: 16,
        delivery: Delivery::Lossless { give_up_after: Some(Duration::from_secs(10)) },
        ..IpcSettings::default()
    };
    let n = 2000u64;
    let node = IpcNode::new(&domain.0, "slow_sub", settings.clone()).unwrap();
    let sub = node.raw_subscriber().unwrap();
    let (d, s) = (domain.0.clone(), settings.clone());
    let barrier = Arc::new(Barrier::new(2));
    let b = barrier.clone();
    let producer = thread::spawn(move || {
        let node = IpcNode::new(&d, "fast_pub", s).unwrap();
        let publisher = node.raw_publisher().unwrap();
        publisher_attached(&publisher, &b);
        let start = Instant::now();
        for seq in 0..n {
            publisher.send(raw(seq)).unwrap();
        }
        start.elapsed()
    });
    subscriber_attached(&sub, &barrier);
    let mut got = Vec::new();
    while (got.len() as u64) < n {
        let s = sub.recv_timeout(Duration::from_secs(5)).unwrap().expect("sample");
        got.push(s.seq);
        if got.len() % 100 == 0 {
            thread::sleep(Duration::from_millis(2)); // slower than the publisher
        }
    }
    let publish_time = producer.join().unwrap();
    assert_eq!(got, (0..n).collect::<Vec<_>>());
    // 20 pauses of 2 ms: the publisher was held back by the full 16-sample buffer.
    assert!(publish_time >= Duration::from_millis(30), "publisher was not held back: {publish_time:?}");
}

#[test]
fn drop_newest_publisher_never_waits() {
    let domain = Domain::new("dn");
    let settings = IpcSettings { subscriber_buffer: 16, delivery: Delivery::DropNewest, ..IpcSettings::default() };
    let node = IpcNode::new(&domain.0, "idle_sub", settings.clone()).unwrap();
    let sub = node.raw_subscriber().unwrap();
    let publisher = node.raw_publisher().unwrap();
    for seq in 0..100 {
        publisher.send(raw(seq)).unwrap();
    }
    let mut got = Vec::new();
    sub.drain_into(&mut got, usize::MAX).unwrap();
    assert_eq!(got.iter().map(|s| s.seq).collect::<Vec<_>>(), (0..16).collect::<Vec<_>>());
}

#[test]
fn lossless_publisher_gives_up_on_a_stuck_subscriber() {
    let domain = Domain::new("gu");
    let limit = Duration::from_millis(50);
    let settings = IpcSettings {
        subscriber_buffer: 4,
        delivery: Delivery::Lossless { give_up_after: Some(limit) },
        ..IpcSettings::default()
    };
    let node = IpcNode::new(&domain.0, "stuck", settings).unwrap();
    let sub = node.raw_subscriber().unwrap();
    let publisher = node.raw_publisher().unwrap();
    for seq in 0..4 {
        publisher.send(raw(seq)).unwrap();
    }
    // A subscriber attaches to a connection when it first looks for samples; until then iceoryx2
    // treats it as disconnected and does not wait for it.
    assert!(sub.has_samples().unwrap());
    let start = Instant::now();
    let err = publisher.send(raw(4)).expect_err("a full, stuck subscriber must fail the send");
    assert!(start.elapsed() >= limit);
    assert!(err.to_string().contains("gyrocomp/raw"), "{err}");
}

#[test]
fn echo_answers_every_raw_sample_with_the_same_seq() {
    let domain = Domain::new("echo");
    let settings = IpcSettings::default();
    let echo = Echo::start(&domain.0, &settings);
    let n = 3000u64;
    {
        let node = IpcNode::new(&domain.0, "client", settings.clone()).unwrap();
        let comp = node.comp_subscriber().unwrap();
        let publisher = node.raw_publisher().unwrap();
        let first = prime(&publisher, &comp, raw(0), Duration::from_secs(5)).unwrap();
        let mut got = vec![first];
        for seq in 1..n {
            publisher.send(raw(seq)).unwrap();
            comp.drain_into(&mut got, usize::MAX).unwrap();
        }
        while (got.len() as u64) < n {
            got.push(comp.recv_timeout(Duration::from_secs(5)).unwrap().expect("answer"));
        }
        for (i, c) in got.iter().enumerate() {
            let r = raw(i as u64);
            assert_eq!((c.seq, c.t_ns, c.rate_dps, c.status), (r.seq, r.t_ns, r.rate_dps, STATUS_NO_MODEL));
        }
    }
    assert_eq!(echo.stop(), n);
}

#[test]
fn status_late_subscriber_gets_the_latest_report() {
    let domain = Domain::new("st");
    let node = IpcNode::new(&domain.0, "daemon", IpcSettings::default()).unwrap();
    let publisher = node.status_publisher().unwrap();
    for v in 1..=3 {
        let s = StatusSample { model_version: v, event: StatusEvent::ModelSwapped as u32, ..Default::default() };
        publisher.send(s).unwrap();
    }
    let sub = node.status_subscriber().unwrap();
    publisher.update_connections().unwrap();
    let s = sub.recv_timeout(Duration::from_secs(2)).unwrap().expect("history sample");
    assert_eq!(s.model_version, 3);
    assert_eq!(StatusEvent::from_u32(s.event), Some(StatusEvent::ModelSwapped));
}

#[test]
fn private_domains_do_not_see_each_other() {
    let (a, b) = (Domain::new("da"), Domain::new("db"));
    let node_a = IpcNode::new(&a.0, "a", IpcSettings::default()).unwrap();
    let node_b = IpcNode::new(&b.0, "b", IpcSettings::default()).unwrap();
    let sub_b = node_b.raw_subscriber().unwrap();
    let pub_a = node_a.raw_publisher().unwrap();
    assert_eq!(pub_a.subscriber_count(), 0, "domain a sees domain b's subscriber");
    pub_a.send(raw(0)).unwrap();
    assert!(sub_b.recv_timeout(Duration::from_millis(50)).unwrap().is_none());
}

#[test]
fn python_client_round_trip() {
    if !python::iceoryx2_wheel_or_skip("python_client_round_trip") {
        return;
    }
    let domain = Domain::new("py");
    let settings = IpcSettings::default();
    let echo = Echo::start(&domain.0, &settings);
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/python/ins_publisher.py");
    let out = Command::new("python3")
        .args([script, "--count", "500", "--rate-hz", "0", "--quiet", "--timeout-s", "20"])
        .args(["--domain-prefix", &domain.0.prefix(), "--domain-root", &domain.0.root_path()])
        .output()
        .expect("run python3");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "python client failed\nstdout:\n{stdout}\nstderr:\n{stderr}");
    assert!(stdout.contains("received 500/500 compensated samples, in order: True"), "{stdout}");
    assert_eq!(echo.stop(), 500);
}

#[test]
fn a_service_with_other_overflow_semantics_is_refused() {
    use iceoryx2::prelude::{NodeBuilder, ServiceName, SignalHandlingMode, ipc};
    let domain = Domain::new("ov");
    // A peer that created gyrocomp/raw with iceoryx2's default (overwriting) overflow.
    let node = NodeBuilder::new()
        .config(domain.0.config())
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()
        .unwrap();
    let _service = node
        .service_builder(&ServiceName::new("gyrocomp/raw").unwrap())
        .publish_subscribe::<RawSample>()
        .enable_safe_overflow(true)
        .subscriber_max_buffer_size(4096)
        .open_or_create()
        .unwrap();
    let ours = IpcNode::new(&domain.0, "ours", IpcSettings::default()).unwrap();
    let err = ours.raw_subscriber().err().expect("overwriting service must be refused");
    assert!(err.to_string().contains("IncompatibleOverflowBehavior"), "{err}");
    assert!(err.to_string().contains("gyrocomp/raw"), "{err}");
}
