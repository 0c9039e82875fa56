//! `rockfrag run STUDY --precision 0.05`: how many records a fixed-grid
//! study needs per level for a median band of ±5 %, from a pilot, without
//! running them all (docs/adaptive.md).

use anyhow::bail;
use rockfrag::fragility::{FragilityOptions, read_fragility_csv, records_for};
use rockfrag::pipeline;
use rockfrag::spec::{Motions, Study};
use rockfrag::study::RunOptions;

/// Records per level of the pilot (fewer if the study has fewer).
pub const PILOT_RECORDS: usize = 10;

/// Runs the pilot of `study` (its grid with [`PILOT_RECORDS`] records per
/// level, in a temporary folder removed afterwards) and prints, per case
/// and limit state, the pilot's band and the records per level a band of
/// half-width `target` (relative to the median) needs.
pub fn size(study: &Study, target: f64, threads: usize) -> anyhow::Result<()> {
    if !(target.is_finite() && (0.001..=0.5).contains(&target)) {
        bail!(
            "--precision {target}: expected a half-width of the median's band relative to the \
             median in [0.001, 0.5] (0.05 is ±5 %)"
        );
    }
    if study.adaptive.is_some() {
        bail!(
            "--precision sizes a fixed grid (grid.pga = [ … ]); study '{}' is adaptive: its \
             [fragility] precision is its target, run it without --precision",
            study.name
        );
    }
    let mut pilot = study.clone();
    let records = match &mut pilot.motions {
        Motions::Synthetic { records, .. } => {
            *records = (*records).min(PILOT_RECORDS);
            *records
        }
        _ => study.records(),
    };
    let levels = study.intensity.levels().len();
    let options = study.fragility.clone().unwrap_or_default();
    pilot.fragility = Some(FragilityOptions {
        bootstrap: options.bootstrap.max(200),
        ..options
    });
    pilot.output.summary = false;
    pilot.output.figures = false;
    let dir = std::env::temp_dir().join(format!("rockfrag-pilot-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let run = pipeline::run(
        &pilot,
        &RunOptions {
            threads,
            ..RunOptions::new(&dir)
        },
    );
    let rows = run.and_then(|_| read_fragility_csv(&dir.join("fragility.csv")));
    let _ = std::fs::remove_dir_all(&dir);
    let rows = rows?;
    println!(
        "pilot: {records} records × {levels} levels per case ({} analyses per case); records per \
         level for a median band of ±{:.1} % (90 % band, estimated from the pilot's bootstrap \
         band by 1/√n: the pilot's own band is uncertain by about ±{:.0} %, so take the \
         numbers as ±{:.0} %):",
        records * levels,
        100.0 * target,
        100.0 / (2.0 * records as f64).sqrt(),
        200.0 / (2.0 * records as f64).sqrt(),
    );
    for row in &rows {
        let id = row.case.id();
        match (row.median, row.median_band) {
            (Some(m), Some(band)) => {
                let half = 0.5 * (band.1 - band.0) / m;
                let n = records_for(records, half, target);
                let caveat = match row.im_range {
                    Some((lo, hi)) if m > hi || m < lo => format!(
                        "; its median {m:.3} lies outside the levels {lo}–{hi}: more records \
                         will not make it trustworthy, move the levels"
                    ),
                    _ => String::new(),
                };
                println!(
                    "  {id} {}: pilot ±{:.1} %; about {n} records per level ({} analyses){caveat}",
                    row.limit_state,
                    100.0 * half,
                    n * levels
                );
            }
            _ => println!(
                "  {id} {}: not fitted from the pilot ({}): the levels miss where it changes, \
                 or the pilot is too small to tell; move the levels or run an adaptive study",
                row.limit_state, row.status
            ),
        }
    }
    Ok(())
}
