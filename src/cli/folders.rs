//! Checks on the study folders the subcommands read.

/// Refuses a folder holding one shard of a study, a part of its analyses,
/// unless `partial` (the command's `--partial`): its fit or figures would
/// look like the study's. `what` is what the command would do with it
/// (`fit`, `draw`).
pub fn refuse_shard(dir: &std::path::Path, partial: bool, what: &str) -> anyhow::Result<()> {
    let manifest = dir.join(rockfrag::study::files::MANIFEST);
    if manifest.exists() && !partial {
        let m = rockfrag::study::Manifest::read(&manifest)?;
        if m.shard != rockfrag::study::Shard::WHOLE {
            anyhow::bail!(
                "{}: holds shard {} of study '{}', a part of its analyses: merge the shards \
                 (rockfrag merge) and {what} the merged folder, or pass --partial to {what} this \
                 part",
                dir.display(),
                m.shard,
                m.study
            );
        }
    }
    Ok(())
}
