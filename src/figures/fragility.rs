//! Fragility curves: probability of exceeding each limit state against
//! PGA, one panel per block (aspect ratio, and width when a study has
//! several), one colour per coefficient of restitution, one line pattern per
//! friction model (infinite friction solid, the first Coulomb model dashed,
//! a second short-dashed), the fitted curves over their 90 % bands, and the
//! observed fraction of each PGA stripe as points (filled for infinite
//! friction, open otherwise).
//!
//! Without fitted curves (no `fragility_curves.csv`) the observed
//! overturning fractions are joined by straight lines and the title says
//! so. A study fitted for several limit states draws every limit state of a
//! case, each with its band and its observed fractions, in the case's
//! colour: the most severe in full colour, the milder ones lighter tints of
//! it (a legend row names them, light to dark, in the case's colour when
//! the figure has one). A limit state's points are the fractions the fit
//! counted, from the definitions of the study's `[fragility]`
//! ([`StudyData::load_study`]); a limit state refitted with other
//! definitions than the spec's has none.
//!
//! A parameter drawn per analysis (`[uncertainty]`) is named with its
//! distribution in the legend or heading (`e ~ U(0.2, 0.6), drawn per
//! analysis`): its case pools every draw.
//!
//! **Inside the stripes, and beyond.** A fit rests on the stripes of its
//! case: below the lowest and above the highest it is the lognormal's
//! extrapolation (a median above the strongest stripe is one). That part of
//! every curve is drawn dotted, in a lighter tint of its colour (a legend
//! entry says so), and the bands are drawn over the stripes only. The IM axis runs
//! on to where every fitted curve reaches P = 0.95 (θ·e^(1.645β)), but no
//! further than [`CAP_STRIPES`] × the last stripe; the title says how many
//! curves are still below 0.95 there ([`ShortCurves`]). Beyond the last
//! stripe the figure evaluates the fitted lognormal itself, from the θ and
//! β of `fragility.csv` (read with [`crate::fragility::read_fragility_csv`]),
//! so the curve files keep their grid (and every other reader of them its
//! numbers). Without `fragility.csv` the curves end where their file does,
//! and the title counts those that stop below 0.95.
//!
//! **Bands that stay readable.** A band per curve is drawn while a panel
//! has at most [`MAX_BANDED`] distinct curves per limit state; beyond that,
//! overlapping bands of four colours make a grey mud, and each curve's
//! uncertainty is shown instead as the 90 % band of its median θ (from
//! `fragility.csv`), a bar at P = 0.5 in the curve's colour, the bars of a
//! panel stacked a little apart so that none hides another.
//!
//! **Friction that changes nothing is said, not hidden.** When a finite
//! friction model gives the same outcomes as μ = ∞ (a stocky block on a
//! grippy floor never slides), its dashed curve lies exactly on the solid
//! one and cannot be seen. A curve counts as the same when its observed
//! fractions are equal and its fitted curves differ by less than
//! [`SAME_CURVE_TOL`] everywhere: if that holds for every case, the legend
//! entry of the model says `(as μ = ∞)`; otherwise each panel names, at its
//! top left, the e values whose dashed curve is the solid one. A curve drawn
//! on its twin gets no band (or bar) of its own.
//!
//! A study of one block draws its one panel a journal column wide.

use crate::detmath as dm;
use plotters::coord::Shift;
use plotters::prelude::{
    Circle, DrawingArea, DrawingBackend, EmptyElement, PathElement, Polygon, Text,
};
use plotters::style::{BLACK, Color, RGBColor};

