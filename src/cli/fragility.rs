//! `rockfrag fragility`: lognormal fragility curves (overturning and any
//! other limit state) from a study's `outcomes.csv`, with bootstrap bands
//! and an OpenQuake export.

use std::io::Write;
use std::path::PathBuf;

use super::args::choice;
use anyhow::Context;
use rockfrag::case::Field;
use rockfrag::fragility::{BootstrapUnit, FragilityOptions, LimitState};
use rockfrag::im::{Im, ImPair};

/// Flags of `rockfrag fragility`.
#[derive(Debug, clap::Args)]
pub struct FragilityArgs {
    /// Study directory holding `outcomes.csv`.
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// Intensity measure the curves are fitted against: PGA in g, PGV in
    /// m/s, PGA/(g tan θc) = PGA·H/B, dimensionless, the floor's peak
    /// acceleration PFA in g or velocity PFV in m/s (a study with
    /// `[support] floor`; docs/floor.md), a record pair's RotD50 PGA or PGV
    /// (docs/orientation.md), the 5 %-damped spectral acceleration
    /// `sa(T)` (T in s) or its geometric mean `sa-avg(T1,T2)` in g, or
    /// `pgv/pga` in s (each also `-floor`, `-rotd50`: measured on the
    /// records again, outcomes.csv untouched). Repeat the flag to compare
    /// IMs: each is fitted, ranked by β with a sufficiency check in the
    /// summary's `## Intensity measures`, and the first is written.
    /// Two IMs joined by a comma (`pga,pgv`; a comma inside a name's
    /// parentheses, as in `sa-avg(0.5,2)`, does not split it) fit a
    /// fragility surface P(LS | IM1, IM2) beside the curves against IM1,
    /// into fragility_surface.csv (docs/surface.md); a pair goes first
    /// [default: the study's `[fragility] im`, else pga, or pga-rotd50 for
    /// a study of record pairs]
    #[arg(long, value_name = "IM", value_parser = im_name)]
    pub im: Vec<ImChoice>,
    /// Bootstrap replicates for the 90 % bands; 0 skips the bootstrap
    /// [default: the study's own `[fragility] bootstrap`, else 1000].
    #[arg(long, value_name = "N", value_parser = bootstrap_replicates)]
    pub bootstrap: Option<usize>,
    /// Bootstrap seed: the same seed gives the same bands on any machine.
    #[arg(long, value_name = "S", default_value_t = FragilityOptions::default().seed)]
    pub seed: u64,
    /// What the bootstrap resamples: whole records (shared across stripes),
    /// or analyses within each stripe (only for independent analyses).
    #[arg(long, value_parser = choice::<BootstrapUnit>(BootstrapUnit::names()), default_value_t = BootstrapUnit::default())]
    pub resample: BootstrapUnit,
    /// Output directory for fragility.csv, fragility_curves.csv,
    /// fragility_bootstrap.csv and
    /// fragility.xml [default: DIR].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// A limit state, in order of increasing severity (repeat the flag):
    /// `NAME=MEASURE>THRESHOLD` for a numeric column of outcomes.csv
    /// (e.g. `slides-5cm=slip_max>0.05`), `NAME=MEASURE` for a yes/no one
    /// (e.g. `overturning=overturned`). [default: the study's
    /// `[[fragility.limit_state]]` tables from DIR/manifest.json, else
    /// overturning alone]
    #[arg(long = "limit-state", value_name = "NAME=MEASURE[>X]", value_parser = parse_limit_state)]
    pub limit_states: Vec<LimitState>,
    /// Case parameters to pool into one curve, comma-separated: `width`,
    /// `aspect`, `restitution`, `friction`. Those the study draws per
    /// analysis (its `[uncertainty]`, read from DIR/manifest.json) are
    /// always pooled.
    #[arg(long, value_name = "PARAMS", value_delimiter = ',', value_parser = choice::<Field>(Field::ALL.iter().map(|f| f.name()).collect()))]
    pub pool: Vec<Field>,
    /// Print every case's bootstrap note (default: one summary line).
    #[arg(long, short)]
    pub verbose: bool,
    /// Fit a folder holding one shard of a study (only its part of the
    /// records and levels); without it that is refused.
    #[arg(long)]
    pub partial: bool,
}

/// A number of bootstrap replicates, at most
/// [`rockfrag::fragility::MAX_BOOTSTRAP`].
fn bootstrap_replicates(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if n <= rockfrag::fragility::MAX_BOOTSTRAP => Ok(n),
        _ => Err(format!(
            "expected {}",
            rockfrag::fragility::bootstrap_limit()
        )),
    }
}

/// What one `--im` names: an IM, or the two IMs of a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ImChoice {
    /// One IM.
    One(Im),
    /// A fragility surface's two IMs.
    Pair(ImPair),
}

