//! Lognormal overturning fragility curves fitted to a study's outcomes, with
//! bootstrap confidence bands and an OpenQuake export.
//!
//! ```text
//! outcomes.csv ─▶ data: cases, stripes, records ─▶ fit: probit MLE (θ, β, SEs)
//!   ─▶ bootstrap: resample records, refit ─▶ output: fragility.csv,
//!      fragility_curves.csv ─▶ nrml: fragility.xml (OpenQuake NRML 0.5)
//! ```
//!
//! ## Model
//!
//! For one case (block geometry, restitution, friction), the probability of
//! overturning at intensity x is lognormal (Baker 2015):
//!
//! ```text
//! P(overturn | IM = x) = Φ(ln(x/θ)/β) = Φ(a + b ln x),  θ = exp(−a/b), β = 1/b
//! ```
//!
//! The analyses at one PGA level form a *stripe*; with nᵢ analyses at xᵢ of
//! which zᵢ overturned, (a, b) maximise the binomial log-likelihood
//! Σ ln C(nᵢ, zᵢ) + zᵢ ln Φ(ηᵢ) + (nᵢ − zᵢ) ln Φ(−ηᵢ), ηᵢ = a + b ln xᵢ. It is
//! concave; Newton's method with step halving converges in a handful of
//! iterations ([`fit_lognormal`]). The observed information at the maximum
//! gives standard errors of (a, b), and of θ and β by the delta method. Those
//! treat every analysis as independent; when the same records are used at
//! every stripe they are not, which is what the bootstrap accounts for.
//!
//! A case cannot be fitted when no analysis or every analysis overturned,
//! when all analyses share one intensity, or when the data are perfectly
//! separated (no overturning below some intensity, all above it: the
//! maximum-likelihood β is 0). The fit then returns an [`Unfit`] reason,
//! written to the `status` column with the numbers left empty.
//!
//! ## Uncertainty
//!
//! Percentile bootstrap ([`bootstrap`]): each replicate resamples whole
//! records with replacement (a drawn record brings its analyses at every
//! stripe) or, for independent trials, analyses within each stripe
//! ([`BootstrapUnit`]); the fit is repeated, and the 5th–95th percentiles
//! (for the default 90 % level) of θ, β and of the curve at each grid point
//! form the bands. Replicates that cannot be fitted (typically separated
//! resamples of a steep curve) are counted by reason and left out of the
//! percentiles; when they are more than a few percent of the total, the
//! bands are conditional on a fit existing and too narrow on the steep side.
//!
//! ## Intensity measures
//!
//! [`IntensityMeasure`]: PGA in g (the stripes' level), PGV in m/s (the
//! `pgv` column: each analysis has its own, so the fit is over analyses
//! grouped by equal PGV), or the dimensionless PGA/(g tan θc) = PGA·(H/B),
//! the block's uplift threshold under infinite friction being 1.
//!
//! ## References
//! - Baker, J. W. (2015). Efficient analytical fragility function fitting
//!   using dynamic structural analysis. *Earthquake Spectra* 31(1), 579–599.
//! - Efron, B. and Tibshirani, R. J. (1993). *An Introduction to the
//!   Bootstrap*. Chapman & Hall.
//! - GEM Foundation. OpenQuake engine manual, *Fragility models* (NRML 0.5).

mod bootstrap;
mod data;
mod fit;
mod nrml;
mod output;

use std::path::Path;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

pub use crate::study::CaseKey;
pub use bootstrap::{
    BootstrapSummary, BootstrapUnit, Interval, bootstrap, percentile, replicate_seed,
};
pub use data::{Analysis, CaseData, Outcomes, read_outcomes};
pub use fit::{LognormalFit, Observation, Unfit, fit_lognormal};
pub use nrml::{
    lognormal_to_moments, moments_to_lognormal, nrml_string, openquake_imt, write_nrml,
};
pub use output::{
    CURVES_HEADER, FRAGILITY_HEADER, OutputPaths, write_curves_csv, write_fragility_csv,
    write_outputs,
};

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
    /// [`replicate_seed`]`(seed, r)` (default: 1).
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

/// A fitted curve sampled on a grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// Intensities, evenly spaced from 0 to the case's largest intensity.
    pub im: Vec<f64>,
    /// Fitted probability of overturning at each intensity.
    pub probability: Vec<f64>,
}

