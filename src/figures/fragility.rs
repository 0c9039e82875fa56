//! Fragility curves: probability of overturning against PGA, one panel per
//! block (aspect ratio, and width when a study has several), one colour per
//! coefficient of restitution, one line pattern per friction model (infinite
//! friction solid, the first Coulomb model dashed, a second short-dashed),
//! the fitted curve over its 90 % band, and the observed fraction of each
//! PGA stripe as points (filled for infinite friction, open otherwise).
//!
//! Without fitted curves (no `fragility_curves.csv`) the observed fractions
//! are joined by straight lines and the title says so. A study fitted for
//! several limit states draws every limit state of a case, each with its
//! band, in the case's colour: the most severe in full colour, the milder
//! ones lighter tints of it (a legend row names them, light to dark); the
//! points stay the observed overturning fractions.
//!
//! A parameter drawn per analysis (`[uncertainty]`) reads `drawn` in the
//! legend or heading: its case pools every draw.

use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingBackend, Polygon, Text};
use plotters::style::{BLACK, Color};

use super::data::{
    StudyData, distinct, distinct_friction, distinct_numbers, friction_label, param_label,
};
use super::figure::{DrawResult, Figure};
use super::layout::{self, Dash, Entry, Frame, Margins, Marker, Sample, curve, markers};
use super::style::{PAGE_WIDTH_IN, Style};
use crate::case::{Case, Param};
use crate::solver::Friction;

/// Figure height (in), before legend rows beyond the first.
const HEIGHT_IN: f64 = 2.9;
/// Panel margins: 24 pt for the y tick labels, 8 pt on the right.
const MARGINS: Margins = Margins::new(24.0, 8.0);
/// Opacity of the confidence bands.
const BAND_ALPHA: f64 = 0.14;

/// One curve: a case's fit (if any) and its observed stripe fractions.
#[derive(Clone, Debug, PartialEq)]
pub struct FragilitySeries {
    /// Index into [`FragilityFigure::restitutions`] (sets the colour).
    pub restitution: usize,
    /// Index into [`FragilityFigure::frictions`] (sets the pattern).
    pub friction: usize,
    /// Fitted curves (im, p, p_lo, p_hi), IM ascending, one per limit state
    /// of [`FragilityFigure::limit_states`] in its order (empty where that
    /// limit state has no fit).
    pub fits: Vec<Vec<(f64, f64, f64, f64)>>,
    /// Observed stripes (pga, fraction overturned, analyses).
    pub observed: Vec<(f64, f64, usize)>,
}

/// One panel: one block.
#[derive(Clone, Debug, PartialEq)]
pub struct FragilityPanel {
    /// Heading, e.g. `H/B = 4`.
    pub label: String,
    /// Its series, by restitution then friction.
    pub series: Vec<FragilitySeries>,
}

/// The fragility figure's data.
#[derive(Clone, Debug, PartialEq)]
pub struct FragilityFigure {
    /// Title.
    pub title: String,
    /// Restitution values, ascending (drawn last).
    pub restitutions: Vec<Param<f64>>,
    /// Friction models, infinite first (drawn last).
    pub frictions: Vec<Param<Friction>>,
    /// Whether fitted curves were available.
    pub fitted: bool,
    /// Panels, by aspect ratio then width.
    pub panels: Vec<FragilityPanel>,
    /// Largest PGA or IM shown (g).
    pub im_max: f64,
    /// The limit states with fitted curves, in order of severity (as
    /// `fragility_curves.csv` lists them); `["overturning"]` without fits.
    pub limit_states: Vec<String>,
}

