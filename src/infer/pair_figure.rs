//! `figures/inference_2d.svg`: the joint posterior over (IM1, IM2), both
//! axes logarithmic: its 50 % and 90 % highest-density regions (shaded,
//! outlined by their contours), its median, and the records' 5–95 % spread
//! of IM2/IM1 (the second IM's prior, dashed rays the posterior cannot
//! leave); above it the marginal of IM1 (the one-IM posterior), beside it
//! the marginal of IM2, each per unit ln IM.

use plotters::coord::Shift;
use plotters::prelude::{
    BindKeyPoints, ChartBuilder, DrawingArea, DrawingBackend, IntoLogRange, LineSeries,
    PathElement, Polygon,
};
use plotters::style::{BLACK, Color, RGBColor};

use super::inference::Inference;
use super::pair::{PairPosterior, REGIONS, ratio_name};
use crate::detmath as dm;
use crate::figures::layout::{self, Dash, Entry, Frame, LogAxis, Margins, Marker, Sample, curve};
use crate::figures::style::{LINE_PT, PALETTE, Style, tick_label};
use crate::figures::{DrawResult, Figure};

/// A contour's segment, from one point (IM1, IM2) to another.
type Segment = [(f64, f64); 2];

/// Figure size (in).
const SIZE_IN: (f64, f64) = (5.5, 4.8);
/// Panel margins (pt).
const MARGINS: Margins = Margins::new(30.0, 8.0);
/// Share of the body the marginals take (above and beside).
const MARGINAL: f64 = 0.26;
/// Colour of the regions.
const REGION: RGBColor = PALETTE[0];
/// Grey of the prior's rays.
const PRIOR: RGBColor = RGBColor(0x88, 0x88, 0x88);

/// The figure's data.
#[derive(Clone, Debug, PartialEq)]
pub struct PairFigure {
    title: String,
    labels: (String, String),
    ratio: String,
    x: Vec<f64>,
    y: Vec<f64>,
    /// Density per unit ln IM1, ln IM2 at `i · y.len() + k`.
    density: Vec<f64>,
    /// The density at the edge of each of [`REGIONS`].
    thresholds: Vec<f64>,
    marginal_first: Vec<f64>,
    marginal_second: Vec<f64>,
    interval_first: (f64, f64),
    interval_second: (f64, f64),
    median: (f64, f64),
    /// The records' 5 % and 95 % IM2/IM1.
    rays: (f64, f64),
    /// The axes' ranges: the 99.5 % region's, widened.
    range: ((f64, f64), (f64, f64)),
}

/// The credible level whose region sets the axes.
const SHOWN: f64 = 0.995;

impl PairFigure {
    /// The figure of `pair` (of the inference `inf`).
    pub fn new(_inf: &Inference, pair: &PairPosterior) -> PairFigure {
        let thresholds = REGIONS
            .iter()
            .map(|&c| {
                (0..pair.density.len())
                    .filter(|&q| pair.credible[q] <= c)
                    .map(|q| pair.density[q])
                    .fold(f64::INFINITY, f64::min)
            })
            .collect();
        let (i1, i2) = (pair.ims.first(), pair.ims.second());
        let show = |s: &super::posterior::Summary, im: crate::im::Im| {
            format!(
                "{} {} [{}, {}] {}",
                im.name().to_uppercase(),
                crate::io_util::sig3(s.median),
                crate::io_util::sig3(s.p05),
                crate::io_util::sig3(s.p95),
                im.unit()
            )
        };
        let ny = pair.y.len();
        let shown: Vec<usize> = (0..pair.density.len())
            .filter(|&q| pair.credible[q] <= SHOWN)
            .collect();
        let span = |v: &mut dyn Iterator<Item = f64>, all: &[f64]| {
            let (lo, hi) = v.fold((f64::INFINITY, 0.0f64), |(a, b), t| (a.min(t), b.max(t)));
            if lo.is_finite() && hi > lo {
                ((lo / 1.3).max(all[0]), (hi * 1.3).min(all[all.len() - 1]))
            } else {
                (all[0], all[all.len() - 1])
            }
        };
        let range = (
            span(&mut shown.iter().map(|&q| pair.x[q / ny]), &pair.x),
            span(&mut shown.iter().map(|&q| pair.y[q % ny]), &pair.y),
        );
        PairFigure {
            range,
            title: format!(
                "Joint: {}, {}",
                show(&pair.first, i1),
                show(&pair.second, i2)
            ),
            labels: (i1.axis_label(), i2.axis_label()),
            ratio: ratio_name(pair.ims),
            x: pair.x.clone(),
            y: pair.y.clone(),
            density: pair.density.clone(),
            thresholds,
            marginal_first: pair.marginal_first.clone(),
            marginal_second: pair.marginal_second.clone(),
            interval_first: (pair.first.p05, pair.first.p95),
            interval_second: (pair.second.p05, pair.second.p95),
            median: (pair.first.median, pair.second.median),
            rays: (pair.ratio.prior.p05, pair.ratio.prior.p95),
        }
    }

