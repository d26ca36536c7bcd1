//! The plots of the simgap report (`gyrocomp simgap --report DIR`): a statistic of the real
//! recording against the simulated 95 % bands before and after the chosen effects
//! ([`BandFigure`]: Allan deviation, PSD bands, bias trajectory), and the gap with each effect
//! added ([`RankingFigure`]).

use plotters::coord::Shift;
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::prelude::*;

use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::diag::simgap::stats::fmt_num;

use super::{Corner, Figure, Mark, PlotError, draw_err, font, legend, log_label, range};

const BEFORE: RGBColor = RGBColor(0xbb, 0xbb, 0xbb);
const AFTER: RGBColor = RGBColor(0x6f, 0xa8, 0xdc);
const REAL: RGBColor = RGBColor(0xc0, 0x39, 0x2b);

/// The quantile band of a simulated ensemble over the points of a statistic.
#[derive(Debug, Clone, Default)]
pub struct Band {
    /// 2.5 % quantile at each point.
    pub lo: Vec<f64>,
    /// Median at each point.
    pub median: Vec<f64>,
    /// 97.5 % quantile at each point.
    pub hi: Vec<f64>,
}

/// A statistic of the real recording against two simulated bands (before and after effects).
pub struct BandFigure<'a> {
    /// Title.
    pub title: String,
    /// Abscissa of each point (τ, frequency or time).
    pub x: &'a [f64],
    /// The real recording's value at each point.
    pub real: &'a [f64],
    /// The baseline simulation's band.
    pub before: &'a Band,
    /// The band with the chosen effects.
    pub after: &'a Band,
    /// Legend of the `after` band.
    pub after_label: &'a str,
    /// Axis descriptions (x, y), with units.
    pub labels: (&'a str, &'a str),
    /// Log-log axes (else linear).
    pub log: bool,
}

impl Figure for BandFigure<'_> {
    fn size(&self) -> (u32, u32) {
        (640, 380)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let ys = || {
            self.real
                .iter()
                .chain([self.before, self.after].into_iter().flat_map(|b| b.lo.iter().chain(&b.median).chain(&b.hi)))
        };
        let (x0, x1) = range(self.x.iter().copied(), self.log, 0.03);
        let (y0, y1) = range(ys().copied(), self.log, 0.05);
        // Room above the data for the legend.
        let y1 = if self.log { y1 * (y1 / y0).powf(0.4) } else { y1 + 0.4 * (y1 - y0) };
        let mut builder = ChartBuilder::on(root);
        builder.caption(&self.title, font(16.0)).margin(8).x_label_area_size(36).y_label_area_size(64);
        if self.log {
            let mut chart = builder.build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale()).map_err(draw_err)?;
            self.content(&mut chart, &log_label, (y0, y1))
        } else {
            let mut chart = builder.build_cartesian_2d(x0..x1, y0..y1).map_err(draw_err)?;
            self.content(&mut chart, &|v: &f64| fmt_num(*v), (y0, y1))
        }
    }
}

impl BandFigure<'_> {
    fn content<'a, DB: DrawingBackend + 'a, X, Y>(
        &self,
        chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
        fmt: &dyn Fn(&f64) -> String,
        (y0, y1): (f64, f64),
    ) -> Result<(), PlotError>
    where
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        chart
            .configure_mesh()
            .x_desc(self.labels.0)
            .y_desc(self.labels.1)
            .x_label_formatter(fmt)
            .y_label_formatter(fmt)
            .x_labels(7)
            .y_labels(6)
            .label_style(font(12.0))
            .axis_desc_style(font(13.0))
            .light_line_style(RGBColor(238, 238, 238))
            .draw()
            .map_err(draw_err)?;
        let clamp = |v: f64| v.clamp(y0, y1);
        let mut entries = vec![("real".to_owned(), Mark::Dot(REAL))];
        for (band, colour, label) in
            [(self.before, BEFORE, "baseline sim, 95 % band"), (self.after, AFTER, self.after_label)]
        {
            let mut outline: Vec<(f64, f64)> = self.x.iter().zip(&band.hi).map(|(&x, &v)| (x, clamp(v))).collect();
            outline.extend(self.x.iter().zip(&band.lo).rev().map(|(&x, &v)| (x, clamp(v))));
            chart.draw_series(std::iter::once(Polygon::new(outline, colour.mix(0.45).filled()))).map_err(draw_err)?;
            entries.push((label.to_owned(), Mark::Fill(colour, 0.45)));
            let median: Vec<(f64, f64)> = self.x.iter().zip(&band.median).map(|(&x, &v)| (x, clamp(v))).collect();
            chart.draw_series(DashedLineSeries::new(median, 5, 4, colour.stroke_width(2))).map_err(draw_err)?;
        }
        let real: Vec<(f64, f64)> = self.x.iter().zip(self.real).map(|(&x, &v)| (x, clamp(v))).collect();
        chart.draw_series(LineSeries::new(real.clone(), REAL.stroke_width(2))).map_err(draw_err)?;
        chart.draw_series(real.iter().map(|&p| Circle::new(p, 3, REAL.filled()))).map_err(draw_err)?;
        legend(&chart.plotting_area().strip_coord_spec(), &entries, Corner::UpperRight, 12.0)?;
        Ok(())
    }
}

