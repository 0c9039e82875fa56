//! The disk space a run's `outcomes.csv` will take, checked before the bulk
//! of the analyses: a grid of 10⁸ analyses writes some 25 GB, and a run
//! that fills the disk after hours has wasted them. The size is estimated
//! from the first rows a run formats (the pilot's, one unit per intensity
//! level, or the first chunk's), compared with the space free on the
//! folder's file system, and said for a big run.

use std::path::Path;

use crate::error::{Error, Result};
use crate::io_util::bytes_text;

/// A run whose `outcomes.csv` is estimated at this or more is told the
/// estimate and the free space (1 GiB).
pub const SAY_FROM_BYTES: u64 = 1 << 30;

/// The margin on the estimate: rows of later levels may be longer than the
/// sample's (more impacts, longer numbers).
const MARGIN: f64 = 1.1;

/// Bytes free to an unprivileged writer on the file system holding `dir`;
/// `None` where it cannot be known.
pub fn free_bytes(dir: &Path) -> Option<u64> {
    #[cfg(unix)]
    {
        rustix::fs::statvfs(dir)
            .ok()
            .map(|s| s.f_bavail.saturating_mul(s.f_frsize))
    }
    #[cfg(not(unix))]
    {
        let _ = dir;
        None
    }
}

/// The estimate of what the rest of a run writes.
#[derive(Clone, Debug, PartialEq)]
pub struct SpaceEstimate {
    /// Analyses still to be written.
    pub analyses: u64,
    /// Mean bytes of a row in the sample.
    pub bytes_per_row: f64,
    /// The bytes still to be written, with a 10 % margin.
    pub bytes: u64,
    /// Bytes free on the folder's file system, if known.
    pub free: Option<u64>,
}

impl SpaceEstimate {
    /// The estimate for `analyses` more rows from a sample of `rows` rows
    /// of `sample_bytes` bytes, with the free space of `dir`.
    pub fn new(dir: &Path, sample_bytes: usize, rows: usize, analyses: u64) -> SpaceEstimate {
        let bytes_per_row = sample_bytes as f64 / rows.max(1) as f64;
        SpaceEstimate {
            analyses,
            bytes_per_row,
            bytes: (analyses as f64 * bytes_per_row * MARGIN).ceil() as u64,
            free: free_bytes(dir),
        }
    }

    /// The line that says it: `outcomes.csv: about 24.6 GiB more (…)`.
    pub fn line(&self) -> String {
        format!(
            "outcomes.csv: about {} more ({} analyses × {:.0} bytes a row, from the first rows, \
             + 10 %); {} free on its file system",
            bytes_text(self.bytes),
            self.analyses,
            self.bytes_per_row,
            self.free.map_or_else(|| "unknown".to_string(), bytes_text)
        )
    }

    /// Refuses a run the free space cannot hold (unless `unchecked`).
    pub fn check(&self, dir: &Path, unchecked: bool) -> Result<()> {
        match self.free {
            Some(free) if !unchecked && self.bytes > free => Err(Error::Conflict {
                path: dir.to_path_buf(),
                message: format!(
                    "not enough disk space: {}; free some space, pass another --out, or fewer \
                     analyses (run the study in shards on other disks and merge them); \
                     --no-space-check runs anyway (where the file system reports its free \
                     space wrongly)",
                    self.line()
                ),
            }),
            _ => Ok(()),
        }
    }
}
