//! `fragility_set.json`: the files of one fit are one set.
//!
//! A fit writes four files (`fragility.csv`, `fragility_curves.csv`,
//! `fragility_bootstrap.csv`, `fragility.xml`), each atomically but one after
//! the other. A refit killed between them would leave files of two fits side
//! by side (a PGV `fragility.csv` beside the PGA bootstrap of the fit before,
//! which `risk` would combine into a band that excludes its own estimate).
//! So the writer first records in `fragility_set.json` that a fit is being
//! written (`"status": "writing"`), then writes the four files, then records
//! each one's size and FNV-1a hash (`"status": "complete"`). Every reader of a
//! fit (the risk integral, the exports, the figures, `summary.md`, and Python
//! through them) calls [`check_set`] first: an interrupted fit, or a file
//! that is not the one its fit wrote (changed, replaced or removed since),
//! is refused with the advice to rerun `rockfrag fragility`. A folder fitted
//! by a rockfrag older than the set file (no `fragility_set.json`) is read as
//! before. A fit with a fragility surface writes `fragility_surface.csv`
//! too, after the four, and lists it in the set.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::io_util::{fnv1a64, write_atomic};

/// The set file's name, beside the fit's files.
pub const SET_FILE: &str = "fragility_set.json";

/// The files of one fit, in the order they are written.
pub const SET_FILES: [&str; 4] = [
    "fragility.csv",
    "fragility_curves.csv",
    "fragility_bootstrap.csv",
    "fragility.xml",
];

/// Contents of `fragility_set.json`.
#[derive(Debug, Serialize, Deserialize)]
struct FitSet {
    /// `writing` while the fit's files are written, `complete` after.
    status: String,
    /// Each file of the set as written (empty while `writing`).
    #[serde(default)]
    files: Vec<SetFile>,
}

/// One file of a set: its name, size and hash.
#[derive(Debug, Serialize, Deserialize)]
struct SetFile {
    name: String,
    bytes: u64,
    fnv1a64: String,
}

fn write_set(dir: &Path, set: &FitSet) -> Result<()> {
    let path = dir.join(SET_FILE);
    write_atomic(&path, |w| {
        serde_json::to_writer_pretty(&mut *w, set)?;
        w.write_all(b"\n")
    })
    .map_err(Error::io(&path))
}

/// Records in `dir` that a fit's files are about to be written: until
/// [`complete`], readers refuse the folder's fit.
pub(crate) fn begin(dir: &Path) -> Result<()> {
    write_set(
        dir,
        &FitSet {
            status: "writing".into(),
            files: Vec::new(),
        },
    )
}

/// The files the set in `dir` lists (none when there is no readable set
/// file).
pub(crate) fn listed(dir: &Path) -> Vec<String> {
    std::fs::read_to_string(dir.join(SET_FILE))
        .ok()
        .and_then(|t| serde_json::from_str::<FitSet>(&t).ok())
        .map_or_else(Vec::new, |s| s.files.into_iter().map(|f| f.name).collect())
}

/// Records the fit's files, now written in `dir`, as one set: those of
/// [`SET_FILES`] and `extra` (a surface's `fragility_surface.csv`).
pub(crate) fn complete(dir: &Path, extra: &[&str]) -> Result<()> {
    let files = SET_FILES
        .iter()
        .chain(extra)
        .map(|name| {
            let path = dir.join(name);
            let bytes = std::fs::read(&path).map_err(Error::io(&path))?;
            Ok(SetFile {
                name: name.to_string(),
                bytes: bytes.len() as u64,
                fnv1a64: format!("{:016x}", fnv1a64(&bytes)),
            })
        })
        .collect::<Result<Vec<_>>>()?;
    write_set(
        dir,
        &FitSet {
            status: "complete".into(),
            files,
        },
    )
}

/// Checks that the fit files in `dir` are the set one fit wrote (see the
/// module's docs); a folder without a set file (fitted by an older
/// rockfrag, or not fitted) passes.
///
/// Errors: [`Error::Conflict`] naming the set file, what does not match and
/// the command that makes a whole set again; [`Error::Parse`] for a set
/// file that cannot be read.
pub fn check_set(dir: &Path) -> Result<()> {
    let path = dir.join(SET_FILE);
    let text = match std::fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(Error::io(&path)(e)),
    };
    let set: FitSet = serde_json::from_str(&text).map_err(|e| Error::Parse {
        path: path.clone(),
        line: e.line(),
        message: format!(
            "{e}; rerun `rockfrag fragility {}` to fit again",
            dir.display()
        ),
    })?;
    let refuse = |what: String| Error::Conflict {
        path: path.clone(),
        message: format!(
            "{what}: the files of one fit are read together or not at all; rerun `rockfrag \
             fragility {}` (with the options of the fit you want) to write a whole set",
            dir.display()
        ),
    };
    if set.status != "complete" {
        return Err(refuse(format!(
            "the fit in this folder was interrupted while its files were written (status \
             {:?}): {} may come from two different fits",
            set.status,
            SET_FILES.join(", ")
        )));
    }
    for f in &set.files {
        let file = dir.join(&f.name);
        let bytes = match std::fs::read(&file) {
            Ok(b) => b,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Err(refuse(format!("{} of this fit is missing", f.name)));
            }
            Err(e) => return Err(Error::io(&file)(e)),
        };
        let hash = format!("{:016x}", fnv1a64(&bytes));
        if bytes.len() as u64 != f.bytes || hash != f.fnv1a64 {
            return Err(refuse(format!(
                "{} is not the file this fit wrote ({} bytes, hash {hash}; the fit wrote {} \
                 bytes, hash {}): it was changed or replaced since",
                f.name,
                bytes.len(),
                f.bytes,
                f.fnv1a64
            )));
        }
    }
    Ok(())
}
