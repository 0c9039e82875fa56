//! The paper's figures: its Tables 1–3 beside this study's means in the
//! friction-demand and restitution figures, its illustrative response
//! history, and the trend of overturning with e (`e_trend`).
//!
//! `e_trend` answers the paper's claim that restitution stabilises the
//! block. Against e, the fraction of runs that overturned or lifted off (the
//! paper's convention), pooled over the study's H/B and PGA levels under
//! infinite friction, in three series, each with its Cochran–Armitage trend
//! test in the legend:
//!
//! - this study's physics (flat: a rock impact's bounces end the ring-down
//!   at Housner's e = 0 ratio whatever e is);
//! - the same records solved with the paper's program rule
//!   (`[solver] rock_impact = "rock"`: rocking continues after a rock
//!   impact with ω₂/ω₁ = 1 − 1.5(1+e)sin²θc), which falls with e;
//! - the paper's published counts (Tables 1–3), which fall too.
//!
//! So the figure shows the stabilisation, where it comes from (the
//! program's rule), and that physics does not produce it. At each e the
//! three series are drawn a little apart ([`DODGE`]), so that no 95 %
//! whisker hides another.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingBackend};
use plotters::style::{BLACK, Color};

use super::check::{RESTITUTIONS, ReadingResult, cell_restitution, paper_totals, solve_study};
use super::tables::{self, TABLES, readings};
use crate::case::Param;
use crate::error::{Error, Result};
use crate::figures::MIN_MODE_S;
use crate::figures::layout::{self, Dash, Entry, Frame, Margins, Marker, Sample, curve, markers};
use crate::figures::style::{LINE_PT, PAGE_WIDTH_IN, PALETTE, Style, tick_label};
use crate::figures::{
    DrawResult, Figure, FigureOptions, FiguresReport, HistoryCase, HistoryChoice, StudyFigures,
    save, trend_text,
};
use crate::motion::{Floor, SynthesisSettings};
use crate::outcome::{Mode, Outcome};
use crate::solver::{Friction, RockImpact, SolverSettings};
use crate::spec::{Intensity, Motions, Study};

/// The paper's illustrative response history: H/B 2, 2B 0.5 m, e 0.6 under
/// Coulomb friction μs 0.6 (above B/H = 0.5: the block rocks from rest, and
/// slides only after impacts and during slide-rock), μk 0.4, at 0.9 g; the
/// run with the most modes among the first 25 records of ensemble `seed` of
/// `motion` ([`most_modes`]). The 25 analyses are solved through the
/// ensemble primitive ([`super::check::solve_study`]); the figure solves
/// the chosen one again, with its time history.
///
/// Errors: a record or analysis that cannot be made.
pub fn history_case(motion: &SynthesisSettings, seed: u64) -> Result<HistoryCase> {
    let mut case = HistoryCase {
        aspect: 2.0,
        width: 0.5,
        restitution: 0.6,
        mu_s: 0.6,
        mu_k: 0.4,
        pga: 0.9,
        seed,
        records: 25,
        record: 0,
    };
    // the case as a study of one block at one PGA: its units are its records
    let mut study = Study::shenton_jones();
    study.motions = Motions::Synthetic {
        settings: motion.clone(),
        seed,
        records: case.records as usize,
        pairs: None,
    };
    study.g = motion.g;
    study.aspects = vec![Param::Fixed(case.aspect)];
    study.widths = vec![Param::Fixed(case.width)];
    study.restitutions = vec![Param::Fixed(case.restitution)];
    study.frictions = vec![Param::Fixed(Friction::Coulomb {
        mu_s: case.mu_s,
        mu_k: case.mu_k,
    })];
    study.intensity = Intensity::Pga(vec![case.pga]);
    study.uncertainty = None;
    study.floor = Floor::default();
    // the figure's solver
    study.solver = SolverSettings::default();
    let runs = solve_study(&study, |unit, _, _, o| (unit.record as u64, o.clone()))?;
    case.record = most_modes(&runs);
    Ok(case)
}