impl FragilityFigure {
    /// Groups the study's outcomes (and fits, if any) into panels and series.
    pub fn from_study(data: &StudyData) -> FragilityFigure {
        let rows = &data.outcomes;
        let curves = data.curves.as_deref().unwrap_or(&[]);
        let cases = rows
            .iter()
            .map(|r| r.case)
            .chain(curves.iter().map(|c| c.case));
        let cases: Vec<Case> = cases.collect();
        let restitutions = distinct(cases.iter().map(|c| c.restitution));
        let frictions = distinct_friction(cases.iter().map(|c| c.friction));
        let blocks = distinct_blocks(&cases);
        let several_widths = distinct(cases.iter().map(|c| c.width)).len() > 1;
        // In order of first appearance: the file lists a case's limit
        // states in order of severity.
        let mut limit_states: Vec<String> = Vec::new();
        for c in curves {
            if !limit_states.contains(&c.limit_state) {
                limit_states.push(c.limit_state.clone());
            }
        }
        if limit_states.is_empty() {
            limit_states.push("overturning".to_string());
        }
        let mut im_max = 0.0_f64;
        let mut panels = Vec::new();
        for &(aspect, width) in &blocks {
            let mut series = Vec::new();
            for (ie, &e) in restitutions.iter().enumerate() {
                for (jf, f) in frictions.iter().enumerate() {
                    let case = Case {
                        aspect,
                        width,
                        restitution: e,
                        friction: *f,
                    };
                    let fits: Vec<Vec<(f64, f64, f64, f64)>> = limit_states
                        .iter()
                        .map(|ls| {
                            curves
                                .iter()
                                .filter(|c| c.case == case && &c.limit_state == ls)
                                .map(|c| (c.im, c.p, c.p_lo, c.p_hi))
                                .collect()
                        })
                        .collect();
                    let mine: Vec<_> = rows.iter().filter(|r| r.case == case).collect();
                    let observed: Vec<(f64, f64, usize)> =
                        distinct_numbers(mine.iter().map(|r| r.pga))
                            .into_iter()
                            .map(|pga| {
                                let at: Vec<_> = mine.iter().filter(|r| r.pga == pga).collect();
                                let k = at.iter().filter(|r| r.overturned).count();
                                (pga, k as f64 / at.len() as f64, at.len())
                            })
                            .collect();
                    if fits.iter().all(Vec::is_empty) && observed.is_empty() {
                        continue;
                    }
                    im_max = fits
                        .iter()
                        .flatten()
                        .map(|p| p.0)
                        .chain(observed.iter().map(|o| o.0))
                        .fold(im_max, f64::max);
                    series.push(FragilitySeries {
                        restitution: ie,
                        friction: jf,
                        fits,
                        observed,
                    });
                }
            }
            let mut label = format!("H/B = {}", param_label(aspect));
            if several_widths || width.is_drawn() {
                label.push_str(&format!(", 2B = {}", param_label(width)));
                if !width.is_drawn() {
                    label.push_str(" m");
                }
            }
            panels.push(FragilityPanel { label, series });
        }
        let fitted = data.curves.is_some();
        let title = if fitted && limit_states.len() > 1 {
            format!(
                "Fragility: {} (light to dark) with 90 % bands; observed overturning (points)",
                limit_states.join(", ")
            )
        } else if fitted {
            "Fragility: fitted curves with 90 % band (lines), observed stripe fractions (points)"
                .to_string()
        } else {
            "Observed overturning fractions per PGA stripe (no fragility_curves.csv: no fits)"
                .to_string()
        };
        FragilityFigure {
            title,
            restitutions,
            frictions,
            fitted,
            panels,
            im_max,
            limit_states,
        }
    }

    /// The legend: colours for e, patterns and markers for friction.
    fn legend(&self) -> Vec<Entry> {
        let mut entries: Vec<Entry> = self
            .restitutions
            .iter()
            .enumerate()
            .map(|(i, e)| {
                Entry::new(
                    Sample::Line(restitution_colour(i), Dash::Solid),
                    format!("e = {}", param_label(*e)),
                )
            })
            .collect();
        if self.fitted && self.limit_states.len() > 1 {
            let n = self.limit_states.len();
            for (k, ls) in self.limit_states.iter().enumerate() {
                entries.push(Entry::new(
                    Sample::Line(layout::tint(BLACK, severity_tint(k, n)), Dash::Solid),
                    ls.clone(),
                ));
            }
        }
        for (j, f) in self.frictions.iter().enumerate() {
            entries.push(Entry::new(
                Sample::LinePoint(BLACK, Dash::nth(j), Marker::Circle, j == 0),
                friction_label(f),
            ));
        }
        if self.fitted {
            entries.push(Entry::new(
                Sample::Block(layout::tint(BLACK, 1.0 - 1.5 * BAND_ALPHA)),
                "90 % band",
            ));
        }
        entries
    }
}

/// How much lighter than its case's colour limit state `k` of `n` (in order
/// of severity) is drawn: the most severe not at all, the mildest 0.6.
fn severity_tint(k: usize, n: usize) -> f64 {
    if n < 2 {
        0.0
    } else {
        0.6 * (n - 1 - k) as f64 / (n - 1) as f64
    }
}

