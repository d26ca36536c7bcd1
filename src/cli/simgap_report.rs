//! The HTML report of `gyrocomp simgap --report DIR`: one self-contained `index.html` with
//! hand-written SVG plots (no scripts): the Allan deviation and the PSD bands of the real
//! recording against the simulated 95 % band before and after the chosen effects (hold-out and
//! training part), the bias trajectory, the effect ranking, and the table of where the gap lies.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::CliError;
use super::simgap_args::SimgapArgs;
use super::simgap_json::where_entries;
use crate::diag::simgap::Diagnosis;
use crate::diag::simgap::gap::PartComparison;
use crate::diag::simgap::stats::{StatInfo, fmt_num};

const WIDTH: f64 = 640.0;
const HEIGHT: f64 = 360.0;
const MARGIN: (f64, f64, f64, f64) = (70.0, 20.0, 30.0, 50.0); // left, right, top, bottom
const BEFORE_FILL: &str = "#bbbbbb";
const AFTER_FILL: &str = "#6fa8dc";
const REAL_COLOUR: &str = "#c0392b";

/// An axis of a plot: linear or log10, with its data range.
#[derive(Debug, Clone, Copy)]
struct Axis {
    log: bool,
    lo: f64,
    hi: f64,
}

impl Axis {
    fn fit(values: impl Iterator<Item = f64>, log: bool) -> Axis {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in values.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
            let v = if log { v.log10() } else { v };
            lo = lo.min(v);
            hi = hi.max(v);
        }
        if !lo.is_finite() {
            (lo, hi) = (0.0, 1.0);
        }
        let pad = if hi > lo { 0.05 * (hi - lo) } else { 0.5 };
        Axis { log, lo: lo - pad, hi: hi + pad }
    }

    fn frac(&self, v: f64) -> f64 {
        let v = if self.log { v.max(1e-300).log10() } else { v };
        (v - self.lo) / (self.hi - self.lo)
    }

    /// Tick positions (in data units) with labels.
    fn ticks(&self) -> Vec<(f64, String)> {
        if self.log {
            let (a, b) = (self.lo.ceil() as i32, self.hi.floor() as i32);
            let step = ((b - a) / 6 + 1).max(1);
            (a..=b).step_by(step as usize).map(|e| (10f64.powi(e), format!("1e{e}"))).collect()
        } else {
            let span = self.hi - self.lo;
            let raw = span / 5.0;
            let mag = 10f64.powf(raw.log10().floor());
            let step = [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * mag).find(|s| span / s <= 6.0).unwrap_or(mag * 10.0);
            let mut t = (self.lo / step).ceil() * step;
            let mut out = Vec::new();
            while t <= self.hi {
                out.push((t, fmt_num(if t.abs() < 1e-12 * step { 0.0 } else { t })));
                t += step;
            }
            out
        }
    }
}

/// An SVG plot under construction.
struct Plot {
    svg: String,
    x: Axis,
    y: Axis,
}

impl Plot {
    fn new(title: &str, x: Axis, y: Axis, x_label: &str, y_label: &str) -> Plot {
        let mut p = Plot { svg: String::new(), x, y };
        let (l, r, t, b) = MARGIN;
        let _ = write!(
            p.svg,
            r##"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" font-family="sans-serif" font-size="11"><rect x="{l}" y="{t}" width="{}" height="{}" fill="white" stroke="#444"/><text x="{}" y="16" text-anchor="middle" font-size="13">{}</text><text x="{}" y="{}" text-anchor="middle">{}</text><text x="14" y="{}" text-anchor="middle" transform="rotate(-90 14 {})">{}</text>"##,
            WIDTH - l - r,
            HEIGHT - t - b,
            WIDTH / 2.0,
            escape(title),
            l + (WIDTH - l - r) / 2.0,
            HEIGHT - 12.0,
            escape(x_label),
            t + (HEIGHT - t - b) / 2.0,
            t + (HEIGHT - t - b) / 2.0,
            escape(y_label)
        );
        for (v, label) in x.ticks() {
            let px = p.px(v);
            let _ = write!(
                p.svg,
                r##"<line x1="{px:.1}" y1="{}" x2="{px:.1}" y2="{}" stroke="#ddd"/><text x="{px:.1}" y="{}" text-anchor="middle">{label}</text>"##,
                t,
                HEIGHT - b,
                HEIGHT - b + 14.0
            );
        }
        for (v, label) in y.ticks() {
            let py = p.py(v);
            let _ = write!(
                p.svg,
                r##"<line x1="{l}" y1="{py:.1}" x2="{}" y2="{py:.1}" stroke="#ddd"/><text x="{}" y="{:.1}" text-anchor="end">{label}</text>"##,
                WIDTH - r,
                l - 4.0,
                py + 4.0
            );
        }
        p
    }

