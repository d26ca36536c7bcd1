//! `gyrocomp compensate --plot F`: two panels per axis over time — the raw and compensated rates
//! over their whole range, then a zoom on the drift: the estimate with its ±1σ band (the
//! pipeline's `drift_std`) over the raw rate of the static samples — with the samples flagged
//! moving or rejected shaded on both. Long recordings are drawn decimated (the extremes of each
//! pixel column, so spikes stay visible), which the title says.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{Corner, Figure, Mark, PlotError, decimate_min_max, draw_err, font, legend, range};

/// Pixel columns of a panel's plotting area (decimation target).
const COLUMNS: usize = 1000;

/// One axis of a compensated recording, sample by sample.
#[derive(Debug, Clone, Default)]
pub struct AxisTrace {
    /// Column name (e.g. `gx_dps`).
    pub column: String,
    /// Raw rate, deg/s.
    pub raw: Vec<f64>,
    /// Drift estimate subtracted, deg/s.
    pub drift: Vec<f64>,
    /// Standard deviation of the drift estimate, deg/s (+∞ while unknown).
    pub drift_std: Vec<f64>,
    /// Compensated rate, deg/s.
    pub compensated: Vec<f64>,
}

/// The compensate plot: shared time axis and flags, one [`AxisTrace`] per axis.
pub struct CompensateFigure<'a> {
    /// Title (e.g. the input file).
    pub title: String,
    /// Time of each sample, s.
    pub t_s: &'a [f64],
    /// Moving flag of each sample (the pipeline's status).
    pub moving: &'a [bool],
    /// Rejected flag of each sample.
    pub rejected: &'a [bool],
    /// The axes, one panel each.
    pub axes: &'a [AxisTrace],
}

/// Time spans [start, end] of the runs of `true` in `flags`, merged across gaps under `min_gap`
/// seconds (so a flickering flag draws as one span per pixel at most).
pub fn flag_spans(t_s: &[f64], flags: &[bool], min_gap: f64) -> Vec<(f64, f64)> {
    let mut spans: Vec<(f64, f64)> = Vec::new();
    let mut start = None;
    let len = t_s.len().min(flags.len());
    for i in 0..=len {
        let on = i < len && flags[i];
        match (on, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                let (a, b) = (t_s[s], t_s[i - 1]);
                match spans.last_mut() {
                    Some(last) if a - last.1 < min_gap => last.1 = b,
                    _ => spans.push((a, b)),
                }
                start = None;
            }
            _ => {}
        }
    }
    spans
}

/// The ±σ envelope of `mid` per pixel column: (x at the column's first sample, min(mid − σ),
/// max(mid + σ)), split into runs where σ is finite.
fn envelope(x: &[f64], mid: &[f64], sd: &[f64], columns: usize) -> Vec<Vec<(f64, f64, f64)>> {
    let len = x.len().min(mid.len()).min(sd.len());
    let columns = columns.clamp(1, len.max(1));
    let mut runs = vec![Vec::new()];
    for c in 0..columns {
        let (a, b) = (c * len / columns, ((c + 1) * len / columns).min(len));
        let ok: Vec<usize> = (a..b).filter(|&i| sd[i].is_finite() && mid[i].is_finite()).collect();
        if ok.is_empty() {
            if runs.last().is_some_and(|r| !r.is_empty()) {
                runs.push(Vec::new());
            }
            continue;
        }
        let lo = ok.iter().map(|&i| mid[i] - sd[i]).fold(f64::INFINITY, f64::min);
        let hi = ok.iter().map(|&i| mid[i] + sd[i]).fold(f64::NEG_INFINITY, f64::max);
        if let Some(run) = runs.last_mut() {
            run.push((x[ok[0]], lo, hi));
        }
    }
    runs.retain(|r| !r.is_empty());
    runs
}

