//! The floor in the product (issue 32): `[support]` in the spec, the floor's
//! peaks in `outcomes.csv`, fits against them, `rockfrag floor` and
//! `simulate --floor-*`.
//!
//! Expectations: a study on a floor feels the floor record of each scaled
//! ground record (the row's outcome is `simulate` on it, bit for bit) and
//! writes its measured peaks `pfa`, `pfv` beside the ground's `pga`, `pgv`;
//! a study without `[support]` has neither the columns nor a `[support]` in
//! its canonical spec (so its hash, and its files, are those of a study
//! written before floors existed); a bad mode is refused naming the file,
//! the line, `support.floor[i].field` and the value.

mod common;

use common::{rockfrag, stderr, stdout};
use rockfrag::fragility::{FragilityOptions, read_outcomes_for};
use rockfrag::im::Im;
use rockfrag::motion::{Floor, floor_record, read_record};
use rockfrag::outcomes_csv::{Column, OutcomesFile};
use rockfrag::solver::{Analysis, Block, simulate};
use rockfrag::spec::Study;
use rockfrag::study::{RunOptions, Source};
use std::path::Path;

const ROOF: &str = r#"name = "roof"
seed = 3
records = 3

[motion]
duration = 12.0

[support]
floor = [{ period = 0.8, damping = 0.05, participation = 1.3 }]

[grid]
width = [0.6]
aspect = [3]
restitution = [0.4]
pga = [0.3, 0.6]
"#;

fn study(text: &str) -> Study {
    Study::from_toml(text, Path::new("roof.toml")).unwrap()
}

#[test]
fn support_is_read_and_written_back() {
    let s = study(ROOF);
    assert_eq!(s.floor, Floor::one_mode(0.8, 0.05, 1.3));
    let back = Study::from_toml(&s.to_toml(), Path::new("roof.toml")).unwrap();
    assert_eq!(back, s);
    // participation defaults to 1
    let one = study(&ROOF.replace(", participation = 1.3", ""));
    assert_eq!(one.floor, Floor::one_mode(0.8, 0.05, 1.0));
    // no [support], or an empty floor: the ground, and no [support] written
    // back (the canonical text, hence the hash, of a study without a floor
    // is unchanged)
    let ground_text = ROOF.replace(
        "[support]\nfloor = [{ period = 0.8, damping = 0.05, participation = 1.3 }]\n",
        "",
    );
    let ground = study(&ground_text);
    assert!(ground.floor.is_ground() && ground.floor.modes.is_empty());
    assert!(
        !ground.to_toml().contains("support"),
        "{}",
        ground.to_toml()
    );
    let empty = study(&ground_text.replace("[grid]", "[support]\nfloor = []\n\n[grid]"));
    assert_eq!(empty.hash(), ground.hash());
}

#[test]
fn bad_modes_name_file_line_field_and_value() {
    for (from, to, field, value) in [
        (
            "period = 0.8",
            "period = -0.8",
            "support.floor[0].period",
            "-0.8",
        ),
        (
            "damping = 0.05",
            "damping = 1.5",
            "support.floor[0].damping",
            "1.5",
        ),
    ] {
        let text = ROOF.replace(from, to);
        let err = Study::from_toml(&text, Path::new("roof.toml"))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("roof.toml") && err.contains(field) && err.contains(value),
            "{err}"
        );
    }
    let err = Study::from_toml(
        &ROOF.replace("participation = 1.3", "participation = 1.3, mass = 2"),
        Path::new("roof.toml"),
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("mass"), "{err}");
}

