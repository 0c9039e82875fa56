//! Building blocks shared by the study figures: the [`Frame`] every study
//! figure starts from (title band, legend and panel margins), legends drawn
//! above the panels, panel headings, the house mesh, line dashes and point
//! markers.
//!
//! Legend samples are drawn as rectangles and circles in pixel coordinates,
//! never as polylines, and every line *sample* is black: the only coloured
//! polylines in a figure are its data curves, which keeps them countable.

use crate::detmath as dm;
use plotters::chart::{ChartBuilder, ChartContext, MeshStyle};
use plotters::coord::Shift;
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::drawing::DrawingAreaErrorKind;
use plotters::prelude::{Cartesian2d, Circle, DrawingArea, DrawingBackend, Rectangle};
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{Color, FontTransform, RGBColor, ShapeStyle, WHITE};

use super::figure::DrawResult;
use super::style::{LINE_PT, Style, tick_label};

/// Height of a title band (pt).
pub const TITLE_BAND_PT: f64 = 16.0;
/// Height of one legend row (pt).
pub const LEGEND_ROW_PT: f64 = 12.0;
/// Room above a panel for its heading (pt).
pub const HEADING_PT: f64 = 13.0;
/// Room below a panel for its x tick labels and axis description (pt).
pub const X_AREA_PT: f64 = 26.0;
/// Length of a legend line sample (pt).
const SAMPLE_PT: f64 = 16.0;
/// Gap between legend entries (pt).
const ENTRY_GAP_PT: f64 = 9.0;
/// Gap between a sample and its label (pt).
const SAMPLE_GAP_PT: f64 = 3.0;
/// Dash and gap of dashed lines (pt).
pub const DASH_PT: (f64, f64) = (3.5, 2.0);
/// Dash and gap of short-dashed lines (pt).
pub const SHORT_DASH_PT: (f64, f64) = (1.2, 1.5);
/// Dot and gap of dotted lines (pt).
pub const DOT_PT: (f64, f64) = (0.6, 1.4);
/// Width of rug ticks (pt).
pub const RUG_PT: f64 = 0.4;
/// Radius of filled point markers (pt).
pub const MARKER_PT: f64 = 1.9;
/// Radius of hollow point markers (pt): larger than filled ones, so that a
/// hollow marker drawn under a filled one at the same place shows as a ring.
pub const HOLLOW_MARKER_PT: f64 = 2.5;

/// Marker radius in pixels.
pub fn marker_px(style: &Style, filled: bool) -> i32 {
    style
        .px(if filled { MARKER_PT } else { HOLLOW_MARKER_PT })
        .round() as i32
}

/// Line pattern of a series.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dash {
    /// Continuous line (one polyline).
    Solid,
    /// Dashes of [`DASH_PT`] (plotters writes one polyline per dash).
    Dashed,
    /// Short dashes of [`SHORT_DASH_PT`].
    Short,
    /// Dots of [`DOT_PT`] (not one of [`Dash::nth`]'s: kept for what a
    /// figure marks apart, such as a curve's extrapolated part).
    Dotted,
}

impl Dash {
    /// The pattern of the `i`-th friction model: solid, dashed, short dashes.
    pub fn nth(i: usize) -> Dash {
        [Dash::Solid, Dash::Dashed, Dash::Short][i % 3]
    }

    /// (dash, gap) in points, `None` for solid.
    pub fn pattern(self) -> Option<(f64, f64)> {
        match self {
            Dash::Solid => None,
            Dash::Dashed => Some(DASH_PT),
            Dash::Short => Some(SHORT_DASH_PT),
            Dash::Dotted => Some(DOT_PT),
        }
    }
}

/// Shape of a point marker.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Marker {
    /// Circle.
    Circle,
    /// Square.
    Square,
}

/// The sample shown beside a legend label.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sample {
    /// A line of the given colour and pattern.
    Line(RGBColor, Dash),
    /// A marker; `filled` or drawn in outline.
    Point(RGBColor, Marker, bool),
    /// A filled block (a shaded band or region).
    Block(RGBColor),
    /// A short vertical tick (a rug mark).
    Tick(RGBColor),
    /// A line with a marker on it (a series drawn as line and points).
    LinePoint(RGBColor, Dash, Marker, bool),
    /// A thick horizontal bar (an interval drawn as a bar).
    Bar(RGBColor),
    /// No sample: the label alone (a heading for the entries after it).
    Text,
}

/// One legend entry.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    /// What the entry looks like.
    pub sample: Sample,
    /// Its label.
    pub label: String,
}

impl Entry {
    /// An entry.
    pub fn new(sample: Sample, label: impl Into<String>) -> Entry {
        Entry {
            sample,
            label: label.into(),
        }
    }
}

