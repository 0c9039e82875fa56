//! An adaptive study: rounds of analyses placed where they narrow the band
//! of each case's fit most, until the band meets the spec's precision
//! (`grid.pga = { min, max }` with `[fragility] precision`; docs/adaptive.md).
//!
//! ```text
//! round 0: every case, 6 levels spread over the lattice × 5 records
//! round r: per case still running: fit_case (the fit and bootstrap of
//!          fragility.csv) ─▶ stop (met / max_analyses / median outside
//!          the range) or place the next analyses by the fit's Fisher
//!          information on the lattice ─▶ solve them all in parallel
//! ```
//!
//! An analysis is the fixed grid's analysis at the same (lattice level,
//! record): [`analyse`] makes its row, and a level's records are taken in
//! order of index (record i at a level is the ensemble's member i, scaled),
//! so records are shared across levels as in a fixed grid. The rows of
//! `outcomes.csv` are in canonical order (level, record, case) whatever the
//! thread count; every decision is a function of the rows so far, so the
//! rounds, and the file, are the same on any number of threads, and a run
//! killed between rounds resumes by replaying them from its checkpoint
//! (`adaptive-checkpoint.json`, the rows done) to the same bytes.

use super::ensemble;
use super::single::analyse;
use super::source::{Source, UnitMotion};
use super::{
    RunOptions, RunReport, Shard, files, manifest, plan, read_checkpoint, write_checkpoint,
};
use crate::case::Case;
use crate::detmath as dm;
use crate::error::{Error, Result};
use crate::fragility::{
    Band, CaseFit, Design, FragilityOptions, MIN_ANALYSES, Precision, Unfit, fit_case, place,
    read_outcomes_for,
};
use crate::outcomes_csv::Columns;
use crate::spec::{Adaptive, Study};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

/// Levels of the first, coarse round, spread evenly over the lattice.
pub const COARSE_LEVELS: usize = 6;
/// Records at each level of the first round.
pub const COARSE_RECORDS: usize = 5;
/// Analyses a later round adds at one level at a time.
pub const BATCH: usize = 5;
/// Fewest analyses a later round adds to a case.
pub const ROUND_MIN: usize = 20;
/// Fewest rounds before a case may stop on its band.
pub const MIN_ROUNDS: usize = 3;
/// A round adds at most 1/`GROWTH_DIVISOR` of a case's analyses so far:
/// rounds small enough that a case stops close to its target rather than
/// well below it, few enough (a look per third more analyses) that
/// stopping on a band narrow by chance does not make the bands
/// overconfident (coverage measured in docs/adaptive.md).
pub const GROWTH_DIVISOR: usize = 3;
/// Most bootstrap replicates that may fail to fit for a band to count.
pub const MAX_UNFIT_SHARE: f64 = 0.02;

/// The file of per-case results an adaptive run writes beside `outcomes.csv`.
pub const ADAPTIVE_CSV: &str = "adaptive.csv";
/// Which lattice level, record and case each row of a finished adaptive
/// run's `outcomes.csv` is (`level,record,case`, 0-based, in the rows'
/// order): what lets the same command on a finished folder replay its
/// rounds without solving them again.
pub const ADAPTIVE_INDEX: &str = "adaptive-index.csv";
/// The checkpoint of an adaptive run under way.
pub const ADAPTIVE_CHECKPOINT: &str = "adaptive-checkpoint.json";

/// Why a case stopped (or that it has not).
#[derive(Clone, Debug, PartialEq)]
pub enum Stop {
    /// Still running.
    Running,
    /// Every band met its target.
    Met,
    /// `max_analyses` reached first.
    MaxAnalyses,
    /// A limit state's median lies outside the range: the message says which.
    Outside(String),
    /// Every level that would narrow the band has used all its records
    /// (`records`, the most per level).
    RecordsExhausted,
}

impl Stop {
    /// The keyword of `adaptive.csv`'s `status`.
    pub fn status(&self) -> &'static str {
        match self {
            Stop::Running => "running",
            Stop::Met => "met",
            Stop::MaxAnalyses => "max_analyses",
            Stop::Outside(_) => "outside_range",
            Stop::RecordsExhausted => "records_exhausted",
        }
    }
}

