//! From what fell to how hard it shook: the intensity a site felt, inferred
//! from the objects that overturned there (`rockfrag infer`).
//!
//! ```text
//! survey.csv (kinds: 2B, H/B, count, overturned[, slid])   spec.toml (records, levels,
//!      │                                                   solver, [uncertainty], [infer])
//!      └──────────────▶ simulate: every kind × record × level × draw ─▶ simulations.csv
//!                        ─▶ likelihood: joint (one motion for all) and naive (one per object)
//!                        ─▶ posterior (prior: log-uniform or a hazard curve), Monte Carlo
//!                           error by bootstrap ─▶ posterior.csv, inference.json,
//!                           summary.md ## Inference, figures/inference.svg
//! ```
//!
//! After an earthquake, a cemetery's tombstones of a few standard sizes
//! (some toppled, some standing), a museum's objects or a hillside's
//! precariously balanced rocks record how hard the ground shook. For every
//! record r of the study at intensity x, each kind j of object is simulated
//! D times, each time with its uncertain properties drawn; the objects of a
//! site all felt one motion, so the likelihood of the survey is the mean
//! over records of the product over kinds ([`likelihood`]):
//!
//! ```text
//! L(x) = (1/R) Σ_r Π_j P(k_j of n_j overturned | x, r)
//! ```
//!
//! Multiplying each kind's fitted fragility curve instead treats every
//! object as if it had its own earthquake; it is computed too (`naive`),
//! and is overconfident. The posterior is prior × L on the grid of the
//! study's levels ([`posterior`]); its Monte Carlo error comes from a
//! bootstrap over records and draws.
//!
//! **Determinism.** Every analysis is a pure function of (kind, record,
//! level, draw), the bootstrap's replicates of (seed, replicate), and sums
//! run in a fixed order: the outputs are byte-identical on any thread
//! count, after an interruption and on a rerun. The simulations are kept in
//! `simulations.csv` with a checkpoint after each level
//! (`simulations.json`, keyed by a hash of everything they depend on): a
//! killed run resumes, and a rerun with other counts or another prior
//! reuses them.
//!
//! ## References
//! - Housner, G. W. (1963). The behavior of inverted pendulum structures
//!   during earthquakes. *Bull. Seismol. Soc. Am.* 53(2), 403–417 (the
//!   inverse problem: intensities from overturned objects).
//! - Purvance, M. D., Anooshehpoor, A. and Brune, J. N. (2008). Freestanding
//!   block overturning fragilities: numerical simulation and experimental
//!   validation. *Earthquake Eng. Struct. Dyn.* 37, 791–808 (precariously
//!   balanced rocks).

pub mod calibrate;
pub mod figure;
pub mod likelihood;
pub mod output;
pub mod posterior;
pub mod simulate;
pub mod survey;

pub use likelihood::{Grid, KindCurve};
pub use posterior::{McError, Posterior, Prior, Summary};
pub use simulate::{Cell, Im, Table};
pub use survey::{Kind, KindModel, SlideRule, Survey};

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::error::{Error, Result};
use crate::risk::read_hazard;
use crate::spec::{InferSettings, Motions, Study, fnv1a64};
use crate::study::{RunLock, Source};

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
    /// Monte Carlo error of the joint method's bounds.
    pub joint_mc: Option<McError>,
    /// Of the naive method's.
    pub naive_mc: Option<McError>,
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
    let curves = likelihood::kind_curves(table, survey, &grid);
    let naive_ln_l = likelihood::naive(&curves, survey, &grid);
    let naive = Posterior::new(&grid, &prior_u, &naive_ln_l);
    let (joint_mc, naive_mc) = if bootstrap > 0 {
        posterior::mc_error(table, survey, &grid, &prior_u, bootstrap, seed)
    } else {
        (None, None)
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
        joint_mc,
        naive_mc,
    })
}

/// Options of one `rockfrag infer` (they do not change the results, save
/// `prior` and `im`).
#[derive(Clone, Debug)]
pub struct InferOptions {
    /// Output folder.
    pub out_dir: PathBuf,
    /// The prior.
    pub prior: PriorChoice,
    /// The IM inferred (default: the levels' IM; PGA for scale factors).
    pub im: Option<Im>,
    /// Worker threads (0: one per core).
    pub threads: usize,
    /// Say each level's simulations on standard error.
    pub progress: bool,
    /// The spec file as the user named it (for messages and the outputs).
    pub spec_file: PathBuf,
    /// Draw `figures/inference.svg`.
    pub figure: bool,
    /// Stop (as if killed) after this many levels of simulations; for tests.
    pub stop_after_levels: Option<usize>,
}

impl InferOptions {
    /// Defaults: log-uniform prior, the levels' IM, all cores, a figure.
    pub fn new(out_dir: impl Into<PathBuf>, spec_file: impl Into<PathBuf>) -> InferOptions {
        InferOptions {
            out_dir: out_dir.into(),
            prior: PriorChoice::LogUniform,
            im: None,
            threads: 0,
            progress: false,
            spec_file: spec_file.into(),
            figure: true,
            stop_after_levels: None,
        }
    }
}