/// The scaffolding every study figure starts from: the canvas filled with
/// [`BACKGROUND`], the title in a band across the top ([`title_band`]), the
/// legend below it ([`legend`]), and the margins its panels share.
pub struct Frame<DB: DrawingBackend> {
    /// What is left below the title and the legend, for the panels.
    pub body: DrawingArea<DB, Shift>,
    /// Room above a panel for its heading (px, [`HEADING_PT`]).
    pub top: u32,
    /// Room below a panel for its x-axis labels (px, [`X_AREA_PT`]).
    pub x_area: u32,
    /// Room left of a panel for its y-axis labels (px).
    pub y_area: u32,
    /// Room right of a panel (px), for half its last x tick label.
    pub right: u32,
    style: Style,
}

/// The margins of a figure's panels that differ between figures (pt); the
/// heading room ([`HEADING_PT`]) and the x-axis label room ([`X_AREA_PT`])
/// are the same in all.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Margins {
    /// Room left of a panel for its y tick labels.
    pub y_area_pt: f64,
    /// Room right of a panel, for half its last x tick label.
    pub right_pt: f64,
}

impl Margins {
    /// `y_area_pt` for the y tick labels and `right_pt` on the right.
    pub const fn new(y_area_pt: f64, right_pt: f64) -> Margins {
        Margins {
            y_area_pt,
            right_pt,
        }
    }
}

impl<DB: DrawingBackend> Frame<DB> {
    /// Fills `root`, writes `title` and the legend `entries` at its top and
    /// returns the frame of what is left, whose panels get `margins`.
    pub fn new(
        root: &DrawingArea<DB, Shift>,
        style: &Style,
        title: &str,
        entries: &[Entry],
        margins: Margins,
    ) -> Result<Frame<DB>, DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&BACKGROUND)?;
        let body = title_band(root, style, title)?;
        let body = legend(&body, style, entries)?;
        Ok(Frame {
            body,
            top: style.ipx(HEADING_PT),
            x_area: style.ipx(X_AREA_PT),
            y_area: style.ipx(margins.y_area_pt),
            right: style.ipx(margins.right_pt),
            style: *style,
        })
    }

    /// Writes a panel heading at the top left of `area`, lined up with the
    /// plot's left edge (see [`heading`]).
    pub fn heading(&self, area: &DrawingArea<DB, Shift>, text: &str) -> DrawResult<DB> {
        heading(area, &self.style, text, self.y_area)
    }

    /// A chart builder on `area` with the frame's margins: room for a
    /// heading above, for y-axis labels on the left, the right margin, and
    /// room for x-axis labels below if `x_labels` (a panel stacked above
    /// another has none).
    pub fn chart<'a, 'b>(
        &self,
        area: &'a DrawingArea<DB, Shift>,
        x_labels: bool,
    ) -> ChartBuilder<'a, 'b, DB> {
        let mut builder = ChartBuilder::on(area);
        builder
            .margin_top(self.top)
            .margin_right(self.right)
            .x_label_area_size(if x_labels { self.x_area } else { 0 })
            .y_label_area_size(self.y_area);
        builder
    }
}

/// Splits a title band off the top of `area`, writes `title` centred in it
/// and returns the rest. A title wider than the area is broken into lines
/// that fit (see [`wrap_title`]), the band growing by a line for each.
pub fn title_band<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    style: &Style,
    title: &str,
) -> Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    let font = style.title_font();
    let (width, _) = area.dim_in_pixel();
    let fits = |t: &str| {
        area.estimate_text_size(t, &font)
            .map_or(true, |(w, _)| w + style.ipx(4.0) <= width)
    };
    let lines = wrap_title(title, &fits);
    let line_h = style.px(TITLE_BAND_PT - 4.0);
    let band_h = style.px(TITLE_BAND_PT) + line_h * (lines.len() - 1) as f64;
    let (band, body) = area.split_vertically(band_h.round() as u32);
    let centred = font.pos(Pos::new(HPos::Center, VPos::Center));
    for (k, line) in lines.iter().enumerate() {
        let y = style.px(TITLE_BAND_PT) / 2.0 + line_h * k as f64;
        band.draw_text(line, &centred, ((width / 2) as i32, y.round() as i32))?;
    }
    Ok(body)
}

