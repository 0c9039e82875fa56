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
//!
//! **The IM axis reaches the top of every curve.** `fragility_curves.csv`
//! samples each fit from 0 to the case's last stripe only, where a curve of
//! a stocky block may still be at P ≈ 0.6. The axis runs on to where every
//! fitted curve reaches P = 0.95 (θ·e^(1.645β)), but no further than
//! `CAP_STRIPES` × the last stripe; the title says how many curves are
//! still below 0.95 there ([`ShortCurves`]). Beyond the last stripe the
//! figure evaluates the fitted lognormal itself, from the θ and β of
//! `fragility.csv` (read with [`crate::fragility::read_fragility_csv`]), so
//! the curve files keep their grid (and every other reader of them its
//! numbers); the bootstrap band stops at the last stripe, where the data
//! stop (its legend entry says so). Without `fragility.csv` the curves end
//! where their file does, and the title counts those that stop below 0.95.
//!
//! **Friction that changes nothing is said, not hidden.** When a finite
//! friction model gives the same outcomes as μ = ∞ (a stocky block on a
//! grippy floor never slides), its dashed curve lies exactly on the solid
//! one and cannot be seen. A curve counts as the same when its observed
//! fractions are equal and its fitted curves differ by less than
//! [`SAME_CURVE_TOL`] everywhere: if that holds for every case, the legend
//! entry of the model says `(as μ = ∞)`; otherwise each panel names, at its
//! top left, the e values whose dashed curve is the solid one.

use crate::detmath as dm;
use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingBackend, Polygon, Text};
use plotters::style::{BLACK, Color};

use super::data::{
    StudyData, distinct, distinct_friction, distinct_numbers, friction_label, param_label, runs,
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
/// The probability every fitted curve should reach inside the IM axis.
pub const P_REACHED: f64 = 0.95;
/// The IM axis ends at most this many times the last stripe.
pub const CAP_STRIPES: f64 = 3.0;
/// Most points of a fitted curve's extension beyond the last stripe (it
/// is sampled at the spacing of the curve's file, `fragility_curves.csv`).
pub const EXTENSION_POINTS: usize = 100;
/// Largest difference in P between two fitted curves drawn as one.
pub const SAME_CURVE_TOL: f64 = 0.005;

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
    /// Each fit's θ and β (g), from `fragility.csv`, in the order of
    /// [`FragilitySeries::fits`] (`None` where the file has none).
    pub lognormal: Vec<Option<(f64, f64)>>,
    /// Each fit of [`FragilitySeries::fits`] continued beyond its last
    /// point to the axis end, (im, p) from its θ and β (empty where
    /// `fragility.csv` has none, or the fit already reaches the end).
    pub extension: Vec<Vec<(f64, f64)>>,
    /// Whether the series is a finite-friction one whose outcomes and fits
    /// are those of μ = ∞ with the same e (see the module docs).
    pub as_infinite: bool,
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
    /// Largest PGA or IM of the data: the last stripe, or the end of the
    /// curves' file (g).
    pub im_max: f64,
    /// End of the IM axis (g): where every fitted curve reaches
    /// `P_REACHED`, at most `CAP_STRIPES` × `im_max`.
    pub x_max: f64,
    /// Fitted curves still below `P_REACHED` at their end.
    pub short_of_reach: ShortCurves,
    /// For each friction model: whether every one of its series is drawn
    /// as μ = ∞ (its legend entry says so).
    pub as_infinite: Vec<bool>,
    /// The limit states with fitted curves, in order of severity (as
    /// `fragility_curves.csv` lists them); `["overturning"]` without fits.
    pub limit_states: Vec<String>,
    /// The IM axis's label ([`StudyData::pga_label`]).
    pub x_label: String,
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
        // the rows' cases in runs (they come sorted by case): the same
        // distinct values below as every row's, without a copy per row
        let cases: Vec<Case> = runs(cases, |a, b| a.total_cmp(b).is_eq());
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
                    let lognormal = limit_states
                        .iter()
                        .zip(&fits)
                        .map(|(ls, fit)| {
                            let l = data
                                .lognormal
                                .iter()
                                .find(|l| l.case == case && &l.limit_state == ls);
                            l.filter(|_| !fit.is_empty()).map(|l| (l.median, l.beta))
                        })
                        .collect();
                    series.push(FragilitySeries {
                        restitution: ie,
                        friction: jf,
                        extension: vec![Vec::new(); fits.len()],
                        fits,
                        observed,
                        lognormal,
                        as_infinite: false,
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
        let (x_max, short_of_reach) = extend(&mut panels, im_max);
        let as_infinite = mark_as_infinite(&mut panels, frictions.len());
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
        let title = std::iter::once(title)
            .chain(short_of_reach.clauses())
            .collect::<Vec<_>>()
            .join("; ");
        FragilityFigure {
            title,
            restitutions,
            frictions,
            fitted,
            panels,
            im_max,
            x_max,
            short_of_reach,
            as_infinite,
            limit_states,
            x_label: data.pga_label().to_string(),
        }
    }

    /// Notes at the top left of panel `k`: the e values whose
    /// finite-friction curve is drawn on the μ = ∞ one, by line pattern,
    /// for the friction models whose legend entry does not already say so.
    pub fn panel_notes(&self, k: usize) -> Vec<String> {
        let Some(panel) = self.panels.get(k) else {
            return Vec::new();
        };
        (1..self.frictions.len())
            .filter(|&j| !self.as_infinite[j])
            .filter_map(|j| {
                let es: Vec<String> = panel
                    .series
                    .iter()
                    .filter(|s| s.friction == j && s.as_infinite)
                    .map(|s| param_label(self.restitutions[s.restitution]))
                    .collect();
                let pattern = match Dash::nth(j) {
                    Dash::Solid => "solid",
                    Dash::Dashed => "dashed",
                    Dash::Short => "short-dashed",
                };
                (!es.is_empty()).then(|| format!("{pattern} = solid: e = {}", es.join(", ")))
            })
            .collect()
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
            let mut label = friction_label(f);
            if self.as_infinite.get(j).copied().unwrap_or(false) {
                label.push_str(" (as μ = ∞)");
            }
            entries.push(Entry::new(
                Sample::LinePoint(BLACK, Dash::nth(j), Marker::Circle, j == 0),
                label,
            ));
        }
        if self.fitted {
            let extended = self
                .panels
                .iter()
                .flat_map(|p| &p.series)
                .any(|s| s.extension.iter().any(|e| !e.is_empty()));
            entries.push(Entry::new(
                Sample::Block(layout::tint(BLACK, 1.0 - 1.5 * BAND_ALPHA)),
                if extended {
                    "90 % band, to the last stripe"
                } else {
                    "90 % band"
                },
            ));
        }
        entries
    }
}

