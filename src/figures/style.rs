//! The house style shared by every figure: sizes in inches and points, fonts,
//! series colours and line weights.
//!
//! Sizes are given as they will be *printed*: a figure is laid out in inches
//! (single journal column [`COLUMN_WIDTH_IN`] = 3.5 in) and text in points
//! (1 pt = 1/72 in), then converted to pixels at the output's resolution
//! ([`SVG_PX_PER_IN`] for SVG, [`PNG_PX_PER_IN`] for PNG). A figure scaled to
//! the column width therefore shows 8 pt tick labels and 9 pt axis labels
//! whatever the format.

use plotters::style::{BLACK, Color, IntoFont, RGBColor, ShapeStyle, TextStyle};

use super::font::FONT_FAMILY;

/// Width of one journal column (in).
pub const COLUMN_WIDTH_IN: f64 = 3.5;
/// Width of a full page, two journal columns (in).
pub const PAGE_WIDTH_IN: f64 = 7.0;
/// SVG resolution (px/in): a single-column figure is 700 px wide.
pub const SVG_PX_PER_IN: f64 = 200.0;
/// PNG resolution (px/in), print quality: a single-column figure is 1050 px wide.
pub const PNG_PX_PER_IN: f64 = 300.0;

/// Tick-label size (pt).
pub const TICK_PT: f64 = 8.0;
/// Axis-label size (pt).
pub const LABEL_PT: f64 = 9.0;
/// Title size (pt).
pub const TITLE_PT: f64 = 9.0;
/// Weight of data lines (pt).
pub const LINE_PT: f64 = 0.6;
/// Weight of axes and grid lines (pt).
pub const AXIS_PT: f64 = 0.4;

/// Series colours, in order of use: the Okabe–Ito palette, distinguishable
/// with the common colour-vision deficiencies and in greyscale by order of
/// lightness of the first four.
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(0x00, 0x72, 0xB2), // blue
    RGBColor(0xD5, 0x5E, 0x00), // vermillion
    RGBColor(0x00, 0x9E, 0x73), // bluish green
    RGBColor(0xCC, 0x79, 0xA7), // reddish purple
    RGBColor(0xE6, 0x9F, 0x00), // orange
    RGBColor(0x56, 0xB4, 0xE9), // sky blue
    RGBColor(0xF0, 0xE4, 0x42), // yellow
    RGBColor(0x00, 0x00, 0x00), // black
];

/// Colour of grid lines.
pub const GRID: RGBColor = RGBColor(0xDD, 0xDD, 0xDD);

/// Formats a tick value compactly and typographically: at most six
/// significant digits, no trailing zeros, a true minus sign (U+2212) and no
/// negative zero.
///
/// ```
/// use rockfrag::figures::style::tick_label;
/// assert_eq!(tick_label(2.0), "2");
/// assert_eq!(tick_label(0.1 + 0.2), "0.3");
/// assert_eq!(tick_label(-100.0), "\u{2212}100");
/// assert_eq!(tick_label(-0.0), "0");
/// ```
pub fn tick_label(v: f64) -> String {
    // Tick positions computed as start + k·step carry rounding noise: a tick
    // meant to be 0 arrives as ±5.6e-17. No axis of ours labels |v| < 1e-12.
    let v = if v.abs() < 1e-12 { 0.0 } else { v };
    let rounded: f64 = format!("{v:.5e}").parse().unwrap_or(v);
    // Adding +0.0 turns -0.0 into 0.0.
    let text = format!("{}", rounded + 0.0);
    match text.strip_prefix('-') {
        Some(abs) => format!("\u{2212}{abs}"),
        None => text,
    }
}

/// Plotters sizes a font by its line height, about 1.24 em (its SVG backend
/// writes `font-size = size / 1.24`); this converts an em size to that.
const LINE_HEIGHT_PER_EM: f64 = 1.24;

/// The style at one output resolution: converts printed sizes to pixels and
/// hands out fonts and line styles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Style {
    /// Output resolution (px/in).
    pub px_per_in: f64,
}

impl Style {
    /// The style for SVG output ([`SVG_PX_PER_IN`]).
    pub const SVG: Style = Style {
        px_per_in: SVG_PX_PER_IN,
    };
    /// The style for PNG output ([`PNG_PX_PER_IN`]).
    pub const PNG: Style = Style {
        px_per_in: PNG_PX_PER_IN,
    };

    /// Pixels for a length in points.
    ///
    /// ```
    /// use rockfrag::figures::style::Style;
    /// assert_eq!(Style::SVG.px(72.0), 200.0);
    /// ```
    pub fn px(&self, pt: f64) -> f64 {
        pt * self.px_per_in / 72.0
    }

    /// Whole pixels for a length in points (at least 1), for margins and
    /// label areas.
    pub fn ipx(&self, pt: f64) -> u32 {
        self.px(pt).round().max(1.0) as u32
    }

    /// Canvas size in pixels for a figure of `(width, height)` inches.
    ///
    /// ```
    /// use rockfrag::figures::style::{COLUMN_WIDTH_IN, Style};
    /// assert_eq!(Style::SVG.canvas((COLUMN_WIDTH_IN, 3.0)), (700, 600));
    /// ```
    pub fn canvas(&self, (width_in, height_in): (f64, f64)) -> (u32, u32) {
        (
            (width_in * self.px_per_in).round() as u32,
            (height_in * self.px_per_in).round() as u32,
        )
    }

    /// Black text of `pt` points (em size) in the embedded sans-serif font.
    pub fn font(&self, pt: f64) -> TextStyle<'static> {
        (FONT_FAMILY, self.px(pt) * LINE_HEIGHT_PER_EM)
            .into_font()
            .color(&BLACK)
    }

    /// Tick labels ([`TICK_PT`]).
    pub fn tick_font(&self) -> TextStyle<'static> {
        self.font(TICK_PT)
    }

    /// Axis labels ([`LABEL_PT`]).
    pub fn label_font(&self) -> TextStyle<'static> {
        self.font(LABEL_PT)
    }

    /// Titles ([`TITLE_PT`]).
    pub fn title_font(&self) -> TextStyle<'static> {
        self.font(TITLE_PT)
    }

    /// Line for the `i`-th data series: [`PALETTE`] colour `i` (cycling),
    /// [`LINE_PT`] wide.
    pub fn series(&self, i: usize) -> ShapeStyle {
        PALETTE[i % PALETTE.len()].stroke_width(self.ipx(LINE_PT))
    }

    /// Axis lines and tick marks: black, [`AXIS_PT`] wide.
    pub fn axis(&self) -> ShapeStyle {
        BLACK.stroke_width(self.ipx(AXIS_PT))
    }

    /// Grid lines: light grey, [`AXIS_PT`] wide.
    pub fn grid(&self) -> ShapeStyle {
        GRID.stroke_width(self.ipx(AXIS_PT))
    }
}
