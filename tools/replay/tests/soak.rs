//! Soak (issue 7): 1 kHz × 3 axes replayed at `--max` through a daemon retraining every 60 s of
//! data: no sample lost, and the daemon's resident memory does not grow after warm-up.
//!
//! The daemon runs in this test process (the `gyrocompd` code, `EmbeddedDaemon`, private domain)
//! and the `replay` binary is a separate process, so this process's RSS is the daemon's. RSS is
//! sampled every 50 ms; warm-up ends when the daemon's status service reports a given model
//! version: growth = the largest RSS after that minus the largest RSS up to that point (RSS also
//! falls when a fit frees its buffers, so a dip is no baseline: a leak shows as new peaks).
//!
//! Measured (release, the hour): RSS steps up while the allocator's arenas settle — 22.6 MB at
//! version 2, 26.1 at 3, 28.2 at 6, 29.0 at 14 — and then stays flat: +0.02 MB from version 14
//! to 59. So warm-up is the first quarter of the run (version 15) for the hour (bound 1 MB, the
//! issue's), and for the short CI run (versions 2 … 4, before the arenas have settled) the bound
//! is 8 MB: it still catches any per-sample leak of 32 bytes or more (300,000 samples).
//!
//! `short_soak`: 5 minutes of data (300,000 samples, five retrains) in every `cargo test`.
//! `hour_soak` (`#[ignore]`): the hour, 3,600,000 samples, 60 retrains —
//! `cargo test --release -p replay --test soak -- --ignored --nocapture`.

use std::path::Path;
use std::process::Command;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use gyrocomp::io::write_sim_csv;
use gyrocomp::config::Config;
use gyrocomp::sim::{Generator, Preset};
use gyrocomp::ipc::{IpcDomain, IpcNode};
use replay::EmbeddedDaemon;
use serde_json::Value;

const RATE_HZ: f64 = 1000.0;

/// Resident set size of this process, bytes (Linux `/proc/self/status`).
fn rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

struct SoakResult {
    summary: Value,
    rss_at_warm: u64,
    rss_max_after: u64,
    daemon_in: u64,
    daemon_out: u64,
    send_failures: u64,
}

fn soak(dir: &Path, seconds: f64, warm_version: u64) -> Option<SoakResult> {
    rss_bytes()?;
    let mut sim = Preset::Mpu6050.config();
    sim.rate_hz = RATE_HZ;
    sim.duration_s = seconds;
    let input = dir.join("soak.csv");
    write_sim_csv(&input, &Generator::generate(&sim, 11).unwrap()).unwrap();

    let mut config = Config::paper();
    config.input.rate_hz = gyrocomp::config::RateSetting::Hz(RATE_HZ);
    config.retrain.mode = "deterministic".into();
    config.retrain.every_samples = 60_000; // 60 s of data
    config.retrain.apply_delay_samples = 1000;
    let (daemon, private) = EmbeddedDaemon::start(&config).unwrap();
    let config_path = dir.join("soak.toml");
    std::fs::write(
        &config_path,
        format!(
            "[input]\nrate_hz = {RATE_HZ}\n[ipc]\ndomain_prefix = \"{}\"\ndomain_root = \"{}\"\n",
            private.ipc.domain_prefix, private.ipc.domain_root
        ),
    )
    .unwrap();

    let done = Arc::new(AtomicBool::new(false));
    let sampler = {
        let done = Arc::clone(&done);
        let private = private.clone();
        std::thread::spawn(move || {
            // iceoryx2 ports stay on the thread that made them.
            let domain = IpcDomain::private(&private.ipc.domain_prefix, Path::new(&private.ipc.domain_root)).unwrap();
            let node = IpcNode::new(&domain, "soak", private.ipc_settings().unwrap()).unwrap();
            let status = node.status_subscriber().unwrap();
            let mut samples = Vec::new();
            let mut warm_rss = None;
            let mut peak = 0;
            let mut by_version = Vec::new();
            while !done.load(Ordering::Relaxed) {
                let rss = rss_bytes().unwrap_or(0);
                peak = peak.max(rss);
                while let Ok(Some(s)) = status.try_recv() {
                    if s.model_version >= warm_version && warm_rss.is_none() {
                        warm_rss = Some(peak);
                    }
                    if by_version.last().is_none_or(|&(v, _)| v != s.model_version) {
                        by_version.push((s.model_version, rss));
                    }
                }
                if warm_rss.is_some() {
                    samples.push(rss);
                }
                std::thread::sleep(Duration::from_millis(50));
            }
            (warm_rss, samples, by_version)
        })
    };
    let out = Command::new(env!("CARGO_BIN_EXE_replay"))
        .arg(&input)
        .args(["--config", config_path.to_str().unwrap(), "--column", "gx_dps,gy_dps,gz_dps"])
        .args(["--daemon", "running", "--find-daemon-s", "5", "--max", "--json"])
        .output()
        .unwrap();
    done.store(true, Ordering::Relaxed);
    let (warm_rss, after, by_version) = sampler.join().unwrap();
    let trend: Vec<String> = by_version.iter().map(|(v, r)| format!("v{v}:{:.2}", *r as f64 / 1e6)).collect();
    eprintln!("soak: RSS (MB) when each model version was first reported: {}", trend.join(" "));
    let run = daemon.stop().unwrap();
    assert!(out.status.success(), "replay: {}", String::from_utf8_lossy(&out.stderr));
    let summary: Value = serde_json::from_slice(&out.stdout).unwrap();

    let rss_at_warm = warm_rss.expect("the daemon reported the warm-up model version during the run");
    Some(SoakResult {
        summary,
        rss_at_warm,
        rss_max_after: after.iter().copied().max().unwrap_or(rss_at_warm),
        daemon_in: run.samples_in,
        daemon_out: run.samples_out,
        send_failures: run.send_failures,
    })
}

fn check(r: &SoakResult, samples: u64, growth_limit: u64) {
    let s = &r.summary;
    let growth = r.rss_max_after.saturating_sub(r.rss_at_warm);
    eprintln!(
        "soak: {samples} samples, {:.1} s, {:.0} samples/s, model version {}; daemon RSS peak during warm-up {:.1} MB, growth {} kB",
        s["duration_s"].as_f64().unwrap(),
        s["samples_per_s"].as_f64().unwrap(),
        s["model_version"],
        r.rss_at_warm as f64 / 1e6,
        growth / 1024
    );
    assert_eq!(
        (s["sent"].as_u64(), s["received"].as_u64(), s["dropped"].as_u64()),
        (Some(samples), Some(samples), Some(0))
    );
    assert_eq!((r.daemon_in, r.daemon_out, r.send_failures), (samples, samples, 0));
    assert!(s["model_version"].as_u64().unwrap() >= samples / 60_000 - 1, "{s}");
    assert!(growth <= growth_limit, "daemon RSS grew by {growth} bytes after warm-up");
}

#[test]
fn short_soak() {
    let dir = tempfile::tempdir().unwrap();
    let Some(r) = soak(dir.path(), 300.0, 2) else {
        eprintln!("soak: no /proc/self/status here; skipped");
        return;
    };
    check(&r, 300_000, 8 << 20);
}

#[test]
#[ignore = "one hour of 1 kHz data (3.6 M samples); run in release with --ignored"]
fn hour_soak() {
    let dir = tempfile::tempdir().unwrap();
    let r = soak(dir.path(), 3600.0, 15).expect("Linux /proc");
    check(&r, 3_600_000, 1 << 20);
}
