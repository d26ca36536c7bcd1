//! `gyrocomp simgap` on cases of the independent generator (tools/simgap/independent_cases.py,
//! numpy, written apart from src/diag/simgap; issue 16): a few REPORT-range seeds (1–999 and
//! 3000–3999; the generator's tuning ranges are 1000–2999), short 10 Hz recordings, diagnosed
//! through the CLI as a user would. Needs python3 with numpy: without it the test is skipped with
//! a SKIP line, and under `CI=true` (where .ci/run installs numpy) it fails instead.
//!
//! Asserted: pure-IEEE recordings (the floor alone) get "no significant gap"; a Gauss–Markov
//! process or a temperature response the IEEE terms absorb is found by its nested-model test; a
//! step in the hold-out part is named a bias jump; spikes are named before any small ramp kept
//! beside them; a ramp is not named a warm-up whose time constant the data do not bound; a slow
//! ramp the IEEE terms absorb is found by its matched filter (a tuning seed, the case that filter
//! was chosen on), and a warm-up and a ramp they absorb by their nested tests (tuning seeds); a
//! faint line the Hann search misses is fitted from the whole part's periodogram (a tuning seed);
//! beside dominant spikes a slow sinusoid is kept with its slow-line fit, not the noise line that
//! scores best alone (a tuning seed); a warm-up of most of an hour whose hold-out part levels off
//! is named a warm-up, not a ramp (a tuning seed);
//! with the case's floor given as the simulator (`--sim`, tools/simgap/score.py
//! `--given-floor`), what the fitted terms absorb is found and a pure floor still shows no gap;
//! and (ignored by default, heavy) on the report set of docs/evaluation.md "Independent cases" the
//! classes named right there stay at their measured counts minus a margin.

#[allow(dead_code)] // its iceoryx2 probe is not used here
#[path = "common/python.rs"]
mod python;

use std::path::Path;
use std::process::Command;

use gyrocomp::diag::simgap::greedy::EDGE_MARGIN;
use serde_json::Value;

/// Whether python3 can import numpy (a SKIP line otherwise, a panic under `CI=true`).
fn numpy_or_skip(test: &str) -> bool {
    python::module_or_skip(test, "numpy", "numpy", "pip install numpy")
}

/// Runs the generator with `args` (report seeds) into `dir`; returns the manifest's cases.
fn generate(dir: &Path, args: &[&str]) -> Vec<Value> {
    generate_in_range(dir, args, "report")
}

/// Runs the generator with `args` into `dir`, its seeds in `range` ("report" or "tuning");
/// returns the manifest's cases.
fn generate_in_range(dir: &Path, args: &[&str], range: &str) -> Vec<Value> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/simgap/independent_cases.py");
    let out = Command::new("python3").arg(script).arg(dir).args(args).output().expect("run python3");
    assert!(out.status.success(), "generator: {}", String::from_utf8_lossy(&out.stderr));
    let manifest: Value = serde_json::from_slice(&std::fs::read(dir.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["seed_range"], range);
    manifest["cases"].as_array().unwrap().clone()
}

/// `gyrocomp simgap --json` on a case, with `extra` arguments: the JSON document.
fn diagnose(dir: &Path, case: &Value, extra: &[&str]) -> Value {
    let path = dir.join(case["file"].as_str().unwrap());
    let out = Command::new(env!("CARGO_BIN_EXE_gyrocomp"))
        .args(["simgap", "--real", path.to_str().unwrap(), "--json"])
        .args(extra)
        .output()
        .expect("run gyrocomp");
    assert!(out.status.success(), "{}: {}", path.display(), String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// One report case of `class` from `seed`, generated into `dir` and diagnosed on two threads: the
/// case's manifest entry and the JSON document.
fn one_case(dir: &Path, seed: &str, class: &str) -> (Value, Value) {
    one_case_in(dir, seed, class, "report")
}

/// [`one_case`] for a seed of the generator's tuning range.
fn one_tuning_case(dir: &Path, seed: &str, class: &str) -> (Value, Value) {
    one_case_in(dir, seed, class, "tuning")
}

/// One case of `class` from `seed` in `range` ("report" or "tuning"), generated into `dir` and
/// diagnosed on two threads: the case's manifest entry and the JSON document.
fn one_case_in(dir: &Path, seed: &str, class: &str, range: &str) -> (Value, Value) {
    let cases = generate_in_range(dir, &["--first-seed", seed, "--per-class", "1", "--classes", class], range);
    let doc = diagnose(dir, &cases[0], &["--threads", "2"]);
    (cases[0].clone(), doc)
}

/// Whether the baseline alone shows a significant gap on either part of a diagnosis document.
fn baseline_shows_a_gap(doc: &Value) -> bool {
    ["train", "holdout"].iter().any(|part| doc["before"][part]["significant"].as_bool().unwrap())
}

/// The result of effect `name` in a diagnosis document.
fn effect<'a>(doc: &'a Value, name: &str) -> &'a Value {
    doc["effects"].as_array().unwrap().iter().find(|e| e["name"] == name).unwrap()
}

