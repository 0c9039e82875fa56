//! File names inside a run's folder.

/// Final outcomes, one row per analysis.
pub const OUTCOMES: &str = "outcomes.csv";
/// Outcomes of a run in progress.
pub const PARTIAL: &str = "outcomes.csv.partial";
/// Progress of a run in progress.
pub const CHECKPOINT: &str = "checkpoint.json";
/// Paper-style tables.
pub const SUMMARY: &str = "summary.md";
/// Provenance and counts.
pub const MANIFEST: &str = "manifest.json";

use crate::error::{Error, Result};
use std::path::Path;

/// Checks that `dir` holds a finished run (its `outcomes.csv`), before a
/// command reads from it. An interrupted run (its checkpoint or partial
/// outcomes) is told to be finished by rerunning `rockfrag run`; a folder
/// that is not a run's is said to be so, not met with a bare "No such file".
pub fn require_finished(dir: &Path) -> Result<()> {
    if dir.join(OUTCOMES).is_file() {
        return Ok(());
    }
    let message = if !dir.is_dir() {
        "no such folder: expected the output folder of `rockfrag run`".to_string()
    } else if dir.join(CHECKPOINT).exists() || dir.join(PARTIAL).exists() {
        let done = std::fs::read_to_string(dir.join(CHECKPOINT))
            .ok()
            .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
            .and_then(|v| v.get("units_done").and_then(serde_json::Value::as_u64));
        format!(
            "holds an unfinished run{}: rerun the `rockfrag run` that started it (the same \
             spec, with `--out {}`) to finish it; it resumes where it stopped",
            done.map_or(String::new(), |n| format!(" ({n} work units done)")),
            dir.display()
        )
    } else {
        format!("holds no {OUTCOMES}: not the output folder of a `rockfrag run`")
    };
    Err(Error::Conflict {
        path: dir.to_path_buf(),
        message,
    })
}
