//! The HTML report of `gyrocomp simgap --report DIR`: one self-contained `index.html` with
//! inline SVG plots drawn by [`super::plot::simgap`] (no scripts): the Allan deviation and the PSD bands of the real
//! recording against the simulated 95 % band before and after the chosen effects (hold-out and
//! training part), the bias trajectory, the effect ranking, and the table of where the gap lies.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::CliError;
use super::plot::simgap::{Band, BandFigure, RankingFigure, RankingRow};
use super::plot::to_svg;
use super::simgap_args::SimgapArgs;
use super::simgap_json::where_entries;
use crate::diag::simgap::Diagnosis;
use crate::diag::simgap::gap::PartComparison;
use crate::diag::simgap::stats::{StatInfo, fmt_num};

fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// The real value and the before/after bands of the statistics `keep` selects, in natural units.
struct Series {
    x: Vec<f64>,
    real: Vec<f64>,
    bands: [Band; 2],
}

fn series(info: &[StatInfo], before: &PartComparison, after: &PartComparison, keep: &str) -> Series {
    let mut idx: Vec<usize> = (0..info.len()).filter(|&i| info[i].statistic == keep).collect();
    // In time/τ/frequency order: the bias trajectory lists its regular blocks, then the finer
    // early ones, which a line in list order would zigzag through.
    idx.sort_by(|&a, &b| info[a].x.total_cmp(&info[b].x));
    let nat = |i: usize, v: f64| info[i].natural(v);
    let band = |p: &PartComparison| Band {
        lo: idx.iter().map(|&i| nat(i, p.bands[i].lo)).collect(),
        median: idx.iter().map(|&i| nat(i, p.bands[i].median)).collect(),
        hi: idx.iter().map(|&i| nat(i, p.bands[i].hi)).collect(),
    };
    Series {
        x: idx.iter().map(|&i| info[i].x).collect(),
        real: idx.iter().map(|&i| nat(i, before.real[i])).collect(),
        bands: [band(before), band(after)],
    }
}

fn band_plot(title: &str, s: &Series, labels: (&str, &str), log: bool, after_label: &str) -> Result<String, CliError> {
    let figure = BandFigure {
        title: title.to_owned(),
        x: &s.x,
        real: &s.real,
        before: &s.bands[0],
        after: &s.bands[1],
        after_label,
        labels,
        log,
    };
    Ok(to_svg(&figure).map_err(|e| format!("simgap report, {title}: {e}"))?)
}

fn ranking_plot(d: &Diagnosis) -> Result<String, CliError> {
    let rows: Vec<RankingRow> = d
        .effects
        .iter()
        .filter_map(|e| {
            e.evaluation.as_ref().map(|ev| RankingRow {
                name: e.kind.name().to_owned(),
                train: ev.train.score.gap,
                hold: ev.hold.score.gap,
            })
        })
        .collect();
    let figure = RankingFigure { rows: &rows, baseline: (d.before.train.score.gap, d.before.hold.score.gap) };
    Ok(to_svg(&figure).map_err(|e| format!("simgap report, ranking: {e}"))?)
}

