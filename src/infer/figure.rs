//! `figures/inference.svg`: (a) the prior, the joint posterior (its 90 %
//! interval shaded, and its pointwise Monte Carlo band from the bootstrap
//! of the simulations: where the posterior is a few records' bumps, the
//! band says how much of its shape more records would change) and the
//! naive posterior on one logarithmic IM axis, as densities per unit ln IM;
//! (b) each kind's fragility, its draws' overturning fraction pooled over
//! the records (solid) and its lognormal fit (dashed), with the fraction
//! observed at the site drawn beside it as a bar across the joint
//! posterior's 90 % interval. Each panel has its legend above it.

use plotters::coord::Shift;
use plotters::prelude::{BindKeyPoints, DrawingArea, DrawingBackend, IntoLogRange, LineSeries};
use plotters::prelude::{PathElement, Polygon};
use plotters::style::{BLACK, Color, RGBColor};

use super::inference::Inference;
use super::survey::Survey;
use crate::detmath as dm;
use crate::figures::layout::{self, Dash, Entry, Frame, Margins, Sample, curve};
use crate::figures::style::{LINE_PT, PAGE_WIDTH_IN, PALETTE, Style, tick_label};
use crate::figures::{DrawResult, Figure};

/// Figure height (in).
const HEIGHT_IN: f64 = 3.0;
/// Panel margins (pt).
const MARGINS: Margins = Margins::new(30.0, 8.0);
/// Grey of the prior.
const PRIOR: RGBColor = RGBColor(0x88, 0x88, 0x88);
/// Colour of the naive posterior.
const NAIVE: RGBColor = RGBColor(0xD5, 0x5E, 0x00);
/// Colour of the Monte Carlo band.
const BAND: RGBColor = RGBColor(0x00, 0x72, 0xB2);
/// Its opacity.
const BAND_ALPHA: f64 = 0.25;
/// Points per curve of the fits.
const SAMPLES: usize = 200;

/// A point of a band: (IM, lower, upper).
pub type BandPoint = (f64, f64, f64);

/// One kind's fragility.
#[derive(Clone, Debug, PartialEq)]
pub struct KindSeries {
    /// Its name.
    pub name: String,
    /// (IM, pooled overturning fraction) on the grid.
    pub pooled: Vec<(f64, f64)>,
    /// (IM, fitted probability), if fitted.
    pub fit: Option<Vec<(f64, f64)>>,
    /// Observed fraction overturned.
    pub observed: f64,
}

/// The figure's data.
#[derive(Clone, Debug, PartialEq)]
pub struct InferenceFigure {
    /// Title.
    pub title: String,
    /// IM axis label.
    pub im_label: String,
    /// IM range.
    pub range: (f64, f64),
    /// Prior density per unit ln IM.
    pub prior: Vec<(f64, f64)>,
    /// Joint posterior density per unit ln IM.
    pub joint: Vec<(f64, f64)>,
    /// Its 90 % interval and median.
    pub interval: (f64, f64, f64),
    /// Its pointwise Monte Carlo 90 % band per unit ln IM, and the
    /// bootstrap replicates behind it (none without a bootstrap).
    pub band: Option<(Vec<BandPoint>, usize)>,
    /// Naive posterior density per unit ln IM.
    pub naive: Option<Vec<(f64, f64)>>,
    /// The naive median.
    pub naive_median: Option<f64>,
    /// The kinds.
    pub kinds: Vec<KindSeries>,
}