    /// The contour of the density at `level` by marching squares in
    /// (ln IM1, ln IM2): its segments in (IM1, IM2) (an ambiguous cell joins
    /// its crossings in a fixed order), and the region at or above it as
    /// one polygon per cell (the cell's corners at or above the level and
    /// the crossings of its edges, in order).
    fn contour(&self, level: f64) -> (Vec<Segment>, Vec<Vec<(f64, f64)>>) {
        let ny = self.y.len();
        let d = |i: usize, k: usize| self.density[i * ny + k];
        let lx: Vec<f64> = self.x.iter().map(|&v| dm::ln(v)).collect();
        let ly: Vec<f64> = self.y.iter().map(|&v| dm::ln(v)).collect();
        let mut out = Vec::new();
        let mut fill = Vec::new();
        for i in 0..self.x.len() - 1 {
            for k in 0..ny - 1 {
                // corners counter-clockwise: (i,k), (i+1,k), (i+1,k+1), (i,k+1)
                let c = [(i, k), (i + 1, k), (i + 1, k + 1), (i, k + 1)];
                let mut cross = Vec::with_capacity(4);
                let mut poly = Vec::with_capacity(8);
                for e in 0..4 {
                    let (a, b) = (c[e], c[(e + 1) % 4]);
                    let (va, vb) = (d(a.0, a.1), d(b.0, b.1));
                    if va >= level {
                        poly.push((self.x[a.0], self.y[a.1]));
                    }
                    if (va >= level) != (vb >= level) {
                        let t = (level - va) / (vb - va);
                        let px = lx[a.0] + t * (lx[b.0] - lx[a.0]);
                        let py = ly[a.1] + t * (ly[b.1] - ly[a.1]);
                        cross.push((dm::exp(px), dm::exp(py)));
                        poly.push((dm::exp(px), dm::exp(py)));
                    }
                }
                for pair in cross.chunks_exact(2) {
                    out.push([pair[0], pair[1]]);
                }
                if poly.len() >= 3 {
                    fill.push(poly);
                }
            }
        }
        (out, fill)
    }
}

