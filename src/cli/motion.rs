//! `rockfrag motion`: one synthetic ground motion to CSV or PEER `.AT2` (and
//! a figure).
//!
//! The flags are checked by clap's value parsers (bad values exit with status
//! 2 and a one-line message naming the flag); the settings they build are
//! validated once by the library.

use std::io::Write;
use std::path::PathBuf;

use super::args::{non_negative, pga_g, positive};
use anyhow::Context;
use rockfrag::motion::{At2, SynthesisSettings, Synthesizer, write_csv, write_csv_to};

/// Flags of `rockfrag motion`.
#[derive(Debug, clap::Args)]
pub struct MotionArgs {
    /// Ensemble seed; record INDEX of ensemble SEED is always the same record.
    #[arg(long, value_name = "N")]
    pub seed: u64,
    /// Peak ground acceleration, in g (converted with g = 9.81 m/s²).
    #[arg(long, value_name = "G", value_parser = pga_g, allow_negative_numbers = true)]
    pub pga: f64,
    /// Index of the record within the ensemble.
    #[arg(long, value_name = "I", default_value_t = 0)]
    pub index: u64,
    /// Output file, written atomically: CSV (header `t,acc,vel,disp`; s,
    /// m/s², m/s, m) or, if the name ends in `.AT2`, a PEER NGA `.AT2`
    /// record (acceleration in g); CSV on standard output if absent.
    #[arg(long, value_name = "FILE.csv|FILE.AT2")]
    pub out: Option<PathBuf>,
    /// Sample interval, s [default: 0.02]; 1/(0.05·dt) must be an integer.
    #[arg(long, value_name = "S", value_parser = positive, allow_negative_numbers = true)]
    pub dt: Option<f64>,
    /// Record duration, s [default: 30].
    #[arg(long, value_name = "S", value_parser = positive, allow_negative_numbers = true)]
    pub duration: Option<f64>,
    /// High-pass corner frequency, Hz [default: 0.07]; 0 disables the filter.
    #[arg(long, value_name = "HZ", value_parser = non_negative, allow_negative_numbers = true)]
    pub highpass: Option<f64>,
    /// Also draw acceleration, velocity and displacement, stacked (SVG, or
    /// PNG by extension), like the paper's Figure 2.
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
}

impl MotionArgs {
    /// The synthesis settings these flags select (defaults otherwise).
    fn settings(&self) -> SynthesisSettings {
        let mut s = SynthesisSettings::default();
        if let Some(dt) = self.dt {
            s.dt = dt;
        }
        if let Some(duration) = self.duration {
            s.duration = duration;
        }
        if let Some(hz) = self.highpass {
            s.baseline.highpass_hz = hz;
        }
        s
    }
}

impl MotionArgs {
    /// `--dt` must fit the generator's fixed frequency step: says which
    /// combination fails and which steps work (the library's message named
    /// df, a setting this command does not offer).
    fn check_dt(&self) -> anyhow::Result<()> {
        match self.dt.and_then(|_| self.settings().dt_misfit("--dt")) {
            Some(message) => anyhow::bail!(message),
            None => Ok(()),
        }
    }
}

/// Runs `rockfrag motion`.
pub fn run(args: MotionArgs) -> anyhow::Result<()> {
    args.check_dt()?;
    let settings = args.settings();
    let overridden = args.dt.is_some() || args.duration.is_some() || args.highpass.is_some();
    let mut synth = Synthesizer::new(&settings).with_context(|| {
        if overridden {
            "settings from --dt, --duration or --highpass"
        } else {
            "default synthesis settings"
        }
    })?;
    let record = synth.generate(args.seed, args.index, settings.pga_from_g(args.pga))?;
    if let Some(path) = &args.plot {
        rockfrag::figures::plot_record(&record, path)?;
    }
    match &args.out {
        Some(path) if is_at2(path) => At2::from_record(&record, settings.g).write(path)?,
        Some(path) => write_csv(path, &record)?,
        None => {
            let mut w = std::io::BufWriter::new(std::io::stdout().lock());
            let written = write_csv_to(&mut w, &record).and_then(|()| w.flush());
            match written {
                // A closed pipe (`rockfrag motion … | head`) is not an error.
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {}
                other => other.context("writing to standard output")?,
            }
        }
    }
    Ok(())
}

/// Whether `path` names a PEER `.AT2` file (any case of the extension).
fn is_at2(path: &std::path::Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("at2"))
}
