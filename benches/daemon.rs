//! Criterion benchmark of the round trip through the daemon loop (issue 5), to compare with the
//! bare iceoryx2 round trip of `benches/ipc.rs`.
//!
//! - `daemon/roundtrip_event`, `daemon/roundtrip_spin`: send one `RawSample`, wait for its
//!   `CompSample`; the answer comes from `gyrocomp::daemon::Daemon::run` (in this process, on its
//!   own thread: pipeline, status reports, retrainer) instead of the echo.
//!
//! The daemon retrains live every 2 s (fixed-size CPSO-LSSVM, window 1000) and the warm-up lasts
//! until a model is installed, so the measured samples go through the model (denoiser, iterated
//! LS-SVM forecast); the background fits share the machine's cores with the measurement, as in
//! production (where they come every 60 s). Each runs in a private iceoryx2 domain.
//! Run: `cargo bench --bench daemon`.

use std::thread;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use gyrocomp::config::Config;
use gyrocomp::daemon::{Daemon, Signals};
use gyrocomp::ipc::{IpcDomain, IpcNode, IpcSettings, RawSample, WaitMode, prime};

/// A small deterministic noise around a constant bias (a static gyro).
fn sample(seq: u64) -> RawSample {
    let h = seq.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11;
    let u = h as f64 / (1u64 << 53) as f64 - 0.5;
    RawSample::new(seq, seq * 1_000_000, [0.02 + 0.01 * u, -0.01 - 0.01 * u, 0.005 * u])
}

fn roundtrip(c: &mut Criterion, mode: WaitMode, label: &str) {
    let domain = IpcDomain::unique("dbench").expect("private domain");
    let mut config = Config::paper();
    config.input.rate_hz = gyrocomp::config::RateSetting::Hz(1000.0);
    // Live retraining as in production (never waits), but every 2 s instead of 60 s so that the
    // warm-up gets a model: fixed-size LS-SVM (100 prototypes) on a 1000-sample window.
    (config.retrain.schedule.mode, config.retrain.schedule.interval_s) = (gyrocomp::stream::RetrainMode::Live, 2.0);
    (config.retrain.schedule.window, config.retrain.schedule.min_samples, config.retrain.fit.exact_max_rows) =
        (1000, 500, 100);
    config.ipc.wait = mode;
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
        let warm_up = std::time::Instant::now();
        while once(seq).model_version == 0 {
            assert!(warm_up.elapsed() < Duration::from_secs(120), "no model installed during the warm-up");
            seq += 1;
        }
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
