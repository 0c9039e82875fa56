//! Every publication figure of a study folder in one call, as `rockfrag
//! figures DIR` draws them.
//!
//! | file | figure |
//! |------|--------|
//! | `motion` | a sample record: acceleration, velocity, displacement ([`super::plot_record`]) |
//! | `spectrum` | ensemble periodograms against the target PSD ([`super::spectrum`]) |
//! | `history` | θ/θc and the modes of one finite-friction run ([`super::history`]) |
//! | `fragility` | fragility curves and observed fractions ([`super::fragility`]) |
//! | `friction_demand` | mean μ_mot and μ_imp against B/H ([`super::friction`]) |
//! | `restitution` | overturning and θmax/θc against e ([`super::restitution`]) |
//!
//! The first three are computed from the study's own motions and the solver
//! (see [`FigureOptions::for_folder`]): for a synthetic study, its generator
//! settings and seed; for a study of recorded motions (`record_files`), its
//! first record as recorded and the history chosen among its records, the
//! synthetic-ensemble spectrum being skipped with a note (it would describe
//! motions the study never ran). The last three are drawn from
//! `DIR/outcomes.csv` and, if present, `DIR/fragility_curves.csv`. Nothing
//! depends on the clock or on the order of the rows, so running twice gives
//! byte-identical files.

use std::path::{Path, PathBuf};

use super::data::StudyData;
use super::figure::{Figure, Format, save};
use super::fragility::FragilityFigure;
use super::friction::FrictionDemandFigure;
use super::history::{HistoryCase, HistoryFigure};
use super::motion::plot_record;
use super::restitution::RestitutionFigure;
use super::spectrum::SpectrumFigure;
use crate::error::{Error, Result};
use crate::motion::{SynthesisSettings, Synthesizer, read_record};
use crate::outcomes_csv::Pooled;
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
    /// Records in the spectrum's ensemble average (default: 200).
    pub spectrum_records: usize,
    /// PGA of the sample record, g (default: 0.6).
    pub motion_pga: f64,
    /// The analyses the history figure chooses from (default: see [`HistoryCase`]).
    pub history: HistoryCase,
    /// Ground-motion generator settings (default: the paper's). For a study
    /// of recorded motions only `g` is used (to read `.AT2` files).
    pub synthesis: SynthesisSettings,
    /// The study's recorded-motion files, in its order; empty (the default)
    /// for a synthetic study. When not empty, the sample record is the first
    /// file, the history is chosen among these records and the spectrum is
    /// skipped.
    pub record_files: Vec<PathBuf>,
    /// Whether the study is the paper's set-up, so that the friction-demand
    /// figure may draw the paper's Tables 1–3 beside its means (default:
    /// false; see [`FigureOptions::for_study`]).
    pub papers: bool,
    /// Case parameters the study draws per analysis (its `[uncertainty]`):
    /// the figures pool the analyses over them (default: none).
    pub pooled: Pooled,
}

impl Default for FigureOptions {
    fn default() -> Self {
        FigureOptions {
            format: Format::Svg,
            seed: 1,
            spectrum_records: 200,
            motion_pga: 0.6,
            history: HistoryCase::default(),
            synthesis: SynthesisSettings::default(),
            record_files: Vec::new(),
            papers: false,
            pooled: Pooled::default(),
        }
    }
}

impl FigureOptions {
    /// The options that draw `study`'s own motions: its seed and generator
    /// settings for the sample record, the spectrum and the history, or its
    /// record files (and `g`) for a study of recorded motions; `papers` set
    /// by [`crate::study::is_papers`]; every other field at its default.
    pub fn for_study(study: &Study) -> FigureOptions {
        let mut options = FigureOptions {
            papers: crate::study::is_papers(study),
            pooled: study.pooled(),
            ..FigureOptions::default()
        };
        match &study.motions {
            Motions::Synthetic { settings, seed, .. } => {
                options.seed = *seed;
                options.history.seed = *seed;
                options.synthesis = settings.clone();
            }
            Motions::Files(files) => {
                options.synthesis.g = study.g;
                options.record_files = files.iter().map(|f| f.path.clone()).collect();
            }
        }
        options
    }

    /// The options for the study folder `dir`: [`FigureOptions::for_study`]
    /// of the spec recorded in `dir/manifest.json`, or the defaults when the
    /// folder has no manifest. Record files are relative to the spec file
    /// the study was run from (`spec_file` in the manifest, as given on the
    /// command line); a file not found there is looked for relative to
    /// `dir`, and if not there either is left for [`study_figures`] to
    /// report.
    ///
    /// Errors: a manifest that cannot be read, or whose spec does not parse.
    pub fn for_folder(dir: &Path) -> Result<FigureOptions> {
        let path = dir.join(MANIFEST);
        if !path.exists() {
            return Ok(FigureOptions::default());
        }
        let manifest = Manifest::read(&path)?;
        let study = Study::from_toml_unchecked(&manifest.spec_toml, &path)?;
        let mut options = FigureOptions::for_study(&study);
        if let Motions::Files(files) = &study.motions {
            let base = Path::new(&manifest.spec_file)
                .parent()
                .unwrap_or(Path::new(""));
            options.record_files = files
                .iter()
                .map(|f| {
                    let from_spec = base.join(&f.given);
                    if from_spec.is_file() || !f.path.is_file() {
                        from_spec
                    } else {
                        f.path.clone()
                    }
                })
                .collect();
        }
        Ok(options)
    }
}

