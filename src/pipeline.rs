//! One run sequence, shared by the command line and Python: lock the
//! folder, run the analyses (resumable, shardable), then — once a whole
//! study's `outcomes.csv` is complete — its `summary.md`, the fragility fit
//! (`[fragility]`) and the figures (`output.figures`), with the paper's
//! layer added for the paper's own study.
//!
//! ```text
//! Study ─▶ study::run ─▶ outcomes.csv, manifest.json
//!       ─▶ finish: summary.md ─▶ fragility.* ─▶ figures/
//! ```
//!
//! [`finish`] alone makes the post-processing of a complete folder (after
//! `merge`, or again after a change to a field that does not change the
//! analyses).

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::figures::{FigureOptions, FiguresReport};
use crate::fragility::{FitReport, FragilityOptions, fit_and_write};
use crate::paper;
use crate::spec::Study;
use crate::study::{self, RunLock, RunOptions, RunReport, Shard, Tally, files};

/// What a study run did: the analyses, and what was made from them.
#[derive(Clone, Debug)]
pub struct StudyReport {
    /// The analyses.
    pub run: RunReport,
    /// What was made from a whole, complete study (`None` for an
    /// unfinished run or a shard).
    pub finish: Option<FinishReport>,
    /// What an adaptive study reached, per case (`None` for a fixed grid or
    /// an unfinished run).
    pub adaptive: Option<study::adaptive::AdaptiveReport>,
}

impl StudyReport {
    /// Analyses that failed (status `failed` in `outcomes.csv`).
    pub fn failed(&self) -> u64 {
        self.run.counts.failed
    }

    /// The message for failed analyses, `None` if none failed: the caller
    /// decides the exit status (everything is written either way).
    pub fn failure(&self) -> Option<String> {
        let c = self.run.counts;
        (c.failed > 0).then(|| {
            format!(
                "{} of {} analyses failed (status 'failed' and the reason in {}); all results \
                 are written",
                c.failed,
                c.analyses,
                self.run.out_dir.join(files::OUTCOMES).display()
            )
        })
    }
}

/// What [`finish`] made.
#[derive(Clone, Debug, Default)]
pub struct FinishReport {
    /// `summary.md`, if written (`output.summary`).
    pub summary: Option<PathBuf>,
    /// The fragility fit (`[fragility]`).
    pub fit: Option<FitReport>,
    /// The figures (`output.figures`).
    pub figures: Option<FiguresReport>,
}

/// Runs `study` into `opts.out_dir` (see [`study::run`]), holding the
/// folder's lock over the analyses and what follows them, and finishes a
/// whole, complete study ([`finish`]).
pub fn run(study: &Study, opts: &RunOptions) -> Result<StudyReport> {
    let dir = &opts.out_dir;
    crate::io_util::create_folder(dir)?;
    let _lock = RunLock::acquire(dir)?;
    if study.adaptive.is_some() {
        let (run, adaptive) = study::adaptive::run(study, opts)?;
        let finish = match &adaptive {
            Some(a) if run.complete && !study::interrupted() => {
                Some(finish_adaptive(study, dir, a)?)
            }
            _ => None,
        };
        return Ok(StudyReport {
            run,
            finish,
            adaptive,
        });
    }
    let run = study::run(study, opts)?;
    let finish = if run.complete && opts.shard == Shard::WHOLE && !study::interrupted() {
        Some(finish(study, dir, run.tally.as_ref())?)
    } else {
        None
    };
    Ok(StudyReport {
        run,
        finish,
        adaptive: None,
    })
}

