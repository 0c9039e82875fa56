//! `rockfrag figures`: the publication figures of a study folder.

use std::path::PathBuf;

use clap::ValueEnum;
use rockfrag::figures::{FigureOptions, Format, study_figures};

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
    /// Study folder holding outcomes.csv (and optionally fragility_curves.csv).
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// Folder the figures are written to (created if missing).
    #[arg(long, value_name = "DIR", default_value = "figures")]
    pub out: PathBuf,
    /// Output format.
    #[arg(long, value_enum, default_value_t = FormatArg::Svg)]
    pub format: FormatArg,
    /// Ensemble seed of the sample record, the spectrum and the history.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub seed: u64,
}

/// Runs `rockfrag figures`.
pub fn run(args: FiguresArgs) -> anyhow::Result<()> {
    let mut options = FigureOptions {
        format: match args.format {
            FormatArg::Svg => Format::Svg,
            FormatArg::Png => Format::Png,
        },
        seed: args.seed,
        ..FigureOptions::default()
    };
    options.history.seed = args.seed;
    let report = study_figures(&args.dir, &args.out, &options)?;
    for note in &report.notes {
        eprintln!("note: {note}");
    }
    for path in &report.written {
        println!("{}", path.display());
    }
    Ok(())
}