/// `title` in lines for which `fits` holds: the whole title if it fits;
/// else broken after the last `; ` that leaves two lines that fit (a title's
/// clauses), else after the last `; ` or `, ` that lets the first line fit,
/// else after the last space that does, and the rest wrapped the same way.
/// A word too long for a line is left whole on its own.
pub fn wrap_title<'t>(title: &'t str, fits: &dyn Fn(&str) -> bool) -> Vec<&'t str> {
    if fits(title) {
        return vec![title];
    }
    let at = |sep: &'static str| {
        title
            .match_indices(sep)
            .map(|(i, _)| i)
            .filter(|&i| fits(&title[..i + sep.len() - 1]))
    };
    let clause = at("; ").filter(|&i| fits(&title[i + 2..])).max();
    let split = clause
        .or_else(|| at("; ").chain(at(", ")).max())
        .map(|i| (&title[..i + 1], &title[i + 2..]))
        .or_else(|| at(" ").max().map(|i| (&title[..i], &title[i + 1..])))
        .or_else(|| title.split_once(' '));
    match split {
        Some((first, rest)) if !rest.is_empty() => {
            let mut lines = vec![first];
            lines.extend(wrap_title(rest, fits));
            lines
        }
        _ => vec![title],
    }
}

/// Average width of a character of the tick font, in ems, for estimates
/// made before anything is drawn (DejaVu Sans runs at about 0.55 em).
const CHAR_EM: f64 = 0.58;

/// An estimate, from the characters alone, of the legend rows `labels` need
/// across a figure `width_in` inches wide (the drawn legend measures its
/// text; a figure sizes its canvas before it draws).
pub fn estimated_legend_rows(labels: &[String], width_in: f64) -> usize {
    let char_pt = CHAR_EM * super::style::TICK_PT;
    let width = width_in * 72.0;
    let mut rows = 1;
    let mut x = 0.0;
    for label in labels {
        let w = SAMPLE_PT + SAMPLE_GAP_PT + label.chars().count() as f64 * char_pt;
        if x > 0.0 && x + w > width {
            rows += 1;
            x = 0.0;
        }
        x += w + ENTRY_GAP_PT;
    }
    rows
}

/// An estimate, from the characters alone, of the lines `title` wraps
/// onto across a figure `width_in` inches wide (see
/// [`estimated_legend_rows`]).
pub fn estimated_title_lines(title: &str, width_in: f64) -> usize {
    let char_pt = CHAR_EM * super::style::TITLE_PT;
    let per_line = ((width_in * 72.0 - 4.0) / char_pt).floor().max(1.0);
    (title.chars().count() as f64 / per_line).ceil().max(1.0) as usize
}

/// Number of legend rows `entries` need across `width` pixels.
pub fn legend_rows<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    style: &Style,
    entries: &[Entry],
) -> usize {
    layout_legend(area, style, entries).len()
}

/// Entries grouped into centred rows that fit the area's width: each row is
/// a list of (entry index, x offset), with the row's width.
fn layout_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    style: &Style,
    entries: &[Entry],
) -> Vec<(Vec<(usize, i32)>, i32)> {
    let (width, _) = area.dim_in_pixel();
    let font = style.tick_font();
    let sample = style.px(SAMPLE_PT);
    let gap = style.px(ENTRY_GAP_PT);
    let sgap = style.px(SAMPLE_GAP_PT);
    let mut rows: Vec<(Vec<(usize, i32)>, i32)> = vec![(vec![], 0)];
    let mut x = 0.0;
    for (i, e) in entries.iter().enumerate() {
        let text_w = area
            .estimate_text_size(&e.label, &font)
            .map_or(6.0 * e.label.len() as f64, |(w, _)| w as f64);
        let w = match e.sample {
            Sample::Text => text_w,
            _ => sample + sgap + text_w,
        };
        if x > 0.0 && x + w > width as f64 {
            rows.push((vec![], 0));
            x = 0.0;
        }
        let row = rows.last_mut().expect("one row at least");
        row.0.push((i, x.round() as i32));
        row.1 = (x + w).round() as i32;
        x += w + gap;
    }
    rows
}

/// Draws `entries` in centred rows of [`LEGEND_ROW_PT`] at the top of
/// `area`; returns the rest of the area below the legend.
pub fn legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    style: &Style,
    entries: &[Entry],
) -> Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    legend_in_rows(area, style, entries, 0)
}

/// As [`legend`], but taking the room of at least `min_rows` rows, so that
/// panels side by side with legends of different lengths stay aligned.
pub fn legend_in_rows<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    style: &Style,
    entries: &[Entry],
    min_rows: usize,
) -> Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    if entries.is_empty() && min_rows == 0 {
        return Ok(area.clone());
    }
    let rows = layout_legend(area, style, entries);
    let row_h = style.px(LEGEND_ROW_PT);
    let n_rows = rows.len().max(min_rows);
    let (band, body) = area.split_vertically((row_h * n_rows as f64).round() as u32);
    let (width, _) = band.dim_in_pixel();
    let sample = style.px(SAMPLE_PT);
    let sgap = style.px(SAMPLE_GAP_PT);
    let font = style.tick_font().pos(Pos::new(HPos::Left, VPos::Center));
    for (r, (items, row_w)) in rows.iter().enumerate() {
        let x0 = (width as i32 - row_w) / 2;
        let yc = (row_h * (r as f64 + 0.5)).round() as i32;
        for &(i, dx) in items {
            let e = &entries[i];
            let xs = x0 + dx;
            let text_x = match e.sample {
                Sample::Text => xs,
                _ => {
                    draw_sample(&band, style, e.sample, xs, yc, sample)?;
                    xs + (sample + sgap).round() as i32
                }
            };
            band.draw_text(&e.label, &font, (text_x, yc))?;
        }
    }
    Ok(body)
}

