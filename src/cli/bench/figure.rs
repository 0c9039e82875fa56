//! The work–precision figure of `rockfrag bench`: error against cost.

use rockfrag::detmath as dm;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::{
    BindKeyPoints, ChartBuilder, Circle, DrawingArea, DrawingBackend, IntoLogRange, LineSeries,
    Rectangle, Text, TriangleMarker, WHITE,
};
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::report::SettingReport;
use rockfrag::Result;
use rockfrag::figures::style::{COLUMN_WIDTH_IN, Style, tick_label};
use rockfrag::figures::{DrawResult, Figure, save};
use rockfrag::solver::{Integrator, Model};

/// Draws the median relative error of θmax/θc against the median time per
/// analysis (log–log): each integrator of the nonlinear model as a line
/// through its tolerances (labelled at both ends), the default setting with
/// the cascade rule off as a square, the linearised model as a
/// triangle.
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
            // the points over one restitution alone are in the table only
            .filter(|r| r.restitution_only.is_none())
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
        // ticks at 1, 2, 5 × 10^k inside the range, so that a range of less
        // than a decade still has several labelled ticks
        let ticks = |lo: f64, hi: f64| -> Vec<f64> {
            let mut v = Vec::new();
            let mut decade = dm::powf(10.0, dm::log10(lo).floor());
            while decade <= hi {
                for m in [1.0, 2.0, 5.0] {
                    let t = m * decade;
                    if t >= lo && t <= hi {
                        v.push(t);
                    }
                }
                decade *= 10.0;
            }
            v
        };
        let (xl, xh) = (x0 / 1.6, x1 * 1.6);
        let (yl, yh) = (y0 / 10.0, y1 * 10.0);
        let x_ticks = ticks(xl, xh);
        let y_ticks: Vec<f64> = ticks(yl, yh)
            .into_iter()
            .filter(|&t| {
                (dm::log10(t).round() - dm::log10(t)).abs() < 1e-9
                    && dm::log10(t).round() as i64 % 2 == 0
            })
            .collect();
        let mut chart = ChartBuilder::on(root)
            .margin(style.ipx(6.0))
            .margin_right(style.ipx(10.0))
            .x_label_area_size(style.ipx(28.0))
            .y_label_area_size(style.ipx(40.0))
            .build_cartesian_2d(
                (xl..xh).log_scale().with_key_points(x_ticks),
                (yl..yh).log_scale().with_key_points(y_ticks),
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
            .x_label_formatter(&|v| tick_label(*v))
            .y_label_formatter(&|v| format!("1e{}", dm::log10(*v).round()))
            .draw()?;
        // one line per integrator, labelled at its loosest and tightest rtol
        let above = style.font(7.0).pos(Pos::new(HPos::Center, VPos::Bottom));
        let below = style.font(7.0).pos(Pos::new(HPos::Center, VPos::Top));
        for (k, integrator) in [Integrator::Taylor, Integrator::Dopri5]
            .into_iter()
            .enumerate()
        {
            let line: Vec<(f64, f64, f64)> = pts
                .iter()
                .filter(|p| {
                    p.2.settings.model == Model::Nonlinear
                        && p.2.settings.integrator == integrator
                        && p.2.settings.settle_cascades
                })
                .map(|p| (p.0, p.1, p.2.settings.rtol))
                .collect();
            if line.is_empty() {
                continue;
            }
            let colour = style.series(k);
            // segment by segment: a polyline's joins grow long spikes where
            // noise in the cost turns it back on itself
            for w in line.windows(2) {
                chart.draw_series(LineSeries::new(
                    [(w[0].0, w[0].1), (w[1].0, w[1].1)],
                    colour,
                ))?;
            }
            chart
                .draw_series(std::iter::once(Circle::new(
                    (line[0].0, line[0].1),
                    style.ipx(2.0),
                    colour.filled(),
                )))?
                .label(match integrator {
                    Integrator::Taylor => "Taylor series",
                    Integrator::Dopri5 => "Dormand–Prince 5(4)",
                })
                .legend(move |(x, y)| Circle::new((x + 6, y), 3, colour.filled()));
            chart.draw_series(
                line.iter()
                    .map(|&(x, y, _)| Circle::new((x, y), style.ipx(2.0), colour.filled())),
            )?;
            // the loosest rtol labelled above its point, the tightest below:
            // neighbours of equal error or equal cost then stay clear
            for (i, p) in [line.first(), line.last()]
                .into_iter()
                .flatten()
                .enumerate()
            {
                let text = format!("rtol {:.0e}", p.2);
                let (y, st) = if i == 0 {
                    (p.1 * 3.0, above.clone())
                } else {
                    (p.1 / 3.0, below.clone())
                };
                chart.draw_series(std::iter::once(Text::new(text, (p.0, y), st)))?;
            }
        }
        // the default setting with every impact followed (cascade rule off)
        let off = style.series(3);
        for p in pts.iter().filter(|p| !p.2.settings.settle_cascades) {
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(p.0 / 1.02, p.1 / 1.6), (p.0 * 1.02, p.1 * 1.6)],
                    off.filled(),
                )))?
                .label("Taylor, cascade rule off")
                .legend(move |(x, y)| {
                    Rectangle::new([(x + 3, y - 3), (x + 9, y + 3)], off.filled())
                });
        }
        let lin = style.series(2);
        for p in pts.iter().filter(|p| p.2.settings.model == Model::Linear) {
            chart
                .draw_series(std::iter::once(TriangleMarker::new(
                    (p.0, p.1),
                    style.ipx(3.0),
                    lin.filled(),
                )))?
                .label("linearised model")
                .legend(move |(x, y)| TriangleMarker::new((x + 6, y), 4, lin.filled()));
        }
        chart
            .configure_series_labels()
            .position(plotters::chart::SeriesLabelPosition::UpperRight)
            .label_font(style.font(7.0))
            .border_style(style.axis())
            .background_style(WHITE)
            .draw()?;
        Ok(())
    }
}
