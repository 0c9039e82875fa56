//! Adaptive studies (issue 39): `grid.pga = { min, max }` with
//! `[fragility] precision`. The rounds are deterministic (same bytes on 1
//! and 2 threads and after a kill and resume), a case stops when its band
//! meets the target, a median outside the range stops its case with a
//! message, and bad specs are refused naming the field.

mod common;

use rockfrag::pipeline;
use rockfrag::spec::Study;
use rockfrag::study::{RunOptions, Shard};
use std::path::Path;

/// The vase of studies/vase.toml at H/B 4 (drawn e and μ), overturning
/// only, ±10 % on the median so that a test run stays small.
const VASE: &str = r#"
name = "vase-adaptive"
seed = 2024

[grid]
width = [0.2]
aspect = [4]
pga = { min = 0.05, max = 3.0 }

[uncertainty]
restitution = { dist = "uniform", min = 0.2, max = 0.6 }
mu_s = { dist = "lognormal", median = 0.5, beta = 0.15 }
mu_k_over_mu_s = { dist = "uniform", min = 0.75, max = 0.95 }

[fragility]
bootstrap = 300
precision = { median = 0.10, beta = 0.3 }
"#;

fn study(text: &str) -> Study {
    Study::from_toml(text, Path::new("vase-adaptive.toml")).unwrap()
}

fn opts(dir: &Path, threads: usize) -> RunOptions {
    RunOptions {
        threads,
        ..RunOptions::new(dir)
    }
}

fn read(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

const OUTPUTS: [&str; 3] = ["outcomes.csv", "adaptive.csv", "fragility.csv"];

/// The rounds depend only on the rows so far, which are in canonical
/// order: one and two threads give the same files, and a run stopped after
/// two rounds and run again replays them from its checkpoint to the same
/// bytes, solving only what was not done.
#[test]
fn same_bytes_on_one_and_two_threads_and_after_a_kill() {
    let s = study(VASE);
    let tmp = tempfile::tempdir().unwrap();
    let (one, two, killed) = (
        tmp.path().join("one"),
        tmp.path().join("two"),
        tmp.path().join("killed"),
    );
    let r1 = pipeline::run(&s, &opts(&one, 1)).unwrap();
    let r2 = pipeline::run(&s, &opts(&two, 2)).unwrap();
    assert!(r1.run.complete && r2.run.complete);
    let rounds = r1.adaptive.as_ref().unwrap().rounds;
    assert!(
        rounds >= 3,
        "at least the minimum of 3 rounds, got {rounds}"
    );
    let stop = RunOptions {
        stop_after_units: Some(2),
        ..opts(&killed, 2)
    };
    let first = pipeline::run(&s, &stop).unwrap();
    assert!(!first.run.complete, "stopped after 2 of {rounds} rounds");
    assert!(killed.join("adaptive-checkpoint.json").exists());
    let second = pipeline::run(&s, &opts(&killed, 1)).unwrap();
    assert!(second.run.complete);
    assert_eq!(
        first.run.analyses_run + second.run.analyses_run,
        r1.run.analyses_run,
        "the resumed run solves only what the killed one had not"
    );
    assert!(!killed.join("adaptive-checkpoint.json").exists());
    for name in OUTPUTS {
        assert!(
            read(&one, name) == read(&two, name),
            "{name}: 1 vs 2 threads"
        );
        assert!(
            read(&one, name) == read(&killed, name),
            "{name}: after a kill"
        );
    }
}

/// The same spec run again on its finished folder solves nothing: the rows
/// of `outcomes.csv`, located by `adaptive-index.csv`, replay the same
/// rounds, `outcomes.csv` keeps its bytes and mtime, and what follows it is
/// remade to the same bytes. Without the index (a folder of an older build)
/// the run starts over, to the same bytes; `--force` also runs it again.
#[test]
fn a_finished_adaptive_folder_is_reused_not_run_again() {
    let s = study(VASE);
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("vase");
    let first = pipeline::run(&s, &opts(&dir, 2)).unwrap();
    assert!(first.run.complete && first.run.analyses_run >= 100);
    let before: Vec<Vec<u8>> = OUTPUTS.iter().map(|n| read(&dir, n)).collect();
    let index = String::from_utf8(read(&dir, "adaptive-index.csv")).unwrap();
    assert_eq!(
        index.lines().count() as u64 - 1,
        first.run.analyses_run,
        "one index line per analysis"
    );
    let mtime = || {
        std::fs::metadata(dir.join("outcomes.csv"))
            .unwrap()
            .modified()
            .unwrap()
    };
    let t0 = mtime();
    let again = pipeline::run(&s, &opts(&dir, 1)).unwrap();
    assert!(again.run.complete && again.run.already_finished);
    assert_eq!(again.run.analyses_run, 0, "nothing solved again");
    assert_eq!(mtime(), t0, "outcomes.csv not rewritten");
    let a = again.adaptive.as_ref().unwrap();
    assert_eq!(a.rounds, first.adaptive.as_ref().unwrap().rounds);
    for (name, bytes) in OUTPUTS.iter().zip(&before) {
        assert!(&read(&dir, name) == bytes, "{name}: reused run");
    }
    // a tighter target decides other analyses: the folder is refused,
    // naming what differs, and left as it was
    let tight = study(&VASE.replace("median = 0.10", "median = 0.07"));
    let err = pipeline::run(&tight, &opts(&dir, 2))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("an adaptive study's [fragility] decides its analyses"),
        "{err}"
    );
    for (name, bytes) in OUTPUTS.iter().zip(&before) {
        assert!(&read(&dir, name) == bytes, "{name}: refused run");
    }
    std::fs::remove_file(dir.join("adaptive-index.csv")).unwrap();
    let redo = pipeline::run(&s, &opts(&dir, 2)).unwrap();
    assert_eq!(
        redo.run.analyses_run, first.run.analyses_run,
        "no index: run again"
    );
    assert!(!redo.run.already_finished);
    let forced = RunOptions {
        force: true,
        ..opts(&dir, 2)
    };
    let forced = pipeline::run(&s, &forced).unwrap();
    assert_eq!(
        forced.run.analyses_run, first.run.analyses_run,
        "--force: run again"
    );
    for (name, bytes) in OUTPUTS.iter().zip(&before) {
        assert!(&read(&dir, name) == bytes, "{name}: run again");
    }
}

