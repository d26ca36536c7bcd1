//! Who may talk to `gyrocompd` (issue 7, item 6). iceoryx2 0.10.0 (without its
//! `dev_permissions` feature, which this project does not enable) creates every shared-memory
//! object and file of a service readable and writable by its owner only, so a process of
//! another uid can neither publish raw samples to the daemon nor subscribe to its answers.
//!
//! Needs root and the `nobody` user (uid 65534) with `setpriv`; skips with a message otherwise.
//! - The daemon runs as root, a client as `nobody`: every port is refused.
//! - Control: daemon and client both as `nobody`: everything works, so the refusal above is the
//!   uid's doing, not a path or a binary `nobody` cannot reach.
//! - The shared-memory objects of the domain: owner-only modes, except iceoryx2's global
//!   management segment (a node counter), which iceoryx2 creates world-writable on purpose.

#[path = "common/ins_child.rs"]
mod ins_child;

use std::os::unix::fs::{MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use gyrocomp::ipc::IpcDomain;
use ins_child::{ChildProc, Progress};

const NOBODY: u32 = 65534;
const AS_NOBODY: [&str; 4] = ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups"];

/// Not a test: the entry point of the child processes (see `tests/common/ins_child.rs`).
#[test]
#[ignore = "entry point of the child processes started by the other tests"]
fn ins_child_entry() {
    ins_child::entry();
}

/// Why this machine cannot run the test, if it cannot.
fn unavailable() -> Option<String> {
    let uid = Command::new("id").arg("-u").output().ok()?;
    if String::from_utf8_lossy(&uid.stdout).trim() != "0" {
        return Some("not running as root".into());
    }
    let reachable = |path: &Path| {
        Command::new(AS_NOBODY[0])
            .args(&AS_NOBODY[1..])
            .args(["test", "-x"])
            .arg(path)
            .status()
            .is_ok_and(|s| s.success())
    };
    let exe = std::env::current_exe().ok()?;
    for path in [exe.as_path(), Path::new(env!("CARGO_BIN_EXE_gyrocompd"))] {
        if !reachable(path) {
            return Some(format!("setpriv to uid {NOBODY} failed, or {} is not executable by it", path.display()));
        }
    }
    None
}

/// A private domain whose root directory anyone may write (so only iceoryx2's own permissions
/// decide), and a config file anyone may read; removed on drop.
struct World {
    domain: IpcDomain,
    config: PathBuf,
    dir: tempfile::TempDir,
}

impl World {
    /// `open_dirs`: also create iceoryx2's `nodes` and `services` directories writable by all
    /// (sticky), so that another uid can create its node and only the service objects' own
    /// permissions stand in its way.
    fn new(tag: &str, open_dirs: bool) -> Self {
        let dir = tempfile::tempdir().unwrap();
        std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o755)).unwrap();
        let root = dir.path().join("iox2");
        let subdirs: &[&str] = if open_dirs { &["", "nodes", "services"] } else { &[""] };
        for sub in subdirs {
            let d = root.join(sub);
            std::fs::create_dir_all(&d).unwrap();
            std::fs::set_permissions(&d, std::fs::Permissions::from_mode(0o1777)).unwrap();
        }
        let prefix = format!("gc{}perm{tag}_", std::process::id());
        let domain = IpcDomain::private(&prefix, &root).unwrap();
        let config = dir.path().join("gyrocompd.toml");
        let text = format!(
            "[denoise]\nwindow = 64\n[ipc]\ndomain_prefix = \"{prefix}\"\ndomain_root = \"{}\"\n",
            root.display()
        );
        std::fs::write(&config, text).unwrap();
        std::fs::set_permissions(&config, std::fs::Permissions::from_mode(0o644)).unwrap();
        Self { domain, config, dir }
    }

    /// Starts gyrocompd, as root or through `wrapper`, and waits until it runs.
    fn daemon(&self, wrapper: &[&str]) -> DaemonProc {
        let log = self.dir.path().join(format!("gyrocompd-{}.log", wrapper.len()));
        let mut cmd = match wrapper.split_first() {
            Some((p, args)) => {
                let mut c = Command::new(p);
                c.args(args).arg(env!("CARGO_BIN_EXE_gyrocompd"));
                c
            }
            None => Command::new(env!("CARGO_BIN_EXE_gyrocompd")),
        };
        let child = cmd
            .arg("--config")
            .arg(&self.config)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(std::fs::File::create(&log).unwrap())
            .spawn()
            .unwrap();
        let d = DaemonProc { child, log };
        let start = Instant::now();
        while !d.log_text().contains("gyrocompd running") {
            assert!(start.elapsed() < Duration::from_secs(20), "gyrocompd did not start:\n{}", d.log_text());
            std::thread::sleep(Duration::from_millis(20));
        }
        d
    }

    /// The domain's shared-memory objects: (name, owner uid, mode bits).
    fn shm_objects(&self) -> Vec<(String, u32, u32)> {
        let prefix = self.domain.prefix();
        std::fs::read_dir("/dev/shm")
            .unwrap()
            .flatten()
            .filter_map(|e| {
                let name = e.file_name().to_string_lossy().into_owned();
                let meta = e.metadata().ok()?;
                name.starts_with(&prefix).then_some((name, meta.uid(), meta.mode() & 0o777))
            })
            .collect()
    }
}

