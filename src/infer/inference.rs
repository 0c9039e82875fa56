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
                read_hazard(path, *site)?.in_unit_of(im.name())?,
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
/// Errors: [`Error::Conflict`] naming the survey when its counts are
/// impossible at every intensity of the grid; as [`Grid::new`].
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
    let prior_u = prior.density_u(&grid);
    let joint_ln_l = likelihood::joint(table, survey, &grid);
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
