//! Every publication figure of a study folder in one call, as `rockfrag
//! figures DIR` draws them.
//!
//! | file | figure |
//! |------|--------|
//! | `motion` | a sample record: acceleration, velocity, displacement ([`super::plot_record`]) |
//! | `spectrum` | ensemble periodograms against the target PSD ([`super::spectrum`]) |
//! | `history` | θ/θc and the modes of one of the study's analyses ([`super::history`]); of a stack's case, every body's φ/θc and slip ([`super::stack_history`]) |
//! | `fragility` | fragility curves and observed fractions ([`super::fragility`]) |
//! | `friction_demand` | mean μ_mot and μ_imp against B/H ([`super::friction`]) |
//! | `restitution` | overturning and θmax/θc against e ([`super::restitution`]) |
//! | `risk` | annual rate of each limit state at a site ([`super::risk`]), once `rockfrag risk` has run |
//! | `surface_<case>_<limit state>` | a fragility surface's contours and observed fractions ([`super::surface`]), one per row of `fragility_surface.csv` when the fit has one |
//!
//! The sample record and the spectrum come from the study's own motions
//! (see [`FigureOptions::for_folder`]): for a synthetic study, its generator
//! settings and seed; for a study of recorded motions (`record_files`), its
//! first record as recorded and the mean spectrum of its records. The
//! history re-solves one of the study's analyses with its time history
//! (see `figures::history`). The last three are drawn from
//! `DIR/outcomes.csv` and, if present, `DIR/fragility_curves.csv`. The risk
//! figure is drawn when `rockfrag risk` has written `DIR/risk.csv`: from
//! the fit (`DIR/fragility.csv`, `DIR/fragility_bootstrap.csv`) and the
//! hazard curve it integrated over (`DIR/risk_hazard.csv`), the same figure
//! `rockfrag risk` drew, in either format; a folder whose `risk.csv` lacks
//! that curve or no longer matches the fit gets a note instead. Nothing
//! depends on the clock or on the order of the rows, so running twice gives
//! byte-identical files.
//!
//! [`StudyFigures::compute`] builds the figures' data and
//! [`StudyFigures::write`] draws them, so that a layer above (the paper's)
//! can add to a figure in between.

use std::path::{Path, PathBuf};

use super::data::StudyData;
use super::figure::{Figure, Format, save};
use super::fragility::FragilityFigure;
use super::friction::FrictionDemandFigure;
use super::history::{HistoryChoice, HistoryFigure, HistorySource};
use super::motion::plot_record;
use super::restitution::RestitutionFigure;
use super::risk::RiskFigure;
use super::spectrum::SpectrumFigure;
use super::stack_history::{StackHistoryFigure, StudyHistory, study_history};
use super::surface::SurfaceFigure;
use crate::case::Field;
use crate::error::{Error, Result};
use crate::motion::{Record, SynthesisSettings, Synthesizer, read_record};
use crate::risk::{
    RiskCsvRow, RiskOptions, USED_HAZARD, assess, read_fragility, read_hazard, read_risk_csv,
};
use crate::spec::{Motions, Study};
use crate::study::Manifest;
use crate::study::files::MANIFEST;

/// What to draw and how.
#[derive(Clone, Debug, PartialEq)]
pub struct FigureOptions {
    /// Output format (default: SVG).
    pub format: Format,
    /// Ensemble seed of the sample record and the spectrum (default: 1, the
    /// study runner's default seed).
    pub seed: u64,
    /// Records in the spectrum's ensemble average (default: 200; for a
    /// study, its own number of records, or of record pairs).
    pub spectrum_records: usize,
    /// PGA of the sample record, g (default: 0.6).
    pub motion_pga: f64,
    /// Which analysis the history figure draws (default: chosen, see
    /// the history module).
    pub history: HistoryChoice,
    /// Ground-motion generator settings (default: the generator's). For a
    /// study of recorded motions only `g` is used (to read `.AT2` files).
    pub synthesis: SynthesisSettings,
    /// The study's recorded-motion files, in its order; empty (the default)
    /// for a synthetic study. When not empty, the sample record is the first
    /// file and the spectrum is the records' own.
    pub record_files: Vec<PathBuf>,
    /// Case fields the study draws per analysis (its `[uncertainty]`): the
    /// figures pool the analyses over them (default: none).
    pub pooled: Vec<Field>,
    /// The study, when known (from its manifest): the history re-solves its
    /// analyses with its solver settings and motions.
    pub study: Option<Study>,
}