/// The effect names of list `key` ("tried", "chosen") of a diagnosis document.
fn names<'a>(doc: &'a Value, key: &str) -> Vec<&'a str> {
    doc[key].as_array().unwrap().iter().map(|v| v.as_str().unwrap()).collect()
}

/// The effect a diagnosis document names first, if any.
fn named_first(doc: &Value) -> Option<&str> {
    doc["chosen"].get(0).and_then(Value::as_str)
}

/// What the diagnosis names first (tools/simgap/score.py's rule), with `extra` arguments.
fn outcome(dir: &Path, case: &Value, extra: &[&str]) -> String {
    let doc = diagnose(dir, case, extra);
    let verdict = doc["verdict"].as_str().unwrap();
    match (verdict, named_first(&doc)) {
        ("explained" | "partly_explained", Some(k)) => k.to_owned(),
        ("no_significant_gap", _) => "none".to_owned(),
        _ => "unexplained".to_owned(),
    }
}

/// Two pure-IEEE recordings (floor only; report seeds 1–2, 3,000 s at 10 Hz): no significant gap.
#[test]
fn pure_ieee_recordings_show_no_significant_gap() {
    if !numpy_or_skip("pure_ieee_recordings_show_no_significant_gap") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let args = ["--first-seed", "1", "--per-class", "2", "--classes", "none", "--durations", "3000,3000"];
    for case in &generate(dir.path(), &args) {
        let got = outcome(dir.path(), case, &["--ensemble", "24", "--threads", "2"]);
        assert_eq!(got, "none", "seed {} on floor {}", case["seed"], case["floor"]);
    }
}

/// A pure floor of white noise and a rate random walk (tuning seed 2190, 10 Hz): the
/// Gauss–Markov process that fits best (σ ≈ 0.004 deg/s, τ ≈ 8 s) lies below the white noise at
/// its own time scale (σ√τ ≈ 0.011 against N ≈ 0.030 deg/√s), so it is no candidate and the
/// recording shows no significant gap. Until the forty-second session its nested test passed
/// (Λ 6.2 against 4.5) and it was named.
#[test]
fn a_gauss_markov_process_below_the_white_noise_is_not_named_on_a_pure_floor() {
    if !numpy_or_skip("a_gauss_markov_process_below_the_white_noise_is_not_named_on_a_pure_floor") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (case, doc) = one_tuning_case(dir.path(), "2190", "none");
    assert_eq!(case["floor"], "nominal_flat");
    let gm = effect(&doc, "gauss_markov");
    let (sigma, tau) =
        (gm["params"]["sigma_dps"].as_f64().unwrap(), gm["params"]["correlation_time_s"].as_f64().unwrap());
    let n = doc["baseline_terms"]["n"].as_f64().unwrap();
    assert!(sigma * tau.sqrt() < n, "σ {sigma}, τ {tau}, N {n}");
    assert_eq!(gm["supported"], false, "{gm}");
    assert_eq!(doc["verdict"], "no_significant_gap", "{doc}");
}

/// A warm-up with small spikes beside it (report seed 763, the generator's
/// "warmup+small_spikes": 3,371 s at 10 Hz on its quiet floor): the spikes enter the model first
/// (they move the distribution statistics most), but the warm-up, the cause of the drift, is named
/// first (src/diag/simgap/naming.rs). The sixth session's diagnosis named the spikes.
#[test]
fn a_warm_up_is_named_before_the_small_spikes_beside_it() {
    if !numpy_or_skip("a_warm_up_is_named_before_the_small_spikes_beside_it") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (case, doc) = one_case(dir.path(), "763", "dominant");
    assert_eq!(case["sub"], "warmup+small_spikes");
    let (tried, chosen) = (names(&doc, "tried"), names(&doc, "chosen"));
    assert_eq!(tried.first().copied(), Some("spikes"), "added first: {tried:?}");
    assert_eq!(chosen.first().copied(), Some("warmup"), "named first: {chosen:?} ({})", doc["verdict"]);
    assert!(chosen.contains(&"spikes"), "{chosen:?}");
}

/// Spikes alone (report seed 3095, the generator's "spikes": 53 per hour of about 1.2 deg/s over
/// 3,915 s at 10 Hz on its flat nominal floor): they move the drift groups of the baseline too,
/// and after them a ramp of 15 deg/h² is kept for a small further gain. The spikes, once
/// simulated, leave no drift gap, so the ramp is not their cause and the spikes are named first.
/// Until the twenty-second session the baseline's drift gap alone decided, and the ramp was named.
/// Since the thirtieth session (the whole part's line beside the Welch line in the spectral
/// group) the ramp's further gain falls short and the spikes are kept alone; the rule itself is
/// pinned by `naming`'s unit test.
#[test]
fn spikes_are_named_first_and_a_small_ramp_only_after_them() {
    if !numpy_or_skip("spikes_are_named_first_and_a_small_ramp_only_after_them") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (case, doc) = one_case(dir.path(), "3095", "spikes");
    assert_eq!(case["floor"], "nominal_flat");
    let tried = names(&doc, "tried");
    assert!(tried[0] == "spikes" && tried[1..].iter().all(|&k| k == "ramp"), "added: {tried:?}");
    assert_eq!(named_first(&doc), Some("spikes"), "{}: {}", doc["verdict"], doc["chosen"]);
}