/// What [`study_figures`] did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FiguresReport {
    /// Files written, in the order of the table above.
    pub written: Vec<PathBuf>,
    /// Figures drawn in reduced form or skipped, and why.
    pub notes: Vec<String>,
}

/// Draws every figure of the study folder `dir` into `out` (created if
/// missing), in `options.format`.
///
/// Errors: [`Error::Io`] if `outcomes.csv` is missing or a file cannot be
/// written, [`Error::Parse`] for malformed CSV.
pub fn study_figures(dir: &Path, out: &Path, options: &FigureOptions) -> Result<FiguresReport> {
    let data = StudyData::load_pooled(dir, options.pooled)?;
    if data.outcomes.is_empty() {
        return Err(Error::Parse {
            path: dir.join("outcomes.csv"),
            line: 0,
            message: "no successful analyses to draw".to_string(),
        });
    }
    std::fs::create_dir_all(out).map_err(Error::io(out))?;
    let ext = options.format.extension();
    let file = |name: &str| out.join(format!("{name}.{ext}"));
    let mut report = FiguresReport::default();

    if options.record_files.is_empty() {
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
        let path = file("motion");
        plot_record(&record, &path)?;
        report.written.push(path);

        let spectrum =
            SpectrumFigure::compute(&options.synthesis, options.seed, options.spectrum_records)?;
        write(&spectrum, file("spectrum"), &mut report)?;

        let history = HistoryFigure::compute(&options.history, &options.synthesis)?;
        write(&history, file("history"), &mut report)?;
    } else {
        recorded_figures(options, &file, &mut report)?;
    }

    let fragility = FragilityFigure::from_study(&data);
    if !fragility.fitted {
        report.notes.push(format!(
            "fragility: no {} — observed fractions only",
            dir.join("fragility_curves.csv").display()
        ));
    }
    write(&fragility, file("fragility"), &mut report)?;

    // Both figures are drawn over fixed values of H/B (and e): a parameter
    // drawn per analysis has none.
    let drawn = |what: &str, param: &str| {
        format!(
            "{what}: skipped, {param} is drawn per analysis ([uncertainty]) and the figure \
             is drawn over fixed values of it"
        )
    };
    match FrictionDemandFigure::from_study(&data) {
        _ if options.pooled.aspect => report.notes.push(drawn("friction_demand", "H/B")),
        Some(fig) if options.papers => write(&fig, file("friction_demand"), &mut report)?,
        Some(fig) => write(&fig.without_paper(), file("friction_demand"), &mut report)?,
        None => report.notes.push(
            "friction_demand: skipped, the study has no infinite-friction analyses".to_string(),
        ),
    }

    if options.pooled.restitution {
        report.notes.push(drawn("restitution", "e"));
    } else if options.pooled.aspect {
        report.notes.push(drawn("restitution", "H/B"));
    } else {
        write(
            &RestitutionFigure::from_study(&data),
            file("restitution"),
            &mut report,
        )?;
    }
    Ok(report)
}

/// The motion and history figures of a study of recorded motions (the
/// spectrum is skipped with a note): the first record as recorded, and the
/// history chosen among the first `options.history.records` records scaled
/// to its PGA. A record file that cannot be read skips both, with a note.
fn recorded_figures(
    options: &FigureOptions,
    file: &dyn Fn(&str) -> PathBuf,
    report: &mut FiguresReport,
) -> Result<()> {
    let g = options.synthesis.g;
    // The spectrum of every record the study ran, as recorded.
    let mut all = Vec::with_capacity(options.record_files.len());
    for path in &options.record_files {
        match read_record(path, g) {
            Ok(r) => all.push(r),
            Err(e) => {
                report.notes.push(format!(
                    "spectrum: skipped, record file {} cannot be read ({e})",
                    path.display()
                ));
                all.clear();
                break;
            }
        }
    }
    if !all.is_empty() {
        let spectrum = SpectrumFigure::recorded(&all, "recorded motions");
        write(&spectrum, file("spectrum"), report)?;
    }
    let n = (options.history.records.max(1) as usize).min(options.record_files.len());
    let mut records = Vec::with_capacity(n);
    let mut names = Vec::with_capacity(n);
    for path in &options.record_files[..n] {
        match read_record(path, g) {
            Ok(r) => records.push(r),
            Err(e) => {
                report.notes.push(format!(
                    "motion, history: skipped, record file {} cannot be read ({e}); \
                     record files are relative to the spec file as given to `rockfrag run`, \
                     from the folder it ran in",
                    path.display()
                ));
                return Ok(());
            }
        }
        names.push(path.file_name().map_or_else(
            || path.display().to_string(),
            |f| f.to_string_lossy().into_owned(),
        ));
    }
    let mut first = records[0].clone();
    first.name = format!(
        "{}, as recorded (PGA {} g)",
        names[0],
        super::style::tick_label((first.pga() / g * 1000.0).round() / 1000.0)
    );
    let path = file("motion");
    plot_record(&first, &path)?;
    report.written.push(path);
    let history = HistoryFigure::compute_recorded(&options.history, &records, &names, g)?;
    write(&history, file("history"), report)?;
    Ok(())
}

fn write<F: Figure>(figure: &F, path: PathBuf, report: &mut FiguresReport) -> Result<()> {
    save(figure, &path)?;
    report.written.push(path);
    Ok(())
}
