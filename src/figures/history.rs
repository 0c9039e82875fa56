//! A time history of one analysis: ground acceleration and θ/θc against
//! time, with the block's mode shaded behind both panels and the impacts
//! marked.
//!
//! The analysis is chosen, not hand-picked: of the records of a
//! [`HistoryCase`], the one whose run shows the most modes (each for at
//! least [`MIN_MODE_S`]) is drawn, preferring runs that do not overturn and
//! then the longest motion; ties go to the lowest record index. The time
//! axis is zoomed to the active part of the record.

use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingBackend, Rectangle};
use plotters::style::{BLACK, Color, RGBColor};

use super::figure::{DrawResult, Figure};
use super::layout::{self, Dash, Entry, Frame, Margins, Sample, curve};
use super::style::{PAGE_WIDTH_IN, PALETTE, Style, tick_label};
use crate::error::{Error, Result};
use crate::motion::{Record, SynthesisSettings, Synthesizer};
use crate::outcome::{Mode, Outcome};
use crate::solver::{Analysis, Block, Friction, History, SolverSettings, simulate};
use crate::spec::Intensity;
use crate::study::Source;
use std::sync::Arc;

/// Figure height (in).
const HEIGHT_IN: f64 = 3.3;
/// Panel margins: 34 pt for the y tick labels, 10 pt on the right.
const MARGINS: Margins = Margins::new(34.0, 10.0);
/// Shortest time in a mode that counts as showing it (s).
pub const MIN_MODE_S: f64 = 0.01;
/// Time shown before the first motion and after the last (s).
const ZOOM_PAD_S: f64 = 1.0;
/// Velocity jump (relative to √(gR)) above which an event is an impact.
const IMPACT_JUMP: f64 = 1e-9;

/// Which analyses the history figure chooses from.
#[derive(Clone, Debug, PartialEq)]
pub struct HistoryCase {
    /// Aspect ratio H/B (default: 2).
    pub aspect: f64,
    /// Base width 2B, m (default: 0.5).
    pub width: f64,
    /// Coefficient of restitution e (default: 0.6).
    pub restitution: f64,
    /// Static friction μs (default: 0.6, above B/H = 0.5: the block rocks
    /// from rest, and slides only after impacts and during slide-rock).
    pub mu_s: f64,
    /// Kinetic friction μk (default: 0.4).
    pub mu_k: f64,
    /// Peak ground acceleration, g (default: 0.9).
    pub pga: f64,
    /// Ensemble seed (default: 1, the study runner's default).
    pub seed: u64,
    /// Records 0..`records` are tried (default: 25).
    pub records: u64,
}

impl Default for HistoryCase {
    fn default() -> Self {
        HistoryCase {
            aspect: 2.0,
            width: 0.5,
            restitution: 0.6,
            mu_s: 0.6,
            mu_k: 0.4,
            pga: 0.9,
            seed: 1,
            records: 25,
        }
    }
}

/// A stretch of time in one mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeInterval {
    /// Start (s).
    pub t0: f64,
    /// End (s).
    pub t1: f64,
    /// The mode.
    pub mode: Mode,
}

/// The history figure's data.
#[derive(Clone, Debug, PartialEq)]
pub struct HistoryFigure {
    /// Title.
    pub title: String,
    /// Shown time window (s).
    pub window: (f64, f64),
    /// Ground acceleration (s, g) inside the window.
    pub acc: Vec<(f64, f64)>,
    /// θ/θc (s, –) inside the window.
    pub theta: Vec<(f64, f64)>,
    /// Mode intervals overlapping the window, clipped to it; consecutive
    /// intervals have different modes.
    pub intervals: Vec<ModeInterval>,
    /// Impact times inside the window (s).
    pub impacts: Vec<f64>,
    /// Index of the chosen record.
    pub record: u64,
    /// The chosen run's outcome.
    pub outcome: Outcome,
}

/// Background colour of each mode, in the order of [`Mode::ALL`].
pub fn mode_colour(mode: Mode) -> RGBColor {
    match mode {
        Mode::Rest => RGBColor(0xEE, 0xEE, 0xEE),
        Mode::Slide => layout::tint(PALETTE[4], 0.55),
        Mode::Rock => layout::tint(PALETTE[5], 0.6),
        Mode::SlideRock => layout::tint(PALETTE[3], 0.5),
        Mode::Flight => layout::tint(PALETTE[2], 0.55),
    }
}

