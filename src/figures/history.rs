//! A time history of one analysis: the acceleration the block feels (the
//! ground's, or the floor's for a study on a floor, whose heading names the
//! floor by its modes) and θ/θc against time, with the block's mode shaded
//! behind both panels and the impacts marked as a rug in a strip of its
//! own above the θ panel (clear of its gridlines). The time axis is zoomed
//! to the active part of the record. A run of bounces (a flight ended by an
//! impact that throws the block into the next) is drawn as the flights it
//! was, alternate ones in a darker shade ([`bounce_colour`]), not as one
//! long flight. The title names the block (a grid value as the spec gave
//! it, a drawn one to three figures) and the record; why this run is drawn
//! heads the θ panel, so that the title keeps to a line or two.
//!
//! The analysis is chosen, not hand-picked ([`HistoryChoice`]). By default
//! it is one of the study's own analyses ([`HistoryFigure::from_study`]),
//! re-solved with its time history:
//!
//! 1. the case: the one asked for (by its [`Case::id`]), else the first
//!    case, in canonical order, with a run that rocked (θmax/θc ≥
//!    [`ROCKED`]) without overturning, else the first case;
//! 2. the stripe: the one asked for, else the stripe nearest (in ln IM) the
//!    median of the case's fitted curve of its most severe limit state
//!    (where a rocking block is most telling: some runs fall, some stand),
//!    else the lowest stripe where a run overturned, else the highest;
//! 3. the record: at that case and stripe, the run with the largest
//!    θmax/θc that did not overturn (else the largest overall); ties go to
//!    the lowest record index.
//!
//! Or one block under one record of a synthetic ensemble (or of the
//! study's record files) at one PGA ([`HistoryCase`]), chosen by the
//! caller among the ensemble's first records: the paper layer solves them
//! through the ensemble primitive ([`crate::study::ensemble`]) and picks
//! the run that shows the most modes; the figure solves only the record it
//! is given, once, with its time history.

use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingBackend, Rectangle};
use plotters::style::{BLACK, Color, RGBColor};

use super::data::{PlotRow, StudyData};
use super::figure::{DrawResult, Figure};
use super::layout::{self, Dash, Entry, Frame, Margins, Sample, curve};
use super::style::{PAGE_WIDTH_IN, PALETTE, Style, tick_label};
use crate::case::{Case, CaseValues, Field, Param};
use crate::detmath as dm;
use crate::error::{Error, Result};
use crate::im::Im;
use crate::io_util::sig3;
use crate::motion::{Record, SynthesisSettings, Synthesizer};
use crate::outcome::{Mode, Outcome};
use crate::outcomes_csv::{Column, OutcomesFile};
use crate::solver::{Analysis, Block, Friction, History, SolverSettings, simulate};
use crate::spec::{Intensity, Motions, Study};
use crate::study::{CommandBlock, Source, plan};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Figure height (in).
const HEIGHT_IN: f64 = 3.3;
/// Panel margins: 34 pt for the y tick labels, 10 pt on the right.
const MARGINS: Margins = Margins::new(34.0, 10.0);
/// Shortest time in a mode that counts as showing it (s).
pub const MIN_MODE_S: f64 = 0.01;
/// Height of the strip above the θ panel that holds the impacts' rug (pt).
const RUG_STRIP_PT: f64 = 7.0;
/// Time shown before the first motion and after the last (s).
const ZOOM_PAD_S: f64 = 1.0;
/// Velocity jump (relative to √(gR)) above which an event is an impact.
const IMPACT_JUMP: f64 = 1e-9;
/// θmax/θc from which a run counts as having rocked, for the choice of the
/// case.
pub const ROCKED: f64 = 0.1;

