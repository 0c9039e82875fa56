//! `rockfrag motion`: one synthetic ground motion to CSV.
//!
//! The flags are checked by clap's value parsers (bad values exit with status
//! 2 and a one-line message naming the flag); the settings they build are
//! validated once by the library.

use std::io::Write;
use std::path::PathBuf;

use anyhow::Context;
use rockfrag::motion::{SynthesisSettings, Synthesizer, write_csv, write_csv_to};

/// Flags of `rockfrag motion`.
#[derive(Debug, clap::Args)]
pub struct MotionArgs {
    /// Ensemble seed; record INDEX of ensemble SEED is always the same record.
    #[arg(long, value_name = "N")]
    pub seed: u64,
    /// Peak ground acceleration, in g (converted with g = 9.81 m/s²).
    #[arg(long, value_name = "G", value_parser = POSITIVE, allow_negative_numbers = true)]
    pub pga: f64,
    /// Index of the record within the ensemble.
    #[arg(long, value_name = "I", default_value_t = 0)]
    pub index: u64,
    /// Output CSV file (header `t,acc,vel,disp`; s, m/s², m/s, m), written
    /// atomically; standard output if absent.
    #[arg(long, value_name = "FILE.csv")]
    pub out: Option<PathBuf>,
    /// Sample interval, s [default: 0.02]; 1/(0.05·dt) must be an integer.
    #[arg(long, value_name = "S", value_parser = POSITIVE, allow_negative_numbers = true)]
    pub dt: Option<f64>,
    /// Record duration, s [default: 30].
    #[arg(long, value_name = "S", value_parser = POSITIVE, allow_negative_numbers = true)]
    pub duration: Option<f64>,
    /// High-pass corner frequency, Hz [default: 0.07]; 0 disables the filter.
    #[arg(long, value_name = "HZ", value_parser = NON_NEGATIVE, allow_negative_numbers = true)]
    pub highpass: Option<f64>,
}

/// A finite number > 0 (or ≥ 0 with `allow_zero`). Its errors carry the
/// reason as clap context, so the one-line message says what was expected.
#[derive(Clone, Copy, Debug)]
struct Bounded {
    allow_zero: bool,
}

const POSITIVE: Bounded = Bounded { allow_zero: false };
const NON_NEGATIVE: Bounded = Bounded { allow_zero: true };

impl clap::builder::TypedValueParser for Bounded {
    type Value = f64;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<f64, clap::Error> {
        use clap::error::{ContextKind, ContextValue, ErrorKind};
        let text = value.to_string_lossy();
        let checked = match text.trim().parse::<f64>() {
            Err(_) => Err("not a number"),
            Ok(v) if !v.is_finite() => Err("must be finite"),
            Ok(v) if self.allow_zero && v < 0.0 => Err("must be ≥ 0"),
            Ok(v) if !self.allow_zero && v <= 0.0 => Err("must be > 0"),
            Ok(v) => Ok(v),
        };
        checked.map_err(|reason| {
            let mut e = clap::Error::new(ErrorKind::ValueValidation).with_cmd(cmd);
            if let Some(a) = arg {
                e.insert(ContextKind::InvalidArg, ContextValue::String(a.to_string()));
            }
            e.insert(
                ContextKind::InvalidValue,
                ContextValue::String(text.into_owned()),
            );
            e.insert(
                ContextKind::Custom,
                ContextValue::String(reason.to_string()),
            );
            e
        })
    }
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

/// Runs `rockfrag motion`.
pub fn run(args: MotionArgs) -> anyhow::Result<()> {
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
    match &args.out {
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
