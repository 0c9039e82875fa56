//! Record pairs in a study (issue 32 part 2): `record_files` as pairs
//! `[["a-H1", "a-H2"], …]`, the direction φ a block faces from
//! `grid.orientation` or drawn (`uncertainty.orientation`, uniform on
//! [0°, 180°) by default), the `phi`, `pga_rotd50` and `pgv_rotd50` columns
//! and fits against `pga-rotd50`.
//!
//! Expectations: a pair at φ = 0° and 90° is its two components, bit for
//! bit, so a pair study on a grid of those two angles gives the outcomes of
//! a study of the components one by one; with PGA levels the pair is scaled
//! to its RotD50 and the row is `simulate --motion2 --orientation` on it, to
//! the bit; drawn angles are uniform and shared by every level and case of a
//! record; a study without pairs has none of the new columns; bad pairs and
//! orientations are refused naming the file, the field and the value.

mod common;

use common::{rockfrag, stderr, stdout};
use rockfrag::fragility::{FragilityOptions, read_outcomes_for};
use rockfrag::im::Im;
use rockfrag::motion::{MeasuredPair, Pair, SynthesisSettings, read_record, synthesize, write_csv};
use rockfrag::outcomes_csv::{Column, OutcomeRow, OutcomesFile};
use rockfrag::spec::{Motions, Orientation, Study};
use rockfrag::study::RunOptions;
use std::path::Path;

/// Writes three synthetic pairs `pK-H1.csv`, `pK-H2.csv` (independent
/// records of one ensemble, H2 weaker) of 12 s into `dir`.
fn write_pairs(dir: &Path) {
    let settings = SynthesisSettings {
        duration: 12.0,
        ..SynthesisSettings::default()
    };
    for k in 0..3u64 {
        let h1 = synthesize(&settings, 5, 2 * k, 0.4 * 9.81).unwrap();
        let h2 = synthesize(&settings, 5, 2 * k + 1, 0.3 * 9.81).unwrap();
        write_csv(dir.join(format!("p{k}-H1.csv")), &h1).unwrap();
        write_csv(dir.join(format!("p{k}-H2.csv")), &h2).unwrap();
    }
}

const PAIRS: &str = r#"record_files = [["p0-H1.csv", "p0-H2.csv"], ["p1-H1.csv", "p1-H2.csv"], ["p2-H1.csv", "p2-H2.csv"]]"#;

/// A spec of the three pairs with `extra` (orientation, levels) and a grid
/// of two blocks.
fn spec(dir: &Path, name: &str, records: &str, extra: &str) -> Study {
    let text = format!(
        "name = \"{name}\"\n{records}\n\n[grid]\nwidth = [0.4]\naspect = [3, 4]\n\
         restitution = [0.5]\n{extra}\n"
    );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, &text).unwrap();
    Study::load(&path).unwrap()
}

fn run(study: &Study, out: &Path) -> Vec<OutcomeRow> {
    let report = rockfrag::study::run(
        study,
        &RunOptions {
            threads: 2,
            ..RunOptions::new(out)
        },
    )
    .unwrap();
    assert!(report.complete);
    let mut file = OutcomesFile::open(&out.join("outcomes.csv"), &[], "the test").unwrap();
    let mut rows = Vec::new();
    while let Some((_, row)) = file.next_row().unwrap() {
        rows.push(row);
    }
    rows
}

