//! `rockfrag simulate` through the binary: outputs, and clear errors for bad input.

mod common;
use common::{rockfrag, stderr, stdout};
use std::io::Write;

/// The JSON outcome carries every documented field, with θmax/θc finite and
/// the run ending at the record's end or at overturning.
#[test]
fn json_outcome_has_the_documented_fields() {
    let o = rockfrag(&[
        "simulate", "--seed", "1", "--pga", "0.6", "--aspect", "4", "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    for key in [
        "overturned",
        "uplifted",
        "theta_max_over_theta_c",
        "mu_motion",
        "mu_impact",
        "mu_impact_eq5",
        "impacts",
        "flights",
        "uplifts",
        "end_time",
        "first_impact_time",
        "energy_gains",
        "time_in_mode",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    let end = v["end_time"].as_f64().unwrap();
    assert!(
        end == 30.0 || v["overturned"].as_bool().unwrap(),
        "end {end}"
    );
}

/// The history CSV has the documented header, one row per record sample at
/// least, and times in order.
#[test]
fn history_csv_has_header_and_ordered_rows() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("h.csv");
    let o = rockfrag(&[
        "simulate",
        "--seed",
        "2",
        "--pga",
        "0.3",
        "--history",
        path.to_str().unwrap(),
    ]);
    // (0.3 g: the H/B 4 block rocks but stands, so the run lasts the record)
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t,mode,theta,theta_dot,x,x_dot,y,y_dot,N,F"
    );
    let times: Vec<f64> = lines
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert!(times.len() >= 1501, "{} rows", times.len());
    assert!(
        times.windows(2).all(|w| w[0] <= w[1]),
        "history out of order"
    );
}

