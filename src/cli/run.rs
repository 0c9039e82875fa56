//! `rockfrag run`: run a study spec (default: the paper's, built in).

use super::args::{shard, threads};
use anyhow::bail;
use rockfrag::figures::FigureOptions;
use rockfrag::spec::{SHENTON_JONES_ORIGIN, Study};
use rockfrag::study::{self, RunOptions, Shard, files};
use std::path::{Path, PathBuf};

/// Flags of `rockfrag run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// Study spec (TOML). Default: the paper's study (studies/shenton-jones.toml, built in).
    #[arg(value_name = "STUDY.toml")]
    pub study: Option<PathBuf>,
    /// Output folder (default: results/<study name>/). Rerunning into a folder
    /// holding an interrupted run of the same study resumes it.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Worker threads (default: one per core). Results do not depend on it.
    #[arg(long, value_name = "N", value_parser = threads)]
    pub threads: Option<usize>,
    /// Run only shard K of N of the work units (for job arrays; merge the
    /// shard folders with `rockfrag merge`).
    #[arg(long, value_name = "K/N", value_parser = shard)]
    pub shard: Option<Shard>,
    /// Stop as if killed after this many work units (for testing resumption).
    #[arg(long, value_name = "UNITS", hide = true)]
    pub stop_after_units: Option<usize>,
    /// Replace a finished run of another spec or shard in the output folder
    /// (without it, that is refused).
    #[arg(long)]
    pub force: bool,
    /// Print the fragility table and every note (default: one line per step).
    #[arg(long, short)]
    pub verbose: bool,
}

/// Runs `rockfrag run`.
pub fn run(args: RunArgs) -> anyhow::Result<()> {
    let (study, spec_file) = match &args.study {
        Some(path) => (Study::load(path)?, path.display().to_string()),
        None => (Study::shenton_jones(), SHENTON_JONES_ORIGIN.to_string()),
    };
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("results").join(&study.name));
    let opts = RunOptions {
        out_dir: out.clone(),
        threads: args.threads.unwrap_or(0),
        shard: args.shard.unwrap_or(Shard::WHOLE),
        progress: true,
        spec_file,
        chunk_analyses: 0,
        stop_after_units: args.stop_after_units,
        force: args.force,
    };
    // Held over the run and what follows it (fragility files, figures): a
    // second run into this folder is refused until all is written.
    std::fs::create_dir_all(&out).map_err(rockfrag::Error::io(&out))?;
    let _lock = study::RunLock::acquire(&out)?;
    let report = study::run(&study, &opts)?;
    let rate = report.analyses_run as f64 / report.wall_seconds.max(1e-9);
    if report.resumed_at_unit > 0 {
        eprintln!("resumed after {} work units", report.resumed_at_unit);
    }
    if !report.complete {
        eprintln!(
            "stopped: {} analyses in {:.1} s; run the same command again to resume",
            report.analyses_run, report.wall_seconds
        );
        return Ok(());
    }
    let c = report.counts;
    eprintln!(
        "study {}{}: {} analyses ({} overturned, {} uplifted, {} failed); {} run in {:.1} s, \
         {:.1} analyses/s on {} thread{}; wrote {}",
        study.name,
        if opts.shard == Shard::WHOLE {
            String::new()
        } else {
            format!(" shard {}", opts.shard)
        },
        c.analyses,
        c.overturned,
        c.uplifted,
        c.failed,
        report.analyses_run,
        report.wall_seconds,
        rate,
        report.threads,
        if report.threads == 1 { "" } else { "s" },
        out.display()
    );
    // The fit and the figures skip failed analyses (and say how many), so
    // they are made before the failures are reported in the exit status.
    if opts.shard == Shard::WHOLE {
        finish(&study, &out, args.verbose)?;
    }
    if c.failed > 0 {
        bail!(
            "{} of {} analyses failed (status 'failed' and the reason in {}); all results are written",
            c.failed,
            c.analyses,
            out.join(files::OUTCOMES).display()
        );
    }
    Ok(())
}

/// What a complete study folder gets when its spec asks: the fragility fit
/// (`[fragility]`) and the figures (`output.figures`, into `DIR/figures/`).
/// Says one line for each, and a line of bootstrap notes if any, on
/// standard error; `verbose` prints the fragility table and every note on
/// standard output.
pub fn finish(study: &Study, dir: &Path, verbose: bool) -> anyhow::Result<()> {
    if let Some(options) = &study.fragility {
        let report = super::fragility::fit_and_write(dir, dir, options)?;
        if verbose {
            print!("{}{}{}", report.table, report.notes(true), report.wrote);
        } else {
            eprint!("{}{}", report.summary(), report.notes(false));
        }
    }
    if study.output.figures {
        let out = dir.join("figures");
        let written = super::figures::draw(dir, &out, &FigureOptions::for_study(study))?;
        eprintln!("drew {} figures into {}", written.len(), out.display());
    }
    Ok(())
}