impl Default for FigureOptions {
    fn default() -> Self {
        FigureOptions {
            format: Format::Svg,
            seed: 1,
            spectrum_records: 200,
            motion_pga: 0.6,
            history: HistoryChoice::default(),
            synthesis: SynthesisSettings::default(),
            record_files: Vec::new(),
            pooled: Vec::new(),
            study: None,
        }
    }
}

impl FigureOptions {
    /// The options that draw `study`'s own motions: its seed and generator
    /// settings for the sample record and the spectrum, or its record files
    /// (and `g`) for a study of recorded motions; every other field at its
    /// default.
    pub fn for_study(study: &Study) -> FigureOptions {
        let mut options = FigureOptions {
            pooled: study.drawn(),
            study: Some(study.clone()),
            ..FigureOptions::default()
        };
        match &study.motions {
            Motions::Synthetic {
                settings,
                seed,
                records,
                pairs,
            } => {
                options.seed = *seed;
                options.synthesis = settings.clone();
                // the records the study ran: a pair's angles share its records
                options.spectrum_records = match pairs {
                    Some(orientation) => records.div_ceil(orientation.per_pair()),
                    None => *records,
                };
            }
            // a pair's components each count as a record of the spectrum
            Motions::Files(_) | Motions::Pairs { .. } => {
                options.synthesis.g = study.g;
                options.record_files = study
                    .motions
                    .files()
                    .iter()
                    .map(|f| f.path.clone())
                    .collect();
            }
        }
        options
    }

    /// The options for the study folder `dir`: [`FigureOptions::for_study`]
    /// of the spec recorded in `dir/manifest.json`, or the defaults when the
    /// folder has no manifest. Record files are relative to the spec file
    /// the study was run from (`spec_file` in the manifest, as given on the
    /// command line); a file not found there is looked for relative to
    /// `dir`, and if not there either is left for [`StudyFigures::compute`]
    /// to report.
    ///
    /// Errors: a manifest that cannot be read, or whose spec does not parse.
    pub fn for_folder(dir: &Path) -> Result<FigureOptions> {
        let Some(study) = study_of_folder(dir)? else {
            return Ok(FigureOptions::default());
        };
        Ok(FigureOptions::for_study(&study))
    }
}

/// The study recorded in `dir/manifest.json` (`None` without a manifest),
/// its record files found relative to the spec file it was run from (as
/// given on the command line) or else relative to `dir`.
///
/// Errors: a manifest that cannot be read, or whose spec does not parse.
pub fn study_of_folder(dir: &Path) -> Result<Option<Study>> {
    let path = dir.join(MANIFEST);
    if !path.exists() {
        return Ok(None);
    }
    let manifest = Manifest::read(&path)?;
    let mut study = Study::from_toml_unchecked(&manifest.spec_toml, &path)?;
    let base = Path::new(&manifest.spec_file)
        .parent()
        .unwrap_or(Path::new(""));
    for f in study.motions.files_mut() {
        let from_spec = base.join(&f.given);
        if from_spec.is_file() || !f.path.is_file() {
            f.path = from_spec;
        }
    }
    Ok(Some(study))
}

/// What [`study_figures`] did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FiguresReport {
    /// Files written, in the order of the table above.
    pub written: Vec<PathBuf>,
    /// Figures drawn in reduced form or skipped, and why.
    pub notes: Vec<String>,
    /// The command that solves the history figure's analysis again
    /// (`rockfrag simulate --study …`), when there is one.
    pub history_command: Option<String>,
}

