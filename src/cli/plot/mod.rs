//! Plots of the command line (`allan --plot`, `compensate --plot`, `eval --protocol motion
//! --plot`, the simgap report), all drawn with `plotters`.
//!
//! The format follows the output file's extension ([`PlotFormat`]): `.svg` (text as `<text>`
//! elements, so no font is needed to write it) or `.png` (the bitmap backend; its text is drawn
//! with a TrueType font found on the system at run time, [`FONT_CANDIDATES`] or `GYROCOMP_FONT`,
//! and a clear error names what to install when there is none). Each figure is a [`Figure`]: it
//! draws itself on any plotters backend, so one figure gives both formats.

pub mod allan;
pub mod compensate;
pub mod motion;
pub mod simgap;
pub mod svg;

use std::path::Path;
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// An error while drawing or writing a plot: the message names the file.
pub type PlotError = String;

/// Environment variable naming a TrueType/OpenType font file for PNG text.
pub const FONT_ENV: &str = "GYROCOMP_FONT";

/// Where PNG output looks for a font (sans-serif), in order, after [`FONT_ENV`].
pub const FONT_CANDIDATES: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu-sans-fonts/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/usr/share/fonts/liberation-sans/LiberationSans-Regular.ttf",
    "/usr/share/fonts/truetype/freefont/FreeSans.ttf",
    "/usr/share/fonts/noto/NotoSans-Regular.ttf",
    "/usr/share/fonts/truetype/noto/NotoSans-Regular.ttf",
    "/System/Library/Fonts/Supplemental/Arial.ttf",
    "/Library/Fonts/Arial.ttf",
    "C:\\Windows\\Fonts\\arial.ttf",
];

/// The font family every figure uses (registered under this name for PNG).
pub const FAMILY: &str = "sans-serif";

/// The image format of a plot file, from its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlotFormat {
    /// Scalable vector graphics (`.svg`).
    Svg,
    /// Portable network graphics (`.png`).
    Png,
}

impl PlotFormat {
    /// The format of `path` from its extension (case-insensitive); an error naming the file
    /// and the extensions understood otherwise.
    pub fn of(path: &Path) -> Result<Self, PlotError> {
        match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("svg") => Ok(Self::Svg),
            Some("png") => Ok(Self::Png),
            _ => Err(format!("{}: unknown plot format: the file name must end in .svg or .png", path.display())),
        }
    }
}

/// A figure that draws itself on any plotters backend.
pub trait Figure {
    /// Width and height in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws the figure on `root` (the whole image).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError>;
}

/// Draws `figure` into `path`, SVG or PNG by its extension ([`PlotFormat::of`]).
pub fn save(figure: &impl Figure, path: &Path) -> Result<(), PlotError> {
    let format = PlotFormat::of(path)?;
    let in_file = |e: PlotError| format!("{}: {e}", path.display());
    match format {
        PlotFormat::Svg => {
            let text = to_svg(figure).map_err(in_file)?;
            std::fs::write(path, text).map_err(|e| format!("{}: cannot write: {e}", path.display()))
        }
        PlotFormat::Png => {
            ensure_font().map_err(in_file)?;
            if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty() && !d.is_dir()) {
                return Err(format!("{}: cannot write: folder {} does not exist", path.display(), dir.display()));
            }
            let root = BitMapBackend::new(path, figure.size()).into_drawing_area();
            root.fill(&WHITE).map_err(draw_err).map_err(in_file)?;
            figure.draw(&root).map_err(in_file)?;
            root.present().map_err(|e| format!("{}: cannot write: {e}", path.display()))
        }
    }
}

/// The figure as SVG text (for embedding in HTML).
pub fn to_svg(figure: &impl Figure) -> Result<String, PlotError> {
    svg::render(figure.size(), |root| figure.draw(root))
}

/// A plotters drawing error as text.
pub fn draw_err<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> PlotError {
    format!("cannot draw: {e}")
}

