//! Lognormal fragility curves fitted to a study's outcomes, one per case and
//! limit state (overturning unless the spec names others), with bootstrap
//! confidence bands and an OpenQuake export.
//!
//! ```text
//! outcomes.csv ─▶ data: cases, stripes, records ─▶ fit: probit MLE (θ, β, SEs)
//!   ─▶ bootstrap: resample records, refit ─▶ files: fragility.csv,
//!      fragility_curves.csv, fragility_bootstrap.csv (each replicate's θ, β)
//!   ─▶ nrml: fragility.xml (OpenQuake NRML 0.5)
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
//! ## Limit states
//!
//! A spec may list limit states in order of increasing severity
//! (`[[fragility.limit_state]]`, [`LimitState`]): an analysis exceeds one when
//! it overturned or its measure — a numeric or yes/no column of
//! `outcomes.csv` — is above the threshold (is yes). Each is fitted as above
//! with "overturned" read as "exceeded". Curves of one case must not cross: a
//! more severe limit state cannot be more likely. Two lognormal curves with
//! β₁ ≠ β₂ always meet once; when the separate fits of a case meet within the
//! case's grid where the probability is between 10⁻³ and 1 − 10⁻³
//! ([`curves_cross`]), the case's fitted limit states are refitted jointly
//! with one β and a median each ([`fit_common_beta`]): the summed
//! log-likelihood Σₖ ℓ(aₖ, b) is concave, and curves with one β never
//! cross. The `beta_model` column says which was done.
//!
//! ## Uncertainty
//!
//! Percentile bootstrap ([`bootstrap()`]): each replicate resamples whole
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
//! [`Im`](crate::im::Im): PGA in g (the stripes' level), PGV in m/s (the
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
mod case;
mod data;
mod files;
mod fit;
mod nrml;
mod options;
mod precision;
mod report;
mod set;
mod status;
mod surface;
mod surface_files;

pub use bootstrap::{BootstrapSummary, Interval, bootstrap, percentile};
pub use case::{
    BetaModel, CaseFit, Curve, ORDER_TOLERANCE, caveat_note, caveat_words, first_inversion,
    fit_case, fit_cases, fit_outcomes, out_of_order,
};
pub use data::{CaseData, Outcomes, Trial, read_outcomes, read_outcomes_for};
pub use files::{
    BOOTSTRAP_HEADER, BootstrapRow, CURVES_HEADER, CurveRow, FRAGILITY_HEADER, FragilityRow,
    OutputPaths, read_bootstrap_csv, read_curves_csv, read_fragility_csv, write_outputs,
    write_outputs_with,
};
pub use fit::{LognormalFit, Observation, Unfit, curves_cross, fit_common_beta, fit_lognormal};
pub use nrml::{
    IML_SIGMAS, NrmlEntry, NrmlFunction, NrmlShape, lognormal_to_moments, model_range,
    moments_to_lognormal, nrml_model_string, nrml_string, write_nrml,
};
pub use options::{
    BootstrapUnit, FragilityOptions, LimitState, MAX_BOOTSTRAP, MAX_GRID_POINTS, MAX_LIMIT_STATES,
    RecordIms, bootstrap_limit,
};
pub use precision::{
    Band, DEFAULT_MAX_ANALYSES, Design, MIN_ANALYSES, Precision, lattice, place, records_for,
    relative_half_width,
};
pub use report::{FitReport, fit_and_write};
pub use set::{SET_FILE, SET_FILES, check_set};
pub use status::{Caveat, FitStatus, UnfitKind, unfit_advice, unfit_words};
pub use surface::{
    SurfaceFit, SurfacePoint, SurfaceUnfit, fit_surface, surface_status, surface_words,
};
pub use surface_files::{
    ObservedBin, SURFACE_FILE, SURFACE_HEADER, SurfaceRow, fit_surfaces, observed_bins,
    read_surface_csv,
};