/// A Gauss–Markov process that the fitted IEEE terms absorb (report seed 842, the generator's
/// "gauss_markov": σ = 0.0027 deg/s, 18 s, on its quiet floor; 3,207 s at 10 Hz): the baseline
/// shows no significant gap on either part, and the nested-model test (src/diag/simgap/nested.rs,
/// the bootstrapped Whittle likelihood ratio) finds the process, which is then named. The seventh
/// session's diagnosis answered "no significant gap" here. Since the sixteenth session it also
/// names one of 0.012 deg/s and 23 s on the nominal floor (report seed 759, 4,420 s), which the
/// test finds only on the whole recording (Λ 23.0 against a threshold of 12.6), not on the
/// training part (13.5 against 13.9).
#[test]
fn an_absorbed_gauss_markov_process_is_found_by_the_nested_test() {
    if !numpy_or_skip("an_absorbed_gauss_markov_process_is_found_by_the_nested_test") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (_, doc) = absorbed_then_named(dir.path(), "842");
    let nested = &effect(&doc, "gauss_markov")["nested"];
    assert_eq!(nested["passed"], true, "{nested}");
    assert!(nested["statistic"].as_f64().unwrap() > 2.0 * nested["threshold"].as_f64().unwrap(), "{nested}");
    let dir = tempfile::tempdir().unwrap();
    let (case, _) = absorbed_then_named(dir.path(), "759");
    assert_eq!(case["floor"], "nominal");
}

/// A temperature response that the fitted IEEE terms absorb (report seed 639, the generator's
/// "temperature": −0.0016 deg/s/°C on its quiet floor, in the high magnitude bin; 4,664 s at
/// 10 Hz): the baseline shows no significant gap on either part, the own-null route's matched
/// filter (the least-squares slope of 1 s means on the temperature) stays inside its band, and
/// the nested-model test (src/diag/simgap/nested_temperature.rs, the Whittle likelihood with and
/// without c·T(t), c weighted by the inverse noise spectrum) finds it at about twice its
/// threshold (Λ 17.9 against 8.8), so temperature is named. Until the twenty-first session the
/// diagnosis answered "no significant gap" here.
#[test]
fn an_absorbed_temperature_response_is_found_by_the_nested_test() {
    if !numpy_or_skip("an_absorbed_temperature_response_is_found_by_the_nested_test") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (case, doc) = one_case(dir.path(), "639", "temperature");
    assert_eq!(case["floor"], "quiet");
    assert!(!baseline_shows_a_gap(&doc), "the baseline alone shows a gap: {}", doc["before"]);
    let temperature = effect(&doc, "temperature");
    assert_eq!(temperature["detector"]["passed"], false, "{}", temperature["detector"]);
    let nested = &temperature["nested"];
    assert_eq!(nested["passed"], true, "{nested}");
    assert!(nested["statistic"].as_f64().unwrap() > 1.5 * nested["threshold"].as_f64().unwrap(), "{nested}");
    assert_eq!(named_first(&doc), Some("temperature"), "{}", doc["verdict"]);
}

/// Bias jumps whose one detected step falls in the hold-out part (report seed 695, the
/// generator's "few_large_steps": two steps over 3,217 s at 10 Hz on its quiet floor): the
/// training part shows no gap and no step, and the hold-out's step is a significant gap. Until the
/// twenty-second session the jumps' rate was counted on the training part alone, zero here, and
/// the verdict was "unexplained"; the steps of the whole recording now count (a point process's
/// next event cannot be placed, only its rate estimated: src/diag/simgap/fit_events.rs), and the
/// jumps explain the hold-out's gap.
#[test]
fn a_step_in_the_holdout_part_is_named_a_bias_jump() {
    if !numpy_or_skip("a_step_in_the_holdout_part_is_named_a_bias_jump") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (case, doc) = one_case(dir.path(), "695", "bias_jumps");
    assert_eq!(case["floor"], "quiet");
    assert_eq!(doc["before"]["train"]["significant"], false, "{}", doc["before"]["train"]);
    assert_eq!(doc["before"]["holdout"]["significant"], true, "{}", doc["before"]["holdout"]);
    let jumps = effect(&doc, "bias_jumps");
    assert_eq!(jumps["params"]["detected"].as_f64(), Some(1.0), "{jumps}");
    assert_eq!(jumps["explains"], true, "{jumps}");
    assert_eq!(named_first(&doc), Some("bias_jumps"), "{}", doc["verdict"]);
}

