//! `rockfrag simulate --free-motion-max SECONDS` (the spec's
//! `solver.free_motion_max`): a body still moving at the record's end is
//! followed after it (default 60 s) or not (0), for one block and a stack;
//! values out of the spec's range are refused naming the flag and value.

mod common;
use common::{rockfrag, stderr, stdout};

/// A 0.5 s record of nearly still ground (one sample of 0.1 m/s², so it is
/// a record), written into `dir`.
fn short_record(dir: &std::path::Path) -> String {
    let mut text = String::from("t,acc\n");
    for i in 0..=50 {
        let acc = if i == 10 { 0.1 } else { 0.0 };
        text.push_str(&format!("{:.2},{acc}\n", i as f64 * 0.01));
    }
    let path = dir.join("short.csv");
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// `end_time` and `failure` of `simulate ARGS --free-motion-max CAP --json`.
fn end_time(args: &[&str], cap: Option<&str>) -> (f64, serde_json::Value) {
    let mut all = vec!["simulate"];
    all.extend_from_slice(args);
    if let Some(cap) = cap {
        all.extend_from_slice(&["--free-motion-max", cap]);
    }
    all.push("--json");
    let o = rockfrag(&all);
    assert!(o.status.success(), "{all:?}: {}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    (v["end_time"].as_f64().unwrap(), v["failure"].clone())
}

/// A block released at θ0 = 0.05 rad (e = 0.8) rocks past a 0.5 s record:
/// with 0 the analysis stops at the record's end (0.5 s, as the paper's
/// program); by default it is followed until it rests, later. The same
/// for a stack whose statue is released tilted.
#[test]
fn zero_stops_at_the_records_end_and_the_default_follows_the_motion() {
    let tmp = tempfile::tempdir().unwrap();
    let rec = short_record(tmp.path());
    let block = ["--motion", &rec, "--theta0", "0.05", "--restitution", "0.8"];
    let stack = [
        "--stack",
        "0.8x1.0,0.3x1.2",
        "--tilts",
        "0,0.05",
        "--motion",
        &rec,
        "--restitution",
        "0.8",
    ];
    for args in [&block[..], &stack[..]] {
        let (stopped, _) = end_time(args, Some("0"));
        let (followed, failure) = end_time(args, None);
        let (sixty, _) = end_time(args, Some("60"));
        // the record's last sample is at 0.5 s (a time, to rounding)
        assert!((stopped - 0.5).abs() < 1e-12, "{args:?}: {stopped}");
        assert!(followed > 1.0, "{args:?}: ended at {followed}");
        assert!(failure.is_null(), "{args:?}: {failure}");
        assert_eq!(followed.to_bits(), sixty.to_bits(), "the default is 60 s");
    }
    // a cap shorter than the motion: a failure naming the cap, not an answer
    let mut args = vec!["simulate"];
    args.extend_from_slice(&stack);
    args.extend_from_slice(&["--free-motion-max", "0.2"]);
    let o = rockfrag(&args);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("still moving 0.2 s after the record's end"),
        "{}",
        stderr(&o)
    );
}

/// Values the spec's `solver.free_motion_max` refuses are refused here,
/// naming the flag and the value; with --study the study's settings apply.
#[test]
fn bad_caps_are_refused_naming_the_flag_and_value() {
    for bad in ["-1", "4000", "nan", "inf", "abc"] {
        let o = rockfrag(&[
            "simulate",
            "--seed",
            "3",
            "--pga",
            "0.3",
            "--free-motion-max",
            bad,
        ]);
        assert!(!o.status.success(), "{bad} was accepted");
        let e = stderr(&o);
        assert!(
            e.contains(&format!("'{bad}' for --free-motion-max")),
            "{bad}: {e}"
        );
    }
    let o = rockfrag(&[
        "simulate",
        "--study",
        "x.toml",
        "--level",
        "0.3",
        "--record",
        "0",
        "--free-motion-max",
        "0",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--free-motion-max"), "{}", stderr(&o));
}
