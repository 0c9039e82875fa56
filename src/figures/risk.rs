//! Risk at a site (`risk.svg`): on a shared logarithmic IM axis, one panel
//! per case, the hazard curve (annual rate of exceedance, left, logarithmic,
//! black; dashed beyond its levels, where the risk integral extrapolates
//! it), each limit state's fragility curve (right, 0–1, solid, one colour per
//! limit state) and the integrand P(LS | im)·|dλ/d ln im| (the rate's
//! deaggregation over intensity, scaled to peak at 1, shaded in the same
//! colour; the tick at the top marks its peak located with the hazard's
//! slope smoothed between levels, see [`crate::risk`]). A case without a fit has
//! only its hazard curve and says "no fit".

use crate::detmath as dm;
use plotters::coord::Shift;
use plotters::prelude::{
    BindKeyPoints, DrawingArea, DrawingBackend, IntoLogRange, LineSeries, PathElement, Polygon,
    Text,
};
use plotters::style::{BLACK, Color};

use super::figure::{DrawResult, Figure};
use super::layout::{self, Dash, Entry, Frame, Margins, Sample, curve};
use super::style::{LINE_PT, PAGE_WIDTH_IN, Style, tick_label};
use crate::risk::{HazardCurve, RiskRow, deaggregation};

/// Panels per row.
const COLUMNS: usize = 4;
/// Height of one row of panels (in).
const ROW_IN: f64 = 1.55;
/// Room above the panels for title and legend (in).
const HEADER_IN: f64 = 0.55;
/// Left margin for the hazard's tick labels, right for the probability's.
const MARGINS: Margins = Margins::new(24.0, 4.0);
/// Room right of a panel for the probability tick labels (pt).
const RIGHT_AXIS_PT: f64 = 18.0;
/// Samples per curve.
const SAMPLES: usize = 240;
/// Opacity of the deaggregation's shading.
const SHADE_ALPHA: f64 = 0.22;

/// One limit state of one panel.
#[derive(Clone, Debug, PartialEq)]
pub struct RiskSeries {
    /// Index into [`RiskFigure::limit_states`] (sets the colour).
    pub limit_state: usize,
    /// (im, P(LS | im)).
    pub fragility: Vec<(f64, f64)>,
    /// (im, integrand scaled to peak at 1).
    pub integrand: Vec<(f64, f64)>,
    /// Where the integrand peaks.
    pub peak_im: f64,
}

/// One panel: one case.
#[derive(Clone, Debug, PartialEq)]
pub struct RiskPanel {
    /// Heading (the case).
    pub label: String,
    /// Its limit states with a fit.
    pub series: Vec<RiskSeries>,
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
    /// Panels, in the order of `risk.csv`'s cases.
    pub panels: Vec<RiskPanel>,
}

impl RiskFigure {
    /// The figure of `rows` (as [`crate::risk::assess`] returns them) over `hazard`.
    pub fn new(rows: &[RiskRow], hazard: &HazardCurve) -> RiskFigure {
        let fitted: Vec<(f64, f64)> = rows.iter().filter_map(|r| r.curve.fit).collect();
        let (h0, h1) = (hazard.iml[0], hazard.iml[hazard.iml.len() - 1]);
        // Wide enough for each integrand's bulk (±3β about the median) and
        // the hazard's levels.
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
        let mut panels: Vec<RiskPanel> = Vec::new();
        for r in rows {
            let label = r.curve.key.to_string();
            if panels.last().is_none_or(|p| p.label != label) {
                panels.push(RiskPanel {
                    label,
                    series: Vec::new(),
                });
            }
            let ls = match limit_states.iter().position(|l| *l == r.curve.limit_state) {
                Some(i) => i,
                None => {
                    limit_states.push(r.curve.limit_state.clone());
                    limit_states.len() - 1
                }
            };
            let (Some((m, b)), Some(integral)) = (r.curve.fit, r.integral) else {
                continue;
            };
            let p = |x: f64| dm::norm_cdf(dm::ln(x / m) / b);
            let density = deaggregation(hazard, m, b, &ims);
            let top = deaggregation(hazard, m, b, &[integral.peak_im])[0]
                .max(density.iter().copied().fold(0.0, f64::max));
            let panel = panels.last_mut().expect("pushed above");
            panel.series.push(RiskSeries {
                limit_state: ls,
                fragility: ims.iter().map(|&x| (x, p(x))).collect(),
                integrand: ims
                    .iter()
                    .zip(&density)
                    .map(|(&x, &d)| (x, if top > 0.0 { d / top } else { 0.0 }))
                    .collect(),
                peak_im: integral.peak_im,
            });
        }
        let (im, unit) = rows.first().map_or(("pga", "g"), |r| {
            (r.curve.im.as_str(), r.curve.im_unit.as_str())
        });
        let im_label = match (im, unit) {
            ("pga", _) => "PGA (g)".to_string(),
            ("pgv", _) => "PGV (m/s)".to_string(),
            ("pfa", _) => "PFA (g)".to_string(),
            ("pfv", _) => "PFV (m/s)".to_string(),
            (name, "1" | "") => name.to_string(),
            (name, u) => format!("{name} ({u})"),
        };
        RiskFigure {
            title: format!(
                "Annual rate: hazard ({}), fragility, deaggregation",
                site_label(hazard)
            ),
            im_label,
            limit_states,
            im_range: (lo, hi),
            hazard: with_rate(grid(h0, h1, SAMPLES)),
            hazard_extended: [with_rate(below), with_rate(above)],
            panels,
        }
    }

