//! Study specs: parsing, defaults, round trips, and one clear error per bad field.

mod common;

use rockfrag::case::Param;
use rockfrag::solver::Friction;
use rockfrag::spec::{Intensity, Motions, SpecFile, Study};
use std::path::{Path, PathBuf};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/specs")
}

fn studies() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("studies")
}

/// A validated study written back as TOML and parsed again is the same
/// study: the canonical text (hashed into the manifest) loses nothing.
#[test]
fn small_spec_round_trips_through_serde() {
    let origin = fixtures().join("small.toml");
    let study = Study::load(&origin).unwrap();
    let text = study.to_toml();
    let again = Study::from_toml(&text, &origin).unwrap();
    assert_eq!(again, study);
    assert_eq!(again.to_toml(), text, "canonical text is a fixed point");
    assert_eq!(again.hash(), study.hash());
}

/// The round trip also holds for every form a spec can take: Coulomb pairs
/// (table and array forms), PGV levels, recorded motions, output options.
#[test]
fn rich_spec_round_trips_and_coulomb_pairs_parse() {
    let origin = fixtures().join("rich.toml");
    let text = common::RICH_SPEC;
    let study = Study::from_toml(text, &origin).unwrap();
    assert_eq!(
        study.frictions,
        vec![
            Friction::Infinite,
            Friction::Coulomb {
                mu_s: 0.7,
                mu_k: 0.6
            },
            Friction::Coulomb {
                mu_s: 0.5,
                mu_k: 0.5
            },
        ]
    );
    assert_eq!(study.intensity, Intensity::Pgv(vec![0.25, 0.5]));
    match &study.motions {
        Motions::Files(files) => {
            assert_eq!(files[0].given, "record-a.csv");
            assert_eq!(files[0].path, fixtures().join("record-a.csv"));
        }
        m => panic!("expected record files, got {m:?}"),
    }
    let again = Study::from_toml(&study.to_toml(), &origin).unwrap();
    assert_eq!(again, study);
}

/// An empty spec is the paper's infinite-friction study at the documented
/// defaults: 25 firm-soil records, 2B = 0.5 m, H/B 2, 4, 6, e 0–0.9,
/// PGA 0.3–1.2 g, default solver settings; the name is the file's stem.
#[test]
fn empty_spec_takes_the_documented_defaults() {
    let study = Study::from_toml("", Path::new("somewhere/my-study.toml")).unwrap();
    assert_eq!(study.name, "my-study");
    assert_eq!(study.g, 9.81);
    assert_eq!(study.widths, vec![0.5]);
    assert_eq!(study.aspects, vec![2.0, 4.0, 6.0]);
    assert_eq!(study.restitutions, vec![0.0, 0.3, 0.6, 0.9]);
    assert_eq!(study.frictions, vec![Friction::Infinite]);
    assert_eq!(study.intensity, Intensity::Pga(vec![0.3, 0.6, 0.9, 1.2]));
    assert_eq!(study.solver, Default::default());
    assert!(study.output.summary);
    match study.motions {
        Motions::Synthetic {
            settings,
            seed,
            records,
            pairs,
        } => {
            assert_eq!(settings, Default::default());
            assert_eq!((seed, records), (1, 25));
            assert_eq!(pairs, None, "one horizontal component by default");
        }
        m => panic!("expected synthetic motions, got {m:?}"),
    }
}

/// The paper's study embedded in the binary is the file in `studies/`, with
/// the paper's grids and both friction models.
#[test]
fn embedded_paper_study_is_the_shipped_file() {
    let embedded = Study::shenton_jones();
    let file = Study::load(&studies().join("shenton-jones.toml")).unwrap();
    assert_eq!(embedded, file);
    assert_eq!(embedded.aspects, vec![2.0, 4.0, 6.0]);
    assert_eq!(embedded.restitutions, vec![0.0, 0.3, 0.6, 0.9]);
    assert_eq!(embedded.intensity, Intensity::Pga(vec![0.3, 0.6, 0.9, 1.2]));
    assert_eq!(embedded.records(), 25);
    assert_eq!(
        embedded.frictions,
        vec![
            Friction::Infinite,
            Friction::Coulomb {
                mu_s: 0.7,
                mu_k: 0.6
            }
        ]
    );
}

