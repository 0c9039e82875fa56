//! The work–precision figure of `rockfrag bench`: error against cost, for
//! single runs (a) and for the fitted fragility curves (b).

use rockfrag::detmath as dm;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::{
    BindKeyPoints, ChartBuilder, Circle, Color, DrawingArea, DrawingBackend, IntoLogRange,
    LineSeries, PathElement, Rectangle, Text, TriangleMarker, WHITE,
};
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::report::{ADEQUATE_BANDS, Report, SettingReport};
use rockfrag::Result;
use rockfrag::figures::style::{COLUMN_WIDTH_IN, Style, tick_label};
use rockfrag::figures::{DrawResult, Figure, save};
use rockfrag::solver::{Integrator, Model};

/// Draws, against the median time per analysis (log–log), (a) the median
/// relative error of θmax/θc and (b) the fragility error: the largest change
/// of a case's fitted median or β in units of the reference fit's 90 % band,
/// without the runs the reference finds sensitive (filled; lines through
/// the tolerances) and with them (open), beside the adequacy line (0.1) and
/// the floor those runs set (the reference under the record scaled by
/// 1 + 1e-9, dotted). Each integrator of the nonlinear model is a line
/// through its tolerances (labelled at both ends in (a)); the default
/// setting with the cascade rules off is a square, the linearised model a
/// triangle. Errors of 0 (exact to rounding in (a), the reference's curves
/// in (b)) are drawn at the bottom of the axis.
pub fn plot_work_precision(report: &Report, path: &Path) -> Result<()> {
    save(&WorkPrecision { report }, path)
}

struct WorkPrecision<'a> {
    report: &'a Report,
}

/// Floor of panel (a): a median error of 0 is drawn here.
const THETA_FLOOR: f64 = 1e-16;
/// Floor of panel (b): an error of 0 is drawn here, its tick labelled 0.
const BANDS_FLOOR: f64 = 2e-3;

#[derive(Clone, Copy, PartialEq)]
enum Panel {
    Theta,
    Fragility,
}

impl Figure for WorkPrecision<'_> {
    fn size_in(&self) -> (f64, f64) {
        (COLUMN_WIDTH_IN, 5.4)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB> {
        root.fill(&WHITE)?;
        let areas = root.split_evenly((2, 1));
        panel(&areas[0], style, self.report, Panel::Theta)?;
        panel(&areas[1], style, self.report, Panel::Fragility)?;
        Ok(())
    }
}