/// Each row's `pga` is the level (the ground's), `pfa`/`pfv` the peaks of
/// the floor record, and the outcome is `simulate` on that floor record,
/// bit for bit; `--im pfa` fits against the floor's peaks.
#[test]
fn a_study_on_a_floor_feels_the_floor_and_records_its_peaks() {
    let s = study(ROOF);
    let dir = tempfile::tempdir().unwrap();
    let report = rockfrag::study::run(
        &s,
        &RunOptions {
            threads: 2,
            ..RunOptions::new(dir.path())
        },
    )
    .unwrap();
    assert!(report.complete);
    let path = dir.path().join("outcomes.csv");
    let header = std::fs::read_to_string(&path).unwrap();
    assert!(
        header.starts_with("aspect,width,restitution,friction,mu_s,mu_k,pga,pgv,pfa,pfv,record,"),
        "{}",
        header.lines().next().unwrap()
    );
    let mut file = OutcomesFile::open(
        &path,
        &[Column::Im(Im::PFA), Column::Im(Im::PFV)],
        "the test",
    )
    .unwrap();
    let mut source = Source::new(&s).unwrap();
    let mut rows = 0;
    let mut amplified = 0;
    while let Some((_, row)) = file.next_row().unwrap() {
        rows += 1;
        let level = row.im(Im::PGA).unwrap();
        let ground = source.record(&s.intensity, level, row.record, s.g).unwrap();
        let felt = floor_record(&ground, &s.floor).unwrap();
        assert_eq!(row.im(Im::PFA), Some(felt.pga() / s.g));
        assert_eq!(row.im(Im::PFV), Some(felt.pgv()));
        assert_eq!(row.im(Im::PGV), Some(ground.pgv()));
        let block = Block::new(0.6, 3.0, s.g).unwrap();
        let mut want = simulate(&Analysis::new(block, 0.4), &felt, &s.solver, None).unwrap();
        // what outcomes.csv does not hold (no [output] time_in_mode, stats)
        want.time_in_mode = Default::default();
        want.transitions = Default::default();
        want.stats = Default::default();
        assert_eq!(row.outcome(), Some(&want));
        amplified += usize::from(row.im(Im::PFA).unwrap() > level);
    }
    assert_eq!(rows, 6);
    // a 0.8-s building under firm-soil motion amplifies at the roof
    assert!(amplified >= 4, "{amplified} of 6 rows with PFA > PGA");

    let options = FragilityOptions {
        im: Some(Im::PFA),
        ..FragilityOptions::default()
    };
    let data = read_outcomes_for(&path, &options).unwrap();
    let mut want: Vec<f64> = Vec::new();
    let mut file = OutcomesFile::open(&path, &[], "the test").unwrap();
    while let Some((_, row)) = file.next_row().unwrap() {
        want.push(row.im(Im::PFA).unwrap());
    }
    let got: Vec<f64> = data.cases[0].trials.iter().map(|t| t.im).collect();
    assert_eq!(got, want);
}

/// A study on the ground cannot be fitted against the floor's peaks: the
/// error names the file and the missing column.
#[test]
fn fitting_a_ground_study_against_pfa_names_the_missing_column() {
    let text = ROOF.replace(
        "[support]\nfloor = [{ period = 0.8, damping = 0.05, participation = 1.3 }]\n",
        "",
    );
    let s = study(&text);
    let dir = tempfile::tempdir().unwrap();
    rockfrag::study::run(&s, &RunOptions::new(dir.path())).unwrap();
    let path = dir.path().join("outcomes.csv");
    let options = FragilityOptions {
        im: Some(Im::PFA),
        ..FragilityOptions::default()
    };
    let err = read_outcomes_for(&path, &options)
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("outcomes.csv") && err.contains("pfa"), "{err}");
}

