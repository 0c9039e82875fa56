//! `rockfrag merge`: join the folders of shards 1/N..N/N into one.

use rockfrag::spec::Study;
use rockfrag::study;
use std::path::PathBuf;

/// Flags of `rockfrag merge`.
#[derive(Debug, clap::Args)]
pub struct MergeArgs {
    /// The shard folders (each from `rockfrag run --shard K/N`), in any order.
    #[arg(value_name = "DIR", required = true)]
    pub dirs: Vec<PathBuf>,
    /// Folder of the merged study.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Replace a finished run of other analyses in the output folder (its
    /// outcomes and the files made from them); without it, that is refused.
    #[arg(long)]
    pub force: bool,
    /// Print the fragility table and every note (default: one line per step).
    #[arg(long, short)]
    pub verbose: bool,
}

/// Runs `rockfrag merge`.
pub fn run(args: MergeArgs) -> anyhow::Result<()> {
    let m = study::merge_into(&args.dirs, &args.out, args.force)?;
    // held over what is made from the merged outcomes, as `run` holds it
    let _lock = study::RunLock::acquire(&args.out)?;
    eprintln!(
        "merged {} shards of study {}: {} analyses ({} overturned, {} failed) into {}",
        args.dirs.len(),
        m.study,
        m.counts.analyses,
        m.counts.overturned,
        m.counts.failed,
        args.out.display()
    );
    let spec = args.out.join(study::files::MANIFEST);
    let whole = Study::from_toml_unchecked(&m.spec_toml, &spec)?;
    let finish = rockfrag::pipeline::finish(&whole, &args.out, None)?;
    super::run::say(&finish, &args.out, args.verbose);
    if m.counts.failed > 0 {
        anyhow::bail!(
            "{} of {} analyses failed in the shards",
            m.counts.failed,
            m.counts.analyses
        );
    }
    Ok(())
}
