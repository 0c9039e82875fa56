//! Merging the folders of shards K/N (K = 1..N) into the folder of the whole
//! study: `outcomes.csv` rows are interleaved back into canonical unit order
//! (unit u comes from shard u mod N + 1) by copying their bytes, so the
//! result is byte-identical to an unsharded run; `summary.md` and
//! `manifest.json` are then made from the merged file. Each shard's
//! `outcomes.csv` is checked against its shard of the study before anything
//! is written, so a damaged shard is named with its line and a failed merge
//! leaves no output behind.

use super::files;
use super::manifest::{self, Manifest};
use super::plan::{self, Shard};
use super::tally::Tally;
use crate::error::{Error, Result};
use crate::spec::Study;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};

/// Merges complete shard folders `dirs` (in any order) into `out`; returns
/// the merged manifest. A folder `out` that holds a run of other analyses
/// is refused ([`merge_into`] with `replace` replaces it).
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<Manifest> {
    merge_into(dirs, out, false)
}

/// [`merge`], and with `replace` (`rockfrag merge --force`) a finished run
/// of other analyses in `out` is replaced: its outcomes and the files made
/// from them are removed ([`super::clear_previous`]). As for a run, `out`
/// is locked while it is written ([`super::RunLock`]: a folder another
/// process is writing is refused), and a folder holding an unfinished run
/// is refused.
pub fn merge_into(dirs: &[PathBuf], out: &Path, replace: bool) -> Result<Manifest> {
    let conflict = |path: &Path, message: String| Error::Conflict {
        path: path.to_path_buf(),
        message,
    };
    if dirs.is_empty() {
        return Err(Error::invalid("DIR", "(none)", "at least one shard folder"));
    }
    let mut shards: Vec<(Manifest, &PathBuf)> = Vec::new();
    for dir in dirs {
        if dir.join(files::CHECKPOINT).exists() {
            return Err(conflict(
                dir,
                "holds an unfinished run (checkpoint.json): rerun its shard to finish it first"
                    .into(),
            ));
        }
        // a folder that is not a finished shard's is named with what it lacks
        let manifest = dir.join(files::MANIFEST);
        let lacking = [files::OUTCOMES, files::MANIFEST]
            .into_iter()
            .find(|f| !dir.join(f).is_file());
        if let Some(file) = lacking {
            return Err(conflict(
                dir,
                if dir.is_dir() {
                    format!(
                        "holds no {file}: not the folder of a finished `rockfrag run --shard K/N` \
                         (each shard's folder has its outcomes.csv and manifest.json)"
                    )
                } else {
                    "no such folder: expected the folder of a finished `rockfrag run --shard K/N`"
                        .to_string()
                },
            ));
        }
        let m = Manifest::read(&manifest)?;
        if std::fs::canonicalize(dir).ok() == std::fs::canonicalize(out).ok() {
            return Err(conflict(
                out,
                "the output folder must not be one of the shard folders".into(),
            ));
        }
        shards.push((m, dir));
    }
    let (first, first_dir) = (&shards[0].0.clone(), shards[0].1.clone());
    let n = first.shard.count;
    for (m, dir) in &shards {
        if m.spec_hash != first.spec_hash || m.records_hash != first.records_hash {
            return Err(conflict(
                dir,
                format!(
                    "is a run of spec {} but {} is of spec {}: shards of different studies cannot be merged",
                    m.spec_hash,
                    first_dir.display(),
                    first.spec_hash
                ),
            ));
        }
        if m.shard.count != n {
            return Err(conflict(
                dir,
                format!("is shard {} where the others are of {n}", m.shard),
            ));
        }
    }
    shards.sort_by_key(|(m, _)| m.shard.index);
    // Every shard 1/N..N/N once: name the missing and the repeated ones.
    let given = |k: usize| shards.iter().filter(|(m, _)| m.shard.index == k).count();
    let missing: Vec<String> = (1..=n)
        .filter(|&k| given(k) == 0)
        .map(|k| format!("{k}/{n}"))
        .collect();
    let repeated: Vec<String> = (1..=n)
        .filter(|&k| given(k) > 1)
        .map(|k| {
            let where_: Vec<String> = shards
                .iter()
                .filter(|(m, _)| m.shard.index == k)
                .map(|(_, d)| d.display().to_string())
                .collect();
            format!("{k}/{n} (in {})", where_.join(" and "))
        })
        .collect();
    if !missing.is_empty() || !repeated.is_empty() {
        let have: Vec<String> = shards
            .iter()
            .map(|(m, d)| format!("{} in {}", m.shard, d.display()))
            .collect();
        let mut what = Vec::new();
        if !missing.is_empty() {
            what.push(format!(
                "shard {} missing (run it with --shard {} and merge again)",
                missing.join(", "),
                missing[0]
            ));
        }
        if !repeated.is_empty() {
            what.push(format!("shard {} given twice", repeated.join(", ")));
        }
        return Err(conflict(
            first_dir.as_path(),
            format!(
                "{}: every shard 1/{n}..{n}/{n} is needed once; given: {}",
                what.join("; "),
                have.join(", ")
            ),
        ));
    }

    let study = Study::from_toml_unchecked(&first.spec_toml, Path::new(&first.spec_file))?;
    if manifest::hash_text(study.hash()) != first.spec_hash {
        return Err(conflict(
            &first_dir,
            "its spec no longer hashes to its recorded hash (written by another rockfrag version?)"
                .into(),
        ));
    }
    let cols = plan::columns(&study);
    let header = cols.header();
    let cases = plan::cases(&study).len();
    let total = plan::unit_count(&study);

    // Each shard's file is checked on its own first (header, every row the
    // analysis expected at its place, the count), so an error names the
    // file to fix and its line, and a failed merge writes nothing.
    let mut readers = Vec::with_capacity(n);
    for (m, dir) in &shards {
        let path = dir.join(files::OUTCOMES);
        Tally::read(&path, &study, m.shard)?;
        let mut r = BufReader::new(std::fs::File::open(&path).map_err(Error::io(&path))?);
        let mut first_line = Vec::new();
        r.read_until(b'\n', &mut first_line)
            .map_err(Error::io(&path))?;
        if first_line != header.as_bytes() {
            return Err(Error::Parse {
                path,
                line: 1,
                message: "header is not the study's".into(),
            });
        }
        readers.push((r, path));
    }
    crate::io_util::create_folder(out)?;
    let _lock = super::lock::RunLock::acquire(out)?;
    if out.join(files::CHECKPOINT).exists() || out.join(files::PARTIAL).exists() {
        return Err(conflict(
            out,
            format!(
                "holds an unfinished run ({} or {}): refusing to merge into it; finish it with \
                 the `rockfrag run` that started it, or pass another --out",
                files::CHECKPOINT,
                files::PARTIAL
            ),
        ));
    }
    let mut whole = Manifest::new(&study, &first.spec_file, None, Shard::WHOLE);
    whole.records_hash = first.records_hash.clone();
    // as `run` does: a finished run of other analyses is refused unless
    // replaced; one of the same analyses is merged again
    manifest::check_finished(out, &whole, replace)?;
    manifest::clear_previous(out)?;
    let out_csv = out.join(files::OUTCOMES);
    let mut row = Vec::new();
    let mut short: Option<PathBuf> = None;
    crate::io_util::write_atomic(&out_csv, |w| {
        w.write_all(header.as_bytes())?;
        for u in 0..total {
            let (r, path) = &mut readers[u % n];
            for _ in 0..cases {
                row.clear();
                if !read_row(r, &mut row)? {
                    short = Some(path.clone());
                    return Err(std::io::Error::other("fewer rows than the study has"));
                }
                w.write_all(&row)?;
            }
        }
        Ok(())
    })
    .map_err(|e| match &short {
        Some(path) => Error::Parse {
            path: path.clone(),
            line: 0,
            message: "fewer rows than its shard of the study has".into(),
        },
        None => Error::io(&out_csv)(e),
    })?;
    for (r, path) in &mut readers {
        row.clear();
        if read_row(r, &mut row).map_err(Error::io(path))? {
            return Err(Error::Parse {
                path: path.clone(),
                line: 0,
                message: "more rows than its shard of the study has".into(),
            });
        }
    }

    let tally = Tally::read(&out_csv, &study, Shard::WHOLE)?;
    let mut m = whole;
    let started = shards
        .iter()
        .map(|(m, _)| m.started_unix)
        .min()
        .unwrap_or(0);
    let finished = shards
        .iter()
        .map(|(m, _)| m.finished_unix)
        .max()
        .unwrap_or(0);
    m.set_times(started, finished);
    m.threads = shards.iter().map(|(m, _)| m.threads).max().unwrap_or(0);
    m.analyses_run = shards.iter().map(|(m, _)| m.analyses_run).sum();
    m.wall_seconds = shards.iter().map(|(m, _)| m.wall_seconds).sum();
    m.counts = tally.counts();
    m.merged_from = shards
        .iter()
        .map(|(_, d)| d.display().to_string())
        .collect();
    m.write(&out.join(files::MANIFEST))?;
    Ok(m)
}

/// Reads one CSV row's bytes (a line break inside quotes does not end it);
/// `false` at the end of the input.
fn read_row(r: &mut impl BufRead, row: &mut Vec<u8>) -> std::io::Result<bool> {
    loop {
        let n = r.read_until(b'\n', row)?;
        if n == 0 {
            return Ok(!row.is_empty());
        }
        if row.iter().filter(|&&b| b == b'"').count() % 2 == 0 {
            return Ok(true);
        }
    }
}
