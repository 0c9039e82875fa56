//! `rockfrag run`: run a study spec (default: the paper's, built in).

use super::args::{shard, threads};
use anyhow::bail;
use rockfrag::pipeline::{self, FinishReport};
use rockfrag::spec::{SHENTON_JONES_ORIGIN, Study};
use rockfrag::study::{RunOptions, Shard};
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
    /// Run every analysis again, replacing the output folder's finished run
    /// (without it, a finished run of the same analyses is kept and only
    /// the fit, summary and figures are redone; one of other analyses is
    /// refused).
    #[arg(long)]
    pub force: bool,
    /// Run even when outcomes.csv is estimated (from the first rows) to
    /// need more space than the output folder's file system has free
    /// (without it, that is refused before the bulk of the analyses).
    #[arg(long)]
    pub no_space_check: bool,
    /// Print the fragility table and every note (default: one line per step).
    #[arg(long, short)]
    pub verbose: bool,
    /// Size a fixed-grid study instead of running it: run a pilot (10
    /// records per level, in a temporary folder) and print, per case, how
    /// many records per level give the median a 90 % band of this
    /// half-width (0.05: ±5 %). Writes nothing.
    #[arg(long, value_name = "HALF_WIDTH")]
    pub precision: Option<f64>,
}

/// Runs `rockfrag run`.
pub fn run(args: RunArgs) -> anyhow::Result<()> {
    let (study, spec_file) = match &args.study {
        Some(path) => (Study::load(path)?, path.display().to_string()),
        None => (Study::shenton_jones(), SHENTON_JONES_ORIGIN.to_string()),
    };
    if let Some(target) = args.precision {
        return super::size::size(&study, target, args.threads.unwrap_or(0));
    }
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
        no_space_check: args.no_space_check,
    };
    let report = pipeline::run(&study, &opts)?;
    let run = &report.run;
    if let Some(note) = rockfrag::threads::cap_note(opts.threads, run.threads) {
        eprintln!("note: {note}");
    }
    let rate = run.analyses_run as f64 / run.wall_seconds.max(1e-9);
    if run.resumed_at_unit > 0 {
        eprintln!("resumed after {} work units", run.resumed_at_unit);
    }
    if rockfrag::study::interrupted() {
        let total = rockfrag::study::unit_count(&study);
        let units = opts.shard.unit_count(total);
        let what = if run.complete {
            "its analyses are all done and saved in outcomes.csv, but the fit, summary and \
             figures were not made"
                .to_string()
        } else {
            format!(
                "{} analyses were saved in {} this time (checkpointed: the run stopped at the end \
                 of a chunk of its {units} work units)",
                run.analyses_run,
                out.display()
            )
        };
        eprintln!(
            "interrupted: {what}; run the same command again to resume where it stopped{}",
            if run.complete {
                " (it keeps the analyses)"
            } else {
                ""
            }
        );
        std::process::exit(130);
    }
    if !run.complete {
        eprintln!(
            "stopped: {} analyses in {:.1} s; run the same command again to resume",
            run.analyses_run, run.wall_seconds
        );
        return Ok(());
    }
    let c = run.counts;
    if let (Some(adaptive), true) = (&report.adaptive, run.already_finished) {
        eprintln!(
            "study {} (adaptive): already finished in {} ({} analyses in {} rounds: {} \
             overturned, {} failed); replayed its rounds from adaptive-index.csv without solving, \
             kept its outcomes.csv and redid what follows it; pass --force to run the analyses \
             again",
            study.name,
            out.display(),
            c.analyses,
            adaptive.rounds,
            c.overturned,
            c.failed
        );
    } else if let Some(adaptive) = &report.adaptive {
        eprintln!(
            "study {} (adaptive): {} analyses ({} overturned, {} failed) in {} rounds; {} run in \
             {:.1} s on {} thread{}; wrote {}",
            study.name,
            c.analyses,
            c.overturned,
            c.failed,
            adaptive.rounds,
            run.analyses_run,
            run.wall_seconds,
            run.threads,
            if run.threads == 1 { "" } else { "s" },
            out.display()
        );
        for case in &adaptive.cases {
            eprintln!(
                "{}",
                rockfrag::study::adaptive::progress_line(adaptive.rounds, case, &adaptive.adaptive)
                    .split_once(": ")
                    .map_or("", |(_, rest)| rest)
            );
        }
    } else if run.already_finished {
        eprintln!(
            "study {}: already finished in {} ({} analyses: {} overturned, {} uplifted, {} failed); \
             kept its outcomes.csv and redid what follows it; pass --force to run the analyses again",
            study.name,
            out.display(),
            c.analyses,
            c.overturned,
            c.uplifted,
            c.failed
        );
    } else {
        eprintln!(
            "study {}{}: {} analyses ({} overturned, {} uplifted, {} failed); {} run in {:.1} s, \
         {:.0} analyses/s on {} thread{}; wrote {}",
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
            run.analyses_run,
            run.wall_seconds,
            rate,
            run.threads,
            if run.threads == 1 { "" } else { "s" },
            out.display()
        );
    }
    if opts.shard != Shard::WHOLE && c.analyses == 0 {
        eprintln!(
            "note: shard {} has no work: the study has {} work units (levels × records), fewer \
             than its {} shards; its folder is complete and `rockfrag merge` takes it",
            opts.shard,
            rockfrag::study::unit_count(&study),
            opts.shard.count
        );
    }
    if let Some(finish) = &report.finish {
        say(finish, &out, args.verbose);
    }
    // The fit and the figures skip failed analyses (and say how many), so
    // they are made before the failures are reported in the exit status.
    if let Some(message) = report.failure() {
        bail!(message);
    }
    Ok(())
}

/// Says what [`pipeline::finish`] made: one line for each step, and a line
/// of bootstrap notes if any, on standard error; `verbose` prints the
/// fragility table and every note on standard output.
pub fn say(finish: &FinishReport, dir: &Path, verbose: bool) {
    if let Some(report) = &finish.fit {
        if verbose {
            print!("{}{}{}", report.table, report.notes(true), report.wrote);
        } else {
            eprint!("{}{}", report.summary(), report.notes(false));
        }
    }
    if let Some(figures) = &finish.figures {
        for note in &figures.notes {
            eprintln!("note: {note}");
        }
        eprintln!(
            "drew {} figures into {}",
            figures.written.len(),
            dir.join("figures").display()
        );
        if let Some(command) = &figures.history_command {
            eprintln!("history: its analysis is solved again by `{command}`");
        }
    }
}