/// A motion file written by `rockfrag motion` drives `simulate` to the same
/// outcome as the synthetic record it came from (the CSV round-trips exactly).
#[test]
fn motion_file_and_seed_give_the_same_outcome() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.csv");
    let o = rockfrag(&[
        "motion",
        "--seed",
        "3",
        "--pga",
        "0.7",
        "--out",
        path.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let a = rockfrag(&["simulate", "--seed", "3", "--pga", "0.7", "--json"]);
    let b = rockfrag(&["simulate", "--motion", path.to_str().unwrap(), "--json"]);
    let (a, b) = (stdout(&a), stdout(&b));
    let va: serde_json::Value = serde_json::from_str(a.trim()).unwrap();
    let vb: serde_json::Value = serde_json::from_str(b.trim()).unwrap();
    assert_eq!(va["theta_max_over_theta_c"], vb["theta_max_over_theta_c"]);
    assert_eq!(va["impacts"], vb["impacts"]);
}

/// `rockfrag motion --out FILE.AT2` writes a PEER record that `simulate`
/// reads back to the same motion: the accelerations round-trip through g
/// (shortest round-trip text, so a/g·g is within an ulp or two of a), and
/// velocity and displacement are integrated again from them, so the outcome
/// agrees with the synthetic record's to far below the solver's tolerance
/// (rtol 1e-8) and the counts are the same.
#[test]
fn motion_written_as_at2_drives_simulate_to_the_same_outcome() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.AT2");
    let o = rockfrag(&[
        "motion",
        "--seed",
        "3",
        "--pga",
        "0.7",
        "--out",
        path.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.lines().nth(2).unwrap().contains("UNITS OF G")
            && text
                .lines()
                .nth(3)
                .unwrap()
                .starts_with("NPTS= 1501, DT= 0.02 SEC"),
        "{}",
        text.lines().take(4).collect::<Vec<_>>().join("\n")
    );
    let a = rockfrag(&["simulate", "--seed", "3", "--pga", "0.7", "--json"]);
    let b = rockfrag(&["simulate", "--motion", path.to_str().unwrap(), "--json"]);
    assert!(b.status.success(), "{}", stderr(&b));
    let va: serde_json::Value = serde_json::from_str(stdout(&a).trim()).unwrap();
    let vb: serde_json::Value = serde_json::from_str(stdout(&b).trim()).unwrap();
    let (ta, tb) = (
        va["theta_max_over_theta_c"].as_f64().unwrap(),
        vb["theta_max_over_theta_c"].as_f64().unwrap(),
    );
    assert!(ta > 0.01, "the record must make the block rock: {ta}");
    assert!((ta - tb).abs() <= 1e-9 * ta, "{ta} vs {tb}");
    assert_eq!(va["impacts"], vb["impacts"]);
    assert_eq!(va["overturned"], vb["overturned"]);
}

/// `--rock-impact rock` (the paper's program, not physics) keeps the block
/// rocking after rock impacts with e > 0: no flights, where the default
/// flies and rings down after every rock impact.
#[test]
fn rock_impact_rule_is_a_flag_and_suppresses_flight() {
    let run = |rule: &str| {
        let o = rockfrag(&[
            "simulate",
            "--seed",
            "3",
            "--pga",
            "0.9",
            "--aspect",
            "2",
            "--restitution",
            "0.6",
            "--rock-impact",
            rule,
            "--json",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        serde_json::from_str::<serde_json::Value>(stdout(&o).trim()).unwrap()
    };
    let (bounce, rock) = (run("bounce"), run("rock"));
    assert!(bounce["flights"].as_u64().unwrap() > 10, "{bounce}");
    assert_eq!(rock["flights"].as_u64().unwrap(), 0, "{rock}");
    assert!(rock["impacts"].as_u64().unwrap() > 0, "{rock}");
}

/// A recorded motion is scaled by `--scale X`, `--pga G` or `--pgv V`: a
/// record written at 0.5 g (too weak to rock an H/B 2 block) and scaled to
/// 0.9 g is the synthetic record made at 0.9 g up to the rounding of the
/// factor (ground motion is linear in its amplitude; the synthesis scales
/// the same record by its own factor), so θmax/θc agrees to 1e-8 relative;
/// `--scale 1.8` and `--pgv` (the record's PGV × 1.8) give that same motion.
#[test]
fn a_recorded_motion_is_scaled_by_factor_pga_or_pgv() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.csv");
    let p = path.to_str().unwrap();
    let o = rockfrag(&["motion", "--seed", "3", "--pga", "0.5", "--out", p]);
    assert!(o.status.success(), "{}", stderr(&o));
    let theta = |args: &[&str]| {
        let o = rockfrag(args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
        v["theta_max_over_theta_c"].as_f64().unwrap()
    };
    let reference = theta(&[
        "simulate", "--aspect", "2", "--seed", "3", "--pga", "0.9", "--json",
    ]);
    let as_recorded = theta(&["simulate", "--aspect", "2", "--motion", p, "--json"]);
    assert!(reference > 0.01 && (as_recorded - reference).abs() > 1e-3 * reference);
    let pgv: f64 = {
        let text = std::fs::read_to_string(&path).unwrap();
        text.lines()
            .skip(1)
            .map(|l| {
                l.split(',')
                    .nth(2)
                    .unwrap()
                    .trim()
                    .parse::<f64>()
                    .unwrap()
                    .abs()
            })
            .fold(0.0, f64::max)
    };
    let pgv = format!("{}", pgv * 1.8);
    for extra in [
        ["--pga", "0.9"],
        ["--scale", "1.8"],
        ["--pgv", pgv.as_str()],
    ] {
        let mut args = vec!["simulate", "--aspect", "2", "--motion", p, "--json"];
        args.extend(extra);
        let t = theta(&args);
        assert!(
            (t - reference).abs() <= 1e-8 * reference,
            "{args:?}: {t} vs {reference}"
        );
    }
    // --scale needs a recorded motion.
    let o = rockfrag(&["simulate", "--seed", "3", "--pga", "0.9", "--scale", "2"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

/// Wrong arguments exit with status 2 and one line naming the argument and
/// what it accepts.
#[test]
fn bad_arguments_exit_2_with_one_line() {
    for (args, needle) in [
        (
            vec!["simulate", "--seed", "1", "--pga", "0.5", "--width", "-1"],
            "--width",
        ),
        (
            vec![
                "simulate",
                "--seed",
                "1",
                "--pga",
                "0.5",
                "--restitution",
                "1.5",
            ],
            "[0, 1]",
        ),
        (
            vec!["simulate", "--seed", "1", "--pga", "0.5", "--model", "fast"],
            "nonlinear, linear",
        ),
        (
            vec!["simulate", "--seed", "1", "--pga", "0.5", "--impact", "x"],
            "newton, energetic",
        ),
        (vec!["simulate", "--seed", "1"], "--pga"),
        (vec!["simulate", "--aspect", "3"], "--motion"),
    ] {
        let o = rockfrag(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = stderr(&o);
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

/// Bad motion files: empty, non-uniform time step, NaN. Each error names the
/// file, and the run exits with status 1 without output.
#[test]
fn bad_motion_files_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("empty.csv", "t,acc\n".to_string()),
        (
            "uneven.csv",
            "t,acc\n0,0\n0.01,0.1\n0.03,0.2\n0.04,0.1\n".to_string(),
        ),
        ("nan.csv", "t,acc\n0,0\n0.01,NaN\n0.02,0.1\n".to_string()),
    ];
    for (name, content) in cases {
        let path = dir.path().join(name);
        std::fs::File::create(&path)
            .unwrap()
            .write_all(content.as_bytes())
            .unwrap();
        let o = rockfrag(&["simulate", "--motion", path.to_str().unwrap(), "--json"]);
        assert_eq!(o.status.code(), Some(1), "{name}");
        let err = stderr(&o);
        assert!(err.contains(name), "{name}: {err}");
        assert!(stdout(&o).is_empty());
    }
}

/// `--integrator` chooses the rock integrator: Taylor (default) and
/// Dormand–Prince give the same θmax/θc to 1e-7 on this run at the default
/// tolerance (measured: 9e-10 relative), and the Taylor run takes one series
/// per step (rhs_calls = steps) against six or more evaluations per step.
#[test]
fn integrator_flag_chooses_the_rock_integrator() {
    let run = |integrator: &str| -> serde_json::Value {
        let o = rockfrag(&[
            "simulate",
            "--seed",
            "1",
            "--pga",
            "0.6",
            "--integrator",
            integrator,
            "--json",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        serde_json::from_str(stdout(&o).trim()).unwrap()
    };
    let (t, d) = (run("taylor"), run("dopri5"));
    let th = |v: &serde_json::Value| v["theta_max_over_theta_c"].as_f64().unwrap();
    assert!(
        ((th(&t) - th(&d)) / th(&d)).abs() < 1e-7,
        "{} vs {}",
        th(&t),
        th(&d)
    );
    assert_eq!(t["stats"]["rhs_calls"], t["stats"]["steps_accepted"]);
    let (rd, sd) = (
        d["stats"]["rhs_calls"].as_u64().unwrap(),
        d["stats"]["steps_accepted"].as_u64().unwrap(),
    );
    assert!(rd >= 6 * sd, "{rd} evaluations for {sd} steps");
}

/// `--follow-cascades` turns the cascade rule off: the same θmax/θc and
/// overturning, bit for bit, with more events (the e = 0 ring-down tails
/// followed impact by impact).
#[test]
fn follow_cascades_flag_keeps_the_motion_and_adds_events() {
    let run = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec!["simulate", "--seed", "1", "--pga", "0.6", "--json"];
        args.extend_from_slice(extra);
        let o = rockfrag(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        serde_json::from_str(stdout(&o).trim()).unwrap()
    };
    let (ruled, followed) = (run(&[]), run(&["--follow-cascades"]));
    assert_eq!(
        ruled["theta_max_over_theta_c"],
        followed["theta_max_over_theta_c"]
    );
    assert_eq!(ruled["overturned"], followed["overturned"]);
    let events = |v: &serde_json::Value| v["stats"]["events"].as_u64().unwrap();
    assert!(
        events(&followed) > events(&ruled),
        "{} events followed against {} ruled",
        events(&followed),
        events(&ruled)
    );
}

/// A PGA meant in cm/s² (`--pga 300`) is refused, as the spec refuses it:
/// 300 g is beyond any recorded motion (the largest are about 4 g). The
/// message names the flag, the unit and what 300 cm/s² would be (0.306 g);
/// 10 g, the limit, is still accepted. The same for `motion` and for a PGV
/// in cm/s.
#[test]
fn pga_in_the_wrong_unit_is_refused() {
    let o = rockfrag(&["simulate", "--seed", "1", "--pga", "300", "--aspect", "4"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("--pga") && err.contains("in g") && err.contains("0.306 g"),
        "{err}"
    );
    let o = rockfrag(&["motion", "--seed", "1", "--pga", "300"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("in g"), "{}", stderr(&o));
    let o = rockfrag(&[
        "simulate", "--seed", "1", "--pga", "10", "--aspect", "4", "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let tmp = tempfile::tempdir().unwrap();
    let rec = tmp.path().join("r.csv");
    let o = rockfrag(&[
        "motion",
        "--seed",
        "1",
        "--pga",
        "0.3",
        "--out",
        rec.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = rockfrag(&[
        "simulate",
        "--motion",
        rec.to_str().unwrap(),
        "--pgv",
        "40",
        "--aspect",
        "4",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("in m/s"), "{}", stderr(&o));
}

/// `--sensitivity` solves the run again under the record scaled by 1 + 1e-9
/// and says whether it is sensitive, and why: on the bench record that
/// decides H/B 6, e = 0, μ 0.7/0.6 at 1.0 g by a hair (record 21 of seed
/// 1991, the default motion model), overturning flips (the block overturns,
/// and under the record larger by 1e-9 stops at 0.82 θc); with `--json` the
/// outcome carries a `sensitivity` object with the perturbed run's
/// overturning and θmax/θc.
#[test]
fn sensitivity_flag_reports_the_perturbed_run() {
    let args = [
        "simulate",
        "--seed",
        "1991",
        "--index",
        "21",
        "--pga",
        "1.0",
        "--aspect",
        "6",
        "--restitution",
        "0",
        "--mu-s",
        "0.7",
        "--mu-k",
        "0.6",
        "--sensitivity",
    ];
    let o = rockfrag(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("sensitive         yes: overturning flipped"),
        "{text}"
    );
    assert!(
        text.contains("record × (1+1e-9) overturned false"),
        "{text}"
    );
    let o = rockfrag(&[&args[..], &["--json"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    let s = &v["sensitivity"];
    assert_eq!(v["overturned"], true);
    assert_eq!(
        (&s["sensitive"], &s["overturned"]),
        (&true.into(), &false.into())
    );
    assert!(s["theta_max_over_theta_c"].as_f64().unwrap() < 1.0);
    // without the flag, no second solve and no object
    let o = rockfrag(&[&args[..args.len() - 1], &["--json"]].concat());
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    assert!(v.get("sensitivity").is_none());
}
