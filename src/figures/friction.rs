//! Friction demand against B/H, under infinite friction (the paper's
//! setting: demand is only meaningful when friction never limits it).
//!
//! (a) Mean μ_mot, the peak |F|/N while rocking, over the runs that rocked
//! (μ_mot > 0) and did not overturn: one line per PGA, pooled over e (the
//! paper found it insensitive to e). (b) Mean μ_imp, the peak |P_t/P_n| over
//! impacts, over the runs with impacts that did not overturn, on a log
//! scale: one line per e, pooled over PGA. (c) The same mean of the peak of
//! the paper's eq. (5) (`mu_impact_eq5`), which is what the paper's μ_imp
//! column reports, on the same log axis as (b) since the paper's values span
//! 0.1–10⁴. Every panel carries the paper's eq. (8),
//! μ = 3 cosθc sinθc/(1 + 3cos²θc), and its small-angle form 0.75·B/H.
//! Published values may be set beside this study's means
//! ([`DemandSeries::reference`], drawn as open squares set
//! [`REFERENCE_DODGE`] of the axis to the right of their B/H so that they do
//! not hide the means, with [`FrictionDemandFigure::reference_label`] in the
//! legend): the paper layer puts its Tables 1–3 there for the paper's study.
//! For an `outcomes.csv` written before the eq. (5) column existed, panel
//! (c) is left out.
//!
//! What is shared (the reference curves, this study's markers, the
//! published values) is in the legend at the top; what belongs to one panel
//! (its PGA or e colours) is in a box under that panel's heading, as wide as
//! its column, so that no legend row reads across two panels. Each panel
//! carries its quantity as a y-axis label.

use crate::detmath as dm;
use plotters::coord::Shift;
use plotters::prelude::{BindKeyPoints, DrawingArea, DrawingBackend, IntoLogRange, Rectangle};
use plotters::style::{BLACK, Color, RGBColor};

use super::data::{PlotRow, StudyData, distinct, distinct_fixed, distinct_numbers, param_label};
use super::figure::{DrawResult, Figure};
use super::fragility::restitution_colour;
use super::layout::{self, Dash, Entry, Frame, LogAxis, Margins, Marker, Sample, curve, markers};
use super::style::{AXIS_PT, LINE_PT, PAGE_WIDTH_IN, Style, tick_label};
use crate::case::Param;
use crate::solver::Friction;

/// Figure height (in).
const HEIGHT_IN: f64 = 3.3;
/// Panel margins: 30 pt for the y tick labels, 10 pt on the right.
const MARGINS: Margins = Margins::new(30.0, 10.0);
/// Horizontal offset of the reference markers, as a fraction of the B/H axis.
pub const REFERENCE_DODGE: f64 = 0.02;
/// Points on each reference curve.
const REFERENCE_POINTS: usize = 120;
/// Room inside a panel legend's box above and below its rows (pt).
const LEGEND_PAD_PT: f64 = 1.5;
/// Room inside a panel legend's box left and right of its rows (pt).
const LEGEND_SIDE_PT: f64 = 3.0;
/// Gap between a panel legend's box and the plot below it, and between
/// the boxes of neighbouring panels (pt).
const LEGEND_GAP_PT: f64 = 6.0;
/// Edge of a panel legend's box.
const LEGEND_EDGE: RGBColor = RGBColor(0xAA, 0xAA, 0xAA);

/// One line of a panel.
#[derive(Clone, Debug, PartialEq)]
pub struct DemandSeries {
    /// Legend label (`0.6 g`, `e = 0.3`).
    pub label: String,
    /// What the series is for: its PGA (g) in panel (a), its e in (b), (c).
    pub at: Param<f64>,
    /// Line colour.
    pub colour: RGBColor,
    /// (B/H, mean) of this study, B/H ascending.
    pub means: Vec<(f64, f64)>,
    /// (B/H, value) of published results in this series (see
    /// [`FrictionDemandFigure::reference_label`]).
    pub reference: Vec<(f64, f64)>,
}

