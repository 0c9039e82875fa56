//! `rockfrag bench`: the speed-against-error report.

use rockfrag::bench::{WorkPrecisionOptions, markdown, work_precision};
use std::path::PathBuf;

/// Flags of `rockfrag bench`.
#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    /// Records per intensity level.
    #[arg(long, value_name = "N", default_value_t = 25)]
    pub records: u64,
    /// Where to write `work_precision.md` and `work_precision.svg`.
    #[arg(long, value_name = "DIR", default_value = "figures")]
    pub out: PathBuf,
    /// Also draw the figure as `work_precision.png`.
    #[arg(long)]
    pub png: bool,
}

/// Runs `rockfrag bench`.
pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    let opts = WorkPrecisionOptions {
        records: args.records,
        ..WorkPrecisionOptions::default()
    };
    eprintln!(
        "rockfrag bench: reference at rtol {:e}, then {} settings …",
        opts.reference_rtol,
        opts.rtols.len() * opts.integrators.len() + 1
    );
    let reports = work_precision(&opts)?;
    let text = markdown(&opts, &reports);
    std::fs::create_dir_all(&args.out)?;
    let md = args.out.join("work_precision.md");
    std::fs::write(md.with_extension("md.tmp"), &text)?;
    std::fs::rename(md.with_extension("md.tmp"), &md)?;
    rockfrag::figures::plot_work_precision(&reports, &args.out.join("work_precision.svg"))?;
    if args.png {
        rockfrag::figures::plot_work_precision(&reports, &args.out.join("work_precision.png"))?;
    }
    print!("{text}");
    Ok(())
}
