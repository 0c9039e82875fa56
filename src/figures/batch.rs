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
//! The first three are computed from the generator and the solver (with the
//! study's generator settings and seed, see [`FigureOptions::for_folder`]),
//! the last three from
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
use crate::motion::{SynthesisSettings, Synthesizer};
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
    /// Ground-motion generator settings (default: the paper's).
    pub synthesis: SynthesisSettings,
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
        }
    }
}

impl FigureOptions {
    /// The options that draw `study`'s own ensemble: its seed and generator
    /// settings for the sample record, the spectrum and the history (for a
    /// study of recorded motions, the defaults), every other field at its
    /// default.
    pub fn for_study(study: &Study) -> FigureOptions {
        let mut options = FigureOptions::default();
        if let Motions::Synthetic { settings, seed, .. } = &study.motions {
            options.seed = *seed;
            options.history.seed = *seed;
            options.synthesis = settings.clone();
        }
        options
    }

    /// The options for the study folder `dir`: [`FigureOptions::for_study`]
    /// of the spec recorded in `dir/manifest.json`, or the defaults when the
    /// folder has no manifest.
    ///
    /// Errors: a manifest that cannot be read, or whose spec does not parse.
    pub fn for_folder(dir: &Path) -> Result<FigureOptions> {
        let path = dir.join(MANIFEST);
        if !path.exists() {
            return Ok(FigureOptions::default());
        }
        let manifest = Manifest::read(&path)?;
        let study = Study::from_toml_unchecked(&manifest.spec_toml, &path)?;
        Ok(FigureOptions::for_study(&study))
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
    let data = StudyData::load(dir)?;
    if data.outcomes.is_empty() {
        return Err(Error::Parse {
            path: dir.join("outcomes.csv"),
            line: 0,
            message: "no successful analyses to draw".to_string(),
        });
    }
    std::fs::create_dir_all(out).map_err(|source| Error::Io {
        path: out.to_path_buf(),
        source,
    })?;
    let ext = options.format.extension();
    let file = |name: &str| out.join(format!("{name}.{ext}"));
    let mut report = FiguresReport::default();

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

    let fragility = FragilityFigure::from_study(&data);
    if !fragility.fitted {
        report.notes.push(format!(
            "fragility: no {} — observed fractions only",
            dir.join("fragility_curves.csv").display()
        ));
    }
    write(&fragility, file("fragility"), &mut report)?;

    match FrictionDemandFigure::from_study(&data) {
        Some(fig) => write(&fig, file("friction_demand"), &mut report)?,
        None => report.notes.push(
            "friction_demand: skipped, the study has no infinite-friction analyses".to_string(),
        ),
    }

    write(
        &RestitutionFigure::from_study(&data),
        file("restitution"),
        &mut report,
    )?;
    Ok(report)
}

fn write<F: Figure>(figure: &F, path: PathBuf, report: &mut FiguresReport) -> Result<()> {
    save(figure, &path)?;
    report.written.push(path);
    Ok(())
}