/// Where one case of an adaptive run is.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseState {
    /// The case's id (`fragility.csv`'s `case_id`).
    pub id: String,
    /// Records used at each lattice level (records 0..n).
    pub counts: Vec<usize>,
    /// Rounds this case took part in.
    pub rounds: usize,
    /// Why it stopped.
    pub stop: Stop,
    /// Per limit state: its name and the band reached (`None`: no fit yet).
    pub bands: Vec<(String, Option<Band>)>,
}

impl CaseState {
    /// Analyses of this case so far.
    pub fn analyses(&self) -> usize {
        self.counts.iter().sum()
    }
}

/// What an adaptive run did, per case.
#[derive(Clone, Debug)]
pub struct AdaptiveReport {
    /// The cases, in canonical order.
    pub cases: Vec<CaseState>,
    /// The spec's targets and limit.
    pub adaptive: Adaptive,
    /// Rounds run.
    pub rounds: usize,
}

/// The rows done, kept between rounds (and in the checkpoint).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
struct Checkpoint {
    analyses_hash: String,
    /// (lattice level, record, case) and the row.
    rows: Vec<(usize, usize, usize, String)>,
}

/// Runs the adaptive study `study` into `opts.out_dir` (the caller holds
/// its lock). Refuses a shard: each round depends on the one before.
pub fn run(study: &Study, opts: &RunOptions) -> Result<(RunReport, Option<AdaptiveReport>)> {
    let t0 = Instant::now();
    let adaptive = study.adaptive.expect("an adaptive study");
    let options = study.fragility.clone().expect("an adaptive study fits");
    let dir = &opts.out_dir;
    if opts.shard != Shard::WHOLE {
        return Err(Error::invalid(
            "--shard",
            opts.shard.to_string(),
            "no shard for an adaptive study (grid.pga = { min, max }): each round is placed \
             from the one before, so it runs whole; on a cluster, run one case per job \
             (docs/adaptive.md)",
        ));
    }
    crate::io_util::create_folder(dir)?;
    let (pool, threads) = crate::threads::pool(opts.threads)?;
    let source = Source::new(study)?;
    let mut manifest = manifest::Manifest::new(study, &opts.spec_file, None, Shard::WHOLE);
    let ckpt_path = dir.join(ADAPTIVE_CHECKPOINT);
    let partial = dir.join(files::PARTIAL);
    let started = manifest::now_unix();
    // rows of an earlier invocation of the same analyses: replayed, not solved
    let mut done: BTreeMap<(usize, usize, usize), String> = BTreeMap::new();
    let mut reused = false;
    match read_checkpoint::<Checkpoint>(&ckpt_path)? {
        Some(old) if old.analyses_hash == manifest.analyses_hash => {
            done.extend(old.rows.into_iter().map(|(l, r, c, t)| ((l, r, c), t)));
        }
        Some(_) => {
            return Err(Error::Conflict {
                path: dir.clone(),
                message: format!(
                    "holds an unfinished adaptive run of other analyses ({}); pass another --out, \
                     or delete it to start over",
                    ckpt_path.display()
                ),
            });
        }
        None => match manifest::check_finished(dir, &manifest, opts.force)? {
            // the same analyses by this build, finished: its rows are
            // replayed through the same rounds, nothing is solved again
            manifest::Finished::Same(_) => match read_index(dir)? {
                Some(rows) => {
                    done = rows;
                    reused = true;
                }
                None => {
                    manifest::clear_previous(dir)?;
                }
            },
            manifest::Finished::No => {
                manifest::clear_previous(dir)?;
            }
        },
    }
    let resumed = if reused { 0 } else { done.len() };
    // what the run reports, stopped between rounds or complete
    let run_report = |complete: bool, counts: super::Counts, analyses_run: u64| RunReport {
        already_finished: false,
        out_dir: dir.clone(),
        complete,
        counts,
        resumed_at_unit: resumed,
        analyses_run,
        wall_seconds: t0.elapsed().as_secs_f64(),
        threads,
        tally: None,
    };
    let cols = plan::columns(study);
    let cases = plan::cases(study);
    let levels = study.intensity.levels().to_vec();
    let mut state: Vec<CaseState> = cases
        .iter()
        .map(|c| CaseState {
            id: c.id(),
            counts: vec![0; levels.len()],
            rounds: 0,
            stop: Stop::Running,
            bands: Vec::new(),
        })
        .collect();
    let mut rows: BTreeMap<(usize, usize, usize), String> = BTreeMap::new();
    let mut analyses_run = 0u64;
    let mut round = 0usize;
    let mut next: Vec<Vec<usize>> = state.iter().map(|_| coarse(levels.len())).collect();
    let mut rounds_here = 0usize;
    loop {
        // the analyses of this round, in canonical order
        let mut jobs = Vec::new();
        for (ci, add) in next.iter().enumerate() {
            for (li, &n) in add.iter().enumerate() {
                let from = state[ci].counts[li];
                jobs.extend((from..from + n).map(|r| (li, r, ci)));
                state[ci].counts[li] += n;
            }
        }
        if jobs.is_empty() {
            break;
        }
        jobs.sort_unstable();
        let todo: Vec<(usize, usize, usize)> = jobs
            .iter()
            .copied()
            .filter(|k| !done.contains_key(k))
            .collect();
        let solved = pool.install(|| solve(study, &cases, &cols, &source, &levels, &todo));
        analyses_run += todo.len() as u64;
        rows.extend(todo.into_iter().zip(solved));
        for k in &jobs {
            if let Some(text) = done.remove(k) {
                rows.insert(*k, text);
            }
        }
        for (ci, add) in next.iter().enumerate() {
            if add.iter().any(|&n| n > 0) {
                state[ci].rounds += 1;
            }
        }
        write_rows(&partial, &cols, &rows)?;
        if !reused || analyses_run > 0 {
            write_checkpoint(
                &ckpt_path,
                &Checkpoint {
                    analyses_hash: manifest.analyses_hash.clone(),
                    rows: rows
                        .iter()
                        .map(|(&(l, r, c), t)| (l, r, c, t.clone()))
                        .collect(),
                },
            )?;
        }
        let fits = pool.install(|| fit_running(&partial, &options, &cases, &state))?;
        next = state
            .iter_mut()
            .zip(fits)
            .map(|(s, fits)| match fits {
                Some(fits) => decide(s, &fits, &adaptive, &options, &levels, study.records()),
                None => vec![0; levels.len()],
            })
            .collect();
        round += 1;
        rounds_here += 1;
        if opts.progress {
            for s in state.iter().filter(|s| s.rounds == round) {
                eprintln!("{}", progress_line(round, s, &adaptive));
            }
        }
        let stop_here = opts.stop_after_units.is_some_and(|n| rounds_here >= n);
        if (stop_here || super::interrupted()) && next.iter().flatten().any(|&n| n > 0) {
            let counts = super::Counts::default();
            return Ok((run_report(false, counts, analyses_run), None));
        }
    }
    let report = AdaptiveReport {
        cases: state,
        adaptive,
        rounds: round,
    };
    write_adaptive_csv(&dir.join(ADAPTIVE_CSV), &report)?;
    let counts = count(&partial)?;
    if reused && analyses_run == 0 && done.is_empty() {
        // the replay wrote the same rows: the folder's outcomes.csv and
        // manifest stay as they were
        std::fs::remove_file(&partial).map_err(Error::io(&partial))?;
        // a finished folder replayed without solving anything
        let run = RunReport {
            already_finished: true,
            ..run_report(true, counts, 0)
        };
        return Ok((run, Some(report)));
    }
    // otherwise (the replay left the finished rows: outcomes.csv was
    // edited by hand since) the folder gets this run's rows
    let index = dir.join(ADAPTIVE_INDEX);
    crate::io_util::write_atomic(&index, |w| {
        w.write_all(b"level,record,case\n")?;
        for (l, r, c) in rows.keys() {
            writeln!(w, "{l},{r},{c}")?;
        }
        Ok(())
    })
    .map_err(Error::io(&index))?;
    manifest.threads = threads;
    manifest.set_times(started, manifest::now_unix());
    manifest.analyses_run = analyses_run;
    manifest.resumed_at_unit = resumed;
    manifest.wall_seconds = t0.elapsed().as_secs_f64();
    manifest.counts = counts;
    manifest.write(&dir.join(files::MANIFEST))?;
    let out = dir.join(files::OUTCOMES);
    crate::io_util::move_into(&partial, &out).map_err(Error::io(&out))?;
    match std::fs::remove_file(&ckpt_path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            return Err(Error::io(&ckpt_path)(e));
        }
        _ => {}
    }
    manifest::record_outputs(dir, &[&dir.join(ADAPTIVE_CSV), &index])?;
    Ok((run_report(true, counts, analyses_run), Some(report)))
}