/// Colour of the `i`-th restitution value.
pub fn restitution_colour(i: usize) -> plotters::style::RGBColor {
    super::style::PALETTE[i % super::style::PALETTE.len()]
}

/// The distinct (aspect, width) pairs, sorted (drawn last).
pub(crate) fn distinct_blocks(cases: &[Case]) -> Vec<(Param<f64>, Param<f64>)> {
    let mut v: Vec<(Param<f64>, Param<f64>)> = cases.iter().map(|c| (c.aspect, c.width)).collect();
    v.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    v.dedup();
    v
}

impl Figure for FragilityFigure {
    fn size_in(&self) -> (f64, f64) {
        (PAGE_WIDTH_IN, HEIGHT_IN)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB> {
        let frame = Frame::new(root, style, &self.title, &self.legend(), MARGINS)?;
        let n = self.panels.len().max(1);
        let body = layout::side_label(
            &frame.body,
            style,
            if self.limit_states.len() > 1 {
                "P(exceeded)"
            } else {
                "P(overturning)"
            },
            frame.top,
            frame.x_area,
        )?;
        let areas = body.split_evenly((1, n));
        let x_max = if self.im_max > 0.0 { self.im_max } else { 1.0 };
        for (panel, area) in self.panels.iter().zip(&areas) {
            frame.heading(area, &panel.label)?;
            let mut chart = frame
                .chart(area, true)
                .build_cartesian_2d(0.0..x_max * 1.03, 0.0..1.0)?;
            let mut mesh = layout::mesh(&mut chart, style);
            mesh.x_labels(6).y_labels(6).x_desc("PGA (g)").draw()?;

            let n_ls = self.limit_states.len();
            for s in &panel.series {
                for (k, fit) in s.fits.iter().enumerate() {
                    if fit.is_empty() {
                        continue;
                    }
                    let colour =
                        layout::tint(restitution_colour(s.restitution), severity_tint(k, n_ls));
                    let mut outline: Vec<(f64, f64)> = fit.iter().map(|p| (p.0, p.3)).collect();
                    outline.extend(fit.iter().rev().map(|p| (p.0, p.2)));
                    chart.draw_series(std::iter::once(Polygon::new(
                        outline,
                        colour.mix(BAND_ALPHA).filled(),
                    )))?;
                }
            }
            if self.fitted
                && panel
                    .series
                    .iter()
                    .all(|s| s.fits.iter().all(Vec::is_empty))
            {
                // a block none of whose cases could be fitted (all or none
                // overturned, or stripes separated): say so in the panel
                let font = style.tick_font();
                for (k, line) in ["no lognormal fit", "(fragility.csv says why)"]
                    .iter()
                    .enumerate()
                {
                    chart.draw_series(std::iter::once(Text::new(
                        *line,
                        (0.04 * x_max, 0.93 - 0.09 * k as f64),
                        font.clone(),
                    )))?;
                }
            }
            // all solid series first, then the dashed ones: a dashed series
            // is a run of consecutive polylines of one colour
            let mut order: Vec<&FragilitySeries> = panel.series.iter().collect();
            order.sort_by_key(|s| (s.friction, s.restitution));
            for s in &order {
                let line_pt = style.ipx(super::style::LINE_PT);
                if self.fitted {
                    for (k, fit) in s.fits.iter().enumerate() {
                        let colour =
                            layout::tint(restitution_colour(s.restitution), severity_tint(k, n_ls));
                        let points: Vec<(f64, f64)> = fit.iter().map(|p| (p.0, p.1)).collect();
                        if !points.is_empty() {
                            let line = colour.stroke_width(line_pt);
                            curve!(chart, points, line, Dash::nth(s.friction), style);
                        }
                    }
                } else {
                    let line = restitution_colour(s.restitution).stroke_width(line_pt);
                    let points: Vec<(f64, f64)> = s.observed.iter().map(|o| (o.0, o.1)).collect();
                    curve!(chart, points, line, Dash::nth(s.friction), style);
                }
            }
            // hollow (finite friction) markers first: a filled one on top
            // at the same place leaves a ring showing both
            for s in order.iter().rev() {
                let colour = restitution_colour(s.restitution);
                markers!(
                    chart,
                    s.observed.iter().map(|o| (o.0, o.1)),
                    colour,
                    Marker::Circle,
                    s.friction == 0,
                    style
                );
            }
        }
        Ok(())
    }
}
