//! `gyrocomp simgap`: the sim-to-real gap diagnosis of one rate column (where the simulation
//! differs, which unmodelled effect explains it, how far the gap shrinks on the held-out part), as
//! text, JSON or an HTML report; `--selftest` runs the diagnosis on simulated recordings with a
//! known effect and prints the confusion table.

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use serde::Serialize;
use serde_json::{Map, Value};

use super::CliError;
use super::input::load_series;
use super::simgap_report::write_report;
use super::simgap_selftest::run_selftest_cli;
use crate::diag::simgap::baseline::NoiseTerms;
use crate::diag::simgap::gap::{Flag, PartComparison};
use crate::diag::simgap::stats::{StatInfo, fmt_num};
use crate::diag::simgap::{Baseline, Diagnosis, Recording, Settings, Verdict, diagnose};
use crate::sim::SimConfig;

/// Arguments of `gyrocomp simgap`.
#[derive(Debug, clap::Args)]
pub struct SimgapArgs {
    /// The real recording: CSV with a header, time column `t_s` (or `t`, `time`), rates in deg/s,
    /// optionally `temp_c` (then `temperature` is a candidate effect).
    /// An MCAP bag (sensor_msgs/msg/Imu) or a EuRoC CSV is read as well.
    #[arg(long, required_unless_present = "selftest")]
    pub real: Option<PathBuf>,
    /// Input format options (MCAP topic, CSV units).
    #[command(flatten)]
    pub input_opts: super::input::InputArgs,
    /// Rate column to diagnose, deg/s.
    #[arg(long, default_value = "gx_dps")]
    pub column: String,
    /// Simulator config (TOML, as `gyrocomp sim --config`) to diagnose instead of the IEEE Std 952
    /// terms fitted to the recording; the axis matching the column (gx → x, gy → y, gz → z) is used.
    #[arg(long)]
    pub sim: Option<PathBuf>,
    /// Share of the recording held out at its end; effects are fitted on the rest.
    #[arg(long, default_value_t = 0.3)]
    pub holdout: f64,
    /// Seed of the simulated ensemble (and of the self-test).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Members of each simulated ensemble (≥ 8).
    #[arg(long, default_value_t = 32)]
    pub ensemble: usize,
    /// Share of the excess gap² an added effect must remove on every part with a significant gap
    /// (whether the result explains the gap is decided on the hold-out part).
    #[arg(long, default_value_t = 0.25)]
    pub min_share: f64,
    /// Most effects combined.
    #[arg(long, default_value_t = 3)]
    pub max_effects: usize,
    /// Worker threads for the ensembles (results do not depend on it).
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// Sample rate in Hz (default: from the time column).
    #[arg(long)]
    pub rate: Option<f64>,
    /// Print JSON: {"gap_before","gap_after","where":[…],"effects":[…],"chosen":[…],…}.
    #[arg(long)]
    pub json: bool,
    /// Write an HTML report with SVG plots into this folder (index.html).
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Run the self-test instead: simulated recordings with a known injected effect.
    #[arg(long)]
    pub selftest: bool,
    /// Self-test: seeded cases per effect and per control.
    #[arg(long, default_value_t = 10)]
    pub cases: usize,
    /// Self-test: length of each simulated recording, s (at 10 Hz).
    #[arg(long, default_value_t = 10000.0)]
    pub duration: f64,
    /// Self-test: only these kinds of case (effect names, `none`, `chirp`; default all).
    #[arg(long, value_delimiter = ',')]
    pub only: Option<Vec<String>>,
    /// Self-test: factor on every injected magnitude (1 = the documented ranges; smaller values
    /// measure how small an effect is still found).
    #[arg(long, default_value_t = 1.0)]
    pub magnitude: f64,
}

impl SimgapArgs {
    /// The diagnosis settings of these arguments.
    pub fn settings(&self) -> Settings {
        Settings {
            holdout: self.holdout,
            ensemble: self.ensemble,
            seed: self.seed,
            min_share: self.min_share,
            max_effects: self.max_effects,
            threads: self.threads.max(1),
        }
    }
}