/// Draws one legend sample, `len` pixels long, starting at `x`, centred on `y`.
fn draw_sample<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    style: &Style,
    sample: Sample,
    x: i32,
    y: i32,
    len: f64,
) -> DrawResult<DB> {
    let lw = style.ipx(LINE_PT) as i32;
    let half = lw / 2;
    match sample {
        Sample::Text => {}
        Sample::LinePoint(colour, dash, marker, filled) => {
            draw_sample(area, style, Sample::Line(colour, dash), x, y, len)?;
            let xc = x + (len / 2.0).round() as i32;
            draw_marker(area, style, (xc, y), colour, marker, filled)?;
        }
        Sample::Line(colour, dash) => {
            // rectangles, not polylines (see the module docs)
            let x1 = x + len.round() as i32;
            let fill = colour.filled();
            match dash.pattern() {
                None => area.draw(&Rectangle::new([(x, y - half), (x1, y - half + lw)], fill))?,
                Some((on, off)) => {
                    let (on, off) = (style.px(on), style.px(off));
                    let mut a = x as f64;
                    while a < x1 as f64 {
                        let b = (a + on).min(x1 as f64);
                        area.draw(&Rectangle::new(
                            [
                                (a.round() as i32, y - half),
                                (b.round() as i32, y - half + lw),
                            ],
                            fill,
                        ))?;
                        a = b + off;
                    }
                }
            }
        }
        Sample::Bar(colour) => {
            let h = style.ipx(1.3) as i32;
            area.draw(&Rectangle::new(
                [(x, y - h / 2), (x + len.round() as i32, y - h / 2 + h)],
                colour.filled(),
            ))?;
        }
        Sample::Point(colour, marker, filled) => {
            let xc = x + (len / 2.0).round() as i32;
            draw_marker(area, style, (xc, y), colour, marker, filled)?;
        }
        Sample::Tick(colour) => {
            let xc = x + (len / 2.0).round() as i32;
            let (w, h) = (style.ipx(RUG_PT).max(1) as i32, style.ipx(6.0) as i32);
            area.draw(&Rectangle::new(
                [(xc, y - h / 2), (xc + w, y + h / 2)],
                colour.filled(),
            ))?;
        }
        Sample::Block(colour) => {
            let h = style.ipx(6.0) as i32;
            area.draw(&Rectangle::new(
                [(x, y - h / 2), (x + len.round() as i32, y + h / 2)],
                colour.filled(),
            ))?;
            area.draw(&Rectangle::new(
                [(x, y - h / 2), (x + len.round() as i32, y + h / 2)],
                ShapeStyle::from(&GREY_EDGE).stroke_width(1),
            ))?;
        }
    }
    Ok(())
}

/// Thin grey edge drawn round legend blocks so that light tints stay visible.
const GREY_EDGE: RGBColor = RGBColor(0x99, 0x99, 0x99);

/// Draws one marker centred at pixel `c` of `area`.
pub fn draw_marker<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    style: &Style,
    c: (i32, i32),
    colour: RGBColor,
    marker: Marker,
    filled: bool,
) -> DrawResult<DB> {
    let r = marker_px(style, filled);
    let s = marker_style(style, colour, filled);
    match marker {
        Marker::Circle => {
            if !filled {
                area.draw(&Circle::new(c, r, HOLLOW_FILL))?;
            }
            area.draw(&Circle::new(c, r, s))
        }
        Marker::Square => {
            let corners = [(c.0 - r, c.1 - r), (c.0 + r, c.1 + r)];
            if !filled {
                area.draw(&Rectangle::new(corners, HOLLOW_FILL))?;
            }
            area.draw(&Rectangle::new(corners, s))
        }
    }
}

/// Interior of hollow markers: white, so that lines do not show through.
pub const HOLLOW_FILL: ShapeStyle = ShapeStyle {
    color: plotters::style::RGBAColor(255, 255, 255, 1.0),
    filled: true,
    stroke_width: 0,
};

/// Style of a marker: filled, or outlined with a white interior.
pub fn marker_style(style: &Style, colour: RGBColor, filled: bool) -> ShapeStyle {
    if filled {
        colour.filled()
    } else {
        colour.stroke_width(style.ipx(LINE_PT))
    }
}