/// What a complete study folder `dir` gets when its spec asks: the
/// fragility fit, `summary.md` (from `tally`, or read from `outcomes.csv`;
/// with the fitted curves) and the figures into `dir/figures`; the paper's
/// layer adds its tables and figures for the paper's own study.
pub fn finish(study: &Study, dir: &Path, tally: Option<&Tally>) -> Result<FinishReport> {
    let mut report = FinishReport::default();
    if let Some(options) = &study.fragility {
        let mut options = options.clone();
        for im in options.im.into_iter().chain(options.surface) {
            if !im.stored() && im.of_record() {
                let values = study::measure_study_records(study, dir, im)?;
                options.measured.push(std::sync::Arc::new(values));
            }
        }
        report.fit = Some(fit_and_write(dir, dir, &options)?);
    }
    if study.output.summary {
        let read;
        let tally = match tally {
            Some(t) => t,
            None => {
                read = Tally::read(&dir.join(files::OUTCOMES), study, Shard::WHOLE)?;
                &read
            }
        };
        let extra: Vec<String> = paper::summary_section(study, tally).into_iter().collect();
        study::write_summary(dir, study, Shard::WHOLE, Some(tally), &extra)?;
        report.summary = Some(dir.join(files::SUMMARY));
    }
    report.figures = study_figures(study, dir)?;
    if report.fit.is_some() {
        record_fit(dir, dir)?;
    }
    if let Some(summary) = &report.summary {
        if let Some(fit) = &report.fit {
            surface_summary(summary, fit)?;
        }
        study::record_outputs(dir, &[summary])?;
    }
    Ok(report)
}

/// What a complete adaptive study folder gets: the fit of its
/// `outcomes.csv` (as a fixed grid's) and a `summary.md` of the study, the
/// precision each case reached ([`study::adaptive::summary_section`]) and
/// the fitted curves, and the figures a fixed grid's folder gets
/// (`output.figures`): the stripes an adaptive run placed are drawn as a
/// fixed grid's are.
fn finish_adaptive(
    study: &Study,
    dir: &Path,
    adaptive: &study::adaptive::AdaptiveReport,
) -> Result<FinishReport> {
    let mut report = FinishReport::default();
    if let Some(options) = &study.fragility {
        report.fit = Some(fit_and_write(dir, dir, options)?);
        record_fit(dir, dir)?;
    }
    if study.output.summary {
        let mut text = format!(
            "# Study `{}`

",
            study.name
        );
        if !study.description.is_empty() {
            text.push_str(&format!(
                "{}

",
                study.description
            ));
        }
        text.push_str(&study::adaptive::summary_section(adaptive));
        let rows = crate::fragility::read_fragility_csv(&dir.join("fragility.csv"))?;
        text.push('\n');
        text.push_str(&study::fragility_section(&rows));
        let path = dir.join(files::SUMMARY);
        crate::io_util::write_atomic(&path, |w| std::io::Write::write_all(w, text.as_bytes()))
            .map_err(Error::io(&path))?;
        study::record_outputs(dir, &[&path])?;
        report.summary = Some(path);
    }
    report.figures = study_figures(study, dir)?;
    Ok(report)
}

/// `summary.md`'s `## Fragility surface` for the surfaces of `fit`, or
/// without it when the fit has none (a refit without a surface).
fn surface_summary(summary: &Path, fit: &FitReport) -> Result<()> {
    match &fit.surfaces {
        Some(rows) => crate::io_util::replace_section(
            summary,
            study::SURFACE_HEADING,
            &study::surface_section(rows),
            &[study::COUNTS_HEADING],
        ),
        None => crate::io_util::remove_section(summary, study::SURFACE_HEADING),
    }
    .map_err(Error::io(summary))
}

/// The figures `output.figures` asks of a complete study folder, drawn into
/// `dir/figures` with the study's own options (fixed grid or adaptive).
fn study_figures(study: &Study, dir: &Path) -> Result<Option<FiguresReport>> {
    if !study.output.figures {
        return Ok(None);
    }
    figures(
        study,
        dir,
        &dir.join("figures"),
        &FigureOptions::for_study(study),
    )
    .map(Some)
}

/// Lists the fit's files in `out` among the outputs of the run in `dir`
/// (when `out` is inside it): a run that replaces it removes them.
fn record_fit(dir: &Path, out: &Path) -> Result<()> {
    let surface = [crate::fragility::SURFACE_FILE]
        .into_iter()
        .filter(|f| out.join(f).is_file());
    let files: Vec<PathBuf> = crate::fragility::SET_FILES
        .iter()
        .copied()
        .chain([crate::fragility::SET_FILE])
        .chain(surface)
        .map(|name| out.join(name))
        .collect();
    let files: Vec<&Path> = files.iter().map(PathBuf::as_path).collect();
    study::record_outputs(dir, &files)
}

