//! Fitting a finished study against an IM its `outcomes.csv` does not hold
//! (issue 38): the records are remade from the folder's manifest and
//! measured, no analysis runs and `outcomes.csv` keeps its bytes and mtime.

mod common;

use std::path::Path;

use common::{rockfrag, run_spec, stderr};
use rockfrag::fragility::{FragilityOptions, read_outcomes, read_outcomes_for};
use rockfrag::im::{Im, spectral_acceleration};
use rockfrag::spec::Study;
use rockfrag::study::{Source, measure_records};

fn spec() -> &'static Path {
    Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/specs/small.toml"
    ))
}

/// The small study with stripes from none to most overturning (levels
/// 0.2–2 g; `aspect = [6]` alone when `one_aspect`), plus `extra` spec
/// lines, run into `dir/small`, which it returns.
fn striped_study(dir: &Path, one_aspect: bool, extra: &str) -> std::path::PathBuf {
    let mut text = std::fs::read_to_string(spec())
        .unwrap()
        .replace("pga = [0.4, 0.8]", "pga = [0.2, 0.5, 1.0, 2.0]");
    if one_aspect {
        text = text.replace("aspect = [4, 6]", "aspect = [6]");
    }
    let path = dir.join("small.toml");
    std::fs::write(&path, text + extra).unwrap();
    let out = dir.join("small");
    let o = run_spec(&path, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    out
}

/// `rockfrag fragility DIR --im "sa(1.0)"` on a finished folder: the fit is
/// against Sa(1.0 s) (fragility.csv's `im`, fragility.xml's `SA(1.0)`),
/// each analysis's IM is the 5 %-damped Sa of the record it felt as the
/// study remakes it (to the bit), and outcomes.csv is untouched.
#[test]
fn a_refit_against_sa_measures_the_records_and_runs_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = striped_study(dir.path(), true, "");
    let outcomes = out.join("outcomes.csv");
    let before = (
        std::fs::read(&outcomes).unwrap(),
        std::fs::metadata(&outcomes).unwrap().modified().unwrap(),
    );
    let o = rockfrag(&[
        "fragility",
        out.to_str().unwrap(),
        "--im",
        "SA(1.0)",
        "--bootstrap",
        "0",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let after = (
        std::fs::read(&outcomes).unwrap(),
        std::fs::metadata(&outcomes).unwrap().modified().unwrap(),
    );
    assert!(before == after, "outcomes.csv was rewritten");
    let csv = std::fs::read_to_string(out.join("fragility.csv")).unwrap();
    assert!(
        csv.lines().skip(1).all(|l| l.contains(",sa(1.0),")),
        "{csv}"
    );
    let xml = std::fs::read_to_string(out.join("fragility.xml")).unwrap();
    assert!(xml.contains("imt=\"SA(1.0)\""), "{xml}");

    // each trial's IM is Sa(1.0 s) of its motion, remade by the study's source
    let sa = Im::sa(1.0).unwrap();
    let measured = measure_records(&out, sa).unwrap();
    let study = Study::load(&dir.path().join("small.toml")).unwrap();
    assert_eq!(
        measured.len(),
        study.records() * study.intensity.levels().len()
    );
    let mut source = Source::new(&study).unwrap();
    for &level in study.intensity.levels() {
        for record in 0..study.records() {
            let m = source.motion(&study, level, record).unwrap();
            let want = spectral_acceleration(&m.felt, 1.0).unwrap() / study.g;
            assert_eq!(measured.get(level, record), Some(want));
            // a 1-s oscillator under these records is not the PGA
            assert!((want / level - 1.0).abs() > 0.01, "{want} at {level} g");
        }
    }
    // without the measured values the reader refuses, saying what it needs
    let e = read_outcomes(&outcomes, sa).unwrap_err().to_string();
    assert!(e.contains("sa(1.0)") && e.contains("study folder"), "{e}");
    let options = FragilityOptions {
        im: Some(sa),
        measured: vec![std::sync::Arc::new(measured.clone())],
        ..FragilityOptions::default()
    };
    let outcomes = read_outcomes_for(&outcomes, &options).unwrap();
    for case in &outcomes.cases {
        for t in &case.trials {
            let record: usize = case.records[t.record].parse().unwrap();
            assert_eq!(Some(t.im), measured.get(t.level, record));
        }
    }
}

/// A floor's or a pair's IM on a study on the ground of single records is
/// refused before anything is written, saying why.
#[test]
fn an_im_the_motions_do_not_have_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("small");
    assert!(run_spec(spec(), &out).status.success());
    let fragility = std::fs::read(out.join("fragility.csv")).ok();
    for (im, why) in [
        ("sa(1.0)-floor", "no floor"),
        ("pgv/pga-rotd50", "no record pairs"),
    ] {
        let o = rockfrag(&["fragility", out.to_str().unwrap(), "--im", im]);
        assert!(!o.status.success());
        assert!(
            stderr(&o).contains(im) && stderr(&o).contains(why),
            "{}",
            stderr(&o)
        );
        assert_eq!(std::fs::read(out.join("fragility.csv")).ok(), fragility);
    }
}

/// `--im` repeated on a finished folder: every IM fitted, the summary's
/// `## Intensity measures` ranks them by β for every case and limit state
/// (ascending, unfitted last), with the residual slope against
/// ln(PGV/PGA); outcomes.csv keeps its bytes and mtime; fragility.csv is
/// the first IM's.
#[test]
fn repeated_im_ranks_the_measures_by_beta() {
    let dir = tempfile::tempdir().unwrap();
    let out = striped_study(dir.path(), false, "");
    let outcomes = out.join("outcomes.csv");
    let before = (
        std::fs::read(&outcomes).unwrap(),
        std::fs::metadata(&outcomes).unwrap().modified().unwrap(),
    );
    let o = rockfrag(&[
        "fragility",
        out.to_str().unwrap(),
        "--im",
        "pgv",
        "--im",
        "pga",
        "--im",
        "sa(1.0)",
        "--bootstrap",
        "50",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let after = (
        std::fs::read(&outcomes).unwrap(),
        std::fs::metadata(&outcomes).unwrap().modified().unwrap(),
    );
    assert!(before == after, "outcomes.csv was rewritten");
    let csv = std::fs::read_to_string(out.join("fragility.csv")).unwrap();
    assert!(csv.lines().skip(1).all(|l| l.contains(",pgv,")), "{csv}");
    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    let section = summary
        .split("## Intensity measures")
        .nth(1)
        .expect("the section");
    let section = section.split("\n## ").next().unwrap();
    let rows: Vec<Vec<&str>> = section
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| case"))
        .map(|l| l.split(" | ").collect())
        .collect();
    // 4 cases × 1 limit state × 3 IMs
    assert_eq!(rows.len(), 12, "{section}");
    for group in rows.chunks(3) {
        let ims: Vec<&str> = group.iter().map(|r| r[3]).collect();
        for im in ["PGA", "PGV", "Sa(1.0 s)"] {
            assert!(ims.contains(&im), "{ims:?}");
        }
        let betas: Vec<f64> = group
            .iter()
            .map(|r| {
                r[5].split(' ')
                    .next()
                    .unwrap()
                    .parse()
                    .unwrap_or(f64::INFINITY)
            })
            .collect();
        assert!(betas.windows(2).all(|w| w[0] <= w[1]), "{betas:?}");
        assert!(
            group
                .iter()
                .all(|r| r[6].contains('±') || r[7].contains("not fitted"))
        );
    }
}

/// A spec asking for a floor's or a pair's IM of a study that has neither
/// is refused when read, naming `fragility.im`, its line and what it needs,
/// before any analysis runs.
#[test]
fn a_spec_fitting_against_an_im_its_motions_lack_is_refused() {
    let base = std::fs::read_to_string(spec()).unwrap();
    for (im, needs) in [("sa(1.0)-floor", "floor"), ("pga-rotd50", "record pairs")] {
        let text = format!("{base}\n[fragility]\nim = \"{im}\"\n");
        let e = Study::from_toml(&text, Path::new("s.toml"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("fragility.im") && e.contains(im) && e.contains(needs),
            "{e}"
        );
    }
    let ok = format!("{base}\n[fragility]\nim = \"sa-avg(0.5,2)\"\n");
    assert!(Study::from_toml(&ok, Path::new("s.toml")).is_ok());
}

/// `rockfrag fragility DIR` without `--im` refits against the IM the
/// study's spec asked for (`[fragility] im = "pgv"` here), so a refit of a
/// finished folder gives the run's own fragility.csv, byte for byte. Before
/// issue 38's IM type, a refit always fell back to PGA: the hospital pairs
/// study's refit read 0.608 g (PGA) where its run had fitted 0.568 g (RotD50).
#[test]
fn a_refit_without_im_keeps_the_studys_own_im() {
    let dir = tempfile::tempdir().unwrap();
    let out = striped_study(
        dir.path(),
        true,
        "\n[fragility]\nim = \"pgv\"\nbootstrap = 0\n",
    );
    let fitted = std::fs::read_to_string(out.join("fragility.csv")).unwrap();
    assert!(
        fitted.lines().skip(1).all(|l| l.contains(",pgv,")),
        "the run did not fit against pgv:\n{fitted}"
    );
    let o = rockfrag(&["fragility", out.to_str().unwrap(), "--bootstrap", "0"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let refit = std::fs::read_to_string(out.join("fragility.csv")).unwrap();
    assert_eq!(fitted, refit, "the refit changed the study's fit");
}

/// An IM whose name holds a comma (`sa-avg(0.2,2.0)`) is quoted in the CSV
/// files (RFC 4180), so fragility.csv reads back with as many fields as
/// its header and its readers get to the IM itself: `export openquake`
/// refuses the IM by name (OpenQuake has no IMT for it), not with a CSV
/// error. Before, the bare comma gave 37 fields under a 36-field header and
/// every reader of the folder failed.
#[test]
fn an_im_named_with_a_comma_is_quoted_in_the_csv_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = striped_study(dir.path(), true, "");
    let folder = out.to_str().unwrap();
    let o = rockfrag(&[
        "fragility",
        folder,
        "--im",
        "sa-avg(0.2,2)",
        "--bootstrap",
        "0",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for file in ["fragility.csv", "fragility_curves.csv"] {
        let mut reader = csv::Reader::from_path(out.join(file)).unwrap();
        let width = reader.headers().unwrap().len();
        for row in reader.records() {
            let row = row.unwrap_or_else(|e| panic!("{file}: {e}"));
            assert_eq!(row.len(), width, "{file}: {row:?}");
            assert!(
                row.iter().any(|f| f == "sa-avg(0.2,2.0)"),
                "{file}: {row:?}"
            );
        }
    }
    let oq = dir.path().join("oq");
    let hazard = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/hazard/hazard_curve-mean-PGA_example.csv"
    );
    let o = rockfrag(&[
        "export",
        "openquake",
        folder,
        "--hazard",
        hazard,
        "--site",
        "0",
        "--out",
        oq.to_str().unwrap(),
    ]);
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(
        err.contains("sa-avg(0.2,2.0)") && !err.contains("CSV error"),
        "{err}"
    );
}