/// The first round: [`COARSE_LEVELS`] lattice levels evenly spread, both
/// ends included, [`COARSE_RECORDS`] records each.
fn coarse(n: usize) -> Vec<usize> {
    let mut add = vec![0; n];
    let k = COARSE_LEVELS.min(n);
    for j in 0..k {
        let i = if k == 1 {
            0
        } else {
            (j * (n - 1) + (k - 1) / 2) / (k - 1)
        };
        add[i] = COARSE_RECORDS;
    }
    add
}

/// Solves `jobs` (lattice level, record, case) in parallel and returns
/// their rows in the same order: the motions of the distinct (level,
/// record) units first, then every analysis.
fn solve(
    study: &Study,
    cases: &[Case],
    cols: &Columns,
    source: &Source,
    levels: &[f64],
    jobs: &[(usize, usize, usize)],
) -> Vec<String> {
    let mut units: Vec<(usize, usize)> = jobs.iter().map(|&(l, r, _)| (l, r)).collect();
    units.dedup();
    let motions: Vec<std::result::Result<UnitMotion, String>> =
        ensemble::motions(source, &units, |src, &(l, r)| {
            src.motion(study, levels[l], r).map_err(|e| e.to_string())
        });
    let records = study.records();
    ensemble::analyses(jobs, |&(l, r, c)| {
        let ui = units.partition_point(|&u| u < (l, r));
        let unit = plan::Unit {
            index: l * records + r,
            level: l,
            record: r,
        };
        let file = study.record_file(r);
        analyse(
            study,
            cols,
            (&cases[c], c),
            &unit,
            &motions[ui],
            file.as_deref(),
        )
        .1
    })
}

