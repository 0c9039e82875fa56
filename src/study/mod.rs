//! Running a study: every (case, record) pair of a [`Study`], on a local
//! rayon pool, streamed to disk, resumable and shardable; and the study's
//! `summary.md` ([`write_summary`]), which the pipeline writes once the
//! analyses are done.
//!
//! ```text
//! Study ─▶ plan: cases × units (level, record), shard K/N
//!   ─▶ chunks of units: records made in parallel, then every (unit, case)
//!      solved in parallel, rows formatted in canonical order
//!   ─▶ outcomes.csv.partial (append, fsync) + checkpoint.json (atomic)
//!   ─▶ manifest.json (atomic) ─▶ rename to outcomes.csv
//! ```
//!
//! Memory stays flat in the number of analyses: only one chunk of rows is
//! held at a time. The rows of a chunk are put in canonical order before
//! they are written, so `outcomes.csv` is byte-identical for any thread
//! count, any interruption and resumption, and any shard split once merged
//! ([`merge()`]).
//!
//! **Resuming.** After each chunk the partial file is synced and
//! `checkpoint.json` records how many units are done and the partial file's
//! length. Running the same study into the same folder again truncates the
//! partial file to that length and carries on; a checkpoint of another spec
//! (different hash) or another shard is refused.
//!
//! **Failures.** An analysis the solver cannot finish (an error, or a panic)
//! is written with status `failed` and its message, counted in the
//! manifest, and the run carries on; the caller decides the exit status.

pub mod adaptive;
pub mod ensemble;
pub mod files;
mod lock;
mod manifest;
mod merge;
pub(crate) mod plan;
mod progress;
mod single;
mod source;
mod measure;
mod compare;
mod space;
mod summary;
mod surface;
mod tally;

pub use compare::{IMS_HEADING, ImFit, compare_ims, ims_section};
pub use lock::RunLock;
pub use manifest::{Finished, Manifest, clear_previous, record_outputs};
pub use measure::{measure_records, measure_study_records};
pub use merge::{merge, merge_into};
pub use plan::{Shard, Unit, unit_count};
use single::analyse;
pub use single::{
    Analysed, CommandBlock, Reanalysis, case_of, locate, reanalyse, simulate_command,
};
pub use source::{Source, UnitMotion};
pub use space::{SAY_FROM_BYTES, SpaceEstimate, free_bytes};
pub use summary::{COUNTS_HEADING, FRAGILITY_HEADING, fragility_section};
pub use surface::{SURFACE_HEADING, surface_section};
pub use tally::{Counts, Tally};

use crate::case::Case;
use crate::error::{Error, Result};
use crate::outcomes_csv::Columns;
use crate::spec::{Motions, Study, fnv1a64};
use plan::columns;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::io::{Seek, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A request to stop: set by the command line's Ctrl-C handler (any caller
/// may set it), read by [`run`] between chunks. A run that sees it stops
/// as if killed after the chunk under way, its analyses saved and
/// checkpointed (so running it again resumes there), and returns as not
/// complete; [`crate::pipeline::run`] then skips what follows the
/// analyses.
pub static INTERRUPT: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether [`INTERRUPT`] is set.
pub fn interrupted() -> bool {
    INTERRUPT.load(std::sync::atomic::Ordering::SeqCst)
}

/// Options of one invocation of a run (they do not change the results).
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Output folder.
    pub out_dir: PathBuf,
    /// Worker threads (0: one per available core; capped at
    /// [`crate::threads::MAX_THREADS_PER_CORE`] per core).
    pub threads: usize,
    /// Which shard of the units to run.
    pub shard: Shard,
    /// Report on standard error: the analyses to run, a time estimate after
    /// the first chunk, then a progress bar on a terminal, or a progress line
    /// every 5 % or minute off one.
    pub progress: bool,
    /// The spec file as the user named it, for the manifest.
    pub spec_file: String,
    /// Analyses per chunk: the unit of parallel work and of checkpointing
    /// (0: 128 per thread, rounded up to whole units).
    pub chunk_analyses: usize,
    /// Stop, as if killed, once this many units have been done by this
    /// invocation (the checkpoint is left for a later run to resume). For tests.
    pub stop_after_units: Option<usize>,
    /// Replace a finished run of another spec or shard in `out_dir` (else
    /// refused).
    pub force: bool,
    /// Run even when the estimated size of `outcomes.csv` exceeds the free
    /// space of `out_dir`'s file system (else refused; [`SpaceEstimate`]).
    pub no_space_check: bool,
}

