//! The simulations behind an inference: every kind of object, with its
//! drawn properties, on every record of the study at every intensity level,
//! counted per (kind, level, record); run level by level into
//! `simulations.csv` with a checkpoint, so that a killed run resumes and a
//! rerun with the same inputs reuses them.
//!
//! Analysis (kind j, record r, level l, draw d) is a pure function of its
//! indices: the record is the study's (`Source::record`), the properties
//! come from the stream keyed by (seed, record, level, j · 2³² + d)
//! ([`KindModel::draw`]). Results are gathered into their places before
//! anything is summed or written, so the table is the same on any thread
//! count and after any interruption.

use std::io::{Seek, Write};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::survey::{KindModel, SlideRule, analysis};
use crate::case::Scene;
use crate::error::{Error, Result};
use crate::io_util::number;
use crate::motion::Record;
use crate::spec::{Intensity, Study};
use crate::study::{Source, ensemble};

/// The intensity measure an inference is of: PGA (g) or PGV (m/s) of the
/// ground ([`Im::PGA`], [`Im::PGV`]); the others are refused
/// ([`inferable`]).
pub use crate::im::Im;

/// `im` if an inference can be of it (PGA or PGV of the ground), else
/// what it can be of.
pub fn inferable(im: Im) -> std::result::Result<Im, String> {
    if im == Im::PGA || im == Im::PGV {
        Ok(im)
    } else {
        Err(format!("pga (g) or pgv (m/s), not {im}"))
    }
}

/// The IM a study's levels are in, if it is an inferable IM exactly: then
/// every record at a level has the level's IM; otherwise each has its own,
/// measured on the scaled record.
pub fn im_of_levels(study: &Study) -> Option<Im> {
    match study.intensity {
        Intensity::Pga(_) => Some(Im::PGA),
        Intensity::Pgv(_) => Some(Im::PGV),
        Intensity::Scale(_) => None,
    }
}

/// `im` of a record (PGA in g with gravity `g`, or PGV).
pub fn im_of_record(im: Im, record: &Record, g: f64) -> f64 {
    let felt = crate::im::Felt {
        ground: record,
        floor: None,
        pair: None,
        g,
    };
    im.on(&felt).expect("an inferable IM is the ground's")
}

/// One kind's draws on one record at one level.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Cell {
    /// Draws (the kind's [`KindModel::draws`]).
    pub draws: u32,
    /// Draws whose analysis failed (left out of the counts).
    pub failed: u32,
    /// Draws that overturned.
    pub overturned: u32,
    /// Draws still standing that slid beyond the sliding limit state (0
    /// without one).
    pub slid: u32,
}

impl Cell {
    /// Draws with an outcome.
    pub fn valid(&self) -> u32 {
        self.draws - self.failed
    }
}

/// Every count of an inference's simulations.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// Kinds of object.
    pub kinds: usize,
    /// The study's intensity levels, in the spec's order.
    pub levels: Vec<f64>,
    /// Records per level.
    pub records: usize,
    /// The IM of record r at level l, at `l · records + r`.
    pub im: Vec<f64>,
    /// The cell of kind j, level l, record r at `(j · levels + l) · records + r`.
    pub cells: Vec<Cell>,
    /// Per kind: nothing drawn, so its fractions are exact (0 or 1).
    pub fixed: Vec<bool>,
}

impl Table {
    /// The cell of kind `j`, level `l`, record `r`.
    pub fn cell(&self, j: usize, l: usize, r: usize) -> Cell {
        self.cells[(j * self.levels.len() + l) * self.records + r]
    }

    /// The IM of record `r` at level `l`.
    pub fn im(&self, l: usize, r: usize) -> f64 {
        self.im[l * self.records + r]
    }

    /// Analyses solved (a kind with nothing drawn counts once per record
    /// and level).
    pub fn analyses(models: &[KindModel], levels: usize, records: usize) -> u64 {
        models.iter().map(|m| m.solved() as u64).sum::<u64>() * (levels * records) as u64
    }
}

/// What one analysis came to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Class {
    Standing,
    Overturned,
    Slid,
    Failed,
}

