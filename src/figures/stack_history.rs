//! The history figure of a stack's case: one of the study's analyses of a
//! stack (chosen as a block's is, see `figures::history`), solved again
//! by the stack solver with its time history, on the motion the study
//! used for that (level, record). Three panels share the time axis:
//!
//! 1. the acceleration the stack feels (the ground's, or the floor's);
//! 2. every body's rotation φ relative to the face it stands on, over its
//!    own θc, one colour per body (bottom first: base, [middle], top); a
//!    body that overturns is marked where its curve ends (its |φ| reached
//!    π/2, or the body under it overturned and it fell with it), and the
//!    legend gives the time;
//! 3. each interface's slip: the body's footprint (its pivot corner while
//!    rocking) along the face below, from its place at the start, in mm
//!    (the quantity of `slip_max`; not drawn in flight, where there is no
//!    contact).
//!
//! The time axis is zoomed to the active part of the record. The modes are
//! not shaded (one shading per body would hide the curves) and the impacts
//! are not marked.

use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingBackend};
use plotters::style::{BLACK, Color};

use super::data::StudyData;
use super::figure::{DrawResult, Figure};
use super::history::{ChosenRun, Drawn, HistoryFigure, HistorySource, acc_label, record_name};
use super::layout::{self, Dash, Entry, Frame, Margins, Marker, Sample, curve, markers};
use super::style::{LINE_PT, PAGE_WIDTH_IN, PALETTE, Style, tick_label};
use crate::case::Case;
use crate::error::{Error, Result};
use crate::io_util::sig3;
use crate::outcome::{Mode, Slot};
use crate::solver::Friction;
use crate::solver::stack::{Stack, StackHistory, StackOutcome, simulate_stack};
use crate::study::{CommandBlock, Source};
use std::path::Path;

/// Figure height (in).
const HEIGHT_IN: f64 = 4.4;
/// Panel margins: 34 pt for the y tick labels, 10 pt on the right.
const MARGINS: Margins = Margins::new(34.0, 10.0);
/// Time shown before the first motion and after the last (s).
const ZOOM_PAD_S: f64 = 1.0;
/// Smallest half-range of the slip panel (mm): a slip of rounding noise is
/// drawn flat, not blown up to fill the panel (and its tick labels stay
/// short).
const MIN_SLIP_MM: f64 = 1.0;

/// A study's history figure: of a block, or of a stack (its case a
/// stack's).
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum StudyHistory {
    /// One block's history.
    Block(Box<HistoryFigure>),
    /// Every body of a stack.
    Stack(Box<StackHistoryFigure>),
}

/// The history figure of the study folder `dir` ([`HistoryFigure::from_study`]),
/// a stack's drawn here when the analysis chosen is a stack's.
pub(crate) fn study_history(
    dir: &Path,
    data: &StudyData,
    options: &HistorySource,
) -> Result<StudyHistory> {
    Ok(match HistoryFigure::from_study(dir, data, options)? {
        Drawn::Block(figure) => StudyHistory::Block(figure),
        Drawn::Stack(chosen) => StudyHistory::Stack(Box::new(StackHistoryFigure::of_chosen(
            dir, options, &chosen,
        )?)),
    })
}

/// One body's curves.
#[derive(Clone, Debug, PartialEq)]
pub struct BodySeries {
    /// Its place in the stack: `base`, `middle` or `top`.
    pub name: String,
    /// Legend text: its place, what it stands on (its φ is relative to
    /// that face), its size and, if it overturned, when.
    pub label: String,
    /// φ/θc (s, –) inside the window, up to its overturning: every row of
    /// the history (its peaks included) while the body is in the scene.
    pub phi: Vec<(f64, f64)>,
    /// Slip along the face below (s, mm) inside the window, in stretches of
    /// contact (none in flight).
    pub slip: Vec<Vec<(f64, f64)>>,
    /// Where it overturned: (time, φ/θc at its last row).
    pub overturn: Option<(f64, f64)>,
}

/// The data of a stack's history figure.
#[derive(Clone, Debug, PartialEq)]
pub struct StackHistoryFigure {
    /// Title: the stack, its interfaces, the record and the level.
    pub title: String,
    /// Heading of the upper panel: the acceleration the stack feels.
    pub acc_label: String,
    /// Heading of the middle panel: φ/θc (each body's rotation relative to
    /// the face it stands on) and why this run is drawn.
    pub phi_label: String,
    /// Shown time window (s).
    pub window: (f64, f64),
    /// Ground (or floor) acceleration (s, g) inside the window.
    pub acc: Vec<(f64, f64)>,
    /// Every body, bottom first.
    pub bodies: Vec<BodySeries>,
    /// Index of the chosen record.
    pub record: u64,
    /// The re-solved analysis's outcome (the study's row's, the same solve).
    pub outcome: StackOutcome,
    /// The command that solves the drawn analysis again and prints its row
    /// of `outcomes.csv` ([`crate::study::simulate_command`] with `--csv`).
    pub command: Option<String>,
}