impl RunOptions {
    /// Defaults: all cores, the whole study, no progress bar.
    pub fn new(out_dir: impl Into<PathBuf>) -> RunOptions {
        RunOptions {
            out_dir: out_dir.into(),
            threads: 0,
            shard: Shard::WHOLE,
            progress: false,
            spec_file: String::new(),
            chunk_analyses: 0,
            stop_after_units: None,
            force: false,
            no_space_check: false,
        }
    }
}

/// What an invocation did.
#[derive(Clone, Debug)]
pub struct RunReport {
    /// Output folder.
    pub out_dir: PathBuf,
    /// Every unit of the shard is done and the final files are written.
    pub complete: bool,
    /// Counts over the whole `outcomes.csv` (zero unless complete).
    pub counts: Counts,
    /// Units found done by an earlier invocation.
    pub resumed_at_unit: usize,
    /// Analyses run by this invocation.
    pub analyses_run: u64,
    /// Wall time of this invocation, s.
    pub wall_seconds: f64,
    /// Worker threads used.
    pub threads: usize,
    /// The folder held a finished run of the same analyses: no analysis
    /// was run, `outcomes.csv` was kept and the manifest took this spec.
    pub already_finished: bool,
    /// The statistics of the whole `outcomes.csv`, for `summary.md` (`None`
    /// unless complete).
    pub tally: Option<Tally>,
}

/// Progress of a run in progress (`checkpoint.json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Checkpoint {
    study: String,
    spec_hash: String,
    /// [`Study::analyses_hash`] (absent in checkpoints of older versions).
    #[serde(default)]
    analyses_hash: Option<String>,
    records_hash: Option<String>,
    shard: Shard,
    units_done: usize,
    bytes: u64,
    started_unix: u64,
}

/// FNV-1a over every record file's bytes, in order (recorded motions only).
fn records_hash(study: &Study) -> Result<Option<u64>> {
    match &study.motions {
        Motions::Synthetic { .. } => Ok(None),
        Motions::Files(_) | Motions::Pairs { .. } => {
            let mut all = Vec::new();
            for f in study.motions.files() {
                let bytes = crate::motion::read_record_bytes(&f.path)?;
                all.extend_from_slice(&fnv1a64(&bytes).to_le_bytes());
            }
            Ok(Some(fnv1a64(&all)))
        }
    }
}

