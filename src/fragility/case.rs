//! One case's fragility: the maximum-likelihood fit, its bootstrap and the
//! sampled curve; and every case of an `outcomes.csv`.

use std::path::Path;

use rayon::prelude::*;

use super::bootstrap::{BootstrapSummary, bootstrap, bootstrap_common_beta};
use super::data::{CaseData, Outcomes, read_outcomes_for};
use super::fit::{LognormalFit, Observation, Unfit, curves_cross, fit_common_beta, fit_lognormal};
use super::options::{FragilityOptions, IntensityMeasure};
use crate::case::Case;
use crate::error::{Error, Result};

/// A fitted curve sampled on a grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// Intensities, evenly spaced from 0 to the case's largest intensity.
    pub im: Vec<f64>,
    /// Fitted probability of exceeding the limit state at each intensity.
    pub probability: Vec<f64>,
}

/// How the β of a case's limit states were fitted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BetaModel {
    /// Each limit state alone, with its own β.
    Separate,
    /// Jointly with one β shared by the case's fitted limit states
    /// ([`fit_common_beta`]), because their separate curves crossed.
    Common,
}

impl BetaModel {
    /// Keyword of the `beta_model` column: `separate` or `common`.
    pub fn name(self) -> &'static str {
        match self {
            BetaModel::Separate => "separate",
            BetaModel::Common => "common",
        }
    }
}

/// Everything known about one case's fragility for one limit state.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseFit {
    /// The case (drawn or pooled parameters marked drawn).
    pub key: Case,
    /// The limit state's name (`overturning` unless limit states were given).
    pub limit_state: String,
    /// The intensity measure of the fit.
    pub im: IntensityMeasure,
    /// Successful analyses.
    pub n_analyses: usize,
    /// Of those, analyses that overturned.
    pub n_overturned: usize,
    /// Of those, analyses that exceeded the limit state (what was fitted).
    pub n_exceeded: usize,
    /// Records with at least one successful analysis.
    pub n_records: usize,
    /// Stripes (PGA levels) with at least one successful analysis.
    pub n_stripes: usize,
    /// Failed analyses, skipped.
    pub n_failed: usize,
    /// Smallest and largest intensity among the analyses (`None` without any).
    pub im_range: Option<(f64, f64)>,
    /// Exceedance counts grouped by equal intensity: what was fitted.
    pub observations: Vec<Observation>,
    /// Separate fit, or one β shared with the case's other limit states.
    pub beta_model: BetaModel,
    /// The maximum-likelihood fit, or why there is none.
    pub fit: std::result::Result<LognormalFit, Unfit>,
    /// The bootstrap (only for a fitted case with replicates requested).
    pub bootstrap: Option<BootstrapSummary>,
    /// The fitted curve (only for a fitted case).
    pub curve: Option<Curve>,
}

/// Fits one case, one fit per limit state of `options` (bit k of
/// [`Trial::exceeded`](super::Trial::exceeded) being limit state k):
/// maximum likelihood for each alone; if two of the fitted curves cross
/// within the case's grid (0, largest intensity] ([`curves_cross`]), the
/// fitted limit states are refitted jointly with one β ([`fit_common_beta`]),
/// so that a more severe limit state is never more likely than a less severe
/// one. Then the bootstrap, if requested (jointly too for a common β).
pub fn fit_case(case: &CaseData, options: &FragilityOptions) -> Vec<CaseFit> {
    let names = options.limit_states();
    let mut fits: Vec<CaseFit> = names
        .iter()
        .enumerate()
        .map(|(k, ls)| separate(case, k, &ls.name, options))
        .collect();
    let Some(im_max) = fits.first().and_then(|f| f.im_range).map(|r| r.1) else {
        return fits;
    };
    let grid = grid(im_max, options.grid_points);
    let fitted: Vec<usize> = (0..fits.len()).filter(|&k| fits[k].fit.is_ok()).collect();
    let ok = |k: usize| fits[k].fit.as_ref().expect("fitted");
    let cross = fitted.iter().enumerate().any(|(i, &k)| {
        fitted[i + 1..]
            .iter()
            .any(|&l| curves_cross(ok(k), ok(l), im_max))
    });
    let common = if cross {
        let sets: Vec<&[Observation]> = fitted
            .iter()
            .map(|&k| fits[k].observations.as_slice())
            .collect();
        fit_common_beta(&sets).ok()
    } else {
        None
    };
    match common {
        Some(joint) => {
            let boots = (options.bootstrap > 0).then(|| {
                bootstrap_common_beta(
                    case,
                    &fitted,
                    &grid,
                    options.bootstrap,
                    options.unit,
                    options.seed,
                    options.confidence,
                )
            });
            for (j, (&k, fit)) in fitted.iter().zip(joint).enumerate() {
                let f = &mut fits[k];
                f.beta_model = BetaModel::Common;
                f.curve = Some(curve(&fit, &grid));
                f.fit = Ok(fit);
                f.bootstrap = boots.as_ref().map(|b| b[j].clone());
            }
        }
        None if options.bootstrap > 0 => {
            for &k in &fitted {
                fits[k].bootstrap = Some(bootstrap_limit_state(case, k, &grid, options));
            }
        }
        None => {}
    }
    fits
}