/// Everything known about one case's fragility.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseFit {
    /// The block configuration.
    pub key: CaseKey,
    /// The intensity measure of the fit.
    pub im: IntensityMeasure,
    /// Successful analyses.
    pub n_analyses: usize,
    /// Of those, analyses that overturned.
    pub n_overturned: usize,
    /// Records with at least one successful analysis.
    pub n_records: usize,
    /// Stripes (PGA levels) with at least one successful analysis.
    pub n_stripes: usize,
    /// Failed analyses, skipped.
    pub n_failed: usize,
    /// Smallest and largest intensity among the analyses (`None` without any).
    pub im_range: Option<(f64, f64)>,
    /// Counts grouped by equal intensity: what was fitted.
    pub observations: Vec<Observation>,
    /// The maximum-likelihood fit, or why there is none.
    pub fit: std::result::Result<LognormalFit, Unfit>,
    /// The bootstrap (only for a fitted case with replicates requested).
    pub bootstrap: Option<BootstrapSummary>,
    /// The fitted curve (only for a fitted case).
    pub curve: Option<Curve>,
}

/// Fits one case: maximum likelihood, then the bootstrap if requested.
pub fn fit_case(case: &CaseData, options: &FragilityOptions) -> CaseFit {
    let mut observations: Vec<Observation> = Vec::new();
    let mut sorted = case.analyses.clone();
    sorted.sort_by(|x, y| x.im.total_cmp(&y.im));
    for a in &sorted {
        match observations.last_mut() {
            Some(o) if o.im == a.im => {
                o.trials += 1;
                o.overturned += u64::from(a.overturned);
            }
            _ => observations.push(Observation {
                im: a.im,
                trials: 1,
                overturned: u64::from(a.overturned),
            }),
        }
    }
    let im_range = observations
        .first()
        .zip(observations.last())
        .map(|(lo, hi)| (lo.im, hi.im));
    let fit = fit_lognormal(&observations);
    let (mut curve, mut boot) = (None, None);
    if let (Ok(f), Some((_, im_max))) = (&fit, im_range) {
        let n = options.grid_points;
        let im: Vec<f64> = (0..n).map(|i| im_max * i as f64 / (n - 1) as f64).collect();
        if options.bootstrap > 0 {
            boot = Some(bootstrap(
                case,
                &im,
                options.bootstrap,
                options.unit,
                options.seed,
                options.confidence,
            ));
        }
        curve = Some(Curve {
            probability: im.iter().map(|&x| f.probability(x)).collect(),
            im,
        });
    }
    CaseFit {
        key: case.key,
        im: options.im,
        n_analyses: case.analyses.len(),
        n_overturned: case.analyses.iter().filter(|a| a.overturned).count(),
        n_records: case.n_records(),
        n_stripes: case.n_stripes(),
        n_failed: case.failed,
        im_range,
        observations,
        fit,
        bootstrap: boot,
        curve,
    }
}

/// Fits every case of `outcomes` (in parallel; the result does not depend on
/// the number of threads). The outcomes must have been read with `options.im`.
pub fn fit_cases(outcomes: &Outcomes, options: &FragilityOptions) -> Result<Vec<CaseFit>> {
    options.validate()?;
    if outcomes.im != options.im {
        return Err(Error::invalid(
            "fragility.im",
            options.im.name(),
            &format!(
                "the intensity measure the outcomes were read with ({})",
                outcomes.im.name()
            ),
        ));
    }
    Ok(outcomes
        .cases
        .par_iter()
        .map(|c| fit_case(c, options))
        .collect())
}

/// Reads `outcomes.csv` at `path` and fits every case: the library's entry
/// point for the study runner.
///
/// ```no_run
/// use rockfrag::fragility::{FragilityOptions, fit_outcomes};
/// let fits = fit_outcomes("study/outcomes.csv".as_ref(), &FragilityOptions::default())?;
/// for f in &fits {
///     match &f.fit {
///         Ok(fit) => println!("{}: θ = {:.3} g, β = {:.2}", f.key, fit.median(), fit.beta()),
///         Err(reason) => println!("{}: {reason}", f.key),
///     }
/// }
/// # Ok::<(), rockfrag::Error>(())
/// ```
pub fn fit_outcomes(path: &Path, options: &FragilityOptions) -> Result<Vec<CaseFit>> {
    options.validate()?;
    let outcomes = read_outcomes(path, options.im)?;
    fit_cases(&outcomes, options)
}