/// Runs `study` (or its shard) into `opts.out_dir`, resuming from a
/// checkpoint there if one matches. The folder is locked ([`RunLock`]) for
/// the run: a second run into it is refused before it touches a file.
pub fn run(study: &Study, opts: &RunOptions) -> Result<RunReport> {
    let t0 = Instant::now();
    let dir = &opts.out_dir;
    crate::io_util::create_folder(dir)?;
    let _lock = RunLock::acquire(dir)?;
    // temporary files of a killed writer (the lock keeps this run's own
    // writers out of the folder)
    for d in [dir.clone(), dir.join("figures")] {
        crate::io_util::remove_stale_temps(&d, std::time::Duration::ZERO, None);
    }
    let (pool, threads) = crate::threads::pool(opts.threads)?;
    let records_hash = records_hash(study)?;
    // the records are read (and a bad one refused) before a file is written
    let mut source = Source::new(study)?;
    let mut manifest = Manifest::new(study, &opts.spec_file, records_hash, opts.shard);
    let cols = columns(study);
    let cases = plan::cases(study);
    let total = plan::unit_count(study);
    let units: Vec<usize> = opts.shard.units(total).collect();

    let partial_path = dir.join(files::PARTIAL);
    let ckpt_path = dir.join(files::CHECKPOINT);
    let fresh = Checkpoint {
        study: study.name.clone(),
        spec_hash: manifest.spec_hash.clone(),
        analyses_hash: Some(manifest.analyses_hash.clone()),
        records_hash: manifest.records_hash.clone(),
        shard: opts.shard,
        units_done: 0,
        bytes: 0,
        started_unix: manifest::now_unix(),
    };
    let (mut ckpt, mut file) = match read_checkpoint::<Checkpoint>(&ckpt_path)? {
        Some(old) => {
            // Only what decides the analyses must match: a change to the
            // post-processing ([fragility], output.summary, ...) resumes.
            let same_analyses = match &old.analyses_hash {
                Some(h) => Some(h) == fresh.analyses_hash.as_ref(),
                None => old.spec_hash == fresh.spec_hash,
            };
            if !same_analyses || old.records_hash != fresh.records_hash {
                return Err(Error::Conflict {
                    path: dir.clone(),
                    message: format!(
                        "holds an unfinished run of study '{}' with analyses hash {} (records {}), \
                         but this spec's analyses hash is {} (records {}): a field other than \
                         name, description, [fragility], output.summary or output.figures \
                         changed, so the analyses done so far are not this spec's; refusing to \
                         resume; pass another --out, or delete {} to start over",
                        old.study,
                        old.analyses_hash.as_deref().unwrap_or(&old.spec_hash),
                        old.records_hash.as_deref().unwrap_or("synthetic"),
                        manifest.analyses_hash,
                        fresh.records_hash.as_deref().unwrap_or("synthetic"),
                        ckpt_path.display()
                    ),
                });
            }
            if old.shard != fresh.shard {
                return Err(Error::Conflict {
                    path: dir.clone(),
                    message: format!(
                        "holds an unfinished run of shard {} but shard {} was asked for: \
                         pass --shard {} to resume it, or another --out",
                        old.shard, fresh.shard, old.shard
                    ),
                });
            }
            resume(dir, &old, &partial_path)?
                .map(|f| (old.clone(), f))
                .map_or_else(|| start(&cols, fresh.clone(), &partial_path), Ok)?
        }
        None => match manifest::check_finished(dir, &manifest, opts.force)? {
            Finished::No => {
                // a run replaced (--force, or another build's): its outcomes
                // and what was made from them go, not to be read as this one's
                manifest::clear_previous(dir)?;
                start(&cols, fresh.clone(), &partial_path)?
            }
            Finished::Same(old) => {
                return reuse_finished(study, dir, opts, manifest, *old, threads, t0);
            }
        },
    };
    let resumed_at_unit = ckpt.units_done;

    let mut bar = progress::Progress::start(
        opts.progress,
        (units.len() * cases.len()) as u64,
        (ckpt.units_done * cases.len()) as u64,
        threads,
    );

    let chunk_analyses = match opts.chunk_analyses {
        0 => threads * 128,
        n => n,
    };
    let chunk_units = chunk_analyses.div_ceil(cases.len()).max(1);
    let limit = opts
        .stop_after_units
        .map_or(units.len(), |n| (ckpt.units_done + n).min(units.len()));
    // the synthetic members used at several levels: filtered once, scaled at each
    pool.install(|| source.prepare(study, &units[ckpt.units_done..limit]));
    let mut analyses_run = 0u64;
    // The pilot: one unit per intensity level, solved first and kept for
    // its chunk, so the estimate and the ETA weigh each level by its own
    // cost (the first chunk, the lowest level, is the cheapest).
    let level_of = |u: usize| plan::unit(study, u).level;
    let mut ahead = HashMap::new();
    // the disk space the rest needs, from the pilot's rows, else the first chunk's
    let mut space_checked = false;
    if opts.progress {
        let left = &units[ckpt.units_done..limit];
        let (pilot, left_per_level) =
            progress::pilot_units(left, level_of, study.intensity.levels().len());
        if !pilot.is_empty() {
            let t = Instant::now();
            let solved = pool.install(|| solve_units(study, &cases, &cols, &source, &pilot));
            let mut forecast = progress::Forecast::new(left_per_level);
            for (&u, (_, seconds)) in pilot.iter().zip(&solved) {
                forecast.solved(level_of(u), *seconds);
            }
            bar.pilot(forecast, pilot.len() * cases.len(), t.elapsed());
            let sample: usize = solved.iter().map(|(text, _)| text.len()).sum();
            let left = ((units.len() - ckpt.units_done) * cases.len()) as u64;
            let space = SpaceEstimate::new(dir, sample, pilot.len() * cases.len(), left);
            if space.bytes >= SAY_FROM_BYTES {
                bar.say(&space.line());
            }
            if let Err(e) = space.check(dir, opts.no_space_check) {
                bar.finish();
                if ckpt.units_done == 0 && !ckpt_path.exists() {
                    // nothing done yet: no partial file is left behind
                    drop(file);
                    let _ = std::fs::remove_file(&partial_path);
                }
                return Err(e);
            }
            space_checked = true;
            ahead.extend(
                pilot
                    .into_iter()
                    .zip(solved.into_iter().map(|(text, _)| text)),
            );
        }
    }
    // A pipeline of two: while one worker appends the chunk solved last
    // (write, fsync, checkpoint), the others solve the next one, and the
    // writer joins them when it is done, so no worker idles while the
    // rows go to disk. An interruption stops the solving; the chunk under
    // way is still written and checkpointed.
    let mut next = ckpt.units_done;
    let mut pending: Option<SolvedChunk> = None;
    loop {
        let todo =
            (next < limit && !interrupted()).then(|| &units[next..(next + chunk_units).min(limit)]);
        if todo.is_none() && pending.is_none() {
            break;
        }
        let saving = pending.take();
        let (saved, solved) = pool.install(|| {
            rayon::join(
                || {
                    saving.map(|(len, text, solved_here)| {
                        save_chunk(&mut file, &partial_path, &ckpt_path, &mut ckpt, len, &text)
                            .map(|()| (len, text.len(), solved_here))
                    })
                },
                || todo.map(|chunk| run_chunk(study, &cases, &cols, &source, chunk, &mut ahead)),
            )
        });
        if let Some(saved) = saved {
            let (len, bytes, solved_here) = saved?;
            if !space_checked {
                space_checked = true;
                let left = ((units.len() - ckpt.units_done) * cases.len()) as u64;
                SpaceEstimate::new(dir, bytes, len * cases.len(), left)
                    .check(dir, opts.no_space_check)?;
            }
            let n = (len * cases.len()) as u64;
            analyses_run += n;
            let solved: Vec<(usize, f64)> = solved_here
                .iter()
                .map(|&(u, seconds)| (level_of(u), seconds))
                .collect();
            bar.inc(n, &solved);
        }
        if let (Some(chunk), Some((text, solved_here))) = (todo, solved) {
            next += chunk.len();
            pending = Some((chunk.len(), text, solved_here));
        }
    }
    bar.finish();
    drop(file);

    let mut report = RunReport {
        out_dir: dir.clone(),
        complete: false,
        counts: Counts::default(),
        resumed_at_unit,
        analyses_run,
        wall_seconds: 0.0,
        threads,
        tally: None,
        already_finished: false,
    };
    if ckpt.units_done < units.len() {
        report.wall_seconds = t0.elapsed().as_secs_f64();
        return Ok(report);
    }

    // Every unit is done: the counts come from the file itself, read back
    // and checked row by row against the plan.
    let tally = Tally::read(&partial_path, study, opts.shard)?;
    report.wall_seconds = t0.elapsed().as_secs_f64();
    manifest.threads = threads;
    manifest.set_times(ckpt.started_unix, manifest::now_unix());
    manifest.resumed_at_unit = resumed_at_unit;
    manifest.analyses_run = analyses_run;
    manifest.wall_seconds = report.wall_seconds;
    manifest.counts = tally.counts();
    manifest.write(&dir.join(files::MANIFEST))?;
    let out = dir.join(files::OUTCOMES);
    crate::io_util::move_into(&partial_path, &out).map_err(Error::io(&out))?;
    // (a shard with no units never wrote a checkpoint)
    match std::fs::remove_file(&ckpt_path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            return Err(Error::io(&ckpt_path)(e));
        }
        _ => {}
    }
    report.complete = true;
    report.counts = tally.counts();
    report.tally = Some(tally);
    Ok(report)
}