/// On a grid of 0° and 90° with scale factors (which multiply a pair as
/// they multiply a record), member 2k + j of the pair study is component j
/// of pair k: every outcome, `pga` and `pgv` equal to the bit those of the
/// study of the six components one by one, whose record 2k + j is the same
/// file. The pair study adds `pga_rotd50`, `pgv_rotd50` and `phi`.
#[test]
fn pairs_at_the_axes_are_their_components() {
    let dir = tempfile::tempdir().unwrap();
    write_pairs(dir.path());
    let levels = "scale_factors = [1.0, 2.0]\norientation = [0, 90]";
    let pairs = spec(dir.path(), "pairs", PAIRS, levels);
    let singles = spec(
        dir.path(),
        "singles",
        r#"record_files = ["p0-H1.csv", "p0-H2.csv", "p1-H1.csv", "p1-H2.csv", "p2-H1.csv", "p2-H2.csv"]"#,
        "scale_factors = [1.0, 2.0]",
    );
    assert_eq!(pairs.records(), 6);
    let a = run(&pairs, &dir.path().join("a"));
    let b = run(&singles, &dir.path().join("b"));
    assert_eq!(a.len(), 2 * 2 * 6);
    assert_eq!(a.len(), b.len());
    let mut rocked = 0;
    for (x, y) in a.iter().zip(&b) {
        assert_eq!((x.case, x.record, x.scale), (y.case, y.record, y.scale));
        assert_eq!(x.result, y.result, "record {}", x.record);
        assert_eq!(
            (x.im(Im::PGA), x.im(Im::PGV)),
            (y.im(Im::PGA), y.im(Im::PGV))
        );
        assert_eq!(x.phi, Some(if x.record % 2 == 0 { 0.0 } else { 90.0 }));
        // the scaled pair's RotD50 (a measured peak: scale-factor levels)
        assert!(
            x.im(Im::PGA_ROTD50)
                .is_some_and(|v| v.is_finite() && v > 0.0)
        );
        assert!(y.im(Im::PGA_ROTD50).is_none() && y.phi.is_none());
        rocked += usize::from(x.outcome().is_some_and(|o| o.theta_max_over_theta_c > 0.1));
    }
    assert!(
        rocked >= 6,
        "only {rocked} rows rocked: the test would be weak"
    );
    let header = |d: &str| {
        std::fs::read_to_string(dir.path().join(d).join("outcomes.csv"))
            .unwrap()
            .lines()
            .next()
            .unwrap()
            .to_string()
    };
    assert!(
        header("a").starts_with(
            "aspect,width,restitution,friction,mu_s,mu_k,pga,pgv,pga_rotd50,pgv_rotd50,\
             record,record_file,phi,scale,"
        ),
        "{}",
        header("a")
    );
    // a study without pairs has none of the pair columns
    assert!(
        !header("b").contains("rotd50") && !header("b").contains("phi"),
        "{}",
        header("b")
    );
}

/// With PGA levels the pair is scaled to its RotD50: `pga_rotd50` is the
/// level, the RotD50 of the scaled pair measured again is the level to
/// 1e-12 (rounding of the scale), `pga` is the peak of the component the
/// block feels (at most the pair's RotD100, at least 0), and the outcome is
/// `rockfrag simulate --motion H1 --motion2 H2 --orientation φ --pga level`,
/// bit for bit.
#[test]
fn a_pair_is_scaled_to_its_rotd50_and_solved_as_simulate_solves_it() {
    let dir = tempfile::tempdir().unwrap();
    write_pairs(dir.path());
    let study = spec(dir.path(), "rotd", PAIRS, "pga = [0.3, 0.6]");
    let rows = run(&study, &dir.path().join("out"));
    let Motions::Pairs { pairs, orientation } = &study.motions else {
        panic!("a study of pairs")
    };
    assert!(matches!(orientation, Orientation::Drawn { .. }));
    let mut checked = 0;
    for row in &rows {
        let level = row.im(Im::PGA_ROTD50).unwrap();
        assert!(level == 0.3 || level == 0.6, "{level}");
        let (p, phi) = orientation.member(row.record);
        assert_eq!(row.phi, Some(phi));
        let read = |f: &rockfrag::spec::RecordFile| read_record(&f.path, study.g).unwrap();
        let m =
            MeasuredPair::new(Pair::new(read(&pairs[p][0]), read(&pairs[p][1])).unwrap()).unwrap();
        let k = level * study.g / m.pga;
        let scaled = Pair {
            h1: m.pair.h1.clone().scaled(k),
            h2: m.pair.h2.clone().scaled(k),
        };
        let rotd50 = rockfrag::motion::rotd(&scaled, 50.0).unwrap() / study.g;
        assert!((rotd50 / level - 1.0).abs() < 1e-12, "{rotd50} vs {level}");
        let rotd100 = rockfrag::motion::rotd(&scaled, 100.0).unwrap() / study.g;
        let felt = m.felt(k, phi).unwrap();
        assert_eq!(row.im(Im::PGA), Some(felt.pga() / study.g));
        assert!(row.im(Im::PGA).unwrap() <= rotd100 * (1.0 + 1e-12));
        // one row per level through the binary (the others are the same path)
        if row.case.aspect == 3.0 && row.record < 2 {
            let file = |j: usize| pairs[p][j].path.to_str().unwrap().to_string();
            let o = rockfrag(&[
                "simulate",
                "--aspect",
                "3",
                "--width",
                "0.4",
                "--restitution",
                "0.5",
                "--motion",
                &file(0),
                "--motion2",
                &file(1),
                "--orientation",
                &phi.to_string(),
                "--pga",
                &level.to_string(),
                "--json",
            ]);
            assert!(o.status.success(), "{}", stderr(&o));
            // read the number as printed (serde_json's default parser may
            // round the last bit; Rust's `parse` is exact)
            let out = stdout(&o);
            let key = "\"theta_max_over_theta_c\":";
            let at = out.find(key).expect("θmax/θc in the JSON") + key.len();
            let end = out[at..].find([',', '}']).unwrap();
            let theta: f64 = out[at..at + end].trim().parse().unwrap();
            let want = row.outcome().unwrap().theta_max_over_theta_c;
            assert_eq!(theta, want, "record {} at {level} g", row.record);
            checked += 1;
        }
    }
    assert_eq!(checked, 4);
}