/// The fits (as `fragility.csv` would have them) of the cases still
/// running, read back from the rows so far; `None` for the others.
fn fit_running(
    partial: &Path,
    options: &FragilityOptions,
    cases: &[Case],
    state: &[CaseState],
) -> Result<Vec<Option<Vec<CaseFit>>>> {
    let outcomes = read_outcomes_for(partial, options)?;
    Ok(cases
        .iter()
        .zip(state)
        .map(|(c, s)| {
            (s.stop == Stop::Running)
                .then(|| outcomes.cases.iter().find(|d| d.key == *c))
                .flatten()
                .map(|d| fit_case(d, options))
        })
        .collect())
}

/// The band of a fitted limit state with a bootstrap.
fn band_of(fit: &CaseFit) -> Option<Band> {
    let f = fit.fit.as_ref().ok()?;
    let b = fit.bootstrap.as_ref()?;
    let (m, s) = (b.median?, b.beta?);
    Some(Band {
        median: f.median(),
        median_band: (m.lo, m.hi),
        beta: f.beta(),
        beta_band: (s.lo, s.hi),
        unfit_share: b.unfit_total() as f64 / b.replicates.max(1) as f64,
    })
}

/// Updates case `s` from its fits after a round and returns the analyses
/// of its next round per lattice level (all zero once it stops).
fn decide(
    s: &mut CaseState,
    fits: &[CaseFit],
    adaptive: &Adaptive,
    options: &FragilityOptions,
    levels: &[f64],
    cap: usize,
) -> Vec<usize> {
    let none = vec![0; levels.len()];
    let n = s.analyses();
    let (min, max) = (adaptive.range.min, adaptive.range.max);
    s.bands = fits
        .iter()
        .map(|f| (f.limit_state.clone(), band_of(f)))
        .collect();
    // a median outside the range: looked at again after one more round
    // at that end, then the case stops
    for f in fits {
        let side = match &f.fit {
            Ok(fit) if fit.median() > max => Some(true),
            Ok(fit) if fit.median() < min => Some(false),
            Err(Unfit::NoneOverturned) => Some(true),
            Err(Unfit::AllOverturned) => Some(false),
            _ => None,
        };
        let Some(above) = side else { continue };
        if s.rounds >= 2 {
            let unit = adaptive.im.unit();
            let field = adaptive.im.name();
            let what = match &f.fit {
                Ok(fit) => format!("fitted at {:.3} {}", fit.median(), adaptive.im.unit()),
                Err(_) if above => "no analysis exceeded it".to_string(),
                Err(_) => "every analysis exceeded it".to_string(),
            };
            s.stop = Stop::Outside(format!(
                "case {}: the median of '{}' lies {} the range {} to {} {unit} ({what}, {n} \
                 analyses); stopped, not extrapolated: widen grid.{field} to {}",
                s.id,
                f.limit_state,
                if above { "above" } else { "below" },
                min,
                max,
                if above {
                    "higher levels"
                } else {
                    "lower levels"
                }
            ));
            return none;
        }
        let mut add = none.clone();
        let end = if above { levels.len() - 1 } else { 0 };
        let near = if above {
            end.saturating_sub(2)
        } else {
            (end + 2).min(levels.len() - 1)
        };
        add[end] = 2 * BATCH;
        add[near] += 2 * BATCH;
        return capped(add, &s.counts, cap);
    }
    let z = dm::norm_inv_cdf(0.5 + 0.5 * options.confidence);
    let target = adaptive.precision;
    let ratio = |b: &Band| {
        let m = b.median_half() / target.median;
        let t = b.beta_half() / target.beta;
        m.max(t)
    };
    let met = |b: &Option<Band>| {
        b.as_ref()
            .is_some_and(|b| b.unfit_share <= MAX_UNFIT_SHARE && ratio(b) <= 1.0)
    };
    let all_met = s.bands.iter().all(|(_, b)| met(b));
    if all_met && n >= MIN_ANALYSES && s.rounds >= MIN_ROUNDS {
        s.stop = Stop::Met;
        return none;
    }
    if n >= adaptive.max_analyses {
        s.stop = Stop::MaxAnalyses;
        return none;
    }
    // how much more: the band narrows as 1/√n, so (ratio² − 1)·n more,
    // at least ROUND_MIN, at most a third as many again (the band estimate is
    // noisy: a smaller step overshoots less)
    let worst = s
        .bands
        .iter()
        .map(|(_, b)| b.as_ref().map_or(2.0, |b| ratio(b) * ratio(b)))
        .fold(0.0, f64::max);
    let mut more = ((worst - 1.0) * n as f64).ceil().max(0.0) as usize;
    more = more.clamp(ROUND_MIN, (n / GROWTH_DIVISOR).max(ROUND_MIN));
    if n + more < MIN_ANALYSES {
        more = MIN_ANALYSES - n;
    }
    more = more.min(adaptive.max_analyses - n);
    let batches = more.div_ceil(BATCH);
    let designs: Vec<Design> = fits
        .iter()
        .zip(&s.bands)
        .filter_map(|(f, (_, b))| {
            let fit = f.fit.as_ref().ok()?;
            let unmet = |half: f64, t: f64| half > t;
            let (m, bt) = match b {
                Some(b) => (
                    unmet(b.median_half(), target.median),
                    unmet(b.beta_half(), target.beta),
                ),
                None => (true, true),
            };
            // bootstrap replicates that cannot be fitted (separated
            // resamples) are cured by analyses on both sides of the
            // median, where β is learnt: β's target stays on until then
            let separated = b.as_ref().is_some_and(|b| b.unfit_share > MAX_UNFIT_SHARE);
            Some(Design {
                a: fit.a,
                b: fit.b,
                se_ln_median: m.then_some(target.median / z),
                se_beta: (bt || separated).then_some(target.beta / z),
            })
        })
        .collect();
    let unfitted: Vec<&CaseFit> = fits.iter().filter(|f| f.fit.is_err()).collect();
    let mut add = none.clone();
    if let Some(f) = unfitted.first() {
        // no fit yet (the outcomes are separated)
        // levels around the change from none exceeding to all: the five
        // nearest its log-midpoint, where the median most likely is
        let (lo, hi) = transition(f, levels);
        let mut near: Vec<usize> = (lo..=hi).collect();
        near.sort_by_key(|&i| (2 * i).abs_diff(lo + hi));
        near.truncate(5);
        for j in 0..batches {
            add[near[j % near.len()]] += BATCH;
        }
    } else if designs
        .iter()
        .any(|d| d.se_ln_median.is_some() || d.se_beta.is_some())
    {
        add = place(levels, &s.counts, &designs, batches, BATCH, cap);
    } else {
        // met but too early to stop: more at the median of the first
        let d = &designs[0];
        let theta = dm::exp(-d.a / d.b);
        let i = levels.partition_point(|&x| x < theta).min(levels.len() - 1);
        add[i] = batches * BATCH;
    }
    let add = capped(add, &s.counts, cap);
    if add.iter().all(|&a| a == 0) {
        s.stop = Stop::RecordsExhausted;
    }
    add
}