/// Checks that `dir` holds a finished run (its `outcomes.csv`), before a
/// command reads from it. An interrupted run (its checkpoint or partial
/// outcomes) is told to be finished by rerunning `rockfrag run`; a folder
/// that is not a run's is said to be so, not met with a bare "No such file".
pub fn require_finished(dir: &Path) -> Result<()> {
    if dir.join(files::OUTCOMES).is_file() {
        return Ok(());
    }
    let message = if !dir.is_dir() {
        "no such folder: expected the output folder of a `rockfrag run` (with its outcomes.csv)"
            .to_string()
    } else if dir.join(files::CHECKPOINT).exists() || dir.join(files::PARTIAL).exists() {
        let done = read_checkpoint::<Checkpoint>(&dir.join(files::CHECKPOINT))
            .ok()
            .flatten()
            .map(|c| c.units_done);
        format!(
            "holds an unfinished run{}: rerun the `rockfrag run` that started it (the same \
             spec, with `--out {}`) to finish it; it resumes where it stopped",
            done.map_or(String::new(), |n| format!(" ({n} work units done)")),
            dir.display()
        )
    } else {
        format!(
            "holds no {}: not the output folder of a `rockfrag run`",
            files::OUTCOMES
        )
    };
    Err(Error::Conflict {
        path: dir.to_path_buf(),
        message,
    })
}