/// Steps a few minutes apart that the fitted terms take in (report seed 3203, `bias_jumps_mid`:
/// steps of ±0.026 deg/s, about every 300 s on the white-noise-and-random-walk floor, a quarter of
/// the per-sample noise each): the baseline shows no significant gap on either part, and until
/// the twenty-eighth session nothing was named. The step process' nested test (a piecewise-constant
/// level against a random walk, src/diag/simgap/nested_jumps.rs) finds it, `bias_jumps` is named
/// first, and its fitted step size is within a quarter of the injected one.
#[test]
fn steps_minutes_apart_that_the_fitted_terms_absorb_are_found_by_their_nested_test() {
    if !numpy_or_skip("steps_minutes_apart_that_the_fitted_terms_absorb_are_found_by_their_nested_test") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (case, doc) = one_case(dir.path(), "3203", "bias_jumps_mid");
    assert_eq!(case["floor"], "nominal_flat");
    assert!(!baseline_shows_a_gap(&doc), "the baseline alone shows a gap: {}", doc["before"]);
    let jumps = effect(&doc, "bias_jumps");
    assert_eq!(jumps["nested"]["passed"], true, "{jumps}");
    assert_eq!(named_first(&doc), Some("bias_jumps"), "{}: {}", doc["verdict"], doc["chosen"]);
    let injected = case["magnitude"].as_f64().unwrap() * case["floor_scale"].as_f64().unwrap();
    let fitted = jumps["params"]["size_dps"].as_f64().unwrap();
    assert!((fitted / injected - 1.0).abs() < 0.25, "fitted step {fitted} against injected {injected}");
}

/// Seven steps of normal sizes (RMS 0.0037 deg/s, 0.4 of the per-sample noise) over 3,041 s on
/// the quiet floor (report seed 682, `few_large_steps`): the window detector (60 s means against
/// their robust σ) holds one of them, and with one step fitted the bias jumps ranked below a
/// temperature response, which was named first. The step process' nested test passes, and its
/// segmentation's change points (more than the window detector's) are the steps fitted now: at
/// least five of the seven, and `bias_jumps` named first.
#[test]
fn the_segmentation_fits_the_steps_where_it_finds_more_than_the_window_detector() {
    if !numpy_or_skip("the_segmentation_fits_the_steps_where_it_finds_more_than_the_window_detector") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (case, doc) = one_case(dir.path(), "682", "bias_jumps");
    assert_eq!((case["sub"].as_str(), case["params"]["jumps"].as_u64()), (Some("few_large_steps"), Some(7)));
    let jumps = effect(&doc, "bias_jumps");
    assert_eq!(jumps["nested"]["passed"], true, "{jumps}");
    let detected = jumps["params"]["detected"].as_f64().unwrap();
    assert!((5.0..=9.0).contains(&detected), "{jumps}");
    assert_eq!(named_first(&doc), Some("bias_jumps"), "{}: {}", doc["verdict"], doc["chosen"]);
}

/// The Gauss–Markov case of report `seed`, diagnosed into `dir`: the baseline alone shows no
/// significant gap on either part, and `gauss_markov` is named first. Its manifest entry and JSON
/// document.
fn absorbed_then_named(dir: &Path, seed: &str) -> (Value, Value) {
    let (case, doc) = one_case(dir, seed, "gauss_markov");
    assert!(!baseline_shows_a_gap(&doc), "seed {seed}: the baseline alone shows a gap: {}", doc["before"]);
    assert_eq!(
        named_first(&doc),
        Some("gauss_markov"),
        "seed {seed} ({}): {}: {}",
        case["floor"],
        doc["verdict"],
        doc["chosen"]
    );
    (case, doc)
}

/// The warm-up of `doc` with its time constant at the grid's edge (the training part's length),
/// and how much better its ranking score (`log_score`, the mean of both parts') is than the
/// ramp's.
fn unbounded_warmup_lead(doc: &Value) -> f64 {
    let (warmup, ramp) = (effect(doc, "warmup"), effect(doc, "ramp"));
    let train_s = doc["train_samples"].as_f64().unwrap() / doc["rate_hz"].as_f64().unwrap();
    let tc = warmup["params"]["time_constant_s"].as_f64().unwrap();
    assert!((tc - train_s).abs() < 1e-6 * train_s, "the warm-up fit is bounded here: {tc} s of {train_s} s");
    ramp["log_score"].as_f64().unwrap() - warmup["log_score"].as_f64().unwrap()
}

/// A ramp (report seed 649, the generator's "ramp": +0.17 deg/s over 3,906 s at 10 Hz on its
/// nominal floor): the warm-up fit sits at the longest time constant of its grid (the training
/// part's length) and scored a little better than the ramp, so the ninth session named a warm-up.
/// The unbounded exponential is now ranked after the ramp unless it leads by more than the margin
/// (src/diag/simgap/greedy.rs, "parsimony at the warm-up grid's edge"), and the ramp is named.
#[test]
fn a_ramp_is_not_named_a_warm_up_whose_time_constant_the_data_do_not_bound() {
    if !numpy_or_skip("a_ramp_is_not_named_a_warm_up_whose_time_constant_the_data_do_not_bound") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (_, doc) = one_case(dir.path(), "649", "ramp");
    let lead = unbounded_warmup_lead(&doc);
    assert!(lead > 0.0 && lead <= EDGE_MARGIN, "the warm-up's lead over the ramp is {lead}");
    assert_eq!(named_first(&doc), Some("ramp"), "{}: {}", doc["verdict"], doc["chosen"]);
}

