//! `rockfrag floor`: the absolute motion of a floor of a linear building
//! under a ground record, as a CSV record; and the floor flags that
//! `simulate` shares.

use std::path::PathBuf;

use super::args::{damping_ratio, finite, positive};
use anyhow::Context;
use rockfrag::motion::{self, Floor, G_STANDARD, Mode};

/// The building's modes at the floor, as flags: `--PREFIX-period` once per
/// mode, `--PREFIX-damping` once (every mode) or once per mode,
/// `--PREFIX-participation` left out (Γφ = 1), once or once per mode.
pub fn floor_of(
    periods: &[f64],
    dampings: &[f64],
    participations: &[f64],
    prefix: &str,
) -> anyhow::Result<Floor> {
    let n = periods.len();
    let pick = |values: &[f64], what: &str, default: Option<f64>| -> anyhow::Result<Vec<f64>> {
        match values.len() {
            0 => match default {
                Some(d) => Ok(vec![d; n]),
                None => anyhow::bail!("--{prefix}period needs --{prefix}damping (e.g. 0.05)"),
            },
            1 => Ok(vec![values[0]; n]),
            k if k == n => Ok(values.to_vec()),
            k => anyhow::bail!(
                "{k} --{prefix}{what} values for {n} --{prefix}period values: give one for \
                 every mode, or one for all"
            ),
        }
    };
    if n == 0 {
        if !dampings.is_empty() || !participations.is_empty() {
            anyhow::bail!(
                "--{prefix}damping and --{prefix}participation describe a mode: give its \
                 --{prefix}period too"
            );
        }
        return Ok(Floor::ground());
    }
    let zeta = pick(dampings, "damping", None)?;
    let gamma = pick(participations, "participation", Some(1.0))?;
    let floor = Floor {
        modes: (0..n)
            .map(|i| Mode {
                period: periods[i],
                damping: zeta[i],
                participation: gamma[i],
            })
            .collect(),
    };
    // the spec's field names (`floor[0].period`) as the flags typed here
    floor.validate().map_err(|e| {
        let mut text = e.to_string();
        for i in 0..n {
            for what in ["period", "damping", "participation"] {
                let which = if n > 1 {
                    format!(" (value {})", i + 1)
                } else {
                    String::new()
                };
                text = text.replace(
                    &format!("floor[{i}].{what}"),
                    &format!("--{prefix}{what}{which}"),
                );
            }
        }
        anyhow::anyhow!(text)
    })?;
    Ok(floor)
}

/// Flags of `rockfrag floor`.
#[derive(Debug, clap::Args)]
pub struct FloorArgs {
    /// Ground-motion record: CSV `t,acc[,vel,disp]` (s, m/s²) or PEER `.AT2`
    /// (g).
    #[arg(value_name = "RECORD")]
    pub record: PathBuf,
    /// Natural period T of a mode of the building (s); repeat for several
    /// modes.
    #[arg(long, value_name = "T", required = true, value_parser = positive, allow_negative_numbers = true)]
    pub period: Vec<f64>,
    /// Damping ratio ζ of the modes (0.05 for 5 %): once for all, or once
    /// per --period.
    #[arg(long, value_name = "Z", required = true, value_parser = damping_ratio, allow_negative_numbers = true)]
    pub damping: Vec<f64>,
    /// Participation Γφ at the floor (participation factor times the mode
    /// shape there; about 1.3 at the roof of a regular building): once for
    /// all, or once per --period [default: 1].
    #[arg(long, value_name = "G", value_parser = finite, allow_negative_numbers = true)]
    pub participation: Vec<f64>,
    /// Gravity (m/s²), to read `.AT2` accelerations in g.
    #[arg(long, value_name = "M/S2", default_value_t = G_STANDARD, value_parser = positive)]
    pub g: f64,
    /// Output file, written atomically: CSV `t,acc,vel,disp` (s, m/s², m/s,
    /// m) with the record's time step; standard output if absent.
    #[arg(long, value_name = "FILE.csv")]
    pub out: Option<PathBuf>,
}

/// Runs `rockfrag floor`.
pub fn run(args: FloorArgs) -> anyhow::Result<()> {
    if let Some(out) = &args.out {
        rockfrag::io_util::refuse_overwriting_input(
            out,
            "--out",
            &args.record,
            "the ground record",
        )?;
    }
    let floor = floor_of(&args.period, &args.damping, &args.participation, "")?;
    let ground = motion::read_record(&args.record, args.g)?;
    let out = motion::floor_record(&ground, &floor)
        .with_context(|| format!("filtering {} through the floor", args.record.display()))?;
    match &args.out {
        Some(path) => {
            motion::write_csv(path, &out)?;
            eprintln!(
                "{}: PGA {:.4} g, PGV {:.4} m/s -> floor PFA {:.4} g, PFV {:.4} m/s ({} samples, \
                 dt {} s)",
                args.record.display(),
                ground.pga() / args.g,
                ground.pgv(),
                out.pga() / args.g,
                out.pgv(),
                out.len(),
                out.dt
            );
        }
        None => {
            let stdout = std::io::stdout();
            motion::write_csv_to(std::io::BufWriter::new(stdout.lock()), &out)?;
        }
    }
    Ok(())
}
