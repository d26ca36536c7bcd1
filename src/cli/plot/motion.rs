//! `gyrocomp eval --protocol motion --plot F`: the angle error |∫(compensated − truth)dt| of each
//! model in each motion segment (log scale), against the white-noise floor 0.674·N·√T of that
//! segment, which no drift model can go below.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{Corner, Figure, Mark, PlotError, draw_err, font, legend, log_label, range};

/// Colours of the models, in order (repeated past twelve).
const COLOURS: [RGBColor; 12] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(0, 0, 128),
    RGBColor(110, 110, 0),
];
/// Width of the legend panel right of the chart, pixels.
const LEGEND_W: u32 = 330;

/// One model's angle error per motion segment.
#[derive(Debug, Clone)]
pub struct ModelErrors {
    /// Model name.
    pub name: String,
    /// |∫(compensated − truth)dt| of each segment, deg.
    pub angle_err_deg: Vec<f64>,
    /// Median of the same, deg (legend).
    pub median_deg: Option<f64>,
}

/// The motion-protocol plot.
pub struct MotionFigure<'a> {
    /// Title (e.g. the input file and column).
    pub title: String,
    /// The models.
    pub models: &'a [ModelErrors],
    /// White-noise floor of each segment, deg (empty when unknown).
    pub floor_deg: &'a [f64],
    /// Length of each segment, s.
    pub segment_s: &'a [f64],
}

impl Figure for MotionFigure<'_> {
    fn size(&self) -> (u32, u32) {
        (1100 + LEGEND_W, 680)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let segments =
            self.models.iter().map(|m| m.angle_err_deg.len()).chain([self.floor_deg.len()]).max().unwrap_or(0);
        let values = self.models.iter().flat_map(|m| m.angle_err_deg.iter()).chain(self.floor_deg).copied();
        let (y_lo, y_hi) = range(values, true, 0.08);
        let (width, _) = root.dim_in_pixel();
        let (root, side) = root.split_horizontally(width.saturating_sub(LEGEND_W));
        let (x_lo, x_hi) = (0.5, segments.max(1) as f64 + 0.5);
        let mut chart = ChartBuilder::on(&root)
            .caption(&self.title, font(21.0))
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(78)
            .build_cartesian_2d(x_lo..x_hi, (y_lo..y_hi).log_scale())
            .map_err(draw_err)?;
        let durations = self.segment_s;
        chart
            .configure_mesh()
            .x_desc("motion segment (number: length in s)")
            .y_desc("angle error |∫(compensated − truth)dt| (deg)")
            .x_labels(segments.clamp(2, 16))
            .x_label_formatter(&|x| {
                let k = x.round();
                if (x - k).abs() > 1e-6 || k < 1.0 {
                    return String::new();
                }
                let i = k as usize - 1;
                durations.get(i).map_or(format!("{k}"), |d| format!("{k}: {d:.0}"))
            })
            .y_label_formatter(&log_label)
            .label_style(font(14.0))
            .axis_desc_style(font(16.0))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(draw_err)?;
        let at = |i: usize, v: f64| ((i + 1) as f64, v.max(y_lo));
        let mut entries = Vec::new();
        if !self.floor_deg.is_empty() {
            let floor: Vec<(f64, f64)> = self.floor_deg.iter().enumerate().map(|(i, &v)| at(i, v)).collect();
            chart.draw_series(DashedLineSeries::new(floor, 10, 6, BLACK.stroke_width(2))).map_err(draw_err)?;
            entries.push(("white-noise floor 0.674·N·√T".to_owned(), Mark::Dashed(BLACK, 2)));
        }
        for (k, m) in self.models.iter().enumerate() {
            let colour = COLOURS[k % COLOURS.len()];
            let points: Vec<(f64, f64)> = m.angle_err_deg.iter().enumerate().map(|(i, &v)| at(i, v)).collect();
            chart.draw_series(LineSeries::new(points.clone(), colour.mix(0.6).stroke_width(1))).map_err(draw_err)?;
            chart.draw_series(points.iter().map(|&p| Circle::new(p, 4, colour.filled()))).map_err(draw_err)?;
            let median = m.median_deg.map_or_else(|| "—".to_owned(), |v| format!("{v:.3}"));
            entries.push((format!("{} (median {median} deg)", m.name), Mark::Dot(colour)));
        }
        // Beside the chart: a dozen models would hide the points under it.
        let side = side.margin(46, 0, 0, 0);
        legend(&side, &entries, Corner::UpperLeft, 14.0)?;
        Ok(())
    }
}
