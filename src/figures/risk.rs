//! Risk at a site (`risk.svg`), drawn to be read at journal size whatever
//! the number of cases: two panels side by side instead of one panel per
//! case.
//!
//! - **(a) Hazard and deaggregation.** The site's hazard curve λ(im) (left
//!   axis, logarithmic, black; dashed beyond its levels, where the risk
//!   integral extrapolates it) and, on the same logarithmic IM axis, the
//!   integrand P(LS | im)·|dλ/d ln im| of every fitted case and limit state
//!   (right axis, each scaled to peak at 1, a thin line in the limit state's
//!   colour): where each rate comes from. The integrands are drawn with the
//!   hazard's log-slope smoothed between its levels
//!   ([`crate::risk::deaggregation_smoothed`]), as each peak is located:
//!   with the log–log interpolant's slope, which jumps at every level, each
//!   was a sawtooth. The ticks along the top mark the peaks (see
//!   [`crate::risk`]). A curve's colour is its limit state's and its line
//!   pattern its case's value of the first parameter that varies between
//!   the cases (H/B in the default study, as panel (b) groups its rows),
//!   while that takes at most three values (solid, dashed, dotted; the
//!   legend names them): nine integrands of three cases and three limit
//!   states are nine looks. Cases that differ only in the other parameters
//!   overlap in one bundle, whose spread is the information. The right-hand
//!   axis has the house's tick marks, its labels clear of them, and its
//!   description beside them, well apart from panel (b).
//! - **(b) Annual rate per case.** One row per case (in `risk.csv`'s order),
//!   one marker per limit state at its annual rate λ_LS on a logarithmic
//!   axis, with the bootstrap band of the rate as a line through it (a
//!   forest plot): every case's result readable at once, where the panels
//!   of one curve plot per case were tiny. Rows are labelled with only the
//!   case parameters that vary between cases; those all cases share are
//!   stated in the panel's heading. Alternate groups of rows of one H/B are
//!   shaded. A limit state without a fit (or with a zero rate) is not left
//!   out silently: its row says so in words at the right (`overturning: no
//!   fit (separated)`). At most `MAX_ROWS` cases are drawn; a note below
//!   the panel names how many more `risk.csv` holds.
//!
//! Logarithmic axes are labelled by [`LogAxis`] (powers of ten with
//! superscripts on the rate axes), and the legend is one short row: the
//! hazard, its extrapolation (when the IM axis reaches beyond the hazard's
//! levels, the only time it is drawn) and one entry per limit state.

use crate::detmath as dm;
use plotters::coord::Shift;
use plotters::prelude::{
    BindKeyPoints, DrawingArea, DrawingBackend, IntoLogRange, LineSeries, PathElement, Rectangle,
    Text,
};
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{BLACK, Color, RGBColor};

use super::data::{friction_label, param_label};
use super::figure::{DrawResult, Figure};
use super::layout::{self, Dash, Entry, Frame, LogAxis, Margins, Marker, Sample, curve};
use super::style::{LINE_PT, PAGE_WIDTH_IN, Style};
use crate::case::Case;
use crate::im::Im;
use crate::risk::{HazardCurve, RiskOptions, RiskRow, deaggregation_smoothed};

