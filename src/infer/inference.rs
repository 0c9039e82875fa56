//! An inference: the grid, the prior, both methods' likelihoods and
//! posteriors, each kind's fragility and the Monte Carlo error, as a pure
//! function of the simulations and the survey; and the prior as asked for.

use std::path::PathBuf;

use super::likelihood::{self, Grid, KindCurve};
use super::posterior::{self, McBand, McError, Posterior, Prior};
use super::simulate::{Im, Table};
use super::survey::Survey;
use crate::error::{Error, Result};
use crate::risk::read_hazard;
use crate::spec::InferSettings;

/// The prior as asked for: `log-uniform`, or `hazard=FILE[,site=K]`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PriorChoice {
    /// Uniform in ln IM over the grid (default).
    LogUniform,
    /// From a hazard curve: OpenQuake's CSV (site `site`) or `iml,annual_rate`.
    Hazard {
        /// The file.
        path: PathBuf,
        /// Its 0-based site (OpenQuake files).
        site: Option<usize>,
    },
}

impl std::str::FromStr for PriorChoice {
    type Err = Error;

    fn from_str(s: &str) -> Result<PriorChoice> {
        const EXPECTED: &str = "log-uniform, or hazard=FILE or hazard=FILE,site=K";
        if s == "log-uniform" {
            return Ok(PriorChoice::LogUniform);
        }
        let Some(rest) = s.strip_prefix("hazard=").filter(|r| !r.is_empty()) else {
            return Err(Error::invalid("prior", s, EXPECTED));
        };
        match rest.rsplit_once(",site=") {
            Some((path, site)) => match site.parse::<usize>() {
                Ok(k) if !path.is_empty() => Ok(PriorChoice::Hazard {
                    path: path.into(),
                    site: Some(k),
                }),
                _ => Err(Error::invalid("prior", s, EXPECTED)),
            },
            None => Ok(PriorChoice::Hazard {
                path: rest.into(),
                site: None,
            }),
        }
    }
}

impl std::fmt::Display for PriorChoice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PriorChoice::LogUniform => write!(f, "log-uniform"),
            PriorChoice::Hazard { path, site: None } => write!(f, "hazard={}", path.display()),
            PriorChoice::Hazard {
                path,
                site: Some(k),
            } => write!(f, "hazard={},site={k}", path.display()),
        }
    }
}

impl PriorChoice {
    /// The prior for `im`: the hazard curve read (in `im`'s unit).
    ///
    /// Errors: as [`read_hazard`], and an OpenQuake curve of another IMT.
    pub fn load(&self, im: Im) -> Result<Prior> {
        match self {
            PriorChoice::LogUniform => Ok(Prior::LogUniform),
            PriorChoice::Hazard { path, site } => Ok(Prior::Hazard(Box::new(
                read_hazard(path, *site)?.in_unit_of(im)?,
            ))),
        }
    }
}

/// An inference: the grid, the prior, both methods' likelihoods and
/// posteriors, each kind's fragility and the Monte Carlo error.
#[derive(Clone, Debug, PartialEq)]
pub struct Inference {
    /// The IM inferred.
    pub im: Im,
    /// Where everything is evaluated.
    pub grid: Grid,
    /// Prior density per unit IM.
    pub prior: Vec<f64>,
    /// ln L of the joint method.
    pub joint_ln_l: Vec<f64>,
    /// Its posterior.
    pub joint: Posterior,
    /// ln L of the naive method.
    pub naive_ln_l: Vec<f64>,
    /// Its posterior (`None` if its likelihood vanishes on the grid).
    pub naive: Option<Posterior>,
    /// Each kind's fragility.
    pub curves: Vec<KindCurve>,
    /// Records the joint posterior effectively rests on
    /// ([`likelihood::effective_records`]).
    pub effective_records: f64,
    /// Monte Carlo error of the joint method's bounds.
    pub joint_mc: Option<McError>,
    /// Of the naive method's.
    pub naive_mc: Option<McError>,
    /// The joint posterior's pointwise Monte Carlo band (with a bootstrap).
    pub joint_band: Option<McBand>,
}

/// Infers the IM from `table` (the simulations of `survey`'s kinds) under
/// `prior`, on a grid of `settings.refine` points per level interval, with
/// `settings.bootstrap` replicates (seed `seed`) for the Monte Carlo error.
/// A pure function of its inputs.
///
/// Errors: [`Error::Parse`] naming the survey's line of a kind whose
/// observed outcome (some overturned, some standing, some slid) none of its
/// simulations gives at any level ([`check_reproduced`]);
/// [`Error::Conflict`] naming the survey when its counts are impossible at
/// every intensity of the grid, or equally likely at every one (the answer
/// would be the prior); as [`Grid::new`].
pub fn infer(
    table: &Table,
    survey: &Survey,
    prior: &Prior,
    im: Im,
    exact: bool,
    settings: &InferSettings,
    seed: u64,
) -> Result<Inference> {
    let bootstrap = settings.bootstrap;
    let grid = Grid::new(table, exact, settings.refine)?;
    check_reproduced(table, survey, &grid, im)?;
    let prior_u = prior.density_u(&grid);
    let joint_ln_l = likelihood::joint(table, survey, &grid);
    check_informative(&joint_ln_l, survey, &grid, im)?;
    let joint = Posterior::new(&grid, &prior_u, &joint_ln_l).ok_or_else(|| Error::Conflict {
        path: survey.path.clone(),
        message: format!(
            "no intensity from {} to {} {} can give these counts under any record of the \
             study (the likelihood is 0 on the whole grid, or the prior is): check the counts, \
             widen the levels, or give the kinds' uncertain properties distributions",
            grid.x[0],
            grid.x[grid.len() - 1],
            im.unit()
        ),
    })?;
    let effective_records = likelihood::effective_records(table, survey, &grid, &prior_u);
    let curves = likelihood::kind_curves(table, survey, &grid);
    let naive_ln_l = likelihood::naive(&curves, survey, &grid);
    let naive = Posterior::new(&grid, &prior_u, &naive_ln_l);
    let (joint_mc, naive_mc, joint_band) = if bootstrap > 0 {
        posterior::mc_error(table, survey, &grid, &prior_u, bootstrap, seed)
    } else {
        (None, None, None)
    };
    Ok(Inference {
        im,
        prior: prior_u.iter().zip(&grid.x).map(|(p, x)| p / x).collect(),
        grid,
        joint_ln_l,
        joint,
        naive_ln_l,
        naive,
        curves,
        effective_records,
        joint_mc,
        naive_mc,
        joint_band,
    })
}

