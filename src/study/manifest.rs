//! `manifest.json`: the provenance of a run — the spec as parsed and its
//! hash, the program's version and commit, when it ran, on how many threads,
//! and what it counted.

use super::plan::Shard;
use super::tally::Counts;
use crate::error::{Error, Result};
use crate::spec::Study;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The git commit this library was built from, or `unknown`.
pub const GIT_COMMIT: &str = env!("ROCKFRAG_GIT_COMMIT");

/// Hash of the source this binary was built from (`src/`, `Cargo.toml`,
/// `Cargo.lock`, committed or not): a finished run is reused only by a
/// build of the same source.
pub const SOURCE_HASH: &str = env!("ROCKFRAG_SOURCE_HASH");

/// What the same spec gives on a rerun, as the manifest states it.
pub const REPRODUCIBILITY: &str = "outcomes.csv, fragility.csv, fragility_curves.csv, \
fragility_bootstrap.csv, fragility.xml, risk.csv, summary.md and the figures are byte-identical \
for the same rockfrag version and spec (spec_hash, and records_hash for record files) on any \
platform with IEEE-754 double arithmetic (x86-64, AArch64, ...; any OS, C library or CPU), with \
any thread count, and for any shard split once merged; this manifest's times and thread count \
are the run's own. Every transcendental function is computed by rockfrag itself (libm crate), \
none by the platform's math library; scripts/check-platforms.sh checks glibc against musl.";

/// Contents of `manifest.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Study name.
    pub study: String,
    /// The spec file as given on the command line (or the built-in study).
    pub spec_file: String,
    /// FNV-1a 64-bit hash of `spec_toml`, as `fnv1a64:<16 hex digits>`.
    pub spec_hash: String,
    /// [`crate::spec::Study::analyses_hash`]: the spec without the fields that only
    /// change the post-processing (empty in manifests of older versions).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub analyses_hash: String,
    /// `SOURCE_HASH` of the build that wrote it (empty in older manifests).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub source_hash: String,
    /// FNV-1a 64-bit hash of the record files' bytes, in order (recorded motions only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub records_hash: Option<String>,
    /// The spec as parsed, every default written out (canonical TOML text).
    pub spec_toml: String,
    /// The same spec as JSON, for reading.
    pub spec: serde_json::Value,
    /// rockfrag's version.
    pub rockfrag_version: String,
    /// What a rerun reproduces (`REPRODUCIBILITY`); empty in manifests
    /// written before it was recorded.
    #[serde(default)]
    pub reproducibility: String,
    /// Git commit of the build (`unknown` without git).
    pub git_commit: String,
    /// The shard this folder holds (1/1: the whole study).
    pub shard: Shard,
    /// Worker threads of the last invocation.
    pub threads: usize,
    /// Start of the run (first invocation), seconds since the Unix epoch.
    pub started_unix: u64,
    /// Start of the run, UTC, ISO 8601.
    pub started_utc: String,
    /// End of the run, seconds since the Unix epoch.
    pub finished_unix: u64,
    /// End of the run, UTC, ISO 8601.
    pub finished_utc: String,
    /// Units done by earlier, interrupted invocations (0 if none).
    pub resumed_at_unit: usize,
    /// Analyses run by the last invocation.
    pub analyses_run: u64,
    /// Wall time of the last invocation, s.
    pub wall_seconds: f64,
    /// Counts over every analysis in `outcomes.csv`.
    pub counts: Counts,
    /// Shard folders this folder was merged from (empty for a run).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub merged_from: Vec<String>,
    /// The files rockfrag made from this run's outcomes inside its folder
    /// (the fit, `summary.md`, figures, risk files), relative to the folder,
    /// in the order first written: what a run that replaces this one
    /// removes ([`clear_previous`]). Empty in manifests of older versions.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub outputs: Vec<String>,
}

