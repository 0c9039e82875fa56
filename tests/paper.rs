//! Reproducing the seed paper (issue 13): the built-in study's records are
//! the rad/s reading of section 4, and under that reading the e = 0 column
//! comes out as the paper's, where the literal reading does not.
//!
//! The ensemble statistics use 2 ensembles per reading (4,800 analyses per
//! reading would be K = 4; `rockfrag paper --replicates 12` is the full check,
//! committed as `studies/paper-check.md`).

use rockfrag::paper::{CheckOptions, check, paper_totals, readings, score};
use rockfrag::spec::{Motions, Study};

/// The built-in study's motion settings are the rad/s-grid reading, and its
/// summary compares with the paper's tables (it is recognised as the paper's).
#[test]
fn the_built_in_study_uses_the_rad_s_grid_reading() {
    let study = Study::shenton_jones();
    let Motions::Synthetic { settings, .. } = &study.motions else {
        panic!("the built-in study is synthetic");
    };
    let grid = readings()
        .into_iter()
        .find(|r| r.name == "rad/s grid")
        .unwrap();
    assert_eq!(*settings, grid.settings);
    // Δω = 0.05 rad/s and ω_max = 25 rad/s, in Hz (Δf rounded by < 1e-4).
    let two_pi = 2.0 * std::f64::consts::PI;
    assert!(
        (settings.frequency_step() * two_pi / 0.05 - 1.0).abs() < 1e-4,
        "{}",
        settings.frequency_step()
    );
    assert!((settings.f_max * two_pi - 25.0).abs() < 1e-12);
    // The literal reading is kept as its own spec file.
    let written = Study::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/shenton-jones-as-written.toml"
    )))
    .unwrap();
    let Motions::Synthetic { settings: w, .. } = &written.motions else {
        panic!("synthetic");
    };
    assert_eq!(*w, readings()[0].settings);
}

/// Under the rad/s grid the e = 0 total is the paper's 159 within the
/// ensemble noise (one ensemble's sd is about 8, so the mean of two is
/// within ±25 of 159 unless the reading is wrong: the literal reading's
/// mean is about 122), near-threshold rotations are within a factor of 3
/// of the paper's, and the paper's own trend over e is significant
/// (Z = −3.05) while ours is flat.
#[test]
fn the_rad_s_reading_reproduces_the_e0_column_and_the_literal_one_does_not() {
    let options = CheckOptions {
        replicates: 2,
        seed: 1991,
        threads: 0,
    };
    let results = check(&options, |_| {}).unwrap();
    assert_eq!(paper_totals(), [159, 160, 138, 127]);
    let by_name = |name: &str| {
        let r = results.iter().find(|r| r.reading.name == name).unwrap();
        score(r)
    };
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let grid = by_name("rad/s grid");
    let written = by_name("as written");
    let g0 = mean(&grid.totals[0]);
    let w0 = mean(&written.totals[0]);
    assert!((g0 - 159.0).abs() < 25.0, "rad/s grid e = 0 total {g0}");
    assert!(w0 < 140.0, "as written e = 0 total {w0}");
    assert!(
        grid.e0_cells_differing <= 2.0,
        "{}",
        grid.e0_cells_differing
    );
    for &(aspect, pga, e, ours, theirs) in &grid.near_threshold {
        let ratio = ours / theirs;
        assert!(
            (1.0 / 3.0..=3.0).contains(&ratio),
            "H/B {aspect} at {pga} g, e = {e}: {ours} against the paper's {theirs}"
        );
    }
    // The paper's fall of overturning with e: flat under the physics, a
    // clear negative trend under the rock rule (Z ≈ −7 over 12 ensembles,
    // about −2.9 over two).
    let rule = by_name("rad/s grid, rock rule");
    assert!(grid.trend_z > -2.0, "physics trend Z = {}", grid.trend_z);
    assert!(rule.trend_z < -2.0, "rock-rule trend Z = {}", rule.trend_z);
    assert_eq!(
        rule.totals[0], grid.totals[0],
        "e = 0 is unaffected by the rule"
    );
    // The literal reading's near-threshold rotations are far too small.
    let (_, _, _, ours, theirs) = written.near_threshold[4]; // H/B 4 at 0.3 g, e = 0
    assert!(ours / theirs < 0.2, "{ours} / {theirs}");
}

/// `summary.md` of the paper's study states the tests: the trend over e for
/// ours and the paper's, and Fisher's test per cell.
#[test]
fn the_summary_of_the_papers_study_carries_the_tests() {
    let dir = tempfile::tempdir().unwrap();
    let mut study = Study::shenton_jones();
    study.output.figures = false;
    study.fragility = None;
    let opts = rockfrag::study::RunOptions::new(dir.path());
    assert!(rockfrag::pipeline::run(&study, &opts).unwrap().run.complete);
    let text = std::fs::read_to_string(dir.path().join("summary.md")).unwrap();
    assert!(text.contains("## Statistics"), "{text}");
    assert!(
        text.contains("The paper's: Z = -3.05, two-sided p = **0.00230\\***"),
        "{text}"
    );
    assert!(text.contains("| p (Fisher) |"));
    assert!(text.contains("of the 44 published cells differ from the paper's count at 5 %"));
}