/// Runs `gyrocomp simgap`.
pub fn run(args: &SimgapArgs) -> Result<(), CliError> {
    if args.selftest {
        return run_selftest_cli(args);
    }
    let path = args.real.as_ref().ok_or("--real FILE is required (or --selftest)")?;
    let series = load_series(path, &args.column, args.rate, &args.input_opts.options())?;
    let temp_c = match series.temp_c {
        Some(t) if t.iter().all(|v| v.is_finite()) => Some(t),
        Some(_) => {
            tracing::warn!(
                "{}: temp_c has empty or non-finite rows; the temperature effect is skipped",
                path.display()
            );
            None
        }
        None => None,
    };
    let baseline = match &args.sim {
        Some(file) => {
            let text = std::fs::read_to_string(file).map_err(|e| format!("{}: cannot read: {e}", file.display()))?;
            let config = SimConfig::from_toml(&text).map_err(|e| format!("{}: {e}", file.display()))?;
            if (config.rate_hz - series.rate_hz).abs() > 1e-6 * series.rate_hz {
                tracing::warn!(
                    "{}: rate_hz {} differs from the recording's {} Hz; the recording's rate is simulated",
                    file.display(),
                    config.rate_hz,
                    series.rate_hz
                );
            }
            Baseline::Given(Box::new(config.axis_model(axis_of_column(&args.column))))
        }
        None => Baseline::Fitted,
    };
    let recording = Recording { rate: &series.values, rate_hz: series.rate_hz, temp_c: temp_c.as_deref() };
    let started = Instant::now();
    let diagnosis = diagnose(&recording, &baseline, &args.settings())
        .map_err(|e| format!("{}: column `{}`: {e}", path.display(), args.column))?;
    let seconds = started.elapsed().as_secs_f64();
    tracing::info!("diagnosis took {seconds:.1} s ({} ensembles of {})", diagnosis.ensembles_run, args.ensemble);
    let mut out = std::io::stdout().lock();
    if args.json {
        serde_json::to_writer(&mut out, &json_report(args, &diagnosis))?;
        writeln!(out)?;
    } else {
        write_text(&mut out, args, &diagnosis, seconds)?;
    }
    if let Some(dir) = &args.report {
        let file = write_report(dir, args, &diagnosis)?;
        if !args.json {
            writeln!(out, "\nReport: {}", file.display())?;
        }
    }
    out.flush()?;
    Ok(())
}

/// The simulator axis of a column name: `g?x…`/`…x_dps` → x, y, z (x when unclear).
fn axis_of_column(column: &str) -> usize {
    let name = column.to_ascii_lowercase();
    ["x", "y", "z"]
        .iter()
        .position(|a| name.starts_with(&format!("g{a}")) || name.contains(&format!("{a}_")))
        .unwrap_or(0)
}

/// One entry of `where`.
#[derive(Debug, Serialize)]
pub struct WhereEntry {
    /// Kind of statistic.
    pub statistic: &'static str,
    /// τ, band, scale or time span.
    pub band: String,
    /// Real value (natural unit).
    pub real: f64,
    /// Ensemble 2.5 % quantile.
    pub sim_lo: f64,
    /// Ensemble 97.5 % quantile.
    pub sim_hi: f64,
    /// Ensemble median.
    pub sim_median: f64,
    /// Standard score of the real value in the band.
    pub z: f64,
    /// Unit of the values.
    pub unit: &'static str,
}

/// The statistics of `part` outside their band, largest |z| first.
pub fn where_entries(info: &[StatInfo], part: &PartComparison) -> Vec<WhereEntry> {
    part.outside_by_size()
        .into_iter()
        .map(|i| {
            let (s, b) = (&info[i], &part.bands[i]);
            WhereEntry {
                statistic: s.statistic,
                band: s.band.clone(),
                real: s.natural(part.real[i]),
                sim_lo: s.natural(b.lo),
                sim_hi: s.natural(b.hi),
                sim_median: s.natural(b.median),
                z: part.z[i],
                unit: s.unit,
            }
        })
        .collect()
}