/// `add` with no level past `cap` records.
fn capped(mut add: Vec<usize>, counts: &[usize], cap: usize) -> Vec<usize> {
    for (a, &c) in add.iter_mut().zip(counts) {
        *a = (*a).min(cap.saturating_sub(c));
    }
    add
}

/// The lattice indices from the highest level where no analysis of `f`
/// exceeded to the lowest where all did (its observations).
fn transition(f: &CaseFit, levels: &[f64]) -> (usize, usize) {
    let index = |im: f64| levels.partition_point(|&x| x < im).min(levels.len() - 1);
    let lo = f
        .observations
        .iter()
        .filter(|o| o.overturned == 0)
        .map(|o| index(o.im))
        .max()
        .unwrap_or(0);
    let hi = f
        .observations
        .iter()
        .filter(|o| o.overturned == o.trials)
        .map(|o| index(o.im))
        .min()
        .unwrap_or(levels.len() - 1);
    if lo <= hi { (lo, hi) } else { (hi, lo) }
}

/// One line of progress: the case, its analyses and how far each band is
/// from its target.
pub fn progress_line(round: usize, s: &CaseState, adaptive: &Adaptive) -> String {
    let t = adaptive.precision;
    let bands: Vec<String> = s
        .bands
        .iter()
        .map(|(name, b)| match b {
            Some(b) => format!(
                "{name} median {:.4} {} ±{:.1} % (target ±{:.1} %), β {:.3} ±{:.3} (target ±{})",
                b.median,
                adaptive.im.unit(),
                100.0 * b.median_half(),
                100.0 * t.median,
                b.beta,
                b.beta_half(),
                t.beta
            ),
            None => format!("{name} not fitted yet"),
        })
        .collect();
    let stop = match &s.stop {
        Stop::Running => String::new(),
        Stop::Met => "; target met".to_string(),
        Stop::MaxAnalyses => format!("; stopped at max_analyses = {}", adaptive.max_analyses),
        Stop::Outside(m) => format!("; {m}"),
        Stop::RecordsExhausted => {
            "; stopped: the levels that would narrow the band have used all their records \
             (raise `records`, the most per level)"
                .to_string()
        }
    };
    format!(
        "round {round}: case {}: {} analyses; {}{stop}",
        s.id,
        s.analyses(),
        bands.join("; ")
    )
}