/// Most cases drawn as rows of panel (b); `risk.csv` has them all.
pub const MAX_ROWS: usize = 40;
/// Height of one row of panel (b) (pt).
const ROW_PT: f64 = 10.5;
/// Smallest height of the panels' plot area (in).
const MIN_PLOT_IN: f64 = 1.9;
/// Room for the title, the legend and the headings (in).
const HEADER_IN: f64 = 0.62;
/// Room below the panels for the x axes and a note (in).
const FOOTER_IN: f64 = 0.5;
/// Width of panel (a) (in), with its axes.
const HAZARD_PANEL_IN: f64 = 2.7;
/// The right-hand axis's description (panel (a)).
const DEAGGREGATION_LABEL: &str = "Deaggregation (peak = 1)";
/// Gap between the right-hand axis's tick labels and its description (pt).
const RIGHT_DESC_GAP_PT: f64 = 2.0;
/// A line of axis-label text (pt), if it cannot be measured.
const LABEL_PT_LINE: f64 = 11.0;
/// Gap between panel (a)'s right-hand axis and panel (b)'s row labels (pt).
const PANEL_GAP_PT: f64 = 20.0;
/// Room beside a plot beyond its widest tick label: tick marks and a gap (pt).
const TICK_ROOM_PT: f64 = 9.0;
/// Samples per integrand curve.
const SAMPLES: usize = 240;
/// Opacity of an integrand line (many overlap).
const INTEGRAND_ALPHA: f64 = 0.45;
/// Colour of the legend's samples of panel (a)'s line patterns.
const GROUP_SAMPLE: RGBColor = RGBColor(0x66, 0x66, 0x66);
/// Shading of alternate H/B groups of rows.
const GROUP_SHADE: RGBColor = RGBColor(0xF2, 0xF2, 0xF2);

/// One fitted limit state of one case.
#[derive(Clone, Debug, PartialEq)]
pub struct RiskSeries {
    /// Index into [`RiskFigure::limit_states`] (sets the colour).
    pub limit_state: usize,
    /// (im, integrand scaled to peak at 1).
    pub integrand: Vec<(f64, f64)>,
    /// Where the integrand peaks.
    pub peak_im: f64,
    /// Annual rate λ_LS (1/yr).
    pub rate: f64,
    /// Bootstrap band of the rate (1/yr), when there is one.
    pub band: Option<(f64, f64)>,
}

/// One case: a row of panel (b).
#[derive(Clone, Debug, PartialEq)]
pub struct RiskCase {
    /// The case.
    pub key: Case,
    /// Row label: the case's parameters that vary between the figure's cases.
    pub label: String,
    /// Its limit states with a fit.
    pub series: Vec<RiskSeries>,
    /// Its limit states without one: (index into
    /// [`RiskFigure::limit_states`], the fit's status).
    pub unfitted: Vec<(usize, String)>,
}

/// The risk figure's data.
#[derive(Clone, Debug, PartialEq)]
pub struct RiskFigure {
    /// Title.
    pub title: String,
    /// IM axis label, e.g. `PGA (g)`.
    pub im_label: String,
    /// Limit-state names, in order of first appearance.
    pub limit_states: Vec<String>,
    /// IM range shown.
    pub im_range: (f64, f64),
    /// Hazard curve (im, λ) inside its levels, sampled log–log.
    pub hazard: Vec<(f64, f64)>,
    /// The extrapolated parts shown: below the lowest level, above the highest.
    pub hazard_extended: [Vec<(f64, f64)>; 2],
    /// Cases, in the order of `risk.csv`; the first `MAX_ROWS` are drawn.
    pub cases: Vec<RiskCase>,
    /// The parameters every case shares (`2B = 0.5 m`), left out of the
    /// row labels and added to the title; empty when none is shared.
    pub common: String,
    /// What the band on a rate is, e.g. `90 % band`.
    pub band_label: String,
}