impl HistoryFigure {
    /// Runs the case's records, chooses one (see the module docs) and
    /// extracts what the figure draws.
    pub fn compute(case: &HistoryCase, motion: &SynthesisSettings) -> Result<Self> {
        let mut synth = Synthesizer::new(motion)?;
        let pga = motion.pga_from_g(case.pga);
        let seed = case.seed;
        Self::choose(
            case,
            motion.g,
            case.records.max(1),
            |i| synth.generate(seed, i, pga),
            |i| format!("record {i} of seed {seed}"),
        )
    }

    /// As [`HistoryFigure::compute`], choosing among a study's recorded
    /// motions (the first `case.records` of `records`, each scaled to
    /// `case.pga` by its PGA, as the study runner scales them) instead of a
    /// synthetic ensemble; `case.seed` is not used. `names` label the
    /// records in the title (one per record).
    ///
    /// Errors: no record, or a record whose PGA is not positive.
    pub fn compute_recorded(
        case: &HistoryCase,
        records: &[Record],
        names: &[String],
        g: f64,
    ) -> Result<Self> {
        if records.is_empty() {
            return Err(Error::InvalidRecord {
                name: "history".to_string(),
                message: "no recorded motion to choose from".to_string(),
            });
        }
        // the runner's own scaling: every series by target PGA / record PGA
        let mut source = Source::Files(Arc::new(records.to_vec()));
        let n = (case.records.max(1) as usize).min(records.len()) as u64;
        Self::choose(
            case,
            g,
            n,
            |i| source.record(&Intensity::Pga(Vec::new()), case.pga, i as usize, g),
            |i| {
                names
                    .get(i as usize)
                    .cloned()
                    .unwrap_or_else(|| format!("record {i}"))
            },
        )
    }

    /// Runs records 0..`count` from `record(i)` (already at the case's PGA),
    /// chooses one (see the module docs) and extracts what the figure draws;
    /// `label(i)` names record i in the title.
    fn choose(
        case: &HistoryCase,
        g: f64,
        count: u64,
        mut record_at: impl FnMut(u64) -> Result<Record>,
        label: impl Fn(u64) -> String,
    ) -> Result<Self> {
        let block = Block::new(case.width, case.aspect, g)?;
        let mut analysis = Analysis::new(block, case.restitution);
        analysis.friction = Friction::Coulomb {
            mu_s: case.mu_s,
            mu_k: case.mu_k,
        };
        let solver = SolverSettings::default();

        let mut best: Option<((bool, usize, f64), u64)> = None;
        for i in 0..count {
            let record = record_at(i)?;
            let out = simulate(&analysis, &record, &solver, None)?;
            let modes = out
                .time_in_mode
                .iter()
                .filter(|&&t| t >= MIN_MODE_S)
                .count();
            let moving = out.end_time - out.time_in_mode[Mode::Rest.index()];
            let score = (!out.overturned, modes, moving);
            // lexicographic: standing, then modes, then time moving
            let better = best.as_ref().is_none_or(|(s, _)| score > *s);
            if better {
                best = Some((score, i));
            }
        }
        let index = best.map_or(0, |(_, i)| i);
        let record = record_at(index)?;
        let mut history = History::default();
        let outcome = simulate(&analysis, &record, &solver, Some(&mut history))?;

        let rows = &history.rows;
        let end = outcome.end_time;
        let mut intervals: Vec<ModeInterval> = Vec::new();
        for (k, r) in rows.iter().enumerate() {
            let t1 = rows.get(k + 1).map_or(end, |n| n.t);
            if t1 <= r.t {
                continue;
            }
            match intervals.last_mut() {
                Some(last) if last.mode == r.mode && last.t1 >= r.t => last.t1 = t1,
                _ => intervals.push(ModeInterval {
                    t0: r.t,
                    t1,
                    mode: r.mode,
                }),
            }
        }
        let v_scale = (g * block.r).sqrt();
        let impacts: Vec<f64> = rows
            .windows(2)
            .filter(|w| {
                let (a, b) = (&w[0], &w[1]);
                a.event && b.event && a.t == b.t && {
                    let jump = (b.theta_dot - a.theta_dot).abs() * block.r
                        + (b.x_dot - a.x_dot).abs()
                        + (b.y_dot - a.y_dot).abs();
                    jump > IMPACT_JUMP * v_scale
                }
            })
            .map(|w| w[0].t)
            .collect();

        let active: Vec<&ModeInterval> = intervals
            .iter()
            .filter(|iv| iv.mode != Mode::Rest)
            .collect();
        let window = match (active.first(), active.last()) {
            (Some(a), Some(b)) => (
                (a.t0 - ZOOM_PAD_S).max(0.0),
                (b.t1 + ZOOM_PAD_S).min(record.duration()),
            ),
            _ => (0.0, record.duration()),
        };
        let inside = |t: f64| t >= window.0 && t <= window.1;
        let intervals = intervals
            .iter()
            .filter(|iv| iv.t1 > window.0 && iv.t0 < window.1)
            .map(|iv| ModeInterval {
                t0: iv.t0.max(window.0),
                t1: iv.t1.min(window.1),
                mode: iv.mode,
            })
            .collect();
        let acc = record
            .acc
            .iter()
            .enumerate()
            .map(|(k, a)| (k as f64 * record.dt, a / g))
            .filter(|&(t, _)| inside(t))
            .collect();
        let theta = rows
            .iter()
            .filter(|r| inside(r.t))
            .map(|r| (r.t, r.theta / block.theta_c))
            .collect();
        let title = format!(
            "H/B = {}, 2B = {} m, e = {}, μₛ = {}, μₖ = {}: {} at {} g",
            tick_label(case.aspect),
            tick_label(case.width),
            tick_label(case.restitution),
            tick_label(case.mu_s),
            tick_label(case.mu_k),
            label(index),
            tick_label(case.pga),
        );
        Ok(HistoryFigure {
            title,
            window,
            acc,
            theta,
            intervals,
            impacts: impacts.into_iter().filter(|&t| inside(t)).collect(),
            record: index,
            outcome,
        })
    }
}

