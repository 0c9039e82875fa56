//! The calibration of `rockfrag infer` (see `rockfrag::infer::calibrate`):
//! synthetic events with a known PGA, each a record outside the study's
//! ensemble with 3–5 kinds of a pool, 10–30 objects of each, inferred by
//! both methods; prints how often each 90 % interval covers the true PGA
//! and the median widths; and how often the 90 % region of the joint
//! posterior over (PGA, PGV) (`infer --im pga,pgv`) holds the true pair.
//!
//! ```text
//! cargo run --release --example infer_calibration -- [EVENTS] [SPEC.toml] [KINDS.csv] [SEED]
//! ```
//!
//! Defaults: 200 events of the cemetery example (`studies/cemetery.toml`)
//! with a pool of five kinds of tombstone (the four of
//! `studies/cemetery-survey.csv` and a cross), seed 1. A pool from a file
//! is a survey (its counts are ignored); `-` keeps the default pool.

use std::path::{Path, PathBuf};
use std::time::Instant;

use rockfrag::infer::calibrate::{CalibrationOptions, calibrate};
use rockfrag::infer::{Im, Survey, settings};
use rockfrag::spec::Study;

/// The default pool: the cemetery survey's kinds and a cross (2B, H/B).
const POOL: &str = "name,width,aspect,count,overturned
slab-tall,0.20,5.0,1,0
slab-low,0.25,3.0,1,0
obelisk,0.35,6.0,1,0
block,0.45,2.0,1,0
cross,0.30,4.0,1,0
";

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let events: usize = args.first().map_or(Ok(200), |a| a.parse())?;
    let spec = args
        .get(1)
        .map_or_else(|| root.join("studies/cemetery.toml"), PathBuf::from);
    let seed: u64 = args.get(3).map_or(Ok(1), |a| a.parse())?;
    let study = Study::load(&spec)?;
    let kinds = match args.get(2).filter(|a| !a.is_empty() && *a != "-") {
        Some(path) => Survey::read(Path::new(path))?,
        None => Survey::parse(POOL, Path::new("infer_calibration.rs"))?,
    };
    let t0 = Instant::now();
    let c = calibrate(
        &study,
        &kinds,
        &settings(&study),
        &CalibrationOptions {
            events,
            counts: (10, 30),
            kinds: (3, 5),
            seed,
            second: Some(Im::PGV),
        },
    )?;
    let failed = |f: fn(&rockfrag::infer::calibrate::Event) -> bool| {
        c.events.iter().filter(|e| f(e)).count()
    };
    println!(
        "{} events, 3-5 of {} kinds of 10-30 objects, study {} ({} records x {} levels, {} analyses; \
         {} analyses of the events' objects) in {:.1} s",
        c.events.len(),
        kinds.kinds.len(),
        study.name,
        study.records(),
        study.intensity.levels().len(),
        c.analyses,
        c.event_analyses,
        t0.elapsed().as_secs_f64()
    );
    println!(
        "joint: 90 % interval covers the true PGA in {:.1} % of the events; median width {:.3} g \
         (p95/p05 {:.2}); {} without a posterior; median effective records {:.1}",
        100.0 * c.joint_coverage,
        c.joint_width,
        c.joint_ratio,
        failed(|e| e.joint.is_none()),
        c.effective_records
    );
    println!(
        "naive: 90 % interval covers the true PGA in {:.1} % of the events; median width {:.3} g \
         (p95/p05 {:.2}); {} without a posterior",
        100.0 * c.naive_coverage,
        c.naive_width,
        c.naive_ratio,
        failed(|e| e.naive.is_none())
    );
    let side = |f: fn(&rockfrag::infer::calibrate::Event) -> Option<rockfrag::infer::Summary>| {
        let below = c
            .events
            .iter()
            .filter(|e| f(e).is_some_and(|s| e.im < s.p05))
            .count();
        let above = c
            .events
            .iter()
            .filter(|e| f(e).is_some_and(|s| e.im > s.p95))
            .count();
        (below, above)
    };
    let (jb, ja) = side(|e| e.joint);
    let (nb, na) = side(|e| e.naive);
    println!("misses: joint {jb} below its 5 % bound and {ja} above its 95 %; naive {nb} and {na}");
    println!(
        "two IMs (PGA, PGV): the 90 % joint region holds the true pair in {:.1} % of the events; \
         the PGV 90 % interval holds the true PGV in {:.1} %",
        100.0 * c.pair_coverage.unwrap_or(f64::NAN),
        100.0 * c.second_coverage.unwrap_or(f64::NAN)
    );
    if std::env::var_os("CALIBRATION_EVENTS").is_some() {
        for e in &c.events {
            let j = e.joint.unwrap();
            println!(
                "{:.4} {:.4} {:.4} {:.4} {:.1} {:?}",
                e.im, j.p05, j.median, j.p95, e.effective_records, e.counts
            );
        }
    }
    Ok(())
}
