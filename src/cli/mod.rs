//! Command-line interface: one module per subcommand, each turning raw flags
//! into validated library types once and then calling the library.

mod args;
mod bench;
mod export;
mod fragility;
mod merge;
mod figures;
mod floor;
mod folders;
mod infer;
mod motion;
mod paper;
mod risk;
mod run;
mod simulate;
mod size;
mod stack;

use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::{Parser, Subcommand};

/// Monte Carlo fragility analysis of free-standing rigid blocks under earthquakes.
#[derive(Debug, Parser)]
#[command(name = "rockfrag", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands, in pipeline order.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Generate one synthetic ground motion (CSV `t,acc,vel,disp`, optional SVG plot).
    Motion(motion::MotionArgs),
    /// Solve one block under one record and print the outcome.
    Simulate(Box<simulate::SimulateArgs>),
    /// The absolute motion of a floor of a linear building (its modes) under
    /// a ground record, as a CSV record `t,acc,vel,disp`.
    Floor(floor::FloorArgs),
    /// Run a study spec (default: the paper's study, built in) into
    /// outcomes.csv, summary.md and manifest.json; resumable and shardable.
    Run(run::RunArgs),
    /// Merge the folders of shards 1/N..N/N of a study into one.
    Merge(merge::MergeArgs),
    /// Fit lognormal fragility curves (overturning and any other limit
    /// state) to a study's outcomes.
    Fragility(fragility::FragilityArgs),
    /// Annual rate of each limit state at a site: the fitted fragility
    /// integrated over a hazard curve (OpenQuake CSV or iml,annual_rate).
    Risk(risk::RiskArgs),
    /// The intensity a site felt, inferred from the objects that overturned there.
    Infer(Box<infer::InferArgs>),
    /// A fitted study's curves for OpenQuake (a classical_damage job) or
    /// pelicun (a damage database).
    Export(export::ExportArgs),
    /// Speed against error: the work–precision report (table and figure).
    Bench(bench::BenchArgs),
    /// Draw the publication figures of a study folder (SVG or PNG).
    Figures(figures::FiguresArgs),
    /// Check the paper's Tables 1–3 over K ensembles under each reading of
    /// its section 4 (paper-check.md).
    Paper(paper::PaperArgs),
}

/// Parses the command line. Every flag and argument that takes a value
/// accepts a negative number as its value (`--theta0 -0.1`, `--level -1`),
/// so that a value out of range is refused by its parser, which says what
/// it expects, instead of being taken for an unknown flag `-1`.
pub fn parse() -> Result<Cli, clap::Error> {
    use clap::{CommandFactory, FromArgMatches};
    let matches = negatives_are_values(Cli::command()).try_get_matches()?;
    Cli::from_arg_matches(&matches)
}

fn negatives_are_values(cmd: clap::Command) -> clap::Command {
    cmd.mut_args(|arg| {
        if arg.get_action().takes_values() {
            arg.allow_negative_numbers(true)
        } else {
            arg
        }
    })
    .mut_subcommands(negatives_are_values)
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Motion(args) => motion::run(args),
        Command::Simulate(args) => simulate::run(*args),
        Command::Floor(args) => floor::run(args),
        Command::Run(args) => run::run(args),
        Command::Merge(args) => merge::run(args),
        Command::Fragility(args) => fragility::run(args),
        Command::Risk(args) => risk::run(args),
        Command::Infer(args) => infer::run(*args),
        Command::Export(args) => export::run(args),
        Command::Bench(args) => bench::run(args),
        Command::Figures(args) => figures::run(args),
        Command::Paper(args) => paper::run(args),
    }
}

/// Checks between flags that clap's parsers, which see one flag at a time,
/// cannot make; an error here is a usage error like theirs (status 2).
pub fn check(cli: &Cli) -> Result<(), clap::Error> {
    match &cli.command {
        Command::Simulate(args) => args.check(),
        _ => Ok(()),
    }
}

/// Prints a clap error as one clear line (argument and accepted values) and
/// exits with status 2; help and version requests print normally and exit 0.
pub fn exit_on_parse_error(err: clap::Error) -> ! {
    match err.kind() {
        ErrorKind::DisplayHelp
        | ErrorKind::DisplayVersion
        | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => err.exit(),
        _ => {}
    }
    eprintln!("{}", one_line(&err));
    std::process::exit(2);
}

fn one_line(err: &clap::Error) -> String {
    let text = |k: ContextKind| match err.get(k) {
        Some(ContextValue::String(s)) => Some(s.clone()),
        Some(ContextValue::Strings(v)) => Some(v.join(", ")),
        _ => None,
    };
    let arg = text(ContextKind::InvalidArg);
    let value = text(ContextKind::InvalidValue);
    let valid = text(ContextKind::ValidValue).or_else(|| text(ContextKind::ValidSubcommand));
    let mut line = match (&arg, &value) {
        (Some(a), Some(v)) => format!("error: invalid value '{v}' for {a}"),
        (Some(a), None) => match err.kind() {
            ErrorKind::MissingRequiredArgument => format!(
                "error: missing required argument {}",
                a.replace('|', " or ")
            ),
            ErrorKind::UnknownArgument => format!("error: unknown argument {a}"),
            ErrorKind::ArgumentConflict => match text(ContextKind::PriorArg) {
                Some(prior) => format!("error: {a} cannot be used with {prior}"),
                None => format!("error: {a} conflicts with another argument"),
            },
            _ => format!("error: problem with argument {a}"),
        },
        _ => {
            // Fall back to clap's own first line.
            let rendered = err.render().to_string();
            rendered
                .lines()
                .next()
                .unwrap_or("error: invalid arguments")
                .to_string()
        }
    };
    if let Some(v) = valid.filter(|_| !matches!(err.kind(), ErrorKind::InvalidSubcommand)) {
        line.push_str(&format!(" (accepted: {v})"));
    }
    if let Some(reason) = std::error::Error::source(err).filter(|_| value.is_some()) {
        // the standard library's words for a count or seed that is not one
        let reason = match reason.to_string().as_str() {
            "invalid digit found in string" | "cannot parse integer from empty string" => {
                "expected a whole number ≥ 0".to_string()
            }
            "number too large to fit in target type" => {
                "expected a smaller whole number".to_string()
            }
            other => other.to_string(),
        };
        line.push_str(&format!(": {reason}"));
    }
    let suggested =
        text(ContextKind::SuggestedSubcommand).or_else(|| text(ContextKind::SuggestedArg));
    if let Some(s) = suggested {
        line.push_str(&format!(" (did you mean '{s}'?)"));
    }
    line.push_str(&format!(
        "; see '{} --help'",
        command_path(std::env::args().skip(1))
    ));
    line
}

/// `rockfrag` followed by the subcommands named on the command line `args`
/// (`rockfrag export openquake`), so an error points to the help of the
/// command it is about.
fn command_path(args: impl Iterator<Item = String>) -> String {
    use clap::CommandFactory;
    let mut cmd = Cli::command();
    let mut path = String::from("rockfrag");
    for arg in args {
        if arg.starts_with('-') {
            continue;
        }
        let Some(sub) = cmd.find_subcommand(&arg).cloned() else {
            break;
        };
        path.push(' ');
        path.push_str(sub.get_name());
        cmd = sub;
    }
    path
}
