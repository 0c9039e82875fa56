//! Figures of ground motions.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::{ChartBuilder, DrawingArea, DrawingBackend, LineSeries, WHITE};
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::figure::{DrawResult, Figure, save};
use super::layout;
use super::style::{COLUMN_WIDTH_IN, Style};
use crate::error::Result;
use crate::motion::{G_STANDARD, Record};

/// Height of the record figure (in).
const RECORD_HEIGHT_IN: f64 = 3.8;
/// Room above each panel for its label (pt).
const HEADING_PT: f64 = 14.0;
/// Room below the bottom panel for time tick labels and the time label (pt).
const X_AREA_PT: f64 = 28.0;
/// Room left of each panel for y tick labels (pt).
const Y_AREA_PT: f64 = 30.0;
/// Room right of the panels, for half the last time tick label (pt).
const RIGHT_PT: f64 = 9.0;

/// Plots a record as three stacked panels sharing the time axis, like Figure 2
/// of Shenton & Jones: acceleration (g, with g = 9.81 m/s²), velocity (cm/s)
/// and displacement (cm) against time (s), titled with the record's name.
///
/// One column wide ([`COLUMN_WIDTH_IN`]) and 3.8 in tall. Each panel's label
/// stands above it, left-aligned, rather than rotated beside it: rotated at
/// 9 pt, "Displacement (cm)" is longer than a panel is tall. The format
/// follows `path`'s extension (see [`super::save`]).
///
/// ```no_run
/// use rockfrag::motion::Record;
/// use std::path::Path;
/// let acc: Vec<f64> = (0..1000).map(|k| (k as f64 * 0.05).sin()).collect();
/// let record = Record::from_acc("sine", 0.01, acc).unwrap();
/// rockfrag::figures::plot_record(&record, Path::new("sine.png")).unwrap();
/// ```
pub fn plot_record(record: &Record, path: &Path) -> Result<()> {
    record.validate()?;
    save(&RecordFigure { record }, path)
}

/// The figure behind [`plot_record`].
struct RecordFigure<'a> {
    record: &'a Record,
}

impl Figure for RecordFigure<'_> {
    fn size_in(&self) -> (f64, f64) {
        (COLUMN_WIDTH_IN, RECORD_HEIGHT_IN)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB> {
        let r = self.record;
        root.fill(&WHITE)?;
        // The title gets a band of its own (plotters' `titled` pads by at
        // most 5 px, which clips the title at print resolution), wrapped
        // when a record's name is longer than the column is wide.
        let body = layout::title_band(root, style, &r.name)?;

        let scaled = |s: &[f64], k: f64| -> Vec<(f64, f64)> {
            s.iter()
                .enumerate()
                .map(|(i, y)| (i as f64 * r.dt, y * k))
                .collect()
        };
        let panels = [
            ("Acceleration (g)", scaled(&r.acc, 1.0 / G_STANDARD)),
            ("Velocity (cm/s)", scaled(&r.vel, 100.0)),
            ("Displacement (cm)", scaled(&r.disp, 100.0)),
        ];

        // Equal plot heights: the bottom panel alone carries the time-axis
        // labels, so it gets their height on top of its share.
        let heading = style.ipx(HEADING_PT);
        let x_area = style.ipx(X_AREA_PT);
        let y_area = style.ipx(Y_AREA_PT);
        let (_, h) = body.dim_in_pixel();
        let plot_h = (h.saturating_sub(x_area + 3 * heading) / 3).max(1);
        let (top, rest) = body.split_vertically(heading + plot_h);
        let (middle, bottom) = rest.split_vertically(heading + plot_h);

        let label_pos = Pos::new(HPos::Left, VPos::Center);
        for (i, (area, (label, data))) in [top, middle, bottom].iter().zip(&panels).enumerate() {
            let last = i == panels.len() - 1;
            area.draw_text(
                label,
                &style.label_font().pos(label_pos),
                (y_area as i32, (heading / 2) as i32),
            )?;
            let peak = data.iter().fold(0.0_f64, |m, &(_, y)| m.max(y.abs()));
            let y_max = if peak > 0.0 { 1.1 * peak } else { 1.0 };
            let mut chart = ChartBuilder::on(area)
                .margin_top(heading)
                .margin_right(style.ipx(RIGHT_PT))
                .y_label_area_size(y_area)
                .x_label_area_size(if last { x_area } else { 0 })
                .build_cartesian_2d(0.0..r.duration(), -y_max..y_max)?;
            let mut mesh = layout::mesh(&mut chart, style);
            mesh.x_labels(7).y_labels(5);
            if last {
                mesh.x_desc("Time (s)");
            }
            mesh.draw()?;
            chart.draw_series(LineSeries::new(data.iter().copied(), style.series(0)))?;
        }
        Ok(())
    }
}