impl StackHistoryFigure {
    /// The history of the study's analysis `chosen` (a stack's case),
    /// solved again with the stack solver on the study's motion for its
    /// (level, record).
    ///
    /// Errors: no study (a stack is known only from its spec), or a record
    /// or analysis that cannot be made.
    pub(super) fn of_chosen(
        dir: &Path,
        options: &HistorySource,
        chosen: &ChosenRun,
    ) -> Result<Self> {
        let id = Case::from(chosen.own).id();
        let Some(study) = options.study else {
            return Err(Error::invalid(
                "history case",
                id,
                "a block's case: a stack is known only from its study's spec (the folder's \
                 manifest is missing)",
            ));
        };
        let drawn = chosen.own.stack.and_then(|name| study.stack_draws(name));
        let stack = match drawn {
            // a stack that draws: this analysis's own draws, as the run made
            // them (the study's stack is only their nominal values)
            Some(_) => {
                let again = crate::study::reanalyse(study, &id, chosen.level, chosen.record, None)?;
                match again.analysed.analysis {
                    Some(crate::case::Scene::Stack(stack)) => stack,
                    _ => {
                        return Err(Error::invalid(
                            "history case",
                            id,
                            "an analysis whose draws make a valid stack (its row failed)",
                        ));
                    }
                }
            }
            None => chosen
                .own
                .stack
                .and_then(|name| study.stacks.iter().find(|s| s.name == name))
                .map(|s| s.stack.clone())
                .ok_or_else(|| Error::invalid("history case", id, "a stack of the study"))?,
        };
        if !study.intensity.levels().contains(&chosen.level) {
            return Err(Error::invalid(
                "history level",
                chosen.level,
                "a study's level",
            ));
        }
        let motion = Source::new(study)?.motion(study, chosen.level, chosen.record)?;
        let record = &motion.felt;
        let mut history = StackHistory::default();
        let outcome = simulate_stack(&stack, record, &study.solver, Some(&mut history))?;

        // a stack of the grid as the spec gave it; a drawn one to three
        // figures (all its digits are in outcomes.csv)
        let num: fn(f64) -> String = if drawn.is_some() {
            drawn_value
        } else {
            tick_label
        };
        let name = chosen.own.stack.map_or_else(String::new, |n| n.to_string());
        let title = format!(
            "Stack {name}: {}; {}; {} at {}",
            bodies_text(&stack, num),
            interfaces_text(&stack, num),
            record_name(options, chosen.record),
            chosen.level_text
        );
        let rows = &history.rows;
        let n = stack.bodies.len();
        // active: a body still in the scene out of rest
        let active = |r: &crate::solver::stack::StackRow| {
            (0..n).any(|k| r.phi[k].is_finite() && r.mode[k] != Mode::Rest)
        };
        let first = rows.iter().position(active);
        let last = rows.iter().rposition(active);
        let end = rows.last().map_or(record.duration(), |r| r.t);
        let window = match (first, last) {
            (Some(a), Some(b)) => (
                (rows[a].t - ZOOM_PAD_S).max(0.0),
                // the analysis may end after the record (its free motion)
                (rows[(b + 1).min(rows.len() - 1)].t + ZOOM_PAD_S).min(end.max(record.duration())),
            ),
            _ => (0.0, end.max(record.dt)),
        };
        let inside = |t: f64| t >= window.0 && t <= window.1;
        let g = stack.g;
        let acc = record
            .acc
            .iter()
            .enumerate()
            .map(|(k, a)| (k as f64 * record.dt, a / g))
            .filter(|&(t, _)| inside(t))
            .collect();
        let bodies = (0..n)
            .map(|k| {
                let body = &stack.bodies[k];
                // θc = atan(B/H), as the solver has it
                let theta_c = crate::detmath::atan((0.5 * body.width) / (0.5 * body.height));
                let phi: Vec<(f64, f64)> = rows
                    .iter()
                    .filter(|r| inside(r.t) && r.phi[k].is_finite())
                    .map(|r| (r.t, r.phi[k] / theta_c))
                    .collect();
                let mut slip: Vec<Vec<(f64, f64)>> = Vec::new();
                let mut open = false;
                for r in rows.iter().filter(|r| inside(r.t)) {
                    if r.slip[k].is_finite() {
                        if !open {
                            slip.push(Vec::new());
                            open = true;
                        }
                        slip.last_mut()
                            .expect("a stretch was opened")
                            .push((r.t, 1e3 * r.slip[k]));
                    } else {
                        open = false;
                    }
                }
                let b = &outcome.bodies[k];
                let over = b.overturn_time.map(|t| {
                    let at = phi.last().map_or(0.0, |p| p.1);
                    (t, at)
                });
                let slot = Slot::of(k, n).name().to_string();
                // what its φ is relative to: the face it stands on
                let on = match k {
                    0 => "the ground".to_string(),
                    _ => format!("the {}", Slot::of(k - 1, n).name()),
                };
                let mut label = format!(
                    "{slot} on {on} ({} × {} m)",
                    num(body.width),
                    num(body.height)
                );
                if let Some((t, _)) = over {
                    let fell = k > 0 && outcome.bodies[k - 1].overturn_time == Some(t);
                    label.push_str(&format!(
                        ", overturned at {} s{}",
                        sig(t),
                        if fell { " with the body below" } else { "" }
                    ));
                }
                BodySeries {
                    name: slot,
                    label,
                    phi,
                    slip,
                    overturn: over,
                }
            })
            .collect();
        // `simulate --study` gives a stack's analysis as its row (--csv)
        let command = crate::study::case_of(study, &chosen.own).map(|(case, _)| {
            let id = case.id();
            let at = CommandBlock::Case(&id);
            let command = crate::study::simulate_command(dir, chosen.level, chosen.record, at);
            format!("{command} --csv")
        });
        Ok(StackHistoryFigure {
            title,
            acc_label: acc_label(options),
            phi_label: format!("Rotation φ/θc: {}", chosen.why),
            window,
            acc,
            bodies,
            record: chosen.record as u64,
            outcome,
            command,
        })
    }
}