/// Which analysis the history figure draws.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum HistoryChoice {
    /// One of the study's analyses, chosen as the module docs of
    /// `figures::history` say.
    #[default]
    Chosen,
    /// One of the study's analyses at this case (its [`Case::id`]), this
    /// stripe (the level, in the study's unit) and/or this record; what is
    /// not given is chosen as for [`HistoryChoice::Chosen`].
    At {
        /// The case's id.
        case: Option<String>,
        /// The stripe's level.
        level: Option<f64>,
        /// The record's index.
        record: Option<u64>,
    },
    /// One block under one record of an ensemble, chosen by the caller.
    Case(HistoryCase),
}

/// One block at one PGA under record `record` of an ensemble, chosen (by
/// the caller, e.g. the paper layer) among records 0..`records`.
#[derive(Clone, Debug, PartialEq)]
pub struct HistoryCase {
    /// Aspect ratio H/B.
    pub aspect: f64,
    /// Base width 2B, m.
    pub width: f64,
    /// Coefficient of restitution e.
    pub restitution: f64,
    /// Static friction μs.
    pub mu_s: f64,
    /// Kinetic friction μk.
    pub mu_k: f64,
    /// Peak ground acceleration, g.
    pub pga: f64,
    /// Ensemble seed.
    pub seed: u64,
    /// Records 0..`records` were tried (the heading says so when more than
    /// one).
    pub records: u64,
    /// The record drawn, one of 0..`records`.
    pub record: u64,
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
    /// Title: the block and the record.
    pub title: String,
    /// Heading of the upper panel: the acceleration the block feels
    /// (`Ground acceleration (g)`, or the floor's, naming the floor).
    pub acc_label: String,
    /// Heading of the lower panel: θ/θc and why this run is drawn.
    pub theta_label: String,
    /// Shown time window (s).
    pub window: (f64, f64),
    /// Ground acceleration (s, g) inside the window.
    pub acc: Vec<(f64, f64)>,
    /// θ/θc (s, –) inside the window.
    pub theta: Vec<(f64, f64)>,
    /// Mode intervals overlapping the window, clipped to it; consecutive
    /// intervals have different modes, but for flights with a bounce (an
    /// impact) between them.
    pub intervals: Vec<ModeInterval>,
    /// Impact times inside the window (s).
    pub impacts: Vec<f64>,
    /// Index of the chosen record.
    pub record: u64,
    /// The chosen run's outcome.
    pub outcome: Outcome,
    /// The command that solves the drawn analysis again
    /// ([`crate::study::simulate_command`]): `None` when the study is not
    /// known, or the analysis is not one its motions and solver make.
    pub command: Option<String>,
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

/// The darker shade of `mode`'s colour that every other flight of a run of
/// bounces is drawn in.
pub fn bounce_colour(mode: Mode) -> RGBColor {
    match mode {
        Mode::Flight => layout::tint(PALETTE[2], 0.3),
        other => mode_colour(other),
    }
}

/// Where the history's analysis comes from: the study (when known) and its
/// motions as the figures see them (see `FigureOptions`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct HistorySource<'a> {
    /// Which analysis.
    pub choice: &'a HistoryChoice,
    /// The study, when known: its motions and solver settings.
    pub study: Option<&'a Study>,
    /// Generator settings of a synthetic study (`g` for record files).
    pub synthesis: &'a SynthesisSettings,
    /// Ensemble seed of a synthetic study.
    pub seed: u64,
    /// Record files of a study of recorded motions.
    pub record_files: &'a [PathBuf],
    /// Case fields the study draws per analysis.
    pub pooled: &'a [Field],
}

