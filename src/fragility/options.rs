//! What a fit is asked for: the intensity measure and the fit's settings
//! (the spec's `[fragility]` table).

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// The intensity measure the curves are fitted against.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum IntensityMeasure {
    /// Peak ground acceleration, in g (default).
    #[default]
    Pga,
    /// Peak ground velocity, in m/s (needs a `pgv` column).
    Pgv,
    /// PGA/(g tan θc) = PGA·(H/B), dimensionless: 1 is the uplift threshold
    /// of a block on a rigid base under infinite friction.
    PgaOverTan,
}

impl IntensityMeasure {
    /// Name used in the CLI and the CSV files.
    pub fn name(self) -> &'static str {
        match self {
            IntensityMeasure::Pga => "pga",
            IntensityMeasure::Pgv => "pgv",
            IntensityMeasure::PgaOverTan => "pga-over-tan",
        }
    }

    /// Unit of the intensity (`1` for dimensionless).
    pub fn unit(self) -> &'static str {
        match self {
            IntensityMeasure::Pga => "g",
            IntensityMeasure::Pgv => "m/s",
            IntensityMeasure::PgaOverTan => "1",
        }
    }
}

/// Settings of the fragility fit. Plain data with documented defaults.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FragilityOptions {
    /// Intensity measure (default: PGA in g).
    pub im: IntensityMeasure,
    /// Bootstrap replicates; 0 skips the bootstrap and leaves the bands
    /// empty (default: 1000).
    pub bootstrap: usize,
    /// What a replicate resamples (default: whole records, shared across stripes).
    pub unit: BootstrapUnit,
    /// Seed of the bootstrap; replicate r draws from a generator seeded with
    /// [`replicate_seed`](super::replicate_seed)`(seed, r)` (default: 1).
    pub seed: u64,
    /// Two-sided confidence level of the intervals and bands, in (0, 1)
    /// (default: 0.9, i.e. the 5th and 95th percentiles).
    pub confidence: f64,
    /// Points of each curve's IM grid, evenly spaced from 0 to the largest
    /// intensity of the case, ≥ 2 (default: 101).
    pub grid_points: usize,
}

impl Default for FragilityOptions {
    fn default() -> Self {
        FragilityOptions {
            im: IntensityMeasure::Pga,
            bootstrap: 1000,
            unit: BootstrapUnit::Records,
            seed: 1,
            confidence: 0.9,
            grid_points: 101,
        }
    }
}

impl FragilityOptions {
    /// Checks the ranges documented on each field.
    pub fn validate(&self) -> Result<()> {
        if !(self.confidence > 0.0 && self.confidence < 1.0) {
            return Err(Error::invalid(
                "fragility.confidence",
                self.confidence,
                "a number in (0, 1)",
            ));
        }
        if self.grid_points < 2 {
            return Err(Error::invalid(
                "fragility.grid_points",
                self.grid_points,
                "an integer ≥ 2",
            ));
        }
        Ok(())
    }
}

/// What a bootstrap replicate resamples.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BootstrapUnit {
    /// Whole records (default): as many records as the case has are drawn
    /// with replacement, and a drawn record brings its analyses at *every*
    /// stripe. Right for a study that scales the same records to each stripe,
    /// where one record's outcomes at different stripes are correlated.
    #[default]
    Records,
    /// Analyses, independently within each stripe (each stripe keeps its
    /// size). Right only when analyses are independent trials, e.g. a
    /// different record for every analysis.
    Analyses,
}