/// Sets the axis end and continues the fitted curves to it: the axis ends
/// where every fitted curve reaches `P_REACHED` (by its θ and β, or else
/// by its sampled points), at least at `im_max` and at most
/// `CAP_STRIPES` × `im_max`; each curve with a θ and β is continued from
/// its last point to that end. Returns the end and the number of fitted
/// curves below `P_REACHED` at its end: those that would need more than
/// the cap, and those without a θ and β whose points stop short.
fn extend(panels: &mut [FragilityPanel], im_max: f64) -> (f64, ShortCurves) {
    let mut short = ShortCurves::default();
    if im_max <= 0.0 {
        return (1.0, short);
    }
    let cap = CAP_STRIPES * im_max;
    let mut reach = im_max;
    for s in panels.iter().flat_map(|p| &p.series) {
        for (fit, params) in s.fits.iter().zip(&s.lognormal) {
            if fit.is_empty() {
                continue;
            }
            let at = match params {
                Some(params) => Some(lognormal_intensity(*params, P_REACHED)),
                None => fit.iter().find(|p| p.1 >= P_REACHED).map(|p| p.0),
            };
            match at {
                Some(x) if x <= cap => reach = reach.max(x),
                Some(_) => {
                    reach = cap;
                    short.capped += 1;
                }
                None => short.unextended += 1,
            }
        }
    }
    let x_max = reach * 1.03;
    for s in panels.iter_mut().flat_map(|p| &mut p.series) {
        for k in 0..s.fits.len() {
            let (Some(last), Some(params)) = (s.fits[k].last(), s.lognormal[k]) else {
                continue;
            };
            let from = last.0;
            if from >= x_max {
                continue;
            }
            // at the spacing of the file's grid (points far closer than a
            // pixel draw as a saw), at most EXTENSION_POINTS
            let fit = &s.fits[k];
            let step = match fit.len() {
                n if n >= 2 => fit[n - 1].0 - fit[n - 2].0,
                _ => 0.0,
            };
            let n = if step > 0.0 {
                ((x_max - from) / step)
                    .ceil()
                    .clamp(2.0, EXTENSION_POINTS as f64) as usize
            } else {
                EXTENSION_POINTS
            };
            s.extension[k] = (1..=n)
                .map(|i| {
                    let x = from + (x_max - from) * i as f64 / n as f64;
                    (x, lognormal_probability(params, x))
                })
                .collect();
        }
    }
    (x_max, short)
}

/// Fitted curves that end below `P_REACHED`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ShortCurves {
    /// Would reach it beyond `CAP_STRIPES` × the last stripe, where the
    /// axis stops.
    pub capped: usize,
    /// Have no θ and β in `fragility.csv` to be continued with, and stop
    /// below it where `fragility_curves.csv` stops.
    pub unextended: usize,
}

