//! The iceoryx2 Python wheel for the Python-client tests: present, or a skip that says so — and
//! under `CI=true` a failure, since CI installs the wheel (`.ci/run`) and a silent skip there
//! would hide a broken client.

use std::io::Write;
use std::process::Command;

/// Whether `python3 -c "import iceoryx2"` works. When it does not: panics under `CI=true`,
/// otherwise writes a SKIP line for `test` straight to the process's stderr (not through
/// `eprintln!`, which the test harness captures: the line shows in a plain `cargo test`) and
/// returns false.
pub fn iceoryx2_wheel_or_skip(test: &str) -> bool {
    module_or_skip(test, "iceoryx2", "the iceoryx2 Python wheel", "pip install iceoryx2==0.10.0")
}

/// Whether `python3 -c "import MODULE"` works; otherwise as [`iceoryx2_wheel_or_skip`]: a panic
/// under `CI=true` (where .ci/run installs `what`), else a SKIP line with `hint`, and false.
pub fn module_or_skip(test: &str, module: &str, what: &str, hint: &str) -> bool {
    let probe = Command::new("python3").args(["-c", &format!("import {module}")]).output();
    if matches!(&probe, Ok(o) if o.status.success()) {
        return true;
    }
    let why = match &probe {
        Ok(o) => String::from_utf8_lossy(&o.stderr).lines().last().unwrap_or("").to_owned(),
        Err(e) => format!("python3 not runnable: {e}"),
    };
    assert!(
        std::env::var("CI").as_deref() != Ok("true"),
        "{test}: CI=true but {what} is not importable ({why}); .ci/run installs it"
    );
    let _ = writeln!(std::io::stderr(), "SKIP {test}: {what} is not importable ({why}; {hint})");
    false
}