/// Registers a system font for PNG text once per process ([`FONT_CANDIDATES`]).
fn ensure_font() -> Result<(), PlotError> {
    static FONT: OnceLock<Result<(), PlotError>> = OnceLock::new();
    FONT.get_or_init(|| {
        let hint = "install a font (Debian/Ubuntu: apt-get install fonts-dejavu-core) or write the plot as .svg, which needs no font";
        if let Some(p) = std::env::var_os(FONT_ENV).map(std::path::PathBuf::from) {
            return register(&p).map_err(|e| format!("{FONT_ENV}={}: {e}; set it to a .ttf file, or {hint}", p.display()));
        }
        for p in FONT_CANDIDATES.iter().map(Path::new).filter(|p| p.is_file()) {
            match register(p) {
                Ok(()) => return Ok(()),
                Err(e) => tracing::debug!("font {}: {e}", p.display()),
            }
        }
        Err(format!(
            "PNG output draws its text with a TrueType font and none was found (looked for {} and \
             {} other paths); set {FONT_ENV} to a .ttf file, or {hint}",
            FONT_CANDIDATES[0],
            FONT_CANDIDATES.len() - 1
        ))
    })
    .clone()
}

fn register(path: &Path) -> Result<(), String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read: {e}"))?;
    // plotters keeps registered fonts for the life of the process: one font, leaked once.
    let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
    plotters::style::register_font(FAMILY, FontStyle::Normal, bytes)
        .map_err(|_| "not a TrueType/OpenType font".to_owned())?;
    tracing::debug!("PNG text font: {}", path.display());
    Ok(())
}

/// The file name of `path` for a title (the whole path when it has none).
pub fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned())
}

/// A text style of [`FAMILY`] at `size` pixels.
pub fn font(size: f64) -> TextStyle<'static> {
    (FAMILY, size).into_font().into()
}

/// The symbol of a legend entry.
#[derive(Debug, Clone, Copy)]
pub enum Mark {
    /// A solid line of this colour and width.
    Line(RGBColor, u32),
    /// A dashed line of this colour and width.
    Dashed(RGBColor, u32),
    /// A filled box of this colour and opacity.
    Fill(RGBColor, f64),
    /// A filled dot of this colour.
    Dot(RGBColor),
}

/// Where a legend sits in its plotting area.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Corner {
    /// Top left.
    UpperLeft,
    /// Top right.
    UpperRight,
}

/// Draws a legend box of `entries` in a corner of `area` (a chart's plotting area), text of
/// `size` pixels. plotters' own series legend measures its text with the font engine directly,
/// which SVG output without a font cannot do; this one measures through the backend.
pub fn legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[(String, Mark)],
    corner: Corner,
    size: f64,
) -> Result<(), PlotError> {
    if entries.is_empty() {
        return Ok(());
    }
    let style = font(size).pos(Pos::new(HPos::Left, VPos::Center));
    let mut text_w = 0;
    for (label, _) in entries {
        text_w = text_w.max(area.estimate_text_size(label, &style).map_err(draw_err)?.0 as i32);
    }
    let (pad, mark_w, line_h) = (8, 22, (size * 1.3).ceil() as i32);
    let (w, h) = (pad * 3 + mark_w + text_w, pad * 2 + line_h * entries.len() as i32);
    let area_w = area.dim_in_pixel().0 as i32;
    let (x0, y0) = match corner {
        Corner::UpperLeft => (10, 10),
        Corner::UpperRight => (area_w - w - 10, 10),
    };
    area.draw(&Rectangle::new([(x0, y0), (x0 + w, y0 + h)], WHITE.mix(0.88).filled())).map_err(draw_err)?;
    area.draw(&Rectangle::new([(x0, y0), (x0 + w, y0 + h)], RGBColor(160, 160, 160))).map_err(draw_err)?;
    for (k, (label, mark)) in entries.iter().enumerate() {
        let y = y0 + pad + line_h * k as i32 + line_h / 2;
        let (a, b) = (x0 + pad, x0 + pad + mark_w);
        match *mark {
            Mark::Line(c, width) => area.draw(&PathElement::new(vec![(a, y), (b, y)], c.stroke_width(width))),
            Mark::Dashed(c, width) => area
                .draw(&PathElement::new(vec![(a, y), (a + 8, y)], c.stroke_width(width)))
                .and_then(|()| area.draw(&PathElement::new(vec![(b - 8, y), (b, y)], c.stroke_width(width)))),
            Mark::Fill(c, alpha) => area.draw(&Rectangle::new([(a, y - 6), (b, y + 6)], c.mix(alpha).filled())),
            Mark::Dot(c) => area.draw(&Circle::new(((a + b) / 2, y), 4, c.filled())),
        }
        .map_err(draw_err)?;
        area.draw(&Text::new(label.clone(), (b + pad, y), style.clone())).map_err(draw_err)?;
    }
    Ok(())
}

