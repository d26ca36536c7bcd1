//! The `--plot FILE` option of `allan`, `compensate` and `eval --protocol motion`: each writes an
//! SVG that is well-formed XML with the expected series in its legend, a PNG that decodes to the
//! figure's size (or, on a machine without a font, a clear error naming what to install), and an
//! unknown extension is refused before any work.

use std::path::Path;
use std::process::Command;

mod common;

use common::{gyrocomp, ok};

/// Checks that `xml` is well-formed as far as tags go: every element opened is closed in order.
fn assert_balanced_tags(xml: &str) {
    let mut stack: Vec<&str> = Vec::new();
    let mut rest = xml;
    while let Some(start) = rest.find('<') {
        let end = rest[start..].find('>').expect("unterminated tag") + start;
        let tag = &rest[start + 1..end];
        rest = &rest[end + 1..];
        if tag.starts_with('?') || tag.starts_with('!') || tag.ends_with('/') {
            continue;
        }
        if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(stack.pop(), Some(name.trim()), "closing </{name}> does not match");
        } else {
            stack.push(tag.split_whitespace().next().unwrap_or(tag));
        }
    }
    assert!(stack.is_empty(), "unclosed elements: {stack:?}");
}

/// Reads an SVG plot and checks its shape and that it names each of `needles`.
fn check_svg(path: &Path, needles: &[&str]) -> String {
    let svg = std::fs::read_to_string(path).unwrap();
    assert!(svg.trim_start().starts_with("<svg"), "{}", &svg[..svg.len().min(200)]);
    assert_balanced_tags(&svg);
    assert!(!svg.contains("NaN"), "no NaN coordinates");
    for n in needles {
        assert!(svg.contains(n), "{} lacks {n:?}", path.display());
    }
    svg
}

/// Runs `args` + `--plot x.png`: a PNG of `size` when a font is found, else the font error.
fn check_png(args: &[&str], dir: &Path, size: (u32, u32)) {
    let png = dir.join("plot.png");
    let out = gyrocomp(&[args, &["--plot", png.to_str().unwrap()]].concat());
    if out.status.success() {
        let bytes = std::fs::read(&png).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
        assert_eq!(&bytes[12..16], b"IHDR");
        let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
        assert_eq!((be(16), be(20)), size, "PNG size");
    } else {
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("fonts-dejavu-core") && err.contains(".svg"), "{err}");
        eprintln!("no font on this machine: PNG refused as expected");
    }
}

/// A 10 Hz simulated recording of `seconds` (`gyrocomp sim`, the paper's preset).
fn recording(dir: &Path, seconds: &str) -> String {
    recording_of(dir, "paper", seconds)
}

/// The same with another preset.
fn recording_of(dir: &Path, preset: &str, seconds: &str) -> String {
    let csv = dir.join("sim.csv").to_str().unwrap().to_owned();
    ok(&["sim", "--preset", preset, "--seed", "3", "--duration", seconds, "-o", &csv]);
    csv
}

#[test]
fn allan_plot_shows_points_band_fit_and_terms() {
    let dir = tempfile::tempdir().unwrap();
    let csv = recording(dir.path(), "2000");
    let svg = dir.path().join("allan.svg");
    ok(&["allan", &csv, "--plot", svg.to_str().unwrap()]);
    let text =
        check_svg(&svg, &["Allan deviation", "averaging time τ (s)", "(deg/s)", "measured", "χ² band", "IEEE 952 fit"]);
    assert!(text.contains("slope -1/2") || text.contains("slope +1/2") || text.contains("slope 0"), "a fitted term");
    check_png(&["allan", &csv], dir.path(), (960, 680));
}

#[test]
fn unknown_plot_extension_is_refused_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let csv = recording(dir.path(), "60");
    for cmd in [&["allan", &csv][..], &["compensate", &csv, "-o", "-"][..]] {
        let out = gyrocomp(&[cmd, &["--plot", "x.pdf"]].concat());
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("x.pdf") && err.contains(".svg or .png"), "{err}");
    }
    let out = gyrocomp(&["eval", &csv, "--plot", "x.svg"]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("--protocol motion"));
}

#[test]
fn compensate_plot_shows_raw_drift_band_compensated_and_flags() {
    let dir = tempfile::tempdir().unwrap();
    let csv = recording(dir.path(), "300");
    let moved = dir.path().join("moved.csv").to_str().unwrap().to_owned();
    ok(&["motion", &csv, "--profile", "turns", "--seed", "3", "-o", &moved]);
    let config = dir.path().join("c.toml");
    let text = format!("{}[input]\nrate_hz = 10.0\n{}", common::PAPER_PIPELINE, common::QUICK_RETRAIN);
    std::fs::write(&config, text).unwrap();
    let svg = dir.path().join("comp.svg");
    let args = ["compensate", &moved, "--config", config.to_str().unwrap(), "--column", "gx_dps,gy_dps"];
    let out_csv = dir.path().join("out.csv").to_str().unwrap().to_owned();
    let args = [&args[..], &["--moving-column", "moving", "-o", &out_csv]].concat();
    ok(&[&args[..], &["--plot", svg.to_str().unwrap()]].concat());
    let text = check_svg(
        &svg,
        &[
            "raw rate",
            "drift estimate",
            "drift ±1σ",
            "compensated",
            "moving (",
            "gx_dps rate (deg/s)",
            "gy_dps drift (deg/s)",
            "raw rate, static samples",
            "time (s)",
        ],
    );
    // 3000 samples: drawn decimated to min/max per pixel column.
    assert!(text.contains("min/max per pixel column"));
    check_png(&args, dir.path(), (1200, 60 + 4 * 270));
}

#[test]
fn eval_motion_plot_shows_each_model_against_the_floor() {
    let dir = tempfile::tempdir().unwrap();
    // The ADIS16405 preset has white noise enough for the floor (N from the Allan fit).
    let csv = recording_of(dir.path(), "adis16405", "900");
    let moved = dir.path().join("moved.csv").to_str().unwrap().to_owned();
    ok(&["motion", &csv, "--profile", "turns", "--seed", "4", "-o", &moved]);
    let config = dir.path().join("c.toml");
    let ten_hz = include_str!("../configs/adis16405_10hz.toml");
    std::fs::write(&config, format!("{ten_hz}\n{}", common::QUICK_RETRAIN)).unwrap();
    let svg = dir.path().join("motion.svg");
    let args = [
        "eval",
        &moved,
        "--protocol",
        "motion",
        "--config",
        config.to_str().unwrap(),
        "--models",
        "bias-hold,last-static,highpass",
    ];
    ok(&[&args[..], &["--plot", svg.to_str().unwrap()]].concat());
    check_svg(
        &svg,
        &[
            "bias-hold (median",
            "last-static (median",
            "highpass (median",
            "white-noise floor",
            "motion segment",
            "angle error",
        ],
    );
    check_png(&args, dir.path(), (1100 + 330, 680));
}

#[test]
fn png_without_a_usable_font_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let csv = recording(dir.path(), "60");
    let png = dir.path().join("a.png");
    for (font, says) in [("/nonexistent/font.ttf", "cannot read"), (csv.as_str(), "not a TrueType/OpenType font")] {
        let out = Command::new(env!("CARGO_BIN_EXE_gyrocomp"))
            .args(["allan", &csv, "--plot", png.to_str().unwrap()])
            .env("GYROCOMP_FONT", font)
            .output()
            .unwrap();
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("a.png") && err.contains(says) && err.contains("fonts-dejavu-core") && err.contains(".svg"),
            "{err}"
        );
    }
    assert!(!png.exists(), "no file left behind");
}
