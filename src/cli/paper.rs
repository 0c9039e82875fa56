//! `rockfrag paper`: the paper's study over K ensembles under each reading of
//! its section 4, scored against Tables 1–3 (`paper-check.md`).

use std::path::PathBuf;
use std::time::Instant;

use rockfrag::paper::{CheckOptions, check, check_markdown, write_e_trend, write_report};

/// Flags of `rockfrag paper`.
#[derive(Debug, clap::Args)]
pub struct PaperArgs {
    /// Ensembles per reading (seeds SEED, SEED+1, …); at least 2.
    #[arg(long, value_name = "K", default_value_t = 12)]
    pub replicates: usize,
    /// Seed of the first ensemble [default: the built-in study's, 1991].
    #[arg(long, value_name = "N")]
    pub seed: Option<u64>,
    /// Folder paper-check.md is written to (created if missing).
    #[arg(long, value_name = "DIR", default_value = "results/paper")]
    pub out: PathBuf,
    /// Worker threads (0: one per core).
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub threads: usize,
    /// Format of the e-trend figure (`e_trend.svg` or `.png` beside the report).
    #[arg(long, value_enum, default_value_t = super::figures::FormatArg::Svg)]
    pub format: super::figures::FormatArg,
}

/// Runs `rockfrag paper`.
pub fn run(args: PaperArgs) -> anyhow::Result<()> {
    let mut options = CheckOptions {
        replicates: args.replicates,
        threads: args.threads,
        ..CheckOptions::default()
    };
    if let Some(seed) = args.seed {
        options.seed = seed;
    }
    let t0 = Instant::now();
    let results = check(&options, |line| {
        eprintln!("{line} ({:.1} s)", t0.elapsed().as_secs_f64())
    })?;
    let text = check_markdown(&results, &options);
    let path = args.out.join("paper-check.md");
    write_report(&path, &text)?;
    let figure = args.out.join(match args.format {
        super::figures::FormatArg::Svg => "e_trend.svg",
        super::figures::FormatArg::Png => "e_trend.png",
    });
    if write_e_trend(&results, &figure)? {
        eprintln!("drew {}", figure.display());
    }
    print!("{text}");
    eprintln!(
        "wrote {} in {:.1} s",
        path.display(),
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}