/// Rows of `outcomes.csv` by (level, record, case).
type Rows = BTreeMap<(usize, usize, usize), String>;

/// The rows of the finished run in `dir`, keyed by (level, record, case)
/// from its [`ADAPTIVE_INDEX`]; `None` when the folder has no index (a
/// run of an older build) or the index does not match `outcomes.csv` row
/// for row, so that the run starts over instead of trusting either.
fn read_index(dir: &Path) -> Result<Option<Rows>> {
    let (index, outcomes) = (dir.join(ADAPTIVE_INDEX), dir.join(files::OUTCOMES));
    let Ok(keys) = std::fs::read_to_string(&index) else {
        return Ok(None);
    };
    let text = std::fs::read_to_string(&outcomes).map_err(Error::io(&outcomes))?;
    let mut rows = text.split_inclusive('\n').skip(1);
    let mut out = BTreeMap::new();
    for line in keys.lines().skip(1) {
        let key: Vec<usize> = line.split(',').filter_map(|v| v.parse().ok()).collect();
        let (&[l, r, c], Some(row)) = (key.as_slice(), rows.next()) else {
            return Ok(None);
        };
        if out.insert((l, r, c), row.to_string()).is_some() {
            return Ok(None);
        }
    }
    Ok(rows.next().is_none().then_some(out))
}

/// `outcomes.csv`'s text of `rows` (header first), written atomically.
fn write_rows(
    path: &Path,
    cols: &Columns,
    rows: &BTreeMap<(usize, usize, usize), String>,
) -> Result<()> {
    crate::io_util::write_atomic(path, |w| {
        w.write_all(cols.header().as_bytes())?;
        for text in rows.values() {
            w.write_all(text.as_bytes())?;
        }
        Ok(())
    })
    .map_err(Error::io(path))
}

