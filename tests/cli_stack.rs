//! `rockfrag simulate --stack` through the binary: the per-body JSON, the
//! history, and errors that name the flag and the value.

mod common;
use common::{rockfrag, stderr, stdout};

/// `--json` prints `{"bodies": [...]}` bottom first, each body with the
/// single block's keys where they mean the same, and the stack's own keys.
#[test]
fn json_has_one_entry_per_body_bottom_first() {
    let o = rockfrag(&[
        "simulate",
        "--stack",
        "0.8x1.0,0.3x1.2",
        "--seed",
        "3",
        "--pga",
        "0.5",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    let bodies = v["bodies"].as_array().unwrap();
    assert_eq!(bodies.len(), 2);
    for b in bodies {
        for key in [
            "theta_max_over_theta_c",
            "overturned",
            "overturn_time",
            "slip_max",
            "mu_impact",
            "uplifted",
            "time_in_mode",
        ] {
            assert!(b.get(key).is_some(), "missing {key}: {b}");
        }
        assert!(b["time_in_mode"]["rock"].is_number());
    }
    for key in ["first_overturned", "failure", "impacts", "end_time"] {
        assert!(v.get(key).is_some(), "missing {key}: {v}");
    }
}

/// Mistakes a user makes are refused with the flag, the value and what is
/// expected, and nothing is solved.
#[test]
fn bad_stacks_are_refused_naming_the_flag() {
    let cases: [(&[&str], &str); 5] = [
        (&["--stack", "0.8x1.0,0.3"], "'0.3' is not WIDTHxHEIGHT"),
        (&["--stack", "0.8x1.0,0.9x1.2"], "footprint"),
        (
            &["--stack", "0.8x1.0,0.3x1.2", "--masses", "1"],
            "--masses 1: 1 values for 2 bodies",
        ),
        (
            &["--stack", "0.8x1.0,0.3x1.2", "--interface-mu", "inf,abc"],
            "'abc' is not a number",
        ),
        (
            &["--stack", "0.8x1.0,0.3x1.2,0.2x0.4,0.1x0.1"],
            "1 to 3 bodies",
        ),
    ];
    for (flags, expected) in cases {
        let mut args = vec!["simulate", "--seed", "3", "--pga", "0.5"];
        args.extend_from_slice(flags);
        let o = rockfrag(&args);
        assert!(!o.status.success(), "{flags:?} was accepted");
        assert!(stderr(&o).contains(expected), "{flags:?}: {}", stderr(&o));
    }
}
