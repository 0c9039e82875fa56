//! `rockfrag simulate --study` solves one analysis of a study again (issue
//! 37): for rows of studies with drawn parameters, record pairs and a
//! floor, `--csv` prints the very bytes of the row the run wrote in
//! `outcomes.csv`; the history figure names the command that solves its
//! analysis again, and that command gives the figure's outcome.

mod common;
use common::{rockfrag, stderr, stdout};
use std::path::Path;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `spec` into `out` and checks, for every `every`-th row of its
/// outcomes.csv (rows are in canonical order: unit-major, level-major
/// units, cases in order), that `simulate --study X --case ID --level L
/// --record R --csv` prints the header and that row byte for byte, `X`
/// the spec file and the finished folder alike. `case_ids` are the
/// study's cases in canonical order; `levels` its levels as written.
fn rows_reproduce(
    spec: &Path,
    out: &Path,
    case_ids: &[&str],
    levels: &[&str],
    records: usize,
    every: usize,
) {
    let o = common::run_spec(spec, out);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(out.join("outcomes.csv")).unwrap();
    let mut lines = text.split_inclusive('\n');
    let header = lines.next().unwrap();
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), case_ids.len() * levels.len() * records);
    let mut checked = 0;
    for (k, row) in rows.iter().enumerate().step_by(every) {
        let unit = k / case_ids.len();
        let case = case_ids[k % case_ids.len()];
        let (level, record) = (levels[unit / records], (unit % records).to_string());
        let study = if checked % 2 == 0 { s(spec) } else { s(out) };
        let o = rockfrag(&[
            "simulate", "--study", study, "--case", case, "--level", level, "--record", &record,
            "--csv",
        ]);
        assert!(o.status.success(), "row {k}: {}", stderr(&o));
        assert_eq!(
            stdout(&o),
            format!("{header}{row}"),
            "row {k} ({case} at {level}, record {record})"
        );
        checked += 1;
    }
    assert!(checked >= 5, "only {checked} rows checked");
}

/// The vase (e, μs and μk drawn per analysis) at fewer records: its drawn
/// values are part of the row, so a simulate that did not draw them as the
/// run did would differ in the e, μs, μk columns and in the outcome.
#[test]
fn rows_with_drawn_parameters_reproduce_bit_for_bit() {
    let tmp = tempfile::tempdir().unwrap();
    let vase = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/studies/vase.toml"))
        .unwrap()
        .replace("records = 50", "records = 4")
        .replace(
            "pga = [0.1, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5, 0.55, 0.6, 0.7, 0.8]",
            "pga = [0.25, 0.5, 0.8]",
        )
        .replace("bootstrap = 1000", "bootstrap = 0")
        .replace("figures = true", "figures = false");
    let spec = tmp.path().join("vase.toml");
    std::fs::write(&spec, vase).unwrap();
    let ids = [
        "a3_w0p2_edrawn_mudrawn",
        "a4_w0p2_edrawn_mudrawn",
        "a5_w0p2_edrawn_mudrawn",
    ];
    rows_reproduce(
        &spec,
        &tmp.path().join("out"),
        &ids,
        &["0.25", "0.5", "0.8"],
        4,
        5,
    );
}

/// Recorded pairs (each block turned to a drawn direction), on the roof of
/// a building (a floor filter), e and μ drawn, at PGA levels of the pair's
/// RotD50; and the same with synthetic pairs (`components = 2`) at PGV
/// levels: every measured column (pga, pga_rotd50, phi, pfa, pfv, record
/// file) and the outcome equal the run's.
#[test]
fn rows_with_pairs_and_a_floor_reproduce_bit_for_bit() {
    let tmp = tempfile::tempdir().unwrap();
    let mut pairs = Vec::new();
    for k in 0..3 {
        for (c, seed) in [(1, 11), (2, 12)] {
            let path = tmp.path().join(format!("r{k}-H{c}.AT2"));
            let o = rockfrag(&[
                "motion",
                "--seed",
                &seed.to_string(),
                "--index",
                &k.to_string(),
                "--pga",
                "0.3",
                "--duration",
                "12",
                "--out",
                s(&path),
            ]);
            assert!(o.status.success(), "{}", stderr(&o));
        }
        pairs.push(format!("[\"r{k}-H1.AT2\", \"r{k}-H2.AT2\"]"));
    }
    let common = "[support]\nfloor = [{ period = 0.6, damping = 0.05, participation = 1.3 }]\n\
                  [uncertainty]\nrestitution = { dist = \"uniform\", min = 0.2, max = 0.6 }\n\
                  mu_s = { dist = \"lognormal\", median = 0.5, beta = 0.15 }\n\
                  mu_k_over_mu_s = { dist = \"uniform\", min = 0.75, max = 0.95 }\n";
    let spec = tmp.path().join("pairs.toml");
    std::fs::write(
        &spec,
        format!(
            "name = \"pairs\"\nrecord_files = [{}]\n[grid]\nwidth = [0.4]\n\
             aspect = [3, 5]\npga = [0.2, 0.45]\n{common}",
            pairs.join(", ")
        ),
    )
    .unwrap();
    let ids = ["a3_w0p4_edrawn_mudrawn", "a5_w0p4_edrawn_mudrawn"];
    rows_reproduce(&spec, &tmp.path().join("out"), &ids, &["0.2", "0.45"], 3, 1);

    let spec = tmp.path().join("synthetic-pairs.toml");
    std::fs::write(
        &spec,
        format!(
            "name = \"synthetic-pairs\"\nseed = 8\nrecords = 3\ncomponents = 2\n\
             [motion]\nduration = 12.0\n[grid]\nwidth = [0.4]\naspect = [4]\n\
             pgv = [0.1, 0.3]\n{common}"
        ),
    )
    .unwrap();
    rows_reproduce(
        &spec,
        &tmp.path().join("out2"),
        &["a4_w0p4_edrawn_mudrawn"],
        &["0.1", "0.3"],
        3,
        1,
    );
}

