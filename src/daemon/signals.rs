//! Signals as flags: SIGTERM and SIGINT ask the daemon to stop, SIGHUP to reload its
//! configuration. The handlers (`signal_hook::flag`) only set atomics; the loop polls them
//! between samples, so a signal never interrupts the processing of a sample.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};

/// The flags the signal handlers set.
#[derive(Debug, Clone, Default)]
pub struct Signals {
    stop: Arc<AtomicBool>,
    reload: Arc<AtomicBool>,
}

impl Signals {
    /// Flags with no handler installed (tests, embedding the loop in another program).
    pub fn new() -> Self {
        Self::default()
    }

    /// Installs handlers: SIGTERM and SIGINT set the stop flag (a second one, while the daemon
    /// is still draining, exits at once with code 1), SIGHUP the reload flag.
    pub fn install() -> std::io::Result<Self> {
        let s = Self::new();
        for sig in [SIGTERM, SIGINT] {
            // Registered first: it sees the flag as it was before this signal's own handler.
            signal_hook::flag::register_conditional_shutdown(sig, 1, Arc::clone(&s.stop))?;
            signal_hook::flag::register(sig, Arc::clone(&s.stop))?;
        }
        signal_hook::flag::register(SIGHUP, Arc::clone(&s.reload))?;
        Ok(s)
    }

    /// Whether a stop was asked for.
    pub fn stop_requested(&self) -> bool {
        self.stop.load(Ordering::Acquire)
    }

    /// Asks for a stop (as SIGTERM does).
    pub fn request_stop(&self) {
        self.stop.store(true, Ordering::Release);
    }

    /// Whether a reload was asked for since the last call (clears the flag).
    pub fn take_reload(&self) -> bool {
        self.reload.swap(false, Ordering::AcqRel)
    }

    /// Asks for a reload (as SIGHUP does).
    pub fn request_reload(&self) {
        self.reload.store(true, Ordering::Release);
    }
}
