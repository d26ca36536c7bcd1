//! Property tests ("fuzzing") of the configuration loader: arbitrary TOML-like text, and the
//! shipped `configs/default.toml` with one value replaced by an arbitrary one (any type, huge,
//! negative, non-finite) or with random character edits. Loading must never panic; an accepted
//! file must give a configuration that builds everything the daemon builds from it (pipeline,
//! CPSO-LSSVM, IPC settings, domain, log format, state directory); a refused one must name the
//! origin and a key or a line.
//!
//! Case counts: proptest's default (256 per property) or `PROPTEST_CASES`.

use gyrocomp::config::Config;
use gyrocomp::stream::Pipeline;
use proptest::prelude::*;

const DEFAULT: &str = include_str!("../configs/default.toml");
const ORIGIN: &str = "fuzz.toml";

/// Every `section.key` of the default file.
fn keys() -> Vec<String> {
    let table: toml::Table = toml::from_str(DEFAULT).unwrap();
    let mut out = Vec::new();
    for (section, body) in &table {
        for key in body.as_table().unwrap().keys() {
            out.push(format!("{section}.{key}"));
        }
    }
    out
}

fn check(text: &str, keys: &[String]) -> Result<(), TestCaseError> {
    match Config::from_toml(text, ORIGIN) {
        Ok(c) => {
            let pc = c.pipeline();
            prop_assert!(pc.is_ok(), "accepted but pipeline() fails: {:?}", pc.err());
            prop_assert!(c.cpso_lssvm().is_ok() && c.ipc_settings().is_ok() && c.ipc_domain().is_ok());
            prop_assert!(c.log_format().is_ok() && c.state_dir().is_ok());
            let built = Pipeline::new(pc.unwrap());
            prop_assert!(built.is_ok(), "accepted but the pipeline refuses it: {:?}", built.err());
        }
        Err(e) => {
            let msg = e.to_string();
            prop_assert!(msg.starts_with(ORIGIN), "message does not name the file: {msg}");
            let names_key = keys.iter().any(|k| msg.contains(k.as_str()));
            prop_assert!(msg.contains("line ") || names_key, "message names neither a line nor a key: {msg}");
        }
    }
    Ok(())
}

/// A TOML value of any type, including the awkward ones.
fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<i64>().prop_map(|v| v.to_string()),
        (0u64..70_000).prop_map(|v| v.to_string()),
        any::<f64>().prop_map(|v| format!("{v:?}")),
        prop::sample::select(vec!["nan", "inf", "-inf", "-0.0", "1e308", "0", "-1", "1", "true", "[]", "{}"])
            .prop_map(str::to_owned),
        "[a-z0-9_./ -]{0,12}".prop_map(|s| format!("{s:?}")),
        prop::sample::select(vec![
            "\"db4\"",
            "\"db1\"",
            "\"live\"",
            "\"deterministic\"",
            "\"spin\"",
            "\"json\"",
            "\"/tmp/x\""
        ])
        .prop_map(str::to_owned),
    ]
}

/// The default file with the value of its `n`-th `key = value` line (modulo the count) replaced.
fn replace_value(n: usize, v: &str) -> String {
    let lines: Vec<&str> = DEFAULT.lines().collect();
    let assignments: Vec<usize> =
        lines.iter().enumerate().filter(|(_, l)| !l.starts_with('#') && l.contains(" = ")).map(|(i, _)| i).collect();
    let target = assignments[n % assignments.len()];
    lines
        .iter()
        .enumerate()
        .map(|(i, l)| if i == target { format!("{} = {v}", l.split(" = ").next().unwrap()) } else { (*l).to_owned() })
        .collect::<Vec<_>>()
        .join("\n")
}

proptest! {
    #[test]
    fn arbitrary_toml_like_text_never_panics(
        text in "(\\[(denoise|retrain|ipc|log|state|motion|x)\\]\n|(window|lag|tau|dim|mode|dir|level|rate_hz|foo) = |[0-9.e+-]{1,8}|\"[a-z/]{0,5}\"|true|\n|#|=|\\[|\\]| ){0,40}"
    ) {
        check(&text, &keys())?;
    }

    #[test]
    fn any_value_for_any_key_never_panics(n in 0usize..200, v in value()) {
        check(&replace_value(n, &v), &keys())?;
    }

    #[test]
    fn random_edits_of_the_default_file_never_panic(
        edits in prop::collection::vec((0.0f64..1.0, 0u8..3, prop::sample::select(b"=[]\"#\n .-0123456789ez".to_vec())), 1..6)
    ) {
        let mut bytes = DEFAULT.as_bytes().to_vec();
        for (at, op, b) in edits {
            let i = ((at * bytes.len() as f64) as usize).min(bytes.len() - 1);
            match op {
                0 => { bytes.remove(i); }
                1 => bytes.insert(i, b),
                _ => bytes[i] = b,
            }
        }
        // Only ASCII is inserted into the ASCII-only assignment lines, but a removal may split
        // a multi-byte character of a comment: such text is not a str, which the loader takes.
        if let Ok(text) = std::str::from_utf8(&bytes) {
            check(text, &keys())?;
        }
    }
}
