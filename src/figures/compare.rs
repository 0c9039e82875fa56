//! Fragility curves of several study folders on one axis of ground PGA: the
//! same block on the ground and on a floor of a building (issue 32's
//! hospital example), or any studies whose curves share a case.
//!
//! Each folder gives one curve: its first case's fit against PGA for its
//! last (most severe) limit state, over the 90 % band, and the observed
//! fraction exceeding overturning at each PGA stripe as points. The legend
//! names each folder by its label (the study's name unless given).

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingBackend, Polygon};
use plotters::style::Color;

use super::data::StudyData;
use super::figure::{DrawResult, Figure};
use super::fragility::restitution_colour;
use super::layout::{self, Dash, Entry, Frame, Margins, Marker, Sample, curve, markers};
use super::style::{COLUMN_WIDTH_IN, Style};
use crate::error::{Error, Result};

/// Figure height (in), before legend rows beyond the first.
const HEIGHT_IN: f64 = 2.8;
/// Panel margins: 24 pt for the y tick labels, 8 pt on the right.
const MARGINS: Margins = Margins::new(24.0, 8.0);
/// Opacity of the confidence bands.
const BAND_ALPHA: f64 = 0.14;

/// One folder's curve.
#[derive(Clone, Debug, PartialEq)]
pub struct CompareSeries {
    /// Legend label.
    pub label: String,
    /// Fitted curve (PGA in g, p, p_lo, p_hi), PGA ascending (empty without
    /// a fit against PGA).
    pub fit: Vec<(f64, f64, f64, f64)>,
    /// Observed stripes (PGA in g, fraction overturned).
    pub observed: Vec<(f64, f64)>,
}

/// Fragility curves of several studies against ground PGA.
#[derive(Clone, Debug, PartialEq)]
pub struct CompareFigure {
    /// Title.
    pub title: String,
    /// One series per folder, in the order given.
    pub series: Vec<CompareSeries>,
    /// Largest PGA shown (g).
    pub im_max: f64,
    /// The x axis's label: ground PGA, or a record pair's RotD50 PGA when
    /// the folders are studies of pairs.
    pub x_label: String,
    /// The y axis's label: `P(overturning)`, or `P(exceeded)` for limit
    /// states other than overturning.
    pub y_label: String,
}

impl CompareFigure {
    /// Reads each `(label, folder)`: its `outcomes.csv` and, when present,
    /// its `fragility_curves.csv` (curves against PGA only). Every row of a
    /// folder counts towards its stripes: compare folders of one case each.
    ///
    /// Errors: a folder without `outcomes.csv`, or unreadable files.
    pub fn from_folders(title: &str, folders: &[(String, PathBuf)]) -> Result<CompareFigure> {
        let mut series = Vec::new();
        let mut im_max = 0.0_f64;
        let mut measures = Vec::new();
        for (label, dir) in folders {
            let data = StudyData::load(dir)?;
            measures.push(data.pga_label());
            // curves against the stripes' PGA only: the figure's axis
            let curves = match data.fit_on_stripes() {
                true => data.curves.unwrap_or_default(),
                false => Vec::new(),
            };
            // the first case's most severe limit state
            let fit: Vec<(f64, f64, f64, f64)> = match curves.first() {
                Some(first) => {
                    let last_ls = curves
                        .iter()
                        .filter(|c| c.case == first.case)
                        .map(|c| c.limit_state.clone())
                        .next_back()
                        .unwrap_or_default();
                    curves
                        .iter()
                        .filter(|c| c.case == first.case && c.limit_state == last_ls)
                        .map(|c| (c.im, c.p, c.p_lo, c.p_hi))
                        .collect()
                }
                None => Vec::new(),
            };
            let mut levels: Vec<f64> = data.outcomes.iter().map(|r| r.pga).collect();
            levels.sort_by(f64::total_cmp);
            levels.dedup();
            let observed = levels
                .iter()
                .map(|&pga| {
                    let at: Vec<bool> = data
                        .outcomes
                        .iter()
                        .filter(|r| r.pga == pga)
                        .map(|r| r.overturned)
                        .collect();
                    let n = at.iter().filter(|&&o| o).count();
                    (pga, n as f64 / at.len() as f64)
                })
                .collect();
            im_max = levels
                .last()
                .copied()
                .into_iter()
                .chain(fit.last().map(|p| p.0))
                .fold(im_max, f64::max);
            series.push(CompareSeries {
                label: label.clone(),
                fit,
                observed,
            });
        }
        if series.is_empty() {
            return Err(Error::invalid(
                "folders",
                "none",
                "at least one study folder",
            ));
        }
        measures.dedup();
        let x_label = match &measures[..] {
            [one] => format!("ground {one}"),
            _ => "ground PGA (g; RotD50 for the studies of record pairs)".to_string(),
        };
        Ok(CompareFigure {
            title: title.to_string(),
            series,
            im_max,
            x_label,
            y_label: "P(overturning)".to_string(),
        })
    }