/// Everything the analyses of one level need.
pub struct Runner<'a> {
    /// The study (records, solver, gravity).
    pub study: &'a Study,
    /// The kinds.
    pub models: &'a [KindModel],
    /// What counts as slid, if the survey counts it.
    pub slide: Option<&'a SlideRule>,
    /// The IM inferred.
    pub im: Im,
    /// The records.
    pub source: Source,
}

impl Runner<'_> {
    /// Runs level `level` (the spec's index) of `record_ids` (the records of
    /// the study, or others, e.g. for a calibration): the IM of each record
    /// and the cells, kind-major.
    pub fn level(&self, level: usize, record_ids: &[usize]) -> Result<(Vec<f64>, Vec<Cell>)> {
        let study = self.study;
        let x = study.intensity.levels()[level];
        let records = ensemble::motions(&self.source, record_ids, |src, &r| {
            src.record(&study.intensity, x, r, study.g)
        });
        let records = records.into_iter().collect::<Result<Vec<Record>>>()?;
        let exact = im_of_levels(study) == Some(self.im);
        let ims: Vec<f64> = records
            .iter()
            .map(|r| {
                if exact {
                    x
                } else {
                    im_of_record(self.im, r, study.g)
                }
            })
            .collect();
        let n = record_ids.len();
        // Every analysis of the level, kind-major, then record, then draw.
        let mut tasks: Vec<(usize, usize, usize)> = Vec::new();
        for (j, m) in self.models.iter().enumerate() {
            for r in 0..n {
                tasks.extend((0..m.solved()).map(|d| (j, r, d)));
            }
        }
        let classes: Vec<Class> = ensemble::analyses(&tasks, |&(j, r, d)| {
            let case = self.models[j].draw(j, record_ids[r], level, d);
            self.classify(&case, &records[r])
        });
        let mut cells = vec![Cell::default(); self.models.len() * n];
        for (&(j, r, _), class) in tasks.iter().zip(&classes) {
            let m = &self.models[j];
            let weight = if m.is_drawn() { 1 } else { m.draws as u32 };
            let c = &mut cells[j * n + r];
            c.draws = m.draws as u32;
            match class {
                Class::Standing => {}
                Class::Overturned => c.overturned += weight,
                Class::Slid => c.slid += weight,
                Class::Failed => c.failed += weight,
            }
        }
        Ok((ims, cells))
    }

    /// What the analysis of `case` (one draw of a kind) under `record`
    /// came to.
    pub(super) fn classify(&self, case: &crate::case::CaseValues, record: &Record) -> Class {
        let Ok(analysis) = analysis(case, self.study.g) else {
            return Class::Failed;
        };
        match ensemble::solve(&Scene::Block(analysis), record, &self.study.solver, None) {
            Ok(o) if o.overturned => Class::Overturned,
            Ok(o) if self.slide.is_some_and(|s| s.slid(&o)) => Class::Slid,
            Ok(_) => Class::Standing,
            Err(_) => Class::Failed,
        }
    }

    /// The whole table, in memory (no files): every level of records
    /// `record_ids`.
    pub fn table(&self, record_ids: &[usize]) -> Result<Table> {
        let levels = self.study.intensity.levels().to_vec();
        let (k, n, nl) = (self.models.len(), record_ids.len(), levels.len());
        let mut table = Table {
            kinds: k,
            levels,
            records: n,
            im: vec![0.0; nl * n],
            cells: vec![Cell::default(); k * nl * n],
            fixed: self.models.iter().map(|m| !m.is_drawn()).collect(),
        };
        for l in 0..nl {
            let (ims, cells) = self.level(l, record_ids)?;
            place(&mut table, l, &ims, &cells);
        }
        Ok(table)
    }
}

fn place(table: &mut Table, l: usize, ims: &[f64], cells: &[Cell]) {
    let (n, nl) = (table.records, table.levels.len());
    table.im[l * n..(l + 1) * n].copy_from_slice(ims);
    for j in 0..table.kinds {
        let at = (j * nl + l) * n;
        table.cells[at..at + n].copy_from_slice(&cells[j * n..(j + 1) * n]);
    }
}