/// The counts of the rows in `path`: analyses, failed, overturned,
/// uplifted and either (as [`super::Tally`] counts a fixed grid's; the
/// rows of an adaptive run are not in a fixed grid's order, so they are
/// counted here without its checks of place).
fn count(path: &Path) -> Result<super::Counts> {
    use crate::outcomes_csv::{Column, OutcomesFile};
    let mut table = OutcomesFile::open(
        path,
        &[Column::Status, Column::Overturned, Column::Uplifted],
        "the study's counts",
    )?;
    let mut c = super::Counts::default();
    while let Some((_, row)) = table.next_row()? {
        c.analyses += 1;
        match &row.result {
            Ok(o) => {
                c.overturned += o.overturned as u64;
                c.uplifted += o.uplifted as u64;
                c.overturned_or_uplifted += (o.overturned || o.uplifted) as u64;
            }
            Err(_) => c.failed += 1,
        }
    }
    Ok(c)
}

/// The header of `adaptive.csv`.
pub const ADAPTIVE_HEADER: &str = "case_id,limit_state,status,analyses,rounds,median,median_lo,\
median_hi,median_half_width,target_median,beta,beta_lo,beta_hi,beta_half_width,target_beta,\
max_analyses,note";

/// Writes `adaptive.csv`: per case and limit state, what it reached.
fn write_adaptive_csv(path: &Path, report: &AdaptiveReport) -> Result<()> {
    let t: Precision = report.adaptive.precision;
    let mut text = String::from(ADAPTIVE_HEADER);
    text.push('\n');
    let num = |x: f64| format!("{x}");
    for s in &report.cases {
        let note = match &s.stop {
            Stop::Outside(m) => m.replace(',', ";"),
            _ => String::new(),
        };
        for (name, b) in &s.bands {
            let cells = match b {
                Some(b) => [
                    num(b.median),
                    num(b.median_band.0),
                    num(b.median_band.1),
                    num(b.median_half()),
                    num(t.median),
                    num(b.beta),
                    num(b.beta_band.0),
                    num(b.beta_band.1),
                    num(b.beta_half()),
                    num(t.beta),
                ],
                None => {
                    let mut c: [String; 10] = Default::default();
                    c[4] = num(t.median);
                    c[9] = num(t.beta);
                    c
                }
            };
            text.push_str(&format!(
                "{},{},{},{},{},{},{},{}\n",
                s.id,
                name,
                s.stop.status(),
                s.analyses(),
                s.rounds,
                cells.join(","),
                report.adaptive.max_analyses,
                note
            ));
        }
    }
    crate::io_util::write_atomic(path, |w| w.write_all(text.as_bytes())).map_err(Error::io(path))
}

/// The `## Precision` section of an adaptive study's `summary.md`: per
/// case and limit state, the analyses used, the band reached and the target.
pub fn summary_section(report: &AdaptiveReport) -> String {
    let t = report.adaptive.precision;
    let unit = report.adaptive.im.unit();
    let mut s = format!(
        "## Precision\n\nAn adaptive run over {} {} to {} {}: {} rounds; each case stops when \
         the 90 % bands of its medians (relative half-width) and of β (absolute) are within ±{} \
         % and ±{}, after at least {MIN_ROUNDS} rounds and {MIN_ANALYSES} analyses, or \
         at {} analyses (docs/adaptive.md).\n\n\
         | case | limit state | status | analyses | median, {unit} | band, {unit} | ± median | target | β | \
         ± β | target |\n|---|---|---|---:|---:|---|---:|---:|---:|---:|---:|\n",
        report.adaptive.im.short(),
        report.adaptive.range.min,
        report.adaptive.range.max,
        report.adaptive.im.unit(),
        report.rounds,
        t.median * 100.0,
        t.beta,
        report.adaptive.max_analyses
    );
    let mut notes = Vec::new();
    for c in &report.cases {
        if let Stop::Outside(m) = &c.stop {
            notes.push(m.clone());
        }
        for (name, b) in &c.bands {
            let cells = match b {
                Some(b) => format!(
                    "{:.4} | {:.4}–{:.4} | {:.1} % | {:.1} % | {:.3} | {:.3} | {}",
                    b.median,
                    b.median_band.0,
                    b.median_band.1,
                    100.0 * b.median_half(),
                    100.0 * t.median,
                    b.beta,
                    b.beta_half(),
                    t.beta
                ),
                None => format!("– | – | – | {:.1} % | – | – | {}", 100.0 * t.median, t.beta),
            };
            s.push_str(&format!(
                "| {} | {} | {} | {} | {cells} |\n",
                c.id,
                name,
                c.stop.status(),
                c.analyses()
            ));
        }
    }
    for n in notes {
        s.push_str(&format!("\n{n}\n"));
    }
    s
}