/// Writes a panel heading at the top left of `area` (inside its top
/// [`HEADING_PT`] band), indented by `indent` pixels to line up with the
/// plot's left edge.
pub fn heading<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    style: &Style,
    text: &str,
    indent: u32,
) -> DrawResult<DB> {
    area.draw_text(
        text,
        &style.label_font().pos(Pos::new(HPos::Left, VPos::Center)),
        (indent as i32, (style.px(HEADING_PT) / 2.0).round() as i32),
    )
}

/// The house mesh of `chart` ([`house_mesh`]), for the caller to add its
/// tick counts and axis descriptions and draw.
pub fn mesh<'a, 'b, X, Y, DB>(
    chart: &'b mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    style: &Style,
) -> MeshStyle<'a, 'b, X, Y, DB>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    DB: DrawingBackend,
{
    let mut mesh = chart.configure_mesh();
    house_mesh(&mut mesh, style);
    mesh
}

/// Applies the house mesh: black axes, light grid at the labelled ticks only,
/// small ticks, compact tick labels ([`tick_label`]) and the label font.
pub fn house_mesh<'a, 'b, X, Y, DB>(mesh: &mut MeshStyle<'a, 'b, X, Y, DB>, style: &Style)
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    DB: DrawingBackend,
{
    mesh.axis_style(style.axis())
        .bold_line_style(style.grid())
        .max_light_lines(0)
        .set_all_tick_mark_size(style.ipx(2.5))
        .label_style(style.tick_font())
        .axis_desc_style(style.label_font())
        .x_label_formatter(&|v| tick_label(*v))
        .y_label_formatter(&|v| tick_label(*v));
}

/// Ticks and labels of a logarithmic axis over [lo, hi], chosen by how many
/// decades it spans (d):
///
/// - d ≤ 1.5: 1, 2 and 5 × 10ᵏ; where that gives fewer than three ticks,
///   1, 1.5, 2, 3, 4, 5, 6 and 8 × 10ᵏ; where that still does (an axis
///   under a factor of about 1.3), evenly spaced ticks at a round step;
/// - d ≤ 3: 1 and 3 × 10ᵏ;
/// - d ≤ 8: the powers of ten;
/// - more: every n-th power of ten, so that at most 8 are labelled.
///
/// Ticks are labelled as plain numbers (`0.05`, `300`) while the axis spans
/// 3 decades or less and every tick lies in [10⁻³, 10⁴]; otherwise as powers
/// of ten with superscripts (`10⁻⁵`, `2×10⁻⁵`), which stay short and never
/// lose a digit to a clipped margin.
#[derive(Clone, Debug, PartialEq)]
pub struct LogAxis {
    /// Tick positions, ascending, inside [lo, hi].
    pub ticks: Vec<f64>,
    /// Whether the labels are powers of ten.
    pub powers: bool,
}

impl LogAxis {
    /// The ticks of an axis over [lo, hi] (0 < lo < hi; a bound that is
    /// not a positive finite number is taken at the nearest one, so the
    /// loop over decades is at most some 630 long).
    pub fn new(lo: f64, hi: f64) -> LogAxis {
        let finite = |x: f64| {
            if x.is_nan() {
                1.0
            } else {
                x.clamp(f64::MIN_POSITIVE, f64::MAX)
            }
        };
        let (lo, hi) = (finite(lo), finite(hi));
        let decades = dm::log10(hi / lo);
        let (multiples, every): (&[f64], i32) = if decades <= 1.5 {
            (&[1.0, 2.0, 5.0], 1)
        } else if decades <= 3.0 {
            (&[1.0, 3.0], 1)
        } else {
            (&[1.0], (decades / 8.0).ceil().max(1.0) as i32)
        };
        let first = dm::log10(lo).floor() as i32;
        let last = dm::log10(hi).ceil() as i32;
        let inside = |t: f64| t >= lo * (1.0 - 1e-9) && t <= hi * (1.0 + 1e-9);
        let on_decades = |multiples: &[f64], every: i32| {
            let mut ticks = Vec::new();
            for k in first..=last {
                if k.rem_euclid(every) != 0 {
                    continue;
                }
                let decade = dm::powf(10.0, k as f64);
                for m in multiples {
                    let t = m * decade;
                    // a tick computed at the end of the range may sit an
                    // ulp outside it
                    if inside(t) {
                        ticks.push(t);
                    }
                }
            }
            ticks
        };
        let mut ticks = on_decades(multiples, every);
        if ticks.len() < 3 && decades <= 1.5 {
            // a narrow axis (under a factor of about 3): 1, 1.5, 2, 3, 4, 5,
            // 6 and 8 × 10ᵏ
            ticks = on_decades(&[1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0], 1);
        }
        if ticks.len() < 3 && decades <= 1.5 {
            // narrower still (under a factor of about 1.3): evenly spaced
            // ticks at a round step of 1, 2 or 5 × 10ᵏ, 3 to 8 of them
            let span = hi - lo;
            let unit = dm::powf(10.0, dm::log10(span / 8.0).floor());
            let step = [1.0, 2.0, 5.0, 10.0]
                .iter()
                .map(|m| m * unit)
                .find(|s| span / s < 8.0)
                .unwrap_or(10.0 * unit);
            let n0 = (lo / step - 1e-6).ceil() as i64;
            ticks = (n0..)
                .map(|n| n as f64 * step)
                .take_while(|&t| t <= hi * (1.0 + 1e-9))
                .filter(|&t| inside(t))
                .collect();
        }
        let powers = decades > 3.0 || ticks.iter().any(|&t| !(1e-3..=1e4).contains(&t));
        LogAxis { ticks, powers }
    }

