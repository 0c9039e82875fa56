//! `rockfrag fragility`: lognormal overturning fragility curves from a study's
//! `outcomes.csv`, with bootstrap bands and an OpenQuake export.

use std::io::Write;
use std::path::PathBuf;

use anyhow::Context;
use clap::ValueEnum;
use rockfrag::detmath as dm;
use rockfrag::fragility::{
    BetaModel, BootstrapUnit, CaseFit, FragilityOptions, IntensityMeasure, Interval, LimitState,
    fit_cases, read_outcomes_for, write_outputs,
};
use rockfrag::outcomes_csv::Pooled;
use rockfrag::spec::Study;
use rockfrag::study::Manifest;

/// Intensity measure, as a CLI value.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ImArg {
    /// Peak ground acceleration, g.
    Pga,
    /// Peak ground velocity, m/s (needs a `pgv` column).
    Pgv,
    /// PGA/(g tan θc) = PGA·H/B, dimensionless.
    PgaOverTan,
}

/// Bootstrap resampling unit, as a CLI value.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ResampleArg {
    /// Whole records, each bringing its analyses at every stripe.
    Records,
    /// Analyses, independently within each stripe.
    Analyses,
}

/// Flags of `rockfrag fragility`.
#[derive(Debug, clap::Args)]
pub struct FragilityArgs {
    /// Study directory holding `outcomes.csv`.
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// Intensity measure the curves are fitted against.
    #[arg(long, value_enum, default_value_t = ImArg::Pga)]
    pub im: ImArg,
    /// Bootstrap replicates for the 90 % bands; 0 skips the bootstrap.
    #[arg(long, value_name = "N", default_value_t = FragilityOptions::default().bootstrap)]
    pub bootstrap: usize,
    /// Bootstrap seed: the same seed gives the same bands on any machine.
    #[arg(long, value_name = "S", default_value_t = FragilityOptions::default().seed)]
    pub seed: u64,
    /// What the bootstrap resamples: whole records (shared across stripes),
    /// or analyses within each stripe (only for independent analyses).
    #[arg(long, value_enum, default_value_t = ResampleArg::Records)]
    pub resample: ResampleArg,
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
    #[arg(long, value_name = "PARAMS", value_delimiter = ',', value_enum)]
    pub pool: Vec<PoolArg>,
    /// Print every case's bootstrap note (default: one summary line).
    #[arg(long, short)]
    pub verbose: bool,
    /// Fit a folder holding one shard of a study (only its part of the
    /// records and levels); without it that is refused.
    #[arg(long)]
    pub partial: bool,
}

/// A case parameter that `--pool` pools over.
#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
pub enum PoolArg {
    /// Base width 2B.
    Width,
    /// Aspect ratio H/B.
    Aspect,
    /// Coefficient of restitution e.
    Restitution,
    /// Friction coefficients μs, μk (Coulomb cases only).
    Friction,
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
        let manifest = self.dir.join("manifest.json");
        let study = if manifest.exists() {
            let m = Manifest::read(&manifest)?;
            Some(Study::from_toml_unchecked(&m.spec_toml, &manifest)?)
        } else {
            None
        };
        let mut pool = study.as_ref().map_or(Pooled::default(), Study::pooled);
        for p in &self.pool {
            match p {
                PoolArg::Width => pool.width = true,
                PoolArg::Aspect => pool.aspect = true,
                PoolArg::Restitution => pool.restitution = true,
                PoolArg::Friction => pool.friction = true,
            }
        }
        let limit_state = if self.limit_states.is_empty() {
            study
                .as_ref()
                .and_then(|s| s.fragility.as_ref())
                .map_or(Vec::new(), |f| f.limit_state.clone())
        } else {
            self.limit_states.clone()
        };
        Ok(FragilityOptions {
            im: match self.im {
                ImArg::Pga => IntensityMeasure::Pga,
                ImArg::Pgv => IntensityMeasure::Pgv,
                ImArg::PgaOverTan => IntensityMeasure::PgaOverTan,
            },
            bootstrap: self.bootstrap,
            unit: match self.resample {
                ResampleArg::Records => BootstrapUnit::Records,
                ResampleArg::Analyses => BootstrapUnit::Analyses,
            },
            seed: self.seed,
            limit_state,
            pool,
            ..FragilityOptions::default()
        })
    }
}

