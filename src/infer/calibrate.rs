//! Calibration: does the joint method's 90 % interval cover the true
//! intensity 90 % of the time?
//!
//! Synthetic events with a known answer: event e draws a PGA (or PGV) x_e
//! from the log-uniform prior over the grid and a record of the study's
//! ground-motion model that is *not* in its ensemble (synthetic index
//! records + 10⁶ + e), scales it to x_e and puts n_j objects of each kind
//! on it (n_j uniform in a range, each object's uncertain properties drawn
//! from the spec's distributions by its own stream); what overturned is
//! the event's survey. Each survey is inferred against the study's
//! simulations (made once), by both methods, and the intervals are checked
//! against x_e. With the prior the events are drawn from, a calibrated
//! method's 90 % interval covers x_e in 90 % of the events, up to the
//! binomial noise of their number.

use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;
use serde::Serialize;

use super::likelihood::{Grid, effective_records, joint, kind_curves, naive};
use super::pair::{PairPosterior, inferable_pair, measure_second};
use super::posterior::{Posterior, Prior, Summary};
use super::simulate::{Class, Im, Runner, Table};
use super::survey::{self, Survey};
use crate::detmath as dm;
use crate::error::{Error, Result};
use crate::im::{Felt, ImPair};
use crate::motion::Record;
use crate::spec::{InferSettings, Motions, Study};
use crate::study::{Source, ensemble};

/// How a calibration is run.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibrationOptions {
    /// Synthetic events.
    pub events: usize,
    /// Objects of each kind per event: uniform from `counts.0` to
    /// `counts.1`, inclusive.
    pub counts: (u64, u64),
    /// Kinds per event: uniform from `kinds.0` to `kinds.1` of the
    /// survey's kinds (at most all of them), chosen at random; a range
    /// reaching the number of kinds or beyond with `kinds.0` puts every kind
    /// in every event.
    pub kinds: (usize, usize),
    /// Seed of the events (their PGAs, records, kinds, counts and objects).
    pub seed: u64,
    /// A second IM: the joint posterior over (the levels' IM, it) of each
    /// event too, and whether its 90 % region holds the event's true pair.
    pub second: Option<Im>,
}

/// One synthetic event and what each method inferred.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Event {
    /// The true IM.
    pub im: f64,
    /// (count, overturned) of each kind.
    pub counts: Vec<(u64, u64)>,
    /// The joint method's bounds (`None`: its likelihood vanished).
    pub joint: Option<Summary>,
    /// The naive method's.
    pub naive: Option<Summary>,
    /// Records the joint posterior effectively rests on.
    pub effective_records: f64,
    /// The true second IM (with [`CalibrationOptions::second`]).
    pub second: Option<f64>,
    /// Its marginal bounds from the joint posterior over both IMs.
    pub second_bounds: Option<Summary>,
    /// The smallest highest-density credible level of the joint posterior
    /// whose region holds the true pair ([`PairPosterior::credible_at`]).
    pub credible: Option<f64>,
}

/// Coverage and widths of a calibration.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Calibration {
    /// The events.
    pub events: Vec<Event>,
    /// Fraction of events whose joint 90 % interval holds the true IM.
    pub joint_coverage: f64,
    /// The same for the naive method.
    pub naive_coverage: f64,
    /// Median width p95 − p05 of the joint intervals (IM unit).
    pub joint_width: f64,
    /// Of the naive intervals.
    pub naive_width: f64,
    /// Median ratio p95/p05 of the joint intervals.
    pub joint_ratio: f64,
    /// Of the naive intervals.
    pub naive_ratio: f64,
    /// Median over the events of the records their joint posterior rests on.
    pub effective_records: f64,
    /// Fraction of events whose 90 % joint region over both IMs holds the
    /// true pair (with a second IM).
    pub pair_coverage: Option<f64>,
    /// Fraction whose 90 % interval of the second IM holds the true one.
    pub second_coverage: Option<f64>,
    /// Analyses of the study's simulations.
    pub analyses: u64,
    /// Analyses of the events' objects.
    pub event_analyses: u64,
}

fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Offset of the events' record indices beyond the ensemble.
const EVENT_RECORDS: usize = 1_000_000;

