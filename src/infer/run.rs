//! `rockfrag infer` as a run: lock the folder, simulate (resuming or
//! reusing earlier simulations), infer, write the outputs.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::inference::{Inference, PriorChoice, infer};
use super::output;
use super::pair::{self, PairPosterior};
use super::simulate::{self, Im, Table};
use super::survey::{self, KindModel, SlideRule, Survey};
use crate::error::{Error, Result};
use crate::spec::{InferSettings, Study, fnv1a64};
use crate::study::{RunLock, Source};

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
    /// A second IM: the joint posterior over (`im`, `second`) too
    /// ([`pair`](super::pair)); `im` must then be given.
    pub second: Option<Im>,
    /// Worker threads (0: one per core).
    pub threads: usize,
    /// Say each level's simulations on standard error.
    pub progress: bool,
    /// The spec file as the user named it (for messages and the outputs).
    pub spec_file: PathBuf,
    /// Draw `figures/inference.svg` (or `.png`); `None`: no figure.
    pub figure: Option<crate::figures::Format>,
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
            second: None,
            threads: 0,
            progress: false,
            spec_file: spec_file.into(),
            figure: Some(crate::figures::Format::Svg),
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
    /// The joint posterior over two IMs, when a second was asked for.
    pub pair: Option<PairPosterior>,
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
    for f in study.motions.files() {
        let bytes = crate::motion::read_record_bytes(&f.path)?;
        text.push_str(&format!("{:016x}\n", fnv1a64(&bytes)));
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
    let im = opts.im.or(simulate::im_of_levels(study)).unwrap_or(Im::PGA);
    let im = simulate::inferable(im).map_err(|e| Error::invalid("--im", im, &e))?;
    let exact = simulate::im_of_levels(study) == Some(im);
    // A pair is checked before the folder is made: a refusal writes nothing.
    let ims = match opts.second {
        None => None,
        Some(second) => Some(pair_of(study, opts.im, im, second)?),
    };
    crate::io_util::create_folder(dir)?;
    let _lock = RunLock::acquire(dir)?;
    let settings = settings(study);
    let models = survey::models(survey, study, &settings, &opts.spec_file)?;
    let slide = survey::slide_rule(survey, study, &settings, &opts.spec_file)?;
    let prior = opts.prior.load(im)?;
    let (pool, threads) = crate::threads::pool(opts.threads)?;
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
        pair: None,
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
    let joint_pair = match ims {
        None => None,
        Some((ims, second)) => Some(pool.install(|| {
            PairPosterior::new(
                ims,
                &sims.table,
                &second,
                survey,
                &inference.grid,
                &prior.density_u(&inference.grid),
                inference.joint.summary,
                settings.bootstrap,
                seed,
            )
        })?),
    };
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
    report.written =
        output::write_all(dir, &inference, &context, opts.figure, joint_pair.as_ref())?;
    report.inference = Some(inference);
    report.pair = joint_pair;
    report.table = Some(sims.table);
    report.wall_seconds = t0.elapsed().as_secs_f64();
    Ok(report)
}

/// The pair `first,second` checked ([`pair::inferable_pair`]) and the
/// second IM of every record at every level, before anything is
/// simulated: refused when the first was not given, or when every record
/// has the same IM2/IM1 (IM2 would be IM1 times a constant).
fn pair_of(
    study: &Study,
    given: Option<Im>,
    first: Im,
    second: Im,
) -> Result<(crate::im::ImPair, Vec<f64>)> {
    let shown = format!("{},{second}", given.map_or("?".into(), |i| i.name()));
    if given.is_none() {
        return Err(Error::invalid(
            "--im",
            shown,
            "the first IM with the second (--im pga,pgv)",
        ));
    }
    let ims = crate::im::ImPair::new(first, second)
        .and_then(pair::inferable_pair)
        .map_err(|e| Error::invalid("--im", shown.clone(), &e))?;
    let ids: Vec<usize> = (0..study.records()).collect();
    let values = pair::measure_second(study, second, &ids)?;
    let firsts = pair::measure_second(study, first, &ids)?;
    let ln_ratio: Vec<f64> = values
        .iter()
        .zip(&firsts)
        .take(ids.len())
        .map(|(y, x)| crate::detmath::ln(y / x))
        .collect();
    let (lo, hi) = ln_ratio
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if (hi - lo).is_nan() || hi - lo <= 1e-9 {
        return Err(Error::invalid(
            "--im",
            shown,
            &format!(
                "records whose {} differ, for a joint posterior: all {} records of the study \
                 have {} = {}, so {} is that times {} and a second IM adds nothing; infer {} \
                 alone (--im {first}), or give the study more records",
                pair::ratio_name(ims),
                ids.len(),
                pair::ratio_name(ims),
                crate::io_util::sig3(crate::detmath::exp(lo)),
                second.name().to_uppercase(),
                first.name().to_uppercase(),
                first.name().to_uppercase(),
            ),
        ));
    }
    Ok((ims, values))
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