/// Limit state `k` of `case` fitted alone, without the bootstrap.
fn separate(case: &CaseData, k: usize, name: &str, options: &FragilityOptions) -> CaseFit {
    let observations = case.observations(k);
    let im_range = observations
        .first()
        .zip(observations.last())
        .map(|(lo, hi)| (lo.im, hi.im));
    let fit = fit_lognormal(&observations);
    let curve = match (&fit, im_range) {
        (Ok(f), Some((_, im_max))) => Some(curve(f, &grid(im_max, options.grid_points))),
        _ => None,
    };
    CaseFit {
        key: case.key,
        limit_state: name.to_string(),
        im: options.im,
        n_analyses: case.trials.len(),
        n_overturned: case.trials.iter().filter(|a| a.overturned).count(),
        n_exceeded: case.trials.iter().filter(|a| a.exceeds(k)).count(),
        n_records: case.n_records(),
        n_stripes: case.n_stripes(),
        n_failed: case.failed,
        im_range,
        observations,
        beta_model: BetaModel::Separate,
        fit,
        bootstrap: None,
        curve,
    }
}

/// The bootstrap of limit state `k` alone.
fn bootstrap_limit_state(
    case: &CaseData,
    k: usize,
    grid: &[f64],
    options: &FragilityOptions,
) -> BootstrapSummary {
    if k == 0 {
        return bootstrap(
            case,
            grid,
            options.bootstrap,
            options.unit,
            options.seed,
            options.confidence,
        );
    }
    // The bootstrap resamples limit state 0: move bit k there.
    let mut view = case.clone();
    for a in &mut view.trials {
        a.exceeded = u64::from(a.exceeds(k));
    }
    bootstrap(
        &view,
        grid,
        options.bootstrap,
        options.unit,
        options.seed,
        options.confidence,
    )
}

/// `n` intensities evenly spaced from 0 to `im_max`.
fn grid(im_max: f64, n: usize) -> Vec<f64> {
    (0..n).map(|i| im_max * i as f64 / (n - 1) as f64).collect()
}

/// `fit` sampled on `grid`.
fn curve(fit: &LognormalFit, grid: &[f64]) -> Curve {
    Curve {
        probability: grid.iter().map(|&x| fit.probability(x)).collect(),
        im: grid.to_vec(),
    }
}

/// Fits every case of `outcomes` (in parallel; the result does not depend on
/// the number of threads): one [`CaseFit`] per case and limit state, the
/// limit states of a case together in order of severity. The outcomes must
/// have been read with `options.im` and `options`' limit states.
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
    if outcomes.limit_states != options.limit_states() {
        return Err(Error::invalid(
            "fragility.limit_state",
            options.limit_states().len(),
            "the limit states the outcomes were read with",
        ));
    }
    let per_case: Vec<Vec<CaseFit>> = outcomes
        .cases
        .par_iter()
        .map(|c| fit_case(c, options))
        .collect();
    Ok(per_case.into_iter().flatten().collect())
}

/// Reads `outcomes.csv` at `path` and fits every case: the library's entry
/// point for the study runner.
///
/// ```no_run
/// use rockfrag::fragility::{FragilityOptions, fit_outcomes};
/// let fits = fit_outcomes("study/outcomes.csv".as_ref(), &FragilityOptions::default())?;
/// for f in &fits {
///     match &f.fit {
///         Ok(fit) => println!("{} {}: θ = {:.3} g, β = {:.2}", f.key, f.limit_state, fit.median(), fit.beta()),
///         Err(reason) => println!("{} {}: {reason}", f.key, f.limit_state),
///     }
/// }
/// # Ok::<(), rockfrag::Error>(())
/// ```
pub fn fit_outcomes(path: &Path, options: &FragilityOptions) -> Result<Vec<CaseFit>> {
    options.validate()?;
    let outcomes = read_outcomes_for(path, options)?;
    fit_cases(&outcomes, options)
}