/// The report of a run into `dir` that found a finished run of the same
/// analyses (`old`, its manifest): `outcomes.csv` is read back and checked
/// against the plan, and the manifest takes this spec (its post-processing
/// fields may differ) while keeping the run's times and counts.
fn reuse_finished(
    study: &Study,
    dir: &Path,
    opts: &RunOptions,
    mut manifest: Manifest,
    old: Manifest,
    threads: usize,
    t0: Instant,
) -> Result<RunReport> {
    let tally = Tally::read(&dir.join(files::OUTCOMES), study, opts.shard)?;
    manifest.threads = old.threads;
    manifest.started_unix = old.started_unix;
    manifest.started_utc = old.started_utc;
    manifest.finished_unix = old.finished_unix;
    manifest.finished_utc = old.finished_utc;
    manifest.resumed_at_unit = old.resumed_at_unit;
    manifest.analyses_run = old.analyses_run;
    manifest.wall_seconds = old.wall_seconds;
    manifest.merged_from = old.merged_from;
    manifest.outputs = old.outputs;
    manifest.counts = tally.counts();
    manifest.write(&dir.join(files::MANIFEST))?;
    Ok(RunReport {
        out_dir: dir.to_path_buf(),
        complete: true,
        counts: tally.counts(),
        resumed_at_unit: 0,
        analyses_run: 0,
        wall_seconds: t0.elapsed().as_secs_f64(),
        threads,
        tally: Some(tally),
        already_finished: true,
    })
}