/// The friction-demand figure's data.
#[derive(Clone, Debug, PartialEq)]
pub struct FrictionDemandFigure {
    /// Title.
    pub title: String,
    /// Panel (a): μ_mot, a series per PGA.
    pub motion: Vec<DemandSeries>,
    /// Panel (b): μ_imp, a series per restitution.
    pub impact: Vec<DemandSeries>,
    /// Panel (c): the paper's eq. (5), a series per restitution; empty when
    /// the study's file has no such column.
    pub eq5: Vec<DemandSeries>,
    /// Largest B/H of the study.
    pub b_over_h_max: f64,
    /// Legend label of the reference values (drawn when any series has
    /// some), e.g. `paper, Tables 1–3`.
    pub reference_label: Option<String>,
}

/// The paper's eq. (8) as a function of B/H: the impulse ratio of a rock
/// impact without slip, 3 cosθc sinθc/(1 + 3 cos²θc), θc = atan(B/H).
pub fn eq8(b_over_h: f64) -> f64 {
    let (s, c) = dm::sin_cos(dm::atan(b_over_h));
    3.0 * c * s / (1.0 + 3.0 * c * c)
}

/// At most `max` levels, evenly spread over `levels` (all of them if they
/// fit): the first, the last and evenly spaced ones between.
pub fn pick_levels(levels: &[f64], max: usize) -> Vec<f64> {
    if levels.len() <= max || max < 2 {
        return levels.to_vec();
    }
    let n = levels.len() - 1;
    let mut v: Vec<f64> = (0..max)
        .map(|i| levels[(i * n + (max - 1) / 2) / (max - 1)])
        .collect();
    v.dedup();
    v
}

/// Most PGA levels drawn as separate lines.
pub const MAX_LEVELS: usize = 5;
/// Levels drawn when there are more than [`MAX_LEVELS`].
pub const PICKED_LEVELS: usize = 4;

/// Colour of PGA level `i` of `n` (dark to light).
pub fn level_colour(i: usize, n: usize) -> RGBColor {
    layout::sequential(i, n)
}

/// The PGA levels drawn as lines: all of them if there are at most
/// [`MAX_LEVELS`]; otherwise [`PICKED_LEVELS`] spread over the range.
pub fn shown_levels(levels: &[f64]) -> Vec<f64> {
    if levels.len() <= MAX_LEVELS {
        levels.to_vec()
    } else {
        pick_levels(levels, PICKED_LEVELS)
    }
}

fn mean(v: impl Iterator<Item = f64>) -> Option<f64> {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    (n > 0).then(|| s / n as f64)
}

impl FrictionDemandFigure {
    /// Averages the study's infinite-friction runs; `None` if it has none.
    pub fn from_study(data: &StudyData) -> Option<FrictionDemandFigure> {
        let rows: Vec<_> = data
            .outcomes
            .iter()
            .filter(|r| r.case.friction == INFINITE && !r.overturned)
            .collect();
        if !data.outcomes.iter().any(|r| r.case.friction == INFINITE) {
            return None;
        }
        let all_inf = data.outcomes.iter().filter(|r| r.case.friction == INFINITE);
        let aspects = distinct_fixed(all_inf.clone().map(|r| r.case.aspect));
        let levels = shown_levels(&distinct_numbers(all_inf.clone().map(|r| r.pga)));
        let es = distinct(all_inf.clone().map(|r| r.case.restitution));
        let widths = distinct(all_inf.map(|r| r.case.width));

        let motion = levels
            .iter()
            .enumerate()
            .map(|(i, &pga)| DemandSeries {
                label: format!("{} g", tick_label(pga)),
                at: Param::Fixed(pga),
                colour: level_colour(i, levels.len()),
                means: aspects
                    .iter()
                    .rev()
                    .filter_map(|&a| {
                        mean(
                            rows.iter()
                                .filter(|r| {
                                    r.case.aspect == Param::Fixed(a)
                                        && r.pga == pga
                                        && r.mu_motion > 0.0
                                })
                                .map(|r| r.mu_motion),
                        )
                        .map(|m| (1.0 / a, m))
                    })
                    .collect(),
                reference: Vec::new(),
            })
            .collect();
        let has_eq5 = rows.iter().all(|r| r.mu_impact_eq5.is_some());
        let impact_series = |value: &dyn Fn(&PlotRow) -> f64| -> Vec<DemandSeries> {
            es.iter()
                .enumerate()
                .map(|(i, &e)| DemandSeries {
                    label: format!("e = {}", param_label(e)),
                    at: e,
                    colour: restitution_colour(i),
                    means: aspects
                        .iter()
                        .rev()
                        .filter_map(|&a| {
                            mean(
                                rows.iter()
                                    .filter(|r| {
                                        r.case.aspect == Param::Fixed(a)
                                            && r.case.restitution == e
                                            && r.impacts > 0
                                    })
                                    .map(|r| value(r)),
                            )
                            .map(|m| (1.0 / a, m))
                        })
                        .collect(),
                    reference: Vec::new(),
                })
                .collect()
        };
        let impact = impact_series(&|r| r.mu_impact);
        let eq5 = if has_eq5 {
            impact_series(&|r| r.mu_impact_eq5.unwrap_or(0.0))
        } else {
            Vec::new()
        };
        let mut title = "Friction demand, infinite friction, runs not overturned".to_string();
        if widths.len() > 1 {
            title.push_str(" (all widths pooled)");
        }
        Some(FrictionDemandFigure {
            title,
            motion,
            impact,
            eq5,
            b_over_h_max: aspects.first().map_or(0.5, |a| 1.0 / a),
            reference_label: None,
        })
    }