/// The simulations' file.
pub const SIMULATIONS: &str = "simulations.csv";
/// Its checkpoint.
pub const CHECKPOINT: &str = "simulations.json";
/// Header of `simulations.csv`: one row per kind, level and record, level
/// by level (kinds, then records, within a level). `kind` is the kind's
/// index in the survey, `level` the level's index in the spec, `im` the
/// record's IM at the level, `draws` the kind's draws, `failed`,
/// `overturned` and `slid` how many of them.
pub const HEADER: &str = "kind,name,level,record,im,draws,failed,overturned,slid";

/// Progress of the simulations (`simulations.json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Checkpoint {
    /// Hash of everything the simulations depend on.
    inputs_hash: String,
    /// Levels written.
    levels_done: usize,
    /// Levels in all.
    levels: usize,
    /// Length of `simulations.csv` after them.
    bytes: u64,
}

/// What [`run_checkpointed`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct SimulationReport {
    /// The table.
    pub table: Table,
    /// Levels found done by an earlier run (reused).
    pub resumed_levels: usize,
    /// Analyses solved by this run.
    pub analyses_run: u64,
}

/// Runs every level not yet in `dir/simulations.csv` (whose checkpoint
/// must carry `hash`; another hash starts over), appending each level's
/// rows and then the checkpoint, and reads the whole file back. `names`
/// are the kinds' names; `stop_after` stops (as if killed) after that many
/// levels, for tests; `progress` says each level on standard error.
pub fn run_checkpointed(
    runner: &Runner,
    names: &[String],
    dir: &Path,
    hash: u64,
    stop_after: Option<usize>,
    progress: bool,
) -> Result<Option<SimulationReport>> {
    let study = runner.study;
    let nl = study.intensity.levels().len();
    let n = study.records();
    let data = dir.join(SIMULATIONS);
    let ckpt_path = dir.join(CHECKPOINT);
    let inputs_hash = format!("{hash:016x}");
    let old = read_checkpoint(&ckpt_path)?.filter(|c| c.inputs_hash == inputs_hash);
    let (mut ckpt, mut file) = match old.and_then(|c| reopen(&data, &c).transpose()) {
        Some(opened) => opened?,
        None => {
            let mut file = std::fs::File::create(&data).map_err(Error::io(&data))?;
            writeln!(file, "{HEADER}").map_err(Error::io(&data))?;
            file.sync_data().map_err(Error::io(&data))?;
            let ckpt = Checkpoint {
                inputs_hash,
                levels_done: 0,
                levels: nl,
                bytes: HEADER.len() as u64 + 1,
            };
            write_checkpoint(&ckpt_path, &ckpt)?;
            (ckpt, file)
        }
    };
    let resumed_levels = ckpt.levels_done;
    let ids: Vec<usize> = (0..n).collect();
    let limit = stop_after.map_or(nl, |s| (resumed_levels + s).min(nl));
    let mut analyses_run = 0;
    while ckpt.levels_done < limit {
        let l = ckpt.levels_done;
        let (ims, cells) = runner.level(l, &ids)?;
        let mut text = String::new();
        for (j, name) in names.iter().enumerate() {
            for r in 0..n {
                let c = cells[j * n + r];
                text.push_str(&format!(
                    "{j},{name},{l},{r},{},{},{},{},{}\n",
                    number(ims[r]),
                    c.draws,
                    c.failed,
                    c.overturned,
                    c.slid
                ));
            }
        }
        file.write_all(text.as_bytes()).map_err(Error::io(&data))?;
        file.sync_data().map_err(Error::io(&data))?;
        ckpt.bytes += text.len() as u64;
        ckpt.levels_done += 1;
        write_checkpoint(&ckpt_path, &ckpt)?;
        let run = Table::analyses(runner.models, 1, n);
        analyses_run += run;
        if progress {
            eprintln!(
                "level {}/{nl} ({} = {}): {run} analyses",
                l + 1,
                runner.im.name(),
                study.intensity.levels()[l]
            );
        }
    }
    drop(file);
    if ckpt.levels_done < nl {
        return Ok(None);
    }
    let fixed: Vec<bool> = runner.models.iter().map(|m| !m.is_drawn()).collect();
    let table = read_table(&data, &fixed, study.intensity.levels(), n)?;
    Ok(Some(SimulationReport {
        table,
        resumed_levels,
        analyses_run,
    }))
}

