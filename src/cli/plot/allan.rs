//! `gyrocomp allan --plot F`: the measured overlapping Allan deviation with its 68 % χ² band, the
//! fitted IEEE Std 952-1997 curve and each fitted term as its straight line of slope −1, −½, 0,
//! +½ or +1 on log-log axes.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{Corner, Figure, Mark, PlotError, draw_err, font, legend, log_label, range};
use crate::diag::allan::AllanDeviation;
use crate::diag::noise_fit::NoiseFit;
use crate::diag::noise_model::{TERMS, basis};

/// Confidence level of the band around the measured points.
pub const BAND_LEVEL: f64 = 0.683;

/// Colour of each term's line, in the order Q, N, B, K, R.
const TERM_COLOURS: [RGBColor; TERMS] = [
    RGBColor(148, 103, 189),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(214, 39, 40),
];
/// Legend text of each term (name, slope, symbol, unit).
const TERM_LABELS: [(&str, &str, &str, &str); TERMS] = [
    ("quantisation", "-1", "Q", "deg"),
    ("white noise (ARW)", "-1/2", "N", "deg/√s"),
    ("bias instability", "0", "B", "deg/s"),
    ("rate random walk", "+1/2", "K", "deg/s/√s"),
    ("rate ramp", "+1", "R", "deg/s²"),
];

/// The Allan deviation plot of one rate column.
pub struct AllanFigure<'a> {
    /// Title (e.g. the file and column).
    pub title: String,
    /// The measured deviation (every τ computed).
    pub allan: &'a AllanDeviation,
    /// The noise-term fit, when there is one.
    pub fit: Option<&'a NoiseFit>,
}

impl Figure for AllanFigure<'_> {
    fn size(&self) -> (u32, u32) {
        (960, 680)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let a = self.allan;
        let band = a.confidence_band(BAND_LEVEL);
        let (x_lo, x_hi) = range(a.tau_s.iter().copied(), true, 0.03);
        // The y range covers the points and the fit, not the widest bands (ν = 1 at the last τ).
        let fitted = self.fit.map(|f| a.tau_s.iter().map(|&t| f.model.allan_deviation(t)).collect::<Vec<_>>());
        let (y_lo, y_hi) = range(a.adev.iter().chain(fitted.iter().flatten()).copied(), true, 0.15);
        // At least 2.5 decades, so that the term lines show beside the curve; at most 6.
        let (y_lo, y_hi) = (y_lo.min(y_hi / 316.0).max(y_hi / 1e6), y_hi * 2.0);
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, font(22.0))
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(78)
            .build_cartesian_2d((x_lo..x_hi).log_scale(), (y_lo..y_hi).log_scale())
            .map_err(draw_err)?;
        chart
            .configure_mesh()
            .x_desc("averaging time τ (s)")
            .y_desc("Allan deviation σ(τ) (deg/s)")
            .x_label_formatter(&log_label)
            .y_label_formatter(&log_label)
            .label_style(font(15.0))
            .axis_desc_style(font(17.0))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(draw_err)?;

        let clamp = |v: f64| v.clamp(y_lo, y_hi);
        let grey = RGBColor(120, 120, 120);
        let mut entries = Vec::new();
        let mut outline: Vec<(f64, f64)> = a.tau_s.iter().zip(&band).map(|(&t, b)| (t, clamp(b.1))).collect();
        outline.extend(a.tau_s.iter().zip(&band).rev().map(|(&t, b)| (t, clamp(b.0))));
        chart.draw_series(std::iter::once(Polygon::new(outline, grey.mix(0.25).filled()))).map_err(draw_err)?;
        entries.push((format!("{:.0} % χ² band, ν = N/m − 1", BAND_LEVEL * 100.0), Mark::Fill(grey, 0.25)));
        let points = a.tau_s.iter().zip(&a.adev).filter(|p| *p.1 > 0.0);
        chart.draw_series(points.map(|(&t, &d)| Circle::new((t, d), 3, BLACK.filled()))).map_err(draw_err)?;
        entries.push((format!("measured ({} samples at {} Hz)", a.samples, a.rate_hz), Mark::Dot(BLACK)));

        if let Some(fit) = self.fit {
            let squares = fit.model.squares();
            let grid: Vec<f64> = (0..=100).map(|i| x_lo * (x_hi / x_lo).powf(i as f64 / 100.0)).collect();
            let total: Vec<(f64, f64)> = grid.iter().map(|&t| (t, fit.model.allan_deviation(t))).collect();
            chart.draw_series(LineSeries::new(total, BLACK.stroke_width(2))).map_err(draw_err)?;
            entries.push((
                format!("IEEE 952 fit (RMS misfit {:.1} %)", 100.0 * fit.rms_relative_residual),
                Mark::Line(BLACK, 2),
            ));
            for j in (0..TERMS).filter(|&j| fit.active[j] && squares[j] > 0.0) {
                let (name, slope, symbol, unit) = TERM_LABELS[j];
                let line: Vec<(f64, f64)> = grid
                    .iter()
                    .map(|&t| (t, (basis(t)[j] * squares[j]).sqrt()))
                    .filter(|p| p.1 >= y_lo && p.1 <= y_hi)
                    .collect();
                let colour = TERM_COLOURS[j];
                chart.draw_series(DashedLineSeries::new(line, 8, 5, colour.stroke_width(2))).map_err(draw_err)?;
                let value = [fit.model.q, fit.model.n, fit.model.b, fit.model.k, fit.model.r][j];
                entries
                    .push((format!("{name}, slope {slope}: {symbol} = {value:.3e} {unit}"), Mark::Dashed(colour, 2)));
            }
        }
        legend(&chart.plotting_area().strip_coord_spec(), &entries, Corner::UpperRight, 14.0)?;
        Ok(())
    }
}