/// The record of `runs` (record, outcome) that shows the most modes (each
/// for at least [`MIN_MODE_S`]), preferring runs that do not overturn and
/// then the longest time moving; ties go to the lowest record.
pub fn most_modes(runs: &[(u64, Outcome)]) -> u64 {
    let mut best: Option<((bool, usize, f64), u64)> = None;
    for (i, out) in runs {
        let modes = out
            .time_in_mode
            .iter()
            .filter(|&&t| t >= MIN_MODE_S)
            .count();
        let moving = out.end_time - out.time_in_mode[Mode::Rest.index()];
        // lexicographic: standing, then modes, then time moving
        let score = (!out.overturned, modes, moving);
        let better = best
            .as_ref()
            .is_none_or(|(s, b)| score > *s || (score == *s && *i < *b));
        if better {
            best = Some((score, *i));
        }
    }
    best.map_or(0, |(_, i)| i)
}

/// Draws the figures of the paper's study folder `dir` into `out`: the
/// generic figures with the paper's values beside ours and its history
/// block, then `e_trend` (which solves the study's infinite-friction cases
/// once more under the paper's program rule).
pub fn draw(
    dir: &Path,
    out: &Path,
    options: &FigureOptions,
    study: &Study,
) -> Result<FiguresReport> {
    let mut options = options.clone();
    if options.history == HistoryChoice::Chosen && options.record_files.is_empty() {
        options.history = HistoryChoice::Case(history_case(&options.synthesis, options.seed)?);
    }
    let mut figures = StudyFigures::compute(dir, &options)?;
    add_tables(&mut figures);
    let mut report = figures.write(out, options.format)?;
    let (es, aspects) = e_trend_grid(study)?;
    let rule = rock_rule_counts(study, &es)?;
    let e_trend = ETrendFigure::of_study(study, &figures, (&es, &aspects), rule);
    let path = out.join(format!("e_trend.{}", options.format.extension()));
    save(&e_trend, &path)?;
    report.written.push(path);
    Ok(report)
}

/// Puts the paper's table values beside this study's in the
/// friction-demand and restitution figures.
pub fn add_tables(figures: &mut StudyFigures) {
    if let Some(f) = &mut figures.friction_demand {
        let aspects: Vec<f64> = figures
            .data
            .outcomes
            .iter()
            .filter_map(|r| r.case.aspect.fixed())
            .collect();
        let has = |a: f64| aspects.contains(&a);
        for s in &mut f.motion {
            s.reference = TABLES
                .iter()
                .filter(|p| Param::Fixed(p.pga) == s.at && has(p.aspect))
                .filter_map(|p| p.mu_motion.map(|m| (1.0 / p.aspect, m)))
                .collect();
        }
        // The paper's μ_imp is its eq. (5): panel (c) when there is one.
        let target = if f.eq5.is_empty() {
            &mut f.impact
        } else {
            &mut f.eq5
        };
        for s in target.iter_mut() {
            s.reference = TABLES
                .iter()
                .filter(|p| Param::Fixed(p.restitution) == s.at && has(p.aspect))
                .filter_map(|p| p.mu_impact.map(|m| (1.0 / p.aspect, m)))
                .collect();
        }
        f.reference_label = Some("paper, Tables 1–3".to_string());
    }
    if let Some(f) = &mut figures.restitution {
        let e_max = f.restitutions.last().copied().unwrap_or(1.0);
        for panel in &mut f.panels {
            let Some(aspect) = panel.aspect.fixed() else {
                continue;
            };
            panel.reference = TABLES
                .iter()
                .filter(|p| p.aspect == aspect && p.restitution <= e_max)
                .filter_map(|p| {
                    let il = f.levels.iter().position(|&l| l == p.pga)?;
                    Some((
                        il,
                        p.restitution,
                        p.overturned as f64 / tables::RECORDS as f64,
                        p.theta_max_over_theta_c,
                    ))
                })
                .collect();
        }
        f.reference_label = Some("paper (μ = ∞)".to_string());
        // The paper's trend beside ours, over the study's blocks and levels.
        let aspects: Vec<f64> = f.panels.iter().filter_map(|p| p.aspect.fixed()).collect();
        let (k, n) = published_counts(&aspects, &f.all_levels, &f.restitutions);
        let has_paper = f.panels.iter().any(|p| !p.reference.is_empty());
        if let Some(theirs) =
            trend_text(&k, &n, &f.restitutions).filter(|_| has_paper && f.has_trend)
        {
            f.title.push_str(&format!(", paper's {theirs}"));
        }
    }
}