/// A warm-up of 51 minutes in a recording of 77 (tuning seed 1050, the generator's `long_warmup`,
/// the failure 4: 2.46 deg/s, T = 3,038 s over 4,648 s at 10 Hz on its noisy floor): over
/// the training part it is nearly straight, so its fit sits at the grid's edge too, but its
/// hold-out part levels off where a ramp would go on, and it leads the ramp by far more than the
/// margin. Until the fortieth session it was named a ramp.
#[test]
fn a_long_warm_up_that_levels_off_in_the_holdout_part_is_not_named_a_ramp() {
    if !numpy_or_skip("a_long_warm_up_that_levels_off_in_the_holdout_part_is_not_named_a_ramp") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (case, doc) = one_tuning_case(dir.path(), "1050", "long_warmup");
    assert!(case["time_scale_s"].as_f64().unwrap() >= 900.0, "{case}");
    let lead = unbounded_warmup_lead(&doc);
    assert!(lead > EDGE_MARGIN, "the warm-up's lead over the ramp is only {lead}");
    let (warmup, ramp) = (effect(&doc, "warmup"), effect(&doc, "ramp"));
    let hold = |e: &Value| e["log_score_holdout"].as_f64().unwrap();
    assert!(hold(ramp) - hold(warmup) > lead, "the lead is not the hold-out part's: {warmup} {ramp}");
    assert_eq!(named_first(&doc), Some("warmup"), "{}: {}", doc["verdict"], doc["chosen"]);
}

/// A slow ramp that the fitted IEEE terms take in (tuning seed 1844, the case the ramp's matched
/// filter was chosen on: -0.031 deg/s over 4,151 s at 10 Hz on the generator's nominal_flat floor,
/// oracle z 9.7): the baseline alone shows no significant gap, and before the seventeenth session
/// nothing was named. The ramp's detector (`ramp_change`, the line through the 1 s means) stands
/// out against its own null beyond the Bonferroni level, sits inside the ramp model's band, and
/// leans the same way in the hold-out part, so the ramp is named.
#[test]
fn a_slow_ramp_the_fitted_terms_absorb_is_found_by_its_matched_filter() {
    if !numpy_or_skip("a_slow_ramp_the_fitted_terms_absorb_is_found_by_its_matched_filter") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (_, doc) = one_tuning_case(dir.path(), "1844", "ramp");
    assert!(!baseline_shows_a_gap(&doc), "the baseline alone shows a gap: {}", doc["before"]);
    let ramp = effect(&doc, "ramp");
    let detector = &ramp["detector"];
    assert_eq!(detector["statistic"], "ramp_change");
    let (z_null, z_hold) = (detector["z_null"].as_f64().unwrap(), detector["z_null_holdout"].as_f64().unwrap());
    assert!(z_null.abs() > 3.23 && z_null * z_hold > 0.0, "{detector}");
    assert!(detector["passed"].as_bool().unwrap(), "{detector}");
    assert_eq!(named_first(&doc), Some("ramp"), "{}: {}", doc["verdict"], doc["chosen"]);
}

/// A faint line (tuning seed 2749, one of the cases the whole-part line search was measured on:
/// 0.0007 deg/s at 0.083 Hz over 3,023 s at 10 Hz on the quiet floor, oracle z 9.1). The Hann
/// search of the sinusoid's fit took a noise ordinate at 0.80 Hz for the strongest line, the
/// baseline alone showed no significant gap and nothing was named. The whole part's rectangular
/// periodogram holds the line, its fit (the second candidate) evaluates better, and its matched
/// filter (`fast_line`) passes against the own null: the sinusoid is named, at the injected
/// frequency.
#[test]
fn a_faint_line_is_fitted_from_the_whole_periodogram_and_named() {
    if !numpy_or_skip("a_faint_line_is_fitted_from_the_whole_periodogram_and_named") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (case, doc) = one_tuning_case(dir.path(), "2749", "sinusoid");
    let sinusoid = effect(&doc, "sinusoid");
    let injected = case["params"]["frequency_hz"].as_f64().unwrap();
    let fitted = sinusoid["params"]["frequency_hz"].as_f64().unwrap();
    assert!((fitted / injected - 1.0).abs() < 0.01, "fitted {fitted} Hz against {injected} Hz");
    assert_eq!(sinusoid["detector"]["statistic"], "fast_line", "{sinusoid}");
    assert_eq!(named_first(&doc), Some("sinusoid"), "{}: {}", doc["verdict"], doc["chosen"]);
}

