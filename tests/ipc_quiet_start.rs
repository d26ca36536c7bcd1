//! A healthy start is quiet (issue 15, item 5): choosing the global iceoryx2 domain logs no
//! warning. iceoryx2's own lookup (`Config::global_config`) warns "No config file was loaded" on
//! every start without a config file, and operators alert on WARN; `IpcDomain::global` does the
//! same lookup itself and hands the node its configuration. This file holds one test, so the
//! process's iceoryx2 singleton is untouched when it runs (a regression to `global_config` would
//! warn here). It creates no iceoryx2 resource.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use gyrocomp::ipc::IpcDomain;
use gyrocomp::ipc::domain::global_config_candidates;
use tracing_subscriber::Layer;
use tracing_subscriber::layer::{Context, SubscriberExt};

/// Counts events at WARN or above.
struct CountWarnings(Arc<AtomicUsize>);

impl<S: tracing::Subscriber> Layer<S> for CountWarnings {
    fn on_event(&self, event: &tracing::Event<'_>, _: Context<'_, S>) {
        if *event.metadata().level() <= tracing::Level::WARN {
            self.0.fetch_add(1, Ordering::SeqCst);
        }
    }
}

#[test]
fn choosing_the_global_domain_logs_no_warning() {
    let warnings = Arc::new(AtomicUsize::new(0));
    let subscriber = tracing_subscriber::registry().with(CountWarnings(warnings.clone()));
    let domain = tracing::subscriber::with_default(subscriber, IpcDomain::global);
    assert_eq!(warnings.load(Ordering::SeqCst), 0, "a warning while choosing the global domain");
    let candidates = global_config_candidates();
    assert_eq!(candidates.first().map(|p| p.as_path()), Some(std::path::Path::new("config/iceoryx2.toml")));
    assert_eq!(candidates.last().map(|p| p.as_path()), Some(std::path::Path::new("/etc/iceoryx2/iceoryx2.toml")));
    if !candidates.iter().any(|p| p.is_file()) {
        assert_eq!(domain.config(), &iceoryx2::config::Config::default(), "no file: iceoryx2's defaults");
    }
}
