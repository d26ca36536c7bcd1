//! Criterion benchmark of the round trip through the daemon loop (issue 5), to compare with the
//! bare iceoryx2 round trip of `benches/ipc.rs`.
//!
//! - `daemon/roundtrip_event`, `daemon/roundtrip_spin`: send one `RawSample`, wait for its
//!   `CompSample`; the answer comes from `gyrocomp::daemon::Daemon::run` (in this process, on its
//!   own thread: pipeline, status reports, retrainer) instead of the echo.
//!
//! The daemon runs deterministic retraining with a cheap CPSO-LSSVM and a warm-up of 1500
//! samples, so the measured samples go through an installed model (denoiser, iterated LS-SVM
//! forecast). Each runs in a private iceoryx2 domain. Run: `cargo bench --bench daemon`.

use std::thread;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use gyrocomp::config::Config;
use gyrocomp::daemon::{Daemon, Signals};
use gyrocomp::stream::ipc::{IpcDomain, IpcNode, IpcSettings, RawSample, WaitMode, prime};

/// A small deterministic noise around a constant bias (a static gyro).
fn sample(seq: u64) -> RawSample {
    let h = seq.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11;
    let u = h as f64 / (1u64 << 53) as f64 - 0.5;
    RawSample::new(seq, seq * 1_000_000, [0.02 + 0.01 * u, -0.01 - 0.01 * u, 0.005 * u])
}

fn roundtrip(c: &mut Criterion, mode: WaitMode, label: &str) {
    let domain = IpcDomain::unique("dbench").expect("private domain");
    let mut config = Config::default();
    config.input.rate_hz = 1000.0;
    config.retrain.mode = "deterministic".into();
    (config.retrain.window, config.retrain.min_samples) = (600, 300);
    (config.retrain.every_samples, config.retrain.apply_delay_samples) = (1000, 10);
    (config.retrain.cpso_candidates, config.retrain.cpso_particles, config.retrain.cpso_iterations) = (2, 1, 1);
    config.ipc.wait = if mode == WaitMode::Spin { "spin" } else { "event" }.into();
    config.ipc.domain_prefix = domain.prefix();
    config.ipc.domain_root = domain.root_path();
    config.log.level = "warn".into();
    let signals = Signals::new();
    let daemon = {
        let (config, signals) = (config.clone(), signals.clone());
        thread::spawn(move || Daemon::new(config, None, signals).run().expect("daemon"))
    };
    {
        let settings = IpcSettings { wait_mode: mode, ..IpcSettings::default() };
        let node = IpcNode::new(&domain, "bench_client", settings).expect("node");
        let comp = node.comp_subscriber().expect("comp subscriber");
        let raw = node.raw_publisher().expect("raw publisher");
        prime(&raw, &comp, sample(0), Duration::from_secs(10)).expect("daemon answers");
        let mut seq = 1u64;
        let once = |seq: u64| {
            raw.send(sample(seq)).expect("send");
            let answer = comp.recv_timeout(Duration::from_secs(10)).expect("receive").expect("answer");
            assert_eq!(answer.seq, seq);
            answer
        };
        while seq < 1500 {
            once(seq);
            seq += 1;
        }
        assert!(once(seq).model_version > 0, "no model installed during the warm-up");
        seq += 1;
        let mut group = c.benchmark_group("daemon");
        group.sample_size(30).measurement_time(Duration::from_secs(3));
        group.bench_function(label, |b| {
            b.iter(|| {
                once(seq);
                seq += 1;
            })
        });
        group.finish();
    }
    signals.request_stop();
    daemon.join().expect("daemon thread");
    let _ = domain.remove_private_files();
}

fn benches(c: &mut Criterion) {
    roundtrip(c, WaitMode::Event, "roundtrip_event");
    roundtrip(c, WaitMode::Spin, "roundtrip_spin");
}

criterion_group!(daemon, benches);
criterion_main!(daemon);