/// The figures of a study folder, computed and not yet drawn.
#[derive(Clone, Debug)]
pub struct StudyFigures {
    /// The sample record.
    pub motion: Option<Record>,
    /// The spectrum.
    pub spectrum: Option<SpectrumFigure>,
    /// The response history (of a block's case).
    pub history: Option<HistoryFigure>,
    /// The response history of a stack's case, every body (drawn as
    /// `history`, in place of [`StudyFigures::history`]).
    pub stack_history: Option<StackHistoryFigure>,
    /// The fragility curves.
    pub fragility: FragilityFigure,
    /// The friction demand (studies with infinite-friction analyses over
    /// fixed H/B).
    pub friction_demand: Option<FrictionDemandFigure>,
    /// The trend with restitution (studies over fixed e and H/B).
    pub restitution: Option<RestitutionFigure>,
    /// The risk at a site (folders where `rockfrag risk` has run).
    pub risk: Option<RiskFigure>,
    /// The fragility surfaces, each with its file stem (folders whose fit
    /// has `fragility_surface.csv`).
    pub surfaces: Vec<(String, SurfaceFigure)>,
    /// Every case's curves side by side, per body (studies with stacks).
    pub stacks: Option<super::compare::CompareFigure>,
    /// The study's data, for a layer that adds figures of its own.
    pub data: StudyData,
    /// Figures drawn in reduced form or skipped, and why.
    pub notes: Vec<String>,
}

impl StudyFigures {
    /// Computes every figure of the study folder `dir`.
    ///
    /// Errors: [`Error::Io`] if `outcomes.csv` is missing, [`Error::Parse`]
    /// for malformed CSV or a folder without successful analyses.
    pub fn compute(dir: &Path, options: &FigureOptions) -> Result<StudyFigures> {
        let data = StudyData::load_study(dir, options.study.as_ref(), &options.pooled)?;
        if data.outcomes.is_empty() {
            return Err(Error::Parse {
                path: dir.join("outcomes.csv"),
                line: 0,
                message: "no successful analyses to draw".to_string(),
            });
        }
        let mut notes = Vec::new();
        let (motion, spectrum) = if options.record_files.is_empty() {
            let mut synth = Synthesizer::new(&options.synthesis)?;
            let mut record = synth.generate(
                options.seed,
                0,
                options.synthesis.pga_from_g(options.motion_pga),
            )?;
            record.name = format!(
                "Record 0 of ensemble seed {}, scaled to {} g",
                options.seed,
                super::style::tick_label(options.motion_pga)
            );
            let pairs = options
                .study
                .as_ref()
                .is_some_and(|s| matches!(s.motions, Motions::Synthetic { pairs: Some(_), .. }));
            let spectrum = if pairs {
                SpectrumFigure::compute_pairs(
                    &options.synthesis,
                    options.seed,
                    options.spectrum_records,
                )?
            } else {
                SpectrumFigure::compute(&options.synthesis, options.seed, options.spectrum_records)?
            };
            (Some(record), Some(spectrum))
        } else {
            recorded_figures(options, &mut notes)
        };
        let source = HistorySource {
            choice: &options.history,
            study: options.study.as_ref(),
            synthesis: &options.synthesis,
            seed: options.seed,
            record_files: &options.record_files,
            pooled: &options.pooled,
        };
        let (history, stack_history) = match study_history(dir, &data, &source) {
            Ok(StudyHistory::Block(h)) => (Some(*h), None),
            Ok(StudyHistory::Stack(h)) => (None, Some(*h)),
            Err(e) => {
                notes.push(format!("history: skipped, {e}"));
                (None, None)
            }
        };

        let fragility = FragilityFigure::from_study(&data);
        if !fragility.fitted {
            notes.push(format!(
                "fragility: no {} — observed fractions only",
                dir.join("fragility_curves.csv").display()
            ));
        }
        // Both figures are drawn over fixed values of H/B (and e): a
        // parameter drawn per analysis has none.
        let drawn = |what: &str, param: &str| {
            format!(
                "{what}: skipped, {param} is drawn per analysis ([uncertainty]) and the figure \
                 is drawn over fixed values of it"
            )
        };
        let pooled = |f: Field| options.pooled.contains(&f);
        let friction_demand = match FrictionDemandFigure::from_study(&data) {
            _ if pooled(Field::Aspect) => {
                notes.push(drawn("friction_demand", "H/B"));
                None
            }
            Some(fig) => Some(fig),
            None => {
                notes.push(
                    "friction_demand: skipped, the study has no infinite-friction analyses"
                        .to_string(),
                );
                None
            }
        };
        let restitution = if pooled(Field::Restitution) {
            notes.push(drawn("restitution", "e"));
            None
        } else if pooled(Field::Aspect) {
            notes.push(drawn("restitution", "H/B"));
            None
        } else {
            Some(RestitutionFigure::from_study(&data))
        };
        let risk = risk_figure(dir, &mut notes);
        let surfaces = surface_figures(dir, options, &mut notes);
        let stacks = super::compare::CompareFigure::of_cases(&data);
        if stacks.is_some() {
            notes.push(
                "fragility: a stack's case is plotted there under its top block's H/B, e \
                 and μ; stacks.* plots each case and body apart"
                    .to_string(),
            );
        }
        Ok(StudyFigures {
            motion,
            spectrum,
            history,
            stack_history,
            fragility,
            friction_demand,
            restitution,
            risk,
            surfaces,
            stacks,
            data,
            notes,
        })
    }