/// Runs `rockfrag fragility`.
pub fn run(args: FragilityArgs) -> anyhow::Result<()> {
    let manifest = args.dir.join(rockfrag::study::files::MANIFEST);
    if manifest.exists() && !args.partial {
        let m = rockfrag::study::Manifest::read(&manifest)?;
        if m.shard != rockfrag::study::Shard::WHOLE {
            anyhow::bail!(
                "{}: holds shard {} of study '{}', a part of its analyses: merge the shards \
                 (rockfrag merge) and fit the merged folder, or pass --partial to fit this part",
                args.dir.display(),
                m.shard,
                m.study
            );
        }
    }
    let options = args.options()?;
    let out = args.out.as_ref().unwrap_or(&args.dir);
    let report = fit_and_write(&args.dir, out, &options)?;
    let mut text = report.table.clone();
    text.push_str(&report.notes(args.verbose));
    text.push_str(&report.wrote);
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(text.as_bytes()) {
        // A closed pipe (`rockfrag fragility … | head`) is not an error.
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other.context("writing to standard output"),
    }
}

/// What a fit wrote and has to say.
pub struct FitReport {
    /// The table of cases (header and one row per case and limit state).
    pub table: String,
    /// One note per case whose bootstrap had replicates it could not fit.
    pub case_notes: Vec<String>,
    /// Those notes in one line, or empty.
    pub bootstrap_line: String,
    /// A note on failed analyses skipped, or empty.
    pub failed_note: String,
    /// `wrote …` (one line).
    pub wrote: String,
    /// Curves fitted, and curves asked for.
    pub fitted: usize,
    /// Curves asked for (cases × limit states).
    pub curves: usize,
    /// The fragility.csv written.
    pub fragility_csv: PathBuf,
}

impl FitReport {
    /// The notes: every case's (`verbose`) or their summary line, then the
    /// note on failed analyses.
    pub fn notes(&self, verbose: bool) -> String {
        let mut text = if verbose {
            self.case_notes.concat()
        } else {
            self.bootstrap_line.clone()
        };
        text.push_str(&self.failed_note);
        text
    }

    /// One line: curves fitted and where they went.
    pub fn summary(&self) -> String {
        let see = if self.fitted < self.curves {
            " (its status column says why a curve was not fitted)"
        } else {
            ""
        };
        format!(
            "fragility: {} of {} curves fitted; wrote {}{see}, fragility_curves.csv, fragility_bootstrap.csv, fragility.xml\n",
            self.fitted,
            self.curves,
            self.fragility_csv.display()
        )
    }
}

/// Fits the curves of `dir/outcomes.csv`, writes the fragility files into
/// `out` and returns what to tell the user (also used by `run` and `merge`
/// when the spec has a `[fragility]` table).
pub fn fit_and_write(
    dir: &std::path::Path,
    out: &std::path::Path,
    options: &FragilityOptions,
) -> anyhow::Result<FitReport> {
    let input = dir.join("outcomes.csv");
    let outcomes = read_outcomes_for(&input, options)?;
    if outcomes.cases.is_empty() {
        anyhow::bail!("{}: no analyses to fit", input.display());
    }
    let fits = fit_cases(&outcomes, options)?;
    let paths = write_outputs(out, &fits)?;

    let failed: usize =
        fits.iter().map(|f| f.n_failed).sum::<usize>() + outcomes.failed_unattributed;
    let failed_note = if failed > 0 {
        format!("note: {failed} failed analyses skipped (error or status not ok in outcomes.csv)\n")
    } else {
        String::new()
    };
    Ok(FitReport {
        table: table(&fits, options),
        case_notes: case_notes(&fits),
        bootstrap_line: bootstrap_line(&fits, &paths.fragility),
        failed_note,
        wrote: format!(
            "wrote {}, {}, {}, {}\n",
            paths.fragility.display(),
            paths.curves.display(),
            paths.bootstrap.display(),
            paths.nrml.display()
        ),
        fitted: fits.iter().filter(|f| f.fit.is_ok()).count(),
        curves: fits.len(),
        fragility_csv: paths.fragility.clone(),
    })
}