/// `t` to three decimals, for a legend.
fn sig(t: f64) -> String {
    tick_label((t * 1000.0).round() / 1000.0)
}

/// A drawn value for a title or legend: three significant figures, without
/// trailing zeros.
fn drawn_value(x: f64) -> String {
    tick_label(sig3(x).parse().unwrap_or(x))
}

/// The bodies for a title: `base 0.6 × 1.0 m, top 0.3 × 1.2 m` (2B × 2H),
/// with their relative masses when they are not of one density; values
/// formatted by `num`.
fn bodies_text(stack: &Stack, num: fn(f64) -> String) -> String {
    let n = stack.bodies.len();
    let density = |b: &crate::solver::stack::StackBody| b.mass / (b.width * b.height);
    let d0 = density(&stack.bodies[0]);
    let same = stack
        .bodies
        .iter()
        .all(|b| (density(b) - d0).abs() <= 1e-12 * d0);
    let list: Vec<String> = stack
        .bodies
        .iter()
        .enumerate()
        .map(|(k, b)| {
            let mut s = format!(
                "{} {} × {} m",
                Slot::of(k, n).name(),
                num(b.width),
                num(b.height)
            );
            if !same {
                s.push_str(&format!(" (mass {})", num(b.mass)));
            }
            if b.offset != 0.0 {
                s.push_str(&format!(", offset {} m", num(b.offset)));
            }
            s
        })
        .collect();
    format!("2B × 2H {}", list.join(", "))
}

/// The interfaces for a title: `e = 0, μ = ∞ at both interfaces`, or each
/// named by the body standing on it (`under the base: …; under the top: …`).
fn interfaces_text(stack: &Stack, num: fn(f64) -> String) -> String {
    let text = |i: &crate::solver::stack::StackInterface| {
        let mu = match i.friction {
            Friction::Infinite => "μ = ∞".to_string(),
            Friction::Coulomb { mu_s, mu_k } => format!("μₛ = {}, μₖ = {}", num(mu_s), num(mu_k)),
        };
        format!("e = {}, {mu}", num(i.restitution))
    };
    let all: Vec<String> = stack.interfaces.iter().map(text).collect();
    let n = all.len();
    if all.iter().all(|t| *t == all[0]) {
        let at = if n == 2 {
            "both interfaces"
        } else {
            "every interface"
        };
        return format!("{} at {at}", all[0]);
    }
    all.iter()
        .enumerate()
        .map(|(k, t)| format!("under the {}: {t}", Slot::of(k, n).name()))
        .collect::<Vec<_>>()
        .join("; ")
}

