//! The fragility surface of one case and limit state in the (IM1, IM2)
//! plane, both axes logarithmic: the fitted contours P = 0.1, 0.5 and 0.9
//! (straight lines, the surface being a probit in ln IM1 and ln IM2) and
//! the observed fraction of the analyses in bins of the plane (each stripe
//! split into bins of IM2, [`crate::fragility::observed_bins`]) as markers
//! shaded by the fraction, with the fraction written beside each.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::{
    BindKeyPoints, Circle, DrawingArea, DrawingBackend, EmptyElement, IntoLogRange, Text,
};
use plotters::style::{Color, RGBColor};

use super::figure::{DrawResult, Figure};
use super::layout::{self, Dash, Entry, Frame, LogAxis, Margins, Marker, Sample, curve};
use super::style::{COLUMN_WIDTH_IN, Style};
use crate::error::{Error, Result};
use crate::fragility::{
    FragilityOptions, ObservedBin, SurfaceFit, SurfaceRow, observed_bins, read_outcomes_for,
};
use crate::spec::Study;

/// Figure height (in), before legend rows beyond the first.
const HEIGHT_IN: f64 = 3.3;
/// Panel margins: 30 pt for the y tick labels, 8 pt on the right.
const MARGINS: Margins = Margins::new(30.0, 8.0);
/// The contours drawn, with their dashes.
const CONTOURS: [(f64, Dash); 3] = [(0.1, Dash::Dotted), (0.5, Dash::Solid), (0.9, Dash::Dashed)];

/// One case and limit state's surface with its observed bins.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceFigure {
    /// Title: the case and limit state.
    pub title: String,
    /// The fitted surface (`None`: not fitted, the bins alone).
    pub fit: Option<SurfaceFit>,
    /// The status of `fragility_surface.csv`.
    pub status: String,
    /// Axis labels of IM1 (x) and IM2 (y).
    pub labels: (String, String),
    /// Observed bins.
    pub bins: Vec<ObservedBin>,
}

impl SurfaceFigure {
    /// The figures of `rows` (`fragility_surface.csv`'s), each with its
    /// file stem ([`SurfaceFigure::file_stem`]), for the study
    /// folder `dir` of `study`: its `outcomes.csv` read against both IMs
    /// (those it does not hold measured on its records again) and binned.
    ///
    /// Errors: unreadable outcomes, or an IM that cannot be measured.
    pub fn for_rows(
        dir: &Path,
        study: Option<&Study>,
        pooled: &[crate::case::Field],
        rows: &[SurfaceRow],
    ) -> Result<Vec<(String, SurfaceFigure)>> {
        let Some(first) = rows.first() else {
            return Ok(Vec::new());
        };
        let path = dir.join("outcomes.csv");
        let limit_state = study
            .and_then(|s| s.fragility.as_ref())
            .map_or_else(Vec::new, |f| f.limit_state.clone());
        let read = |im: crate::im::Im| -> Result<crate::fragility::Outcomes> {
            let mut measured = Vec::new();
            if !im.stored() && im.of_record() {
                let Some(s) = study else {
                    return Err(Error::invalid(
                        "im",
                        im,
                        "an IM outcomes.csv holds: the folder has no manifest.json to measure \
                         the records again",
                    ));
                };
                measured.push(std::sync::Arc::new(crate::study::measure_study_records(
                    s, dir, im,
                )?));
            }
            read_outcomes_for(
                &path,
                &FragilityOptions {
                    im: Some(im),
                    measured,
                    limit_state: limit_state.clone(),
                    pool: pooled.to_vec(),
                    ..FragilityOptions::default()
                },
            )
        };
        let (o1, o2) = (read(first.ims.first())?, read(first.ims.second())?);
        let mut figures = Vec::new();
        for row in rows {
            let (Some(c1), Some(c2)) = (
                o1.cases.iter().find(|c| c.key == row.case),
                o2.cases.iter().find(|c| c.key == row.case),
            ) else {
                continue;
            };
            let Some(k) = o1
                .limit_states
                .iter()
                .position(|l| l.name == row.limit_state)
            else {
                continue;
            };
            let fit = row.coefficients.map(|[a, b1, b2]| SurfaceFit {
                a,
                b1,
                b2,
                cov: [[0.0; 3]; 3],
                loglik: row.loglik.unwrap_or(f64::NAN),
                iterations: row.iterations.unwrap_or(0),
            });
            figures.push((
                SurfaceFigure::file_stem(row),
                SurfaceFigure {
                    title: format!("{} ({}), {}", row.case, row.case.id(), row.limit_state),
                    fit,
                    status: row.status.clone(),
                    labels: (row.ims.first().axis_label(), row.ims.second().axis_label()),
                    bins: observed_bins(c1, c2, k)?,
                },
            ));
        }
        Ok(figures)
    }

    /// The file name of the figure of `row`: `surface_<case id>_<limit
    /// state>` (without extension).
    pub fn file_stem(row: &SurfaceRow) -> String {
        format!("surface_{}_{}", row.case.id(), row.limit_state)
    }
}

/// The shade of an observed fraction: light (0) to dark (1).
fn shade(fraction: f64) -> RGBColor {
    let c = super::style::PALETTE[0];
    layout::tint(c, 0.85 * (1.0 - fraction))
}

