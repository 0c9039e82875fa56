//! `rockfrag run` and `rockfrag merge` through the binary: the files they
//! write, and one-line errors that name the file and the field.

mod common;
use common::{rockfrag, run_spec, stderr};
use std::path::Path;

const SMALL: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/fixtures/specs/small.toml"
);

/// A small spec runs to completion and writes outcomes.csv, summary.md and
/// manifest.json into --out, with no partial file or checkpoint left.
#[test]
fn run_writes_the_three_files() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = rockfrag(&[
        "run",
        SMALL,
        "--out",
        out.to_str().unwrap(),
        "--threads",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for name in ["outcomes.csv", "summary.md", "manifest.json"] {
        let len = std::fs::metadata(out.join(name))
            .map(|m| m.len())
            .unwrap_or(0);
        assert!(len > 0, "{name} missing or empty");
    }
    assert!(!out.join("outcomes.csv.partial").exists());
    assert!(!out.join("checkpoint.json").exists());
    assert!(stderr(&o).contains("24 analyses"), "{}", stderr(&o));
}

/// A bad spec fails with a non-zero status and one line naming the file,
/// the field path and the accepted range.
#[test]
fn bad_spec_is_one_line_with_file_and_field() {
    let bad =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/specs/bad-restitution.toml");
    let tmp = tempfile::tempdir().unwrap();
    let o = rockfrag(&[
        "run",
        bad.to_str().unwrap(),
        "--out",
        tmp.path().to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("bad-restitution.toml:3:"), "{err}");
    assert!(
        err.contains("grid.restitution[1]") && err.contains("[0, 1]"),
        "{err}"
    );
}

/// Bad flags are one-line usage errors with status 2.
#[test]
fn bad_shard_or_threads_flag_exits_2() {
    for args in [
        ["run", SMALL, "--shard", "4/3"],
        ["run", SMALL, "--threads", "0"],
    ] {
        let o = rockfrag(&args);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert_eq!(stderr(&o).trim_end().lines().count(), 1, "{}", stderr(&o));
    }
}

/// The documented cluster workflow: shards run into their own folders, a
/// stopped shard resumed by rerunning the same command, then merged into a
/// folder byte-identical to an unsharded run.
#[test]
fn shards_resume_and_merge_through_the_cli() {
    let tmp = tempfile::tempdir().unwrap();
    let p = |name: &str| tmp.path().join(name).to_str().unwrap().to_string();
    let o = rockfrag(&["run", SMALL, "--out", &p("whole")]);
    assert!(o.status.success(), "{}", stderr(&o));
    for k in 1..=2 {
        let shard = format!("{k}/2");
        let dir = p(&format!("shard-{k}"));
        let o = rockfrag(&[
            "run",
            SMALL,
            "--shard",
            &shard,
            "--out",
            &dir,
            "--stop-after-units",
            "1",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(stderr(&o).contains("resume"), "{}", stderr(&o));
        let o = rockfrag(&["run", SMALL, "--shard", &shard, "--out", &dir]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let o = rockfrag(&["merge", &p("shard-2"), &p("shard-1"), "--out", &p("merged")]);
    assert!(o.status.success(), "{}", stderr(&o));
    let read = |d: &str| std::fs::read(tmp.path().join(d).join("outcomes.csv")).unwrap();
    assert_eq!(read("whole"), read("merged"));
}

/// The embedded paper study needs no file: `rockfrag run` with no argument
/// finds it (checked without running it, through a folder holding another
/// study's unfinished run, which it must refuse to resume).
#[test]
fn default_study_is_built_in() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().to_str().unwrap();
    let o = rockfrag(&["run", SMALL, "--out", out, "--stop-after-units", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_rockfrag"))
        .args(["run", "--out", out])
        .current_dir(tmp.path())
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("'small'") && err.contains("refusing to resume"),
        "{err}"
    );
}

/// `fragility`, `figures`, `risk` and `export` on the folder of a run that
/// was stopped do not answer "No such file or directory": they say the run
/// is unfinished and that rerunning `rockfrag run` finishes it.
#[test]
fn commands_on_an_unfinished_folder_say_to_rerun() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("stopped");
    let out = out.to_str().unwrap();
    let o = rockfrag(&["run", SMALL, "--out", out, "--stop-after-units", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let hazard = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/hazard/hazard_curve-mean-PGA_example.csv"
    );
    let job = tmp.path().join("job");
    let commands: [Vec<&str>; 4] = [
        vec!["fragility", out],
        vec!["figures", out],
        vec!["risk", out, "--hazard", hazard],
        vec![
            "export",
            "openquake",
            out,
            "--hazard",
            hazard,
            "--out",
            job.to_str().unwrap(),
        ],
    ];
    for args in commands {
        let o = rockfrag(&args);
        assert!(
            !o.status.success(),
            "{args:?} succeeded on an unfinished run"
        );
        let err = stderr(&o);
        assert!(
            err.contains("unfinished run") && err.contains("rockfrag run") && err.contains(out),
            "{args:?}: {err}"
        );
        assert!(!err.contains("No such file"), "{args:?}: {err}");
    }
}

/// A spec with a `[fragility]` table and `output.figures` gets, when the run
/// completes, the fragility files and the figures in the same folder; the
/// fragility.csv rows are one per case (4 here) and every figure is an SVG.
/// The outcomes carry the measured PGV of each scaled record, so the curves
/// can also be fitted against PGV.
#[test]
fn run_fits_fragility_and_draws_figures_when_the_spec_asks() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = tmp.path().join("asks.toml");
    let text = std::fs::read_to_string(SMALL)
        .unwrap()
        .replace("name = \"small\"", "name = \"asks\"")
        + "\n[output]\nfigures = true\n\n[fragility]\nbootstrap = 50\n";
    std::fs::write(&spec, text).unwrap();
    let out = tmp.path().join("out");
    let o = run_spec(&spec, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    for name in ["fragility.csv", "fragility_curves.csv", "fragility.xml"] {
        assert!(out.join(name).exists(), "{name} missing");
    }
    let rows = std::fs::read_to_string(out.join("fragility.csv")).unwrap();
    assert_eq!(rows.lines().count(), 1 + 4, "{rows}");
    let before = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(before.contains("IM the PGA in g"), "{before}");
    for name in common::FIGURES {
        let svg = std::fs::read_to_string(out.join("figures").join(format!("{name}.svg")))
            .unwrap_or_else(|e| panic!("{name}.svg: {e}"));
        assert!(
            svg.trim_end().ends_with("</svg>"),
            "{name}.svg is incomplete"
        );
    }

    // pgv: a positive measured peak on every row, differing between records
    // at one level (the records have one PGA but different PGVs)
    let mut reader = csv::Reader::from_path(out.join("outcomes.csv")).unwrap();
    let headers = reader.headers().unwrap().clone();
    let at = |n: &str| headers.iter().position(|h| h == n).unwrap();
    let (pga, pgv) = (at("pga"), at("pgv"));
    let mut at_04: Vec<f64> = Vec::new();
    for row in reader.records() {
        let row = row.unwrap();
        let v: f64 = row[pgv].parse().unwrap();
        assert!(v > 0.0 && v < 5.0, "pgv = {v} m/s");
        if &row[pga] == "0.4" {
            at_04.push(v);
        }
    }
    at_04.sort_by(f64::total_cmp);
    at_04.dedup();
    assert_eq!(at_04.len(), 3, "one PGV per record at 0.4 g: {at_04:?}");
    let o = rockfrag(&[
        "fragility",
        out.to_str().unwrap(),
        "--im",
        "pgv",
        "--bootstrap",
        "0",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));

    // The refit replaces summary.md's section of curves, in its place (before
    // the counts), once: the summary describes the curves on disk.
    let after = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert_eq!(after.matches("## Fragility").count(), 1, "{after}");
    assert!(after.contains("IM the PGV in m/s"), "{after}");
    assert!(!after.contains("IM the PGA in g"), "{after}");
    let (fit, counts) = (
        after.find("## Fragility"),
        after.find("## Counts per stripe"),
    );
    assert!(fit < counts, "{after}");
    assert!(
        stderr(&o).contains("summary.md (## Fragility)"),
        "{}",
        stderr(&o)
    );
}

/// `figures --case ID --level X` draws the history of that case at that
/// stripe (its title names the block and the level); without them the
/// figure shows one of the study's own blocks (H/B 4 or 6 of the small
/// study, never the paper's illustrative H/B 2 block); a case or level the
/// study does not have is an error naming what it has, not a skipped figure.
#[test]
fn figures_history_takes_case_and_level() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("small");
    let d = out.to_str().unwrap();
    let o = rockfrag(&["run", SMALL, "--out", d]);
    assert!(o.status.success(), "{}", stderr(&o));
    let title = |figs: &std::path::Path| {
        // The title may wrap over several <text> lines: join their texts.
        let svg = std::fs::read_to_string(figs.join("history.svg")).unwrap();
        let texts: Vec<&str> = svg
            .split("<text")
            .skip(1)
            .filter_map(|t| {
                t.split_once('>')
                    .map(|(_, rest)| rest.split('<').next().unwrap_or(""))
            })
            .collect();
        let all = texts.join(" ");
        let i = all.find("H/B = ").expect("a title naming the block");
        all[i..(i + 160).min(all.len())].to_string()
    };
    let f0 = tmp.path().join("f0");
    let o = rockfrag(&["figures", d, "--out", f0.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let t = title(&f0);
    assert!(t.contains("H/B = 4") || t.contains("H/B = 6"), "{t}");
    assert!(t.contains("2B = 0.5"), "{t}");

    let f1 = tmp.path().join("f1");
    let o = rockfrag(&[
        "figures",
        d,
        "--out",
        f1.to_str().unwrap(),
        "--case",
        "a6_w0p5_e0p6_inf",
        "--level",
        "0.4",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let t = title(&f1);
    assert!(
        t.contains("H/B = 6") && t.contains("e = 0.6") && t.contains("0.4 g"),
        "{t}"
    );

    let o = rockfrag(&[
        "figures",
        d,
        "--out",
        f1.to_str().unwrap(),
        "--case",
        "a3_nope",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("a3_nope") && stderr(&o).contains("a6_w0p5_e0p6_inf"),
        "{}",
        stderr(&o)
    );
    let o = rockfrag(&[
        "figures",
        d,
        "--out",
        f1.to_str().unwrap(),
        "--level",
        "0.5",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("0.4, 0.8"), "{}", stderr(&o));
}
