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
    /// FNV-1a 64-bit hash of the record files' bytes, in order (recorded motions only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub records_hash: Option<String>,
    /// The spec as parsed, every default written out (canonical TOML text).
    pub spec_toml: String,
    /// The same spec as JSON, for reading.
    pub spec: serde_json::Value,
    /// rockfrag's version.
    pub rockfrag_version: String,
    /// What a rerun reproduces ([`REPRODUCIBILITY`]); empty in manifests
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
            records_hash: records_hash.map(hash_text),
            spec: serde_json::to_value(study.to_spec_file()).expect("spec serialises to JSON"),
            spec_toml,
            rockfrag_version: env!("CARGO_PKG_VERSION").to_string(),
            reproducibility: REPRODUCIBILITY.to_string(),
            git_commit: GIT_COMMIT.to_string(),
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

/// Refuses to start a run into `dir` over a finished run (its
/// `outcomes.csv`) of another spec, other record files or another shard
/// than `this` describes, unless `force`. A finished run of the same spec
/// and shard is simply run again.
pub fn check_finished(dir: &Path, this: &Manifest, force: bool) -> Result<()> {
    let outcomes = dir.join(super::files::OUTCOMES);
    if force || !outcomes.exists() {
        return Ok(());
    }
    let path = dir.join(super::files::MANIFEST);
    let what = match Manifest::read(&path) {
        Ok(old) => {
            if old.spec_hash == this.spec_hash
                && old.records_hash == this.records_hash
                && old.shard == this.shard
            {
                return Ok(());
            }
            let mut diff = Vec::new();
            if old.spec_hash != this.spec_hash {
                diff.push(format!(
                    "spec hash {} (study '{}', from {}), not {}",
                    old.spec_hash, old.study, old.spec_file, this.spec_hash
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
            format!("a finished run of another spec: {}", diff.join("; "))
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
