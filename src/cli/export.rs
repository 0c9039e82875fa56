//! `rockfrag export`: a fitted study's curves for OpenQuake or pelicun.

use std::path::PathBuf;

use rockfrag::export::{export_openquake, export_pelicun};
use rockfrag::figures::study_of_folder;

/// Flags of `rockfrag export`.
#[derive(Debug, clap::Args)]
pub struct ExportArgs {
    /// Which tool.
    #[command(subcommand)]
    pub to: ExportTo,
}

/// The tools rockfrag's curves are exported to.
#[derive(Debug, clap::Subcommand)]
pub enum ExportTo {
    /// A runnable OpenQuake classical_damage job (job.ini, exposure.xml,
    /// fragility.xml, a one-site hazard.csv resampled for OpenQuake's
    /// quadrature, expected.csv with rockfrag's rates, README.md).
    Openquake(OpenQuakeArgs),
    /// A pelicun damage database (NAME.csv and NAME.json), one component
    /// per case fitted for every limit state.
    Pelicun(PelicunArgs),
}

/// Flags of `rockfrag export openquake`.
#[derive(Debug, clap::Args)]
pub struct OpenQuakeArgs {
    /// Fitted study folder (fragility.csv and fragility.xml).
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// Hazard curve for the fit's IM: OpenQuake's hazard-curve CSV or a plain
    /// iml,annual_rate file in the fit's unit (as `rockfrag risk` reads it).
    #[arg(long, value_name = "FILE")]
    pub hazard: PathBuf,
    /// Site of an OpenQuake file: its 0-based data row [default: 0].
    #[arg(long, value_name = "K")]
    pub site: Option<usize>,
    /// The job folder to write (created if missing).
    #[arg(long, value_name = "JOBDIR")]
    pub out: PathBuf,
}

/// Flags of `rockfrag export pelicun`.
#[derive(Debug, clap::Args)]
pub struct PelicunArgs {
    /// Fitted study folder (fragility.csv; manifest.json for the limit
    /// states' descriptions).
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// The folder to write NAME.csv and NAME.json into (created if missing).
    #[arg(long, value_name = "FOLDER")]
    pub out: PathBuf,
    /// The database's file name [default: rockfrag_<study name>].
    #[arg(long, value_name = "NAME")]
    pub name: Option<String>,
}

/// Runs `rockfrag export`.
pub fn run(args: ExportArgs) -> anyhow::Result<()> {
    match args.to {
        ExportTo::Openquake(a) => {
            let job = export_openquake(&a.dir, &a.hazard, a.site, &a.out)?;
            eprintln!(
                "wrote {}: {} fragility functions (assets), {} hazard levels ({} per decade, \
                 slope {:.2}), investigation time {} yr",
                job.dir.display(),
                job.functions,
                job.levels,
                job.levels_per_decade,
                job.slope,
                job.investigation_time
            );
            for o in &job.omitted {
                eprintln!("note: not in the model: {o}");
            }
            println!("{}", job.dir.join("job.ini").display());
        }
        ExportTo::Pelicun(a) => {
            let study = study_of_folder(&a.dir)?;
            let study_name = study.as_ref().map_or_else(
                || {
                    a.dir
                        .file_name()
                        .map_or("study".to_string(), |n| n.to_string_lossy().into_owned())
                },
                |s| s.name.clone(),
            );
            let limit_states = study
                .as_ref()
                .and_then(|s| s.fragility.as_ref())
                .map_or_else(Vec::new, |f| f.limit_states());
            let name = a
                .name
                .clone()
                .unwrap_or_else(|| format!("rockfrag_{}", study_name.replace(['-', '.'], "_")));
            let db = export_pelicun(&a.dir, &a.out, &name, &study_name, &limit_states)?;
            eprintln!(
                "wrote {} and {}: {} components",
                db.csv.display(),
                db.json.display(),
                db.components
            );
            for o in &db.omitted {
                eprintln!(
                    "note: left out (pelicun needs every limit state): {o}; run stripes \
                     where it is exceeded, or more records"
                );
            }
            for o in &db.partial {
                eprintln!(
                    "note: {o}; pelicun will never predict those damage states for it, \
                     which the study supports only up to its highest stripe"
                );
            }
            println!("{}", db.csv.display());
        }
    }
    Ok(())
}