impl Drop for World {
    fn drop(&mut self) {
        let _ = self.domain.remove_private_files();
    }
}

struct DaemonProc {
    child: Child,
    log: PathBuf,
}

impl DaemonProc {
    fn log_text(&self) -> String {
        std::fs::read_to_string(&self.log).unwrap_or_default()
    }
}

impl Drop for DaemonProc {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        if std::thread::panicking() {
            eprintln!("--- gyrocompd log ---\n{}", self.log_text());
        }
    }
}

fn probe(world: &World) -> Progress {
    let mut child = ChildProc::start("probe", &world.domain, &[], &AS_NOBODY);
    let line = child.wait_for("probe", Duration::from_secs(30), |_| true);
    child.wait_exit(Duration::from_secs(30));
    line
}

#[test]
fn another_uid_can_neither_publish_nor_subscribe() {
    if let Some(why) = unavailable() {
        eprintln!("SKIP another_uid_can_neither_publish_nor_subscribe: {why}");
        return;
    }
    // Control: the daemon and the client under the same uid (nobody) talk.
    {
        let world = World::new("same", false);
        let _daemon = world.daemon(&AS_NOBODY);
        let same = probe(&world);
        eprintln!("daemon nobody, client nobody: {}", same.line);
        assert!(
            same.line.contains("raw_publisher=ok comp_subscriber=ok status_subscriber=ok answered=ok"),
            "{}",
            same.line
        );
    }

    // The daemon as root, the client as nobody: refused, whether iceoryx2 made the directories
    // (the client cannot even create its node) or they are open to all (its node exists, every
    // port is refused).
    for open_dirs in [false, true] {
        let world = World::new(if open_dirs { "open" } else { "other" }, open_dirs);
        let _daemon = world.daemon(&[]);
        let other = probe(&world);
        eprintln!("daemon root, client nobody, open directories {open_dirs}: {}", other.line);
        let fields = &other.fields;
        let refused = |k: &str| fields.get(k).is_none_or(|v| v == "refused");
        assert!(
            refused("raw_publisher") && refused("comp_subscriber") && refused("status_subscriber"),
            "{}",
            other.line
        );
        assert!(!other.line.contains("answered=ok"), "{}", other.line);
        if open_dirs {
            assert!(other.line.contains("node=ok"), "the node should exist, the ports not: {}", other.line);
        }
    }

    let world = World::new("modes", false);
    let _daemon = world.daemon(&[]);

    let objects = world.shm_objects();
    assert!(!objects.is_empty());
    for (name, uid, mode) in &objects {
        eprintln!("/dev/shm/{name}: uid {uid}, mode {mode:o}");
        if name.ends_with("global_mgmt") {
            continue; // iceoryx2's node counter, world-writable by design (docs/usage.md)
        }
        assert_eq!(mode & 0o077, 0, "{name} is accessible to other users: mode {mode:o}");
    }
}