impl ShortCurves {
    /// The clauses the title adds, e.g. `2 curves below P = 0.95 at the
    /// axis end (3 × the last stripe)`.
    fn clauses(self) -> Vec<String> {
        let curves = |n: usize| format!("{n} curve{}", if n == 1 { "" } else { "s" });
        let mut v = Vec::new();
        if self.capped > 0 {
            v.push(format!(
                "{} below P = {P_REACHED} at the axis end ({CAP_STRIPES} × the last stripe)",
                curves(self.capped)
            ));
        }
        if self.unextended > 0 {
            v.push(format!(
                "{} end below P = {P_REACHED} (no θ, β in fragility.csv)",
                curves(self.unextended)
            ));
        }
        v
    }
}

/// P(im) = Φ(ln(im/θ)/β) of the lognormal curve (θ, β); 0 at im ≤ 0.
pub fn lognormal_probability((median, beta): (f64, f64), im: f64) -> f64 {
    if im <= 0.0 {
        0.0
    } else {
        dm::norm_cdf(dm::ln(im / median) / beta)
    }
}

/// The intensity at which the lognormal curve (θ, β) reaches P = `p`:
/// θ·exp(β·Φ⁻¹(p)).
pub fn lognormal_intensity((median, beta): (f64, f64), p: f64) -> f64 {
    median * dm::exp(beta * dm::norm_inv_cdf(p))
}

/// Marks the finite-friction series drawn on their μ = ∞ twin (same
/// panel and e): equal observed fractions and fitted curves within
/// [`SAME_CURVE_TOL`]. Returns, per friction model, whether all its series
/// are (false for μ = ∞ itself and for a model without series).
fn mark_as_infinite(panels: &mut [FragilityPanel], n_frictions: usize) -> Vec<bool> {
    let same_fit = |a: &[(f64, f64, f64, f64)], b: &[(f64, f64, f64, f64)]| {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(p, q)| p.0 == q.0 && (p.1 - q.1).abs() <= SAME_CURVE_TOL)
    };
    // μ = ∞ (index 0) is never "as μ = ∞"
    let mut all: Vec<bool> = (0..n_frictions).map(|j| j > 0).collect();
    let mut any = vec![false; n_frictions];
    for panel in panels.iter_mut() {
        let twins: Vec<bool> = panel
            .series
            .iter()
            .map(|s| {
                s.friction > 0
                    && panel.series.iter().any(|t| {
                        t.friction == 0
                            && t.restitution == s.restitution
                            && t.observed.len() == s.observed.len()
                            && t.observed
                                .iter()
                                .zip(&s.observed)
                                .all(|(a, b)| a.0 == b.0 && a.1 == b.1)
                            && t.fits.len() == s.fits.len()
                            && t.fits.iter().zip(&s.fits).all(|(a, b)| same_fit(a, b))
                    })
            })
            .collect();
        for (s, twin) in panel.series.iter_mut().zip(twins) {
            s.as_infinite = twin;
            if s.friction > 0 {
                any[s.friction] = true;
                all[s.friction] &= twin;
            }
        }
    }
    all.iter().zip(&any).map(|(a, b)| *a && *b).collect()
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
    let cmp = |a: &(Param<f64>, Param<f64>), b: &(Param<f64>, Param<f64>)| {
        a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1))
    };
    let mut v = runs(cases.iter().map(|c| (c.aspect, c.width)), |a, b| {
        cmp(a, b).is_eq()
    });
    v.sort_by(cmp);
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
        let x_max = if self.x_max > 0.0 { self.x_max } else { 1.0 };
        for (k_panel, (panel, area)) in self.panels.iter().zip(&areas).enumerate() {
            frame.heading(area, &panel.label)?;
            let mut chart = frame
                .chart(area, true)
                .build_cartesian_2d(0.0..x_max, 0.0..1.0)?;
            let mut mesh = layout::mesh(&mut chart, style);
            mesh.x_labels(6)
                .y_labels(6)
                .x_desc(self.x_label.as_str())
                .draw()?;

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
            let unfitted = self.fitted
                && panel
                    .series
                    .iter()
                    .all(|s| s.fits.iter().all(Vec::is_empty));
            if unfitted {
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
                        let points: Vec<(f64, f64)> = fit
                            .iter()
                            .map(|p| (p.0, p.1))
                            .chain(s.extension[k].iter().copied())
                            .collect();
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
            // which curves hide under the solid ones, at the top left (below
            // the no-fit lines, if any)
            let font = style.tick_font();
            let below = if unfitted { 2 } else { 0 };
            for (k, line) in self.panel_notes(k_panel).iter().enumerate() {
                chart.draw_series(std::iter::once(Text::new(
                    line.clone(),
                    (0.04 * x_max, 0.93 - 0.09 * (k + below) as f64),
                    font.clone(),
                )))?;
            }
        }
        Ok(())
    }
}
