//! The work–precision figure of `rockfrag bench`: error against cost.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::{
    ChartBuilder, Circle, DrawingArea, DrawingBackend, IntoLogRange, LineSeries, Text,
    TriangleMarker, WHITE,
};
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::style::{COLUMN_WIDTH_IN, Style, tick_label};
use super::{DrawResult, Figure, save};
use crate::bench::SettingReport;
use crate::error::Result;
use crate::solver::Model;

/// Draws the median relative error of θmax/θc against the median time per
/// analysis (log–log): the nonlinear model as a line through its tolerances
/// (each point labelled with its rtol), the linearised model as a triangle.
/// Settings whose median error is 0 (exact to rounding) are drawn at 1e-16.
pub fn plot_work_precision(reports: &[SettingReport], path: &Path) -> Result<()> {
    save(&WorkPrecision { reports }, path)
}

struct WorkPrecision<'a> {
    reports: &'a [SettingReport],
}

const FLOOR: f64 = 1e-16;

impl Figure for WorkPrecision<'_> {
    fn size_in(&self) -> (f64, f64) {
        (COLUMN_WIDTH_IN, 2.8)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB> {
        root.fill(&WHITE)?;
        let pts: Vec<(f64, f64, &SettingReport)> = self
            .reports
            .iter()
            .map(|r| (r.median_time * 1e6, r.theta_err.0.max(FLOOR), r))
            .collect();
        let (mut x0, mut x1) = (f64::INFINITY, 0.0_f64);
        let (mut y0, mut y1) = (f64::INFINITY, 0.0_f64);
        for &(x, y, _) in &pts {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
        let mut chart = ChartBuilder::on(root)
            .margin(style.ipx(6.0))
            .margin_right(style.ipx(14.0))
            .x_label_area_size(style.ipx(28.0))
            .y_label_area_size(style.ipx(34.0))
            .build_cartesian_2d(
                (x0 / 3.0..x1 * 3.0).log_scale(),
                (y0 / 10.0..y1 * 10.0).log_scale(),
            )?;
        chart
            .configure_mesh()
            .axis_style(style.axis())
            .bold_line_style(style.grid())
            .max_light_lines(0)
            .label_style(style.tick_font())
            .axis_desc_style(style.label_font())
            .x_desc("Median time per analysis (µs)")
            .y_desc("Median rel. error of θmax")
            .x_labels(8)
            .x_label_formatter(&|v| tick_label(*v))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()?;
        let nonlinear: Vec<(f64, f64)> = pts
            .iter()
            .filter(|p| p.2.settings.model == Model::Nonlinear)
            .map(|p| (p.0, p.1))
            .collect();
        let line = style.series(0);
        chart.draw_series(LineSeries::new(nonlinear.iter().copied(), line))?;
        chart.draw_series(
            nonlinear
                .iter()
                .map(|&(x, y)| Circle::new((x, y), style.ipx(2.0), line.filled())),
        )?;
        // rtol labels alternate right and left of their points so that
        // neighbours with nearly equal cost do not overprint
        let right = style.font(7.0).pos(Pos::new(HPos::Left, VPos::Center));
        let left = style.font(7.0).pos(Pos::new(HPos::Right, VPos::Center));
        for (i, p) in pts
            .iter()
            .filter(|p| p.2.settings.model == Model::Nonlinear)
            .enumerate()
        {
            let text = format!("rtol {:.0e}", p.2.settings.rtol);
            let (x, st) = if i % 2 == 0 {
                (p.0 * 1.12, right.clone())
            } else {
                (p.0 / 1.12, left.clone())
            };
            chart.draw_series(std::iter::once(Text::new(text, (x, p.1), st)))?;
        }
        let label_style = style.font(7.0).pos(Pos::new(HPos::Left, VPos::Center));
        let lin = style.series(1);
        for p in pts.iter().filter(|p| p.2.settings.model == Model::Linear) {
            chart.draw_series(std::iter::once(TriangleMarker::new(
                (p.0, p.1),
                style.ipx(3.0),
                lin.filled(),
            )))?;
            chart.draw_series(std::iter::once(Text::new(
                "linearised",
                (p.0 * 1.12, p.1),
                label_style.clone(),
            )))?;
        }
        Ok(())
    }
}