impl Figure for StackHistoryFigure {
    fn size_in(&self) -> (f64, f64) {
        (PAGE_WIDTH_IN, HEIGHT_IN)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB> {
        let colour = |k: usize| PALETTE[k % PALETTE.len()];
        let mut entries: Vec<Entry> = self
            .bodies
            .iter()
            .enumerate()
            .map(|(k, b)| Entry::new(Sample::Line(colour(k), Dash::Solid), b.label.clone()))
            .collect();
        if self.bodies.iter().any(|b| b.overturn.is_some()) {
            entries.push(Entry::new(
                Sample::Point(BLACK, Marker::Circle, false),
                "overturned",
            ));
        }
        let frame = Frame::new(root, style, &self.title, &entries, MARGINS)?;
        let (_, h) = frame.body.dim_in_pixel();
        let plot_h = h.saturating_sub(frame.x_area + 3 * frame.top);
        let (top, rest) = frame.body.split_vertically(frame.top + plot_h * 3 / 10);
        let (middle, bottom) = rest.split_vertically(frame.top + plot_h * 2 / 5);
        let (t0, t1) = self.window;
        let line = |k: usize| colour(k).stroke_width(style.ipx(LINE_PT));

        // (a) the acceleration
        frame.heading(&top, &self.acc_label)?;
        let peak = self.acc.iter().fold(0.0_f64, |m, &(_, y)| m.max(y.abs()));
        let y_max = if peak > 0.0 { 1.12 * peak } else { 1.0 };
        let mut chart = frame
            .chart(&top, false)
            .build_cartesian_2d(t0..t1, -y_max..y_max)?;
        let mut mesh = layout::mesh(&mut chart, style);
        mesh.x_labels(10).y_labels(5).disable_x_mesh();
        mesh.draw()?;
        curve!(
            chart,
            self.acc.iter().copied(),
            BLACK.stroke_width(style.ipx(LINE_PT)),
            Dash::Solid,
            style
        );

        // (b) every body's φ/θc, overturning marked
        frame.heading(&middle, &self.phi_label)?;
        let peak = self
            .bodies
            .iter()
            .flat_map(|b| b.phi.iter())
            .fold(0.0_f64, |m, &(_, y)| m.max(y.abs()));
        let y_max = if peak > 0.0 { 1.12 * peak } else { 1.0 };
        let mut chart = frame
            .chart(&middle, false)
            .build_cartesian_2d(t0..t1, -y_max..y_max)?;
        let mut mesh = layout::mesh(&mut chart, style);
        mesh.x_labels(10).y_labels(5).disable_x_mesh();
        mesh.draw()?;
        for (k, b) in self.bodies.iter().enumerate() {
            curve!(chart, b.phi.iter().copied(), line(k), Dash::Solid, style);
        }
        for (k, b) in self.bodies.iter().enumerate() {
            if let Some(p) = b.overturn {
                markers!(chart, [p], colour(k), Marker::Circle, false, style);
            }
        }

        // (c) every interface's slip (mm)
        frame.heading(
            &bottom,
            "Slip along the face below (mm): the footprint, or the pivot while rocking",
        )?;
        let peak = self
            .bodies
            .iter()
            .flat_map(|b| b.slip.iter().flatten())
            .fold(0.0_f64, |m, &(_, y)| m.max(y.abs()));
        let y_max = (1.12 * peak).max(MIN_SLIP_MM);
        let mut chart = frame
            .chart(&bottom, true)
            .build_cartesian_2d(t0..t1, -y_max..y_max)?;
        let mut mesh = layout::mesh(&mut chart, style);
        mesh.x_labels(10)
            .y_labels(5)
            .disable_x_mesh()
            .x_desc("Time (s)");
        mesh.draw()?;
        for (k, b) in self.bodies.iter().enumerate() {
            for stretch in &b.slip {
                curve!(chart, stretch.iter().copied(), line(k), Dash::Solid, style);
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::drawn_value;

    /// A drawn stack's title showed its draws to six figures
    /// (`top 0.377614 × 1 m`, `μₛ = 0.569688`); three are what a reader
    /// compares, without trailing zeros, with the figures' minus sign.
    #[test]
    fn drawn_values_are_titled_to_three_figures() {
        assert_eq!(drawn_value(0.377_614), "0.378");
        assert_eq!(drawn_value(0.569_688), "0.57");
        assert_eq!(drawn_value(1.0), "1");
        assert_eq!(drawn_value(12.345), "12.3");
        assert_eq!(drawn_value(-0.0524), "\u{2212}0.0524");
    }
}