/// `rockfrag floor` writes the floor record of a record file with its time
/// step; zero participation gives the record back; `simulate --floor-*`
/// solves the block on that floor.
#[test]
fn the_floor_command_and_simulate_flags() {
    let dir = tempfile::tempdir().unwrap();
    let ground = dir.path().join("ground.csv");
    let roof = dir.path().join("roof.csv");
    let p = |p: &Path| p.to_str().unwrap().to_string();
    let o = rockfrag(&[
        "motion",
        "--seed",
        "4",
        "--pga",
        "0.5",
        "--out",
        &p(&ground),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = rockfrag(&[
        "floor",
        &p(&ground),
        "--period",
        "0.8",
        "--damping",
        "0.05",
        "--participation",
        "1.3",
        "--out",
        &p(&roof),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("PFA"), "{}", stderr(&o));
    let g = read_record(&ground, 9.81).unwrap();
    let r = read_record(&roof, 9.81).unwrap();
    assert_eq!(r.dt, g.dt);
    assert_eq!(r.len(), g.len());
    let want = floor_record(&g, &Floor::one_mode(0.8, 0.05, 1.3)).unwrap();
    assert_eq!(r.acc, want.acc);
    assert_eq!(r.vel, want.vel);
    assert_eq!(r.disp, want.disp);

    // standard output, zero participation: the record itself
    let o = rockfrag(&[
        "floor",
        &p(&ground),
        "--period",
        "0.8",
        "--damping",
        "0.05",
        "--participation",
        "0",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stdout(&o), std::fs::read_to_string(&ground).unwrap());

    // simulate on the floor = simulate on the floor's record
    let on_floor = rockfrag(&[
        "simulate",
        "--motion",
        &p(&ground),
        "--aspect",
        "3",
        "--width",
        "0.6",
        "--floor-period",
        "0.8",
        "--floor-damping",
        "0.05",
        "--floor-participation",
        "1.3",
        "--json",
    ]);
    let on_record = rockfrag(&[
        "simulate",
        "--motion",
        &p(&roof),
        "--aspect",
        "3",
        "--width",
        "0.6",
        "--json",
    ]);
    assert!(on_floor.status.success(), "{}", stderr(&on_floor));
    assert_eq!(stdout(&on_floor), stdout(&on_record));

    // a damping without a period, or counts that do not match: refused
    for args in [
        vec!["--floor-damping", "0.05"],
        vec![
            "--floor-period",
            "0.8",
            "--floor-period",
            "0.3",
            "--floor-damping",
            "0.05",
            "--floor-participation",
            "1.3",
            "--floor-participation",
            "-0.4",
            "--floor-participation",
            "0.1",
        ],
        vec!["--floor-period", "0.8"],
    ] {
        let mut all = vec!["simulate", "--seed", "1", "--pga", "0.3"];
        all.extend(args.iter().copied());
        let o = rockfrag(&all);
        assert!(!o.status.success(), "{args:?} accepted");
        assert!(stderr(&o).contains("--floor-"), "{}", stderr(&o));
    }
}

/// The hospital example (studies/hospital-equipment*.toml, bootstrap off):
/// the roof's curve against ground PGA lies left of the ground's (the
/// building amplifies the records near its period), and the comparison
/// figure draws both.
#[test]
fn the_hospital_roof_curve_lies_left_of_the_ground_curve() {
    let studies = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies");
    let dir = tempfile::tempdir().unwrap();
    let mut medians = Vec::new();
    for name in ["hospital-equipment-ground", "hospital-equipment"] {
        let mut s = Study::load(&studies.join(format!("{name}.toml"))).unwrap();
        s.fragility.as_mut().unwrap().bootstrap = 0;
        s.output.figures = false;
        let out = dir.path().join(name);
        rockfrag::pipeline::run(&s, &RunOptions::new(&out)).unwrap();
        let rows = rockfrag::fragility::read_fragility_csv(&out.join("fragility.csv")).unwrap();
        let (median, beta) = rows[0].fit().expect("fitted");
        assert!(beta > 0.1 && beta < 1.0, "{name}: β = {beta}");
        medians.push(median);
    }
    let (ground, roof) = (medians[0], medians[1]);
    // measured (against the pairs' RotD50 PGA): 1.07 g and 0.557 g; the
    // building halves the median
    assert!(roof < 0.7 * ground, "roof {roof} g, ground {ground} g");
    let figure = rockfrag::figures::CompareFigure::from_folders(
        "t",
        &[
            (
                "ground".into(),
                dir.path().join("hospital-equipment-ground"),
            ),
            ("roof".into(), dir.path().join("hospital-equipment")),
        ],
    )
    .unwrap();
    assert_eq!(figure.series.len(), 2);
    // the example's records are synthetic pairs (components = 2)
    assert_eq!(figure.x_label, "ground RotD50 PGA (g)");
    assert!(
        figure
            .series
            .iter()
            .all(|s| !s.fit.is_empty() && s.observed.len() == 16)
    );
    figure.save(&dir.path().join("compare.svg")).unwrap();
}
