//! PNG output without spikes: plotters' bitmap backend, with wide polylines
//! split at their sharp turns.
//!
//! Plotters fills a polyline wider than one pixel as a single polygon whose
//! corners are where the line's offset edges meet. At a turn of more than
//! 90° the edges on the inside of the turn meet far from the line (at a
//! near reversal, arbitrarily far), and nothing caps that side: a noisy
//! trace (an accelerogram, a periodogram, a deaggregation sampled finely)
//! threw spikes across its panel and into the next one in the PNGs, though
//! the SVGs, whose renderers join lines themselves, were right.
//!
//! [`Raster`] wraps a backend and draws such a polyline as pieces split at
//! every turn sharper than 90° (where the incoming and outgoing steps have
//! a negative dot product, in whole pixels: no transcendental function), so
//! that no piece has a turn whose inner corner lies further than √2 half
//! widths from the line, and covers each joint with a disc of the line's
//! width (opaque lines only: a translucent disc would darken the joint). A
//! polyline without such a turn is drawn exactly as before; everything else
//! goes to the wrapped backend unchanged.

use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};

/// A backend whose wide polylines are split at turns sharper than 90°.
pub struct Raster<B>(pub B);

/// Where `points` (consecutive duplicates removed) turn by more than 90°:
/// the indices of the vertices at which to split.
fn sharp_turns(points: &[BackendCoord]) -> Vec<usize> {
    (1..points.len().saturating_sub(1))
        .filter(|&i| {
            let (a, b, c) = (points[i - 1], points[i], points[i + 1]);
            let dot = i64::from(b.0 - a.0) * i64::from(c.0 - b.0)
                + i64::from(b.1 - a.1) * i64::from(c.1 - b.1);
            dot < 0
        })
        .collect()
}

impl<B: DrawingBackend> DrawingBackend for Raster<B> {
    type ErrorType = B::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.0.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        if style.stroke_width() <= 1 {
            return self.0.draw_path(path, style);
        }
        let mut points: Vec<BackendCoord> = Vec::new();
        for p in path {
            if points.last() != Some(&p) {
                points.push(p);
            }
        }
        let turns = sharp_turns(&points);
        if turns.is_empty() {
            return self.0.draw_path(points, style);
        }
        let colour = style.color();
        let mut start = 0;
        for &i in &turns {
            self.0.draw_path(points[start..=i].iter().copied(), style)?;
            if colour.alpha >= 1.0 {
                self.0
                    .draw_circle(points[i], style.stroke_width() / 2, &colour, true)?;
            }
            start = i;
        }
        self.0.draw_path(points[start..].iter().copied(), style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.fill_polygon(vert, style)
    }

    fn draw_text<T: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &T,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_text(text, style, pos)
    }

    fn estimate_text_size<T: BackendTextStyle>(
        &self,
        text: &str,
        style: &T,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        self.0.estimate_text_size(text, style)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.blit_bitmap(pos, size, src)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::prelude::{BitMapBackend, IntoDrawingArea, PathElement, WHITE};
    use plotters::style::{Color, RGBColor};

    /// Rows of a `w`×`h` RGB buffer holding a non-white pixel.
    fn inked_rows(buf: &[u8], w: usize) -> Vec<usize> {
        buf.chunks(3 * w)
            .enumerate()
            .filter(|(_, row)| row.iter().any(|&b| b != 255))
            .map(|(y, _)| y)
            .collect()
    }

    /// A noisy trace between y = 30 and y = 70 (x steps of 1 px, y jumping
    /// by up to 40 px: turns of nearly 180°), 3 px wide, drawn on a
    /// 300×100 canvas: the rows inked.
    fn noisy(wrap: bool) -> Vec<usize> {
        let (w, h) = (300, 100);
        let mut buf = vec![0u8; w * h * 3];
        // a fixed pseudo-random sequence (LCG), no dependence on a crate
        let mut state: u64 = 12345;
        let points: Vec<(i32, i32)> = (0..250)
            .map(|i| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (25 + i, 30 + ((state >> 33) % 41) as i32)
            })
            .collect();
        let line = PathElement::new(points, Color::stroke_width(&RGBColor(0, 0, 0), 3));
        {
            let bitmap = BitMapBackend::with_buffer(&mut buf, (w as u32, h as u32));
            if wrap {
                let root = Raster(bitmap).into_drawing_area();
                root.fill(&WHITE).unwrap();
                root.draw(&line).unwrap();
                root.present().unwrap();
            } else {
                let root = bitmap.into_drawing_area();
                root.fill(&WHITE).unwrap();
                root.draw(&line).unwrap();
                root.present().unwrap();
            }
        }
        inked_rows(&buf, w)
    }

    #[test]
    fn a_noisy_trace_stays_within_its_band_plus_half_its_width() {
        let rows = noisy(true);
        assert!(!rows.is_empty());
        let (top, bottom) = (rows[0], rows[rows.len() - 1]);
        assert!(top >= 28 && bottom <= 72, "inked rows {top}..={bottom}");
    }

    /// What [`Raster`] is for: plotters alone throws the trace's inner
    /// corners far outside it.
    #[test]
    fn plotters_alone_spikes_at_sharp_turns() {
        let rows = noisy(false);
        let (top, bottom) = (rows[0], rows[rows.len() - 1]);
        assert!(top < 27 || bottom > 73, "inked rows {top}..={bottom}");
    }

    #[test]
    fn only_turns_sharper_than_a_right_angle_split_a_line() {
        let pts = [(0, 0), (10, 0), (10, 10), (0, 8), (5, 8)];
        // (10,0): 90°, not split; (10,10): 101°; (0,8): 169°
        assert_eq!(sharp_turns(&pts), [2, 3]);
        assert!(sharp_turns(&pts[..2]).is_empty());
    }
}