    fn legend(&self) -> Vec<Entry> {
        let mut entries = vec![
            Entry::new(Sample::Line(BLACK, Dash::Solid), "hazard λ (1/yr, left)"),
            Entry::new(Sample::Line(BLACK, Dash::Dashed), "extrapolated"),
        ];
        for (i, ls) in self.limit_states.iter().enumerate() {
            entries.push(Entry::new(
                Sample::Line(colour(i), Dash::Solid),
                format!("P({ls} | IM) (right)"),
            ));
            entries.push(Entry::new(
                Sample::Block(layout::tint(colour(i), 1.0 - 1.5 * SHADE_ALPHA)),
                "its deaggregation (peak = 1)",
            ));
        }
        entries
    }
}

/// `site K of FILE` for an OpenQuake curve, else the file name.
fn site_label(hazard: &HazardCurve) -> String {
    let name = hazard
        .path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    match &hazard.source {
        crate::risk::HazardSource::OpenQuake { site, .. } => format!("site {site} of {name}"),
        crate::risk::HazardSource::Plain => name,
    }
}

fn colour(i: usize) -> plotters::style::RGBColor {
    super::style::PALETTE[i % super::style::PALETTE.len()]
}

/// 1, 2, 5 × powers of ten in [lo, hi].
fn log_ticks(lo: f64, hi: f64, multiples: &[f64]) -> Vec<f64> {
    let mut v = Vec::new();
    let mut decade = dm::powf(10.0, dm::log10(lo).floor());
    while decade <= hi {
        for m in multiples {
            let t = m * decade;
            if t >= lo && t <= hi {
                v.push(t);
            }
        }
        decade *= 10.0;
    }
    v
}

impl Figure for RiskFigure {
    fn size_in(&self) -> (f64, f64) {
        let rows = self.panels.len().div_ceil(COLUMNS).max(1);
        (PAGE_WIDTH_IN, HEADER_IN + ROW_IN * rows as f64)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB> {
        let frame = Frame::new(root, style, &self.title, &self.legend(), MARGINS)?;
        let n_rows = self.panels.len().div_ceil(COLUMNS).max(1);
        let areas = frame.body.split_evenly((n_rows, COLUMNS));
        let (xl, xh) = self.im_range;
        let rates = self
            .hazard
            .iter()
            .chain(self.hazard_extended.iter().flatten())
            .map(|p| p.1)
            .filter(|r| *r > 0.0);
        let (y_min, y_max) = rates.fold((f64::INFINITY, 0.0_f64), |(a, b), r| (a.min(r), b.max(r)));
        let (yl, yh) = (y_min.max(1e-12 * y_max) / 2.0, y_max * 2.0);
        let x_ticks = log_ticks(xl, xh, &[1.0, 3.0]);
        let y_ticks = log_ticks(yl, yh, &[1.0]);
        let thin = style.ipx(LINE_PT);
        for (panel, area) in self.panels.iter().zip(&areas) {
            frame.heading(area, &panel.label)?;
            let mut builder = frame.chart(area, true);
            builder.right_y_label_area_size(style.ipx(RIGHT_AXIS_PT));
            let mut chart = builder
                .build_cartesian_2d(
                    (xl..xh).log_scale().with_key_points(x_ticks.clone()),
                    (yl..yh).log_scale().with_key_points(y_ticks.clone()),
                )?
                .set_secondary_coord((xl..xh).log_scale(), 0.0..1.05);
            layout::mesh(&mut chart, style)
                .x_desc(self.im_label.as_str())
                .x_label_formatter(&|v| tick_label(*v))
                .y_label_formatter(&|v| format!("1e{}", dm::log10(*v).round()))
                .draw()?;
            chart
                .configure_secondary_axes()
                .axis_style(style.axis())
                .label_style(style.tick_font())
                .y_labels(3)
                .y_label_formatter(&|v| tick_label(*v))
                .draw()?;
            for s in &panel.series {
                let c = colour(s.limit_state);
                let mut shade: Vec<(f64, f64)> = s.integrand.clone();
                shade.push((xh, 0.0));
                shade.push((xl, 0.0));
                chart.draw_secondary_series(std::iter::once(Polygon::new(
                    shade,
                    c.mix(SHADE_ALPHA).filled(),
                )))?;
                chart.draw_secondary_series(LineSeries::new(
                    s.fragility.clone(),
                    c.stroke_width(thin),
                ))?;
                chart.draw_secondary_series(std::iter::once(PathElement::new(
                    vec![(s.peak_im, 0.95), (s.peak_im, 1.05)],
                    c.stroke_width(thin),
                )))?;
            }
            chart.draw_series(LineSeries::new(
                self.hazard.clone(),
                BLACK.stroke_width(thin),
            ))?;
            for part in &self.hazard_extended {
                curve!(
                    chart,
                    part.clone(),
                    BLACK.stroke_width(thin),
                    Dash::Dashed,
                    style
                );
            }
            if panel.series.is_empty() {
                chart.draw_secondary_series(std::iter::once(Text::new(
                    "no fit",
                    (xl * 1.2, 0.12),
                    style.tick_font(),
                )))?;
            }
        }
        Ok(())
    }
}