/// Writes `dir/index.html`; returns its path.
pub fn write_report(dir: &Path, args: &SimgapArgs, d: &Diagnosis) -> Result<PathBuf, CliError> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: cannot create: {e}", dir.display()))?;
    let file = dir.join("index.html");
    let chosen: Vec<&str> = d.chosen.iter().map(|k| k.name()).collect();
    let kept: Vec<&str> = d.tried.iter().map(|k| k.name()).collect();
    let after_label = if kept.is_empty() {
        "no effect kept (= baseline)".to_owned()
    } else if chosen.is_empty() {
        format!("with {} (does not explain)", kept.join(" + "))
    } else {
        format!("with {}", kept.join(" + "))
    };
    let source = args.real.as_ref().map_or(String::new(), |p| p.display().to_string());
    let mut html = format!(
        "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>simgap: {}</title><style>body{{font-family:sans-serif;max-width:1320px;margin:1em auto}}table{{border-collapse:collapse}}td,th{{border:1px solid #ccc;padding:2px 6px;text-align:right}}td:first-child,td:nth-child(2){{text-align:left}}</style></head><body>",
        escape(&source)
    );
    let _ = write!(
        html,
        "<h1>Sim-to-real gap: <code>{}</code> of {}</h1><p><b>Verdict: {}</b>. Chosen: {}. Gap (RMS standard score over statistic groups; a matching simulation leaves about {:.2}): hold-out {:.3} → {:.3}, training {:.3} → {:.3}. {} samples at {} Hz, training 0–{} s, hold-out to {} s, ensembles of {} (seed {}).</p>",
        escape(&args.column),
        escape(&source),
        d.verdict.text(),
        if chosen.is_empty() { "none".to_owned() } else { chosen.join(" + ") },
        d.before.hold.null.median,
        d.before.hold.score.gap,
        d.after.hold.score.gap,
        d.before.train.score.gap,
        d.after.train.score.gap,
        d.samples,
        fmt_num(d.rate_hz),
        fmt_num(d.n_train as f64 / d.rate_hz),
        fmt_num(d.samples as f64 / d.rate_hz),
        args.ensemble,
        args.seed
    );
    for (part, info, before, after) in [
        ("hold-out", d.layout_hold.info(), &d.before.hold, &d.after.hold),
        ("training", d.layout_train.info(), &d.before.train, &d.after.train),
    ] {
        let _ = write!(html, "<h2>{part} part</h2><div>");
        let allan = series(info, before, after, "allan_deviation");
        html.push_str(&band_plot(
            &format!("Allan deviation, {part}"),
            &allan,
            ("τ (s)", "Allan deviation (deg/s)"),
            true,
            &after_label,
        )?);
        let psd = series(info, before, after, "psd");
        html.push_str(&band_plot(
            &format!("PSD bands, {part}"),
            &psd,
            ("f (Hz)", "PSD ((deg/s)²/Hz)"),
            true,
            &after_label,
        )?);
        let traj = series(info, before, after, "bias_trajectory");
        html.push_str(&band_plot(
            &format!("Bias trajectory, {part}"),
            &traj,
            ("t (s)", "bias from mean (deg/s)"),
            false,
            &after_label,
        )?);
        html.push_str("</div>");
    }
    let _ = write!(html, "<h2>Which effect</h2>{}", ranking_plot(d)?);
    html.push_str("<h2>Where (hold-out part, baseline)</h2><table><tr><th>statistic</th><th>band</th><th>real</th><th>sim 2.5 %</th><th>sim 97.5 %</th><th>z</th></tr>");
    for e in where_entries(d.layout_hold.info(), &d.before.hold, &d.located_hold) {
        let _ = write!(
            html,
            "<tr><td>{}</td><td>{}</td><td>{:.4e}</td><td>{:.4e}</td><td>{:.4e}</td><td>{:.2}</td></tr>",
            e.statistic,
            escape(&e.band),
            e.real,
            e.sim_lo,
            e.sim_hi,
            e.z
        );
    }
    html.push_str("</table><h2>Effects</h2><table><tr><th>effect</th><th>parameters</th><th>gap training</th><th>gap hold-out</th><th>accepted alone</th></tr>");
    for e in &d.effects {
        let params = e.params.as_ref().map_or_else(
            || e.note.clone().unwrap_or_default(),
            |p| p.named().iter().map(|(k, v)| format!("{k} = {v:.4e}")).collect::<Vec<_>>().join(", "),
        );
        let (g, h) = e.evaluation.as_ref().map_or(("–".to_owned(), "–".to_owned()), |v| {
            (format!("{:.3}", v.train.score.gap), format!("{:.3}", v.hold.score.gap))
        });
        let _ = write!(
            html,
            "<tr><td>{}</td><td>{}</td><td>{g}</td><td>{h}</td><td>{}</td></tr>",
            e.kind.name(),
            escape(&params),
            if e.accepted() { "yes" } else { "no" }
        );
    }
    html.push_str("</table>");
    for (kind, params) in d.kept_with_other_fit() {
        let params = params.named().iter().map(|(k, v)| format!("{k} = {v:.4e}")).collect::<Vec<_>>().join(", ");
        let _ = write!(
            html,
            "<p>{} is kept with another of its candidate fits than the one listed: {}.</p>",
            kind.name(),
            escape(&params)
        );
    }
    html.push_str("<p>Bands are the 2.5–97.5 % quantiles of the simulated ensemble; dashed lines their medians.</p>");
    html.push_str("</body></html>\n");
    std::fs::write(&file, html).map_err(|e| format!("{}: cannot write: {e}", file.display()))?;
    Ok(file)
}