use super::data::{
    StudyData, distinct, distinct_friction, drawn_label, friction_label, param_label, runs,
    same_stripe, stripes,
};
use super::figure::{DrawResult, Figure};
use super::layout::{
    self, Dash, Entry, Frame, HOLLOW_FILL, Margins, Marker, Sample, curve, marker_px, marker_style,
    markers,
};
use super::style::{COLUMN_WIDTH_IN, PAGE_WIDTH_IN, Style};
use crate::case::{Case, Field, Param};
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
pub const CAP_STRIPES: f64 = 1.5;
/// Most points of a fitted curve's extension beyond the last stripe (it
/// is sampled at the spacing of the curve's file, `fragility_curves.csv`).
pub const EXTENSION_POINTS: usize = 100;
/// Largest difference in P between two fitted curves drawn as one.
pub const SAME_CURVE_TOL: f64 = 0.005;
/// Most distinct curves of one limit state in a panel drawn with bands;
/// a panel with more shows the bands of the medians as bars.
pub const MAX_BANDED: usize = 2;
/// How much lighter (towards white) the extrapolated part of a curve is;
/// it is dotted, too.
pub const EXTRAPOLATED_TINT: f64 = 0.3;
/// Vertical spacing of the median bars of one panel (in P).
const BAR_STEP: f64 = 0.03;
/// Thickness of a median bar (pt).
const BAR_PT: f64 = 1.3;

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
    /// Observed stripes (pga, fraction exceeding, analyses), one list per
    /// limit state in the order of [`FragilitySeries::fits`] (empty where
    /// the limit state's counts are not known).
    pub observed: Vec<Vec<(f64, f64, usize)>>,
    /// The lowest and highest stripe of the case: where its fits rest on
    /// data (`None` without stripes).
    pub stripe_range: Option<(f64, f64)>,
    /// Each fit's θ and β (g), from `fragility.csv`, in the order of
    /// [`FragilitySeries::fits`] (`None` where the file has none).
    pub lognormal: Vec<Option<(f64, f64)>>,
    /// Each fit's bootstrap band of θ (g), from `fragility.csv`.
    pub median_band: Vec<Option<(f64, f64)>>,
    /// Each fit of [`FragilitySeries::fits`] continued beyond its last
    /// point to the axis end, (im, p) from its θ and β (empty where
    /// `fragility.csv` has none, or the fit already reaches the end).
    pub extension: Vec<Vec<(f64, f64)>>,
    /// Whether the series is a finite-friction one whose outcomes and fits
    /// are those of μ = ∞ with the same e (see the module docs).
    pub as_infinite: bool,
}

impl FragilitySeries {
    /// Limit state `k`'s fitted curve and its extension, (im, p), split at
    /// the stripes' range: (below the lowest stripe, over the stripes,
    /// above the highest), each part sharing its end point with the next.
    pub fn curve_parts(&self, k: usize) -> [Vec<(f64, f64)>; 3] {
        let points: Vec<(f64, f64)> = self.fits[k]
            .iter()
            .map(|p| (p.0, p.1))
            .chain(self.extension[k].iter().copied())
            .collect();
        let Some((lo, hi)) = self.stripe_range else {
            return [Vec::new(), points, Vec::new()];
        };
        let at = |x: f64| interpolate(&points, x);
        let inside = |x: f64| x >= lo && x <= hi;
        let mut below: Vec<(f64, f64)> = points.iter().copied().filter(|p| p.0 < lo).collect();
        let mut middle: Vec<(f64, f64)> = points.iter().copied().filter(|p| inside(p.0)).collect();
        let mut above: Vec<(f64, f64)> = points.iter().copied().filter(|p| p.0 > hi).collect();
        if points.first().is_some_and(|p| p.0 < lo) && points.last().is_some_and(|p| p.0 >= lo) {
            let joint = (lo, at(lo));
            below.push(joint);
            if middle.first().is_none_or(|p| p.0 > lo) {
                middle.insert(0, joint);
            }
        }
        if points.last().is_some_and(|p| p.0 > hi) && points.first().is_some_and(|p| p.0 <= hi) {
            let joint = (hi, at(hi));
            above.insert(0, joint);
            if middle.last().is_none_or(|p| p.0 < hi) {
                middle.push(joint);
            }
        }
        [below, middle, above]
    }

    /// Limit state `k`'s band over the stripes: (im, p_lo, p_hi).
    pub fn band(&self, k: usize) -> Vec<(f64, f64, f64)> {
        let (lo, hi) = self
            .stripe_range
            .unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
        self.fits[k]
            .iter()
            .filter(|p| p.0 >= lo && p.0 <= hi)
            .map(|p| (p.0, p.2, p.3))
            .collect()
    }
}