impl Manifest {
    /// The fields that describe the study, the program and the shard; the
    /// times, threads and counts are the caller's to fill in.
    pub fn new(
        study: &Study,
        spec_file: &str,
        records_hash: Option<u64>,
        shard: Shard,
    ) -> Manifest {
        let spec_toml = study.to_toml();
        Manifest {
            study: study.name.clone(),
            spec_file: spec_file.to_string(),
            spec_hash: hash_text(study.hash()),
            analyses_hash: hash_text(study.analyses_hash()),
            records_hash: records_hash.map(hash_text),
            spec: serde_json::to_value(study.to_spec_file()).expect("spec serialises to JSON"),
            spec_toml,
            rockfrag_version: env!("CARGO_PKG_VERSION").to_string(),
            reproducibility: REPRODUCIBILITY.to_string(),
            git_commit: GIT_COMMIT.to_string(),
            source_hash: SOURCE_HASH.to_string(),
            shard,
            threads: 0,
            started_unix: 0,
            started_utc: String::new(),
            finished_unix: 0,
            finished_utc: String::new(),
            resumed_at_unit: 0,
            analyses_run: 0,
            wall_seconds: 0.0,
            counts: Counts::default(),
            merged_from: Vec::new(),
            outputs: Vec::new(),
        }
    }

    /// Sets the start and end times from epoch seconds.
    pub fn set_times(&mut self, started: u64, finished: u64) {
        self.started_unix = started;
        self.started_utc = iso8601(started);
        self.finished_unix = finished;
        self.finished_utc = iso8601(finished);
    }

    /// Writes the manifest atomically (temporary file, then rename).
    pub fn write(&self, path: &Path) -> Result<()> {
        crate::io_util::write_atomic(path, |w| {
            serde_json::to_writer_pretty(&mut *w, self)?;
            w.write_all(b"\n")
        })
        .map_err(Error::io(path))
    }

    /// Reads a manifest.
    pub fn read(path: &Path) -> Result<Manifest> {
        let text = std::fs::read_to_string(path).map_err(Error::io(path))?;
        serde_json::from_str(&text).map_err(|e| Error::Parse {
            path: path.to_path_buf(),
            line: e.line(),
            message: e.to_string(),
        })
    }
}

/// What a run into a folder finds there (`check_finished`).
#[derive(Clone, Debug, PartialEq)]
pub enum Finished {
    /// No finished run, one to be replaced (`--force`), or one of the same
    /// analyses by another build of rockfrag: run the analyses.
    No,
    /// A finished run of the same analyses (`Manifest` is its manifest):
    /// its `outcomes.csv` is kept and only the post-processing is redone.
    Same(Box<Manifest>),
}

impl Manifest {
    /// Whether `self` (a finished run's manifest) ran the analyses `this`
    /// describes: the same analyses hash (the spec hash for manifests of
    /// versions without one), record files and shard.
    fn same_analyses(&self, this: &Manifest) -> bool {
        let same_spec = if self.analyses_hash.is_empty() {
            self.spec_hash == this.spec_hash
        } else {
            self.analyses_hash == this.analyses_hash
        };
        same_spec && self.records_hash == this.records_hash && self.shard == this.shard
    }
}

/// Looks for a finished run (`outcomes.csv`) in `dir`. Without `force`, a
/// finished run of the same analyses as `this` is [`Finished::Same`] and a
/// finished run of other analyses (another spec, other record files or
/// another shard) is refused; with `force`, or when another build of
/// rockfrag made it, the folder's run is replaced.
pub fn check_finished(dir: &Path, this: &Manifest, force: bool) -> Result<Finished> {
    let outcomes = dir.join(super::files::OUTCOMES);
    if force || !outcomes.exists() {
        return Ok(Finished::No);
    }
    let path = dir.join(super::files::MANIFEST);
    let what = match Manifest::read(&path) {
        Ok(old) => {
            if old.same_analyses(this) {
                // Another build may give other bits (same version, same spec,
                // same bytes), so only this build's own runs are reused.
                let same_build = old.rockfrag_version == this.rockfrag_version
                    && !old.source_hash.is_empty()
                    && old.source_hash == this.source_hash;
                return Ok(if same_build {
                    Finished::Same(Box::new(old))
                } else {
                    Finished::No
                });
            }
            let mut diff = Vec::new();
            if !old.same_analyses(&Manifest {
                records_hash: old.records_hash.clone(),
                shard: old.shard,
                ..this.clone()
            }) {
                diff.push(format!(
                    "study '{}' from {} (spec hash {}), whose analyses differ from this spec's \
                     (a field other than name, description, output.summary, output.figures \
                     and, for a fixed grid, [fragility] changed; an adaptive study's \
                     [fragility] decides its analyses)",
                    old.study, old.spec_file, old.spec_hash
                ));
            }
            if old.records_hash != this.records_hash {
                diff.push(format!(
                    "record files {}, not {}",
                    old.records_hash.as_deref().unwrap_or("none (synthetic)"),
                    this.records_hash.as_deref().unwrap_or("none (synthetic)")
                ));
            }
            if old.shard != this.shard {
                diff.push(format!("shard {}, not {}", old.shard, this.shard));
            }
            format!("a finished run of other analyses: {}", diff.join("; "))
        }
        Err(e) => format!("an outcomes.csv whose manifest cannot be read ({e})"),
    };
    Err(Error::Conflict {
        path: dir.to_path_buf(),
        message: format!(
            "holds {what}: refusing to overwrite it; pass another --out, or --force to replace it"
        ),
    })
}

