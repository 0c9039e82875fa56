//! `rockfrag motion`: one synthetic ground motion to CSV (and SVG).

/// Flags of `rockfrag motion`.
#[derive(Debug, clap::Args)]
pub struct MotionArgs {}

/// Runs `rockfrag motion`.
pub fn run(_args: MotionArgs) -> anyhow::Result<()> {
    anyhow::bail!("not yet implemented")
}