impl Figure for PairFigure {
    fn size_in(&self) -> (f64, f64) {
        SIZE_IN
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB> {
        let legend = vec![
            Entry::new(
                Sample::Block(layout::tint(REGION, 0.35)),
                "50 % region (highest density)",
            ),
            Entry::new(Sample::Block(layout::tint(REGION, 0.78)), "90 % region"),
            Entry::new(
                Sample::Line(PRIOR, Dash::Dashed),
                format!("records' 5–95 % {} (the prior)", self.ratio),
            ),
            Entry::new(Sample::Point(BLACK, Marker::Circle, true), "medians"),
        ];
        let frame = Frame::new(root, style, &self.title, &legend, MARGINS)?;
        let body = layout::side_label(&frame.body, style, &self.labels.1, frame.top, frame.x_area)?;
        let (w, h) = body.dim_in_pixel();
        let (top_h, side_w) = ((h as f64 * MARGINAL) as u32, (w as f64 * MARGINAL) as u32);
        let (top, rest) = body.split_vertically(top_h);
        let (main, side) = rest.split_horizontally(w - side_w);
        let (top_main, _) = top.split_horizontally(w - side_w);
        let ((xl, xh), (yl, yh)) = self.range;
        let (xa, ya) = (LogAxis::new(xl, xh), LogAxis::new(yl, yh));
        let thin = style.ipx(LINE_PT);

        // The joint.
        let mut chart = frame.chart(&main, true).build_cartesian_2d(
            (xl..xh).log_scale().with_key_points(xa.ticks.clone()),
            (yl..yh).log_scale().with_key_points(ya.ticks.clone()),
        )?;
        layout::mesh(&mut chart, style)
            .x_desc(self.labels.0.as_str())
            .x_label_formatter(&|v| xa.label(*v))
            .y_label_formatter(&|v| ya.label(*v))
            .draw()?;
        // The regions, 90 % then 50 % over it, filled cell by cell and
        // outlined.
        for (&level, shade) in self.thresholds.iter().zip([0.35, 0.78]).rev() {
            if !level.is_finite() {
                continue;
            }
            let (segments, fill) = self.contour(level);
            let colour = layout::tint(REGION, shade);
            chart.draw_series(fill.into_iter().map(|p| Polygon::new(p, colour.filled())))?;
            let stroke = REGION.stroke_width(thin);
            chart.draw_series(
                segments
                    .into_iter()
                    .map(|s| PathElement::new(s.to_vec(), stroke)),
            )?;
        }
        for ratio in [self.rays.0, self.rays.1] {
            let pts: Vec<(f64, f64)> = (0..=100)
                .map(|t| xl * dm::powf(xh / xl, t as f64 / 100.0))
                .map(|x| (x, ratio * x))
                .filter(|&(_, y)| y >= yl && y <= yh)
                .collect();
            if pts.len() > 1 {
                curve!(chart, pts, PRIOR.stroke_width(thin), Dash::Dashed, style);
            }
        }
        layout::markers!(chart, [self.median], BLACK, Marker::Circle, true, style);

        // IM1's marginal above.
        let per_ln1: Vec<(f64, f64)> = self
            .x
            .iter()
            .copied()
            .zip(self.marginal_first.iter().copied())
            .filter(|p| p.0 >= xl && p.0 <= xh)
            .collect();
        let top1 = per_ln1.iter().map(|p| p.1).fold(0.0, f64::max) * 1.08;
        let mut chart = frame.chart(&top_main, false).build_cartesian_2d(
            (xl..xh).log_scale().with_key_points(xa.ticks.clone()),
            0.0..top1.max(1e-300),
        )?;
        layout::mesh(&mut chart, style)
            .y_labels(3)
            .x_label_formatter(&|_| String::new())
            .y_label_formatter(&|v| tick_label(*v))
            .draw()?;
        let (p05, p95) = self.interval_first;
        shade_interval(&mut chart, &per_ln1, p05, p95, false)?;
        chart.draw_series(LineSeries::new(per_ln1, BLACK.stroke_width(thin)))?;

        // IM2's marginal beside.
        let per_ln2: Vec<(f64, f64)> = self
            .marginal_second
            .iter()
            .copied()
            .zip(self.y.iter().copied())
            .filter(|p| p.1 >= yl && p.1 <= yh)
            .collect();
        let top2 = per_ln2.iter().map(|p| p.0).fold(0.0, f64::max) * 1.08;
        let mut builder = ChartBuilder::on(&side);
        builder
            .margin_top(frame.top)
            .margin_right(frame.right)
            .x_label_area_size(frame.x_area)
            .y_label_area_size(0);
        let mut chart = builder.build_cartesian_2d(
            0.0..top2.max(1e-300),
            (yl..yh).log_scale().with_key_points(ya.ticks.clone()),
        )?;
        layout::mesh(&mut chart, style)
            .x_labels(3)
            .x_desc("density per ln IM")
            .x_label_formatter(&|v| tick_label(*v))
            .y_label_formatter(&|_| String::new())
            .draw()?;
        let (q05, q95) = self.interval_second;
        shade_interval(&mut chart, &per_ln2, q05, q95, true)?;
        chart.draw_series(LineSeries::new(per_ln2, BLACK.stroke_width(thin)))?;
        Ok(())
    }
}

/// Shades a marginal's 90 % interval: `points` are (IM, density), or
/// (density, IM) when `sideways`.
fn shade_interval<DB: DrawingBackend, X, Y>(
    chart: &mut plotters::chart::ChartContext<
        '_,
        DB,
        plotters::coord::cartesian::Cartesian2d<X, Y>,
    >,
    points: &[(f64, f64)],
    lo: f64,
    hi: f64,
    sideways: bool,
) -> DrawResult<DB>
where
    X: plotters::coord::ranged1d::Ranged<ValueType = f64>,
    Y: plotters::coord::ranged1d::Ranged<ValueType = f64>,
{
    let im = |p: &(f64, f64)| if sideways { p.1 } else { p.0 };
    let d = |p: &(f64, f64)| if sideways { p.0 } else { p.1 };
    let inside: Vec<&(f64, f64)> = points
        .iter()
        .filter(|p| im(p) >= lo && im(p) <= hi)
        .collect();
    if inside.len() < 2 {
        return Ok(());
    }
    let mut outline: Vec<(f64, f64)> = Vec::new();
    for p in &inside {
        outline.push(if sideways {
            (d(p), im(p))
        } else {
            (im(p), d(p))
        });
    }
    let (first, last) = (im(inside[0]), im(inside[inside.len() - 1]));
    if sideways {
        outline.push((0.0, last));
        outline.push((0.0, first));
    } else {
        outline.push((last, 0.0));
        outline.push((first, 0.0));
    }
    chart.draw_series(std::iter::once(plotters::prelude::Polygon::new(
        outline,
        layout::tint(BLACK, 0.85).filled(),
    )))?;
    Ok(())
}