impl ImChoice {
    /// The IM the curves are fitted against: the pair's first.
    pub fn first(self) -> Im {
        match self {
            ImChoice::One(im) => im,
            ImChoice::Pair(p) => p.first(),
        }
    }
}

/// An intensity measure's name ([`Im`]), or two joined by a comma
/// ([`ImPair`]).
fn im_name(text: &str) -> Result<ImChoice, String> {
    match text.parse::<Im>() {
        Ok(im) => Ok(ImChoice::One(im)),
        Err(e) => match ImPair::parse(text) {
            Some(pair) => pair
                .map(ImChoice::Pair)
                .map_err(|e| format!("expected {e}")),
            None => Err(format!(
                "expected {e}, or two joined by a comma for a fragility surface (pga,pgv)"
            )),
        },
    }
}

/// Parses `NAME=MEASURE>THRESHOLD` or `NAME=MEASURE`.
fn parse_limit_state(text: &str) -> Result<LimitState, String> {
    let (name, rest) = text.split_once('=').ok_or_else(|| {
        format!("{text:?}: expected NAME=MEASURE>THRESHOLD (e.g. slides-5cm=slip_max>0.05) or NAME=MEASURE")
    })?;
    let (measure, exceeds) = match rest.split_once('>') {
        Some((m, x)) => {
            let x: f64 = x
                .trim()
                .parse()
                .map_err(|_| format!("{text:?}: threshold {x:?} is not a number"))?;
            (m, Some(x))
        }
        None => (rest, None),
    };
    Ok(LimitState {
        name: name.trim().to_string(),
        measure: measure.trim().to_string(),
        exceeds,
    })
}

impl FragilityArgs {
    /// The fit's options: the flags, with the limit states and pooled
    /// parameters of the study recorded in `DIR/manifest.json` when there
    /// is one (flags take precedence; pooled parameters add up).
    fn options(&self) -> anyhow::Result<FragilityOptions> {
        if let Some(later) = self.im.iter().skip(1).find_map(|c| match c {
            ImChoice::Pair(p) => Some(p),
            ImChoice::One(_) => None,
        }) {
            anyhow::bail!(
                "--im {later}: a surface's pair of IMs goes first (--im {later} --im …), and \
                 there is one surface per fit"
            );
        }
        let given = FragilityOptions {
            im: self.im.first().map(|c| c.first()),
            surface: match self.im.first() {
                Some(ImChoice::Pair(p)) => Some(p.second()),
                _ => None,
            },
            bootstrap: match self.bootstrap {
                Some(n) => n,
                None => rockfrag::pipeline::study_bootstrap(&self.dir)?,
            },
            unit: self.resample,
            seed: self.seed,
            limit_state: self.limit_states.clone(),
            pool: self.pool.clone(),
            ..FragilityOptions::default()
        };
        Ok(rockfrag::pipeline::folder_fit_options(&self.dir, &given)?)
    }
}

/// Runs `rockfrag fragility`.
pub fn run(args: FragilityArgs) -> anyhow::Result<()> {
    rockfrag::study::require_finished(&args.dir)?;
    super::folders::refuse_shard(&args.dir, args.partial, "fit")?;
    let options = args.options()?;
    let out = args.out.as_ref().unwrap_or(&args.dir);
    if let Some(warning) = rockfrag::pipeline::fewer_replicates(out, options.bootstrap) {
        eprintln!("note: {warning}");
    }
    let report = rockfrag::pipeline::refit(&args.dir, out, &options)?;
    // The table is the data (stdout); the notes and the files written are
    // status (stderr), as for every subcommand.
    eprint!("{}{}", report.notes(args.verbose), report.wrote);
    let mut table = report.table.clone();
    let mut ims: Vec<Im> = Vec::new();
    for im in args.im.iter().map(|c| c.first()) {
        if !ims.contains(&im) {
            ims.push(im);
        }
    }
    if ims.len() > 1 {
        let fits = rockfrag::study::compare_ims(&args.dir, &options, &ims)?;
        let section = rockfrag::study::ims_section(&fits);
        let summary = args.dir.join("summary.md");
        if rockfrag::pipeline::same_folder(&args.dir, out) && summary.exists() {
            rockfrag::io_util::replace_section(
                &summary,
                rockfrag::study::IMS_HEADING,
                &section,
                &[rockfrag::study::COUNTS_HEADING],
            )
            .with_context(|| format!("updating {}", summary.display()))?;
            eprintln!(
                "updated {} ({})",
                summary.display(),
                rockfrag::study::IMS_HEADING
            );
        }
        table.push('\n');
        table.push_str(&section);
    }
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(table.as_bytes()) {
        // A closed pipe (`rockfrag fragility … | head`) is not an error.
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other.context("writing to standard output"),
    }
}