impl Figure for SurfaceFigure {
    fn size_in(&self) -> (f64, f64) {
        (COLUMN_WIDTH_IN, HEIGHT_IN)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB> {
        let black = plotters::style::BLACK;
        let mut legend: Vec<Entry> = CONTOURS
            .iter()
            .map(|&(p, dash)| Entry::new(Sample::Line(black, dash), format!("P = {p}")))
            .collect();
        legend.push(Entry::new(
            Sample::Point(shade(0.5), Marker::Circle, true),
            "observed (darker: more exceeded)",
        ));
        let title = match self.status.as_str() {
            "ok" => self.title.clone(),
            s => format!("{} [{s}]", self.title),
        };
        let frame = Frame::new(root, style, &title, &legend, MARGINS)?;
        let body = layout::side_label(&frame.body, style, &self.labels.1, frame.top, frame.x_area)?;
        let range = |f: fn(&ObservedBin) -> f64| {
            let lo = self.bins.iter().map(f).fold(f64::INFINITY, f64::min);
            let hi = self.bins.iter().map(f).fold(0.0, f64::max);
            if lo.is_finite() && hi > lo {
                (lo / 1.25, hi * 1.25)
            } else if hi > 0.0 {
                (hi / 2.0, hi * 2.0)
            } else {
                (0.1, 1.0)
            }
        };
        let ((mut xl, mut xh), (yl, yh)) = (range(|b| b.im1), range(|b| b.im2));
        // room for the 0.1 and 0.9 contours at the middle IM2, within a
        // factor of 2 of the data
        if let Some(fit) = &self.fit {
            let y_mid = (yl * yh).sqrt();
            for (p, _) in CONTOURS {
                if let Some(x) = fit.im1_at(p, y_mid) {
                    xl = xl.min((x / 1.1).max(xl / 2.0));
                    xh = xh.max((x * 1.1).min(xh * 2.0));
                }
            }
        }
        let (xa, ya) = (LogAxis::new(xl, xh), LogAxis::new(yl, yh));
        let mut chart = frame.chart(&body, true).build_cartesian_2d(
            (xl..xh).log_scale().with_key_points(xa.ticks.clone()),
            (yl..yh).log_scale().with_key_points(ya.ticks.clone()),
        )?;
        layout::mesh(&mut chart, style)
            .x_desc(self.labels.0.as_str())
            .x_label_formatter(&|v| xa.label(*v))
            .y_label_formatter(&|v| ya.label(*v))
            .draw()?;
        if let Some(fit) = &self.fit {
            let line = black.stroke_width(style.ipx(super::style::LINE_PT));
            for &(p, dash) in &CONTOURS {
                // the contour, sampled along both axes (a steep one is
                // short in x) and kept inside the panel
                let t = |i: usize| i as f64 / 200.0;
                let mut points: Vec<(f64, f64)> = (0..=200)
                    .filter_map(|i| {
                        let x = xl * crate::detmath::powf(xh / xl, t(i));
                        Some((x, fit.im2_at(p, x)?))
                    })
                    .chain((0..=200).filter_map(|i| {
                        let y = yl * crate::detmath::powf(yh / yl, t(i));
                        Some((fit.im1_at(p, y)?, y))
                    }))
                    .filter(|&(x, y)| x >= xl && x <= xh && y >= yl && y <= yh)
                    .collect();
                points.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
                if points.len() > 1 {
                    curve!(chart, points, line, dash, style);
                }
            }
        }
        let r = layout::marker_px(style, true) + style.ipx(1.0) as i32;
        let font = style.tick_font();
        // a bin's k/n is written beside its marker only where it overlaps
        // no marker and no label already written (dense stripes would
        // otherwise print over each other; the shade still gives the
        // fraction)
        let at: Vec<(i32, i32)> = self
            .bins
            .iter()
            .map(|b| chart.backend_coord(&(b.im1, b.im2)))
            .collect();
        let mut taken: Vec<(i32, i32, i32, i32)> = at
            .iter()
            .map(|&(x, y)| (x - r, y - r, x + r, y + r))
            .collect();
        let overlaps = |a: &(i32, i32, i32, i32), b: &(i32, i32, i32, i32)| {
            a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
        };
        for (i, b) in self.bins.iter().enumerate() {
            let f = b.exceeded as f64 / b.trials as f64;
            let fill = shade(f).filled();
            let edge = black.stroke_width(style.ipx(super::style::AXIS_PT));
            chart.draw_series(std::iter::once(
                EmptyElement::at((b.im1, b.im2))
                    + Circle::new((0, 0), r, fill)
                    + Circle::new((0, 0), r, edge),
            ))?;
            let label = format!("{}/{}", b.exceeded, b.trials);
            let (w, h) = chart
                .plotting_area()
                .estimate_text_size(&label, &font)
                .unwrap_or((0, 0));
            let (x, y) = at[i];
            let rect = (x + r + 1, y - r, x + r + 1 + w as i32, y - r + h as i32);
            let mine = (x - r, y - r, x + r, y + r);
            if taken.iter().any(|t| *t != mine && overlaps(t, &rect)) {
                continue;
            }
            taken.push(rect);
            chart.draw_series(std::iter::once(
                EmptyElement::at((b.im1, b.im2)) + Text::new(label, (r + 1, -r), font.clone()),
            ))?;
        }
        Ok(())
    }
}