impl HistoryFigure {
    /// The history of `options.choice` for the study folder `dir` whose
    /// data the figures read (`data`): one of the study's analyses,
    /// re-solved with its time history (see the [module docs](self)), or a
    /// [`HistoryCase`]. The study's motions and solver settings are
    /// `options.study`'s; without a study (a folder with no manifest), a
    /// synthetic PGA study of `options.synthesis` and `options.seed` with
    /// the default solver settings.
    ///
    /// Errors: a case or stripe asked for that the study does not have, or
    /// a record or analysis that cannot be made.
    pub(super) fn from_study(
        dir: &Path,
        data: &StudyData,
        options: &HistorySource,
    ) -> Result<Drawn> {
        let (case_id, level) = match options.choice {
            HistoryChoice::Case(case) => {
                let drawn = if options.record_files.is_empty() {
                    Self::compute(case, options.synthesis)
                } else {
                    let records = options
                        .record_files
                        .iter()
                        .take(case.records.max(1) as usize)
                        .map(|p| crate::motion::read_record(p, options.synthesis.g))
                        .collect::<Result<Vec<_>>>()?;
                    let names: Vec<String> = options
                        .record_files
                        .iter()
                        .map(|p| {
                            p.file_name().map_or_else(
                                || p.display().to_string(),
                                |f| f.to_string_lossy().into_owned(),
                            )
                        })
                        .collect();
                    Self::compute_recorded(case, &records, &names, options.synthesis.g)
                };
                return drawn.map(|mut figure| {
                    figure.command = case_command(dir, options, case, figure.record);
                    Drawn::Block(Box::new(figure))
                });
            }
            HistoryChoice::Chosen => (None, (None, None)),
            HistoryChoice::At {
                case,
                level,
                record,
            } => (case.as_deref(), (*level, *record)),
        };
        let chosen = choose_run(dir, data, options, case_id, level)?;
        if chosen.own.stack.is_some() {
            return Ok(Drawn::Stack(Box::new(chosen)));
        }
        let solver = options
            .study
            .map_or_else(SolverSettings::default, |s| s.solver);
        let (record, g) = match options.study {
            Some(study) => {
                let mut source = Source::new(study)?;
                let m = source.motion(study, chosen.level, chosen.record)?;
                (m.felt, study.g)
            }
            None => {
                let mut synth = Synthesizer::new(options.synthesis)?;
                let pga = options.synthesis.pga_from_g(chosen.level);
                let r = synth.generate(options.seed, chosen.record as u64, pga)?;
                (r, options.synthesis.g)
            }
        };
        let own = chosen.own;
        let analysis = own.analysis(g)?;
        let (aspect, width, e, friction) = (own.aspect, own.width, own.restitution, own.friction);
        // Three figures: a drawn value has all its digits in outcomes.csv.
        let friction = match friction {
            Friction::Infinite => "μ = ∞".to_string(),
            Friction::Coulomb { mu_s, mu_k } => format!("μₛ = {}, μₖ = {}", sig3(mu_s), sig3(mu_k)),
        };
        let record_name = record_name(options, chosen.record);
        // A value of the grid as the spec gave it; a drawn one to three
        // figures (all its digits are in outcomes.csv).
        let value = |x: f64, field: Field| {
            if options.pooled.contains(&field) {
                sig3(x)
            } else {
                tick_label(x)
            }
        };
        let friction = if options.pooled.contains(&Field::Friction) {
            friction
        } else {
            super::data::friction_label(&Param::Fixed(analysis.friction))
        };
        let title = format!(
            "H/B = {}, 2B = {} m, e = {}, {friction}; {record_name} at {}",
            value(aspect, Field::Aspect),
            value(width, Field::Width),
            value(e, Field::Restitution),
            chosen.level_text,
        );
        let acc_label = acc_label(options);
        let labels = (acc_label, format!("Rotation θ/θc: {}", chosen.why));
        let mut figure = Self::of_run(
            &analysis,
            &record,
            &solver,
            g,
            title,
            labels,
            chosen.record as u64,
        )?;
        // the study's own case of the analysis (drawn parameters drawn)
        figure.command = options.study.and_then(|study| {
            let (case, _) = crate::study::case_of(study, &chosen.own)?;
            Some(crate::study::simulate_command(
                dir,
                chosen.level,
                chosen.record,
                CommandBlock::Case(&case.id()),
            ))
        });
        Ok(Drawn::Block(Box::new(figure)))
    }

