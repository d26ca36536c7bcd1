//! iceoryx2 domains: which set of services a process sees.
//!
//! iceoryx2 names every shared-memory object and file it creates with `global.prefix` (default
//! `iox2_`) and keeps its service and node files under `global.root_path` (default
//! `/tmp/iceoryx2/`). Two processes only see each other's services when both settings agree, so a
//! [`IpcDomain::private`] configuration with its own prefix and root path is a private domain:
//! tests running in parallel, and a test beside a running daemon, never collide.
//!
//! [`IpcDomain::global`] looks the configuration up where iceoryx2 itself would —
//! `config/iceoryx2.toml` in the working directory, then `$HOME/.config/iceoryx2/iceoryx2.toml`,
//! then `/etc/iceoryx2/iceoryx2.toml` — and hands it to the node explicitly, with iceoryx2's
//! built-in defaults when there is none (logged at INFO). iceoryx2's own lookup
//! (`Config::global_config`) warns "No config file was loaded" on every such start, and
//! operators alert on WARN; a file that exists but cannot be read still gets a warning.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use iceoryx2::config::Config;
use iceoryx2::prelude::{FileName, Path as IoxPath, SemanticString};

use super::error::{IpcError, IpcResult};

/// Where iceoryx2 looks for its configuration, in its order (`iceoryx2::config::Config`'s
/// lookup: project-local, user, system); the user's directory from `$HOME` (iceoryx2 reads the
/// password database; the two agree unless `HOME` was changed).
pub fn global_config_candidates() -> Vec<PathBuf> {
    let mut paths = vec![PathBuf::from("config").join("iceoryx2.toml")];
    if let Some(home) = std::env::var_os("HOME").filter(|h| !h.is_empty()) {
        paths.push(PathBuf::from(home).join(".config").join("iceoryx2").join("iceoryx2.toml"));
    }
    paths.push(PathBuf::from("/etc").join("iceoryx2").join("iceoryx2.toml"));
    paths
}

/// The iceoryx2 configuration a node is created with.
#[derive(Debug, Clone)]
pub struct IpcDomain {
    config: Config,
    private_root: Option<PathBuf>,
}

impl IpcDomain {
    /// The domain of the first iceoryx2 config file found, or iceoryx2's defaults (module
    /// documentation).
    pub fn global() -> Self {
        for path in global_config_candidates() {
            if !path.is_file() {
                continue;
            }
            match Self::from_file(&path) {
                Ok(domain) => {
                    tracing::info!(path = %path.display(), "iceoryx2 configuration");
                    return domain;
                }
                Err(error) => {
                    tracing::warn!(path = %path.display(), %error, "iceoryx2 config file not usable; trying the next")
                }
            }
        }
        tracing::info!("no iceoryx2 config file found: iceoryx2's built-in defaults");
        Self { config: Config::default(), private_root: None }
    }

    /// A domain from an iceoryx2 TOML config file.
    pub fn from_file(path: &Path) -> IpcResult<Self> {
        let text = path.to_str().ok_or_else(|| IpcError::Setting(format!("non-UTF-8 path {}", path.display())))?;
        let file = iceoryx2::prelude::FilePath::new(text.as_bytes())
            .map_err(|e| IpcError::iox("parse config path", text, e))?;
        let config = Config::from_file(&file).map_err(|e| IpcError::iox("read config file", text, e))?;
        Ok(Self { config, private_root: None })
    }

    /// A private domain: iceoryx2's defaults with `global.prefix = prefix` and
    /// `global.root_path = root` (an absolute directory, created by iceoryx2 on demand).
    /// `prefix` may hold letters, digits, `_`, `-` and `.`.
    pub fn private(prefix: &str, root: &Path) -> IpcResult<Self> {
        let mut config = Config::default();
        config.global.prefix =
            FileName::new(prefix.as_bytes()).map_err(|e| IpcError::iox("set domain prefix", prefix, e))?;
        let mut root_text = root
            .to_str()
            .ok_or_else(|| IpcError::Setting(format!("non-UTF-8 root path {}", root.display())))?
            .to_owned();
        if !root_text.ends_with('/') {
            root_text.push('/');
        }
        let root_path =
            IoxPath::new(root_text.as_bytes()).map_err(|e| IpcError::iox("set domain root path", &root_text, e))?;
        config.global.set_root_path(&root_path);
        Ok(Self { config, private_root: Some(root.to_path_buf()) })
    }

    /// A private domain unique to this process and call: prefix `gc<pid>x<n>_<tag>_` and root
    /// `<temp dir>/gyrocomp-iox2/<prefix>`. For tests and benches; remove it with
    /// [`IpcDomain::remove_private_files`] when done.
    pub fn unique(tag: &str) -> IpcResult<Self> {
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let prefix = format!("gc{}x{n}_{tag}_", std::process::id());
        let root = std::env::temp_dir().join("gyrocomp-iox2").join(&prefix);
        Self::private(&prefix, &root)
    }

    /// The iceoryx2 configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The prefix of every object of this domain.
    pub fn prefix(&self) -> String {
        self.config.global.prefix.to_string()
    }

    /// The root path of this domain's files.
    pub fn root_path(&self) -> String {
        self.config.global.root_path().to_string()
    }

    /// Removes what a private domain left behind: its root directory and, on Linux, the
    /// shared-memory objects in `/dev/shm` named with its prefix (iceoryx2 keeps a per-process
    /// management object until the process ends, and a crashed test leaves more). Call it only
    /// when no node of the domain is alive in any process. Returns the names of the removed
    /// shared-memory objects. Does nothing for other domains.
    pub fn remove_private_files(&self) -> std::io::Result<Vec<String>> {
        let Some(root) = &self.private_root else { return Ok(Vec::new()) };
        if root.exists() {
            std::fs::remove_dir_all(root)?;
        }
        let prefix = self.prefix();
        let mut removed = Vec::new();
        if let Ok(dir) = std::fs::read_dir("/dev/shm") {
            for entry in dir.flatten() {
                let name = entry.file_name().to_string_lossy().into_owned();
                if name.starts_with(&prefix) && std::fs::remove_file(entry.path()).is_ok() {
                    removed.push(name);
                }
            }
        }
        Ok(removed)
    }
}