fn params_map(params: &[(&'static str, f64)]) -> Map<String, Value> {
    params.iter().map(|&(k, v)| (k.to_owned(), Value::from(v))).collect()
}

fn json_report<'a>(args: &'a SimgapArgs, d: &Diagnosis) -> JsonReport<'a> {
    let effects: Vec<Value> = d
        .effects
        .iter()
        .map(|e| {
            let mut m = Map::new();
            m.insert("name".into(), e.kind.name().into());
            m.insert(
                "params".into(),
                Value::Object(params_map(&e.params.as_ref().map_or_else(Vec::new, |p| p.named()))),
            );
            m.insert("gap".into(), e.evaluation.as_ref().map(|v| v.train.score.gap).into());
            m.insert("gap_holdout".into(), e.evaluation.as_ref().map(|v| v.hold.score.gap).into());
            m.insert("explains".into(), e.accepted().into());
            m.insert("share_train".into(), e.judgement.and_then(|j| j.share_train).into());
            m.insert("share_holdout".into(), e.judgement.and_then(|j| j.share_hold).into());
            m.insert("explains_against_own_null".into(), e.accepted_by_own_null().into());
            m.insert("gap_own_null".into(), e.own_null.as_ref().map(|v| v.train.score.gap).into());
            m.insert("gap_holdout_own_null".into(), e.own_null.as_ref().map(|v| v.hold.score.gap).into());
            m.insert("note".into(), e.note.clone().into());
            Value::Object(m)
        })
        .collect();
    let part = |p: &PartComparison| {
        serde_json::json!({
            "gap": p.score.gap,
            "significant": p.significant,
            "gap_threshold": p.null.gap_threshold(),
            "max_abs_z": p.score.max_abs_z,
            "t": p.t,
            "t_threshold": p.null.threshold,
            "t_members": p.null.t,
            "flag": p.flag,
            "null_median": p.null.median,
            "outside": p.score.outside,
            "allan_decades": p.score.allan_decades,
            "groups": p.score.groups,
        })
    };
    JsonReport {
        gap_before: d.before.hold.score.gap,
        gap_after: d.after.hold.score.gap,
        r#where: where_entries(d.layout_hold.info(), &d.before.hold),
        effects,
        chosen: d.chosen.iter().map(|k| k.name()).collect(),
        tried: d.tried.iter().map(|k| k.name()).collect(),
        verdict: d.verdict,
        gap_before_train: d.before.train.score.gap,
        gap_after_train: d.after.train.score.gap,
        before: serde_json::json!({"train": part(&d.before.train), "holdout": part(&d.before.hold)}),
        after: serde_json::json!({"train": part(&d.after.train), "holdout": part(&d.after.hold)}),
        where_train: where_entries(d.layout_train.info(), &d.before.train),
        where_after: where_entries(d.layout_hold.info(), &d.after.hold),
        baseline_terms: d.baseline_terms,
        grid_step_dps: d.grid_step,
        column: &args.column,
        samples: d.samples,
        rate_hz: d.rate_hz,
        train_samples: d.n_train,
        holdout: args.holdout,
        ensemble: args.ensemble,
        seed: args.seed,
        min_share: args.min_share,
        ensembles_run: d.ensembles_run,
        gap_definition: "root of the mean over statistic groups of the mean z^2 in the group; z = (real - ensemble median) / ensemble sd",
    }
}

/// The JSON document of `--json`; the first five keys are the interface of issue 8, in order.
#[derive(Serialize)]
struct JsonReport<'a> {
    gap_before: f64,
    gap_after: f64,
    r#where: Vec<WhereEntry>,
    effects: Vec<Value>,
    chosen: Vec<&'static str>,
    tried: Vec<&'static str>,
    verdict: Verdict,
    gap_before_train: f64,
    gap_after_train: f64,
    before: Value,
    after: Value,
    where_train: Vec<WhereEntry>,
    where_after: Vec<WhereEntry>,
    baseline_terms: Option<NoiseTerms>,
    grid_step_dps: Option<f64>,
    column: &'a str,
    samples: usize,
    rate_hz: f64,
    train_samples: usize,
    holdout: f64,
    ensemble: usize,
    seed: u64,
    min_share: f64,
    ensembles_run: usize,
    gap_definition: &'static str,
}