    /// The figure of the case's record `case.record` of ensemble
    /// `case.seed` (made by `motion`, at `case.pga`), solved once with its
    /// time history.
    ///
    /// Errors: a record or block that cannot be made, or a record not
    /// among the `case.records` tried.
    pub fn compute(case: &HistoryCase, motion: &SynthesisSettings) -> Result<Self> {
        let mut synth = Synthesizer::new(motion)?;
        let pga = motion.pga_from_g(case.pga);
        let seed = case.seed;
        Self::of_case(
            case,
            motion.g,
            |i| synth.generate(seed, i, pga),
            |i| format!("record {i} of seed {seed}"),
        )
    }

    /// As [`HistoryFigure::compute`], under a study's recorded motion
    /// `records[case.record]` (scaled to `case.pga` by its PGA, as the
    /// study runner scales it) instead of a synthetic one; `case.seed` is
    /// not used. `names` label the records in the title (one per record).
    ///
    /// Errors: no such record, or a record whose PGA is not positive.
    pub fn compute_recorded(
        case: &HistoryCase,
        records: &[Record],
        names: &[String],
        g: f64,
    ) -> Result<Self> {
        if case.record as usize >= records.len() {
            return Err(Error::InvalidRecord {
                name: "history".to_string(),
                message: format!(
                    "record {} asked for, of {} recorded motions",
                    case.record,
                    records.len()
                ),
            });
        }
        // the runner's own scaling: every series by target PGA / record PGA
        let mut source = Source::Files(Arc::new(records.to_vec()));
        Self::of_case(
            case,
            g,
            |i| source.record(&Intensity::Pga(Vec::new()), case.pga, i as usize, g),
            |i| {
                names
                    .get(i as usize)
                    .cloned()
                    .unwrap_or_else(|| format!("record {i}"))
            },
        )
    }

    /// The figure of record `case.record` from `record_at(i)` (already at
    /// the case's PGA); `label(i)` names record i in the title.
    fn of_case(
        case: &HistoryCase,
        g: f64,
        record_at: impl FnOnce(u64) -> Result<Record>,
        label: impl Fn(u64) -> String,
    ) -> Result<Self> {
        let count = case.records.max(1);
        let index = case.record;
        if index >= count {
            return Err(Error::invalid(
                "history record",
                index,
                &format!("one of the records tried (0–{})", count - 1),
            ));
        }
        let block = Block::new(case.width, case.aspect, g)?;
        let mut analysis = Analysis::new(block, case.restitution);
        analysis.friction = Friction::Coulomb {
            mu_s: case.mu_s,
            mu_k: case.mu_k,
        };
        let solver = SolverSettings::default();
        let record = record_at(index)?;
        let title = format!(
            "H/B = {}, 2B = {} m, e = {}, μₛ = {}, μₖ = {}; {} at {} g",
            tick_label(case.aspect),
            tick_label(case.width),
            tick_label(case.restitution),
            tick_label(case.mu_s),
            tick_label(case.mu_k),
            label(index),
            tick_label(case.pga),
        );
        let why = if count > 1 {
            format!(
                "Rotation θ/θc: of records 0–{}, the run showing the most modes",
                count - 1
            )
        } else {
            "Rotation θ/θc".to_string()
        };
        let labels = ("Ground acceleration (g)".to_string(), why);
        Self::of_run(&analysis, &record, &solver, g, title, labels, index)
    }