/// The paper's counts per e (overturned or lifted off, of its runs) over
/// `aspects` and `levels`: a cell it left out (H/B 2 at 0.3 g, no rocking)
/// counts its 25 runs with none overturned.
fn published_counts(aspects: &[f64], levels: &[f64], es: &[f64]) -> (Vec<u64>, Vec<u64>) {
    let runs = (aspects.len() * levels.len()) as u64 * tables::RECORDS as u64;
    es.iter()
        .map(|&e| {
            let k: u64 = TABLES
                .iter()
                .filter(|p| p.restitution == e && aspects.contains(&p.aspect))
                .filter(|p| levels.contains(&p.pga))
                .map(|p| u64::from(p.overturned))
                .sum();
            (k, runs)
        })
        .unzip()
}

/// Figure height (in).
const HEIGHT_IN: f64 = 3.2;
/// How far apart the e-trend's three series are drawn at one e, as a
/// fraction of the largest e.
pub const DODGE: f64 = 0.015;
/// Panel margins: 30 pt for the y tick labels, 10 pt on the right.
const MARGINS: Margins = Margins::new(30.0, 10.0);

/// One series of the e-trend figure: counts per e and their trend.
#[derive(Clone, Debug, PartialEq)]
pub struct ETrendSeries {
    /// Legend label, with the trend test.
    pub label: String,
    /// (e, overturned or lifted off, runs), e ascending.
    pub counts: Vec<(f64, u64, u64)>,
}

/// The trend of overturning with e under physics, under the paper's
/// program rule and in the paper's counts (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct ETrendFigure {
    /// Title.
    pub title: String,
    /// This study (physics), the paper's program rule, the paper's counts.
    pub series: [ETrendSeries; 3],
}

impl ETrendFigure {
    /// The figure of three series of counts per e, in their order: the
    /// physics (labelled `physics`), the paper's program rule and the
    /// paper's tables, each labelled with its Cochran–Armitage trend test.
    fn of_counts(title: String, physics: &str, series: [Vec<(f64, u64, u64)>; 3]) -> ETrendFigure {
        let label = |what: &str, c: &[(f64, u64, u64)]| {
            let k: Vec<u64> = c.iter().map(|x| x.1).collect();
            let n: Vec<u64> = c.iter().map(|x| x.2).collect();
            let es: Vec<f64> = c.iter().map(|x| x.0).collect();
            match trend_text(&k, &n, &es) {
                Some(t) => format!("{what}: {t}"),
                None => what.to_string(),
            }
        };
        let names = [
            physics,
            "paper's program rule (rock_impact = \"rock\")",
            "paper, Tables 1–3",
        ];
        let [a, b, c] = series;
        let one = |what: &str, counts: Vec<(f64, u64, u64)>| ETrendSeries {
            label: label(what, &counts),
            counts,
        };
        ETrendFigure {
            title,
            series: [one(names[0], a), one(names[1], b), one(names[2], c)],
        }
    }

    /// The three series for `study` (the paper's) over its e values `es`
    /// and H/B values `aspects` ([`e_trend_grid`]): this study's counts
    /// from its figures' data, the program rule's counts `rule` (the
    /// study's infinite-friction cases solved again with `rock_impact =
    /// "rock"`, [`rock_rule_counts`]), and the paper's tables over the same
    /// blocks, levels and e.
    pub fn of_study(
        study: &Study,
        figures: &StudyFigures,
        (es, aspects): (&[f64], &[f64]),
        rule: Vec<(f64, u64, u64)>,
    ) -> ETrendFigure {
        let infinite = Param::Fixed(Friction::Infinite);
        let levels = study.intensity.levels().to_vec();
        // Physics: this study's own runs.
        let ours: Vec<(f64, u64, u64)> = es
            .iter()
            .map(|&e| {
                let (k, n) = figures
                    .data
                    .outcomes
                    .iter()
                    .filter(|r| {
                        r.case.restitution == Param::Fixed(e) && r.case.friction == infinite
                    })
                    .fold((0, 0), |(k, n), r| {
                        (k + u64::from(r.overturned || r.uplifted), n + 1)
                    });
                (e, k, n)
            })
            .collect();
        let (pk, pn) = published_counts(aspects, &levels, es);
        let paper: Vec<(f64, u64, u64)> = es
            .iter()
            .zip(pk.iter().zip(&pn))
            .map(|(&e, (&k, &n))| (e, k, n))
            .collect();
        let runs = ours.first().map_or(0, |c| c.2);
        let title = format!(
            "Overturned or lifted off against e, μ = ∞, {runs} runs per e (H/B {}; {} PGA \
             levels), 95 % binomial intervals; trend tests Cochran–Armitage",
            aspects
                .iter()
                .map(|a| tick_label(*a))
                .collect::<Vec<_>>()
                .join(", "),
            levels.len()
        );
        Self::of_counts(title, "physics (this study)", [ours, rule, paper])
    }
}

