//! `[infer]`: the settings of `rockfrag infer` (inferring the intensity a
//! site felt from the objects that overturned there), read with the rest of
//! the spec. A study run ignores the table.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// The `[infer]` table. Plain data; every field has a default.
///
/// ```toml
/// [infer]
/// draws = 40          # property draws per kind, record and level
/// refine = 8          # grid points per interval between levels
/// seating = 0.2       # effective base width uniform in 80–100 % of the nominal
/// bootstrap = 200     # replicates for the Monte Carlo error
/// # seed = 7          # seed of the draws (default: [uncertainty]'s, else the study's)
/// # slide_limit_state = "slides-5cm"   # the limit state a survey's `slid` counts
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct InferSettings {
    /// Analyses per kind of object, record and intensity level, each with
    /// its own draw of the kind's uncertain properties. A kind whose
    /// properties are all fixed is solved once per record and level (every
    /// draw would be the same). At least 1 (default: 40).
    pub draws: usize,
    /// Intervals of the posterior's grid per interval between two levels
    /// (geometric): the fractions overturned are interpolated between a
    /// record's levels, so a record whose scaling matches the survey
    /// between two levels is not missed. At least 1; 1 evaluates at the
    /// levels only (default: 8).
    pub refine: usize,
    /// Seating: how much of its base an object may not rest on. Each draw's
    /// effective base width 2B is the nominal times a factor uniform in
    /// [1 − seating, 1] (its height unchanged, so H/B grows as 2B shrinks):
    /// a tombstone on an uneven bed rocks about a point inside its
    /// footprint. In [0, 0.9]; 0 turns it off (default: 0).
    pub seating: f64,
    /// Bootstrap replicates (over records and over draws) for the Monte
    /// Carlo error of the posterior's median and bounds; 0 skips it
    /// (default: 200).
    pub bootstrap: usize,
    /// Seed of the property draws and of the bootstrap (default: the
    /// `[uncertainty]` table's seed, else the study's `seed`, else 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// The `[[fragility.limit_state]]` (by name) whose exceedance a survey's
    /// `slid` column counts among the objects still standing; needed only
    /// when the spec has several limit states on `slip_max` or `slip_final`
    /// (default: the one such limit state).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slide_limit_state: Option<String>,
}

impl Default for InferSettings {
    fn default() -> Self {
        InferSettings {
            draws: 40,
            refine: 8,
            seating: 0.0,
            bootstrap: 200,
            seed: None,
            slide_limit_state: None,
        }
    }
}

/// Most draws per kind, record and level accepted.
pub const MAX_DRAWS: usize = 1_000_000;

impl InferSettings {
    /// Checks the ranges documented on each field; errors name the field
    /// (`infer.draws`, …).
    pub fn validate(&self) -> Result<()> {
        if !(1..=MAX_DRAWS).contains(&self.draws) {
            return Err(Error::invalid(
                "infer.draws",
                self.draws,
                &format!("a whole number of draws from 1 to {MAX_DRAWS}"),
            ));
        }
        if !(1..=1000).contains(&self.refine) {
            return Err(Error::invalid(
                "infer.refine",
                self.refine,
                "a whole number of intervals from 1 to 1000",
            ));
        }
        if !(0.0..=0.9).contains(&self.seating) {
            return Err(Error::invalid(
                "infer.seating",
                self.seating,
                "a fraction of the base width in [0, 0.9]",
            ));
        }
        if self.bootstrap > 100_000 {
            return Err(Error::invalid(
                "infer.bootstrap",
                self.bootstrap,
                "at most 100000 replicates (0 skips the bootstrap)",
            ));
        }
        Ok(())
    }
}
