//! Error messages of the binaries.

/// Formats an error with its chain of causes, one `caused by:` line each, for a binary's last
/// message on stderr.
pub fn error_chain(error: &dyn std::error::Error) -> String {
    let mut msg = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        msg.push_str(&format!("\n  caused by: {cause}"));
        source = cause.source();
    }
    msg
}