/// A case stops when its bootstrap band is within the target, after at
/// least 100 analyses; the band it reports is the one fragility.csv has,
/// and the analyses went mostly near the median. With
/// `output.figures` the run draws the fragility figure of its stripes, as
/// a fixed grid's run does.
#[test]
fn a_case_stops_when_its_band_meets_the_target() {
    let s = study(&format!("{VASE}\n[output]\nfigures = true\n"));
    let tmp = tempfile::tempdir().unwrap();
    let report = pipeline::run(&s, &opts(tmp.path(), 2)).unwrap();
    let a = report.adaptive.unwrap();
    let case = &a.cases[0];
    assert_eq!(case.stop.status(), "met");
    assert!(case.analyses() >= 100, "{} analyses", case.analyses());
    let band = case.bands[0].1.unwrap();
    assert!(band.median_half() <= 0.10, "±{}", band.median_half());
    assert!(band.beta_half() <= 0.3, "β ±{}", band.beta_half());
    let fragility = String::from_utf8(read(tmp.path(), "fragility.csv")).unwrap();
    let lo = format!("{}", band.median_band.0);
    assert!(fragility.contains(&lo), "fragility.csv has the band {lo}");
    // Fisher information puts most analyses after the coarse round within
    // a factor 1.5 of θ (a fixed grid over 0.05–3 g puts 2 of its 12
    // levels there).
    let levels = s.intensity.levels();
    let near: usize = case
        .counts
        .iter()
        .zip(levels)
        .filter(|(_, x)| (**x / band.median).ln().abs() < 1.5f64.ln())
        .map(|(n, _)| n)
        .sum();
    let placed = case.analyses() - 30; // after the coarse round
    assert!(
        2 * near > placed,
        "{near} of {placed} placed analyses near θ = {}: {:?}",
        band.median,
        case.counts
    );
    let summary = String::from_utf8(read(tmp.path(), "summary.md")).unwrap();
    assert!(summary.contains("## Precision") && summary.contains("| met |"));
    let figure = tmp.path().join("figures").join("fragility.svg");
    let svg = std::fs::read_to_string(&figure).unwrap_or_else(|e| panic!("{figure:?}: {e}"));
    assert!(svg.contains("<svg"), "{figure:?} is an SVG");
    // The coarse round's stripes hold 5 analyses, the median's several
    // times more: their points are drawn with area ∝ analyses (a stripe of
    // 5 must not look like one of 20), so the smallest circle's radius is
    // the full marker's (the largest, also the legend's) times
    // √(fewest/most), to the pixel, not below 2 px.
    let most = *case.counts.iter().max().unwrap();
    let fewest = *case.counts.iter().filter(|&&n| n > 0).min().unwrap();
    assert!(most >= 4 * fewest, "{:?}", case.counts);
    let mut radii: Vec<u32> = svg
        .split("<circle")
        .skip(1)
        .filter_map(|c| c.split(" r=\"").nth(1)?.split('"').next()?.parse().ok())
        .collect();
    radii.sort_unstable();
    radii.dedup();
    let full = *radii.last().unwrap() as f64;
    let smallest = ((full * (fewest as f64 / most as f64).sqrt()).round() as u32).max(2);
    assert!(
        radii.len() >= 2 && radii[0] == smallest,
        "point radii {radii:?} for stripes of {fewest} to {most} analyses: smallest {smallest}"
    );
}