/// Linear interpolation of (x, y) points, x ascending, at `x` (clamped to
/// the ends).
fn interpolate(points: &[(f64, f64)], x: f64) -> f64 {
    let i = points.partition_point(|p| p.0 <= x);
    match i {
        0 => points.first().map_or(0.0, |p| p.1),
        i if i >= points.len() => points[points.len() - 1].1,
        i => {
            let (a, b) = (points[i - 1], points[i]);
            a.1 + (b.1 - a.1) * (x - a.0) / (b.0 - a.0)
        }
    }
}

/// One panel: one block.
#[derive(Clone, Debug, PartialEq)]
pub struct FragilityPanel {
    /// Heading, e.g. `H/B = 4`.
    pub label: String,
    /// Its series, by restitution then friction.
    pub series: Vec<FragilitySeries>,
    /// Whether its curves' uncertainty is drawn as bars of the medians'
    /// bands instead of bands (more than [`MAX_BANDED`] distinct curves).
    pub median_bars: bool,
}

/// Ratio of the most to the fewest analyses of the drawn stripes from
/// which points are drawn with their area proportional to their analyses
/// (a fixed grid's stripes differ only by a few failed analyses).
pub const SIZED_STRIPES: usize = 2;

/// Radius (px) of the point of a stripe of `n` analyses when the largest
/// has `n_max` and a full point is `r` px: area ∝ analyses, never below
/// 2 px so that the smallest still shows.
pub fn sized_radius(r: i32, n: usize, n_max: usize) -> i32 {
    let share = n as f64 / n_max.max(1) as f64;
    ((r as f64 * share.sqrt()).round() as i32).max(2)
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
    /// The IM axis's label: the fit's IM ([`StudyData::curve_im`]).
    pub x_label: String,
    /// The fewest and most analyses of a drawn stripe when they differ by
    /// [`SIZED_STRIPES`] or more (an adaptive run's stripes hold 5 to
    /// hundreds): the points' area is then proportional to their analyses,
    /// so a stripe of 5 does not look like one of 200. `None`: one size.
    pub sized: Option<(usize, usize)>,
    /// The legend's text of a drawn e (`e ~ U(0.2, 0.6), drawn per
    /// analysis`), when the study draws it.
    pub drawn_restitution: Option<String>,
    /// The legend's text of drawn friction, when the study draws it (`μₛ ~
    /// LN(0.5, 0.15), μₖ/μₛ ~ U(0.75, 0.95)`, and `drawn per analysis` when
    /// e is not drawn).
    pub drawn_friction: Option<String>,
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
        let study = data.study.as_ref();
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
                        stack: None,
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
                    let levels = stripes(mine.iter().map(|r| r.pga));
                    // the overturning fractions from the rows themselves
                    let overturned: Vec<(f64, f64, usize)> = levels
                        .iter()
                        .map(|&pga| {
                            let at: Vec<_> =
                                mine.iter().filter(|r| same_stripe(r.pga, pga)).collect();
                            let k = at.iter().filter(|r| r.overturned).count();
                            (pga, k as f64 / at.len() as f64, at.len())
                        })
                        .collect();
                    let observed: Vec<Vec<(f64, f64, usize)>> = limit_states
                        .iter()
                        .map(|ls| {
                            let counted: Vec<(f64, f64, usize)> = data
                                .observed
                                .iter()
                                .filter(|o| o.case == case && &o.limit_state == ls)
                                .map(|o| (o.im, o.exceeded as f64 / o.trials as f64, o.trials))
                                .collect();
                            if !counted.is_empty() {
                                counted
                            } else if ls == "overturning"
                                && !data.observed.iter().any(|o| &o.limit_state == ls)
                            {
                                // no spec's definition to count by: the name says it
                                overturned.clone()
                            } else {
                                Vec::new()
                            }
                        })
                        .collect();
                    let observed = if curves.is_empty() {
                        vec![overturned]
                    } else {
                        observed
                    };
                    if fits.iter().all(Vec::is_empty) && observed.iter().all(Vec::is_empty) {
                        continue;
                    }
                    im_max = fits
                        .iter()
                        .flatten()
                        .map(|p| p.0)
                        .chain(levels.iter().copied())
                        .fold(im_max, f64::max);
                    let fitted = |ls: &String, fit: &Vec<(f64, f64, f64, f64)>| {
                        data.lognormal
                            .iter()
                            .find(|l| l.case == case && &l.limit_state == ls)
                            .filter(|_| !fit.is_empty())
                    };
                    let lognormal = limit_states
                        .iter()
                        .zip(&fits)
                        .map(|(ls, fit)| fitted(ls, fit).map(|l| (l.median, l.beta)))
                        .collect();
                    let median_band = limit_states
                        .iter()
                        .zip(&fits)
                        .map(|(ls, fit)| fitted(ls, fit).and_then(|l| l.median_band))
                        .collect();
                    series.push(FragilitySeries {
                        restitution: ie,
                        friction: jf,
                        extension: vec![Vec::new(); fits.len()],
                        fits,
                        observed,
                        stripe_range: levels.first().zip(levels.last()).map(|(a, b)| (*a, *b)),
                        lognormal,
                        median_band,
                        as_infinite: false,
                    });
                }
            }
            let mut label = match drawn_label(study, Field::Aspect).filter(|_| aspect.is_drawn()) {
                Some(d) => d,
                None => format!("H/B = {}", param_label(aspect)),
            };
            if several_widths || width.is_drawn() {
                match drawn_label(study, Field::Width).filter(|_| width.is_drawn()) {
                    Some(d) => label.push_str(&format!(", {d}")),
                    None => {
                        label.push_str(&format!(", 2B = {}", param_label(width)));
                        if !width.is_drawn() {
                            label.push_str(" m");
                        }
                    }
                }
            }
            panels.push(FragilityPanel {
                label,
                series,
                median_bars: false,
            });
        }
        let fitted = data.curves.is_some();
        let as_infinite = mark_as_infinite(&mut panels, frictions.len());
        let (x_max, short_of_reach) = extend(&mut panels, im_max);
        for panel in &mut panels {
            let distinct = panel
                .series
                .iter()
                .filter(|s| !s.as_infinite && s.fits.iter().any(|f| !f.is_empty()))
                .count();
            // bars need every curve's band of θ (from fragility.csv)
            let bands_known = panel.series.iter().filter(|s| !s.as_infinite).all(|s| {
                (0..s.fits.len()).all(|k| s.fits[k].is_empty() || s.median_band[k].is_some())
            });
            panel.median_bars = distinct > MAX_BANDED && bands_known;
        }
        let title = if fitted && limit_states.len() > 1 {
            format!(
                "Fragility: {} (light to dark); observed fractions (points)",
                limit_states.join(", ")
            )
        } else if fitted {
            "Fragility: fitted curves (lines), observed stripe fractions (points)".to_string()
        } else {
            "Observed overturning fractions per PGA stripe (no fragility_curves.csv: no fits)"
                .to_string()
        };
        let counts = panels
            .iter()
            .flat_map(|p| &p.series)
            .flat_map(|s| s.observed.iter().flatten())
            .map(|o| o.2)
            .filter(|&n| n > 0);
        let (fewest, most) = counts.fold((usize::MAX, 0), |(lo, hi), n| (lo.min(n), hi.max(n)));
        let sized = (most > 0 && most >= SIZED_STRIPES * fewest).then_some((fewest, most));
        let title = std::iter::once(title)
            .chain(short_of_reach.clauses())
            .chain(sized.map(|(lo, hi)| format!("point area ∝ analyses ({lo} to {hi})")))
            .collect::<Vec<_>>()
            .join("; ");
        // "drawn per analysis" once, on the first drawn entry of the legend
        let drawn_restitution =
            drawn_label(study, Field::Restitution).map(|d| format!("{d}, drawn per analysis"));
        let drawn_friction = drawn_label(study, Field::Friction).map(|d| match drawn_restitution {
            Some(_) => d,
            None => format!("{d}, drawn per analysis"),
        });
        FragilityFigure {
            title,
            drawn_restitution,
            drawn_friction,
            restitutions,
            frictions,
            fitted,
            panels,
            im_max,
            x_max,
            short_of_reach,
            as_infinite,
            limit_states,
            x_label: data.curve_im().axis_label(),
            sized,
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
                    Dash::Short | Dash::Dotted => "short-dashed",
                };
                (!es.is_empty()).then(|| format!("{pattern} = solid: e = {}", es.join(", ")))
            })
            .collect()
    }

    /// The colour of the legend's samples that stand for no one case: the
    /// case's colour when the figure has one e, else black.
    fn neutral(&self) -> RGBColor {
        if self.restitutions.len() == 1 {
            restitution_colour(0)
        } else {
            BLACK
        }
    }

    /// Whether any curve is drawn outside its stripes.
    pub fn extrapolates(&self) -> bool {
        self.fitted
            && self.panels.iter().flat_map(|p| &p.series).any(|s| {
                (0..s.fits.len()).any(|k| {
                    let [below, _, above] = s.curve_parts(k);
                    below.len() > 1 || above.len() > 1
                })
            })
    }

    /// The legend: colours for e, tints for limit states, patterns and
    /// markers for friction, then the bands and the extrapolation.
    pub fn legend(&self) -> Vec<Entry> {
        let neutral = self.neutral();
        let mut entries: Vec<Entry> = self
            .restitutions
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let label = match (&self.drawn_restitution, e) {
                    (Some(d), Param::Drawn) => d.clone(),
                    _ => format!("e = {}", param_label(*e)),
                };
                Entry::new(Sample::Line(restitution_colour(i), Dash::Solid), label)
            })
            .collect();
        if self.fitted && self.limit_states.len() > 1 {
            let n = self.limit_states.len();
            for (k, ls) in self.limit_states.iter().enumerate() {
                entries.push(Entry::new(
                    Sample::Line(layout::tint(neutral, severity_tint(k, n)), Dash::Solid),
                    ls.clone(),
                ));
            }
        }
        for (j, f) in self.frictions.iter().enumerate() {
            let mut label = match (&self.drawn_friction, f) {
                (Some(d), Param::Drawn) => d.clone(),
                _ => friction_label(f),
            };
            if self.as_infinite.get(j).copied().unwrap_or(false) {
                label.push_str(" (as μ = ∞)");
            }
            entries.push(Entry::new(
                Sample::LinePoint(neutral, Dash::nth(j), Marker::Circle, j == 0),
                label,
            ));
        }
        if self.fitted {
            if self.panels.iter().any(|p| !p.median_bars) {
                entries.push(Entry::new(
                    Sample::Block(layout::tint(neutral, 1.0 - 1.5 * BAND_ALPHA)),
                    "90 % band, over the stripes",
                ));
            }
            if self.panels.iter().any(|p| p.median_bars) {
                entries.push(Entry::new(
                    Sample::Bar(neutral),
                    "90 % band of the median (at P = 0.5)",
                ));
            }
            if self.extrapolates() {
                entries.push(Entry::new(
                    Sample::Line(layout::tint(neutral, EXTRAPOLATED_TINT), Dash::Dotted),
                    "extrapolated beyond the stripes (dotted)",
                ));
            }
        }
        entries
    }
}