/// One note per curve whose bootstrap had replicates that could not be
/// fitted.
fn case_notes(fits: &[CaseFit]) -> Vec<String> {
    fits.iter()
        .filter_map(|f| {
            let b = f.bootstrap.as_ref().filter(|b| b.unfit_total() > 0)?;
            let reasons: Vec<String> = b.unfit.iter().map(|(k, n)| format!("{k} {n}")).collect();
            Some(format!(
                "note: {} {}: {} of {} bootstrap replicates could not be fitted ({}); \
                 the intervals come from the other {}\n",
                f.key,
                f.limit_state,
                b.unfit_total(),
                b.replicates,
                reasons.join(", "),
                b.fitted
            ))
        })
        .collect()
}

/// The bootstrap notes in one line, by reason: `bootstrap: 16 cases had
/// separated replicates (max 12 of 1000); see fragility.csv`; empty if none.
fn bootstrap_line(fits: &[CaseFit], csv: &std::path::Path) -> String {
    // reason -> (curves with it, most replicates of one curve, its replicates)
    let mut by_reason: std::collections::BTreeMap<&str, (usize, usize, usize)> =
        std::collections::BTreeMap::new();
    for b in fits.iter().filter_map(|f| f.bootstrap.as_ref()) {
        for (reason, &n) in &b.unfit {
            let e = by_reason.entry(reason).or_insert((0, 0, b.replicates));
            e.0 += 1;
            if n > e.1 {
                (e.1, e.2) = (n, b.replicates);
            }
        }
    }
    if by_reason.is_empty() {
        return String::new();
    }
    let parts: Vec<String> = by_reason
        .iter()
        .map(|(reason, (curves, max, of))| {
            let what = if *curves == 1 { "curve" } else { "curves" };
            format!("{curves} {what} had {reason} replicates (max {max} of {of})")
        })
        .collect();
    format!(
        "bootstrap: {}; the intervals come from the others (boot_unfit in {}; --verbose lists them)\n",
        parts.join(", "),
        csv.display()
    )
}

fn table(fits: &[CaseFit], options: &FragilityOptions) -> String {
    // The band's heading only when there is a band (a bootstrap).
    let pct = match options.bootstrap {
        0 => String::new(),
        _ => format!(" [{}%]", (options.confidence * 100.0).round()),
    };
    let unit = match options.im.unit() {
        "1" => String::new(),
        u => format!(" ({u})"),
    };
    let header: Vec<String> = [
        "case",
        "limit state",
        "analyses",
        "exceeded",
        "stripes",
        "records",
        &format!("median{unit}{pct}"),
        &format!("beta{pct}"),
        "status",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let mut rows = vec![header];
    for f in fits {
        let band = |i: Option<Interval>| {
            i.map_or(String::new(), |i| {
                format!(" [{}, {}]", sig(i.lo), sig(i.hi))
            })
        };
        let boot = f.bootstrap.as_ref();
        let (median, beta, status) = match &f.fit {
            Ok(fit) => (
                format!("{}{}", sig(fit.median()), band(boot.and_then(|b| b.median))),
                format!("{}{}", sig(fit.beta()), band(boot.and_then(|b| b.beta))),
                match f.beta_model {
                    BetaModel::Separate => "ok".to_string(),
                    BetaModel::Common => "ok (β common to the case's limit states)".to_string(),
                },
            ),
            Err(reason) => ("-".into(), "-".into(), format!("not fitted: {reason}")),
        };
        rows.push(vec![
            f.key.to_string(),
            f.limit_state.clone(),
            f.n_analyses.to_string(),
            f.n_exceeded.to_string(),
            f.n_stripes.to_string(),
            f.n_records.to_string(),
            median,
            beta,
            status,
        ]);
    }
    super::table::aligned(&rows)
}

/// Three significant digits, without exponent for ordinary magnitudes.
fn sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return x.to_string();
    }
    let digits = (2 - dm::log10(x.abs()).floor() as i32).clamp(0, 12) as usize;
    format!("{x:.digits$}")
}
