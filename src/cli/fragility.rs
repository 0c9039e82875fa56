//! `rockfrag fragility`: lognormal fragility curves from a study's outcomes.

use anyhow::Context;
use clap::ValueEnum;
use rockfrag::fragility::{fit_outcomes, fragility_csv, nrml};
use std::path::PathBuf;

/// Intensity measure, as a CLI value.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ImArg {
    /// Peak ground acceleration (g).
    Pga,
    /// PGA/(g·tanθc) = PGA·H/B (dimensionless).
    PgaOverTan,
}

/// Flags of `rockfrag fragility`.
#[derive(Debug, clap::Args)]
pub struct FragilityArgs {
    /// A study's output directory (with outcomes.csv).
    pub dir: PathBuf,
    /// Intensity measure.
    #[arg(long, value_enum, default_value_t = ImArg::Pga)]
    pub im: ImArg,
    /// Bootstrap replicates over records.
    #[arg(long, value_name = "N", default_value_t = 1000)]
    pub bootstrap: usize,
    /// Bootstrap seed.
    #[arg(long, value_name = "S", default_value_t = 1)]
    pub seed: u64,
    /// Where to write fragility.csv and fragility.xml [default: DIR].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// Runs `rockfrag fragility`.
pub fn run(args: FragilityArgs) -> anyhow::Result<()> {
    let im = match args.im {
        ImArg::Pga => "pga",
        ImArg::PgaOverTan => "pga-over-tan",
    };
    let fits = fit_outcomes(
        &args.dir.join("outcomes.csv"),
        im,
        args.bootstrap,
        args.seed,
    )?;
    let out = args.out.unwrap_or(args.dir);
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let write = |name: &str, text: String| -> anyhow::Result<()> {
        let path = out.join(name);
        let tmp = out.join(format!(".{name}.tmp"));
        std::fs::write(&tmp, text).with_context(|| format!("writing {}", tmp.display()))?;
        std::fs::rename(&tmp, &path).with_context(|| format!("writing {}", path.display()))?;
        Ok(())
    };
    write("fragility.csv", fragility_csv(&fits, im))?;
    write(
        "fragility.xml",
        nrml(&fits, if im == "pga" { "PGA" } else { "PGA/tan" }),
    )?;
    println!(
        "{:>6} {:>6} {:>5} {:>8} {:>10} {:>20} {:>8} {:>16}",
        "H/B", "2B", "e", "friction", "median", "90% band", "beta", "90% band"
    );
    for c in &fits {
        let fr = if c.key[3] == "coulomb" {
            format!("{}/{}", c.key[4], c.key[5])
        } else {
            "inf".into()
        };
        match (&c.fit, &c.boot) {
            (Ok(f), Some(b)) => println!(
                "{:>6} {:>6} {:>5} {:>8} {:>10.4} {:>9.4}–{:<10.4} {:>8.3} {:>7.3}–{:<8.3}",
                c.key[0],
                c.key[1],
                c.key[2],
                fr,
                f.median,
                b.median.0,
                b.median.1,
                f.beta,
                b.beta.0,
                b.beta.1
            ),
            (fit, _) => println!(
                "{:>6} {:>6} {:>5} {:>8}  cannot fit: {}",
                c.key[0],
                c.key[1],
                c.key[2],
                fr,
                fit.as_ref()
                    .err()
                    .map_or("-".to_string(), |e| e.to_string())
            ),
        }
    }
    Ok(())
}