/// A vase that cannot overturn below 0.12 g: the case stops early, with a
/// message naming the case and the range, instead of extrapolating.
#[test]
fn a_median_above_the_range_stops_the_case_with_a_message() {
    let text = VASE.replace("max = 3.0", "max = 0.12");
    let s = study(&text);
    let tmp = tempfile::tempdir().unwrap();
    let report = pipeline::run(&s, &opts(tmp.path(), 2)).unwrap();
    let case = &report.adaptive.unwrap().cases[0];
    assert_eq!(case.stop.status(), "outside_range");
    assert!(case.analyses() < 100, "stopped early: {}", case.analyses());
    let rockfrag::study::adaptive::Stop::Outside(message) = &case.stop else {
        unreachable!()
    };
    for words in ["a4_w0p2_edrawn_mudrawn", "above the range 0.05 to 0.12 g"] {
        assert!(message.contains(words), "{message}");
    }
    let summary = String::from_utf8(read(tmp.path(), "summary.md")).unwrap();
    assert!(summary.contains(message.as_str()));
}

/// The canonical spec of an adaptive study keeps the range (not the
/// lattice) and reads back to the same study.
#[test]
fn canonical_spec_keeps_the_range() {
    let s = study(VASE);
    let toml = s.to_toml();
    assert!(toml.contains("min = 0.05"), "{toml}");
    let back = Study::from_toml_unchecked(&toml, Path::new("vase-adaptive.toml")).unwrap();
    assert_eq!(back, s);
    // the lattice: 20 levels a decade over 0.05–3 g, both ends
    assert_eq!(s.intensity.levels().len(), 37);
}