/// Refits the curves of the study folder `dir` into `out`
/// ([`fit_and_write`]) and, when they replace the folder's own
/// (`out` = `dir`), the `## Fragility` section of its `summary.md`.
pub fn refit(dir: &Path, out: &Path, options: &FragilityOptions) -> Result<FitReport> {
    study::require_finished(dir)?;
    let mut report = fit_and_write(dir, out, options)?;
    record_fit(dir, out)?;
    let summary = dir.join(files::SUMMARY);
    if same_folder(dir, out) && summary.exists() {
        let rows = crate::fragility::read_fragility_csv(&report.fragility_csv)?;
        crate::io_util::replace_section(
            &summary,
            study::FRAGILITY_HEADING,
            &study::fragility_section(&rows),
            &[study::COUNTS_HEADING],
        )
        .map_err(Error::io(&summary))?;
        surface_summary(&summary, &report)?;
        report.wrote = format!(
            "{}; updated {} ({})\n",
            report.wrote.trim_end(),
            summary.display(),
            study::FRAGILITY_HEADING
        );
    }
    Ok(report)
}

/// `options` completed from the study recorded in `dir/manifest.json`, if
/// any, as `rockfrag fragility` and Python's `fragility` do: its drawn
/// parameters are pooled (with those `options` pools), its own
/// `[fragility]` limit states are fitted unless `options` names some, and
/// against its own `[fragility] im` unless `options` names one (a study of
/// record pairs without one: its RotD50 PGA).
pub fn folder_fit_options(dir: &Path, options: &FragilityOptions) -> Result<FragilityOptions> {
    let manifest = dir.join(files::MANIFEST);
    let study = if manifest.exists() {
        let m = study::Manifest::read(&manifest)?;
        Some(Study::from_toml_unchecked(&m.spec_toml, &manifest)?)
    } else {
        None
    };
    let mut pool = study.as_ref().map_or_else(Vec::new, Study::drawn);
    for &field in &options.pool {
        if !pool.contains(&field) {
            pool.push(field);
        }
    }
    pool.sort();
    let limit_state = if options.limit_state.is_empty() {
        study
            .as_ref()
            .and_then(|s| s.fragility.as_ref())
            .map_or(Vec::new(), |f| f.limit_state.clone())
    } else {
        options.limit_state.clone()
    };
    let study_im = study.as_ref().and_then(|study| match &study.fragility {
        Some(f) => Some((f.im, f.surface)),
        None => study
            .motions
            .orientation()
            .map(|_| (Some(crate::im::Im::PGA_ROTD50), None)),
    });
    // the IM(s) given, else the study's own (with its surface, if any)
    let (im, surface) = match options.im {
        Some(im) => (Some(im), options.surface),
        None => study_im.unwrap_or((None, None)),
    };
    let mut measured = Vec::new();
    for im in im.into_iter().chain(surface) {
        if !im.stored() && im.of_record() {
            measured.push(std::sync::Arc::new(study::measure_records(dir, im)?));
        }
    }
    Ok(FragilityOptions {
        im,
        surface,
        measured,
        limit_state,
        pool,
        ..options.clone()
    })
}

/// The bootstrap replicates of a refit of the study folder `dir` when the
/// caller gives none: the study's own `[fragility] bootstrap` (from
/// `dir/manifest.json`), so that a refit does not silently swap a study's
/// 1000-replicate bands for fewer; the default without a study.
pub fn study_bootstrap(dir: &Path) -> Result<usize> {
    let manifest = dir.join(files::MANIFEST);
    if !manifest.exists() {
        return Ok(FragilityOptions::default().bootstrap);
    }
    let m = study::Manifest::read(&manifest)?;
    let study = Study::from_toml_unchecked(&m.spec_toml, &manifest)?;
    Ok(study
        .fragility
        .map_or(FragilityOptions::default().bootstrap, |f| f.bootstrap))
}

/// A warning when a refit with `bootstrap` replicates would replace, in
/// `out`, a fit drawn with more (its `fragility.csv`): the bands of the new
/// fit are noisier, which the caller asked for but may not have meant.
pub fn fewer_replicates(out: &Path, bootstrap: usize) -> Option<String> {
    let path = out.join("fragility.csv");
    let rows = crate::fragility::read_fragility_csv(&path).ok()?;
    let before = rows.iter().filter_map(|r| r.boot_replicates).max()?;
    (bootstrap < before).then(|| {
        format!(
            "{} held a fit with {before} bootstrap replicates; this one has {bootstrap}, so its \
             90 % bands are noisier (give the study's {before}, or write the refit elsewhere)",
            path.display()
        )
    })
}