/// The `q` quantile of the finite values of `v` (NaN when there is none).
fn quantile(v: impl Iterator<Item = f64>, q: f64) -> f64 {
    let mut v: Vec<f64> = v.filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

const RAW: RGBColor = RGBColor(150, 150, 150);
const DRIFT: RGBColor = RGBColor(31, 90, 180);
const COMPENSATED: RGBColor = RGBColor(30, 150, 60);
const MOVING: RGBColor = RGBColor(255, 170, 60);
const REJECTED: RGBColor = RGBColor(220, 40, 40);

impl Figure for CompensateFigure<'_> {
    fn size(&self) -> (u32, u32) {
        (1200, 60 + 2 * 270 * self.axes.len().max(1) as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let n = self.t_s.len();
        let decimated = n > 2 * COLUMNS;
        let title = if decimated {
            format!("{} ({n} samples, drawn as min/max per pixel column)", self.title)
        } else {
            format!("{} ({n} samples)", self.title)
        };
        let root = root.titled(&title, font(20.0)).map_err(draw_err)?;
        let panels = root.split_evenly((2 * self.axes.len().max(1), 1));
        let (t0, t1) = range(self.t_s.iter().copied(), false, 0.0);
        let min_gap = (t1 - t0) / COLUMNS as f64;
        let flags = Flags {
            moving: flag_spans(self.t_s, self.moving, min_gap),
            rejected: flag_spans(self.t_s, self.rejected, min_gap),
            min_width: min_gap * 0.5,
        };
        for (k, axis) in self.axes.iter().enumerate() {
            self.rates_panel(&panels[2 * k], (t0, t1), axis, &flags)?;
            self.drift_panel(&panels[2 * k + 1], (t0, t1), axis, &flags)?;
        }
        Ok(())
    }
}

/// The flagged time spans shaded on every panel.
struct Flags {
    moving: Vec<(f64, f64)>,
    rejected: Vec<(f64, f64)>,
    min_width: f64,
}

/// Legend entries of a panel.
type Entries = Vec<(String, Mark)>;

type Chart<'a, DB> =
    ChartContext<'a, DB, Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>>;

impl CompensateFigure<'_> {
    /// A panel with its axes and the flagged spans shaded; the legend entries of the spans.
    fn panel<'a, DB: DrawingBackend>(
        area: &'a DrawingArea<DB, Shift>,
        (t0, t1): (f64, f64),
        (y0, y1): (f64, f64),
        y_desc: &str,
        flags: &Flags,
    ) -> Result<(Chart<'a, DB>, Entries), PlotError> {
        let mut chart = ChartBuilder::on(area)
            .margin(8)
            .x_label_area_size(36)
            .y_label_area_size(80)
            .build_cartesian_2d(t0..t1, y0..y1)
            .map_err(draw_err)?;
        chart
            .configure_mesh()
            .x_desc("time (s)")
            .y_desc(y_desc)
            .label_style(font(13.0))
            .axis_desc_style(font(15.0))
            .light_line_style(WHITE)
            .draw()
            .map_err(draw_err)?;
        let mut entries = Vec::new();
        for (spans, colour, label) in [(&flags.moving, MOVING, "moving"), (&flags.rejected, REJECTED, "rejected")] {
            if spans.is_empty() && label == "rejected" {
                continue;
            }
            let shade = colour.mix(0.25).filled();
            let w = flags.min_width;
            chart
                .draw_series(spans.iter().map(|&(a, b)| Rectangle::new([(a, y0), (b.max(a + w), y1)], shade)))
                .map_err(draw_err)?;
            let plural = if spans.len() == 1 { "" } else { "s" };
            entries.push((format!("{label} ({} span{plural})", spans.len()), Mark::Fill(colour, 0.25)));
        }
        Ok((chart, entries))
    }

    /// Raw and compensated rates over their whole range (motions included).
    fn rates_panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        t: (f64, f64),
        axis: &AxisTrace,
        flags: &Flags,
    ) -> Result<(), PlotError> {
        let raw = decimate_min_max(self.t_s, &axis.raw, COLUMNS);
        let comp = decimate_min_max(self.t_s, &axis.compensated, COLUMNS);
        let y = range(raw.iter().chain(&comp).map(|p| p.1), false, 0.06);
        let (mut chart, mut entries) = Self::panel(area, t, y, &format!("{} rate (deg/s)", axis.column), flags)?;
        chart.draw_series(LineSeries::new(raw, RAW.stroke_width(1))).map_err(draw_err)?;
        entries.push(("raw rate".to_owned(), Mark::Line(RAW, 2)));
        chart.draw_series(LineSeries::new(comp, COMPENSATED.stroke_width(1))).map_err(draw_err)?;
        entries.push(("compensated = raw − drift".to_owned(), Mark::Line(COMPENSATED, 2)));
        legend(&chart.plotting_area().strip_coord_spec(), &entries, Corner::UpperRight, 13.0)
    }

    /// The drift estimate with its ±1σ band over the raw rate of the static samples (the noise
    /// envelope per pixel column), zoomed on them.
    fn drift_panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        t: (f64, f64),
        axis: &AxisTrace,
        flags: &Flags,
    ) -> Result<(), PlotError> {
        let still: Vec<f64> = (0..axis.raw.len())
            .map(|i| {
                if self.moving.get(i) == Some(&false) && self.rejected.get(i) == Some(&false) {
                    0.0
                } else {
                    f64::INFINITY
                }
            })
            .collect();
        let noise = envelope(self.t_s, &axis.raw, &still, COLUMNS);
        let band = envelope(self.t_s, &axis.drift, &axis.drift_std, COLUMNS);
        let drift = decimate_min_max(self.t_s, &axis.drift, COLUMNS);
        // Zoom: the static raw rate (0.1–99.9 % quantiles) and the estimate; the band is clipped.
        let static_raw = || axis.raw.iter().zip(&still).filter(|p| *p.1 == 0.0).map(|p| *p.0);
        let (q_lo, q_hi) = (quantile(static_raw(), 0.001), quantile(static_raw(), 0.999));
        let (y0, y1) = range(drift.iter().map(|p| p.1).chain([q_lo, q_hi]), false, 0.08);
        let y_desc = format!("{} drift (deg/s)", axis.column);
        let (mut chart, mut entries) = Self::panel(area, t, (y0, y1), &y_desc, flags)?;
        let columns = noise
            .iter()
            .flatten()
            .map(|&(x, lo, hi)| PathElement::new(vec![(x, lo.max(y0)), (x, hi.min(y1))], RAW.mix(0.6)));
        chart.draw_series(columns).map_err(draw_err)?;
        entries.push(("raw rate, static samples".to_owned(), Mark::Line(RAW, 2)));
        let shade = DRIFT.mix(0.25).filled();
        for run in &band {
            let mut outline: Vec<(f64, f64)> = run.iter().map(|&(x, _, hi)| (x, hi.clamp(y0, y1))).collect();
            outline.extend(run.iter().rev().map(|&(x, lo, _)| (x, lo.clamp(y0, y1))));
            chart.draw_series(std::iter::once(Polygon::new(outline, shade))).map_err(draw_err)?;
        }
        entries.push(("drift ±1σ".to_owned(), Mark::Fill(DRIFT, 0.25)));
        chart.draw_series(LineSeries::new(drift, DRIFT.stroke_width(2))).map_err(draw_err)?;
        entries.push(("drift estimate".to_owned(), Mark::Line(DRIFT, 2)));
        legend(&chart.plotting_area().strip_coord_spec(), &entries, Corner::UpperRight, 13.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_merge_across_short_gaps() {
        let t: Vec<f64> = (0..10).map(f64::from).collect();
        let f = [false, true, true, false, true, false, false, false, true, true];
        assert_eq!(flag_spans(&t, &f, 0.5), vec![(1.0, 2.0), (4.0, 4.0), (8.0, 9.0)]);
        assert_eq!(flag_spans(&t, &f, 2.5), vec![(1.0, 4.0), (8.0, 9.0)]);
        assert!(flag_spans(&t, &[false; 10], 1.0).is_empty());
    }

    #[test]
    fn envelope_skips_unknown_sigma() {
        let x: Vec<f64> = (0..6).map(f64::from).collect();
        let mid = [0.0; 6];
        let sd = [f64::INFINITY, 1.0, 1.0, f64::INFINITY, 2.0, 2.0];
        let runs = envelope(&x, &mid, &sd, 6);
        assert_eq!(runs, vec![vec![(1.0, -1.0, 1.0), (2.0, -1.0, 1.0)], vec![(4.0, -2.0, 2.0), (5.0, -2.0, 2.0)]]);
    }
}