#[test]
fn bad_adaptive_specs_name_the_field() {
    let cases = [
        (
            VASE.replace("precision = { median = 0.10, beta = 0.3 }", ""),
            "grid.pga",
        ),
        (
            VASE.replace("pga = { min = 0.05, max = 3.0 }", "pga = [0.1, 0.2]"),
            "fragility.precision",
        ),
        (VASE.replace("max = 3.0", "max = 0.06"), "grid.pga.max"),
        (VASE.replace("min = 0.05", "min = -1"), "grid.pga.min"),
        (
            VASE.replace("median = 0.10", "median = 5"),
            "fragility.precision.median",
        ),
        (
            VASE.replace("bootstrap = 300", "bootstrap = 0"),
            "fragility.bootstrap",
        ),
        (
            VASE.replace("[fragility]", "[fragility]\nmax_analyses = 10"),
            "fragility.max_analyses",
        ),
    ];
    for (text, field) in cases {
        let err = Study::from_toml(&text, Path::new("vase-adaptive.toml"))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("vase-adaptive.toml") && err.contains(field),
            "{field}: {err}"
        );
    }
    let s = study(VASE);
    let tmp = tempfile::tempdir().unwrap();
    let sharded = RunOptions {
        shard: Shard::new(1, 2).unwrap(),
        ..opts(tmp.path(), 1)
    };
    let err = pipeline::run(&s, &sharded).unwrap_err().to_string();
    assert!(
        err.contains("--shard") && err.contains("one case per job"),
        "{err}"
    );
    assert!(!tmp.path().join("outcomes.csv").exists());
}

/// `rockfrag run SPEC --precision 0.05` on a fixed grid sizes it from a
/// pilot: per case, the pilot's band and the records per level for ±5 %
/// (at least the pilot's 10, more when its band is wider), and writes
/// nothing where it runs. An adaptive spec is refused.
#[test]
fn precision_flag_sizes_a_fixed_grid_from_a_pilot() {
    let tmp = tempfile::tempdir().unwrap();
    let fixed = VASE
        .replace(
            "pga = { min = 0.05, max = 3.0 }",
            "pga = [0.2, 0.3, 0.4, 0.5, 0.6, 0.8]",
        )
        .replace("precision = { median = 0.10, beta = 0.3 }", "");
    std::fs::write(tmp.path().join("fixed.toml"), fixed).unwrap();
    std::fs::write(tmp.path().join("adaptive.toml"), VASE).unwrap();
    let run = |spec: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_rockfrag"))
            .args(["run", spec, "--precision", "0.05"])
            .current_dir(tmp.path())
            .output()
            .unwrap()
    };
    let out = run("fixed.toml");
    assert!(out.status.success(), "{}", common::stderr(&out));
    let text = common::stdout(&out);
    assert!(text.contains("pilot: 10 records × 6 levels"), "{text}");
    let line = text
        .lines()
        .find(|l| l.contains("a4_w0p2_edrawn_mudrawn overturning"))
        .unwrap_or_else(|| panic!("{text}"));
    // "pilot ±P %; about N records per level": N = 10 (P/5)², rounded up
    let number = |after: &str| -> f64 {
        let rest = &line[line.find(after).unwrap() + after.len()..];
        rest.split([' ', '%']).next().unwrap().parse().unwrap()
    };
    let (p, n) = (number("pilot ±"), number("about "));
    let expected = (10.0 * (p / 5.0).powi(2)).max(10.0);
    assert!((n - expected).abs() <= 0.1 * expected + 1.0, "{line}");
    let mut left: Vec<String> = std::fs::read_dir(tmp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["adaptive.toml", "fixed.toml"], "nothing written");
    let refused = run("adaptive.toml");
    assert!(!refused.status.success());
    assert!(common::stderr(&refused).contains("is adaptive"));
}