/// Whether `a` and `b` name the same folder (by their canonical paths when
/// both exist).
pub fn same_folder(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// Draws the figures of the study folder `dir` into `out`: the generic
/// ones, with the paper's layer for the paper's own study.
pub fn figures(
    study: &Study,
    dir: &Path,
    out: &Path,
    options: &FigureOptions,
) -> Result<FiguresReport> {
    study::require_finished(dir)?;
    let report = paper::study_figures(study, dir, out, options)?;
    let written: Vec<&Path> = report.written.iter().map(PathBuf::as_path).collect();
    study::record_outputs(dir, &written)?;
    Ok(report)
}

/// What [`risk`] computed and wrote.
#[derive(Clone, Debug)]
pub struct RiskReport {
    /// One row per case and limit state.
    pub rows: Vec<crate::risk::RiskRow>,
    /// The hazard curve as integrated (in the fit's unit).
    pub hazard: crate::risk::HazardCurve,
    /// The fit's intensity measure.
    pub im: crate::im::Im,
    /// Whether the folder had `fragility_bootstrap.csv` (a band on the
    /// rates).
    pub banded: bool,
    /// `risk.csv`, `risk_hazard.csv` and `figures/risk.svg`, in that order.
    pub written: [PathBuf; 3],
    /// `summary.md`, when its `## Risk` section was written (the output is
    /// the study folder itself).
    pub summary: Option<PathBuf>,
}

/// `rockfrag risk` (and Python's `risk`): the fitted folder `dir`'s curves
/// integrated over the hazard curve `hazard` (site `site` of an OpenQuake
/// file), written into `out` (default `dir`) as `risk.csv`,
/// `risk_hazard.csv` (the hazard as integrated, for `rockfrag figures`) and
/// `figures/risk.svg`, and as `dir/summary.md`'s `## Risk` when `out` is
/// `dir`.
///
/// Errors: bad options, an unfitted or unfinished folder, a hazard curve in
/// another IM, `out` naming a `.csv` file, or files that cannot be written.
pub fn risk(
    dir: &Path,
    hazard: &Path,
    site: Option<usize>,
    options: &crate::risk::RiskOptions,
    out: Option<&Path>,
) -> Result<RiskReport> {
    use crate::risk::{
        USED_HAZARD, assess, read_fragility, read_hazard, summary_section, write_risk_csv,
        write_used_hazard,
    };
    options.validate()?;
    let fragility = read_fragility(dir)?;
    let hazard = read_hazard(hazard, site)?.in_unit_of(fragility.im())?;
    let rows = assess(&fragility, &hazard, options)?;
    let out = out.unwrap_or(dir);
    if out.extension().is_some_and(|e| e == "csv") {
        return Err(Error::invalid(
            "out",
            out.display().to_string(),
            "a folder (risk.csv and figures/risk.svg go into it), not a file",
        ));
    }
    let figures = out.join("figures");
    std::fs::create_dir_all(&figures).map_err(Error::io(&figures))?;
    let csv = out.join("risk.csv");
    write_risk_csv(&csv, &rows, options)?;
    let used = out.join(USED_HAZARD);
    write_used_hazard(&used, &hazard)?;
    let figure = figures.join("risk.svg");
    crate::figures::save(&crate::figures::RiskFigure::new(&rows, &hazard), &figure)?;
    study::record_outputs(dir, &[&csv, &used, &figure])?;
    let summary = dir.join("summary.md");
    let summary = (same_folder(out, dir) && summary.exists()).then_some(summary);
    if let Some(path) = &summary {
        let section = summary_section(&rows, &hazard, options);
        crate::io_util::replace_section(path, "## Risk", &section, &[]).map_err(Error::io(path))?;
    }
    Ok(RiskReport {
        im: fragility.im(),
        banded: fragility.bootstrap.is_some(),
        rows,
        hazard,
        written: [csv, used, figure],
        summary,
    })
}
