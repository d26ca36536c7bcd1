//! Criterion benchmark of the bare iceoryx2 round trip (issue 5): the baseline the daemon's
//! latency is compared against.
//!
//! - `ipc/roundtrip_event`: send one `RawSample` on `gyrocomp/raw`, an echo thread answers with one
//!   `CompSample` on `gyrocomp/compensated`; both sides sleep on the event services and notify.
//! - `ipc/roundtrip_spin`: the same with both sides polling and no notifications.
//!
//! Each runs in a private iceoryx2 domain. Run: `cargo bench --bench ipc`. On a machine with two
//! shared cores, the spinning pair competes for both, so read the figures as orders of magnitude.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use gyrocomp::ipc::{IpcDomain, IpcNode, IpcSettings, RawSample, WaitMode, prime, run_echo};

fn roundtrip(c: &mut Criterion, mode: WaitMode, label: &str) {
    let domain = IpcDomain::unique("bench").expect("private domain");
    let settings = IpcSettings { wait_mode: mode, notify: mode == WaitMode::Event, ..IpcSettings::default() };
    let stop = Arc::new(AtomicBool::new(false));
    let ready = Arc::new(AtomicBool::new(false));
    let echo = {
        let (d, s, st, rd) = (domain.clone(), settings.clone(), stop.clone(), ready.clone());
        thread::spawn(move || run_echo(&d, &s, &st, &rd, None).expect("echo"))
    };
    while !ready.load(Ordering::Acquire) {
        thread::sleep(Duration::from_millis(1));
    }
    {
        let node = IpcNode::new(&domain, "bench_client", settings).expect("node");
        let comp = node.comp_subscriber().expect("comp subscriber");
        let raw = node.raw_publisher().expect("raw publisher");
        prime(&raw, &comp, RawSample::new(0, 0, [0.0; 3]), Duration::from_secs(5)).expect("echo answers");
        let mut seq = 1u64;
        let mut group = c.benchmark_group("ipc");
        group.sample_size(30).measurement_time(Duration::from_secs(3));
        group.bench_function(label, |b| {
            b.iter(|| {
                raw.send(RawSample::new(seq, seq, [0.1, 0.2, 0.3])).expect("send");
                let answer = comp.recv_timeout(Duration::from_secs(5)).expect("receive").expect("answer");
                assert_eq!(answer.seq, seq);
                seq += 1;
            })
        });
        group.finish();
    }
    stop.store(true, Ordering::Release);
    echo.join().expect("echo thread");
    let _ = domain.remove_private_files();
}

fn benches(c: &mut Criterion) {
    roundtrip(c, WaitMode::Event, "roundtrip_event");
    roundtrip(c, WaitMode::Spin, "roundtrip_spin");
}

criterion_group!(ipc, benches);
criterion_main!(ipc);
