//! Intensity measures `outcomes.csv` does not hold (`sa(T)`, `sa-avg`,
//! `pgv/pga`, …), measured after the run on the motions the analyses felt:
//! the records are regenerated (synthetic) or reread (files) from the
//! study recorded in the folder's `manifest.json`, deterministically, so a
//! fit against any IM needs no analysis to be run again and leaves
//! `outcomes.csv` as it was. Each motion (a record at a level) is measured
//! once, whatever the number of blocks that felt it.

use std::collections::{BTreeSet, HashMap};
use std::path::Path;

use super::files;
use super::manifest::Manifest;
use super::source::Source;
use crate::error::{Error, Result};
use crate::fragility::RecordIms;
use crate::im::{At, Im};
use crate::outcomes_csv::{Column, OutcomesFile};
use crate::spec::Study;

/// The study a folder's `manifest.json` records, for measuring `im` on its
/// records. Errors: no manifest (a file of outcomes alone cannot be
/// measured again), or one that cannot be read.
fn folder_study(dir: &Path, im: Im) -> Result<Study> {
    let manifest = dir.join(files::MANIFEST);
    if !manifest.exists() {
        return Err(Error::invalid(
            "im",
            im,
            &format!(
                "an IM outcomes.csv holds ({}, pga-over-tan): {im} is measured on the \
                 records again, from the study in {}, which is missing",
                Im::COLUMNS.map(Im::name).join(", "),
                manifest.display()
            ),
        ));
    }
    let m = Manifest::read(&manifest)?;
    Study::from_toml_unchecked(&m.spec_toml, &manifest)
}

/// Measures `im` on every motion the successful analyses of
/// `dir/outcomes.csv` felt (see the module's documentation).
///
/// Errors: the study cannot be recovered, a record cannot be remade, or
/// `im` is not defined on the study's motions (a floor's IM on the ground,
/// a RotD50 without record pairs), naming the IM.
pub fn measure_records(dir: &Path, im: Im) -> Result<RecordIms> {
    let study = folder_study(dir, im)?;
    measure_study_records(&study, dir, im)
}

/// As [`measure_records`], for the folder `dir` of `study`.
pub fn measure_study_records(study: &Study, dir: &Path, im: Im) -> Result<RecordIms> {
    let study = study.clone();
    let level_column = super::plan::columns(&study).level();
    let path = dir.join(files::OUTCOMES);
    let mut table = OutcomesFile::open(
        &path,
        &[Column::Record, level_column],
        &format!("measuring {im} on the records"),
    )?;
    let mut motions = BTreeSet::new();
    while let Some((line, row)) = table.next_row()? {
        if row.result.is_err() {
            continue;
        }
        let Some(level) = row.intensity(level_column) else {
            return Err(table.error_at(line, format!("no `{level_column}` (the level)")));
        };
        motions.insert((level.to_bits(), row.record));
    }
    let mut source = Source::new(&study)?;
    let mut values = HashMap::with_capacity(motions.len());
    for (bits, record) in motions {
        let level = f64::from_bits(bits);
        let motion = source.motion(&study, level, record)?;
        let Some(v) = motion.im(im).filter(|v| v.is_finite() && *v > 0.0) else {
            let why = match im.at() {
                At::Floor if study.floor.is_ground() => "the study has no floor",
                At::RotD50 if study.motions.orientation().is_none() => {
                    "the study has no record pairs"
                }
                _ => "it is zero or not finite",
            };
            return Err(Error::invalid(
                "im",
                im,
                &format!(
                    "an IM the study's motions have: record {record} at level {level} has \
                     none ({why})"
                ),
            ));
        };
        values.insert((bits, record), v);
    }
    Ok(RecordIms {
        im,
        level_column,
        values,
    })
}