    /// The label of tick `v`.
    pub fn label(&self, v: f64) -> String {
        if self.powers {
            power_label(v)
        } else {
            tick_label(v)
        }
    }
}

/// `v` as a power of ten with a superscript exponent: `10⁻⁵`, `1` → `10⁰`,
/// `2e-5` → `2×10⁻⁵`; an empty label for v ≤ 0 or NaN.
pub fn power_label(v: f64) -> String {
    if v.is_nan() || v <= 0.0 {
        return String::new();
    }
    let mut k = dm::log10(v).floor();
    let mut m = v / dm::powf(10.0, k);
    // 0.001 may come out as 9.99…×10⁻⁴
    if m >= 9.999_999 {
        k += 1.0;
        m /= 10.0;
    }
    let exponent: String = format!("{}", k as i64)
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            d => SUPERSCRIPT_DIGITS[d.to_digit(10).expect("a digit") as usize],
        })
        .collect();
    if (m - 1.0).abs() < 1e-6 {
        format!("10{exponent}")
    } else {
        format!("{}×10{exponent}", tick_label((m * 1e4).round() / 1e4))
    }
}

/// ⁰ to ⁹.
const SUPERSCRIPT_DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];

/// Width in pixels of the widest of `labels` in the tick font.
pub fn widest<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    style: &Style,
    labels: impl IntoIterator<Item = String>,
) -> u32 {
    let font = style.tick_font();
    labels
        .into_iter()
        .map(|l| area.estimate_text_size(&l, &font).map_or(0, |(w, _)| w))
        .max()
        .unwrap_or(0)
}

/// A lighter tint of `c`: `amount` = 0 gives `c`, 1 gives white.
pub fn tint(c: RGBColor, amount: f64) -> RGBColor {
    let mix = |a: u8| (a as f64 + (255.0 - a as f64) * amount).round() as u8;
    RGBColor(mix(c.0), mix(c.1), mix(c.2))
}

/// Colour `i` of `n` on a dark-to-light sequential scale (plasma: deep
/// blue, purple, red, orange; cut before its pale yellow end so that thin
/// lines stay visible on white), for ordered levels such as PGA.
pub fn sequential(i: usize, n: usize) -> RGBColor {
    const STOPS: [(f64, RGBColor); 5] = [
        (0.0, RGBColor(0x0D, 0x08, 0x87)),
        (0.25, RGBColor(0x7E, 0x03, 0xA8)),
        (0.5, RGBColor(0xCC, 0x47, 0x78)),
        (0.75, RGBColor(0xF8, 0x95, 0x40)),
        (1.0, RGBColor(0xF0, 0xF9, 0x21)),
    ];
    let t = if n <= 1 {
        0.0
    } else {
        0.8 * i as f64 / (n - 1) as f64
    };
    let k = STOPS
        .windows(2)
        .position(|w| t <= w[1].0)
        .unwrap_or(STOPS.len() - 2);
    let ((t0, a), (t1, b)) = (STOPS[k], STOPS[k + 1]);
    let u = (t - t0) / (t1 - t0);
    let lerp = |x: u8, y: u8| (x as f64 + (y as f64 - x as f64) * u).round() as u8;
    RGBColor(lerp(a.0, b.0), lerp(a.1, b.1), lerp(a.2, b.2))
}

/// Background of every figure.
pub const BACKGROUND: RGBColor = WHITE;

/// Width of the strip left of a row of panels that holds its rotated
/// y-axis label (pt).
pub const SIDE_LABEL_PT: f64 = 13.0;

/// Splits a [`SIDE_LABEL_PT`] strip off the left of `area` and writes `text`
/// in it, rotated to read upwards, centred on the plot region (the area less
/// `top` pixels of headings and `bottom` pixels of x-axis labels); returns
/// the rest of the area.
pub fn side_label<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    style: &Style,
    text: &str,
    top: u32,
    bottom: u32,
) -> Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    let (strip, rest) = area.split_horizontally(style.ipx(SIDE_LABEL_PT));
    let (w, h) = strip.dim_in_pixel();
    let yc = (top as i32 + (h as i32 - bottom as i32)) / 2;
    let font = style
        .label_font()
        .transform(FontTransform::Rotate270)
        .pos(Pos::new(HPos::Center, VPos::Center));
    strip.draw_text(text, &font, ((w / 2) as i32, yc))?;
    Ok(rest)
}