impl ETrendFigure {
    /// The figure of `rockfrag paper`'s check: the rad/s grid's ensembles
    /// under the physics and under the paper's program rule, pooled over the
    /// ensembles, beside the paper's counts; `None` if the check has not
    /// both.
    pub fn from_check(results: &[ReadingResult]) -> Option<ETrendFigure> {
        let grid = readings().into_iter().find(|r| r.name == "rad/s grid")?;
        let pooled = |rule: RockImpact| -> Option<Vec<(f64, u64, u64)>> {
            let r = results
                .iter()
                .find(|r| r.reading.settings == grid.settings && r.rock_impact == rule)?;
            let mut counts: Vec<(f64, u64, u64)> =
                RESTITUTIONS.iter().map(|&e| (e, 0, 0)).collect();
            for cells in &r.ensembles {
                for (ci, cell) in cells.iter().enumerate() {
                    let ei = cell_restitution(ci);
                    counts[ei].1 += u64::from(cell.overturned);
                    counts[ei].2 += u64::from(cell.runs);
                }
            }
            Some(counts)
        };
        let ours = pooled(RockImpact::Bounce)?;
        let rule = pooled(RockImpact::Rock)?;
        let k = results.first().map_or(0, |r| r.ensembles.len());
        let paper: Vec<(f64, u64, u64)> = RESTITUTIONS
            .iter()
            .zip(paper_totals())
            .map(|(&e, k)| (e, u64::from(k), 300))
            .collect();
        let title = format!(
            "Overturned or lifted off against e, μ = ∞, the paper's study on the rad/s grid, \
             {k} ensembles ({} runs per e), 95 % binomial intervals; trend tests \
             Cochran–Armitage",
            ours.first().map_or(0, |c| c.2)
        );
        Some(Self::of_counts(title, "physics", [ours, rule, paper]))
    }
}

/// The e and H/B values of `study` for `e_trend`.
///
/// Errors: a study without infinite friction or with a drawn e or H/B.
fn e_trend_grid(study: &Study) -> Result<(Vec<f64>, Vec<f64>)> {
    let es: Option<Vec<f64>> = study.restitutions.iter().map(|e| e.fixed()).collect();
    let aspects: Option<Vec<f64>> = study.aspects.iter().map(|a| a.fixed()).collect();
    let (Some(es), Some(aspects)) = (es, aspects) else {
        return Err(Error::invalid(
            "e_trend",
            "(drawn e or H/B)",
            "a study over fixed e and H/B",
        ));
    };
    if !study.frictions.contains(&Param::Fixed(Friction::Infinite)) {
        return Err(Error::invalid(
            "e_trend",
            "(no infinite friction)",
            "a study with infinite friction",
        ));
    }
    Ok((es, aspects))
}

/// The study's infinite-friction cases solved on its records with the
/// paper's program rule, through the ensemble primitive
/// ([`super::check::solve_study`]): (e, overturned or lifted off, runs) per
/// e of `es`. Counts are summed, so the result does not depend on the
/// threads.
///
/// Errors: a record or analysis that cannot be made.
fn rock_rule_counts(study: &Study, es: &[f64]) -> Result<Vec<(f64, u64, u64)>> {
    let mut rule = study.clone();
    rule.frictions = vec![Param::Fixed(Friction::Infinite)];
    rule.uncertainty = None;
    rule.solver.rock_impact = RockImpact::Rock;
    let fell = solve_study(&rule, |_, _, own, o| {
        (own.restitution, o.overturned || o.uplifted)
    })?;
    let mut counts: Vec<(f64, u64, u64)> = es.iter().map(|&e| (e, 0, 0)).collect();
    for (e, fell) in fell {
        let Some(c) = counts.iter_mut().find(|c| c.0 == e) else {
            return Err(Error::invalid("e_trend", e, "one of the study's e"));
        };
        c.1 += u64::from(fell);
        c.2 += 1;
    }
    Ok(counts)
}