    /// The figure of one run: `analysis` under `record`, solved with its
    /// time history.
    fn of_run(
        analysis: &Analysis,
        record: &Record,
        solver: &SolverSettings,
        g: f64,
        title: String,
        (acc_label, theta_label): (String, String),
        index: u64,
    ) -> Result<Self> {
        let block = &analysis.block;
        let mut history = History::default();
        let outcome = simulate(analysis, record, solver, Some(&mut history))?;

        let rows = &history.rows;
        let end = outcome.end_time;
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
        // Consecutive rows of one mode make one interval, except flights:
        // an impact between two flights (a bounce) ends one and starts the
        // next, so a run of bounces is drawn as the flights it was.
        let bounce = |t: f64| impacts.binary_search_by(|x| x.total_cmp(&t)).is_ok();
        let mut intervals: Vec<ModeInterval> = Vec::new();
        for (k, r) in rows.iter().enumerate() {
            let t1 = rows.get(k + 1).map_or(end, |n| n.t);
            if t1 <= r.t {
                continue;
            }
            match intervals.last_mut() {
                Some(last)
                    if last.mode == r.mode
                        && last.t1 >= r.t
                        && !(r.mode == Mode::Flight && bounce(r.t)) =>
                {
                    last.t1 = t1
                }
                _ => intervals.push(ModeInterval {
                    t0: r.t,
                    t1,
                    mode: r.mode,
                }),
            }
        }

        let active: Vec<&ModeInterval> = intervals
            .iter()
            .filter(|iv| iv.mode != Mode::Rest)
            .collect();
        let window = match (active.first(), active.last()) {
            (Some(a), Some(b)) => (
                (a.t0 - ZOOM_PAD_S).max(0.0),
                // the analysis may end after the record (its free motion)
                (b.t1 + ZOOM_PAD_S).min(end.max(record.duration())),
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
        Ok(HistoryFigure {
            title,
            acc_label,
            theta_label,
            window,
            acc,
            theta,
            intervals,
            impacts: impacts.into_iter().filter(|&t| inside(t)).collect(),
            record: index,
            outcome,
            command: None,
        })
    }
}

/// The command that solves again the analysis a [`HistoryCase`] figure
/// drew (its `record`): the case's block under the study's motion at
/// `case.pga`, when that is what the figure solved — the study's own
/// ensemble (its seed) or record files, scaled to one of its PGA levels on
/// the ground, under the default solver settings the figure uses.
fn case_command(
    dir: &Path,
    options: &HistorySource,
    case: &HistoryCase,
    record: u64,
) -> Option<String> {
    let study = options.study?;
    let same_motion = match &study.motions {
        Motions::Synthetic {
            settings,
            seed,
            pairs: None,
            ..
        } => *seed == options.seed && settings == options.synthesis,
        Motions::Files(_) => !options.record_files.is_empty(),
        _ => false,
    };
    let at_level = matches!(&study.intensity, Intensity::Pga(levels) if levels.contains(&case.pga));
    (same_motion
        && at_level
        && study.floor.is_ground()
        && study.solver == SolverSettings::default()
        && (record as usize) < study.records())
    .then(|| {
        crate::study::simulate_command(
            dir,
            case.pga,
            record as usize,
            CommandBlock::Block {
                width: case.width,
                aspect: case.aspect,
                restitution: case.restitution,
                friction: Friction::Coulomb {
                    mu_s: case.mu_s,
                    mu_k: case.mu_k,
                },
            },
        )
    })
}

/// What [`HistoryFigure::from_study`] gives: a block's figure, or the
/// analysis of a stack's case it chose (`figures::stack_history` draws it).
pub(super) enum Drawn {
    /// One block's history.
    Block(Box<HistoryFigure>),
    /// A stack's analysis, chosen.
    Stack(Box<ChosenRun>),
}

/// The analysis [`HistoryFigure::from_study`] draws.
pub(super) struct ChosenRun {
    /// Its own block (drawn parameters as drawn), or its stack's values.
    pub own: CaseValues,
    /// Its record's index.
    pub record: usize,
    /// Its level, in the study's unit (g for PGA studies).
    pub level: f64,
    /// The level for the title (`0.6 g`).
    pub level_text: String,
    /// Why it was chosen, for the title.
    pub why: String,
}

/// Chooses the analysis to draw (see the [module docs](self)) from the
/// study's data, and reads its own block and level back from
/// `dir/outcomes.csv`.
fn choose_run(
    dir: &Path,
    data: &StudyData,
    options: &HistorySource,
    case_id: Option<&str>,
    (level, record): (Option<f64>, Option<u64>),
) -> Result<ChosenRun> {
    let rows = &data.outcomes;
    // `dedup` as it goes: one copy a run of rows, not one a row
    let all: Vec<Case> = super::data::runs(rows.iter().map(|r| r.case), |_, _| true);
    // by default a block's case, if the study has one; else a stack's
    let blocks: Vec<Case> = all.iter().copied().filter(|c| c.stack.is_none()).collect();
    let cases = if case_id.is_some() || blocks.is_empty() {
        all
    } else {
        blocks
    };
    let case = match case_id {
        Some(id) => *cases.iter().find(|c| c.id() == id).ok_or_else(|| {
            Error::invalid(
                "history case",
                id,
                &format!(
                    "the id of one of the study's cases ({})",
                    cases.iter().map(Case::id).collect::<Vec<_>>().join(", ")
                ),
            )
        })?,
        None => cases
            .iter()
            .find(|c| {
                rows.iter()
                    .any(|r| r.case == **c && !r.overturned && r.theta_max_over_theta_c >= ROCKED)
            })
            .or(cases.first())
            .copied()
            .ok_or_else(|| Error::invalid("history", "(no analyses)", "a successful analysis"))?,
    };
    let mine: Vec<_> = rows.iter().filter(|r| r.case == case).collect();
    let mut stripes: Vec<f64> = mine.iter().map(|r| r.pga).collect();
    stripes.sort_by(f64::total_cmp);
    stripes.dedup();
    // The case's fitted median of its most severe limit state: where its
    // curve crosses 1/2 (of a fit against the stripes' PGA).
    let on_stripes = data.fit_on_stripes();
    let median = data
        .curves
        .as_ref()
        .filter(|_| on_stripes)
        .and_then(|curves| {
            let last = curves
                .iter()
                .filter(|c| c.case == case)
                .map(|c| &c.limit_state)
                .next_back()?;
            let pts: Vec<_> = curves
                .iter()
                .filter(|c| c.case == case && &c.limit_state == last)
                .collect();
            pts.windows(2)
                .find(|w| w[0].p < 0.5 && w[1].p >= 0.5)
                .map(|w| w[0].im + (0.5 - w[0].p) / (w[1].p - w[0].p) * (w[1].im - w[0].im))
        });
    let (pga, why) = match level {
        Some(l) => {
            let Some(&s) = stripes.iter().find(|&&s| s == l) else {
                return Err(Error::invalid(
                    "history level",
                    l,
                    &format!(
                        "one of the case's stripes ({})",
                        stripes
                            .iter()
                            .map(|s| s.to_string())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ));
            };
            (s, "the stripe asked for".to_string())
        }
        None => match median {
            Some(m) if m > 0.0 => {
                let s = *stripes
                    .iter()
                    .min_by(|a, b| {
                        (dm::ln(**a) - dm::ln(m))
                            .abs()
                            .total_cmp(&(dm::ln(**b) - dm::ln(m)).abs())
                    })
                    .expect("the case has analyses");
                (
                    s,
                    format!("stripe nearest its median {} g", tick_label(round3(m))),
                )
            }
            _ => match mine
                .iter()
                .filter(|r| r.overturned)
                .map(|r| r.pga)
                .reduce(f64::min)
            {
                Some(s) => (s, "lowest stripe with an overturn".to_string()),
                None => (
                    *stripes.last().expect("the case has analyses"),
                    "highest stripe".to_string(),
                ),
            },
        },
    };
    let at: Vec<&PlotRow> = mine.iter().copied().filter(|r| r.pga == pga).collect();
    // The largest θmax/θc of `runs`, the lowest record on a tie (rows are
    // sorted by record).
    let best = |runs: Vec<&PlotRow>| -> Option<PlotRow> {
        runs.into_iter()
            .fold(None::<&PlotRow>, |best, r| match best {
                Some(b) if b.theta_max_over_theta_c >= r.theta_max_over_theta_c => Some(b),
                _ => Some(r),
            })
            .copied()
    };
    let standing: Vec<&PlotRow> = at.iter().copied().filter(|r| !r.overturned).collect();
    let (run, which) = match (record, best(standing)) {
        (Some(n), _) => match at.iter().find(|r| r.record == n) {
            Some(r) => (**r, "the record asked for"),
            None => {
                let ids: Vec<String> = at.iter().map(|r| r.record.to_string()).collect();
                let want = format!("a record of the stripe's analyses ({})", ids.join(", "));
                return Err(Error::invalid("history record", n, &want));
            }
        },
        (None, Some(r)) => (r, "largest θmax/θc not overturned"),
        (None, None) => (
            best(at).expect("the stripe has analyses"),
            "largest θmax/θc",
        ),
    };
    // Its own block and level, from outcomes.csv.
    let pooled = options.pooled;
    let cols = options.study.map(plan::columns);
    let mut table = OutcomesFile::open(
        &dir.join("outcomes.csv"),
        &[Column::Im(Im::PGA)],
        "the history",
    )?;
    let rotd50 = data.im.is_rotd50();
    while let Some((_, row)) = table.next_row()? {
        // the stripe's PGA as `read_outcomes` took it
        if row.record as u64 == run.record
            && row.im(data.im) == Some(run.pga)
            && row.case.pooled(pooled) == case
            && row.result.is_ok()
        {
            let level = match &cols {
                Some(cols) => row.level(cols).unwrap_or(run.pga),
                None => run.pga,
            };
            let level_text = match options.study.map(|s| &s.intensity) {
                Some(Intensity::Pgv(_)) => format!("PGV {} m/s", tick_label(level)),
                Some(Intensity::Scale(_)) => format!("scale {}", tick_label(level)),
                _ if rotd50 => format!("RotD50 PGA {} g", tick_label(level)),
                _ => format!("{} g", tick_label(level)),
            };
            return Ok(ChosenRun {
                own: row.case,
                record: row.record,
                level,
                level_text,
                why: format!("{which}, {why}"),
            });
        }
    }
    Err(Error::invalid(
        "history",
        run.record,
        "a run of outcomes.csv",
    ))
}

/// The record of analysis `record` as the study names it: its file, or its
/// index and seed.
pub(super) fn record_name(options: &HistorySource, record: usize) -> String {
    match options.study.map(|s| &s.motions) {
        Some(Motions::Files(files)) => files.get(record).map_or_else(
            || format!("record {}", record),
            |f| {
                Path::new(&f.given)
                    .file_name()
                    .map_or_else(|| f.given.clone(), |n| n.to_string_lossy().into_owned())
            },
        ),
        Some(Motions::Synthetic {
            seed,
            pairs: Some(orientation),
            ..
        }) => {
            let (p, phi) = orientation.member(record);
            format!("pair {p} of seed {seed} (φ = {}°)", sig3(phi))
        }
        Some(Motions::Synthetic { seed, .. }) => {
            format!("record {} of seed {seed}", record)
        }
        Some(Motions::Pairs { pairs, orientation }) => {
            let (p, phi) = orientation.member(record);
            let name = |f: &crate::spec::RecordFile| {
                Path::new(&f.given)
                    .file_name()
                    .map_or_else(|| f.given.clone(), |n| n.to_string_lossy().into_owned())
            };
            format!(
                "{} + {} (φ = {}°)",
                name(&pairs[p][0]),
                name(&pairs[p][1]),
                sig3(phi)
            )
        }
        None => format!("record {} of seed {}", record, options.seed),
    }
}

/// Heading of the acceleration panel: the acceleration the analysis felt
/// (the ground's, or the floor's, naming the floor).
pub(super) fn acc_label(options: &HistorySource) -> String {
    let felt = match options.study.map(|s| s.motions.orientation().is_some()) {
        Some(true) => "acceleration along φ",
        _ => "acceleration",
    };
    match options.study.map(|s| &s.floor) {
        Some(floor) if !floor.is_ground() => {
            format!("Floor {felt} (g), on {}", floor_text(floor))
        }
        _ => format!("Ground {felt} (g)"),
    }
}

/// A floor for a heading: `a floor of a building with T = 0.8 s, ζ = 5 %,
/// Γφ = 1.3` (its modes, `;` between them).
fn floor_text(floor: &crate::motion::Floor) -> String {
    let modes: Vec<String> = floor
        .modes
        .iter()
        .map(|m| {
            format!(
                "T = {} s, ζ = {} %, Γφ = {}",
                tick_label(m.period),
                tick_label(m.damping * 100.0),
                tick_label(m.participation)
            )
        })
        .collect();
    format!("a floor of a building with {}", modes.join("; "))
}

/// `x` to three decimals, for a title.
fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

impl HistoryFigure {
    /// The colour of each interval: its mode's, and for a flight that
    /// follows a flight (a bounce between them), alternately
    /// [`bounce_colour`], so that a run of bounces shows its flights.
    pub fn shades(&self) -> Vec<RGBColor> {
        let mut odd = false;
        let mut prev: Option<Mode> = None;
        self.intervals
            .iter()
            .map(|iv| {
                odd = prev == Some(iv.mode) && !odd;
                prev = Some(iv.mode);
                if odd {
                    bounce_colour(iv.mode)
                } else {
                    mode_colour(iv.mode)
                }
            })
            .collect()
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
        if self.intervals.windows(2).any(|w| w[0].mode == w[1].mode) {
            entries.push(Entry::new(
                Sample::Block(bounce_colour(Mode::Flight)),
                "flight after a bounce",
            ));
        }
        entries.push(Entry::new(Sample::Tick(BLACK), "impact"));
        let frame = Frame::new(root, style, &self.title, &entries, MARGINS)?;

        let (_, h) = frame.body.dim_in_pixel();
        // the impacts' rug gets a strip of its own above the θ panel, clear
        // of the data and of the gridlines
        let rug = style.ipx(RUG_STRIP_PT);
        let plot_h = h.saturating_sub(frame.x_area + 2 * frame.top + rug);
        let (top, bottom) = frame.body.split_vertically(frame.top + plot_h * 2 / 5);
        let (t0, t1) = self.window;

        let panels = [
            (&top, self.acc_label.as_str(), &self.acc),
            (&bottom, self.theta_label.as_str(), &self.theta),
        ];
        for (k, (area, label, data)) in panels.into_iter().enumerate() {
            let last = k == 1;
            frame.heading(area, label)?;
            let peak = data.iter().fold(0.0_f64, |m, &(_, y)| m.max(y.abs()));
            let y_max = if peak > 0.0 { 1.12 * peak } else { 1.0 };
            let mut builder = frame.chart(area, last);
            if last {
                builder.margin_top(frame.top + rug);
            }
            let mut chart = builder.build_cartesian_2d(t0..t1, -y_max..y_max)?;
            chart.draw_series(
                self.intervals
                    .iter()
                    .zip(self.shades())
                    .map(|(iv, c)| Rectangle::new([(iv.t0, -y_max), (iv.t1, y_max)], c.filled())),
            )?;
            let mut mesh = layout::mesh(&mut chart, style);
            mesh.x_labels(10).y_labels(5).disable_x_mesh();
            if last {
                mesh.x_desc("Time (s)");
            }
            mesh.draw()?;
            if last {
                // impacts: a rug of short ticks in the strip above the plot
                let (x0, y0) = area.get_base_pixel();
                let (_, y_px) = chart.plotting_area().get_pixel_range();
                let (y_lo, y_hi) = (
                    y_px.start - y0 - rug as i32 + style.ipx(1.0) as i32,
                    y_px.start - y0 - style.ipx(1.5) as i32,
                );
                let w = style.ipx(layout::RUG_PT).max(1) as i32;
                for &t in &self.impacts {
                    let (x, _) = chart.backend_coord(&(t, 0.0));
                    area.draw(&Rectangle::new(
                        [(x - x0, y_lo), (x - x0 + w, y_hi)],
                        BLACK.filled(),
                    ))?;
                }
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
