//! `rockfrag figures`: the publication figures of a study folder.

use std::path::PathBuf;

use clap::ValueEnum;
use rockfrag::figures::{FigureOptions, Format, study_figures, study_of_folder};

/// Output format, as a CLI value.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum FormatArg {
    /// Scalable vector graphics.
    Svg,
    /// Portable network graphics at 300 px/in.
    Png,
}

/// Flags of `rockfrag figures`.
#[derive(Debug, clap::Args)]
pub struct FiguresArgs {
    /// Study folder holding outcomes.csv (and optionally fragility_curves.csv
    /// and manifest.json); default: the built-in study's folder.
    #[arg(value_name = "DIR", default_value = "results/shenton-jones")]
    pub dir: PathBuf,
    /// Folder the figures are written to (created if missing) [default:
    /// DIR/figures].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = FormatArg::Svg)]
    pub format: FormatArg,
    /// Ensemble seed of the sample record, the spectrum and the history
    /// (default: the study's, from DIR/manifest.json; 1 without one).
    #[arg(long, value_name = "N")]
    pub seed: Option<u64>,
}

/// Runs `rockfrag figures`.
pub fn run(args: FiguresArgs) -> anyhow::Result<()> {
    rockfrag::study::files::require_finished(&args.dir)?;
    let study = study_of_folder(&args.dir)?;
    let mut options = study
        .as_ref()
        .map_or_else(FigureOptions::default, FigureOptions::for_study);
    options.format = match args.format {
        FormatArg::Svg => Format::Svg,
        FormatArg::Png => Format::Png,
    };
    if let Some(seed) = args.seed {
        options.seed = seed;
    }
    let out = args.out.unwrap_or_else(|| args.dir.join("figures"));
    let report = match &study {
        Some(study) => rockfrag::pipeline::figures(study, &args.dir, &out, &options)?,
        None => study_figures(&args.dir, &out, &options)?,
    };
    for note in &report.notes {
        eprintln!("note: {note}");
    }
    for path in &report.written {
        println!("{}", path.display());
    }
    Ok(())
}
