//! `gyrocomp simgap --selftest`: runs the seeded self-test cases and prints each case, the
//! confusion table and the gap shrink per kind of case (or JSON with `--json`).

use std::io::Write;
use std::time::Instant;

use super::CliError;
use super::simgap_args::SimgapArgs;
use crate::diag::simgap::selftest::{
    CONFUSION_COLUMNS, CaseResult, Injected, RATE_HZ, SelftestSettings, confusion, run_selftest,
};
use crate::diag::simgap::{EffectKind, Verdict};

/// Runs the self-test of `args` (`--cases`, `--duration`, `--seed`, the diagnosis settings).
pub fn run_selftest_cli(args: &SimgapArgs) -> Result<(), CliError> {
    let settings = SelftestSettings {
        cases: args.cases,
        duration_s: args.duration,
        scale: args.magnitude,
        seed: args.seed,
        diagnosis: args.settings(),
    };
    let kinds = match &args.only {
        Some(names) => names
            .iter()
            .map(|n| {
                Injected::from_name(n).ok_or_else(|| format!("--only: unknown kind `{n}` (effect names, none, chirp)"))
            })
            .collect::<Result<Vec<_>, _>>()?,
        None => Injected::all(),
    };
    let mut out = std::io::stdout().lock();
    if !args.json {
        writeln!(
            out,
            "Self-test: {} cases of each of {} kinds, {} s at {} Hz each, magnitudes ×{}, ensembles of {}, seed {}",
            args.cases,
            kinds.len(),
            args.duration,
            RATE_HZ,
            args.magnitude,
            args.ensemble,
            args.seed
        )?;
        writeln!(
            out,
            "{:<16} {:>4} {:<6} {:<26} {:>15} {:>15}  injected",
            "case", "#", "ok", "outcome", "gap train", "gap hold"
        )?;
    }
    let started = Instant::now();
    let mut failure = None;
    let results = run_selftest(&settings, &kinds, |r| {
        if !args.json
            && let Err(e) = write_case(&mut out, r)
        {
            failure = Some(e);
        }
    })?;
    if let Some(e) = failure {
        return Err(e.into());
    }
    let seconds = started.elapsed().as_secs_f64();
    if args.json {
        let table: Vec<serde_json::Value> = confusion(&results)
            .into_iter()
            .map(|(injected, row)| serde_json::json!({"injected": injected.name(), "counts": row.to_vec()}))
            .collect();
        let columns: Vec<&str> =
            EffectKind::ALL.iter().map(|k| k.name()).chain(["no significant gap", "unexplained"]).collect();
        serde_json::to_writer(
            &mut out,
            &serde_json::json!({"cases": results, "confusion": {"columns": columns, "rows": table}, "seconds": seconds}),
        )?;
        writeln!(out)?;
    } else {
        write_summary(&mut out, &results, seconds)?;
    }
    out.flush()?;
    Ok(())
}

fn outcome(r: &CaseResult) -> String {
    match (r.verdict, r.named) {
        (Verdict::Explained, Some(k)) => format!("named {}", k.name()),
        (Verdict::PartlyExplained, Some(k)) => format!("named {} (partly)", k.name()),
        (v, _) => v.text().to_owned(),
    }
}

fn write_case(out: &mut impl Write, r: &CaseResult) -> std::io::Result<()> {
    writeln!(
        out,
        "{:<16} {:>4} {:<6} {:<26} {:>6.2} → {:<6.2} {:>6.2} → {:<6.2}  {}",
        r.injected.name(),
        r.case,
        if r.correct { "ok" } else { "WRONG" },
        outcome(r),
        r.gap_train.0,
        r.gap_train.1,
        r.gap_hold.0,
        r.gap_hold.1,
        r.magnitudes
    )
}

fn write_summary(out: &mut impl Write, results: &[CaseResult], seconds: f64) -> std::io::Result<()> {
    writeln!(out)?;
    writeln!(out, "Confusion table (rows: injected; columns: what the diagnosis said first):")?;
    let short = ["warm", "temp", "ramp", "sin", "jump", "spike", "quant", "gm", "no-gap", "unexpl"];
    debug_assert_eq!(short.len(), CONFUSION_COLUMNS);
    write!(out, "  {:<16}", "")?;
    for s in short {
        write!(out, " {s:>6}")?;
    }
    writeln!(out, " {:>9} {:>23} {:>23}", "correct", "mean gap hold-out", "mean gap train")?;
    for (injected, row) in confusion(results) {
        let rows: Vec<&CaseResult> = results.iter().filter(|r| r.injected == injected).collect();
        let n = rows.len() as f64;
        let correct = rows.iter().filter(|r| r.correct).count();
        let mean = |f: &dyn Fn(&CaseResult) -> f64| rows.iter().map(|r| f(r)).sum::<f64>() / n;
        write!(out, "  {:<16}", injected.name())?;
        for c in row {
            write!(out, " {c:>6}")?;
        }
        writeln!(
            out,
            " {:>4}/{:<4} {:>9.2} → {:<9.2} {:>9.2} → {:<9.2}",
            correct,
            rows.len(),
            mean(&|r| r.gap_hold.0),
            mean(&|r| r.gap_hold.1),
            mean(&|r| r.gap_train.0),
            mean(&|r| r.gap_train.1)
        )?;
    }
    let correct = results.iter().filter(|r| r.correct).count();
    writeln!(out, "\nCorrect: {correct}/{} cases; {seconds:.1} s.", results.len())
}
