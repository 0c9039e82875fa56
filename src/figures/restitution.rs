//! The trend with restitution: against e, (top row) the fraction of
//! records that overturn and (bottom row) the mean θmax/θc of the runs that
//! did not, one column per block, one colour per PGA level, infinite
//! friction solid with filled points beside each Coulomb model dashed with
//! open points. The title states the trend of overturning over e
//! (Cochran–Armitage). Published values may be drawn as open squares
//! ([`RestitutionPanel::reference`], labelled
//! [`RestitutionFigure::reference_label`]): the paper layer draws the seed
//! paper's Tables 1–3 there for its study.
//!
//! A friction model whose every line lies on the μ = ∞ one (a friction that
//! changes no outcome) says so in its legend entry, `(as μ = ∞)`: its
//! dashed lines cannot be seen under the solid ones.
//!
//! The fraction counts only runs that reached θ = π/2 (the `overturned`
//! column); the trend in the title counts overturned or uplifted runs, the
//! seed paper's convention, so that it compares with the paper's.

use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingBackend};
use plotters::style::{BLACK, Color};

use super::data::{
    StudyData, distinct, distinct_fixed, distinct_friction, distinct_numbers, friction_label,
    param_label, runs,
};
use super::figure::{DrawResult, Figure};
use super::fragility::distinct_blocks;
use super::friction::{level_colour, shown_levels};
use super::layout::{self, Dash, Entry, Frame, Margins, Marker, Sample, curve, markers};
use super::style::{LINE_PT, PAGE_WIDTH_IN, Style, tick_label};
use crate::case::{Case, Param};
use crate::solver::Friction;
use crate::stats::{cochran_armitage, p_text};

/// Figure height (in).
const HEIGHT_IN: f64 = 4.6;
/// Panel margins: 28 pt for the y tick labels, 8 pt on the right.
const MARGINS: Margins = Margins::new(28.0, 8.0);
/// Largest difference, as a fraction of an axis's range, between two lines
/// drawn as one (half a percent: under a line's width at print size).
const SAME_LINE_TOL: f64 = 0.005;
/// Gap between the two rows of panels (pt).
const ROW_GAP_PT: f64 = 6.0;

/// One line: a PGA level under one friction model, over e.
#[derive(Clone, Debug, PartialEq)]
pub struct RestitutionSeries {
    /// Index into [`RestitutionFigure::levels`] (sets the colour).
    pub level: usize,
    /// Index into [`RestitutionFigure::frictions`] (sets the pattern).
    pub friction: usize,
    /// (e, fraction overturned), e ascending.
    pub overturned: Vec<(f64, f64)>,
    /// (e, mean θmax/θc of the runs not overturned); e where every run
    /// overturned are left out.
    pub theta: Vec<(f64, f64)>,
}

/// One column: one block.
#[derive(Clone, Debug, PartialEq)]
pub struct RestitutionPanel {
    /// Heading, e.g. `H/B = 4`.
    pub label: String,
    /// The block's H/B.
    pub aspect: Param<f64>,
    /// The block's 2B.
    pub width: Param<f64>,
    /// Series, by friction then level.
    pub series: Vec<RestitutionSeries>,
    /// Published (level index, e, fraction overturned, mean θmax/θc) for
    /// this block, drawn as open squares.
    pub reference: Vec<(usize, f64, f64, Option<f64>)>,
}

/// The restitution figure's data.
#[derive(Clone, Debug, PartialEq)]
pub struct RestitutionFigure {
    /// Title.
    pub title: String,
    /// PGA levels drawn (g), ascending.
    pub levels: Vec<f64>,
    /// Every PGA level of the study (g), ascending.
    pub all_levels: Vec<f64>,
    /// Friction models, infinite first.
    pub frictions: Vec<Param<Friction>>,
    /// Columns, by aspect ratio then width.
    pub panels: Vec<RestitutionPanel>,
    /// The values of e, ascending.
    pub restitutions: Vec<f64>,
    /// Largest e.
    pub e_max: f64,
    /// Whether the title states this study's trend over e.
    pub has_trend: bool,
    /// Legend label of the reference values, e.g. `paper (μ = ∞)`.
    pub reference_label: Option<String>,
    /// For each friction model: whether each of its lines is drawn exactly
    /// on the μ = ∞ line of its block and PGA (a friction that changes no
    /// outcome), which its legend entry then says, the dashed lines being
    /// hidden under the solid ones.
    pub as_infinite: Vec<bool>,
}