/// Writes `dir/summary.md` of `study` (shard `shard`) from `tally` (read
/// from `dir/outcomes.csv` when `None`), with the fitted curves of
/// `dir/fragility.csv` when it exists, the provenance of `dir/manifest.json`,
/// and `extra` sections after the generic ones (a layer's: the paper's
/// tables for its study). Atomic.
pub fn write_summary(
    dir: &Path,
    study: &Study,
    shard: Shard,
    tally: Option<&Tally>,
    extra: &[String],
) -> Result<()> {
    let read;
    let tally = match tally {
        Some(t) => t,
        None => {
            read = Tally::read(&dir.join(files::OUTCOMES), study, shard)?;
            &read
        }
    };
    let fragility = dir.join("fragility.csv");
    crate::fragility::check_set(dir)?;
    let fits = if fragility.exists() {
        Some(crate::fragility::read_fragility_csv(&fragility)?)
    } else {
        None
    };
    let manifest = Manifest::read(&dir.join(files::MANIFEST)).ok();
    let path = dir.join(files::SUMMARY);
    let mut text = tally.markdown(study, shard, fits.as_deref(), manifest.as_ref());
    for section in extra {
        text.push('\n');
        text.push_str(section);
    }
    crate::io_util::write_atomic(&path, |w| w.write_all(text.as_bytes())).map_err(Error::io(&path))
}

/// A chunk solved and not yet written: its unit count, its rows, and the
/// units solved in it with their thread seconds.
type SolvedChunk = (usize, String, Vec<(usize, f64)>);

/// Appends the rows of a chunk of `units` units to the partial file,
/// syncs it and checkpoints the run past them.
fn save_chunk(
    file: &mut std::fs::File,
    partial_path: &Path,
    ckpt_path: &Path,
    ckpt: &mut Checkpoint,
    units: usize,
    text: &str,
) -> Result<()> {
    file.write_all(text.as_bytes())
        .map_err(Error::io(partial_path))?;
    file.sync_data().map_err(Error::io(partial_path))?;
    ckpt.bytes += text.len() as u64;
    ckpt.units_done += units;
    write_checkpoint(ckpt_path, ckpt)
}

/// The rows of one chunk of units, in canonical order: the units solved
/// ahead by the pilot are taken from `ahead`, the others solved here.
/// Returns the text and the units solved here with their thread seconds.
fn run_chunk(
    study: &Study,
    cases: &[Case],
    cols: &Columns,
    source: &Source,
    chunk: &[usize],
    ahead: &mut HashMap<usize, String>,
) -> (String, Vec<(usize, f64)>) {
    let todo: Vec<usize> = chunk
        .iter()
        .copied()
        .filter(|u| !ahead.contains_key(u))
        .collect();
    let solved = solve_units(study, cases, cols, source, &todo);
    let seconds = todo
        .iter()
        .zip(&solved)
        .map(|(&u, (_, t))| (u, *t))
        .collect();
    let mut solved = solved.into_iter();
    let text = chunk
        .iter()
        .map(|u| match ahead.remove(u) {
            Some(rows) => rows,
            None => solved.next().expect("one solved unit per unit to do").0,
        })
        .collect();
    (text, seconds)
}

/// Solves `units` (every case of each) and returns, per unit, its rows in
/// canonical order and the thread time its record and analyses took, s.
fn solve_units(
    study: &Study,
    cases: &[Case],
    cols: &Columns,
    source: &Source,
    chunk: &[usize],
) -> Vec<(String, f64)> {
    let levels = study.intensity.levels();
    let (records, record_seconds): (Vec<std::result::Result<UnitMotion, String>>, Vec<f64>) =
        ensemble::motions(source, chunk, |src, &u| {
            let t0 = Instant::now();
            let unit = plan::unit(study, u);
            let record = src
                .motion(study, levels[unit.level], unit.record)
                .map_err(|e| e.to_string());
            (record, t0.elapsed().as_secs_f64())
        })
        .into_iter()
        .unzip();
    // each unit's record file, once per unit (not per analysis)
    let file_names: Vec<Option<String>> = chunk
        .iter()
        .map(|&u| study.record_file(plan::unit(study, u).record))
        .collect();
    // every case of each unit, unit-major: `outcomes.csv`'s order
    let jobs: Vec<(usize, usize)> = (0..chunk.len())
        .flat_map(|ui| (0..cases.len()).map(move |ci| (ui, ci)))
        .collect();
    let rows: Vec<(String, f64)> = ensemble::analyses(&jobs, |&(ui, ci)| {
        let t0 = Instant::now();
        let unit = plan::unit(study, chunk[ui]);
        let (_, text) = analyse(
            study,
            cols,
            (&cases[ci], ci),
            &unit,
            &records[ui],
            file_names[ui].as_deref(),
        );
        (text, t0.elapsed().as_secs_f64())
    });
    rows.chunks(cases.len().max(1))
        .zip(record_seconds)
        .map(|(unit, record)| {
            let text = unit.iter().map(|(r, _)| r.as_str()).collect();
            (text, record + unit.iter().map(|(_, t)| t).sum::<f64>())
        })
        .collect()
}