    fn px(&self, v: f64) -> f64 {
        MARGIN.0 + self.x.frac(v) * (WIDTH - MARGIN.0 - MARGIN.1)
    }

    fn py(&self, v: f64) -> f64 {
        HEIGHT - MARGIN.3 - self.y.frac(v) * (HEIGHT - MARGIN.2 - MARGIN.3)
    }

    fn band(&mut self, x: &[f64], lo: &[f64], hi: &[f64], fill: &str) {
        let mut points: Vec<String> =
            x.iter().zip(hi).map(|(&a, &b)| format!("{:.1},{:.1}", self.px(a), self.py(b))).collect();
        points.extend(x.iter().zip(lo).rev().map(|(&a, &b)| format!("{:.1},{:.1}", self.px(a), self.py(b))));
        let _ = write!(
            self.svg,
            r#"<polygon points="{}" fill="{fill}" fill-opacity="0.45" stroke="none"/>"#,
            points.join(" ")
        );
    }

    fn line(&mut self, x: &[f64], y: &[f64], colour: &str, dashed: bool, dots: bool) {
        let points: Vec<String> =
            x.iter().zip(y).map(|(&a, &b)| format!("{:.1},{:.1}", self.px(a), self.py(b))).collect();
        let dash = if dashed { r#" stroke-dasharray="4 3""# } else { "" };
        let _ = write!(
            self.svg,
            r#"<polyline points="{}" fill="none" stroke="{colour}" stroke-width="1.6"{dash}/>"#,
            points.join(" ")
        );
        if dots {
            for (&a, &b) in x.iter().zip(y) {
                let _ = write!(
                    self.svg,
                    r#"<circle cx="{:.1}" cy="{:.1}" r="2.5" fill="{colour}"/>"#,
                    self.px(a),
                    self.py(b)
                );
            }
        }
    }

    fn legend(&mut self, entries: &[(&str, &str)]) {
        for (i, (colour, label)) in entries.iter().enumerate() {
            let y = MARGIN.2 + 14.0 + 15.0 * i as f64;
            let x = WIDTH - MARGIN.1 - 190.0;
            let _ = write!(
                self.svg,
                r#"<rect x="{x}" y="{:.1}" width="14" height="9" fill="{colour}" fill-opacity="0.7"/><text x="{}" y="{y:.1}">{}</text>"#,
                y - 8.0,
                x + 18.0,
                escape(label)
            );
        }
    }

    fn finish(mut self) -> String {
        self.svg.push_str("</svg>");
        self.svg
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// The real value and the before/after bands of the statistics `keep` selects, in natural units.
struct Series {
    x: Vec<f64>,
    real: Vec<f64>,
    bands: [(Vec<f64>, Vec<f64>, Vec<f64>); 2],
}

fn series(info: &[StatInfo], before: &PartComparison, after: &PartComparison, keep: &str) -> Series {
    let idx: Vec<usize> = (0..info.len()).filter(|&i| info[i].statistic == keep).collect();
    let nat = |i: usize, v: f64| info[i].natural(v);
    let band = |p: &PartComparison| {
        (
            idx.iter().map(|&i| nat(i, p.bands[i].lo)).collect(),
            idx.iter().map(|&i| nat(i, p.bands[i].median)).collect(),
            idx.iter().map(|&i| nat(i, p.bands[i].hi)).collect(),
        )
    };
    Series {
        x: idx.iter().map(|&i| info[i].x).collect(),
        real: idx.iter().map(|&i| nat(i, before.real[i])).collect(),
        bands: [band(before), band(after)],
    }
}

fn band_plot(title: &str, s: &Series, x_label: &str, y_label: &str, log: bool, after_label: &str) -> String {
    let all_y = s.real.iter().chain(s.bands.iter().flat_map(|(a, b, c)| a.iter().chain(b).chain(c))).copied();
    let mut p = Plot::new(title, Axis::fit(s.x.iter().copied(), log), Axis::fit(all_y, log), x_label, y_label);
    for (k, fill) in [(0, BEFORE_FILL), (1, AFTER_FILL)] {
        let (lo, med, hi) = &s.bands[k];
        p.band(&s.x, lo, hi, fill);
        p.line(&s.x, med, fill, true, false);
    }
    p.line(&s.x, &s.real, REAL_COLOUR, false, true);
    p.legend(&[(REAL_COLOUR, "real"), (BEFORE_FILL, "baseline sim, 95 % band"), (AFTER_FILL, after_label)]);
    p.finish()
}

fn ranking_plot(d: &Diagnosis) -> String {
    let rows: Vec<(&str, f64, f64)> = d
        .effects
        .iter()
        .filter_map(|e| e.evaluation.as_ref().map(|ev| (e.kind.name(), ev.train.score.gap, ev.hold.score.gap)))
        .collect();
    let base = (d.before.train.score.gap, d.before.hold.score.gap);
    let max = rows.iter().flat_map(|r| [r.1, r.2]).chain([base.0, base.1]).fold(0.0, f64::max) * 1.1;
    let (l, top) = (110.0, 40.0);
    let row_h = 34.0;
    let height = top + row_h * rows.len() as f64 + 40.0;
    let w = WIDTH - l - 30.0;
    let x = |v: f64| l + w * v / max.max(1e-12);
    let mut svg = format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{height}" font-family="sans-serif" font-size="11"><text x="{}" y="16" text-anchor="middle" font-size="13">Gap with each effect added (shorter is better)</text>"##,
        WIDTH / 2.0
    );
    for (label, v, colour) in [("baseline, training", base.0, "#555"), ("baseline, hold-out", base.1, REAL_COLOUR)] {
        let _ = write!(
            svg,
            r#"<line x1="{:.1}" y1="{}" x2="{:.1}" y2="{}" stroke="{colour}" stroke-dasharray="4 3"/><text x="{:.1}" y="{}" text-anchor="middle" fill="{colour}">{label}</text>"#,
            x(v),
            top - 6.0,
            x(v),
            height - 30.0,
            x(v),
            if colour == "#555" { top - 10.0 } else { height - 16.0 }
        );
    }
    for (i, (name, train, hold)) in rows.iter().enumerate() {
        let y = top + row_h * i as f64;
        let _ = write!(
            svg,
            r##"<text x="{}" y="{:.1}" text-anchor="end">{name}</text><rect x="{l}" y="{:.1}" width="{:.1}" height="11" fill="#888"/><rect x="{l}" y="{:.1}" width="{:.1}" height="11" fill="{AFTER_FILL}"/><text x="{:.1}" y="{:.1}">{train:.2} / {hold:.2}</text>"##,
            l - 6.0,
            y + 16.0,
            y + 4.0,
            x(*train) - l,
            y + 16.0,
            x(*hold) - l,
            x(train.max(*hold)) + 4.0,
            y + 14.0
        );
    }
    let _ = write!(
        svg,
        r##"<rect x="{l}" y="{:.1}" width="12" height="9" fill="#888"/><text x="{}" y="{:.1}">training</text><rect x="{}" y="{:.1}" width="12" height="9" fill="{AFTER_FILL}"/><text x="{}" y="{:.1}">hold-out</text></svg>"##,
        height - 10.0,
        l + 16.0,
        height - 2.0,
        l + 90.0,
        height - 10.0,
        l + 106.0,
        height - 2.0
    );
    svg
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
        html.push_str(&band_plot(&format!("Allan deviation, {part}"), &allan, "tau (s)", "deg/s", true, &after_label));
        let psd = series(info, before, after, "psd");
        html.push_str(&band_plot(&format!("PSD bands, {part}"), &psd, "Hz", "(deg/s)^2/Hz", true, &after_label));
        let traj = series(info, before, after, "bias_trajectory");
        html.push_str(&band_plot(
            &format!("Bias trajectory, {part}"),
            &traj,
            "t (s)",
            "deg/s from mean",
            false,
            &after_label,
        ));
        html.push_str("</div>");
    }
    let _ = write!(html, "<h2>Which effect</h2>{}", ranking_plot(d));
    html.push_str("<h2>Where (hold-out part, baseline)</h2><table><tr><th>statistic</th><th>band</th><th>real</th><th>sim 2.5 %</th><th>sim 97.5 %</th><th>z</th></tr>");
    for e in where_entries(d.layout_hold.info(), &d.before.hold) {
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
    html.push_str("<p>Bands are the 2.5–97.5 % quantiles of the simulated ensemble; dashed lines their medians.</p>");
    html.push_str("</body></html>\n");
    std::fs::write(&file, html).map_err(|e| format!("{}: cannot write: {e}", file.display()))?;
    Ok(file)
}