/// Draws a data curve as a solid or dashed series on a chart (a macro, so that
/// it works for any coordinate system): `curve!(chart, points, style, dash, px)`
/// where `px` converts points to pixels (the figure's [`Style`]).
macro_rules! curve {
    ($chart:expr, $points:expr, $shape:expr, $dash:expr, $style:expr) => {{
        match $dash.pattern() {
            None => {
                $chart.draw_series(plotters::prelude::LineSeries::new($points, $shape))?;
            }
            Some((on, off)) => {
                $chart.draw_series(plotters::prelude::DashedLineSeries::new(
                    $points,
                    $style.px(on).round() as i32,
                    $style.px(off).round() as i32,
                    $shape,
                ))?;
            }
        }
    }};
}
pub(crate) use curve;

/// Draws point markers at data coordinates on a chart (a macro, for any
/// coordinate system): `markers!(chart, points, colour, marker, filled, style)`.
macro_rules! markers {
    ($chart:expr, $points:expr, $colour:expr, $marker:expr, $filled:expr, $style:expr) => {{
        use plotters::prelude::{Circle, EmptyElement, Rectangle};
        let r = $crate::figures::layout::marker_px(&$style, $filled);
        let s = $crate::figures::layout::marker_style(&$style, $colour, $filled);
        let under = $crate::figures::layout::HOLLOW_FILL;
        let points: Vec<_> = $points.into_iter().collect();
        match ($marker, $filled) {
            ($crate::figures::layout::Marker::Circle, true) => {
                $chart.draw_series(points.into_iter().map(|p| Circle::new(p, r, s)))?;
            }
            ($crate::figures::layout::Marker::Circle, false) => {
                $chart.draw_series(points.into_iter().map(|p| {
                    EmptyElement::at(p) + Circle::new((0, 0), r, under) + Circle::new((0, 0), r, s)
                }))?;
            }
            ($crate::figures::layout::Marker::Square, filled) => {
                let fill = if filled { s } else { under };
                $chart.draw_series(points.into_iter().map(|p| {
                    EmptyElement::at(p)
                        + Rectangle::new([(-r, -r), (r, r)], fill)
                        + Rectangle::new([(-r, -r), (r, r)], s)
                }))?;
            }
        }
    }};
}
pub(crate) use markers;

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::prelude::{BitMapBackend, IntoDrawingArea};
    use plotters::style::BLACK;

    #[test]
    fn frame_body_and_panel_margins_are_the_house_sizes_in_pixels() {
        // At 200 px/in (1 pt = 25/9 px) a one-line title band is 16 pt =
        // 44 px and a one-row legend 12 pt = 33 px: the body is the rest of
        // a 700 × 400 px canvas, full width. A panel's plot starts 13 pt =
        // 36 px below its area's top (its heading) and 30 pt = 83 px in from
        // its left (its y labels, as asked); with x labels it stops 26 pt =
        // 72 px higher than without. Pixel counts are whole: exact equality.
        crate::figures::font::register().unwrap();
        let mut buffer = vec![0u8; 700 * 400 * 3];
        let root = BitMapBackend::with_buffer(&mut buffer, (700, 400)).into_drawing_area();
        let entries = [Entry::new(Sample::Line(BLACK, Dash::Solid), "a line")];
        let margins = Margins::new(30.0, 10.0);
        let frame = Frame::new(&root, &Style::SVG, "Title", &entries, margins).unwrap();
        assert_eq!(frame.body.dim_in_pixel(), (700, 400 - 44 - 33));
        let plot = |x_labels: bool| {
            let chart = frame
                .chart(&frame.body, x_labels)
                .build_cartesian_2d(0.0..1.0, 0.0..1.0)
                .unwrap();
            chart.plotting_area().get_pixel_range()
        };
        let ((x, y), (_, y_bare)) = (plot(true), plot(false));
        assert_eq!(y.start, 44 + 33 + 36);
        assert_eq!(x.start, 83);
        assert_eq!(x.end, 700 - 28);
        assert_eq!(y_bare.end - y.end, 72);
    }

    #[test]
    fn a_long_title_is_wrapped_into_as_many_lines_as_fit() {
        // The museum study's history title: two lines were not enough, and
        // the second ran off both sides of the figure (issue 29, item 10).
        crate::figures::font::register().unwrap();
        let title = "H/B = 5.00, 2B = 0.380 m, e = 0.231, μₛ = 0.634, μₖ = 0.560: record \
                     22 of seed 77 at 0.5 g (largest θmax/θc not overturned, stripe nearest \
                     its median 0.519 g)";
        // a full page wide, 7 in at 200 px/in
        let (w, h) = (1400_u32, 400_u32);
        let mut svg = String::new();
        let body_h = {
            let root =
                plotters::prelude::SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
            let body = title_band(&root, &Style::SVG, title).unwrap();
            root.present().unwrap();
            body.dim_in_pixel().1
        };
        let lines: Vec<&str> = svg
            .split("<text")
            .skip(1)
            .map(|t| t[t.find('>').unwrap() + 1..t.find("</text>").unwrap()].trim())
            .collect();
        assert_eq!(lines.len(), 3, "{lines:?}");
        // the band: 16 pt for the first line and 12 pt for each other one
        let band = (Style::SVG.px(16.0) + 2.0 * Style::SVG.px(12.0)).round() as u32;
        assert_eq!(body_h, h - band);
        let mut buffer = vec![0u8; (w * h * 3) as usize];
        let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
        for line in &lines {
            let (lw, _) = root
                .estimate_text_size(line, &Style::SVG.title_font())
                .unwrap();
            assert!(lw < w, "{line:?} is {lw} px wide, the figure {w}");
        }
        assert_eq!(lines.join(" "), title);
    }

    #[test]
    fn log_axes_label_decades_as_powers_of_ten_when_they_span_many() {
        // A spectrum's y axis over 7 decades: a tick per decade, labelled
        // 10⁻⁶ … 10⁰, every label different (a plain "0.000001" loses
        // digits to the margin and reads like "0.00001").
        let axis = LogAxis::new(5e-7, 3.0);
        assert!(axis.powers);
        let labels: Vec<String> = axis.ticks.iter().map(|&t| axis.label(t)).collect();
        assert_eq!(
            labels,
            ["10⁻⁶", "10⁻⁵", "10⁻⁴", "10⁻³", "10⁻²", "10⁻¹", "10⁰"]
        );
        assert_ne!(axis.label(1e-5), axis.label(1e-6));
        // Two decades inside [10⁻³, 10⁴]: 1 and 3 × 10ᵏ as plain numbers.
        let axis = LogAxis::new(0.025, 5.0);
        assert!(!axis.powers);
        let labels: Vec<String> = axis.ticks.iter().map(|&t| axis.label(t)).collect();
        assert_eq!(labels, ["0.03", "0.1", "0.3", "1", "3"]);
        // Under a decade and a half: 1, 2, 5.
        assert_eq!(LogAxis::new(0.07, 0.6).ticks, [0.1, 0.2, 0.5]);
        // A narrow axis, where 1, 2, 5 would label two ticks (0.5 and 1,
        // the 2-D inference figure's PGA axis): at least three, and the
        // finer multiples.
        let labels = |a: &LogAxis| -> Vec<String> { a.ticks.iter().map(|&t| a.label(t)).collect() };
        let axis = LogAxis::new(0.3, 1.4);
        assert_eq!(labels(&axis), ["0.3", "0.4", "0.5", "0.6", "0.8", "1"]);
        // Under a factor 1.3: evenly spaced at a round step.
        let axis = LogAxis::new(0.42, 0.51);
        assert_eq!(labels(&axis), ["0.42", "0.44", "0.46", "0.48", "0.5"]);
        for (lo, hi) in [
            (0.42, 0.51),
            (3.3, 3.9),
            (1.01, 1.02),
            (0.3, 1.4),
            (0.11, 0.19),
        ] {
            let n = LogAxis::new(lo, hi).ticks.len();
            assert!((3..=8).contains(&n), "[{lo}, {hi}]: {n} ticks");
        }
        // Twenty decades: at most 8 labelled.
        assert!(LogAxis::new(1e-20, 1.0).ticks.len() <= 8);
        assert_eq!(power_label(2e-5), "2×10⁻⁵");
        assert_eq!(power_label(1e4), "10⁴");
        assert_eq!(power_label(0.001), "10⁻³");
        assert_eq!(power_label(0.0), "");
    }

    #[test]
    fn sequential_scale_runs_dark_to_light() {
        // The first level is the darkest, the last the lightest (sum of
        // channels as a proxy for lightness), and one level is the dark end.
        let lightness = |c: RGBColor| c.0 as u32 + c.1 as u32 + c.2 as u32;
        let cs: Vec<RGBColor> = (0..4).map(|i| sequential(i, 4)).collect();
        assert!(cs.windows(2).all(|w| lightness(w[0]) < lightness(w[1])));
        assert_eq!(sequential(0, 1), RGBColor(0x0D, 0x08, 0x87));
        assert_eq!(tint(RGBColor(0, 0, 0), 1.0), RGBColor(255, 255, 255));
    }
}