/// Runs a calibration of `kinds` (their geometry, restitution and friction
/// as a survey gives them; their counts are the events') under `study`,
/// the study's levels in its IM, synthetic records only.
///
/// Errors: [`Error::InvalidParameter`] for recorded motions or scale
/// factors; as [`survey::models`].
pub fn calibrate(
    study: &Study,
    kinds: &Survey,
    settings: &InferSettings,
    options: &CalibrationOptions,
) -> Result<Calibration> {
    let Some(im) = super::simulate::im_of_levels(study) else {
        return Err(Error::invalid(
            "grid.scale_factors",
            "(given)",
            "PGA or PGV levels for a calibration (the events are scaled to a known IM)",
        ));
    };
    if !matches!(study.motions, Motions::Synthetic { .. }) {
        return Err(Error::invalid(
            "record_files",
            "(given)",
            "a synthetic ensemble for a calibration (its events need records outside it)",
        ));
    }
    let (lo, hi) = options.counts;
    if !(lo >= 1 && hi >= lo) {
        return Err(Error::invalid(
            "counts",
            format!("{lo}..{hi}"),
            "a range of counts from 1 up",
        ));
    }
    let n_kinds = kinds.kinds.len();
    let (k_lo, k_hi) = (options.kinds.0.min(n_kinds), options.kinds.1.min(n_kinds));
    if !(k_lo >= 1 && k_hi >= k_lo) {
        return Err(Error::invalid(
            "kinds",
            format!("{}..{}", options.kinds.0, options.kinds.1),
            "a range of kinds per event from 1 up",
        ));
    }
    let mut template = kinds.clone();
    for k in &mut template.kinds {
        k.count = hi;
        k.overturned = 0;
        k.slid = None;
    }
    let models = survey::models(
        &template,
        study,
        settings,
        std::path::Path::new("(calibration)"),
    )?;
    let runner = Runner {
        study,
        models: &models,
        slide: None,
        im,
        source: Source::new(study)?,
    };
    let records: Vec<usize> = (0..study.records()).collect();
    let table = runner.table(&records)?;
    let pair = match options.second {
        None => None,
        Some(second) => {
            let ims = ImPair::new(im, second)
                .and_then(inferable_pair)
                .map_err(|e| Error::invalid("second", second, &e))?;
            Some((ims, measure_second(study, second, &records)?))
        }
    };
    let grid = Grid::new(&table, true, settings.refine)?;
    let prior_u = Prior::LogUniform.density_u(&grid);
    let (u0, u1) = (grid.u[0], grid.u[grid.len() - 1]);

    // Each event: its IM, record and counts from its own stream.
    struct Draw {
        im: f64,
        record: usize,
        counts: Vec<u64>,
    }
    let draws: Vec<Draw> = (0..options.events)
        .map(|e| {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(splitmix64(
                splitmix64(options.seed ^ 0xCA11_B4A7_E000_0001) ^ splitmix64(e as u64),
            ));
            let im = dm::exp(u0 + (u1 - u0) * rng.random::<f64>());
            let mut counts: Vec<u64> = models
                .iter()
                .map(|_| lo + ((rng.random::<f64>() * (hi - lo + 1) as f64) as u64).min(hi - lo))
                .collect();
            if k_lo < n_kinds {
                // k of the kinds (partial Fisher–Yates); the others get no
                // objects and drop out of the event's survey.
                let span = k_hi - k_lo + 1;
                let k = k_lo + ((rng.random::<f64>() * span as f64) as usize).min(span - 1);
                let mut order: Vec<usize> = (0..n_kinds).collect();
                for i in 0..k {
                    let left = n_kinds - i;
                    let pick = i + ((rng.random::<f64>() * left as f64) as usize).min(left - 1);
                    order.swap(i, pick);
                }
                for &j in &order[k..] {
                    counts[j] = 0;
                }
            }
            Draw {
                im,
                record: study.records() + EVENT_RECORDS + e,
                counts,
            }
        })
        .collect();
    // Every event's objects on its record, events in parallel.
    let counts: Vec<Observed> = ensemble::motions(&runner.source, &draws, |src, d| {
        let record = src.record(&study.intensity, d.im, d.record, study.g)?;
        let felt = Felt {
            ground: &record,
            floor: None,
            pair: None,
            g: study.g,
        };
        let truth = options.second.and_then(|im2| im2.on(&felt));
        Ok((observe(&runner, &d.counts, d.record, &record), truth))
    })
    .into_iter()
    .collect::<Result<Vec<_>>>()?;
    let event_analyses: u64 = draws.iter().flat_map(|d| d.counts.iter()).sum();
    let events: Vec<Event> = draws
        .par_iter()
        .zip(&counts)
        .map(|(d, (c, truth))| {
            let mut s = template.clone();
            for (k, &(n, o)) in s.kinds.iter_mut().zip(c) {
                k.count = n;
                k.overturned = o;
            }
            // An object whose every analysis failed leaves its kind empty.
            s.kinds.retain(|k| k.count > 0);
            let kept: Vec<usize> = (0..c.len()).filter(|&j| c[j].0 > 0).collect();
            let t = select_kinds(&table, &kept);
            let joint = Posterior::new(&grid, &prior_u, &joint(&t, &s, &grid)).map(|p| p.summary);
            let two = match (&pair, joint, truth) {
                (Some((ims, second)), Some(first), Some(y)) => {
                    PairPosterior::new(*ims, &t, second, &s, &grid, &prior_u, first, 0, 0)
                        .ok()
                        .map(|p| (p.second, p.credible_at(d.im, *y)))
                }
                _ => None,
            };
            let curves = kind_curves(&t, &s, &grid);
            let naive =
                Posterior::new(&grid, &prior_u, &naive(&curves, &s, &grid)).map(|p| p.summary);
            Event {
                im: d.im,
                counts: c.clone(),
                joint,
                naive,
                effective_records: effective_records(&t, &s, &grid, &prior_u),
                second: *truth,
                second_bounds: two.map(|p| p.0),
                credible: two.map(|p| p.1),
            }
        })
        .collect();
    let coverage = |f: fn(&Event) -> Option<Summary>| {
        events
            .iter()
            .filter(|e| f(e).is_some_and(|s| s.p05 <= e.im && e.im <= s.p95))
            .count() as f64
            / events.len().max(1) as f64
    };
    let median = |f: &dyn Fn(&Event) -> Option<f64>| {
        let mut v: Vec<f64> = events.iter().filter_map(f).collect();
        v.sort_by(f64::total_cmp);
        match v.len() {
            0 => f64::NAN,
            n if n % 2 == 1 => v[n / 2],
            n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
        }
    };
    let share = |f: &dyn Fn(&Event) -> bool| {
        options
            .second
            .map(|_| events.iter().filter(|e| f(e)).count() as f64 / events.len().max(1) as f64)
    };
    Ok(Calibration {
        pair_coverage: share(&|e| e.credible.is_some_and(|c| c <= 0.9)),
        second_coverage: share(&|e| match (e.second, e.second_bounds) {
            (Some(y), Some(b)) => b.p05 <= y && y <= b.p95,
            _ => false,
        }),
        joint_coverage: coverage(|e| e.joint),
        naive_coverage: coverage(|e| e.naive),
        joint_width: median(&|e| e.joint.map(|s| s.p95 - s.p05)),
        naive_width: median(&|e| e.naive.map(|s| s.p95 - s.p05)),
        joint_ratio: median(&|e| e.joint.map(|s| s.p95 / s.p05)),
        naive_ratio: median(&|e| e.naive.map(|s| s.p95 / s.p05)),
        effective_records: median(&|e| Some(e.effective_records)),
        analyses: Table::analyses(&models, table.levels.len(), table.records),
        event_analyses,
        events,
    })
}