/// A case, level or record the study does not have is refused, listing
/// what it has; `--study` without --level and --record says it needs them.
#[test]
fn simulate_study_names_what_the_study_has() {
    let spec = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/specs/small.toml"
    );
    let err = stderr(&rockfrag(&[
        "simulate", "--study", spec, "--case", "x", "--level", "0.4", "--record", "0",
    ]));
    assert!(err.contains("a4_w0p5_e0_inf, a4_w0p5_e0p6_inf"), "{err}");
    let err = stderr(&rockfrag(&[
        "simulate",
        "--study",
        spec,
        "--case",
        "a4_w0p5_e0_inf",
        "--level",
        "0.5",
        "--record",
        "0",
    ]));
    assert!(
        err.contains("one of the study's levels (0.4, 0.8)"),
        "{err}"
    );
    let err = stderr(&rockfrag(&[
        "simulate",
        "--study",
        spec,
        "--case",
        "a4_w0p5_e0_inf",
        "--level",
        "0.4",
        "--record",
        "3",
    ]));
    assert!(err.contains("0 to 2 (3 records per level)"), "{err}");
    let o = rockfrag(&["simulate", "--study", spec, "--case", "a4_w0p5_e0_inf"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("--study needs --level X and --record N"),
        "{}",
        stderr(&o)
    );
}

/// The history figure of the built-in study (the paper's illustrative
/// block, not one of the study's cases) and of a study with drawn
/// parameters (one of its own analyses) each name the command that solves
/// their analysis again; run with `--json --history`, it gives the outcome
/// the figure drew, bit for bit. Before, the figure said "record 21 of seed 1991 at 0.9 g" and
/// `simulate --seed 1991 --index 21 --pga 0.9` solved another record (the
/// default motion model, not the study's `shenton-jones` preset).
#[test]
fn the_history_figure_names_the_command_that_solves_it_again() {
    use rockfrag::figures::{FigureOptions, HistoryChoice, StudyFigures, study_of_folder};
    let tmp = tempfile::tempdir().unwrap();
    let vase = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/studies/vase.toml"))
        .unwrap()
        .replace("records = 50", "records = 6")
        .replace("bootstrap = 1000", "bootstrap = 0");
    let vase_spec = tmp.path().join("vase.toml");
    std::fs::write(&vase_spec, vase).unwrap();
    for (dir, spec) in [("paper", None), ("vase", Some(&vase_spec))] {
        let out = tmp.path().join(dir);
        let o = match spec {
            Some(spec) => common::run_spec(spec, &out),
            None => rockfrag(&["run", "--out", s(&out)]),
        };
        let err = stderr(&o);
        assert!(o.status.success(), "{err}");
        let command = err
            .lines()
            .find_map(|l| l.strip_prefix("history: its analysis is solved again by `"))
            .and_then(|l| l.strip_suffix('`'))
            .unwrap_or_else(|| panic!("no command in {err}"));
        let words: Vec<&str> = command.split(' ').collect();
        assert_eq!(words[..3], ["rockfrag", "simulate", "--study"], "{command}");
        // with its time history, as the figure solves it (a solve that
        // records a history may differ in the last bit of time_in_mode)
        let csv = tmp.path().join(format!("{dir}-history.csv"));
        let mut args = words[1..].to_vec();
        args.extend(["--json", "--history", s(&csv)]);
        let o = rockfrag(&args);
        assert!(o.status.success(), "{command}: {}", stderr(&o));
        // as text: serde_json's float parser may miss a last bit, its writer
        // (the shortest round trip) does not
        let solved = stdout(&o);

        let study = study_of_folder(&out).unwrap().unwrap();
        let mut options = FigureOptions::for_study(&study);
        if spec.is_none() {
            // the paper layer's illustrative block (src/paper/figures.rs)
            options.history = HistoryChoice::Case(
                rockfrag::paper::history_case(&options.synthesis, options.seed).unwrap(),
            );
        }
        let figures = StudyFigures::compute(&out, &options).unwrap();
        let history = figures.history.expect("a history figure");
        assert_eq!(history.command.as_deref(), Some(command));
        let drawn = history.outcome.to_json().to_string();
        if spec.is_none() {
            // a block of its own: solved with its history, as the figure
            assert_eq!(solved.trim_end(), drawn, "{command}");
        } else {
            // a case of the study: the outcome is the run's (solved without
            // a history, as outcomes.csv), the figure's was solved with
            // one: they may differ in the last bits of time_in_mode only
            // (the solver decides rest sample by sample with a history)
            let (a, b) = (without_time_in_mode(&solved), without_time_in_mode(&drawn));
            assert_eq!(a.trim_end(), b, "{command}");
            let json: serde_json::Value = serde_json::from_str(&solved).unwrap();
            for (mode, t) in json["time_in_mode"].as_object().unwrap() {
                let t = t.as_f64().unwrap();
                let m = rockfrag::outcome::Mode::ALL
                    .iter()
                    .find(|m| m.name() == mode)
                    .unwrap();
                let u = history.outcome.time_in_mode[m.index()];
                assert!((t - u).abs() <= 1e-12 * 30.0, "{mode}: {t} vs {u}");
            }
        }
    }
}

/// The outcome's JSON text without its `time_in_mode` object.
fn without_time_in_mode(json: &str) -> String {
    let start = json.find("\"time_in_mode\":{").expect("time_in_mode");
    let end = start + json[start..].find('}').expect("its end") + 1;
    format!("{}{}", &json[..start], &json[end..])
}