/// Min/max decimation for drawing: at most `2·columns` points that keep each column's extremes
/// (in time order), so a line through them looks like the full series at that width. Returns
/// (x, y) pairs; the input unchanged when it is already short enough. Non-finite values skipped.
pub fn decimate_min_max(x: &[f64], y: &[f64], columns: usize) -> Vec<(f64, f64)> {
    let len = x.len().min(y.len());
    let columns = columns.max(1);
    if len <= 2 * columns {
        return (0..len).filter(|&i| y[i].is_finite()).map(|i| (x[i], y[i])).collect();
    }
    let mut out = Vec::with_capacity(2 * columns);
    for c in 0..columns {
        let (a, b) = (c * len / columns, ((c + 1) * len / columns).min(len));
        let finite = (a..b).filter(|&i| y[i].is_finite());
        let lo = finite.clone().min_by(|&i, &j| y[i].total_cmp(&y[j]));
        let hi = finite.max_by(|&i, &j| y[i].total_cmp(&y[j]));
        if let (Some(lo), Some(hi)) = (lo, hi) {
            let (first, second) = if lo <= hi { (lo, hi) } else { (hi, lo) };
            out.push((x[first], y[first]));
            if second != first {
                out.push((x[second], y[second]));
            }
        }
    }
    out
}

/// The range of the finite values of `values` (of the positive ones when `log`), widened by
/// `pad` of its span (a factor for `log`) on each side; (0, 1) or (1, 10) when there is none.
pub fn range(values: impl Iterator<Item = f64>, log: bool, pad: f64) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return if log { (1.0, 10.0) } else { (0.0, 1.0) };
    }
    if log {
        let f = if hi > lo { (hi / lo).powf(pad) } else { 2.0 };
        (lo / f, hi * f)
    } else {
        let d = if hi > lo { pad * (hi - lo) } else { lo.abs().max(1.0) * 0.5 };
        (lo - d, hi + d)
    }
}

/// A tick label for a log axis: powers of ten as `1e-3`, others in short `{:e}` form.
pub fn log_label(v: &f64) -> String {
    let e = v.log10();
    if (e - e.round()).abs() < 1e-9 { format!("1e{}", e.round() as i32) } else { format!("{v:.1e}") }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_follows_the_extension() {
        assert_eq!(PlotFormat::of(Path::new("a/b.SVG")), Ok(PlotFormat::Svg));
        assert_eq!(PlotFormat::of(Path::new("b.png")), Ok(PlotFormat::Png));
        let e = PlotFormat::of(Path::new("b.pdf")).unwrap_err();
        assert!(e.contains("b.pdf") && e.contains(".svg or .png"), "{e}");
        assert!(PlotFormat::of(Path::new("noext")).is_err());
    }

    #[test]
    fn decimation_keeps_the_extremes_of_each_column() {
        let x: Vec<f64> = (0..1000).map(f64::from).collect();
        let mut y: Vec<f64> = x.iter().map(|v| (v * 0.1).sin()).collect();
        y[500] = 9.0;
        y[501] = f64::NAN;
        let d = decimate_min_max(&x, &y, 10);
        assert!(d.len() <= 20);
        assert!(d.contains(&(500.0, 9.0)));
        assert!(d.windows(2).all(|w| w[0].0 < w[1].0), "time order");
        assert_eq!(decimate_min_max(&x[..5], &y[..5], 10).len(), 5);
    }

    #[test]
    fn ranges_pad_and_survive_empty_input() {
        assert_eq!(range([1.0, 3.0].into_iter(), false, 0.5), (0.0, 4.0));
        let (lo, hi) = range([0.0, 1e-3, 1e-1, f64::NAN].into_iter(), true, 0.0);
        assert_eq!((lo, hi), (1e-3, 1e-1));
        assert_eq!(range(std::iter::empty(), true, 0.1), (1.0, 10.0));
        assert_eq!(log_label(&1e-3), "1e-3");
    }
}