/// What a folder's run wrote after its analyses, as rockfrag names it,
/// for manifests written before they listed their `outputs`.
const OLDER_OUTPUTS: [&str; 8] = [
    "fragility.csv",
    "fragility_curves.csv",
    "fragility_bootstrap.csv",
    "fragility.xml",
    crate::fragility::SET_FILE,
    "risk.csv",
    "risk_hazard.csv",
    super::files::SUMMARY,
];

/// Adds the files `written` that lie inside `dir` to the `outputs` of the
/// manifest of `dir`, when the folder holds a run (else nothing is done):
/// the run that replaces this one removes them.
pub fn record_outputs(dir: &Path, written: &[&Path]) -> Result<()> {
    let path = dir.join(super::files::MANIFEST);
    if !path.is_file() {
        return Ok(());
    }
    let Ok(root) = std::fs::canonicalize(dir) else {
        return Ok(());
    };
    let mut m = Manifest::read(&path)?;
    let before = m.outputs.len();
    for file in written {
        let inside = file
            .parent()
            .and_then(|p| std::fs::canonicalize(p).ok())
            .zip(file.file_name())
            .and_then(|(p, name)| p.join(name).strip_prefix(&root).ok().map(Path::to_path_buf));
        let Some(rel) = inside else { continue };
        let rel = rel.to_string_lossy().replace('\\', "/");
        if !m.outputs.contains(&rel) {
            m.outputs.push(rel);
        }
    }
    if m.outputs.len() == before {
        return Ok(());
    }
    m.write(&path)
}

/// Removes the finished run that `dir` holds, before a run or merge that
/// replaces it writes there: the files its manifest lists as its
/// `outputs` (the fixed names of the fit, risk and summary for a manifest
/// of an older version), then its `outcomes.csv` and `manifest.json`. Only
/// files rockfrag wrote, by those names, inside `dir`: nothing else in the
/// folder is touched. Returns the files removed.
pub fn clear_previous(dir: &Path) -> Result<Vec<std::path::PathBuf>> {
    let manifest = dir.join(super::files::MANIFEST);
    let listed: Vec<String> = match Manifest::read(&manifest) {
        Ok(m) if !m.outputs.is_empty() => m.outputs,
        Ok(_) => OLDER_OUTPUTS.iter().map(|s| s.to_string()).collect(),
        Err(_) => Vec::new(),
    };
    let mut removed = Vec::new();
    let plain = |rel: &str| {
        Path::new(rel)
            .components()
            .all(|c| matches!(c, std::path::Component::Normal(_)))
    };
    let names = listed
        .iter()
        .map(String::as_str)
        .filter(|r| plain(r))
        .chain([super::files::OUTCOMES, super::files::MANIFEST]);
    for rel in names {
        let path = dir.join(rel);
        let is_file = std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_file());
        if is_file {
            std::fs::remove_file(&path).map_err(Error::io(&path))?;
            removed.push(path);
        }
    }
    Ok(removed)
}

/// A hash as written in manifests and checkpoints.
pub fn hash_text(h: u64) -> String {
    format!("fnv1a64:{h:016x}")
}

/// Seconds since the Unix epoch, now.
pub fn now_unix() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs())
}

/// Epoch seconds as UTC ISO 8601, `YYYY-MM-DDThh:mm:ssZ` (proleptic Gregorian).
pub fn iso8601(secs: u64) -> String {
    let days = (secs / 86_400) as i64;
    let rem = secs % 86_400;
    // Civil date from days since 1970-01-01 (H. Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + (month <= 2) as i64;
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn iso8601_known_dates() {
        assert_eq!(iso8601(0), "1970-01-01T00:00:00Z");
        assert_eq!(iso8601(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(iso8601(1_700_000_000), "2023-11-14T22:13:20Z");
    }
}