/// One effect's gap on the training and hold-out parts.
#[derive(Debug, Clone)]
pub struct RankingRow {
    /// Effect name.
    pub name: String,
    /// Gap on the training part with the effect added.
    pub train: f64,
    /// Gap on the hold-out part with the effect added.
    pub hold: f64,
}

/// Which gap of a row a bar shows.
type Pick = fn(&RankingRow) -> f64;

/// Height of the legend strip under the ranking chart, pixels.
const LEGEND_H: u32 = 96;

/// Horizontal bars of the gap with each effect added, against the baseline's gaps.
pub struct RankingFigure<'a> {
    /// The effects, top to bottom.
    pub rows: &'a [RankingRow],
    /// The baseline's gap (training, hold-out).
    pub baseline: (f64, f64),
}

impl Figure for RankingFigure<'_> {
    fn size(&self) -> (u32, u32) {
        (640, 120 + LEGEND_H + 44 * self.rows.len().max(1) as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let rows = self.rows.len().max(1);
        let max = self
            .rows
            .iter()
            .flat_map(|r| [r.train, r.hold])
            .chain([self.baseline.0, self.baseline.1])
            .fold(0.0, f64::max);
        // Room right of the longest bar for its value.
        let x1 = (max * 1.3).max(1e-9);
        let (y0, y1) = (-0.6, rows as f64 - 0.4);
        // Row i (top to bottom) sits at y = rows − 1 − i.
        let row_y = |i: usize| (rows - 1 - i) as f64;
        let names: Vec<String> = self.rows.iter().rev().map(|r| r.name.clone()).collect();
        let (_, height) = root.dim_in_pixel();
        let (root, strip) = root.split_vertically(height.saturating_sub(LEGEND_H));
        let mut chart = ChartBuilder::on(&root)
            .caption("Gap with each effect added (shorter is better)", font(16.0))
            .margin(8)
            .x_label_area_size(36)
            .y_label_area_size(110)
            .build_cartesian_2d(0.0..x1, y0..y1)
            .map_err(draw_err)?;
        chart
            .configure_mesh()
            .disable_y_mesh()
            .light_line_style(WHITE)
            .x_desc("gap (RMS standard score)")
            .y_labels(rows * 4 + 1)
            .y_label_formatter(&|y| {
                let k = y.round();
                if (y - k).abs() > 1e-6 || k < 0.0 {
                    return String::new();
                }
                names.get(k as usize).cloned().unwrap_or_default()
            })
            .label_style(font(12.0))
            .axis_desc_style(font(13.0))
            .draw()
            .map_err(draw_err)?;
        let train = RGBColor(0x88, 0x88, 0x88);
        let bars = |pick: Pick, off: (f64, f64)| {
            self.rows
                .iter()
                .enumerate()
                .map(move |(i, r)| (row_y(i) - off.1, row_y(i) - off.0, pick(r)))
                .collect::<Vec<_>>()
        };
        let mut entries = Vec::new();
        let parts: [(Pick, (f64, f64), RGBColor, &str); 2] =
            [(|r| r.train, (-0.34, -0.02), train, "training"), (|r| r.hold, (0.02, 0.34), AFTER, "hold-out")];
        for (pick, off, colour, label) in parts {
            let rects =
                bars(pick, off).into_iter().map(|(a, b, v)| Rectangle::new([(0.0, a), (v, b)], colour.filled()));
            chart.draw_series(rects).map_err(draw_err)?;
            entries.push((label.to_owned(), Mark::Fill(colour, 1.0)));
        }
        chart
            .draw_series(self.rows.iter().enumerate().map(|(i, r)| {
                let at = (r.train.max(r.hold) + 0.01 * x1, row_y(i));
                Text::new(
                    format!("{:.2} / {:.2}", r.train, r.hold),
                    at,
                    font(12.0).pos(Pos::new(HPos::Left, VPos::Center)),
                )
            }))
            .map_err(draw_err)?;
        for (v, colour, label) in [
            (self.baseline.0, RGBColor(0x55, 0x55, 0x55), "baseline, training"),
            (self.baseline.1, REAL, "baseline, hold-out"),
        ] {
            chart
                .draw_series(DashedLineSeries::new([(v, y0), (v, y1)], 6, 4, colour.stroke_width(2)))
                .map_err(draw_err)?;
            entries.push((format!("{label} {v:.2}"), Mark::Dashed(colour, 2)));
        }
        // Under the chart: inside it, the legend would cover the longest bar, wherever that is.
        legend(&strip.margin(0, 0, 110, 0), &entries, Corner::UpperLeft, 12.0)?;
        Ok(())
    }
}
