//! A plotters bitmap backend that can draw text without a font library.
//!
//! plotters draws text on bitmaps through a font feature (`ttf`, which pulls in font-kit and
//! the system's FreeType/fontconfig, or `ab_glyph`, which needs a font file at run time);
//! without one its bitmap backend panics on the first label. This wrapper forwards every
//! shape to plotters' `BitMapBackend` and draws text itself from the public-domain 8x8 glyphs
//! of the `font8x8` crate, scaled by whole pixels, honouring anchors and 90-degree rotations.
//! The SVG plot needs none of this: SVG viewers draw its text.

use font8x8::legacy::BASIC_LEGACY;
use plotters::backend::BitMapBackend;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};

/// Pixel height of one unscaled glyph.
const GLYPH: i32 = 8;

/// `BitMapBackend` plus 8x8 bitmap text.
pub struct TextBitmap<'a> {
    inner: BitMapBackend<'a>,
}

impl<'a> TextBitmap<'a> {
    /// Draws into `rgb` (width x height x 3 bytes).
    pub fn new(rgb: &'a mut [u8], size: (u32, u32)) -> Self {
        Self {
            inner: BitMapBackend::with_buffer(rgb, size),
        }
    }
}

/// Whole-pixel scale for a font size. plotters lays out legends and multi-line text with its
/// own estimate (about 0.455 x size per character, 0.8 x size per line), so glyphs are scaled
/// to fit inside it: sizes below 35 draw at 8 px, 35 to 52 at 16 px, and so on.
fn scale(size: f64) -> i32 {
    ((size * 0.455 / GLYPH as f64).floor() as i32).max(1)
}

fn glyph(c: char) -> [u8; 8] {
    let i = c as usize;
    if i < 128 {
        BASIC_LEGACY[i]
    } else {
        BASIC_LEGACY['?' as usize]
    }
}

type Res<E> = Result<(), DrawingErrorKind<E>>;

impl DrawingBackend for TextBitmap<'_> {
    type ErrorType = <BitMapBackend<'static> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }
    fn ensure_prepared(&mut self) -> Res<Self::ErrorType> {
        self.inner.ensure_prepared()
    }
    fn present(&mut self) -> Res<Self::ErrorType> {
        self.inner.present()
    }
    fn draw_pixel(&mut self, point: BackendCoord, color: BackendColor) -> Res<Self::ErrorType> {
        self.inner.draw_pixel(point, color)
    }
    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Res<Self::ErrorType> {
        self.inner.draw_line(from, to, style)
    }
    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Res<Self::ErrorType> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }
    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Res<Self::ErrorType> {
        self.inner.draw_path(path, style)
    }
    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Res<Self::ErrorType> {
        self.inner.draw_circle(center, radius, style, fill)
    }
    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Res<Self::ErrorType> {
        self.inner.fill_polygon(vert, style)
    }
    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Res<Self::ErrorType> {
        self.inner.blit_bitmap(pos, size, src)
    }

    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Res<Self::ErrorType> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let s = scale(style.size());
        let (w, h) = (GLYPH * s * text.chars().count() as i32, GLYPH * s);
        let anchor = style.anchor();
        let dx = match anchor.h_pos {
            HPos::Left => 0,
            HPos::Right => -w,
            HPos::Center => -w / 2,
        };
        let dy = match anchor.v_pos {
            VPos::Top => 0,
            VPos::Center => -h / 2,
            VPos::Bottom => -h,
        };
        let transform = style.transform();
        let (width, height) = self.get_size();
        for (ci, c) in text.chars().enumerate() {
            for (row, bits) in glyph(c).iter().enumerate() {
                for col in 0..8 {
                    if bits >> col & 1 == 0 {
                        continue;
                    }
                    for sy in 0..s {
                        for sx in 0..s {
                            let x = ci as i32 * GLYPH * s + col * s + sx + dx;
                            let y = row as i32 * s + sy + dy;
                            let (x, y) = transform.transform(x, y);
                            let (x, y) = (pos.0 + x, pos.1 + y);
                            if x >= 0 && y >= 0 && x < width as i32 && y < height as i32 {
                                self.inner.draw_pixel((x, y), color)?;
                            }
                        }
                    }
                }
            }
        }
        Ok(())
    }

    fn estimate_text_size<S: BackendTextStyle>(
        &self,
        text: &str,
        style: &S,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        let s = scale(style.size()) as u32;
        Ok((
            GLYPH as u32 * s * text.chars().count() as u32,
            GLYPH as u32 * s,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::prelude::*;

    #[test]
    fn draws_text_where_the_anchor_says() {
        let (w, h) = (64u32, 16u32);
        let mut rgb = vec![255u8; (w * h * 3) as usize];
        {
            let root = TextBitmap::new(&mut rgb, (w, h)).into_drawing_area();
            root.draw_text("Hi", &("sans-serif", 12).into_font().color(&BLACK), (0, 0))
                .unwrap();
            root.present().unwrap();
        }
        let dark = |x: u32, y: u32| rgb[((y * w + x) * 3) as usize] < 128;
        assert!(
            (0..8).any(|y| (0..8).any(|x| dark(x, y))),
            "the H is drawn in the first cell"
        );
        assert!(
            !(0..16).any(|y| (20..64).any(|x| dark(x, y))),
            "nothing past two glyphs"
        );
        // 'H' in font8x8 has both vertical strokes: its left column lights on several rows.
        let left = (0..8).filter(|y| dark(0, *y)).count();
        assert!(
            left >= 5,
            "left stroke of H, least significant bit leftmost ({left} rows)"
        );
    }
}