/// Ticks at 1, 2, 5 × 10^k inside [lo, hi], so that a range of less than a
/// decade still has several labelled ticks.
fn ticks(lo: f64, hi: f64) -> Vec<f64> {
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
}

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    style: &Style,
    report: &Report,
    which: Panel,
) -> DrawResult<DB> {
    let floor = match which {
        Panel::Theta => THETA_FLOOR,
        Panel::Fragility => BANDS_FLOOR,
    };
    // (time in µs, the filled point's error, the open point's, if any)
    let point = |r: &SettingReport| -> (f64, f64, Option<f64>) {
        let t = r.median_time * 1e6;
        match which {
            Panel::Theta => (t, r.theta_err.0.max(floor), None),
            Panel::Fragility => (
                t,
                r.fragility_robust.bands().max(floor),
                Some(r.fragility.bands().max(floor)),
            ),
        }
    };
    let pts: Vec<(f64, f64, Option<f64>, &SettingReport)> = report
        .settings
        .iter()
        // the points over one restitution alone are in the table only
        .filter(|r| r.restitution_only.is_none())
        .map(|r| {
            let (x, y, open) = point(r);
            (x, y, open, r)
        })
        .filter(|p| p.1.is_finite())
        .collect();
    let (mut x0, mut x1) = (f64::INFINITY, 0.0_f64);
    let (mut y0, mut y1) = (f64::INFINITY, 0.0_f64);
    for &(x, y, open, _) in &pts {
        x0 = x0.min(x);
        x1 = x1.max(x);
        for v in std::iter::once(y).chain(open.filter(|v| v.is_finite())) {
            y0 = y0.min(v);
            y1 = y1.max(v);
        }
    }
    let floor_line = report.floor.bands();
    let (yl, yh) = match which {
        // room above the points for the legend
        Panel::Theta => (y0 / 10.0, y1 * 1e5),
        Panel::Fragility => (BANDS_FLOOR / 1.5, y1.max(floor_line).max(1.0) * 1.5),
    };
    let (xl, xh) = (x0 / 1.6, x1 * 1.6);
    let x_ticks = ticks(xl, xh);
    let mut y_ticks: Vec<f64> = ticks(yl, yh)
        .into_iter()
        .filter(|&t| {
            let decade = (dm::log10(t).round() - dm::log10(t)).abs() < 1e-9;
            match which {
                // relative errors: every other decade, up to 1
                Panel::Theta => decade && dm::log10(t).round() as i64 % 2 == 0 && t <= 1.0,
                Panel::Fragility => decade,
            }
        })
        .collect();
    if which == Panel::Fragility {
        y_ticks.insert(0, BANDS_FLOOR);
    }
    let (caption, y_desc) = match which {
        Panel::Theta => ("(a) Single runs", "Median rel. error of θmax"),
        Panel::Fragility => ("(b) Fragility curves", "Error (90 % bands)"),
    };
    let mut chart = ChartBuilder::on(area)
        .caption(caption, style.font(8.0))
        .margin(style.ipx(4.0))
        .margin_right(style.ipx(10.0))
        .x_label_area_size(style.ipx(26.0))
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
        .y_desc(y_desc)
        .x_label_formatter(&|v| tick_label(*v))
        .y_label_formatter(&|v| match which {
            Panel::Theta => format!("1e{}", dm::log10(*v).round() as i64),
            // the floor holds the errors of 0
            Panel::Fragility if *v == BANDS_FLOOR => "0".to_string(),
            Panel::Fragility => tick_label(*v),
        })
        .draw()?;
    if which == Panel::Fragility {
        // the adequacy line and the floor the sensitive runs set
        let thin = style.axis();
        // each label on the side of its line away from the other line, so
        // that the two do not overlap when the lines are close
        let floor_above = !(floor_line.is_finite() && floor_line < ADEQUATE_BANDS);
        let (note_above, note_below) = (
            style.font(6.5).pos(Pos::new(HPos::Left, VPos::Bottom)),
            style.font(6.5).pos(Pos::new(HPos::Left, VPos::Top)),
        );
        chart.draw_series(std::iter::once(PathElement::new(
            vec![(xl, ADEQUATE_BANDS), (xh, ADEQUATE_BANDS)],
            thin,
        )))?;
        chart.draw_series(std::iter::once(if floor_above {
            Text::new(
                format!("adequate: {ADEQUATE_BANDS} band"),
                (xl * 1.05, ADEQUATE_BANDS / 1.05),
                note_below.clone(),
            )
        } else {
            Text::new(
                format!("adequate: {ADEQUATE_BANDS} band"),
                (xl * 1.05, ADEQUATE_BANDS * 1.05),
                note_above.clone(),
            )
        }))?;
        if floor_line.is_finite() && floor_line > 0.0 {
            let dotted: Vec<(f64, f64)> = (0..40)
                .map(|i| xl * dm::powf(xh / xl, i as f64 / 39.0))
                .map(|x| (x, floor_line))
                .collect();
            chart.draw_series(
                dotted
                    .iter()
                    .map(|&p| Circle::new(p, style.ipx(0.5), thin.color.filled())),
            )?;
            let (y, note) = if floor_above {
                (floor_line * 1.05, note_above)
            } else {
                (floor_line / 1.05, note_below)
            };
            chart.draw_series(std::iter::once(Text::new(
                "reference × (1 + 1e-9)".to_string(),
                (xl * 1.05, y),
                note,
            )))?;
        }
    }
    // one line per integrator, labelled at its loosest and tightest rtol
    let above = style.font(7.0).pos(Pos::new(HPos::Center, VPos::Bottom));
    let below = style.font(7.0).pos(Pos::new(HPos::Center, VPos::Top));
    for (k, integrator) in [Integrator::Taylor, Integrator::Dopri5]
        .into_iter()
        .enumerate()
    {
        let line: Vec<(f64, f64, Option<f64>, f64)> = pts
            .iter()
            .filter(|p| {
                p.3.settings.model == Model::Nonlinear
                    && p.3.settings.integrator == integrator
                    && p.3.settings.settle_cascades
            })
            .map(|p| (p.0, p.1, p.2, p.3.settings.rtol))
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
                .map(|&(x, y, _, _)| Circle::new((x, y), style.ipx(2.0), colour.filled())),
        )?;
        chart.draw_series(line.iter().filter_map(|&(x, _, open, _)| {
            open.filter(|v| v.is_finite())
                .map(|v| Circle::new((x, v), style.ipx(2.0), colour.stroke_width(1)))
        }))?;
        if which == Panel::Theta {
            // the loosest rtol labelled above its point, the tightest below:
            // neighbours of equal error or equal cost then stay clear
            for (i, p) in [line.first(), line.last()]
                .into_iter()
                .flatten()
                .enumerate()
            {
                let text = format!("rtol {:.0e}", p.3);
                let (y, st) = if i == 0 {
                    (p.1 * 3.0, above.clone())
                } else {
                    (p.1 / 3.0, below.clone())
                };
                chart.draw_series(std::iter::once(Text::new(text, (p.0, y), st)))?;
            }
        }
    }
    // the default setting with every impact followed (cascade rules off)
    let off = style.series(3);
    for p in pts.iter().filter(|p| !p.3.settings.settle_cascades) {
        let square = |y: f64, filled: bool| {
            let st = if filled {
                off.filled()
            } else {
                off.stroke_width(1)
            };
            Rectangle::new([(p.0 / 1.04, y / 1.25), (p.0 * 1.04, y * 1.25)], st)
        };
        chart
            .draw_series(std::iter::once(square(p.1, true)))?
            .label("Taylor, cascade rules off")
            .legend(move |(x, y)| Rectangle::new([(x + 3, y - 3), (x + 9, y + 3)], off.filled()));
        if let Some(v) = p.2.filter(|v| v.is_finite()) {
            chart.draw_series(std::iter::once(square(v, false)))?;
        }
    }
    let lin = style.series(2);
    for p in pts.iter().filter(|p| p.3.settings.model == Model::Linear) {
        chart
            .draw_series(std::iter::once(TriangleMarker::new(
                (p.0, p.1),
                style.ipx(3.0),
                lin.filled(),
            )))?
            .label("linearised model")
            .legend(move |(x, y)| TriangleMarker::new((x + 6, y), 4, lin.filled()));
        if let Some(v) = p.2.filter(|v| v.is_finite()) {
            chart.draw_series(std::iter::once(TriangleMarker::new(
                (p.0, v),
                style.ipx(3.0),
                lin.stroke_width(1),
            )))?;
        }
    }
    if which == Panel::Theta {
        chart
            .configure_series_labels()
            .position(plotters::chart::SeriesLabelPosition::UpperLeft)
            .label_font(style.font(7.0))
            .border_style(style.axis())
            .background_style(WHITE)
            .draw()?;
    } else {
        let key = style.font(6.5).pos(Pos::new(HPos::Right, VPos::Top));
        chart.draw_series(std::iter::once(Text::new(
            "filled: without sensitive runs; open: all runs".to_string(),
            (xh / 1.05, yh / 1.1),
            key,
        )))?;
    }
    Ok(())
}