impl RestitutionFigure {
    /// Groups the study's outcomes by block, PGA level, friction and e.
    pub fn from_study(data: &StudyData) -> RestitutionFigure {
        let rows = &data.outcomes;
        let all_levels = distinct_numbers(rows.iter().map(|r| r.pga));
        let levels = shown_levels(&all_levels);
        let frictions = distinct_friction(rows.iter().map(|r| r.case.friction));
        let es = distinct_fixed(rows.iter().map(|r| r.case.restitution));
        let cases: Vec<Case> = runs(rows.iter().map(|r| r.case), |a, b| a.total_cmp(b).is_eq());
        let blocks = distinct_blocks(&cases);
        let several_widths = distinct(blocks.iter().map(|b| b.1)).len() > 1;
        let mut panels = Vec::new();
        let (mut n_min, mut n_max) = (usize::MAX, 0);
        for &(aspect, width) in &blocks {
            let mut series = Vec::new();
            for (jf, f) in frictions.iter().enumerate() {
                for (il, &pga) in levels.iter().enumerate() {
                    let mut overturned = Vec::new();
                    let mut theta = Vec::new();
                    for &e in &es {
                        let case = Case {
                            aspect,
                            width,
                            restitution: Param::Fixed(e),
                            friction: *f,
                            stack: None,
                        };
                        let at: Vec<_> = rows
                            .iter()
                            .filter(|r| r.case == case && r.pga == pga)
                            .collect();
                        if at.is_empty() {
                            continue;
                        }
                        n_min = n_min.min(at.len());
                        n_max = n_max.max(at.len());
                        let k = at.iter().filter(|r| r.overturned).count();
                        overturned.push((e, k as f64 / at.len() as f64));
                        let standing: Vec<f64> = at
                            .iter()
                            .filter(|r| !r.overturned)
                            .map(|r| r.theta_max_over_theta_c)
                            .collect();
                        if !standing.is_empty() {
                            theta.push((e, standing.iter().sum::<f64>() / standing.len() as f64));
                        }
                    }
                    if !overturned.is_empty() {
                        series.push(RestitutionSeries {
                            level: il,
                            friction: jf,
                            overturned,
                            theta,
                        });
                    }
                }
            }
            let mut label = format!("H/B = {}", param_label(aspect));
            if several_widths {
                label.push_str(&format!(", 2B = {} m", param_label(width)));
            }
            panels.push(RestitutionPanel {
                label,
                aspect,
                width,
                series,
                reference: Vec::new(),
            });
        }
        let mut title =
            "Against e: fraction overturned, and mean θmax/θc of the runs not overturned"
                .to_string();
        let mut notes = Vec::new();
        if n_max > 0 {
            notes.push(if n_min == n_max {
                format!("{n_max} records per point")
            } else {
                format!("{n_min}–{n_max} records per point")
            });
        }
        if levels.len() < all_levels.len() {
            notes.push(format!(
                "{} of {} PGA levels",
                levels.len(),
                all_levels.len()
            ));
        }
        if !notes.is_empty() {
            title.push_str(&format!("; {}", notes.join(", ")));
        }
        // The trend over e as summary.md tests it: Cochran–Armitage on the
        // counts (overturned or uplifted, the paper's convention) pooled over
        // blocks and levels, infinite friction.
        let infinite = Param::Fixed(Friction::Infinite);
        let pooled: Vec<(u64, u64)> = es
            .iter()
            .map(|&e| {
                let at = rows.iter().filter(|r| {
                    r.case.restitution == Param::Fixed(e) && r.case.friction == infinite
                });
                at.fold((0, 0), |(k, n), r| {
                    (k + (r.overturned || r.uplifted) as u64, n + 1)
                })
            })
            .collect();
        let ks: Vec<u64> = pooled.iter().map(|p| p.0).collect();
        let ns: Vec<u64> = pooled.iter().map(|p| p.1).collect();
        let ours = trend_text(&ks, &ns, &es);
        if let Some(ours) = &ours {
            title.push_str(&format!(
                "; trend over e (μ = ∞, overturned or uplifted): {ours}"
            ));
        }
        // "on the μ = ∞ line": within SAME_LINE_TOL of each axis's range
        let theta_top = panels
            .iter()
            .flat_map(|p| &p.series)
            .flat_map(|s| s.theta.iter().map(|t| t.1))
            .fold(0.0_f64, f64::max);
        let close = |a: &[(f64, f64)], b: &[(f64, f64)], range: f64| {
            a.len() == b.len()
                && a.iter()
                    .zip(b)
                    .all(|(p, q)| p.0 == q.0 && (p.1 - q.1).abs() <= SAME_LINE_TOL * range)
        };
        let as_infinite = (0..frictions.len())
            .map(|j| {
                let mine = || {
                    panels
                        .iter()
                        .flat_map(|p| p.series.iter().map(move |s| (p, s)))
                };
                j > 0
                    && mine().any(|(_, s)| s.friction == j)
                    && mine().filter(|(_, s)| s.friction == j).all(|(p, s)| {
                        p.series.iter().any(|t| {
                            t.friction == 0
                                && t.level == s.level
                                && close(&t.overturned, &s.overturned, 1.0)
                                && close(&t.theta, &s.theta, theta_top)
                        })
                    })
            })
            .collect();
        RestitutionFigure {
            title,
            levels,
            all_levels,
            frictions,
            as_infinite,
            panels,
            e_max: es.last().copied().unwrap_or(1.0),
            restitutions: es,
            has_trend: ours.is_some(),
            reference_label: None,
        }
    }

