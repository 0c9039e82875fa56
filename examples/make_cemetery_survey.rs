//! Makes `studies/cemetery-survey.csv`, the SYNTHETIC survey of the
//! `rockfrag infer` example: four kinds of tombstone (sizes and counts
//! below) put on one record of `studies/cemetery.toml`'s ground-motion
//! model that is not in its ensemble (index 1,000,000), scaled to a PGA of
//! 0.45 g; each tombstone draws its own restitution and friction from the
//! spec's `[uncertainty]`, and what overturned is the survey. Inferring
//! from it should give back about 0.45 g.
//!
//! ```text
//! cargo run --release --example make_cemetery_survey
//! ```

use std::path::Path;

use rockfrag::infer::calibrate::synthetic_survey;
use rockfrag::infer::{Survey, settings};
use rockfrag::spec::Study;

/// The record (of the spec's model, outside its 40-record ensemble).
const RECORD: usize = 1_000_000;
/// Its PGA, g.
const PGA: f64 = 0.45;
/// The kinds: name, base width 2B (m), H/B, count (overturned filled in).
const KINDS: &str = "name,width,aspect,count,overturned
slab-tall,0.20,5.0,24,0
slab-low,0.25,3.0,30,0
obelisk,0.35,6.0,12,0
block,0.45,2.0,18,0
";

fn main() -> anyhow::Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let study = Study::load(&root.join("studies/cemetery.toml"))?;
    let kinds = Survey::parse(KINDS, Path::new("make_cemetery_survey.rs"))?;
    let survey = synthetic_survey(&study, &kinds, &settings(&study), PGA, RECORD)?;
    let mut text = format!(
        "# SYNTHETIC survey, not a real cemetery: made by `cargo run --release --example \
         make_cemetery_survey`\n# from record {RECORD} of studies/cemetery.toml's ground-motion \
         model (not in its ensemble), scaled to PGA {PGA} g;\n# each tombstone's restitution \
         and friction drawn from the spec's [uncertainty]. Infer with:\n#   rockfrag infer \
         studies/cemetery-survey.csv --study studies/cemetery.toml\n\
         name,width,aspect,count,overturned\n"
    );
    for k in &survey.kinds {
        text.push_str(&format!(
            "{},{},{},{},{}\n",
            k.name, k.width, k.aspect, k.count, k.overturned
        ));
    }
    let out = root.join("studies/cemetery-survey.csv");
    std::fs::write(&out, &text)?;
    print!("{text}");
    eprintln!("wrote {}", out.display());
    Ok(())
}
