//! `rockfrag figures`: the publication figures of a study folder.

use std::path::PathBuf;

use super::args::positive;
use clap::ValueEnum;
use rockfrag::figures::{
    CompareFigure, FigureOptions, Format, HistoryChoice, study_figures, study_of_folder,
};

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
    /// and manifest.json; once `rockfrag risk` has run, risk.csv and
    /// risk_hazard.csv for the risk figure); default: the built-in study's
    /// folder.
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
    /// Instead of DIR's figures, one figure `compare.svg` (or `.png`) of the
    /// fragility curves against ground PGA of DIR and each --compare folder
    /// (e.g. the same block on the ground and on a floor); repeat for more.
    #[arg(long, value_name = "DIR")]
    pub compare: Vec<PathBuf>,
    /// The history figure's case: its id (the `case_id` of fragility.csv,
    /// e.g. `a4_w0p5_e0_inf`) [default: the first case with a run that
    /// rocked without overturning].
    #[arg(long, value_name = "CASE_ID")]
    pub case: Option<String>,
    /// The history figure's stripe: an intensity level of the study, in its
    /// unit (g for PGA) [default: the stripe nearest the case's fitted median].
    #[arg(long, value_name = "X", value_parser = positive)]
    pub level: Option<f64>,
    /// The history figure's record: its index in the study's ensemble (the
    /// `record` column of outcomes.csv) [default: at the case and stripe,
    /// the analysis with the largest θmax/θc that did not overturn].
    #[arg(long, value_name = "N")]
    pub record: Option<u64>,
    /// Draw a folder holding one shard of a study (only its part of the
    /// records and levels, said on the console); without it that is refused.
    #[arg(long)]
    pub partial: bool,
}

/// Runs `rockfrag figures`.
pub fn run(args: FiguresArgs) -> anyhow::Result<()> {
    if !args.compare.is_empty() {
        return compare(&args);
    }
    refuse_inference(&args.dir)?;
    rockfrag::study::require_finished(&args.dir)?;
    super::folders::refuse_shard(&args.dir, args.partial, "draw")?;
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
    let asked = args.case.is_some() || args.level.is_some() || args.record.is_some();
    if asked {
        options.history = HistoryChoice::At {
            case: args.case.clone(),
            level: args.level,
            record: args.record,
        };
    }
    let out = args.out.unwrap_or_else(|| args.dir.join("figures"));
    let report = match &study {
        Some(study) => rockfrag::pipeline::figures(study, &args.dir, &out, &options)?,
        None => study_figures(&args.dir, &out, &options)?,
    };
    for path in &report.written {
        println!("{}", path.display());
    }
    if let Some(command) = &report.history_command {
        eprintln!("history: its analysis is solved again by `{command}`");
    }
    if args.partial {
        eprintln!(
            "note: {} holds one shard of its study: these figures show only that part of its \
             records and levels, not the study",
            args.dir.display()
        );
    }
    // A history asked for by --case/--level/--record that cannot be drawn
    // is an error, not a note: the user named it.
    let mut failed = None;
    for note in &report.notes {
        match note.strip_prefix("history: skipped, ") {
            Some(why) if asked => failed = Some(why.to_string()),
            _ => eprintln!("note: {note}"),
        }
    }
    if let Some(why) = failed {
        anyhow::bail!("figures --case/--level/--record: {why}");
    }
    Ok(())
}

/// Refuses the folder of a `rockfrag infer` (which has no outcomes.csv),
/// naming the command that draws its figure in PNG: the same `infer`
/// with `--format png`, which reuses the simulations kept in the folder.
fn refuse_inference(dir: &std::path::Path) -> anyhow::Result<()> {
    use rockfrag::infer::output::INFERENCE;
    let json = dir.join(INFERENCE);
    if dir.join(rockfrag::study::files::OUTCOMES).exists() || !json.is_file() {
        return Ok(());
    }
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json)?)?;
    let text = |k: &str| v.get(k).and_then(|x| x.as_str()).unwrap_or("?").to_string();
    let prior = text("prior");
    // an inference over two IMs names both (`--im pga,pgv`)
    let im = match v
        .get("two_im")
        .and_then(|t| t.get("im2"))
        .and_then(|x| x.as_str())
    {
        Some(im2) => format!("{},{im2}", text("im")),
        None => text("im"),
    };
    anyhow::bail!(
        "{}: holds an inference (`rockfrag infer`), not a study run: its figure is \
         figures/inference.svg there; for a PNG, run the inference again with --format png \
         (it reuses the simulations kept in the folder): rockfrag infer {} --study {} --out {}{} \
         --im {} --format png",
        dir.display(),
        text("observations"),
        text("spec"),
        dir.display(),
        if prior == "log-uniform" {
            String::new()
        } else {
            format!(" --prior {prior}")
        },
        im
    )
}

/// `rockfrag figures DIR --compare DIR2 …`: one figure of the folders'
/// curves, each labelled by its study's name and support.
fn compare(args: &FiguresArgs) -> anyhow::Result<()> {
    let mut folders = Vec::new();
    for dir in std::iter::once(&args.dir).chain(&args.compare) {
        let label = match study_of_folder(dir)? {
            Some(study) if study.floor.is_ground() => format!("{} (ground)", study.name),
            Some(study) => {
                let modes: Vec<String> = study
                    .floor
                    .modes
                    .iter()
                    .map(|m| format!("T = {} s, Γφ = {}", m.period, m.participation))
                    .collect();
                format!("{} (floor: {})", study.name, modes.join("; "))
            }
            None => dir.display().to_string(),
        };
        folders.push((label, dir.clone()));
    }
    let figure = CompareFigure::from_folders("Fragility against ground PGA", &folders)?;
    let ext = match args.format {
        FormatArg::Svg => "svg",
        FormatArg::Png => "png",
    };
    let out = args.out.clone().unwrap_or_else(|| args.dir.join("figures"));
    rockfrag::io_util::create_folder(&out)?;
    let path = out.join(format!("compare.{ext}"));
    figure.save(&path)?;
    println!("{}", path.display());
    Ok(())
}