/// `lo` to `hi` with the IM's unit, for messages.
fn span(grid: &Grid, im: Im) -> String {
    format!(
        "from {} to {} {}",
        crate::io_util::sig3(grid.x[0]),
        crate::io_util::sig3(grid.x[grid.len() - 1]),
        im.unit()
    )
}

/// Refuses a kind whose observed outcome none of its simulations gives at
/// any level: some overturned where none of its draws on any record at any
/// level did (a 20 m slab typed for 20 cm), some standing where every draw
/// overturned, some slid where none did. Its likelihood is then the same at
/// every intensity (with drawn properties the beta-binomial's prior keeps
/// it above 0), and the posterior would be the prior presented as an
/// answer.
///
/// Errors: [`Error::Parse`] naming the survey, the kind's line, what was
/// observed, what the simulations gave and what to check.
pub fn check_reproduced(table: &Table, survey: &Survey, grid: &Grid, im: Im) -> Result<()> {
    let nl = table.levels.len();
    for (j, kind) in survey.kinds.iter().enumerate() {
        let cells =
            || (0..nl).flat_map(move |l| (0..table.records).map(move |r| table.cell(j, l, r)));
        let any = |f: &dyn Fn(&super::simulate::Cell) -> bool| cells().any(|c| f(&c));
        let slid = kind.slid.unwrap_or(0);
        let standing = kind.count - kind.overturned - slid;
        // Standing: neither overturned nor (when slides are counted) slid.
        let counts_slides = kind.slid.is_some();
        let stood = |c: &super::simulate::Cell| {
            c.valid() > c.overturned + if counts_slides { c.slid } else { 0 }
        };
        let what = format!(
            "its simulations on {} records at {} levels {}",
            table.records,
            nl,
            span(grid, im)
        );
        let problem = if kind.overturned > 0 && !any(&|c| c.overturned > 0) {
            Some(format!(
                "{} of {} overturned, but none of {what} overturned; check its width \
                 (2B, in m) and aspect (H/B), its restitution and friction, or add stronger \
                 levels",
                kind.overturned, kind.count
            ))
        } else if standing > 0 && !any(&stood) {
            Some(format!(
                "{standing} of {} stood{}, but every one of {what} {}; check its width \
                 (2B, in m) and aspect (H/B), its restitution and friction, or add weaker \
                 levels",
                kind.count,
                if counts_slides {
                    " without sliding"
                } else {
                    ""
                },
                if counts_slides {
                    "overturned or slid"
                } else {
                    "overturned"
                }
            ))
        } else if slid > 0 && !any(&|c| c.slid > 0) {
            Some(format!(
                "{slid} of {} slid beyond the sliding limit state, but none of {what} did \
                 (standing); check its friction, the limit state's threshold, or add \
                 stronger levels",
                kind.count
            ))
        } else {
            None
        };
        if let Some(problem) = problem {
            return Err(Error::Parse {
                path: survey.path.clone(),
                line: kind.line,
                message: format!(
                    "kind \"{}\" (2B = {} m, H/B = {}): {problem}. The model cannot produce \
                     what was observed, so the survey's likelihood would not depend on the \
                     intensity and the answer would be the prior",
                    kind.name, kind.width, kind.aspect
                ),
            });
        }
    }
    Ok(())
}

/// Refuses a survey whose joint likelihood is the same at every grid point
/// (within 10⁻⁹ in ln L): every kind shows what every level and record
/// give it (all standing where nothing overturns them, say), so the data
/// say nothing about the intensity and the posterior is the prior.
fn check_informative(ln_l: &[f64], survey: &Survey, grid: &Grid, im: Im) -> Result<()> {
    let finite = || ln_l.iter().copied().filter(|l| l.is_finite());
    let (lo, hi) = finite().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), l| {
        (a.min(l), b.max(l))
    });
    if finite().count() == ln_l.len() && hi - lo <= 1e-9 {
        return Err(Error::Conflict {
            path: survey.path.clone(),
            message: format!(
                "the survey is equally likely at every intensity {}: under every record and \
                 level the kinds do what was observed ({}), so the data say nothing about the \
                 intensity and the answer would be the prior. Add kinds that overturn within \
                 the levels, or levels where these kinds overturn",
                span(grid, im),
                survey
                    .kinds
                    .iter()
                    .map(|k| format!("{} {} of {} overturned", k.name, k.overturned, k.count))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        });
    }
    Ok(())
}