impl RiskFigure {
    /// The figure of `rows` (as [`crate::risk::assess`] returns them, with
    /// its default options' band) over `hazard`.
    pub fn new(rows: &[RiskRow], hazard: &HazardCurve) -> RiskFigure {
        let fitted: Vec<(f64, f64)> = rows.iter().filter_map(|r| r.curve.fit).collect();
        let (h0, h1) = (hazard.iml[0], hazard.iml[hazard.iml.len() - 1]);
        // Wide enough for each integrand's bulk (±3.5β about the median)
        // and the hazard's levels.
        let lo = fitted
            .iter()
            .map(|&(m, b)| m * dm::exp(-3.5 * b))
            .fold(h0, f64::min);
        let hi = fitted
            .iter()
            .map(|&(m, b)| m * dm::exp(3.5 * b))
            .fold(h1, f64::max);
        let grid = |a: f64, b: f64, n: usize| -> Vec<f64> {
            (0..n)
                .map(|i| a * dm::powf(b / a, i as f64 / (n - 1) as f64))
                .collect()
        };
        let ims = grid(lo, hi, SAMPLES);
        let with_rate = |xs: Vec<f64>| -> Vec<(f64, f64)> {
            xs.into_iter().map(|x| (x, hazard.rate_at(x))).collect()
        };
        let below = if lo < h0 {
            grid(lo, h0, 30)
        } else {
            Vec::new()
        };
        let above = if hi > h1 {
            grid(h1, hi, 30)
        } else {
            Vec::new()
        };
        let mut limit_states: Vec<String> = Vec::new();
        let mut cases: Vec<RiskCase> = Vec::new();
        for r in rows {
            if cases.last().is_none_or(|c| c.key != r.curve.key) {
                cases.push(RiskCase {
                    key: r.curve.key,
                    label: String::new(),
                    series: Vec::new(),
                    unfitted: Vec::new(),
                });
            }
            let ls = match limit_states.iter().position(|l| *l == r.curve.limit_state) {
                Some(i) => i,
                None => {
                    limit_states.push(r.curve.limit_state.clone());
                    limit_states.len() - 1
                }
            };
            let case = cases.last_mut().expect("pushed above");
            let (Some((m, b)), Some(integral)) = (r.curve.fit, r.integral) else {
                case.unfitted
                    .push((ls, format!("no fit ({})", r.curve.status)));
                continue;
            };
            if integral.rate.is_nan() || integral.rate <= 0.0 {
                // a log axis has no room for it: said in words instead
                case.unfitted.push((ls, "rate 0".to_string()));
                continue;
            }
            let density = deaggregation_smoothed(hazard, m, b, &ims);
            let top = deaggregation_smoothed(hazard, m, b, &[integral.peak_im])[0]
                .max(density.iter().copied().fold(0.0, f64::max));
            case.series.push(RiskSeries {
                limit_state: ls,
                integrand: ims
                    .iter()
                    .zip(&density)
                    .map(|(&x, &d)| (x, if top > 0.0 { d / top } else { 0.0 }))
                    .collect(),
                peak_im: integral.peak_im,
                rate: integral.rate,
                band: r.band.map(|b| (b.lo, b.hi)),
            });
        }
        let keys: Vec<Case> = cases.iter().map(|c| c.key).collect();
        let (labels, common) = case_labels(&keys);
        for (c, label) in cases.iter_mut().zip(labels) {
            c.label = label;
        }
        let im_label = rows.first().map_or(Im::PGA, |r| r.curve.im).axis_label();
        let pct = (RiskOptions::default().confidence * 100.0).round();
        RiskFigure {
            title: format!("Annual rate of each limit state at {}", hazard.site()),
            im_label,
            limit_states,
            im_range: (lo, hi),
            hazard: with_rate(grid(h0, h1, SAMPLES)),
            hazard_extended: [with_rate(below), with_rate(above)],
            cases,
            common,
            band_label: format!("{pct} % band"),
        }
    }

    /// The cases drawn as rows: the first `MAX_ROWS`.
    pub fn shown(&self) -> &[RiskCase] {
        &self.cases[..self.cases.len().min(MAX_ROWS)]
    }

    /// The right-hand notes of panel (b), one per shown case: its limit
    /// states without a rate, in words (empty when it has none).
    pub fn notes(&self) -> Vec<String> {
        self.shown()
            .iter()
            .map(|c| {
                c.unfitted
                    .iter()
                    .map(|(ls, why)| format!("{}: {why}", self.limit_states[*ls]))
                    .collect::<Vec<_>>()
                    .join("; ")
            })
            .collect()
    }

    /// The rate axis's range: every rate and band, with room either side.
    fn rate_range(&self) -> (f64, f64) {
        let (lo, hi) = self
            .shown()
            .iter()
            .flat_map(|c| &c.series)
            .flat_map(|s| {
                let (a, b) = s.band.unwrap_or((s.rate, s.rate));
                [s.rate, a, b]
            })
            .filter(|v| *v > 0.0 && v.is_finite())
            .fold((f64::INFINITY, 0.0_f64), |(l, h), v| (l.min(v), h.max(v)));
        if hi > 0.0 {
            (lo / 2.0, hi * 2.0)
        } else {
            (1e-6, 1e-2)
        }
    }

