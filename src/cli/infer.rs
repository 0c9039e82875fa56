//! `rockfrag infer`: the intensity a site felt, inferred from a survey of
//! the objects that overturned there.

use std::io::Write;
use std::path::PathBuf;

use anyhow::Context;
use rockfrag::im::ImPair;
use rockfrag::infer::{self, Im, InferOptions, PriorChoice, Survey, output};
use rockfrag::spec::Study;

use super::args::threads;
use super::figures::FormatArg;
use rockfrag::figures::Format;

/// Flags of `rockfrag infer`.
#[derive(Debug, clap::Args)]
pub struct InferArgs {
    /// The survey: CSV `name,width,aspect,count,overturned` (optional
    /// `restitution,mu_s,mu_k,slid`), one row per kind of object.
    #[arg(value_name = "OBSERVATIONS.csv")]
    pub observations: PathBuf,
    /// The study spec: records or ground-motion model, intensity levels,
    /// solver, [uncertainty] of the objects' properties, [infer] draws.
    #[arg(long, value_name = "SPEC.toml")]
    pub study: PathBuf,
    /// Output folder (default: results/<survey file stem>/). Rerunning into
    /// it resumes or reuses the simulations.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Prior of the IM: log-uniform over the levels, or the density of the
    /// IM given shaking above the lowest level from a hazard curve
    /// (OpenQuake CSV or iml,annual_rate; site K of an OpenQuake file).
    #[arg(long, value_name = "log-uniform|hazard=FILE[,site=K]", default_value = "log-uniform",
          value_parser = prior)]
    pub prior: PriorChoice,
    /// IM to infer [default: the levels' IM; pga for scale factors]; two
    /// joined by a comma (pga,pgv) also give their joint posterior
    /// (posterior_2d.csv, figures/inference_2d.svg).
    #[arg(long, value_name = "pga|pgv|IM1,IM2", value_parser = im)]
    pub im: Option<(Im, Option<Im>)>,
    /// Format of figures/inference.svg (or .png).
    #[arg(long, value_enum, default_value_t = FormatArg::Svg)]
    pub format: FormatArg,
    /// Worker threads (default: one per core). Results do not depend on it.
    #[arg(long, value_name = "N", value_parser = threads)]
    pub threads: Option<usize>,
    /// Stop as if killed after this many levels (for testing resumption).
    #[arg(long, value_name = "LEVELS", hide = true)]
    pub stop_after_levels: Option<usize>,
}

fn prior(s: &str) -> Result<PriorChoice, String> {
    s.parse()
        .map_err(|_| "expected log-uniform, hazard=FILE or hazard=FILE,site=K".to_string())
}

/// One IM (pga or pgv), or two joined by a comma (the joint posterior's).
fn im(s: &str) -> Result<(Im, Option<Im>), String> {
    match ImPair::parse(s) {
        Some(pair) => pair
            .and_then(infer::pair::inferable_pair)
            .map(|p| (p.first(), Some(p.second())))
            .map_err(|e| format!("expected {e}")),
        None => s
            .parse::<Im>()
            .ok()
            .and_then(|im| infer::inferable(im).ok())
            .map(|im| (im, None))
            .ok_or_else(|| {
                "expected pga or pgv, or two IMs joined by a comma for their joint posterior \
                 (pga,pgv)"
                    .to_string()
            }),
    }
}

/// Runs `rockfrag infer`.
pub fn run(args: InferArgs) -> anyhow::Result<()> {
    let study = Study::load(&args.study)?;
    let survey = Survey::read(&args.observations)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| infer::default_out(&args.observations));
    let opts = InferOptions {
        prior: args.prior.clone(),
        im: args.im.map(|i| i.0),
        second: args.im.and_then(|i| i.1),
        threads: args.threads.unwrap_or(0),
        progress: true,
        stop_after_levels: args.stop_after_levels,
        figure: Some(match args.format {
            FormatArg::Svg => Format::Svg,
            FormatArg::Png => Format::Png,
        }),
        ..InferOptions::new(&out, &args.study)
    };
    let report = infer::run(&study, &survey, &opts)?;
    if let Some(note) = rockfrag::threads::cap_note(opts.threads, report.threads) {
        eprintln!("note: {note}");
    }
    if report.resumed_levels > 0 {
        eprintln!(
            "reused the simulations of {} level(s) in {}",
            report.resumed_levels,
            out.join("simulations.csv").display()
        );
    }
    let Some(inference) = &report.inference else {
        eprintln!(
            "stopped: {} analyses in {:.1} s; run the same command again to resume",
            report.analyses_run, report.wall_seconds
        );
        return Ok(());
    };
    let draws: Vec<String> = survey
        .kinds
        .iter()
        .zip(&report.draws)
        .map(|(k, d)| format!("{} {d}", k.name))
        .collect();
    eprintln!(
        "infer {} with study {}: {} kinds × {} records × {} levels (draws: {}), {} analyses \
         ({} run now, {} failed) in {:.1} s on {} thread{}",
        args.observations.display(),
        study.name,
        survey.kinds.len(),
        study.records(),
        study.intensity.levels().len(),
        draws.join(", "),
        report.analyses,
        report.analyses_run,
        report.failed,
        report.wall_seconds,
        report.threads,
        if report.threads == 1 { "" } else { "s" }
    );
    let mut text = output::console(inference);
    if let Some(pair) = &report.pair {
        text.push_str(&infer::pair_output::console(inference, pair));
    }
    text.push_str(&format!(
        "wrote {}\n",
        report
            .written
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    ));
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(text.as_bytes()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other.context("writing to standard output"),
    }
}