impl Figure for ETrendFigure {
    fn size_in(&self) -> (f64, f64) {
        (PAGE_WIDTH_IN, HEIGHT_IN)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB> {
        let looks = [
            (PALETTE[0], Dash::Solid, Marker::Circle, true),
            (PALETTE[1], Dash::Dashed, Marker::Circle, false),
            (BLACK, Dash::Short, Marker::Square, false),
        ];
        let entries: Vec<Entry> = self
            .series
            .iter()
            .zip(looks)
            .map(|(s, (c, d, m, f))| Entry::new(Sample::LinePoint(c, d, m, f), s.label.clone()))
            .collect();
        let frame = Frame::new(root, style, &self.title, &entries, MARGINS)?;
        let fraction = |c: &(f64, u64, u64)| (c.0, c.1 as f64 / c.2.max(1) as f64);
        // 95 % binomial half-width of a count.
        let half = |c: &(f64, u64, u64)| {
            let p = fraction(c).1;
            1.96 * (p * (1.0 - p) / c.2.max(1) as f64).sqrt()
        };
        // The y axis spans the points and their intervals, in steps of 0.05.
        let (lo, hi) = self
            .series
            .iter()
            .flat_map(|s| s.counts.iter())
            .map(|c| (fraction(c).1 - half(c), fraction(c).1 + half(c)))
            .fold((1.0_f64, 0.0_f64), |(l, h), (a, b)| (l.min(a), h.max(b)));
        let y_lo = ((lo - 0.02) / 0.05).floor().max(0.0) * 0.05;
        let y_hi = (((hi + 0.02) / 0.05).ceil() * 0.05)
            .min(1.0)
            .max(y_lo + 0.1);
        let e_max = self.series[0].counts.last().map_or(1.0, |c| c.0).max(0.1);
        frame.heading(
            &frame.body,
            "Fraction overturned or lifted off (paper's convention)",
        )?;
        let mut chart = frame
            .chart(&frame.body, true)
            .build_cartesian_2d(-0.04 * e_max..e_max * 1.04 + 0.01, y_lo..y_hi)?;
        let mut mesh = layout::mesh(&mut chart, style);
        mesh.x_labels(6)
            .y_labels(6)
            .x_desc("Coefficient of restitution e")
            .draw()?;
        // The three series at one e are set a little apart (dodged), so
        // that no whisker hides another.
        let dodge = |i: usize| (i as f64 - 1.0) * DODGE * e_max;
        // Lines and 95 % binomial whiskers (±1.96 √(p(1−p)/n)) first, then
        // the markers in reverse order, so that a filled marker on top of a
        // hollow one at the same place leaves a ring showing both.
        for (i, (s, (colour, dash, _, _))) in self.series.iter().zip(looks).enumerate() {
            let points: Vec<(f64, f64)> = s
                .counts
                .iter()
                .map(|c| (fraction(c).0 + dodge(i), fraction(c).1))
                .collect();
            let line = colour.stroke_width(style.ipx(LINE_PT));
            curve!(chart, points, line, dash, style);
            for c in &s.counts {
                let (e, p) = fraction(c);
                let h = half(c);
                chart.draw_series(std::iter::once(plotters::prelude::PathElement::new(
                    vec![
                        (e + dodge(i), (p - h).max(y_lo)),
                        (e + dodge(i), (p + h).min(y_hi)),
                    ],
                    line,
                )))?;
            }
        }
        for (i, (s, (colour, _, marker, filled))) in self.series.iter().zip(looks).enumerate().rev()
        {
            let points: Vec<(f64, f64)> = s
                .counts
                .iter()
                .map(|c| (fraction(c).0 + dodge(i), fraction(c).1))
                .collect();
            markers!(chart, points, colour, marker, filled, style);
        }
        Ok(())
    }
}