    /// Draws every figure into `out` (created if missing) in `format`, in
    /// the order of the table above.
    pub fn write(&self, out: &Path, format: Format) -> Result<FiguresReport> {
        crate::io_util::create_folder(out)?;
        let file = |name: &str| out.join(format!("{name}.{}", format.extension()));
        let mut report = FiguresReport {
            written: Vec::new(),
            notes: self.notes.clone(),
            history_command: match (&self.history, &self.stack_history) {
                (Some(h), _) => h.command.clone(),
                (None, Some(h)) => h.command.clone(),
                (None, None) => None,
            },
        };
        if let Some(record) = &self.motion {
            let path = file("motion");
            plot_record(record, &path)?;
            report.written.push(path);
        }
        if let Some(f) = &self.spectrum {
            write(f, file("spectrum"), &mut report)?;
        }
        if let Some(f) = &self.history {
            write(f, file("history"), &mut report)?;
        }
        if let Some(f) = &self.stack_history {
            write(f, file("history"), &mut report)?;
        }
        write(&self.fragility, file("fragility"), &mut report)?;
        if let Some(f) = &self.friction_demand {
            write(f, file("friction_demand"), &mut report)?;
        }
        if let Some(f) = &self.restitution {
            write(f, file("restitution"), &mut report)?;
        }
        if let Some(f) = &self.risk {
            write(f, file("risk"), &mut report)?;
        }
        for (stem, f) in &self.surfaces {
            write(f, file(stem), &mut report)?;
        }
        if let Some(f) = &self.stacks {
            write(f, file("stacks"), &mut report)?;
        }
        Ok(report)
    }
}

/// Draws every figure of the study folder `dir` into `out` (created if
/// missing), in `options.format`: [`StudyFigures::compute`], then
/// [`StudyFigures::write`].
///
/// Errors: [`Error::Io`] if `outcomes.csv` is missing or a file cannot be
/// written, [`Error::Parse`] for malformed CSV.
pub fn study_figures(dir: &Path, out: &Path, options: &FigureOptions) -> Result<FiguresReport> {
    StudyFigures::compute(dir, options)?.write(out, options.format)
}