    /// Panel (a)'s line pattern of each case: the index of its value of
    /// the first parameter that varies between the cases (H/B, 2B, e,
    /// friction, as panel (b)'s rows are grouped), while it takes at most
    /// three values (`None` for all: one pattern, the curves a bundle);
    /// with the values, in order, for the legend.
    pub fn groups(&self) -> Vec<Option<usize>> {
        self.grouping().map_or_else(
            || vec![None; self.cases.len()],
            |(of, _)| of.into_iter().map(Some).collect(),
        )
    }

    /// See [`RiskFigure::groups`]: each case's group and the groups' labels.
    fn grouping(&self) -> Option<(Vec<usize>, Vec<String>)> {
        let keys: Vec<[String; 4]> = self
            .cases
            .iter()
            .map(|c| {
                [
                    format!("H/B {}", param_label(c.key.aspect)),
                    format!("2B {}", param_label(c.key.width)),
                    format!("e {}", param_label(c.key.restitution)),
                    compact_friction(&friction_label(&c.key.friction)),
                ]
            })
            .collect();
        let field = (0..4).find(|&k| keys.iter().any(|p| p[k] != keys[0][k]))?;
        let mut values: Vec<String> = Vec::new();
        let of: Vec<usize> = keys
            .iter()
            .map(|p| match values.iter().position(|v| *v == p[field]) {
                Some(i) => i,
                None => {
                    values.push(p[field].clone());
                    values.len() - 1
                }
            })
            .collect();
        (values.len() <= 3).then_some((of, values))
    }

    fn legend(&self) -> Vec<Entry> {
        let mut entries = vec![Entry::new(Sample::Line(BLACK, Dash::Solid), "hazard λ")];
        // only when the IM axis reaches beyond the hazard's levels
        if self.hazard_extended.iter().any(|p| p.len() > 1) {
            entries.push(Entry::new(
                Sample::Line(BLACK, Dash::Dashed),
                "extrapolated",
            ));
        }
        for (i, ls) in self.limit_states.iter().enumerate() {
            entries.push(Entry::new(
                Sample::LinePoint(colour(i), Dash::Solid, Marker::Circle, true),
                ls.clone(),
            ));
        }
        // which deaggregation curve is which case's
        if let Some((_, values)) = self.grouping() {
            entries.push(Entry::new(Sample::Text, "(a):"));
            for (i, v) in values.into_iter().enumerate() {
                entries.push(Entry::new(Sample::Line(GROUP_SAMPLE, Dash::nth(i)), v));
            }
        }
        entries
    }
}

/// Row labels of `keys` naming only the parameters that vary between them,
/// and the text of those they all share (all of them for a single case,
/// whose row then needs no label).
fn case_labels(keys: &[Case]) -> (Vec<String>, String) {
    // (value, row label, heading text) of each parameter
    let parts = |c: &Case| -> [(String, String, String); 4] {
        let (a, w, e) = (
            param_label(c.aspect),
            param_label(c.width),
            param_label(c.restitution),
        );
        let f = friction_label(&c.friction);
        let metres = if c.width.is_drawn() { "" } else { " m" };
        [
            (a.clone(), format!("H/B {a}"), format!("H/B = {a}")),
            (w.clone(), format!("2B {w}"), format!("2B = {w}{metres}")),
            (e.clone(), format!("e {e}"), format!("e = {e}")),
            (f.clone(), compact_friction(&f), f),
        ]
    };
    let all: Vec<[(String, String, String); 4]> = keys.iter().map(parts).collect();
    // one case: its parameters are all shared, and its row needs no label
    let varies = |k: usize| all.iter().any(|p| p[k].0 != all[0][k].0);
    let labels = all
        .iter()
        .map(|p| {
            (0..4)
                .filter(|&k| varies(k))
                .map(|k| p[k].1.clone())
                .collect::<Vec<_>>()
                .join(", ")
        })
        .collect();
    let common = match all.first() {
        Some(p) => (0..4)
            .filter(|&k| !varies(k))
            .map(|k| p[k].2.clone())
            .collect::<Vec<_>>()
            .join(", "),
        _ => String::new(),
    };
    (labels, common)
}