/// The manifest's counts of an adaptive run are those of its
/// outcomes.csv: uplifts (and "overturned or uplifted", the seed paper's
/// count) included. Before, an adaptive run wrote `uplifted = 0` and
/// `overturned_or_uplifted = 0` beside 62 overturned analyses. The small
/// study's H/B 4 block at e = 0, μ = ∞ lifts off in about a third of its
/// analyses, so the check cannot pass on zeros.
#[test]
fn the_manifest_counts_uplifts_of_an_adaptive_run() {
    let dir = tempfile::tempdir().unwrap();
    let spec = dir.path().join("ad.toml");
    std::fs::write(
        &spec,
        "name = \"ad\"\nseed = 5\nrecords = 200\n[motion]\nduration = 10.0\n[grid]\n\
         width = [0.5]\naspect = [4]\nrestitution = [0.0]\nfriction = [\"inf\"]\n\
         pga = { min = 0.05, max = 3.0 }\n[fragility]\nprecision = { median = 0.1, beta = 0.3 }\n",
    )
    .unwrap();
    let out = dir.path().join("ad");
    let o = common::run_spec(&spec, &out);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let mut reader = csv::Reader::from_path(out.join("outcomes.csv")).unwrap();
    let header = reader.headers().unwrap().clone();
    let at = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (ot, up) = (at("overturned"), at("uplifted"));
    let yes = |v: &str| v == "true" || v == "1";
    let (mut n, mut overturned, mut uplifted, mut either) = (0u64, 0u64, 0u64, 0u64);
    for row in reader.records() {
        let row = row.unwrap();
        n += 1;
        overturned += yes(&row[ot]) as u64;
        uplifted += yes(&row[up]) as u64;
        either += (yes(&row[ot]) || yes(&row[up])) as u64;
    }
    assert!(
        uplifted > 0 && overturned > 0,
        "{uplifted} uplifted, {overturned} overturned"
    );
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("manifest.json")).unwrap()).unwrap();
    let counts = &manifest["counts"];
    assert_eq!(counts["analyses"], n);
    assert_eq!(counts["overturned"], overturned);
    assert_eq!(counts["uplifted"], uplifted);
    assert_eq!(counts["overturned_or_uplifted"], either);
}

/// A PGV range (m/s) is an adaptive run over PGV levels: the lattice is
/// PGV's, every analysis is scaled to a lattice PGV, the curve is fitted
/// against PGV (rocking is governed by it), the summary speaks in m/s, the
/// canonical spec keeps the range in `grid.pgv`, and a PGA range beside it
/// is refused naming the field.
#[test]
fn a_pgv_range_places_pgv_levels() {
    let text = VASE.replace(
        "pga = { min = 0.05, max = 3.0 }",
        "pgv = { min = 0.05, max = 2.0 }",
    );
    let s = study(&text);
    let toml = s.to_toml();
    assert!(
        toml.contains("pgv = { min = 0.05, max = 2.0 }") || toml.contains("[grid.pgv]"),
        "{toml}"
    );
    let back = Study::from_toml_unchecked(&toml, Path::new("vase-adaptive.toml")).unwrap();
    assert_eq!(back, s);
    // about 20 levels a decade over 0.05–2 m/s, both ends: ceil(20·log10(40))
    // = 33 equal steps, 34 levels
    let levels = s.intensity.levels().to_vec();
    assert_eq!(levels.len(), 34, "{levels:?}");
    let tmp = tempfile::tempdir().unwrap();
    let report = pipeline::run(&s, &opts(tmp.path(), 2)).unwrap();
    assert_eq!(report.adaptive.unwrap().cases[0].stop.status(), "met");
    let outcomes = String::from_utf8(read(tmp.path(), "outcomes.csv")).unwrap();
    let header: Vec<&str> = outcomes.lines().next().unwrap().split(',').collect();
    let pgv = header.iter().position(|&c| c == "pgv").unwrap();
    for line in outcomes.lines().skip(1) {
        let v: f64 = line.split(',').nth(pgv).unwrap().parse().unwrap();
        // each record scaled to its level's PGV (to rounding of the scale)
        assert!(
            levels.iter().any(|l| ((v - l) / l).abs() < 1e-9),
            "pgv {v} is not a lattice level"
        );
    }
    let fragility = String::from_utf8(read(tmp.path(), "fragility.csv")).unwrap();
    assert!(
        fragility
            .lines()
            .nth(1)
            .unwrap()
            .contains(",overturning,pgv,"),
        "{fragility}"
    );
    let summary = String::from_utf8(read(tmp.path(), "summary.md")).unwrap();
    assert!(
        summary.contains("An adaptive run over PGV 0.05 to 2 m/s"),
        "{summary}"
    );
    let both = text.replace("[grid]\n", "[grid]\npga = { min = 0.05, max = 3.0 }\n");
    let err = Study::from_toml(&both, Path::new("both.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("grid.pgv") && err.contains("grid.pga"),
        "{err}"
    );
}