/// The fragility study is large enough for fragility curves: at least 200
/// records per stripe, 12 PGA stripes, both friction models.
#[test]
fn fragility_study_has_enough_stripes_and_records() {
    let study = Study::load(&studies().join("fragility.toml")).unwrap();
    assert!(study.records() >= 200);
    assert!(study.intensity.levels().len() >= 12);
    assert!(study.frictions.iter().any(|f| *f == Friction::Infinite));
    assert!(
        study
            .frictions
            .iter()
            .any(|f| matches!(f, Param::Fixed(Friction::Coulomb { .. })))
    );
}

/// Every bad fixture `bad-*.toml` fails with the error its first line
/// announces (`# expect: …`), and the one-line message names the file.
#[test]
fn every_bad_spec_names_its_field() {
    let mut checked = 0;
    let mut entries: Vec<PathBuf> = std::fs::read_dir(fixtures())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let name = p.file_name().unwrap().to_string_lossy();
            name.starts_with("bad-") && name.ends_with(".toml")
        })
        .collect();
    entries.sort();
    for path in entries {
        let text = std::fs::read_to_string(&path).unwrap();
        let expect = text
            .lines()
            .next()
            .and_then(|l| l.strip_prefix("# expect: "))
            .unwrap_or_else(|| panic!("{} lacks '# expect: …'", path.display()))
            .trim();
        let err = match Study::load(&path) {
            Ok(_) => panic!("{} was accepted", path.display()),
            Err(e) => e.to_string(),
        };
        assert!(
            err.contains(expect),
            "{}:\n  got    {err}\n  wanted {expect}",
            path.display()
        );
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        assert!(err.contains(&name), "{err} does not name {name}");
        assert!(!err.contains('\n'), "not one line: {err}");
        checked += 1;
    }
    assert!(checked >= 7, "only {checked} bad fixtures");
}

/// A field's error points at the line where it is written.
#[test]
fn errors_carry_the_line_of_the_field() {
    let err = Study::load(&fixtures().join("bad-negative-width.toml"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("bad-negative-width.toml:3:"), "{err}");
}

/// The raw form serialises to JSON (the manifest's copy of the spec).
#[test]
fn raw_spec_serialises_to_json() {
    let study = Study::load(&fixtures().join("small.toml")).unwrap();
    let json = serde_json::to_value(study.to_spec_file()).unwrap();
    assert_eq!(json["grid"]["friction"][0], "inf");
    let back: SpecFile = serde_json::from_value(json).unwrap();
    assert_eq!(back, study.to_spec_file());
}

/// Limit states parse in order, survive the canonical round trip, and a spec
/// without them keeps its canonical text free of them (so its hash is the
/// one it had before limit states existed).
#[test]
fn limit_states_round_trip_and_default_to_overturning() {
    let origin = fixtures().join("limit-states.toml");
    let text = r#"
        [fragility]
        bootstrap = 0
        [[fragility.limit_state]]
        name = "uplift"
        measure = "theta_max_over_theta_c"
        exceeds = 0.0
        [[fragility.limit_state]]
        name = "slides-5cm"
        measure = "slip_max"
        exceeds = 0.05
        [[fragility.limit_state]]
        name = "overturning"
        measure = "overturned"
    "#;
    let study = Study::from_toml(text, &origin).unwrap();
    let options = study.fragility.clone().unwrap();
    let names: Vec<String> = options.limit_states().into_iter().map(|l| l.name).collect();
    assert_eq!(names, ["uplift", "slides-5cm", "overturning"]);
    assert_eq!(options.limit_state[1].exceeds, Some(0.05));
    assert_eq!(options.limit_state[2].exceeds, None);
    let again = Study::from_toml(&study.to_toml(), &origin).unwrap();
    assert_eq!(again, study);

    let plain = Study::from_toml("[fragility]\n", &origin).unwrap();
    assert!(!plain.to_toml().contains("limit_state"));
    let only = plain.fragility.unwrap().limit_states();
    assert_eq!(only.len(), 1);
    assert_eq!(only[0].name, "overturning");
    assert_eq!(only[0].measure, "overturned");

    // A time-in-mode measure is accepted when [output] writes that column
    // (bad-limit-state-column-not-written.toml is the refusal).
    let timed = "[output]\ntime_in_mode = true\n[[fragility.limit_state]]\n\
                 name = \"rocks-1s\"\nmeasure = \"t_rock\"\nexceeds = 1.0\n";
    assert!(Study::from_toml(timed, &origin).is_ok());
}