    fn legend(&self) -> Vec<Entry> {
        let mut entries = vec![Entry::new(Sample::Text, "PGA:")];
        entries.extend(self.levels.iter().enumerate().map(|(i, pga)| {
            Entry::new(
                Sample::Line(level_colour(i, self.levels.len()), Dash::Solid),
                format!("{} g", tick_label(*pga)),
            )
        }));
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
        if let Some(label) = &self.reference_label {
            entries.push(Entry::new(
                Sample::Point(BLACK, Marker::Square, false),
                label.clone(),
            ));
        }
        entries
    }
}

/// The Cochran–Armitage trend of `k` of `n` over the scores `e`, as the
/// figures state it (`Z = −3.05, p = 0.002`, `p = 1.2×10⁻⁵`, with a true
/// minus sign as on the axes); `None` when undefined.
pub fn trend_text(k: &[u64], n: &[u64], e: &[f64]) -> Option<String> {
    cochran_armitage(k, n, e).map(|t| {
        let z = format!("{:.2}", t.z);
        let z = match z.strip_prefix('-') {
            Some(abs) => format!("\u{2212}{abs}"),
            None => z,
        };
        // p below 0.001 as 1.2×10⁻⁵, not 1.2e-5
        let p = if t.p > 0.0 && t.p < 0.001 {
            let rounded: f64 = format!("{:.1e}", t.p).parse().unwrap_or(t.p);
            layout::power_label(rounded)
        } else {
            p_text(t.p)
        };
        format!("Z = {z}, p = {p}")
    })
}

impl Figure for RestitutionFigure {
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
        let (heading, x_area) = (frame.top, frame.x_area);
        let gap = style.ipx(ROW_GAP_PT);
        let (_, h) = frame.body.dim_in_pixel();
        let plot_h = h.saturating_sub(x_area + heading + gap) / 2;
        let (top, bottom) = frame.body.split_vertically(heading + plot_h);
        let top = layout::side_label(&top, style, "P(overturning)", heading, 0)?;
        let bottom = layout::side_label(&bottom, style, "Mean θmax/θc", gap, x_area)?;
        let theta_max = self
            .panels
            .iter()
            .flat_map(|p| {
                p.series
                    .iter()
                    .flat_map(|s| s.theta.iter().map(|t| t.1))
                    .chain(p.reference.iter().filter_map(|q| q.3))
            })
            .fold(0.0_f64, f64::max);
        let theta_top = if theta_max > 0.0 {
            theta_max * 1.1
        } else {
            1.0
        };
        let x_range = -0.04 * self.e_max.max(0.1)..self.e_max * 1.04 + 0.01;
        for (row, area_row) in [top, bottom].iter().enumerate() {
            let cells = area_row.split_evenly((1, n));
            for (panel, area) in self.panels.iter().zip(&cells) {
                let mut builder = frame.chart(area, row == 1);
                if row == 0 {
                    frame.heading(area, &panel.label)?;
                } else {
                    // the bottom row has no headings: only a gap above it
                    builder.margin_top(gap);
                }
                let y_hi = if row == 0 { 1.0 } else { theta_top };
                let mut chart = builder.build_cartesian_2d(x_range.clone(), 0.0..y_hi)?;
                let mut mesh = layout::mesh(&mut chart, style);
                mesh.x_labels(6).y_labels(6);
                if row == 1 {
                    mesh.x_desc("Coefficient of restitution e");
                }
                mesh.draw()?;
                let points = |s: &RestitutionSeries| -> Vec<(f64, f64)> {
                    if row == 0 {
                        s.overturned.clone()
                    } else {
                        s.theta.clone()
                    }
                };
                for s in &panel.series {
                    let colour = level_colour(s.level, self.levels.len());
                    let line = colour.stroke_width(style.ipx(LINE_PT));
                    curve!(chart, points(s), line, Dash::nth(s.friction), style);
                }
                for q in &panel.reference {
                    let colour = level_colour(q.0, self.levels.len());
                    let value = if row == 0 { Some(q.2) } else { q.3 };
                    markers!(
                        chart,
                        value.map(|v| (q.1, v)),
                        colour,
                        Marker::Square,
                        false,
                        style
                    );
                }
                // hollow (finite friction) markers first: a filled one on
                // top at the same place leaves a ring showing both
                for s in panel.series.iter().rev() {
                    let colour = level_colour(s.level, self.levels.len());
                    markers!(
                        chart,
                        points(s),
                        colour,
                        Marker::Circle,
                        s.friction == 0,
                        style
                    );
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trend_text_writes_a_true_minus_and_small_p_as_a_power_of_ten() {
        // Overturning falling steeply with e: Z < 0, p far below 0.001.
        let (k, n, e) = ([90, 60, 30, 5], [100; 4], [0.0, 0.3, 0.6, 0.9]);
        let text = trend_text(&k, &n, &e).unwrap();
        assert!(text.starts_with("Z = \u{2212}"), "{text}");
        assert!(text.contains("×10⁻"), "{text}");
        assert!(!text.contains('-') && !text.contains("e-"), "{text}");
    }
}