/// A slow sinusoid under dominant spikes (tuning seed 2473, the case the thirty-ninth session's
/// change was made on: 0.26 deg/s at 0.0081 Hz with 106 spikes of about 6.8 deg/s, 3,411 s at
/// 10 Hz on the noisy floor). Alone beside the baseline, whose every score the spikes' misfit of
/// the distribution sets, the sinusoid's fit at a noise line of the whole periodogram scores best
/// and is the one listed; the greedy combination keeps the spikes first and then, trying every
/// candidate fit beside them, the Hann search's slow line, which explains the rest; the sinusoid,
/// the bias motion, is named first. Until then only the listed fit was tried beside the spikes
/// and the case was "partly explained" by the spikes.
#[test]
fn beside_spikes_the_sinusoid_is_kept_with_its_slow_line_fit() {
    if !numpy_or_skip("beside_spikes_the_sinusoid_is_kept_with_its_slow_line_fit") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (case, doc) = one_tuning_case(dir.path(), "2473", "dominant");
    assert_eq!(case["sub"], "sinusoid+small_spikes");
    let injected = case["params"]["frequency_hz"].as_f64().unwrap();
    let listed = effect(&doc, "sinusoid")["params"]["frequency_hz"].as_f64().unwrap();
    assert!(listed > 100.0 * injected, "the fit that scores best alone is a noise line: {listed} Hz");
    let tried = names(&doc, "tried");
    assert_eq!(tried, ["spikes", "sinusoid"], "added: {tried:?}");
    let kept = doc["tried_params"][1]["frequency_hz"].as_f64().unwrap();
    assert!((kept / injected - 1.0).abs() < 0.01, "kept {kept} Hz against {injected} Hz");
    assert_eq!(doc["verdict"], "explained");
    assert_eq!(named_first(&doc), Some("sinusoid"), "{}", doc["chosen"]);
    // The text and HTML reports say which fit the final model holds, beside the table's listed one.
    let path = dir.path().join(case["file"].as_str().unwrap());
    let html = dir.path().join("report");
    let out = Command::new(env!("CARGO_BIN_EXE_gyrocomp"))
        .args(["simgap", "--real", path.to_str().unwrap(), "--threads", "2", "--report", html.to_str().unwrap()])
        .output()
        .expect("run gyrocomp");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let line = text.lines().find(|l| l.starts_with("Kept with another of its candidate fits")).unwrap_or_default();
    assert!(line.contains("sinusoid") && line.contains("frequency_hz=8.1"), "text report: {text}");
    let page = std::fs::read_to_string(html.join("index.html")).unwrap();
    assert!(page.contains("sinusoid is kept with another of its candidate fits"), "HTML report");
}

/// A warm-up and a ramp that the fitted IEEE terms take in (tuning seeds 2500 and 2642, cases the
/// twenty-sixth session's nested tests were measured on): 0.94 deg/s settling over 369 s on the
/// noisy floor (3,576 s, oracle z 12; the Allan-fitted K is 19× the floor's), and 0.035 deg/s over
/// 3,991 s on white noise and a random walk (oracle z 11). The baseline alone shows no gap, and
/// the effects' own matched filters do not pass against their own nulls: nothing was named. The
/// nested tests (the Whittle likelihood with and without the exponential; the generalised
/// least-squares slope under the terms fitted to the detrended recording) find them.
#[test]
fn an_absorbed_warm_up_and_ramp_are_found_by_their_nested_tests() {
    if !numpy_or_skip("an_absorbed_warm_up_and_ramp_are_found_by_their_nested_tests") {
        return;
    }
    for (seed, class, name) in [("2500", "warmup", "warmup"), ("2642", "ramp", "ramp")] {
        let dir = tempfile::tempdir().unwrap();
        let (_, doc) = one_tuning_case(dir.path(), seed, class);
        assert!(!baseline_shows_a_gap(&doc), "seed {seed}: the baseline alone shows a gap: {}", doc["before"]);
        let nested = &effect(&doc, name)["nested"];
        assert!(nested["passed"].as_bool().unwrap(), "seed {seed}: {nested}");
        assert!(
            !effect(&doc, name)["detector"]["passed"].as_bool().unwrap(),
            "seed {seed}: the detector alone finds it"
        );
        assert_eq!(named_first(&doc), Some(name), "seed {seed}: {}: {}", doc["verdict"], doc["chosen"]);
    }
}

