//! The one-pipeline property through the `gyrocompd` binary (issue 15 item 7): a stream with
//! publisher moving flags, a detected turn, a NaN rate, a spike, a duplicate and a skipped `seq`,
//! a time jump, NaN temperatures and a publisher restart (seq back to 0), sent over iceoryx2 to
//! the daemon process with the default configuration, is answered bit for bit as the offline
//! driver's pipeline (what `gyrocomp compensate` runs) answers the same samples.

#[path = "common/daemon_proc.rs"]
mod daemon_proc;

use std::time::Duration;

use daemon_proc::DaemonProc;
use gyrocomp::config::Config;
use gyrocomp::daemon::convert::{input_from_raw, output_from_comp};
use gyrocomp::ipc::{CompSample, Delivery, IpcDomain, IpcNode, IpcSettings, RAW_FLAG_MOVING, RawSample, prime};
use gyrocomp::sim::{Generator, Preset};
use gyrocomp::stream::{STATUS_GAP, STATUS_MOVING, STATUS_REJECTED};

/// 400 s of the ADIS16405 preset at 10 Hz with every kind of event the daemon must treat as the
/// offline driver does.
fn stream() -> Vec<RawSample> {
    let mut sim = Preset::Adis16405.config();
    sim.duration_s = 400.0;
    let out = Generator::generate(&sim, 17).unwrap();
    let mut samples = Vec::new();
    let (mut seq, mut t_ns) = (0u64, 1_000_000_000u64);
    for k in 0..out.t_s.len() {
        let mut rate = [out.axes[0].raw[k], out.axes[1].raw[k], out.axes[2].raw[k]];
        let mut flags = 0;
        if (1000..1300).contains(&k) {
            rate[0] += 20.0; // a turn: flagged by the publisher for its first 200 samples only
            flags = if k < 1200 { RAW_FLAG_MOVING } else { 0 };
        }
        match k {
            1500 => rate[1] = f64::NAN,
            1600 => rate[0] += 50.0,
            1800..=1804 => {
                // seq skipped: the samples never reach the daemon
                seq += 1;
                t_ns += 100_000_000;
                continue;
            }
            2000 => t_ns += 30_000_000_000,
            3500 => seq = 0, // the publisher restarted
            _ => {}
        }
        let temp_c = if (2100..2150).contains(&k) { f64::NAN } else { 25.0 + 0.001 * k as f64 };
        let s = RawSample { temp_c, flags, ..RawSample::new(seq, t_ns, rate) };
        samples.push(s);
        if k == 1700 {
            samples.push(s); // a duplicate
        }
        seq += 1;
        t_ns += 100_000_000;
    }
    samples
}

#[test]
fn the_daemon_binary_answers_bit_for_bit_as_the_offline_pipeline() {
    let dir = tempfile::tempdir().unwrap();
    let domain = IpcDomain::unique("equiv").unwrap();
    let text = format!(
        "[ipc]\ndomain_prefix = \"{}\"\ndomain_root = \"{}\"\n[log]\nlevel = \"info\"\n",
        domain.prefix(),
        domain.root_path().trim_end_matches('/'),
    );
    let config_path = dir.path().join("gyrocompd.toml");
    std::fs::write(&config_path, &text).unwrap();
    let _daemon = DaemonProc::start(&config_path, dir.path().join("gyrocompd.log"));

    let delivery = Delivery::Lossless { give_up_after: Some(Duration::from_secs(5)) };
    let node = IpcNode::new(&domain, "equivalence_client", IpcSettings { delivery, ..IpcSettings::default() }).unwrap();
    let raw = node.raw_publisher().unwrap();
    let comp = node.comp_subscriber().unwrap();
    assert!(raw.wait_for_subscriber(Duration::from_secs(30)), "the daemon subscribes to raw");
    let samples = stream();
    let _cleanup = Cleanup(&domain);
    let mut answers: Vec<CompSample> =
        vec![prime(&raw, &comp, samples[0], Duration::from_secs(30)).expect("first answer")];
    for chunk in samples[1..].chunks(32) {
        for s in chunk {
            raw.send(*s).unwrap();
        }
        for s in chunk {
            let a = comp.recv_timeout(Duration::from_secs(20)).unwrap().expect("an answer per sample");
            assert_eq!((a.seq, a.t_ns), (s.seq, s.t_ns), "answers in order");
            answers.push(a);
        }
    }

    let config = Config::from_toml(&text, "test").unwrap();
    let mut offline = gyrocomp::drive::build_pipeline(&gyrocomp::drive::offline_config(&config)).unwrap();
    let mut seen = 0u32;
    for (k, (s, a)) in samples.iter().zip(&answers).enumerate() {
        let want = offline.process(&input_from_raw(s));
        assert_eq!(output_from_comp(a), want, "sample {k} (seq {})", s.seq);
        for (bit, flag) in [STATUS_MOVING, STATUS_REJECTED, STATUS_GAP].into_iter().enumerate() {
            if want.status & flag != 0 {
                seen |= 1 << bit;
            }
        }
    }
    eprintln!("{} samples compared; offline stats {:?}", answers.len(), offline.stats());
    assert_eq!(seen, 0b111, "the stream exercised moving, rejected and gap samples");
    let stats = offline.stats();
    assert!(stats.input.duplicates >= 1 && stats.input.restarts >= 1 && stats.input.seq_skipped >= 5, "{stats:?}");
}

/// Removes the private domain's files when the test ends.
struct Cleanup<'a>(&'a IpcDomain);

impl Drop for Cleanup<'_> {
    fn drop(&mut self) {
        let _ = self.0.remove_private_files();
    }
}
