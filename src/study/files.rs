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