impl InferenceFigure {
    /// The figure of an inference of `survey`.
    pub fn new(inf: &Inference, survey: &Survey) -> InferenceFigure {
        let g = &inf.grid;
        let per_u = |d: &[f64]| -> Vec<(f64, f64)> {
            g.x.iter().zip(d).map(|(&x, &v)| (x, v * x)).collect()
        };
        let (lo, hi) = (g.x[0], g.x[g.len() - 1]);
        let xs: Vec<f64> = (0..SAMPLES)
            .map(|i| lo * dm::powf(hi / lo, i as f64 / (SAMPLES - 1) as f64))
            .collect();
        let kinds = survey
            .kinds
            .iter()
            .zip(&inf.curves)
            .map(|(k, c)| KindSeries {
                name: k.name.clone(),
                pooled: g.x.iter().copied().zip(c.pooled.iter().copied()).collect(),
                fit: c
                    .fit
                    .as_ref()
                    .ok()
                    .map(|f| xs.iter().map(|&x| (x, f.probability(x))).collect()),
                observed: k.overturned as f64 / k.count as f64,
            })
            .collect();
        let s = inf.joint.summary;
        InferenceFigure {
            title: format!(
                "{} inferred from {}: joint median {} [{}, {}] {}",
                inf.im.name().to_uppercase(),
                survey
                    .path
                    .file_name()
                    .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
                tick_label(round3(s.median)),
                tick_label(round3(s.p05)),
                tick_label(round3(s.p95)),
                inf.im.unit()
            ),
            im_label: inf.im.axis_label(),
            range: (lo, hi),
            prior: per_u(&inf.prior),
            joint: per_u(&inf.joint.density),
            interval: (s.p05, s.p95, s.median),
            band: inf.joint_band.as_ref().map(|b| {
                let points =
                    g.x.iter()
                        .zip(b.lo.iter().zip(&b.hi))
                        .map(|(&x, (&lo, &hi))| (x, lo * x, hi * x))
                        .collect();
                (points, b.replicates)
            }),
            naive: inf.naive.as_ref().map(|p| per_u(&p.density)),
            naive_median: inf.naive.as_ref().map(|p| p.summary.median),
            kinds,
        }
    }

    /// Panel (a)'s legend.
    fn legend_a(&self) -> Vec<Entry> {
        let mut e = vec![
            Entry::new(Sample::Line(PRIOR, Dash::Dashed), "prior"),
            Entry::new(Sample::Line(NAIVE, Dash::Short), "naive posterior"),
            Entry::new(Sample::Line(BLACK, Dash::Solid), "joint posterior"),
            Entry::new(
                Sample::Block(layout::tint(BLACK, 0.85)),
                "its 90 % interval",
            ),
        ];
        if let Some((_, n)) = &self.band {
            e.push(Entry::new(
                Sample::Block(layout::tint(BAND, 1.0 - BAND_ALPHA)),
                format!("its MC band ({n} replicates)"),
            ));
        }
        e
    }

    /// Panel (b)'s legend.
    fn legend_b(&self) -> Vec<Entry> {
        let mut e: Vec<Entry> = self
            .kinds
            .iter()
            .enumerate()
            .map(|(i, k)| Entry::new(Sample::Line(colour(i), Dash::Solid), k.name.clone()))
            .collect();
        e.push(Entry::new(
            Sample::Line(BLACK, Dash::Dashed),
            "lognormal fit",
        ));
        e.push(Entry::new(
            Sample::Bar(BLACK),
            "observed, across the 90 % interval",
        ));
        e
    }
}

fn round3(x: f64) -> f64 {
    let scale = dm::powf(10.0, 2.0 - dm::log10(x.abs()).floor());
    (x * scale).round() / scale
}

fn colour(i: usize) -> RGBColor {
    // The palette without the vermillion of the naive posterior.
    let p: Vec<RGBColor> = PALETTE.iter().copied().filter(|c| *c != NAIVE).collect();
    p[i % p.len()]
}

/// 1, 2, 5 × powers of ten in [lo, hi].
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let mut v = Vec::new();
    let mut decade = dm::powf(10.0, dm::log10(lo).floor());
    while decade <= hi {
        for m in [1.0, 2.0, 5.0] {
            let t = m * decade;
            if t >= lo * (1.0 - 1e-9) && t <= hi * (1.0 + 1e-9) {
                v.push(t);
            }
        }
        decade *= 10.0;
    }
    v
}