/// What an event's objects did ((objects, overturned) per kind) and its
/// true second IM.
type Observed = (Vec<(u64, u64)>, Option<f64>);

/// Level key of the objects' own draw streams (no study level has it).
const OBJECTS: usize = usize::MAX >> 1;

/// What `counts[j]` objects of each kind of `runner` did on `record`
/// (index `index`): (objects with an outcome, overturned) per kind; each
/// object's properties from the stream keyed by (record, kind, object).
fn observe(runner: &Runner, counts: &[u64], index: usize, record: &Record) -> Vec<(u64, u64)> {
    let tasks: Vec<(usize, usize)> = counts
        .iter()
        .enumerate()
        .flat_map(|(j, &n)| (0..n as usize).map(move |o| (j, o)))
        .collect();
    let classes: Vec<Class> = ensemble::analyses(&tasks, |&(j, o)| {
        runner.classify(&runner.models[j].draw(j, index, OBJECTS, o), record)
    });
    let mut out = vec![(0, 0); counts.len()];
    for (&(j, _), class) in tasks.iter().zip(&classes) {
        match class {
            Class::Failed => {}
            Class::Overturned => {
                out[j].0 += 1;
                out[j].1 += 1;
            }
            Class::Standing | Class::Slid => out[j].0 += 1,
        }
    }
    out
}

/// A synthetic survey: `kinds` (their geometry and properties; their
/// counts kept) on record `record` of the study's ground-motion model (an
/// index outside its ensemble gives a record it does not hold), scaled to
/// `im` in the study's IM; each object's uncertain properties drawn from
/// the spec's distributions. Returns the survey with what overturned.
///
/// Errors: as [`calibrate`].
pub fn synthetic_survey(
    study: &Study,
    kinds: &Survey,
    settings: &InferSettings,
    im: f64,
    record: usize,
) -> Result<Survey> {
    let Some(im_kind) = super::simulate::im_of_levels(study) else {
        return Err(Error::invalid(
            "grid.scale_factors",
            "(given)",
            "PGA or PGV levels (the survey's record is scaled to a known IM)",
        ));
    };
    let models = survey::models(kinds, study, settings, std::path::Path::new("(survey)"))?;
    let runner = Runner {
        study,
        models: &models,
        slide: None,
        im: im_kind,
        source: Source::new(study)?,
    };
    let mut source = runner.source.clone();
    let motion = source.record(&study.intensity, im, record, study.g)?;
    let counts: Vec<u64> = kinds.kinds.iter().map(|k| k.count).collect();
    let observed = observe(&runner, &counts, record, &motion);
    let mut out = kinds.clone();
    for (k, (n, o)) in out.kinds.iter_mut().zip(observed) {
        k.count = n;
        k.overturned = o;
        k.slid = None;
    }
    Ok(out)
}

/// The table of kinds `kept` only.
fn select_kinds(table: &Table, kept: &[usize]) -> Table {
    if kept.len() == table.kinds {
        return table.clone();
    }
    let per = table.levels.len() * table.records;
    let mut cells = Vec::with_capacity(kept.len() * per);
    for &j in kept {
        cells.extend_from_slice(&table.cells[j * per..(j + 1) * per]);
    }
    Table {
        kinds: kept.len(),
        cells,
        fixed: kept.iter().map(|&j| table.fixed[j]).collect(),
        ..table.clone()
    }
}