/// Drawn directions are uniform on [0°, 180°): over 4,000 records the
/// Kolmogorov–Smirnov distance to U(0, 180) is below 1.63/√n = 0.026 (the
/// 1 % critical value: a fixed seed, so the test passes or fails for good,
/// and a draw that is not uniform, e.g. [0, 90) or a bias of a few degrees,
/// is far above it). In a study, a record's direction is the same at every
/// level and for every case.
#[test]
fn drawn_directions_are_uniform_and_shared_by_a_records_analyses() {
    let orientation = Orientation::unknown(1);
    let n = 4000;
    let mut phi: Vec<f64> = (0..n).map(|r| orientation.member(r).1).collect();
    phi.sort_by(f64::total_cmp);
    assert!(phi[0] >= 0.0 && phi[n - 1] < 180.0);
    let d = phi
        .iter()
        .enumerate()
        .map(|(i, &x)| {
            let f = x / 180.0;
            (f - i as f64 / n as f64)
                .abs()
                .max(((i + 1) as f64 / n as f64 - f).abs())
        })
        .fold(0.0, f64::max);
    assert!(d < 1.63 / (n as f64).sqrt(), "KS distance {d}");

    let dir = tempfile::tempdir().unwrap();
    write_pairs(dir.path());
    let study = spec(dir.path(), "drawn", PAIRS, "pga = [0.3, 0.6]");
    let rows = run(&study, &dir.path().join("out"));
    for r in 0..3 {
        let mine: Vec<f64> = rows
            .iter()
            .filter(|x| x.record == r)
            .map(|x| x.phi.unwrap())
            .collect();
        assert_eq!(mine.len(), 2 * 2, "2 cases × 2 levels");
        assert!(mine.iter().all(|&p| p == mine[0]), "record {r}: {mine:?}");
    }
    // a different seed draws different directions
    let other = spec(
        dir.path(),
        "drawn2",
        PAIRS,
        "pga = [0.3, 0.6]\n\n[uncertainty]\nseed = 2\norientation = { dist = \"uniform\", min = 0, max = 180 }",
    );
    let Motions::Pairs { orientation, .. } = &other.motions else {
        panic!()
    };
    assert_ne!(orientation.member(0).1, rows[0].phi.unwrap());
}

