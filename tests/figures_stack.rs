//! The history figure of a stack's case (issue 40): `rockfrag figures DIR
//! --case stack_NAME` draws every body of the stack, re-solved by the
//! stack solver on the study's motion for the analysis drawn, and its
//! curves are that analysis's: each body's peak |φ|/θc is the one
//! `outcomes.csv` holds (the same solve), and a body that overturned is
//! marked at the time `outcomes.csv` gives.

mod common;

use common::{rockfrag, stderr};
use rockfrag::figures::{FigureOptions, HistoryChoice, StudyFigures};
use std::collections::HashMap;
use std::fs;
use std::path::Path;

/// The statue of `studies/statue-on-pedestal.toml` on its pedestal, with
/// finite friction under the statue (so that it can slip), 6 records at 3
/// levels: at 0.9 g some statues overturn and some do not.
const SPEC: &str = r#"name = "statue-small"
seed = 40
records = 6
[motion]
duration = 12.0
[grid]
pga = [0.3, 0.6, 0.9]
[[grid.stack]]
name = "statue_on_pedestal"
blocks = [ { width = 0.6, height = 1.0 }, { width = 0.3, height = 1.2 } ]
interfaces = [ { restitution = 0.0, friction = "inf" }, { restitution = 0.0, mu_s = 0.6, mu_k = 0.5 } ]
[output]
figures = false
[fragility]
bootstrap = 0
[[fragility.limit_state]]
name = "statue-overturns"
measure = "top.overturned"
"#;

const CASE: &str = "stack_statue_on_pedestal";

/// The rows of `dir/outcomes.csv` as maps from column to text.
fn rows(dir: &Path) -> Vec<HashMap<String, String>> {
    let text = fs::read_to_string(dir.join("outcomes.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(str::to_string))
                .collect()
        })
        .collect()
}

fn study(dir: &Path) {
    fs::write(dir.join("st.toml"), SPEC).unwrap();
    let out = dir.join("out");
    let o = rockfrag(&[
        "run",
        dir.join("st.toml").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// `figures --case stack_… --format svg` draws the stack's history (the
/// refusal "not a stack yet" is gone), titled by the stack and naming
/// every body.
#[test]
fn figures_draws_a_stacks_history() {
    let tmp = tempfile::tempdir().unwrap();
    study(tmp.path());
    let out = tmp.path().join("out");
    let figs = tmp.path().join("figs");
    let o = rockfrag(&[
        "figures",
        out.to_str().unwrap(),
        "--case",
        CASE,
        "--level",
        "0.9",
        "--format",
        "svg",
        "--out",
        figs.to_str().unwrap(),
    ]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("not a stack yet"), "{err}");
    assert!(!err.contains("history: skipped"), "{err}");
    // the command it prints solves the analysis again
    let command = err
        .lines()
        .find_map(|l| l.strip_prefix("history: its analysis is solved again by `"))
        .and_then(|l| l.strip_suffix('`'))
        .expect("the history's command");
    let args: Vec<&str> = command.split(' ').skip(1).collect();
    let again = rockfrag(&args);
    assert!(again.status.success(), "{command}: {}", stderr(&again));
    let svg = fs::read_to_string(figs.join("history.svg")).unwrap();
    for text in [
        "Stack statue_on_pedestal",
        "base on the ground (0.6",
        "top on the base (0.3",
        "at 0.9 g",
    ] {
        assert!(svg.contains(text), "history.svg lacks {text:?}");
    }
}

/// The figure's data, for every analysis of the study (`--level X
/// --record N`): one series per body, bottom first,
/// whose peak |φ|/θc is the analysis's `outcomes.csv` value to 1e-9
/// (relative: the same solve, whose history has a row at every peak); a
/// body that overturned is marked at its `outcomes.csv` overturning time,
/// and its curve ends there. The default choice, with only stack cases,
/// draws the stack.
#[test]
fn stack_history_curves_are_the_analysiss() {
    let tmp = tempfile::tempdir().unwrap();
    study(tmp.path());
    let out = tmp.path().join("out");
    let table = rows(&out);
    let mut overturned_drawn = 0;
    for row in &table {
        let level: f64 = row["pga"].parse().unwrap();
        let record: u64 = row["record"].parse().unwrap();
        let mut options = FigureOptions::for_folder(&out).unwrap();
        options.history = HistoryChoice::At {
            case: Some(CASE.to_string()),
            level: Some(level),
            record: Some(record),
        };
        let figures = StudyFigures::compute(&out, &options).unwrap();
        assert!(figures.history.is_none());
        let fig = figures.stack_history.expect("a stack's history figure");
        assert_eq!(fig.record, record);
        assert_eq!(fig.bodies.len(), 2);
        for (body, name) in fig.bodies.iter().zip(["base", "top"]) {
            assert_eq!(body.name, name);
            let want: f64 = row[&format!("{name}.theta_max_over_theta_c")]
                .parse()
                .unwrap();
            let peak = body.phi.iter().fold(0.0_f64, |m, p| m.max(p.1.abs()));
            let overturned = row[&format!("{name}.overturned")] == "true";
            assert_eq!(body.overturn.is_some(), overturned, "{name} at {level} g");
            if overturned {
                overturned_drawn += 1;
                let t: f64 = row[&format!("{name}.overturn_time")].parse().unwrap();
                let (tm, _) = body.overturn.unwrap();
                assert_eq!(tm, t, "{name}'s overturning time");
                assert!(
                    body.phi.iter().all(|p| p.0 <= t),
                    "{name} drawn after it fell"
                );
                assert!(body.label.contains("overturned at"), "{}", body.label);
            }
            assert!(
                (peak - want).abs() <= 1e-9 * want.max(1e-300),
                "{name} at {level} g, record {}: peak |φ|/θc {peak} against {want}",
                fig.record
            );
        }
        // the ground's acceleration in g: its peak inside the window is at
        // most the level's PGA
        let acc = fig.acc.iter().fold(0.0_f64, |m, p| m.max(p.1.abs()));
        assert!(
            acc > 0.0 && acc <= level * (1.0 + 1e-9),
            "{acc} at {level} g"
        );
    }
    // the study has overturned statues: their marks were checked
    assert!(overturned_drawn > 0, "no overturned body was drawn");

    // by default (only stack cases): the stack, an analysis that rocked and
    // stood, as for blocks
    let options = FigureOptions::for_folder(&out).unwrap();
    let figures = StudyFigures::compute(&out, &options).unwrap();
    let fig = figures.stack_history.expect("the default draws the stack");
    assert!(fig.bodies.iter().all(|b| b.overturn.is_none()));
}
