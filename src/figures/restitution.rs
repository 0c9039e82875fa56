//! The paper's claim that restitution stabilises the block, tested: against
//! e, (top row) the fraction of records that overturn and (bottom row) the
//! mean θmax/θc of the runs that did not, one column per block, one colour
//! per PGA level, infinite friction solid with filled points beside each
//! Coulomb model dashed with open points. The paper's Tables 1–3 (infinite
//! friction, 25 records) are drawn as open squares: # OT/25 on top, the
//! mean θmax/θc below.
//!
//! The paper counted as overturned both the runs that reached θ = π/2 and
//! those its program stopped at a lift-off; this study's fraction counts
//! only the former (the `overturned` column).

use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingBackend};
use plotters::style::{BLACK, Color};

use super::data::{StudyData, distinct, distinct_friction, friction_label};
use super::figure::{DrawResult, Figure};
use super::friction::{level_colour, shown_levels};
use super::layout::{self, Dash, Entry, Frame, Margins, Marker, Sample, curve, markers};
use super::style::{LINE_PT, PAGE_WIDTH_IN, Style, tick_label};
use crate::outcomes_csv::CaseKey;
use crate::solver::Friction;
use crate::stats::{cochran_armitage, p_text};
use crate::study::paper::{RECORDS, TABLES};

/// Figure height (in).
const HEIGHT_IN: f64 = 4.6;
/// Panel margins: 28 pt for the y tick labels, 8 pt on the right.
const MARGINS: Margins = Margins::new(28.0, 8.0);
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
    /// Series, by friction then level.
    pub series: Vec<RestitutionSeries>,
    /// The paper's (level index, e, # OT/25, mean θmax/θc) for this block.
    pub paper: Vec<(usize, f64, f64, Option<f64>)>,
}

/// The restitution figure's data.
#[derive(Clone, Debug, PartialEq)]
pub struct RestitutionFigure {
    /// Title.
    pub title: String,
    /// PGA levels drawn (g), ascending.
    pub levels: Vec<f64>,
    /// Friction models, infinite first.
    pub frictions: Vec<Friction>,
    /// Columns, by aspect ratio then width.
    pub panels: Vec<RestitutionPanel>,
    /// Largest e.
    pub e_max: f64,
}

impl RestitutionFigure {
    /// Groups the study's outcomes by block, PGA level, friction and e.
    pub fn from_study(data: &StudyData) -> RestitutionFigure {
        let rows = &data.outcomes;
        let all_levels = distinct(rows.iter().map(|r| r.pga));
        let levels = shown_levels(&all_levels);
        let frictions = distinct_friction(rows.iter().map(|r| r.case.friction));
        let es = distinct(rows.iter().map(|r| r.case.restitution));
        let mut blocks: Vec<(f64, f64)> =
            rows.iter().map(|r| (r.case.aspect, r.case.width)).collect();
        blocks.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        blocks.dedup_by(|a, b| super::data::same(a.0, b.0) && super::data::same(a.1, b.1));
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
                        let case = CaseKey {
                            aspect,
                            width,
                            restitution: e,
                            friction: *f,
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
            let paper = TABLES
                .iter()
                .filter(|p| {
                    p.aspect == aspect && p.restitution <= es.last().copied().unwrap_or(1.0)
                })
                .filter_map(|p| {
                    let il = levels.iter().position(|&l| l == p.pga)?;
                    Some((
                        il,
                        p.restitution,
                        p.overturned as f64 / RECORDS as f64,
                        p.theta_max_over_theta_c,
                    ))
                })
                .collect();
            let mut label = format!("H/B = {}", tick_label(aspect));
            if several_widths {
                label.push_str(&format!(", 2B = {} m", tick_label(width)));
            }
            panels.push(RestitutionPanel {
                label,
                series,
                paper,
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
        // blocks and levels, infinite friction; the paper's beside it.
        let pooled: Vec<(u64, u64)> = es
            .iter()
            .map(|&e| {
                let at = rows
                    .iter()
                    .filter(|r| r.case.restitution == e && r.case.friction == Friction::Infinite);
                at.fold((0, 0), |(k, n), r| {
                    (k + (r.overturned || r.uplifted) as u64, n + 1)
                })
            })
            .collect();
        let trend = |k: &[u64], n: &[u64]| {
            cochran_armitage(k, n, &es).map(|t| format!("Z = {:.2}, p = {}", t.z, p_text(t.p)))
        };
        let ks: Vec<u64> = pooled.iter().map(|p| p.0).collect();
        let ns: Vec<u64> = pooled.iter().map(|p| p.1).collect();
        if let Some(ours) = trend(&ks, &ns) {
            title.push_str(&format!(
                "; trend over e (μ = ∞, overturned or uplifted): {ours}"
            ));
            let aspects: Vec<f64> = blocks.iter().map(|b| b.0).collect();
            let published: Vec<(u64, u64)> = es
                .iter()
                .map(|&e| {
                    let at: Vec<_> = TABLES
                        .iter()
                        .filter(|p| p.restitution == e && aspects.contains(&p.aspect))
                        .filter(|p| all_levels.contains(&p.pga))
                        .collect();
                    let k = at.iter().map(|p| p.overturned as u64).sum();
                    (
                        k,
                        (aspects.len() * all_levels.len()) as u64 * RECORDS as u64,
                    )
                })
                .collect();
            let has_paper = panels.iter().any(|p| !p.paper.is_empty());
            let kp: Vec<u64> = published.iter().map(|p| p.0).collect();
            let np: Vec<u64> = published.iter().map(|p| p.1).collect();
            if let Some(theirs) = trend(&kp, &np).filter(|_| has_paper) {
                title.push_str(&format!(", paper's {theirs}"));
            }
        }
        RestitutionFigure {
            title,
            levels,
            frictions,
            panels,
            e_max: es.last().copied().unwrap_or(1.0),
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
            entries.push(Entry::new(
                Sample::LinePoint(BLACK, Dash::nth(j), Marker::Circle, j == 0),
                friction_label(f),
            ));
        }
        entries.push(Entry::new(
            Sample::Point(BLACK, Marker::Square, false),
            "paper (μ = ∞)",
        ));
        entries
    }
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
                    .chain(p.paper.iter().filter_map(|q| q.3))
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
                for q in &panel.paper {
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
