//! SVG output that needs no font: plotters' SVG backend writes text as `<text>` elements (the
//! viewer picks the font), but plotters measures text to lay out tick labels and legends, and with
//! its `ab_glyph` font engine (needed for PNG) that measurement fails when no font is registered.
//! [`FontFreeSvg`] wraps the SVG backend and answers the measurement from the character count
//! (a sans-serif average of 0.6 em per character), so SVG plots are written on any machine.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters_backend::{BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind};

/// Average advance of a sans-serif character, in em.
const EM_PER_CHAR: f64 = 0.6;

/// plotters' SVG backend with text measured without a font (module docs).
pub struct FontFreeSvg<'a>(SVGBackend<'a>);

/// Draws with `draw` on an SVG canvas of `size` pixels (white background) and returns the SVG text.
pub fn render(
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<FontFreeSvg<'_>, Shift>) -> Result<(), String>,
) -> Result<String, String> {
    let mut text = String::new();
    {
        let root = FontFreeSvg(SVGBackend::with_string(&mut text, size)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| format!("cannot draw: {e}"))?;
        draw(&root)?;
        root.present().map_err(|e| format!("cannot draw: {e}"))?;
    }
    Ok(text)
}

type Result2<E> = Result<(), DrawingErrorKind<E>>;

impl DrawingBackend for FontFreeSvg<'_> {
    type ErrorType = <SVGBackend<'static> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.0.get_size()
    }
    fn ensure_prepared(&mut self) -> Result2<Self::ErrorType> {
        self.0.ensure_prepared()
    }
    fn present(&mut self) -> Result2<Self::ErrorType> {
        self.0.present()
    }
    fn draw_pixel(&mut self, point: BackendCoord, color: BackendColor) -> Result2<Self::ErrorType> {
        self.0.draw_pixel(point, color)
    }
    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result2<Self::ErrorType> {
        self.0.draw_line(from, to, style)
    }
    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result2<Self::ErrorType> {
        self.0.draw_rect(upper_left, bottom_right, style, fill)
    }
    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result2<Self::ErrorType> {
        self.0.draw_path(path, style)
    }
    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result2<Self::ErrorType> {
        self.0.draw_circle(center, radius, style, fill)
    }
    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result2<Self::ErrorType> {
        self.0.fill_polygon(vert, style)
    }
    fn draw_text<S: BackendTextStyle>(&mut self, text: &str, style: &S, pos: BackendCoord) -> Result2<Self::ErrorType> {
        self.0.draw_text(text, style, pos)
    }
    fn estimate_text_size<S: BackendTextStyle>(
        &self,
        text: &str,
        style: &S,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        // plotters' font size is 1.24 × the CSS size it writes (`font-size = size / 1.24`).
        let em = style.size() / 1.24;
        let width = (EM_PER_CHAR * em * text.chars().count() as f64).ceil() as u32;
        Ok((width, em.ceil() as u32))
    }
    fn blit_bitmap(&mut self, pos: BackendCoord, (iw, ih): (u32, u32), src: &[u8]) -> Result2<Self::ErrorType> {
        self.0.blit_bitmap(pos, (iw, ih), src)
    }
}