/// Sets the axis end and continues the fitted curves to it (after
/// [`mark_as_infinite`]: a twin counts with its μ = ∞ curve): the axis ends
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
    // a curve drawn on its μ = ∞ twin is not one more curve short
    for s in panels
        .iter()
        .flat_map(|p| &p.series)
        .filter(|s| !s.as_infinite)
    {
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
    /// axis end (1.5 × the last stripe)`.
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
    let same_observed = |a: &[(f64, f64, usize)], b: &[(f64, f64, usize)]| {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.0 == y.0 && x.1 == y.1)
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
                                .all(|(a, b)| same_observed(a, b))
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
        // one block: one panel a column wide, taller for the legend rows
        // and title lines the narrower page wraps onto
        let width = if self.panels.len() <= 1 {
            COLUMN_WIDTH_IN
        } else {
            PAGE_WIDTH_IN
        };
        let labels: Vec<String> = self.legend().into_iter().map(|e| e.label).collect();
        let extra = layout::estimated_legend_rows(&labels, width).saturating_sub(1)
            + layout::estimated_title_lines(&self.title, width).saturating_sub(1);
        (
            width,
            HEIGHT_IN + extra as f64 * layout::LEGEND_ROW_PT / 72.0,
        )
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
        let n_ls = self.limit_states.len();
        let ls_colour = |s: &FragilitySeries, k: usize| {
            layout::tint(restitution_colour(s.restitution), severity_tint(k, n_ls))
        };
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

            if !panel.median_bars {
                for s in panel.series.iter().filter(|s| !s.as_infinite) {
                    for k in 0..s.fits.len() {
                        let band = s.band(k);
                        if band.is_empty() {
                            continue;
                        }
                        let mut outline: Vec<(f64, f64)> =
                            band.iter().map(|p| (p.0, p.2)).collect();
                        outline.extend(band.iter().rev().map(|p| (p.0, p.1)));
                        chart.draw_series(std::iter::once(Polygon::new(
                            outline,
                            ls_colour(s, k).mix(BAND_ALPHA).filled(),
                        )))?;
                    }
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
            let line_pt = style.ipx(super::style::LINE_PT);
            for s in &order {
                if self.fitted {
                    for k in 0..s.fits.len() {
                        let colour = ls_colour(s, k);
                        let [below, middle, above] = s.curve_parts(k);
                        let light = layout::tint(colour, EXTRAPOLATED_TINT).stroke_width(line_pt);
                        for part in [below, above] {
                            if part.len() > 1 {
                                curve!(chart, part, light, Dash::Dotted, style);
                            }
                        }
                        if middle.len() > 1 {
                            let line = colour.stroke_width(line_pt);
                            curve!(chart, middle, line, Dash::nth(s.friction), style);
                        }
                    }
                } else {
                    let line = restitution_colour(s.restitution).stroke_width(line_pt);
                    let points: Vec<(f64, f64)> =
                        s.observed.iter().flatten().map(|o| (o.0, o.1)).collect();
                    curve!(chart, points, line, Dash::nth(s.friction), style);
                }
            }
            if panel.median_bars {
                // the medians' bands as bars at P = 0.5, stacked apart
                let bars: Vec<(RGBColor, (f64, f64))> = order
                    .iter()
                    .filter(|s| !s.as_infinite)
                    .flat_map(|s| {
                        (0..s.fits.len())
                            .filter_map(move |k| s.median_band[k].map(|b| (ls_colour(s, k), b)))
                    })
                    .collect();
                let first = 0.5 - BAR_STEP * (bars.len().saturating_sub(1)) as f64 / 2.0;
                let bar = style.ipx(BAR_PT);
                for (i, (colour, (lo, hi))) in bars.into_iter().enumerate() {
                    let y = first + BAR_STEP * i as f64;
                    chart.draw_series(std::iter::once(PathElement::new(
                        vec![(lo, y), (hi.min(x_max), y)],
                        colour.stroke_width(bar),
                    )))?;
                }
            }
            // hollow (finite friction) markers first: a filled one on top
            // at the same place leaves a ring showing both
            for s in order.iter().rev() {
                for (k, observed) in s.observed.iter().enumerate() {
                    let colour = if self.fitted {
                        ls_colour(s, k)
                    } else {
                        restitution_colour(s.restitution)
                    };
                    let filled = s.friction == 0;
                    if let Some((_, most)) = self.sized {
                        // as `markers!` draws circles, each at its own radius
                        let r = marker_px(style, filled);
                        let ms = marker_style(style, colour, filled);
                        let ri = |o: &(f64, f64, usize)| sized_radius(r, o.2, most);
                        if filled {
                            chart.draw_series(
                                observed.iter().map(|o| Circle::new((o.0, o.1), ri(o), ms)),
                            )?;
                        } else {
                            chart.draw_series(observed.iter().map(|o| {
                                EmptyElement::at((o.0, o.1))
                                    + Circle::new((0, 0), ri(o), HOLLOW_FILL)
                                    + Circle::new((0, 0), ri(o), ms)
                            }))?;
                        }
                    } else {
                        markers!(
                            chart,
                            observed.iter().map(|o| (o.0, o.1)),
                            colour,
                            Marker::Circle,
                            filled,
                            style
                        );
                    }
                }
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

#[cfg(test)]
mod tests {
    use super::sized_radius;

    /// Area ∝ analyses: a quarter of the analyses, half the radius; the
    /// largest stripe keeps the full marker; a tiny stripe stays visible.
    #[test]
    fn sized_points_have_area_proportional_to_analyses() {
        assert_eq!(sized_radius(10, 25, 100), 5);
        assert_eq!(sized_radius(10, 100, 100), 10);
        assert_eq!(sized_radius(10, 1, 1000), 2);
    }
}