/// `μₛ = 0.7, μₖ = 0.6` → `μₛ/μₖ 0.7/0.6`, `μ = ∞` → `μ ∞` (row labels).
fn compact_friction(label: &str) -> String {
    match label {
        "μ = ∞" => "μ ∞".to_string(),
        "μₛ, μₖ drawn" => "μ drawn".to_string(),
        other => {
            let values: Vec<&str> = other
                .split(", ")
                .filter_map(|p| p.split(" = ").nth(1))
                .collect();
            format!("μₛ/μₖ {}", values.join("/"))
        }
    }
}

fn colour(i: usize) -> RGBColor {
    super::style::PALETTE[i % super::style::PALETTE.len()]
}

/// Pixels to points at `style`'s resolution.
fn pt(style: &Style, px: u32) -> f64 {
    px as f64 * 72.0 / style.px_per_in
}

impl Figure for RiskFigure {
    fn size_in(&self) -> (f64, f64) {
        let rows = self.shown().len().max(1) as f64;
        let plot = (rows * ROW_PT / 72.0).max(MIN_PLOT_IN);
        (PAGE_WIDTH_IN, HEADER_IN + plot + FOOTER_IN)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB> {
        let (xl, xh) = self.im_range;
        let rates = self
            .hazard
            .iter()
            .chain(self.hazard_extended.iter().flatten())
            .map(|p| p.1)
            .filter(|r| *r > 0.0);
        let (y_min, y_max) = rates.fold((f64::INFINITY, 0.0_f64), |(a, b), r| (a.min(r), b.max(r)));
        let (yl, yh) = if y_max > 0.0 {
            (y_min.max(1e-12 * y_max) / 2.0, y_max * 2.0)
        } else {
            (1e-6, 1.0)
        };
        let im_axis = LogAxis::new(xl, xh);
        let lambda_axis = LogAxis::new(yl, yh);
        let (rl, rh) = self.rate_range();
        let rate_axis = LogAxis::new(rl, rh);
        let shown = self.shown();
        let labels: Vec<String> = shown.iter().map(|c| c.label.clone()).collect();
        let notes = self.notes();

        let lambda_w = layout::widest(
            root,
            style,
            lambda_axis.ticks.iter().map(|&t| lambda_axis.label(t)),
        );
        let mut title = self.title.clone();
        if !self.common.is_empty() {
            title.push_str(&format!("; {}", self.common));
        }
        let frame = Frame::new(
            root,
            style,
            &title,
            &self.legend(),
            Margins::new(pt(style, lambda_w) + TICK_ROOM_PT, 0.0),
        )?;
        let (left, right) = frame
            .body
            .split_horizontally(style.ipx(HAZARD_PANEL_IN * 72.0));
        let thin = style.ipx(LINE_PT);

        // (a) hazard and deaggregation
        let left = layout::side_label(
            &left,
            style,
            "Annual rate λ (1/yr)",
            frame.top,
            frame.x_area,
        )?;
        frame.heading(&left, "(a) Hazard and deaggregation")?;
        // the right-hand axis: tick marks, labels (twice the ticks' length
        // from the axis), then its description beside them, close enough to
        // read as its own
        let right_labels = ["0", "0.5", "1"].map(String::from);
        let label_font = style.label_font();
        let desc_h = left
            .estimate_text_size(DEAGGREGATION_LABEL, &label_font)
            .map_or(style.ipx(LABEL_PT_LINE), |(_, h)| h);
        let right_area = style.ipx(2.0 * 2.5 + RIGHT_DESC_GAP_PT)
            + layout::widest(root, style, right_labels)
            + desc_h;
        let mut builder = frame.chart(&left, true);
        builder.right_y_label_area_size(right_area);
        let mut chart = builder
            .build_cartesian_2d(
                (xl..xh).log_scale().with_key_points(im_axis.ticks.clone()),
                (yl..yh)
                    .log_scale()
                    .with_key_points(lambda_axis.ticks.clone()),
            )?
            .set_secondary_coord((xl..xh).log_scale(), 0.0..1.05);
        layout::mesh(&mut chart, style)
            .x_desc(self.im_label.as_str())
            .x_label_formatter(&|v| im_axis.label(*v))
            .y_label_formatter(&|v| lambda_axis.label(*v))
            .draw()?;
        // the house's tick marks: the labels stand clear of them (plotters
        // puts a label twice the tick's length from the axis)
        chart
            .configure_secondary_axes()
            .axis_style(style.axis())
            .set_all_tick_mark_size(style.ipx(2.5))
            .label_style(style.tick_font())
            .axis_desc_style(style.label_font())
            .y_desc(DEAGGREGATION_LABEL)
            .y_labels(3)
            .y_label_formatter(&|v| super::style::tick_label(*v))
            .draw()?;
        let groups = self.groups();
        for (case, group) in self.cases.iter().zip(&groups) {
            for s in &case.series {
                let c = colour(s.limit_state)
                    .mix(INTEGRAND_ALPHA)
                    .stroke_width(thin);
                let dash = group.map_or(Dash::Solid, Dash::nth);
                match dash.pattern() {
                    None => {
                        chart.draw_secondary_series(LineSeries::new(
                            s.integrand.iter().copied(),
                            c,
                        ))?;
                    }
                    Some((on, off)) => {
                        chart.draw_secondary_series(plotters::prelude::DashedLineSeries::new(
                            s.integrand.iter().copied(),
                            style.px(on).round() as i32,
                            style.px(off).round() as i32,
                            c,
                        ))?;
                    }
                }
            }
        }
        for s in self.cases.iter().flat_map(|c| &c.series) {
            let c = colour(s.limit_state);
            chart.draw_secondary_series(std::iter::once(PathElement::new(
                vec![(s.peak_im, 1.0), (s.peak_im, 1.05)],
                c.stroke_width(thin),
            )))?;
        }
        chart.draw_series(LineSeries::new(
            self.hazard.iter().copied(),
            BLACK.stroke_width(style.ipx(0.8)),
        ))?;
        for part in &self.hazard_extended {
            curve!(
                chart,
                part.iter().copied(),
                BLACK.stroke_width(style.ipx(0.8)),
                Dash::Dashed,
                style
            );
        }

        // (b) one row per case
        let label_w = layout::widest(root, style, labels.iter().cloned());
        let note_w = layout::widest(root, style, notes.iter().cloned());
        let heading = format!("(b) Annual rate per case, {}", self.band_label);
        layout::heading(
            &right,
            style,
            &heading,
            label_w + style.ipx(TICK_ROOM_PT + PANEL_GAP_PT),
        )?;
        let n = shown.len().max(1);
        let note_room = if note_w > 0 {
            note_w + style.ipx(4.0)
        } else {
            style.ipx(10.0)
        };
        let mut chart = frame
            .chart(&right, true)
            .margin_left(style.ipx(PANEL_GAP_PT))
            .margin_right(note_room)
            .y_label_area_size(label_w + style.ipx(TICK_ROOM_PT))
            .build_cartesian_2d(
                (rl..rh)
                    .log_scale()
                    .with_key_points(rate_axis.ticks.clone()),
                -0.5..n as f64 - 0.5,
            )?;
        // alternate H/B groups shaded, under the grid
        let mut group = 0;
        for (i, c) in shown.iter().enumerate() {
            if i > 0 && c.key.aspect != shown[i - 1].key.aspect {
                group += 1;
            }
            if group % 2 == 1 {
                let y = (n - 1 - i) as f64;
                chart.draw_series(std::iter::once(Rectangle::new(
                    [(rl, y - 0.5), (rh, y + 0.5)],
                    GROUP_SHADE.filled(),
                )))?;
            }
        }
        layout::mesh(&mut chart, style)
            .x_desc("Annual rate of exceedance (1/yr)")
            .x_label_formatter(&|v| rate_axis.label(*v))
            .y_labels(0)
            .draw()?;
        // a light line along each row, its label left of the axis
        let label_font = style.tick_font().pos(Pos::new(HPos::Right, VPos::Center));
        let (base_x, base_y) = right.get_base_pixel();
        let (x_px, _) = chart.plotting_area().get_pixel_range();
        for (i, label) in labels.iter().enumerate() {
            let y = (n - 1 - i) as f64;
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(rl, y), (rh, y)],
                style.grid(),
            )))?;
            let (_, y_px) = chart.backend_coord(&(rl, y));
            right.draw(&Text::new(
                label.clone(),
                (x_px.start - base_x - style.ipx(3.0) as i32, y_px - base_y),
                label_font.clone(),
            ))?;
        }
        let n_ls = self.limit_states.len().max(1);
        let step = (0.7 / n_ls as f64).min(0.25);
        let r = layout::marker_px(style, true);
        for (i, c) in shown.iter().enumerate() {
            let y0 = (n - 1 - i) as f64;
            for s in &c.series {
                let y = y0 + step * ((n_ls - 1) as f64 / 2.0 - s.limit_state as f64);
                let col = colour(s.limit_state);
                if let Some((a, b)) = s.band {
                    chart.draw_series(std::iter::once(PathElement::new(
                        vec![(a.max(rl), y), (b.min(rh), y)],
                        col.stroke_width(style.ipx(0.9)),
                    )))?;
                }
                chart.draw_series(std::iter::once(plotters::prelude::Circle::new(
                    (s.rate, y),
                    r,
                    col.filled(),
                )))?;
            }
        }
        // the notes, right of the plot, on their rows
        let font = style.tick_font().pos(Pos::new(HPos::Left, VPos::Center));
        for (i, note) in notes.iter().enumerate() {
            if note.is_empty() {
                continue;
            }
            let y = (n - 1 - i) as f64;
            let (_, y_px) = chart.backend_coord(&(rh, y));
            right.draw(&Text::new(
                note.clone(),
                (x_px.end - base_x + style.ipx(4.0) as i32, y_px - base_y),
                font.clone(),
            ))?;
        }
        if self.cases.len() > shown.len() {
            let (w, h) = right.dim_in_pixel();
            right.draw(&Text::new(
                format!("{} more cases in risk.csv", self.cases.len() - shown.len()),
                (
                    w as i32 - style.ipx(4.0) as i32,
                    h as i32 - style.ipx(4.0) as i32,
                ),
                style.tick_font().pos(Pos::new(HPos::Right, VPos::Bottom)),
            ))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn row_labels_name_what_varies_and_the_heading_what_is_shared() {
        use crate::solver::Friction;
        let coulomb = Friction::Coulomb {
            mu_s: 0.7,
            mu_k: 0.6,
        };
        let keys = [
            Case::fixed(2.0, 0.5, 0.0, Friction::Infinite),
            Case::fixed(2.0, 0.5, 0.0, coulomb),
            Case::fixed(4.0, 0.5, 0.3, Friction::Infinite),
        ];
        let (labels, common) = case_labels(&keys);
        assert_eq!(
            labels,
            [
                "H/B 2, e 0, μ ∞",
                "H/B 2, e 0, μₛ/μₖ 0.7/0.6",
                "H/B 4, e 0.3, μ ∞"
            ]
        );
        assert_eq!(common, "2B = 0.5 m");
        // one case: every parameter shared, none in its row
        let (labels, common) = case_labels(&keys[..1]);
        assert_eq!(labels, [""]);
        assert_eq!(common, "H/B = 2, 2B = 0.5 m, e = 0, μ = ∞");
    }
}
