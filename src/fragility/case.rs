//! One case's fragility: the maximum-likelihood fit, its bootstrap and the
//! sampled curve; and every case of an `outcomes.csv`.

use std::path::Path;

use rayon::prelude::*;

use super::bootstrap::{BootstrapSummary, bootstrap, bootstrap_common_beta};
use super::data::{CaseData, Outcomes, read_outcomes_for};
use super::fit::{LognormalFit, Observation, Unfit, curves_cross, fit_common_beta, fit_lognormal};
use super::options::FragilityOptions;
use super::status::Caveat;
use crate::case::Case;
use crate::detmath as dm;
use crate::error::{Error, Result};
use crate::im::Im;
use crate::io_util::sig3;

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

/// The caveat of a fitted curve in words, for the console and the summary:
/// `im_range` its stripes' span, `inversion` (for [`Caveat::OutOfOrder`])
/// the milder limit state it is more likely than, where and by how much
/// ([`first_inversion`]), `unit` the IM's.
pub fn caveat_words(
    caveat: Caveat,
    im_range: Option<(f64, f64)>,
    inversion: Option<(&str, f64, f64)>,
    unit: &str,
) -> String {
    let unit = if unit == "1" {
        String::new()
    } else {
        format!(" {unit}")
    };
    let at = |i: usize| {
        im_range.map_or(String::new(), |r| {
            format!(" ({}{unit})", sig3(if i == 0 { r.0 } else { r.1 }))
        })
    };
    match caveat {
        Caveat::ExtrapolatedAbove => format!(
            "median above the strongest stripe{}: the curve is extrapolated from its lower \
             part; run stripes up to and beyond the median",
            at(1)
        ),
        Caveat::ExtrapolatedBelow => format!(
            "median below the weakest stripe{}: the curve is extrapolated from its upper \
             part; run stripes down to and below the median",
            at(0)
        ),
        Caveat::OutOfOrder => {
            let what = inversion.map_or(" a milder limit state".to_string(), |(name, x, d)| {
                format!(
                    " {name} (listed as milder) at {}{unit}, by {}",
                    sig3(x),
                    sig3(d)
                )
            });
            format!(
                "out of order: more likely than{what}, so OpenQuake and pelicun would give a \
                 damage state a negative probability; left out of fragility.xml and the \
                 exports. List the limit states in the order this case exceeds them, or \
                 define them so that a more severe one implies the milder"
            )
        }
    }
}

/// How much more likely than a milder limit state a more severe one may be
/// somewhere within the stripes before it is [`Caveat::OutOfOrder`] (below
/// this, a damage state's negative probability is rounding).
pub const ORDER_TOLERANCE: f64 = 1e-6;

/// Points (log-spaced over the stripes' range) at which [`out_of_order`]
/// compares two curves.
const ORDER_POINTS: usize = 400;

/// Where within `im_range` the lognormal curve `severe` (θ, β) is most
/// above `milder`, and by how much, when by more than [`ORDER_TOLERANCE`].
pub fn out_of_order(
    milder: (f64, f64),
    severe: (f64, f64),
    im_range: (f64, f64),
) -> Option<(f64, f64)> {
    // P = Φ(ln(x/θ)/β), the lognormal fragility.
    let p = |(theta, beta): (f64, f64), x: f64| dm::norm_cdf(dm::ln(x / theta) / beta);
    let (lo, hi) = (dm::ln(im_range.0), dm::ln(im_range.1));
    (0..=ORDER_POINTS)
        .map(|i| dm::exp(lo + (hi - lo) * i as f64 / ORDER_POINTS as f64))
        .map(|x| (x, p(severe, x) - p(milder, x)))
        .fold(None, |best: Option<(f64, f64)>, (x, d)| match best {
            Some(b) if b.1 >= d => Some(b),
            _ => Some((x, d)),
        })
        .filter(|&(_, d)| d > ORDER_TOLERANCE)
}

/// The first of the `milder` limit states (name, (θ, β)) of a case that
/// the curve `severe` is more likely than within `im_range`
/// ([`out_of_order`]): its name, where and by how much. For the notes of a
/// [`Caveat::OutOfOrder`] curve.
pub fn first_inversion<'a>(
    severe: (f64, f64),
    milder: impl IntoIterator<Item = (&'a str, (f64, f64))>,
    im_range: (f64, f64),
) -> Option<(&'a str, f64, f64)> {
    milder
        .into_iter()
        .find_map(|(name, fit)| out_of_order(fit, severe, im_range).map(|(x, d)| (name, x, d)))
}

