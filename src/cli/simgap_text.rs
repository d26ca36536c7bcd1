//! The text report of `gyrocomp simgap`: baseline, gap before and after, where, which, verdict.

use std::io::Write;

use super::simgap_args::SimgapArgs;
use super::simgap_json::where_entries;
use crate::diag::simgap::baseline::NoiseTerms;
use crate::diag::simgap::gap::{Flag, PartComparison};
use crate::diag::simgap::stats::fmt_num;
use crate::diag::simgap::{Diagnosis, Verdict};
use crate::sim::{AxisConfig, BiasInstability};

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

/// The recording's fitted IEEE Std 952 terms beside the given simulator's, in datasheet units.
fn write_terms_beside_simulator(out: &mut impl Write, t: &NoiseTerms, sim: &AxisConfig) -> std::io::Result<()> {
    let b_sim = match &sim.bias_instability {
        Some(BiasInstability::Flicker { b_deg_h, .. } | BiasInstability::GaussMarkov { b_deg_h, .. }) => Some(*b_deg_h),
        None => None,
    };
    let show = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.3}"));
    writeln!(out, "  {:<22} {:>12} {:>12}", "IEEE Std 952 term", "simulator", "recording")?;
    for (name, simulated, recorded) in [
        ("N, deg/√h", sim.arw_deg_rt_h, t.n_deg_rt_h()),
        ("B, deg/h", b_sim, t.b_deg_h()),
        ("K, deg/h/√h", sim.rrw_deg_h_rt_h, t.k_deg_h_rt_h()),
    ] {
        writeln!(out, "  {name:<22} {:>12} {recorded:>12.3}", show(simulated))?;
    }
    writeln!(out, "  (recording: fitted to the training part's robust Allan deviation, for comparison only)")
}

pub(super) fn write_text(out: &mut impl Write, args: &SimgapArgs, d: &Diagnosis, seconds: f64) -> std::io::Result<()> {
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
                t.n_deg_rt_h(),
                t.b_deg_h(),
                fmt_num(t.floor_from_s),
                t.k_deg_h_rt_h(),
                t.q,
                t.rms_relative_residual
            )?;
            writeln!(
                out,
                "  (rate ramp R {:.3} deg/h² fitted so that a trend is not taken for K; not simulated)",
                t.r * 3600.0 * 3600.0
            )?
        }
        None => {
            writeln!(out, "Baseline: {}", args.sim.as_ref().map_or(String::new(), |p| p.display().to_string()))?;
            if let Some(t) = &d.recording_terms {
                write_terms_beside_simulator(out, t, &d.baseline_model.axis)?;
            }
        }
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
    let entries = where_entries(d.layout_hold.info(), &d.before.hold, &d.located_hold);
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
        "  (\"no evid.\": its nested test finds no more of it than recordings without it, nor does its detector: not a candidate)"
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
                    match (e.supported, j.is_some_and(|j| j.explains), e.accepted_by_own_null()) {
                        (false, _, _) => "no evid.",
                        (true, true, _) => "yes",
                        (true, false, true) => "own null",
                        (true, false, false) => "no",
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
    for (kind, params) in d.kept_with_other_fit() {
        let params: Vec<String> = params.named().iter().map(|(k, v)| format!("{k}={v:.4e}")).collect();
        writeln!(
            out,
            "Kept with another of its candidate fits than the one listed: {} {}",
            kind.name(),
            params.join(" ")
        )?;
    }
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
        let residual = where_entries(d.layout_hold.info(), &d.after.hold, &d.located_hold);
        let residual = if residual.is_empty() {
            where_entries(d.layout_train.info(), &d.after.train, &d.located_train)
        } else {
            residual
        };
        writeln!(out, "Residual (after the chosen effects; outside the band, largest first):")?;
        for e in residual.iter().take(5) {
            writeln!(out, "  {:<16} {:<44} z {:>8.2}", e.statistic, e.band, e.z)?;
        }
    }
    Ok(())
}