/// The oracle's evidence (tools/simgap/oracle.py, the upper bound the confusion matrix is binned
/// by) reproduces its closed forms: the floor's block-mean covariance equals the samples'
/// covariance summed over blocks (white, Gauss–Markov bank, rate random walk); a ramp and a
/// sinusoid on white noise have z² = Σ(e − ē)²/σ² and nA²/(2σ²); a weak Gauss–Markov process has
/// E[Λ] ≈ Σ(S_gm/S)². The fitted-levels oracle (the floor's IEEE levels unknown) gives a ramp on
/// white noise at most the known floor's evidence, a fast sinusoid the same, and more rate random
/// walk none. And every generated case carries both: numbers, or null for quantisation.
#[test]
fn the_oracle_evidence_matches_its_closed_forms() {
    if !numpy_or_skip("the_oracle_evidence_matches_its_closed_forms") {
        return;
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/simgap/oracle.py");
    let out = Command::new("python3").arg(script).output().expect("run python3");
    assert!(out.status.success(), "oracle self-check: {}", String::from_utf8_lossy(&out.stderr));
    let dir = tempfile::tempdir().unwrap();
    let cases = generate(
        dir.path(),
        &["--first-seed", "11", "--per-class", "1", "--durations", "3000,3000", "--classes", "ramp,quantization"],
    );
    assert!(cases[0]["oracle_z"].as_f64().is_some_and(|z| z > 0.0), "{}", cases[0]);
    assert!(cases[0]["oracle_z_fitted"].as_f64().is_some_and(|z| z > 0.0), "{}", cases[0]);
    assert!(cases[1]["oracle_z"].is_null() && cases[1]["oracle_z_fitted"].is_null(), "{}", cases[1]);
}

/// What the fitted-levels oracle says of the cases the evaluation names (docs/evaluation.md,
/// twenty-seventh session): a Gauss–Markov process of 206 s on a 4,429 s recording (report 754)
/// is plain to a test that knows the floor (z 29.5) and under 5 σ to one that fits its levels,
/// since the fitted rate random walk takes it in but for the lowest bins; a sinusoid of 0.46 Hz
/// (report 672), which no IEEE term resembles, keeps its evidence.
#[test]
fn the_fitted_levels_oracle_separates_absorbed_from_visible_effects() {
    if !numpy_or_skip("the_fitted_levels_oracle_separates_absorbed_from_visible_effects") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let absorbed = &generate(dir.path(), &["--first-seed", "754", "--per-class", "1", "--classes", "gauss_markov"])[0];
    let (known, fitted) = (absorbed["oracle_z"].as_f64().unwrap(), absorbed["oracle_z_fitted"].as_f64().unwrap());
    assert!(known > 20.0 && fitted < 5.0, "754: known {known}, fitted {fitted}");
    let other = tempfile::tempdir().unwrap();
    let line = &generate(other.path(), &["--first-seed", "672", "--per-class", "1", "--classes", "sinusoid"])[0];
    let (known, fitted) = (line["oracle_z"].as_f64().unwrap(), line["oracle_z_fitted"].as_f64().unwrap());
    assert!((fitted / known - 1.0).abs() < 0.05, "672: known {known}, fitted {fitted}");
}

/// The steps' Gaussianity check (tools/simgap/step_gaussianity.py, the evidence the evaluation
/// gives for many small steps): steps of ten window-difference σ every ten minutes stand out from
/// phase-randomised surrogates of the recording, a Gaussian rate random walk does not.
#[test]
fn the_step_gaussianity_check_sees_steps_and_not_a_random_walk() {
    if !numpy_or_skip("the_step_gaussianity_check_sees_steps_and_not_a_random_walk") {
        return;
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/simgap/step_gaussianity.py");
    let out = Command::new("python3").arg(script).arg("--selfcheck").output().expect("run python3");
    assert!(out.status.success(), "step gaussianity self-check: {}", String::from_utf8_lossy(&out.stderr));
}

/// The case's noise floor as a `gyrocomp sim` config (tools/simgap/score.py `floor_sim_toml`,
/// the bias from the training part), written into `dir`; its path.
fn floor_sim(dir: &Path, case: &Value) -> std::path::PathBuf {
    let tools = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/simgap");
    let code = "import json, sys; sys.path.insert(0, sys.argv[1]); import score; \
                m = json.load(open(sys.argv[2] + '/manifest.json')); \
                case = [c for c in m['cases'] if c['seed'] == int(sys.argv[3])][0]; \
                print(score.given_floor_args(sys.argv[2], case, m['floors'], sys.argv[2])[1])";
    let out = Command::new("python3")
        .args(["-c", code, tools.to_str().unwrap(), dir.to_str().unwrap(), &case["seed"].to_string()])
        .output()
        .expect("run python3");
    assert!(out.status.success(), "floor_sim_toml: {}", String::from_utf8_lossy(&out.stderr));
    std::path::PathBuf::from(String::from_utf8(out.stdout).unwrap().trim())
}

/// The sim-to-real use: the simulator was set up before the recording, so the diagnosis is given
/// it (`--sim`) instead of fitting the IEEE terms to the recording. A Gauss–Markov process of
/// 0.0010 deg/s and 42 s on the generator's quiet floor (report seed 758, 4,571 s at 10 Hz) is
/// taken by the fitted terms into their bias instability and rate random walk (no significant
/// gap, nested test below its threshold), and found once the floor is given (its Gauss–Markov
/// bank approximated by a flicker floor) — report seed 759, used here until the sixteenth
/// session, is now found with fitted terms too
/// ([`an_absorbed_gauss_markov_process_is_found_by_the_nested_test`]); a warm-up beside a small
/// Gauss–Markov process is named first (the detector test runs against the given model); the
/// floor alone (report seed 2, the noisy floor) still shows no gap.
#[test]
fn with_its_simulator_given_the_diagnosis_finds_what_the_fitted_terms_absorb() {
    if !numpy_or_skip("with_its_simulator_given_the_diagnosis_finds_what_the_fitted_terms_absorb") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cases = generate(dir.path(), &["--first-seed", "758", "--per-class", "1", "--classes", "gauss_markov"]);
    let case = &cases[0];
    assert_eq!(case["sub"], "gm_1min");
    assert_eq!(outcome(dir.path(), case, &["--threads", "2"]), "none", "the fitted terms no longer absorb it");
    let sim = floor_sim(dir.path(), case);
    let given = ["--threads", "2", "--sim", sim.to_str().unwrap()];
    assert_eq!(outcome(dir.path(), case, &given), "gauss_markov");
    // A warm-up beside a small Gauss–Markov process (report seed 775, quiet floor): with the
    // floor given, the warm-up's own detector, tested against the given model, puts it first.
    let dominant = generate(dir.path(), &["--first-seed", "775", "--per-class", "1", "--classes", "dominant"]);
    assert_eq!(dominant[0]["sub"], "warmup+small_gauss_markov");
    let sim = floor_sim(dir.path(), &dominant[0]);
    assert_eq!(outcome(dir.path(), &dominant[0], &["--threads", "2", "--sim", sim.to_str().unwrap()]), "warmup");
    let control_dir = tempfile::tempdir().unwrap();
    let controls = generate(control_dir.path(), &["--first-seed", "2", "--per-class", "1", "--classes", "none"]);
    let sim = floor_sim(control_dir.path(), &controls[0]);
    let given = ["--threads", "2", "--sim", sim.to_str().unwrap()];
    assert_eq!(outcome(control_dir.path(), &controls[0], &given), "none", "floor {}", controls[0]["floor"]);
}

/// A Gauss–Markov process of 0.035 deg/s and 217 s on white noise and a rate random walk
/// (tuning seed 2559, 4,019 s at 10 Hz, oracle z 61): the fitted terms take it for a random walk
/// 80 times the floor's, and until the twenty-third session the effect's own fit put it at 0.2 s
/// (two samples, the grid's edge), so even with the floor given nothing explained the gap. Its
/// correlation time is now fitted within a factor of two, and with the floor given it is named.
#[test]
fn a_gauss_markov_process_of_minutes_is_fitted_at_its_own_time_scale() {
    if !numpy_or_skip("a_gauss_markov_process_of_minutes_is_fitted_at_its_own_time_scale") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cases = generate_in_range(
        dir.path(),
        &["--first-seed", "2559", "--per-class", "1", "--classes", "gauss_markov"],
        "tuning",
    );
    let case = &cases[0];
    assert_eq!(case["floor"], "nominal_flat");
    let sim = floor_sim(dir.path(), case);
    let doc = diagnose(dir.path(), case, &["--threads", "2", "--sim", sim.to_str().unwrap()]);
    let gm = effect(&doc, "gauss_markov");
    let corr = gm["params"]["correlation_time_s"].as_f64().unwrap();
    let injected = case["time_scale_s"].as_f64().unwrap();
    assert!((0.5..2.0).contains(&(corr / injected)), "fitted {corr} s against {injected} s: {gm}");
    assert_eq!(named_first(&doc), Some("gauss_markov"), "{}: {}", doc["verdict"], doc["chosen"]);
}

/// The report set of docs/evaluation.md ("Independent cases": `independent_cases.py DIR
/// --first-seed 1 --per-class 3`, default diagnosis settings), on the classes it gets mostly right
/// (sinusoid 3/3, quantization 3/3, spikes 2/3 measured) and the pure-IEEE control (3/3): each
/// class at least its measured count minus one, the control exactly. Heavy (12 diagnoses of 3,000–5,000 s), so ignored by default:
/// `cargo test --release --test simgap_independent -- --ignored`.
#[test]
#[ignore = "12 diagnoses; run with --release -- --ignored"]
fn report_seeds_keep_the_measured_confusion() {
    if !numpy_or_skip("report_seeds_keep_the_measured_confusion") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cases = generate(dir.path(), &["--first-seed", "1", "--per-class", "3"]);
    for (class, least) in MEASURED {
        let right = cases
            .iter()
            .filter(|c| c["klass"] == *class)
            .filter(|c| outcome(dir.path(), c, &["--threads", "2"]) == c["expected"].as_str().unwrap())
            .count();
        assert!(right >= *least, "{class}: {right} of 3 right, at least {least} expected");
    }
}

/// (class, least right of 3): the count measured on the report set minus one; the control exact.
const MEASURED: &[(&str, usize)] = &[("sinusoid", 2), ("quantization", 2), ("spikes", 1), ("none", 3)];