/// The fit of a study of pairs is against the pair's RotD50 PGA unless the
/// spec names a measure, and the NRML calls it PGA (OpenQuake's hazard is,
/// for most of its models, the RotD50); `pga` stays available, against the
/// felt component.
#[test]
fn pairs_are_fitted_against_rotd50_by_default() {
    let dir = tempfile::tempdir().unwrap();
    write_pairs(dir.path());
    let study = spec(
        dir.path(),
        "fit",
        PAIRS,
        "pga = [0.5, 1.0, 1.5, 2.0]\n\n[fragility]\nbootstrap = 0",
    );
    assert_eq!(study.fragility.as_ref().unwrap().im, Some(Im::PGA_ROTD50));
    let named = spec(
        dir.path(),
        "fit-pga",
        PAIRS,
        "pga = [0.5, 1.0, 1.5, 2.0]\n\n[fragility]\nbootstrap = 0\nim = \"pga\"",
    );
    assert_eq!(named.fragility.as_ref().unwrap().im, Some(Im::PGA));
    // the fit on completion is the command's (`rockfrag run`)
    let out = dir.path().join("out");
    let o = common::run_spec(&dir.path().join("fit.toml"), &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let fit = std::fs::read_to_string(out.join("fragility.csv")).unwrap();
    assert!(fit.contains(",pga-rotd50,"), "{fit}");
    let xml = std::fs::read_to_string(out.join("fragility.xml")).unwrap();
    assert!(xml.contains("imt=\"PGA\""), "{xml}");
    // the summary says what the levels and the `pga` column are
    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(
        summary.contains("Record pairs: under each record the blocks face")
            && summary.contains("the levels are the pair's RotD50 PGA")
            && summary.contains("| RotD50 PGA (g) |"),
        "{summary}"
    );
    // the trials of the fit are at the levels
    let path = out.join("outcomes.csv");
    let data = read_outcomes_for(
        &path,
        &FragilityOptions {
            im: Some(Im::PGA_ROTD50),
            ..FragilityOptions::default()
        },
    )
    .unwrap();
    assert!(
        data.cases[0]
            .trials
            .iter()
            .all(|t| [0.5, 1.0, 1.5, 2.0].contains(&t.im))
    );
    let felt = read_outcomes_for(&path, &FragilityOptions::default()).unwrap();
    assert!(
        felt.cases[0]
            .trials
            .iter()
            .any(|t| ![0.5, 1.0, 1.5, 2.0].contains(&t.im))
    );
    let mut file = OutcomesFile::open(&path, &[Column::Phi], "the test").unwrap();
    assert!(file.next_row().unwrap().is_some());
}

/// Bad pairs and orientations are refused naming the spec, the field and
/// the value.
#[test]
fn bad_pairs_and_orientations_are_named() {
    let dir = tempfile::tempdir().unwrap();
    write_pairs(dir.path());
    let cases = [
        (
            r#"record_files = [["p0-H1.csv", "p0-H2.csv"], "p1-H1.csv"]"#,
            "",
            "record_files[1]",
            "p1-H1.csv",
        ),
        (
            r#"record_files = ["p1-H1.csv", ["p0-H1.csv", "p0-H2.csv"]]"#,
            "",
            "record_files[1]",
            "p0-H2.csv",
        ),
        (
            r#"record_files = [["p0-H1.csv", "p0-H1.csv"]]"#,
            "",
            "record_files[0][1]",
            "p0-H1.csv",
        ),
        (
            r#"record_files = [["p0-H1.csv", "missing.csv"]]"#,
            "",
            "record_files[0][1]",
            "missing.csv",
        ),
        (
            r#"record_files = ["p0-H1.csv"]"#,
            "orientation = [0, 90]",
            "grid.orientation",
            "given",
        ),
        (
            PAIRS,
            "orientation = [0, 400]",
            "grid.orientation[1]",
            "400",
        ),
        (PAIRS, "orientation = [30, 30]", "grid.orientation[1]", "30"),
        (
            PAIRS,
            "orientation = [0]\n[uncertainty]\norientation = 45",
            "uncertainty.orientation",
            "given",
        ),
        (
            PAIRS,
            "[uncertainty]\norientation = { dist = \"uniform\", min = 90, max = 30 }",
            "uncertainty.orientation.max",
            "30",
        ),
        (
            "seed = 3",
            "[uncertainty]\norientation = 45",
            "uncertainty.orientation",
            "given",
        ),
    ];
    for (records, extra, field, value) in cases {
        let text = format!("name = \"bad\"\n{records}\n[grid]\naspect = [3]\n{extra}\n");
        let path = dir.path().join("bad.toml");
        std::fs::write(&path, &text).unwrap();
        let err = Study::load(&path).unwrap_err().to_string();
        assert!(
            err.contains("bad.toml") && err.contains(field) && err.contains(value),
            "{text}\n→ {err}"
        );
    }
}

/// A pair study's canonical spec reads back to the same study (grid and
/// drawn orientations, with and without block draws); a study of single
/// components writes no orientation.
#[test]
fn pair_specs_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    write_pairs(dir.path());
    for (name, extra, want) in [
        (
            "grid",
            "orientation = [0, 45, 90]",
            Some(Orientation::Grid(vec![0.0, 45.0, 90.0])),
        ),
        ("default", "", Some(Orientation::unknown(1))),
        (
            "only",
            "[uncertainty]\nseed = 9\norientation = { dist = \"uniform\", min = 0, max = 90 }",
            None,
        ),
        (
            "both",
            "[uncertainty]\nrestitution = { dist = \"uniform\", min = 0.2, max = 0.6 }\n\
             orientation = 30",
            Some(Orientation::Grid(vec![30.0])),
        ),
    ] {
        let text = format!("name = \"{name}\"\n{PAIRS}\n[grid]\naspect = [3]\n{extra}\n");
        let path = dir.path().join(format!("{name}.toml"));
        std::fs::write(&path, &text).unwrap();
        let s = Study::load(&path).unwrap();
        let Motions::Pairs { orientation, .. } = &s.motions else {
            panic!("{name}: a study of pairs")
        };
        if let Some(want) = want {
            assert_eq!(orientation, &want, "{name}");
        }
        assert_eq!(s.uncertainty.is_some(), name == "both", "{name}");
        let back = Study::from_toml(&s.to_toml(), &path).unwrap();
        assert_eq!(back, s, "{name}: {}", s.to_toml());
    }
    let singles = spec(dir.path(), "singles", r#"record_files = ["p0-H1.csv"]"#, "");
    assert!(!singles.to_toml().contains("orientation"));
}

/// `components = 2`: synthetic pairs of independent components of the same
/// model, at their natural amplitudes (H1 is record k of the ensemble, H2
/// record k of [`second_component_seed`]), scaled together to the level's
/// RotD50 and turned like recorded pairs: at φ = 0° the block feels H1
/// times the pair's factor, to the bit; H1 and H2 differ; the columns are
/// those of pairs; `components` is refused beside record files and above 2.
#[test]
fn synthetic_pairs_are_two_independent_components() {
    use rockfrag::motion::{Synthesizer, second_component_seed};
    let text = "name = \"syn\"\nseed = 4\nrecords = 3\ncomponents = 2\n\n[motion]\nduration = 10.0\n\n\
                [grid]\nwidth = [0.4]\naspect = [3]\nrestitution = [0.5]\npga = [0.4, 0.8]\n\
                orientation = [0, 90]\n";
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("syn.toml");
    std::fs::write(&path, text).unwrap();
    let study = Study::load(&path).unwrap();
    assert_eq!(study.records(), 6);
    // drawn directions take the study's seed, as the block's draws do, and
    // read back the same with a block drawn beside them
    let drawn_text = text
        .replace("orientation = [0, 90]\n", "")
        .replace("restitution = [0.5]\n", "")
        + "\n[uncertainty]\nrestitution = { dist = \"uniform\", min = 0.2, max = 0.6 }\n";
    let drawn = Study::from_toml(&drawn_text, &path).unwrap();
    assert_eq!(drawn.motions.orientation(), Some(&Orientation::unknown(4)));
    assert_eq!(Study::from_toml(&drawn.to_toml(), &path).unwrap(), drawn);
    // fitted against the pair's RotD50 by default, as recorded pairs are
    let fitted = Study::from_toml(&format!("{text}\n[fragility]\n"), &path).unwrap();
    assert_eq!(fitted.fragility.unwrap().im, Some(Im::PGA_ROTD50));
    let back = Study::from_toml(&study.to_toml(), &path).unwrap();
    assert_eq!(back, study);
    let rows = run(&study, &dir.path().join("out"));
    let Motions::Synthetic { settings, .. } = &study.motions else {
        panic!("synthetic")
    };
    let mut synth = Synthesizer::new(settings).unwrap();
    for row in &rows {
        let level = row.im(Im::PGA_ROTD50).unwrap();
        let k = row.record / 2;
        let h1 = synth.generate_natural(4, k as u64).unwrap();
        let h2 = synth
            .generate_natural(second_component_seed(4), k as u64)
            .unwrap();
        assert_ne!(h1.acc, h2.acc);
        let m = MeasuredPair::new(Pair::new(h1.clone(), h2.clone()).unwrap()).unwrap();
        let scale = level * study.g / m.pga;
        let (want, phi) = if row.record % 2 == 0 {
            (h1.scaled(scale), 0.0)
        } else {
            (h2.scaled(scale), 90.0)
        };
        assert_eq!(row.phi, Some(phi));
        assert_eq!(row.im(Im::PGA), Some(want.pga() / study.g));
        assert_eq!(row.im(Im::PGV), Some(want.pgv()));
    }
    for (extra, field, value) in [
        ("components = 3\n", "components", "3"),
        (
            "record_files = [[\"a.csv\", \"b.csv\"]]\ncomponents = 2\n",
            "components",
            "2",
        ),
    ] {
        let text = format!("name = \"bad\"\n{extra}[grid]\naspect = [3]\n");
        let path = dir.path().join("bad.toml");
        std::fs::write(&path, &text).unwrap();
        std::fs::write(dir.path().join("a.csv"), "t,acc\n0,0\n0.01,1\n").unwrap();
        std::fs::write(dir.path().join("b.csv"), "t,acc\n0,0\n0.01,1\n").unwrap();
        let err = Study::from_toml_unchecked(&text, &path)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("bad.toml") && err.contains(field) && err.contains(value),
            "{text}\n→ {err}"
        );
    }
}