/// Reads a checkpoint (this module's or an adaptive run's), `None` when
/// there is none.
pub(super) fn read_checkpoint<T: serde::de::DeserializeOwned>(path: &Path) -> Result<Option<T>> {
    match std::fs::read_to_string(path) {
        Ok(text) => serde_json::from_str(&text)
            .map(Some)
            .map_err(|e| Error::Parse {
                path: path.to_path_buf(),
                line: e.line(),
                message: format!("unreadable checkpoint ({e}); delete it to start over"),
            }),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(Error::io(path)(e)),
    }
}

/// Writes a checkpoint atomically.
pub(super) fn write_checkpoint<T: Serialize>(path: &Path, ckpt: &T) -> Result<()> {
    crate::io_util::write_atomic(path, |w| {
        serde_json::to_writer(&mut *w, ckpt)?;
        Ok(())
    })
    .map_err(Error::io(path))
}

/// Starts a run from scratch: the partial file holds the header only. The
/// first checkpoint is written after the first chunk: a checkpoint always
/// has work to resume.
fn start(cols: &Columns, ckpt: Checkpoint, partial: &Path) -> Result<(Checkpoint, std::fs::File)> {
    let mut file = std::fs::File::create(partial).map_err(Error::io(partial))?;
    let header = cols.header();
    file.write_all(header.as_bytes())
        .map_err(Error::io(partial))?;
    file.sync_data().map_err(Error::io(partial))?;
    let ckpt = Checkpoint {
        bytes: header.len() as u64,
        ..ckpt
    };
    Ok((ckpt, file))
}

/// Reopens the partial file of a checkpoint, cut to its recorded length;
/// `None` if it is missing or shorter (then the run starts over). A run
/// killed between renaming the partial file and removing the checkpoint is
/// picked up from `outcomes.csv`.
fn resume(dir: &Path, ckpt: &Checkpoint, partial: &Path) -> Result<Option<std::fs::File>> {
    if !partial.exists() {
        let done = dir.join(files::OUTCOMES);
        let len = std::fs::metadata(&done).map(|m| m.len()).ok();
        if len != Some(ckpt.bytes) {
            return Ok(None);
        }
        // a link at outcomes.csv is kept (its target is rewritten when the
        // run finishes): its content is copied back, not the link moved
        let link = std::fs::symlink_metadata(&done).is_ok_and(|m| m.file_type().is_symlink());
        if link {
            std::fs::copy(&done, partial).map_err(Error::io(partial))?;
        } else {
            std::fs::rename(&done, partial).map_err(Error::io(partial))?;
        }
    }
    let mut file = std::fs::OpenOptions::new()
        .write(true)
        .open(partial)
        .map_err(Error::io(partial))?;
    let len = file.metadata().map_err(Error::io(partial))?.len();
    if len < ckpt.bytes {
        return Ok(None);
    }
    file.set_len(ckpt.bytes).map_err(Error::io(partial))?;
    file.seek(std::io::SeekFrom::End(0))
        .map_err(Error::io(partial))?;
    Ok(Some(file))
}