impl Figure for HistoryFigure {
    fn size_in(&self) -> (f64, f64) {
        (PAGE_WIDTH_IN, HEIGHT_IN)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB> {
        let mut entries: Vec<Entry> = Mode::ALL
            .iter()
            .map(|&m| Entry::new(Sample::Block(mode_colour(m)), m.name()))
            .collect();
        entries.push(Entry::new(Sample::Tick(BLACK), "impact"));
        let frame = Frame::new(root, style, &self.title, &entries, MARGINS)?;

        let (_, h) = frame.body.dim_in_pixel();
        let plot_h = h.saturating_sub(frame.x_area + 2 * frame.top);
        let (top, bottom) = frame.body.split_vertically(frame.top + plot_h * 2 / 5);
        let (t0, t1) = self.window;

        let panels = [
            (&top, "Ground acceleration (g)", &self.acc),
            (&bottom, "Rotation θ/θc", &self.theta),
        ];
        for (k, (area, label, data)) in panels.into_iter().enumerate() {
            let last = k == 1;
            frame.heading(area, label)?;
            let peak = data.iter().fold(0.0_f64, |m, &(_, y)| m.max(y.abs()));
            let y_max = if peak > 0.0 { 1.12 * peak } else { 1.0 };
            let mut chart = frame
                .chart(area, last)
                .build_cartesian_2d(t0..t1, -y_max..y_max)?;
            chart.draw_series(self.intervals.iter().map(|iv| {
                Rectangle::new(
                    [(iv.t0, -y_max), (iv.t1, y_max)],
                    mode_colour(iv.mode).filled(),
                )
            }))?;
            let mut mesh = layout::mesh(&mut chart, style);
            mesh.x_labels(10).y_labels(5).disable_x_mesh();
            if last {
                mesh.x_desc("Time (s)");
            }
            mesh.draw()?;
            if last {
                // impacts: a rug of short ticks along the top edge
                let tick = 0.12 * y_max;
                let tick_style = BLACK.stroke_width(style.ipx(layout::RUG_PT));
                chart.draw_series(self.impacts.iter().map(|&t| {
                    plotters::prelude::PathElement::new(
                        vec![(t, y_max), (t, y_max - tick)],
                        tick_style,
                    )
                }))?;
            }
            curve!(
                chart,
                data.iter().copied(),
                BLACK.stroke_width(style.ipx(super::style::LINE_PT)),
                Dash::Solid,
                style
            );
        }
        Ok(())
    }
}