    /// Whether any panel carries a reference value.
    pub fn has_reference(&self) -> bool {
        self.motion
            .iter()
            .chain(&self.impact)
            .chain(&self.eq5)
            .any(|s| !s.reference.is_empty())
    }
}

/// Infinite friction, as a case parameter.
const INFINITE: Param<Friction> = Param::Fixed(Friction::Infinite);

/// Draws each series' means (line and filled circles) and the reference
/// values (open squares, moved right by `dodge`) on `chart`.
macro_rules! draw_series_set {
    ($chart:expr, $series:expr, $style:expr, $dodge:expr) => {{
        for s in $series.iter() {
            let line = s.colour.stroke_width($style.ipx(LINE_PT));
            curve!($chart, s.means.iter().copied(), line, Dash::Solid, $style);
        }
        for s in $series.iter() {
            markers!(
                $chart,
                s.reference.iter().map(|&(x, y)| (x + $dodge, y)),
                s.colour,
                Marker::Square,
                false,
                $style
            );
            markers!(
                $chart,
                s.means.iter().copied(),
                s.colour,
                Marker::Circle,
                true,
                $style
            );
        }
    }};
}

impl Figure for FrictionDemandFigure {
    fn size_in(&self) -> (f64, f64) {
        (PAGE_WIDTH_IN, HEIGHT_IN)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB> {
        let mut shared = vec![
            Entry::new(Sample::Line(BLACK, Dash::Solid), "eq. (8)"),
            Entry::new(Sample::Line(BLACK, Dash::Dashed), "0.75·B/H"),
            Entry::new(
                Sample::Point(BLACK, Marker::Circle, true),
                "this study, mean",
            ),
        ];
        if let Some(label) = self
            .reference_label
            .as_ref()
            .filter(|_| self.has_reference())
        {
            shared.push(Entry::new(
                Sample::Point(BLACK, Marker::Square, false),
                label.clone(),
            ));
        }
        let frame = Frame::new(root, style, &self.title, &shared, MARGINS)?;
        // (heading, y-axis label, series)
        let mut panels: Vec<(&str, &str, &Vec<DemandSeries>)> = vec![
            ("(a) During rocking", "Mean μₘₒₜ = max |F|/N", &self.motion),
            ("(b) Impacts (log scale)", "Mean max |Pₜ/Pₙ|", &self.impact),
        ];
        if !self.eq5.is_empty() {
            panels.push(("(c) Eq. (5) (log scale)", "Mean max of eq. (5)", &self.eq5));
        }
        let areas = frame.body.split_evenly((1, panels.len()));
        let x_max = self.b_over_h_max * 1.12;
        let reference = |f: &dyn Fn(f64) -> f64, lo: f64| -> Vec<(f64, f64)> {
            (1..=REFERENCE_POINTS)
                .map(|i| {
                    let x = x_max * i as f64 / REFERENCE_POINTS as f64;
                    (x, f(x))
                })
                .filter(|&(_, y)| y >= lo)
                .collect()
        };
        let ref_style = BLACK.stroke_width(style.ipx(LINE_PT));
        let three_quarters = |x: f64| 0.75 * x;

        // Each panel's own legend, boxed under its heading and as wide as
        // its plot, so that it cannot be read as a row of its neighbour's.
        let legends: Vec<Vec<Entry>> = panels
            .iter()
            .enumerate()
            .map(|(k, (_, _, series))| {
                let mut entries = Vec::new();
                match k {
                    0 => entries.push(Entry::new(Sample::Text, "PGA (g):")),
                    // (c) has the colours of (b)
                    2 => {
                        entries.push(Entry::new(Sample::Text, "e: as in (b)"));
                        return entries;
                    }
                    _ => entries.push(Entry::new(Sample::Text, "e:")),
                }
                entries.extend(series.iter().map(|s| {
                    Entry::new(
                        Sample::Line(s.colour, Dash::Solid),
                        s.label
                            .trim_start_matches("e = ")
                            .trim_end_matches(" g")
                            .to_string(),
                    )
                }));
                entries
            })
            .collect();
        let columns: Vec<_> = areas
            .iter()
            .zip(&panels)
            .map(|(area, (_, label, _))| {
                layout::side_label(area, style, label, frame.top, frame.x_area)
            })
            .collect::<Result<_, _>>()?;
        // The box spans the panel's column, side label included, less a gap
        // to the next column.
        let legend_area = |area: &DrawingArea<DB, Shift>, rows: usize| {
            let (w, _) = area.dim_in_pixel();
            let pad = style.ipx(LEGEND_PAD_PT);
            let h = (style.px(layout::LEGEND_ROW_PT) * rows as f64).round() as u32 + 2 * pad;
            let x0 = style.ipx(2.0);
            let width = w.saturating_sub(x0 + style.ipx(LEGEND_GAP_PT));
            (x0, frame.top, width, h)
        };
        let own_rows: Vec<usize> = areas
            .iter()
            .zip(&legends)
            .map(|(area, entries)| {
                let (x0, y0, w, h) = legend_area(area, 1);
                let side = style.ipx(LEGEND_SIDE_PT);
                let inner = area.clone().shrink((x0 + side, y0), (w - 2 * side, h));
                layout::legend_rows(&inner, style, entries)
            })
            .collect();
        // the plots start below the tallest box, level with each other
        let rows = own_rows.iter().copied().max().unwrap_or(1);
        // (b) and (c) share their log axis, so that they compare at a glance
        let (lo, hi) = panels[1..]
            .iter()
            .flat_map(|(_, _, series)| series.iter())
            .flat_map(|s| s.means.iter().chain(&s.reference))
            .map(|p| p.1)
            .filter(|v| *v > 0.0 && v.is_finite())
            .fold((f64::INFINITY, 0.0_f64), |(l, h), v| (l.min(v), h.max(v)));
        let (lo, hi) = if hi > 0.0 { (lo, hi) } else { (0.1, 1.0) };
        for (k, ((area, (heading, _, series)), entries)) in
            columns.iter().zip(&panels).zip(&legends).enumerate()
        {
            frame.heading(area, heading)?;
            let column = &areas[k];
            let (x0, y0, w, h) = legend_area(column, own_rows[k]);
            let pad = style.ipx(LEGEND_PAD_PT);
            column.draw(&Rectangle::new(
                [(x0 as i32, y0 as i32), ((x0 + w) as i32, (y0 + h) as i32)],
                LEGEND_EDGE.stroke_width(style.ipx(AXIS_PT)),
            ))?;
            let side = style.ipx(LEGEND_SIDE_PT);
            let inner = column
                .clone()
                .shrink((x0 + side, y0 + pad), (w - 2 * side, h - 2 * pad));
            layout::legend(&inner, style, entries)?;
            let top = y0 + legend_area(column, rows).3 + style.ipx(LEGEND_GAP_PT);
            if k == 0 {
                let hi = series
                    .iter()
                    .flat_map(|s| s.means.iter().chain(&s.reference))
                    .map(|p| p.1)
                    .fold(0.0_f64, f64::max);
                let y_hi = hi.max(0.75 * x_max) * 1.08;
                let mut chart = frame
                    .chart(area, true)
                    .margin_top(top)
                    .build_cartesian_2d(0.0..x_max, 0.0..y_hi)?;
                let mut mesh = layout::mesh(&mut chart, style);
                mesh.x_labels(7).y_labels(7).x_desc("B/H").draw()?;
                curve!(chart, reference(&eq8, 0.0), ref_style, Dash::Solid, style);
                curve!(
                    chart,
                    reference(&three_quarters, 0.0),
                    ref_style,
                    Dash::Dashed,
                    style
                );
                draw_series_set!(chart, series, style, x_max * REFERENCE_DODGE);
            } else {
                let y_lo = lo.min(eq8(self.b_over_h_max)) * 0.6;
                let y_axis = LogAxis::new(y_lo, hi * 1.6);
                let mut chart = frame.chart(area, true).margin_top(top).build_cartesian_2d(
                    0.0..x_max,
                    (y_lo..hi * 1.6)
                        .log_scale()
                        .with_key_points(y_axis.ticks.clone()),
                )?;
                let mut mesh = layout::mesh(&mut chart, style);
                mesh.x_labels(7)
                    .y_label_formatter(&|v| y_axis.label(*v))
                    .x_desc("B/H")
                    .draw()?;
                curve!(chart, reference(&eq8, y_lo), ref_style, Dash::Solid, style);
                curve!(
                    chart,
                    reference(&three_quarters, y_lo),
                    ref_style,
                    Dash::Dashed,
                    style
                );
                draw_series_set!(chart, series, style, x_max * REFERENCE_DODGE);
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::Block;
    use crate::solver::impact::rock_impact_mu;

    #[test]
    fn eq8_is_the_solvers_rock_impact_ratio_and_the_papers_values() {
        // The curve drawn is the solver's eq. (8), and it gives the paper's
        // e = 0 column (0.353, 0.185, 0.124) to the table's 3 digits.
        for (aspect, table) in [(2.0, 0.353), (4.0, 0.185), (6.0, 0.124)] {
            let block = Block::new(0.5, aspect, 9.81).unwrap();
            assert!((eq8(1.0 / aspect) - rock_impact_mu(&block)).abs() < 1e-12);
            assert!((eq8(1.0 / aspect) - table).abs() < 5e-4, "H/B = {aspect}");
        }
        // small-angle limit 0.75·B/H
        assert!((eq8(1e-4) / 1e-4 - 0.75).abs() < 1e-6);
    }

    #[test]
    fn eq5_panel_exists_when_the_column_does() {
        // With mu_impact_eq5 read, panel (c) has a series per e with this
        // study's mean of it; without the column (a file from before it),
        // no panel (c). No reference values unless a layer sets them.
        let row = |e: f64, eq5: Option<f64>| PlotRow {
            case: crate::case::Case::fixed(4.0, 0.5, e, Friction::Infinite),
            pga: 0.6,
            record: 0,
            overturned: false,
            uplifted: false,
            theta_max_over_theta_c: 0.5,
            mu_motion: 0.3,
            mu_impact: 0.4,
            impacts: 10,
            mu_impact_eq5: eq5,
        };
        let with = StudyData {
            outcomes: vec![row(0.0, Some(0.185)), row(0.9, Some(250.0))],
            curves: None,
            lognormal: Vec::new(),
            ..StudyData::default()
        };
        let f = FrictionDemandFigure::from_study(&with).unwrap();
        assert_eq!(f.eq5.len(), 2);
        assert_eq!(f.eq5[1].means, vec![(0.25, 250.0)]);
        assert_eq!(f.impact[1].means, vec![(0.25, 0.4)]);
        assert!(!f.has_reference());
        let without = StudyData {
            outcomes: vec![row(0.0, None), row(0.9, None)],
            curves: None,
            lognormal: Vec::new(),
            ..StudyData::default()
        };
        let f = FrictionDemandFigure::from_study(&without).unwrap();
        assert!(f.eq5.is_empty());
    }

    #[test]
    fn many_levels_are_thinned_to_spread_ones() {
        // Up to five levels are all drawn; otherwise four spread levels.
        let few = [0.3, 0.6, 0.9];
        assert_eq!(shown_levels(&few), few.to_vec());
        let odd: Vec<f64> = (1..=10).map(|k| k as f64 * 0.25).collect();
        assert_eq!(shown_levels(&odd), vec![0.25, 1.0, 1.75, 2.5]);
    }
}