/// The risk figure of the folder `dir`, as `rockfrag risk` drew it: `None`
/// without `risk.csv`; `None` and a note when the hazard curve it used
/// (`risk_hazard.csv`) is missing or unreadable, or when the fit gives
/// other rates than `risk.csv` holds (refitted since), so that a figure
/// never disagrees with `risk.csv`.
fn risk_figure(dir: &Path, notes: &mut Vec<String>) -> Option<RiskFigure> {
    let csv = dir.join("risk.csv");
    if !csv.is_file() {
        return None;
    }
    let rerun = format!("rerun `rockfrag risk {} --hazard FILE`", dir.display());
    let used = dir.join(USED_HAZARD);
    if !used.is_file() {
        notes.push(format!(
            "risk: skipped, {} has no {USED_HAZARD} beside it (the hazard curve it was \
             computed over, written by rockfrag risk from this version on): {rerun}",
            csv.display()
        ));
        return None;
    }
    let computed = (|| -> Result<_> {
        let fragility = read_fragility(dir)?;
        let hazard = read_hazard(&used, None)?;
        let rows = assess(&fragility, &hazard, &RiskOptions::default())?;
        Ok((rows, hazard))
    })();
    let (rows, hazard) = match computed {
        Ok(r) => r,
        Err(e) => {
            notes.push(format!("risk: skipped, {e}"));
            return None;
        }
    };
    // the rates the fit gives now, as risk.csv would hold them
    let key = |r: &RiskCsvRow| {
        let rate = r.annual_rate.filter(|v| v.is_finite());
        (r.case, r.limit_state.clone(), rate)
    };
    let now: Vec<_> = rows
        .iter()
        .map(|r| key(&RiskCsvRow::of(r, RiskOptions::default().years)))
        .collect();
    let written = read_risk_csv(&csv).map(|w| w.iter().map(key).collect::<Vec<_>>());
    if written.ok().as_ref() != Some(&now) {
        notes.push(format!(
            "risk: skipped, {} does not hold the rates of the fit in {} (refitted since \
             rockfrag risk ran?): {rerun}",
            csv.display(),
            dir.join("fragility.csv").display()
        ));
        return None;
    }
    Some(RiskFigure::new(&rows, &hazard))
}

/// The surface figures of the folder `dir` (none without
/// `fragility_surface.csv` in a whole fit set); a note instead when its
/// analyses cannot be read against both IMs.
fn surface_figures(
    dir: &Path,
    options: &FigureOptions,
    notes: &mut Vec<String>,
) -> Vec<(String, SurfaceFigure)> {
    let csv = dir.join(crate::fragility::SURFACE_FILE);
    if !csv.is_file() {
        return Vec::new();
    }
    let drawn = (|| -> Result<_> {
        crate::fragility::check_set(dir)?;
        let rows = crate::fragility::read_surface_csv(&csv)?;
        SurfaceFigure::for_rows(dir, options.study.as_ref(), &options.pooled, &rows)
    })();
    drawn.unwrap_or_else(|e| {
        notes.push(format!("surface: skipped, {e}"));
        Vec::new()
    })
}

/// The sample record and spectrum of a study of recorded motions: the first
/// record as recorded, and the mean spectrum of every record as recorded. A
/// record file that cannot be read skips the figure it is needed for, with
/// a note.
fn recorded_figures(
    options: &FigureOptions,
    notes: &mut Vec<String>,
) -> (Option<Record>, Option<SpectrumFigure>) {
    let g = options.synthesis.g;
    let mut all = Vec::with_capacity(options.record_files.len());
    for path in &options.record_files {
        match read_record(path, g) {
            Ok(r) => all.push(r),
            Err(e) => {
                notes.push(format!(
                    "motion, spectrum: skipped, record file {} cannot be read ({e}); record \
                     files are relative to the spec file as given to `rockfrag run`, from the \
                     folder it ran in",
                    path.display()
                ));
                return (None, None);
            }
        }
    }
    let spectrum = SpectrumFigure::recorded(&all, "recorded motions");
    let mut first = all.swap_remove(0);
    let name = options.record_files[0].file_name().map_or_else(
        || options.record_files[0].display().to_string(),
        |f| f.to_string_lossy().into_owned(),
    );
    first.name = format!(
        "{name}, as recorded (PGA {} g)",
        super::style::tick_label((first.pga() / g * 1000.0).round() / 1000.0)
    );
    (Some(first), Some(spectrum))
}

fn write<F: Figure>(figure: &F, path: PathBuf, report: &mut FiguresReport) -> Result<()> {
    save(figure, &path)?;
    report.written.push(path);
    Ok(())
}