/// Everything known about one case's fragility for one limit state.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseFit {
    /// The case (drawn or pooled parameters marked drawn).
    pub key: Case,
    /// The limit state's name (`overturning` unless limit states were given).
    pub limit_state: String,
    /// The intensity measure of the fit.
    pub im: Im,
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
    /// What the fitted curve is to be read with, if anything.
    pub caveat: Option<Caveat>,
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
    let Some(im_range) = fits.first().and_then(|f| f.im_range) else {
        return fits;
    };
    let im_max = im_range.1;
    let grid = grid(im_max, options.grid_points);
    // Limit states are ordered in severity within a body's (a stack's
    // `top.…`, `base.…`; a block's and the stack-wide ones are one body):
    // the crossing rule and the caveats apply within each.
    let mut bodies: Vec<Option<crate::outcome::Slot>> = Vec::new();
    for ls in &names {
        if !bodies.contains(&ls.body()) {
            bodies.push(ls.body());
        }
    }
    for body in bodies {
        let fitted: Vec<usize> = (0..fits.len())
            .filter(|&k| fits[k].fit.is_ok() && names[k].body() == body)
            .collect();
        fit_ordered(case, options, &mut fits, &fitted, &grid, im_range);
    }
    fits
}

/// The crossing rule and the bootstrap over `fitted`, limit states of one
/// body in order of severity (see [`fit_case`]).
fn fit_ordered(
    case: &CaseData,
    options: &FragilityOptions,
    fits: &mut [CaseFit],
    fitted: &[usize],
    grid: &[f64],
    im_range: (f64, f64),
) {
    let ok = |k: usize| fits[k].fit.as_ref().expect("fitted");
    let cross = fitted.iter().enumerate().any(|(i, &k)| {
        fitted[i + 1..]
            .iter()
            .any(|&l| curves_cross(ok(k), ok(l), im_range))
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
                    fitted,
                    grid,
                    options.bootstrap,
                    options.unit,
                    options.seed,
                    options.confidence,
                )
            });
            for (j, (&k, fit)) in fitted.iter().zip(joint).enumerate() {
                let f = &mut fits[k];
                f.beta_model = BetaModel::Common;
                f.curve = Some(curve(&fit, grid));
                f.fit = Ok(fit);
                f.bootstrap = boots.as_ref().map(|b| b[j].clone());
            }
        }
        None if options.bootstrap > 0 => {
            for &k in fitted {
                fits[k].bootstrap = Some(bootstrap_limit_state(case, k, grid, options));
            }
        }
        None => {}
    }
    set_caveats(fits, fitted, im_range);
}

/// The caveat of `fits[i]` in words ([`caveat_words`]), naming the milder
/// limit state of its case it is more likely than; `None` without one.
/// `fits` are a fit's curves, a case's limit states together in order.
pub fn caveat_note(fits: &[CaseFit], i: usize) -> Option<String> {
    let f = &fits[i];
    let caveat = f.caveat?;
    let pair = |g: &CaseFit| g.fit.as_ref().ok().map(|x| (x.median(), x.beta()));
    let inversion = match (caveat, pair(f), f.im_range) {
        (Caveat::OutOfOrder, Some(severe), Some(range)) => first_inversion(
            severe,
            fits[..i]
                .iter()
                .filter(|g| g.key == f.key)
                .filter_map(|g| pair(g).map(|p| (g.limit_state.as_str(), p))),
            range,
        ),
        _ => None,
    };
    Some(caveat_words(caveat, f.im_range, inversion, f.im.unit()))
}

/// Each fitted curve's [`Caveat`]: out of order when it is more likely than
/// a milder fitted limit state of the case somewhere within the stripes
/// (with one β the medians inverted; else curves that still cross there),
/// else extrapolated when its median lies outside the stripes.
fn set_caveats(fits: &mut [CaseFit], fitted: &[usize], im_range: (f64, f64)) {
    for (i, &l) in fitted.iter().enumerate() {
        let pair = |k: usize| {
            let f = fits[k].fit.as_ref().expect("fitted");
            (f.median(), f.beta())
        };
        let severe = pair(l);
        let inverted = fitted[..i]
            .iter()
            .any(|&k| out_of_order(pair(k), severe, im_range).is_some());
        let median = severe.0;
        fits[l].caveat = if inverted {
            Some(Caveat::OutOfOrder)
        } else {
            Caveat::of_median(median, fits[l].im_range)
        };
    }
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
        im: options.im(),
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
        caveat: None,
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
    if outcomes.im != options.im() {
        return Err(Error::invalid(
            "fragility.im",
            options.im(),
            &format!(
                "the intensity measure the outcomes were read with ({})",
                outcomes.im
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