/// Reopens the data file of a matching checkpoint, cut to its recorded
/// length; `None` (start over) when it is missing or shorter.
fn reopen(data: &Path, ckpt: &Checkpoint) -> Result<Option<(Checkpoint, std::fs::File)>> {
    let Ok(mut file) = std::fs::OpenOptions::new().write(true).open(data) else {
        return Ok(None);
    };
    let len = file.metadata().map_err(Error::io(data))?.len();
    if len < ckpt.bytes {
        return Ok(None);
    }
    file.set_len(ckpt.bytes).map_err(Error::io(data))?;
    file.seek(std::io::SeekFrom::End(0))
        .map_err(Error::io(data))?;
    Ok(Some((ckpt.clone(), file)))
}

fn read_checkpoint(path: &Path) -> Result<Option<Checkpoint>> {
    match std::fs::read_to_string(path) {
        // An unreadable checkpoint is a run to start over, not an error:
        // the simulations are a cache of the inputs.
        Ok(text) => Ok(serde_json::from_str(&text).ok()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(Error::io(path)(e)),
    }
}

fn write_checkpoint(path: &Path, ckpt: &Checkpoint) -> Result<()> {
    crate::io_util::write_atomic(path, |w| {
        serde_json::to_writer(&mut *w, ckpt)?;
        Ok(())
    })
    .map_err(Error::io(path))
}

/// Reads `simulations.csv` back into a table of `fixed.len()` kinds (those
/// with nothing drawn marked), `levels` and `records` records; every cell
/// must be there once.
///
/// Errors: [`Error::Parse`] naming the line of anything malformed or
/// missing.
pub fn read_table(path: &Path, fixed: &[bool], levels: &[f64], records: usize) -> Result<Table> {
    let kinds = fixed.len();
    let text = std::fs::read_to_string(path).map_err(Error::io(path))?;
    let bad = |line: usize, message: String| Error::Parse {
        path: PathBuf::from(path),
        line,
        message,
    };
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, h)) if h == HEADER => {}
        _ => return Err(bad(1, format!("expected the header {HEADER}"))),
    }
    let nl = levels.len();
    let mut table = Table {
        kinds,
        levels: levels.to_vec(),
        records,
        im: vec![f64::NAN; nl * records],
        cells: vec![Cell::default(); kinds * nl * records],
        fixed: fixed.to_vec(),
    };
    let mut seen = vec![false; kinds * nl * records];
    for (i, line) in lines {
        let f: Vec<&str> = line.split(',').collect();
        let parsed = (f.len() == 9).then(|| {
            let u = |s: &str| s.parse::<usize>().ok();
            let c = |s: &str| s.parse::<u32>().ok();
            Some((
                u(f[0])?,
                u(f[2])?,
                u(f[3])?,
                f[4].parse::<f64>().ok()?,
                Cell {
                    draws: c(f[5])?,
                    failed: c(f[6])?,
                    overturned: c(f[7])?,
                    slid: c(f[8])?,
                },
            ))
        });
        let Some(Some((j, l, r, im, cell))) = parsed else {
            return Err(bad(i + 1, format!("expected a row `{HEADER}`")));
        };
        if j >= kinds
            || l >= nl
            || r >= records
            || cell.failed + cell.overturned + cell.slid > cell.draws
        {
            return Err(bad(
                i + 1,
                "a row outside the inference's kinds, levels and records".into(),
            ));
        }
        let at = (j * nl + l) * records + r;
        if seen[at] {
            return Err(bad(i + 1, "a repeated row".into()));
        }
        seen[at] = true;
        table.cells[at] = cell;
        table.im[l * records + r] = im;
    }
    if let Some(at) = seen.iter().position(|s| !s) {
        return Err(bad(
            0,
            format!(
                "no row for kind {}, level {}, record {}",
                at / (nl * records),
                at / records % nl,
                at % records
            ),
        ));
    }
    Ok(table)
}