/// What a `rockfrag infer` did.
#[derive(Clone, Debug)]
pub struct InferReport {
    /// Output folder.
    pub out_dir: PathBuf,
    /// The inference (`None` when stopped before the simulations were done).
    pub inference: Option<Inference>,
    /// The simulations' table (`None` likewise).
    pub table: Option<Table>,
    /// Levels of simulations reused from an earlier run.
    pub resumed_levels: usize,
    /// Analyses solved by this run.
    pub analyses_run: u64,
    /// Analyses behind the inference.
    pub analyses: u64,
    /// Analyses that failed (left out of the counts).
    pub failed: u64,
    /// Draws per kind.
    pub draws: Vec<usize>,
    /// Wall time, s.
    pub wall_seconds: f64,
    /// Worker threads.
    pub threads: usize,
    /// The files written.
    pub written: Vec<PathBuf>,
}

/// The settings of `study`'s `[infer]` table (its defaults without one).
pub fn settings(study: &Study) -> InferSettings {
    study.infer.clone().unwrap_or_default()
}

/// FNV-1a of everything the simulations depend on: the spec without its
/// `[infer]` table's bootstrap, the kinds as simulated, the IM, the
/// sliding rule and the record files' bytes.
fn inputs_hash(
    study: &Study,
    models: &[KindModel],
    slide: Option<&SlideRule>,
    im: Im,
) -> Result<u64> {
    let mut bare = study.clone();
    bare.infer = None;
    let mut text = bare.to_toml();
    text.push_str(&format!("\n{models:?}\n{slide:?}\n{}\n", im.name()));
    if let Motions::Files(files) = &study.motions {
        for f in files {
            let bytes = std::fs::read(&f.path).map_err(Error::io(&f.path))?;
            text.push_str(&format!("{:016x}\n", fnv1a64(&bytes)));
        }
    }
    Ok(fnv1a64(text.as_bytes()))
}

/// Runs `rockfrag infer`: simulates `survey`'s kinds under `study` into
/// `opts.out_dir` (resuming or reusing earlier simulations there), infers
/// and writes `posterior.csv`, `inference.json`, `summary.md`'s
/// `## Inference` and `figures/inference.svg`. The folder is locked for
/// the run.
///
/// Errors: as [`survey::models`], [`survey::slide_rule`], [`infer`]; I/O.
pub fn run(study: &Study, survey: &Survey, opts: &InferOptions) -> Result<InferReport> {
    let t0 = Instant::now();
    let dir = &opts.out_dir;
    std::fs::create_dir_all(dir).map_err(Error::io(dir))?;
    let _lock = RunLock::acquire(dir)?;
    let settings = settings(study);
    let models = survey::models(survey, study, &settings, &opts.spec_file)?;
    let slide = survey::slide_rule(survey, study, &settings, &opts.spec_file)?;
    let im = opts.im.or(Im::of_levels(study)).unwrap_or(Im::Pga);
    let exact = Im::of_levels(study) == Some(im);
    let prior = opts.prior.load(im)?;
    let threads = if opts.threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        opts.threads
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::invalid("threads", threads, &format!("a usable thread count ({e})")))?;
    let hash = inputs_hash(study, &models, slide.as_ref(), im)?;
    let names: Vec<String> = survey.kinds.iter().map(|k| k.name.clone()).collect();
    let runner = simulate::Runner {
        study,
        models: &models,
        slide: slide.as_ref(),
        im,
        source: Source::new(study)?,
    };
    let sims = pool.install(|| {
        simulate::run_checkpointed(
            &runner,
            &names,
            dir,
            hash,
            opts.stop_after_levels,
            opts.progress,
        )
    })?;
    let draws: Vec<usize> = models.iter().map(|m| m.draws).collect();
    let analyses = Table::analyses(&models, study.intensity.levels().len(), study.records());
    let mut report = InferReport {
        out_dir: dir.clone(),
        inference: None,
        table: None,
        resumed_levels: 0,
        analyses_run: 0,
        analyses,
        failed: 0,
        draws,
        wall_seconds: 0.0,
        threads,
        written: Vec::new(),
    };
    let Some(sims) = sims else {
        report.wall_seconds = t0.elapsed().as_secs_f64();
        return Ok(report);
    };
    report.resumed_levels = sims.resumed_levels;
    report.analyses_run = sims.analyses_run;
    report.failed = failed_analyses(&sims.table, &models);
    let seed = survey::draws_seed(study, &settings);
    let inference =
        pool.install(|| infer(&sims.table, survey, &prior, im, exact, &settings, seed))?;
    let context = output::Context {
        study,
        survey,
        models: &models,
        spec_file: &opts.spec_file,
        prior: &opts.prior,
        slide: slide.as_ref(),
        bootstrap: settings.bootstrap,
        analyses,
        records: study.records(),
        levels: study.intensity.levels().len(),
    };
    report.written = output::write_all(dir, &inference, &context, opts.figure)?;
    report.inference = Some(inference);
    report.table = Some(sims.table);
    report.wall_seconds = t0.elapsed().as_secs_f64();
    Ok(report)
}

/// Analyses that failed: draws of kinds with something drawn, single
/// analyses of the others.
fn failed_analyses(table: &Table, models: &[KindModel]) -> u64 {
    let nl = table.levels.len();
    let mut failed = 0;
    for (j, m) in models.iter().enumerate() {
        for l in 0..nl {
            for r in 0..table.records {
                let f = u64::from(table.cell(j, l, r).failed);
                failed += if m.is_drawn() { f } else { f.min(1) };
            }
        }
    }
    failed
}

/// The default output folder of a survey: `results/<its file stem>/`.
pub fn default_out(survey: &Path) -> PathBuf {
    let stem = survey
        .file_stem()
        .map_or_else(|| "infer".into(), |s| s.to_string_lossy().into_owned());
    PathBuf::from("results").join(stem)
}