fn write_part_gaps(out: &mut impl Write, label: &str, p: (&PartComparison, &PartComparison)) -> std::io::Result<()> {
    let mark = |c: &PartComparison| if c.significant { "*" } else { " " };
    let flag = |c: &PartComparison| match c.flag {
        Flag::Gap => "gap".to_owned(),
        Flag::Group(g) => g.name().to_owned(),
    };
    writeln!(
        out,
        "  {label:<8} gap       {:>9.3}{} {:>9.3}{}   (a matching simulation leaves {:.3} / {:.3}; the gap alone is significant above {:.3} / {:.3})",
        p.0.score.gap,
        mark(p.0),
        p.1.score.gap,
        mark(p.1),
        p.0.null.median,
        p.1.null.median,
        p.0.null.gap_threshold(),
        p.1.null.gap_threshold()
    )?;
    writeln!(
        out,
        "  {:<8} test T    {:>9.2}  {:>9.2}    (threshold {:.2} / {:.2}; stands out most: {} / {})",
        "",
        p.0.t,
        p.1.t,
        p.0.null.threshold,
        p.1.null.threshold,
        flag(p.0),
        flag(p.1)
    )
}

fn write_text(out: &mut impl Write, args: &SimgapArgs, d: &Diagnosis, seconds: f64) -> std::io::Result<()> {
    let path = args.real.as_ref().map_or_else(String::new, |p| p.display().to_string());
    let split_s = d.n_train as f64 / d.rate_hz;
    writeln!(
        out,
        "Sim-to-real gap of `{}` in {path}: {} samples at {} Hz; training 0-{} s, hold-out {}-{} s",
        args.column,
        d.samples,
        fmt_num(d.rate_hz),
        fmt_num(split_s),
        fmt_num(split_s),
        fmt_num(d.samples as f64 / d.rate_hz)
    )?;
    match &d.baseline_terms {
        Some(t) => {
            writeln!(
                out,
                "Baseline: IEEE Std 952 terms fitted to the training part (robust Allan deviation): N {:.4} deg/√h, B {:.3} deg/h (flicker floor from {} s), K {:.3} deg/h/√h, Q {:.3e} deg; Allan misfit {:.3}",
                t.n * 60.0,
                t.b * 3600.0,
                fmt_num(t.floor_from_s),
                t.k * 216_000.0,
                t.q,
                t.rms_relative_residual
            )?;
            writeln!(
                out,
                "  (rate ramp R {:.3} deg/h² fitted so that a trend is not taken for K; not simulated)",
                t.r * 3600.0 * 3600.0
            )?
        }
        None => writeln!(out, "Baseline: {}", args.sim.as_ref().map_or(String::new(), |p| p.display().to_string()))?,
    }
    if let Some(step) = d.grid_step {
        writeln!(out, "The recorded values sit on a {} deg/s grid.", fmt_num(step))?;
    }
    writeln!(
        out,
        "Ensembles of {} members (seed {}), {} ensembles run, {seconds:.1} s.",
        args.ensemble, args.seed, d.ensembles_run
    )?;
    writeln!(out)?;
    writeln!(out, "Gap (RMS standard score, groups weighted equally; * = significant):")?;
    writeln!(out, "  {:<18} {:>10} {:>10}", "", "training", "hold-out")?;
    write_part_gaps(out, "before", (&d.before.train, &d.before.hold))?;
    write_part_gaps(out, "after", (&d.after.train, &d.after.hold))?;
    writeln!(out)?;
    let entries = where_entries(d.layout_hold.info(), &d.before.hold);
    writeln!(out, "Where (hold-out part, baseline; outside the ensemble's 95 % band, largest first):")?;
    if entries.is_empty() {
        writeln!(out, "  nowhere")?;
    }
    writeln!(
        out,
        "  {:<16} {:<44} {:>11} {:>11} {:>11} {:>8}",
        "statistic", "band", "real", "sim 2.5%", "sim 97.5%", "z"
    )?;
    for e in entries.iter().take(15) {
        writeln!(
            out,
            "  {:<16} {:<44} {:>11.4e} {:>11.4e} {:>11.4e} {:>8.2}",
            e.statistic, e.band, e.real, e.sim_lo, e.sim_hi, e.z
        )?;
    }
    if entries.len() > 15 {
        writeln!(out, "  … {} more (see --json)", entries.len() - 15)?;
    }
    writeln!(out, "  per group (RMS z, outside/total):")?;
    for g in &d.before.hold.score.groups {
        writeln!(out, "    {:<26} {:>8.2}  {}/{}", g.group.name(), g.rms_z, g.outside, g.statistics)?;
    }
    writeln!(out)?;
    writeln!(out, "Which (candidate effects, best first; share = part of the excess gap removed):")?;
    writeln!(
        out,
        "  (accepted \"own null\": the recording leaves the noise refitted without the effect, and the effect removes that gap)"
    )?;
    writeln!(
        out,
        "  {:<13} {:>9} {:>9} {:>8} {:>8} {:>9}  params",
        "effect", "gap train", "gap hold", "share tr", "share ho", "accepted"
    )?;
    for e in &d.effects {
        let share = |s: Option<f64>| s.map_or("-".to_owned(), |v| format!("{:.0}%", 100.0 * v));
        match (&e.evaluation, &e.params) {
            (Some(ev), Some(p)) => {
                let j = e.judgement;
                let params: Vec<String> = p.named().iter().map(|(k, v)| format!("{k}={v:.4e}")).collect();
                writeln!(
                    out,
                    "  {:<13} {:>9.3} {:>9.3} {:>8} {:>8} {:>9}  {}",
                    e.kind.name(),
                    ev.train.score.gap,
                    ev.hold.score.gap,
                    share(j.and_then(|j| j.share_train)),
                    share(j.and_then(|j| j.share_hold)),
                    match (j.is_some_and(|j| j.explains), e.accepted_by_own_null()) {
                        (true, _) => "yes",
                        (false, true) => "own null",
                        (false, false) => "no",
                    },
                    params.join(" ")
                )?;
            }
            _ => writeln!(out, "  {:<13} not applicable: {}", e.kind.name(), e.note.as_deref().unwrap_or(""))?,
        }
    }
    writeln!(out)?;
    let names = |v: &[crate::diag::simgap::EffectKind]| {
        if v.is_empty() { "none".to_owned() } else { v.iter().map(|k| k.name()).collect::<Vec<_>>().join(" + ") }
    };
    writeln!(out, "Chosen: {}", names(&d.chosen))?;
    if d.chosen.is_empty() && !d.tried.is_empty() {
        writeln!(out, "Kept by the greedy combination but not explaining the hold-out part: {}", names(&d.tried))?;
    }
    let how_far = match d.verdict {
        Verdict::Explained | Verdict::PartlyExplained => format!(
            "; hold-out gap {:.3} → {:.3} (training {:.3} → {:.3})",
            d.before.hold.score.gap, d.after.hold.score.gap, d.before.train.score.gap, d.after.train.score.gap
        ),
        _ => String::new(),
    };
    writeln!(out, "Verdict: {}{how_far}", d.verdict.text())?;
    if d.verdict == Verdict::PartlyExplained {
        let residual = where_entries(d.layout_hold.info(), &d.after.hold);
        let residual = if residual.is_empty() { where_entries(d.layout_train.info(), &d.after.train) } else { residual };
        writeln!(out, "Residual (after the chosen effects; outside the band, largest first):")?;
        for e in residual.iter().take(5) {
            writeln!(out, "  {:<16} {:<44} z {:>8.2}", e.statistic, e.band, e.z)?;
        }
    }
    Ok(())
}