/// A study of pairs gives the same bytes whatever the threads and shards:
/// a record's direction is drawn from its own stream (seed, record), not
/// from the order the units run in. One thread, two threads, and three
/// shards (on 1 and 2 threads) merged: one `outcomes.csv`.
#[test]
fn pairs_are_the_same_bits_for_any_threads_and_shards() {
    use rockfrag::study::{Shard, files};
    let text = "name = \"det\"\nseed = 9\nrecords = 5\ncomponents = 2\n\n[motion]\nduration = 8.0\n\n\
                [grid]\naspect = [3, 5]\nrestitution = [0.3]\npga = [0.3, 0.9]\n\n[uncertainty]\n\
                mu_s = { dist = \"lognormal\", median = 0.6, beta = 0.2 }\nmu_k_over_mu_s = 0.8\n";
    let dir = tempfile::tempdir().unwrap();
    let study = Study::from_toml(text, &dir.path().join("det.toml")).unwrap();
    let read = |d: &Path| std::fs::read(d.join(files::OUTCOMES)).unwrap();
    let whole = |threads: usize| {
        let out = dir.path().join(format!("t{threads}"));
        let o = RunOptions {
            threads,
            ..RunOptions::new(&out)
        };
        assert!(rockfrag::study::run(&study, &o).unwrap().complete);
        read(&out)
    };
    let one = whole(1);
    assert_eq!(one, whole(2));
    let mut dirs = Vec::new();
    for k in [2, 3, 1] {
        let out = dir.path().join(format!("s{k}"));
        let o = RunOptions {
            shard: Shard::new(k, 3).unwrap(),
            threads: k % 2 + 1,
            ..RunOptions::new(&out)
        };
        rockfrag::study::run(&study, &o).unwrap();
        dirs.push(out);
    }
    let merged = dir.path().join("merged");
    rockfrag::study::merge(&dirs, &merged).unwrap();
    assert_eq!(one, read(&merged));
    // and the directions are in it, one per record
    let text = String::from_utf8(one).unwrap();
    assert!(text.lines().next().unwrap().contains(",phi,"));
}