impl Figure for InferenceFigure {
    fn size_in(&self) -> (f64, f64) {
        (PAGE_WIDTH_IN, HEIGHT_IN)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB> {
        let frame = Frame::new(root, style, &self.title, &[], MARGINS)?;
        // Each panel its legend, both taking as many rows as the longer;
        // each panel's y-axis label in a strip of its own (a label drawn by
        // the mesh at the figure's left edge loses its descenders).
        let halves = frame.body.split_evenly((1, 2));
        let legends = [self.legend_a(), self.legend_b()];
        let rows = halves
            .iter()
            .zip(&legends)
            .map(|(h, l)| layout::legend_rows(h, style, l))
            .max()
            .unwrap_or(1);
        let mut areas = Vec::with_capacity(2);
        for ((half, entries), text) in halves
            .iter()
            .zip(&legends)
            .zip(["density per ln IM", "P(overturn)"])
        {
            let below = layout::legend_in_rows(half, style, entries, rows)?;
            areas.push(layout::side_label(
                &below,
                style,
                text,
                frame.top,
                frame.x_area,
            )?);
        }
        let (xl, xh) = self.range;
        let ticks = log_ticks(xl, xh);
        let thin = style.ipx(LINE_PT);
        let thick = style.ipx(2.5 * LINE_PT);

        // (a) The posteriors.
        let top = self
            .joint
            .iter()
            .chain(self.naive.iter().flatten())
            .chain(&self.prior)
            .map(|p| p.1)
            .chain(self.band.iter().flat_map(|b| b.0.iter().map(|p| p.2)))
            .fold(0.0, f64::max)
            * 1.08;
        frame.heading(&areas[0], "(a) prior and posteriors")?;
        let mut chart = frame.chart(&areas[0], true).build_cartesian_2d(
            (xl..xh).log_scale().with_key_points(ticks.clone()),
            0.0..top.max(1e-300),
        )?;
        layout::mesh(&mut chart, style)
            .x_desc(self.im_label.as_str())
            .x_label_formatter(&|v| tick_label(*v))
            .y_labels(4)
            .draw()?;
        let (p05, p95, median) = self.interval;
        let mut shade: Vec<(f64, f64)> = self
            .joint
            .iter()
            .copied()
            .filter(|p| p.0 >= p05 && p.0 <= p95)
            .collect();
        if !shade.is_empty() {
            let at = |x: f64| interpolate(&self.joint, x);
            shade.insert(0, (p05, at(p05)));
            shade.push((p95, at(p95)));
            shade.push((p95, 0.0));
            shade.push((p05, 0.0));
            chart.draw_series(std::iter::once(Polygon::new(
                shade,
                layout::tint(BLACK, 0.85).filled(),
            )))?;
        }
        if let Some((band, _)) = &self.band {
            let mut outline: Vec<(f64, f64)> = band.iter().map(|p| (p.0, p.2)).collect();
            outline.extend(band.iter().rev().map(|p| (p.0, p.1)));
            chart.draw_series(std::iter::once(Polygon::new(
                outline,
                BAND.mix(BAND_ALPHA).filled(),
            )))?;
        }
        curve!(
            chart,
            self.prior.clone(),
            PRIOR.stroke_width(thin),
            Dash::Dashed,
            style
        );
        if let Some(naive) = &self.naive {
            curve!(
                chart,
                naive.clone(),
                NAIVE.stroke_width(thin),
                Dash::Short,
                style
            );
        }
        chart.draw_series(LineSeries::new(
            self.joint.clone(),
            BLACK.stroke_width(thin),
        ))?;
        chart.draw_series(std::iter::once(PathElement::new(
            vec![(median, 0.0), (median, interpolate(&self.joint, median))],
            BLACK.stroke_width(thin),
        )))?;

        // (b) The kinds' fragility and what was observed.
        frame.heading(&areas[1], "(b) fragility of each kind, observed fraction")?;
        let mut chart = frame
            .chart(&areas[1], true)
            .build_cartesian_2d((xl..xh).log_scale().with_key_points(ticks), 0.0..1.02)?;
        layout::mesh(&mut chart, style)
            .x_desc(self.im_label.as_str())
            .x_label_formatter(&|v| tick_label(*v))
            .y_labels(6)
            .draw()?;
        for (i, k) in self.kinds.iter().enumerate() {
            let c = colour(i);
            chart.draw_series(LineSeries::new(k.pooled.clone(), c.stroke_width(thin)))?;
            if let Some(fit) = &k.fit {
                curve!(
                    chart,
                    fit.clone(),
                    c.stroke_width(thin),
                    Dash::Dashed,
                    style
                );
            }
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(p05, k.observed), (p95, k.observed)],
                c.stroke_width(thick),
            )))?;
        }
        Ok(())
    }
}

/// Linear interpolation of a polyline at x.
fn interpolate(points: &[(f64, f64)], x: f64) -> f64 {
    let i = points.partition_point(|p| p.0 <= x);
    match i {
        0 => points[0].1,
        i if i >= points.len() => points[points.len() - 1].1,
        i => {
            let (a, b) = (points[i - 1], points[i]);
            a.1 + (b.1 - a.1) * (x - a.0) / (b.0 - a.0)
        }
    }
}
