//! `rockfrag bench`: the speed-against-error report.

mod figure;
mod fragility;
mod report;

use report::{WorkPrecisionOptions, markdown, work_precision};
use std::path::PathBuf;

/// Flags of `rockfrag bench`.
#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    /// Records per intensity level (at least 1).
    #[arg(long, value_name = "N", default_value_t = 25, value_parser = records)]
    pub records: u64,
    /// Where to write `work_precision.md` and `work_precision.svg`.
    #[arg(long, value_name = "DIR", default_value = "figures")]
    pub out: PathBuf,
    /// Also draw the figure as `work_precision.png`.
    #[arg(long)]
    pub png: bool,
}

/// A number of records per level ≥ 1 (`--records 0` panicked: the
/// reference had no analysis to fit).
fn records(text: &str) -> Result<u64, String> {
    match text.trim().parse::<u64>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err("expected a whole number of records per intensity level ≥ 1".into()),
    }
}

/// Runs `rockfrag bench`.
pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    let opts = WorkPrecisionOptions {
        records: args.records,
        ..WorkPrecisionOptions::default()
    };
    eprintln!(
        "rockfrag bench: reference at rtol {:e} and its sensitivity, then {} settings …",
        opts.reference_rtol,
        opts.rtols.len() * opts.integrators.len() + 1
    );
    let report = work_precision(&opts)?;
    let text = markdown(&opts, &report);
    let md = args.out.join("work_precision.md");
    rockfrag::io_util::write_atomic(&md, |w| w.write_all(text.as_bytes()))?;
    figure::plot_work_precision(&report, &args.out.join("work_precision.svg"))?;
    if args.png {
        figure::plot_work_precision(&report, &args.out.join("work_precision.png"))?;
    }
    print!("{text}");
    Ok(())
}
