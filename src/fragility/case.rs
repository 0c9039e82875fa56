//! One case's fragility: the maximum-likelihood fit, its bootstrap and the
//! sampled curve; and every case of an `outcomes.csv`.

use std::path::Path;

use rayon::prelude::*;

use super::bootstrap::{BootstrapSummary, bootstrap};
use super::data::{CaseData, Outcomes, read_outcomes};
use super::fit::{LognormalFit, Observation, Unfit, fit_lognormal};
use super::options::{FragilityOptions, IntensityMeasure};
use crate::error::{Error, Result};
use crate::outcomes_csv::CaseKey;

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