    /// The curves of one study folder's cases side by side (a study with
    /// stacks: the `stacks` figure): one series per case and limit state,
    /// the fitted curve against PGA with its band and the observed
    /// fraction exceeding it at each stripe, labelled `case: limit state`.
    /// A block is its own base and top: of its limit states of a body
    /// (`top.…`, `base.…`), only the top's are drawn. `None` when the
    /// folder has no stacks.
    pub fn of_cases(data: &StudyData) -> Option<CompareFigure> {
        let study = data.study.as_ref()?;
        if study.stacks.is_empty() {
            return None;
        }
        let limit_states = study.fragility.as_ref().map_or_else(
            || vec![crate::fragility::LimitState::overturning()],
            |f| f.limit_states(),
        );
        let curves = match data.fit_on_stripes() {
            true => data.curves.clone().unwrap_or_default(),
            false => Vec::new(),
        };
        let mut series = Vec::new();
        let mut im_max = 0.0_f64;
        for case in crate::study::plan::cases(study) {
            for ls in &limit_states {
                let other_body = ls.body().is_some_and(|b| b != crate::outcome::Slot::Top);
                if case.stack.is_none() && other_body {
                    continue;
                }
                let fit: Vec<(f64, f64, f64, f64)> = curves
                    .iter()
                    .filter(|c| c.case == case && c.limit_state == ls.name)
                    .map(|c| (c.im, c.p, c.p_lo, c.p_hi))
                    .collect();
                let observed: Vec<(f64, f64)> = data
                    .observed
                    .iter()
                    .filter(|o| o.case == case && o.limit_state == ls.name && o.trials > 0)
                    .map(|o| (o.im, o.exceeded as f64 / o.trials as f64))
                    .collect();
                im_max = observed
                    .iter()
                    .map(|o| o.0)
                    .chain(fit.last().map(|p| p.0))
                    .fold(im_max, f64::max);
                let name = match case.stack {
                    Some(s) => format!("stack {s}"),
                    None => format!(
                        "block H/B {} 2B {} m",
                        case.aspect.text(),
                        case.width.text()
                    ),
                };
                series.push(CompareSeries {
                    label: format!("{name}: {}", ls.name),
                    fit,
                    observed,
                });
            }
        }
        let overturning = limit_states.iter().all(|ls| {
            ls.column()
                .is_some_and(|(c, _)| c.name().ends_with("overturned"))
        });
        Some(CompareFigure {
            title: format!("{}: fragility by body", study.name),
            series,
            im_max,
            x_label: format!("ground {}", data.pga_label()),
            y_label: if overturning {
                "P(overturning)"
            } else {
                "P(exceeded)"
            }
            .to_string(),
        })
    }

    /// Draws the figure into `path` (SVG or PNG by extension).
    pub fn save(&self, path: &Path) -> Result<()> {
        super::figure::save(self, path)
    }
}

impl Figure for CompareFigure {
    fn size_in(&self) -> (f64, f64) {
        (COLUMN_WIDTH_IN, HEIGHT_IN)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB> {
        let mut legend: Vec<Entry> = self
            .series
            .iter()
            .enumerate()
            .map(|(i, s)| {
                Entry::new(
                    Sample::LinePoint(restitution_colour(i), Dash::Solid, Marker::Circle, true),
                    s.label.clone(),
                )
            })
            .collect();
        legend.push(Entry::new(
            Sample::Block(layout::tint(plotters::style::BLACK, 1.0 - 1.5 * BAND_ALPHA)),
            "90 % band",
        ));
        let frame = Frame::new(root, style, &self.title, &legend, MARGINS)?;
        let body = layout::side_label(&frame.body, style, &self.y_label, frame.top, frame.x_area)?;
        let x_max = if self.im_max > 0.0 { self.im_max } else { 1.0 };
        let mut chart = frame
            .chart(&body, true)
            .build_cartesian_2d(0.0..x_max * 1.03, 0.0..1.0)?;
        let mut mesh = layout::mesh(&mut chart, style);
        mesh.x_labels(6)
            .y_labels(6)
            .x_desc(self.x_label.as_str())
            .draw()?;
        for (i, s) in self.series.iter().enumerate() {
            if s.fit.is_empty() {
                continue;
            }
            let colour = restitution_colour(i);
            let mut outline: Vec<(f64, f64)> = s.fit.iter().map(|p| (p.0, p.3)).collect();
            outline.extend(s.fit.iter().rev().map(|p| (p.0, p.2)));
            chart.draw_series(std::iter::once(Polygon::new(
                outline,
                colour.mix(BAND_ALPHA).filled(),
            )))?;
        }
        for (i, s) in self.series.iter().enumerate() {
            let colour = restitution_colour(i);
            let line = colour.stroke_width(style.ipx(super::style::LINE_PT));
            let points: Vec<(f64, f64)> = if s.fit.is_empty() {
                s.observed.clone()
            } else {
                s.fit.iter().map(|p| (p.0, p.1)).collect()
            };
            curve!(chart, points, line, Dash::Solid, style);
            markers!(
                chart,
                s.observed.iter().copied(),
                colour,
                Marker::Circle,
                true,
                style
            );
        }
        Ok(())
    }
}
