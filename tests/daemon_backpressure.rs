//! The daemon's backpressure path end to end (issue 15, item 7): a client that stops reading
//! (alive, subscribed, never receiving) fills its compensated buffer; the lossless publisher
//! then waits `give_up_ms` per answer for it, gives up, and counts a send failure — the daemon
//! neither blocks forever nor drops a raw sample: every raw sample is still answered to the INS,
//! `samples_in = samples_out + send_failures` on the status service, and `send_failures` is
//! exactly the number of answers that found the stalled buffer full. Once that client is killed,
//! the daemon cleans its dead node after a failed send and the failures stop. Private iceoryx2
//! domain, every process killed and the domain removed on drop; waits on state, not on sleeps.

#[path = "common/daemon_proc.rs"]
mod daemon_proc;
#[path = "common/ins_child.rs"]
mod ins_child;

use std::time::{Duration, Instant};

use daemon_proc::{DaemonProc, prime_until, round_trip, wait_status};
use gyrocomp::ipc::{Delivery, IpcDomain, IpcNode, IpcSettings, StatusEvent};
use ins_child::ChildProc;

/// Subscriber buffer of every port in this test (the daemon's `[ipc] subscriber_buffer`).
const BUFFER: usize = 16;
/// The daemon's `[ipc] give_up_ms`.
const GIVE_UP_MS: u64 = 100;
/// Answers sent while the client is stalled: more than its buffer holds.
const DURING_STALL: u64 = 40;

/// Not a test: the entry point of the child processes (see `tests/common/ins_child.rs`).
#[test]
#[ignore = "entry point of the child processes started by the other tests"]
fn ins_child_entry() {
    ins_child::entry();
}

struct Setup {
    domain: IpcDomain,
    dir: tempfile::TempDir,
}

impl Drop for Setup {
    fn drop(&mut self) {
        let _ = self.domain.remove_private_files();
    }
}

#[test]
fn stalled_client_costs_give_up_per_answer_is_counted_and_cleaned_once_dead() {
    let setup = Setup { domain: IpcDomain::unique("backpressure").unwrap(), dir: tempfile::tempdir().unwrap() };
    let config = setup.dir.path().join("gyrocompd.toml");
    std::fs::write(
        &config,
        format!(
            "[input]\nrate_hz = 100.0\ngap_factor = 1000.0\n\
             [ipc]\nsubscriber_buffer = {BUFFER}\ndelivery = \"lossless\"\ngive_up_ms = {GIVE_UP_MS}\n\
             domain_prefix = \"{}\"\ndomain_root = \"{}\"\n\
             [log]\nlevel = \"info\"\n",
            setup.domain.prefix(),
            setup.domain.root_path().trim_end_matches('/'),
        ),
    )
    .unwrap();
    let mut daemon = DaemonProc::start(&config, setup.dir.path().join("gyrocompd.log"));
    let delivery = Delivery::Lossless { give_up_after: Some(Duration::from_secs(5)) };
    let node = IpcNode::new(
        &setup.domain,
        "bp_ins",
        IpcSettings { delivery, subscriber_buffer: BUFFER, ..IpcSettings::default() },
    )
    .unwrap();
    let raw = node.raw_publisher().unwrap();
    let comp = node.comp_subscriber().unwrap();
    let status = node.status_subscriber().unwrap();
    let (_, mut seq) = prime_until(&raw, &comp, 0, Duration::from_secs(30));
    let mut sent = seq; // every seq below `seq` reached this daemon (first start)

    // A second client subscribes, takes answers until it is attached and empty, then stalls.
    let mut stalled = ChildProc::start("stalled", &setup.domain, &[("GC_BUFFER", BUFFER.to_string())], &[]);
    stalled.wait_for("subscribed", Duration::from_secs(30), |_| true);
    let start = Instant::now();
    let stall = loop {
        assert!(start.elapsed() < Duration::from_secs(30), "the stalled client never got an answer");
        round_trip(&raw, &comp, seq);
        seq += 1;
        sent += 1;
        let waited = Instant::now();
        while stalled.last("stalled").is_none() && waited.elapsed() < Duration::from_millis(200) {
            std::thread::sleep(Duration::from_millis(2));
        }
        if let Some(line) = stalled.last("stalled") {
            break line;
        }
    };
    // Answers after the last one it read wait in its buffer.
    let unread = seq - 1 - stall.get("last_seq");

    // The stall: every raw sample is still answered to the INS, in order; the stalled buffer
    // takes BUFFER - unread more answers, each later one costs give_up_ms and a send failure.
    let before = Instant::now();
    for _ in 0..DURING_STALL {
        round_trip(&raw, &comp, seq);
        seq += 1;
        sent += 1;
    }
    let stall_time = before.elapsed();
    let failures = (unread + DURING_STALL).saturating_sub(BUFFER as u64);
    assert!(failures >= DURING_STALL - BUFFER as u64, "unread {unread}");
    eprintln!("stall: {DURING_STALL} answers in {stall_time:?}, {failures} given up after {GIVE_UP_MS} ms each");
    let report = wait_status(&status, Duration::from_secs(10), |s| s.samples_in == sent);
    assert_eq!(report.send_failures, failures, "{report:?}");
    assert_eq!(report.samples_in, report.samples_out + report.send_failures, "{report:?}");
    // Giving up is what bounded the stall: at least give_up_ms per failure went by, but for the
    // last one — the INS may get its answer before the daemon gives up on the stalled client, so
    // the last wait can end after the loop does (seen in CI: 2.38 s for 24 failures of 100 ms).
    assert!(stall_time >= Duration::from_millis(GIVE_UP_MS * failures.saturating_sub(1)), "{stall_time:?}");

    // The stalled client dies with a full buffer: its node is dead, its port still there.
    stalled.kill();
    assert!(IpcNode::dead_nodes(&setup.domain).unwrap().dead >= 1);
    let start = Instant::now();
    while IpcNode::dead_nodes(&setup.domain).unwrap().dead > 0 {
        assert!(start.elapsed() < Duration::from_secs(30), "the daemon never cleaned the dead client");
        round_trip(&raw, &comp, seq);
        seq += 1;
        sent += 1;
    }
    daemon.wait_log("dead iceoryx2 nodes cleaned after a failed send", Duration::from_secs(5));
    let cleaned = wait_status(&status, Duration::from_secs(10), |s| s.samples_in == sent);
    assert!(cleaned.send_failures > failures, "sends to the dead client failed until it was cleaned: {cleaned:?}");

    // After the cleanup nothing fails any more.
    for _ in 0..100 {
        round_trip(&raw, &comp, seq);
        seq += 1;
        sent += 1;
    }
    daemon.signal("TERM");
    let last = wait_status(&status, Duration::from_secs(10), |s| s.event == StatusEvent::Stopping as u32);
    assert!(daemon.wait_exit(Duration::from_secs(10)).success());
    assert_eq!((last.samples_in, last.send_failures), (sent, cleaned.send_failures), "{last:?}");
    assert_eq!(last.samples_in, last.samples_out + last.send_failures, "{last:?}");
}
