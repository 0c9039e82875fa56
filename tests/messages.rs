//! Messages a user meets (issue 37, "Messages"): each case as a user would
//! type it, and the message that must say what is wrong in words, with the
//! value readable and the fix named.

mod common;
use common::{rockfrag, stderr};
use std::path::Path;
use std::process::Command;

const SMALL: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/fixtures/specs/small.toml"
);

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A synthetic record written by `rockfrag motion` to `dir/name`.
fn record(dir: &Path, name: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    let o = rockfrag(&[
        "motion",
        "--seed",
        "1",
        "--pga",
        "0.3",
        "--duration",
        "10",
        "--out",
        s(&path),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    path
}

/// The longest run of digits in `text`: a value printed in full decimal
/// (1e300, `f64::MIN_POSITIVE`) has about 300.
fn longest_digits(text: &str) -> usize {
    text.split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0)
}

/// Tiny and huge values are printed with an exponent: `f64::MIN_POSITIVE`
/// as a block's aspect, a record scaled by 1e300 (its PGA, its slip). A
/// value printed in full has 300 digits; the readable form has at most 17
/// (the shortest round trip), so 20 is the bound.
#[test]
fn tiny_and_huge_values_are_printed_readably() {
    let tmp = tempfile::tempdir().unwrap();
    let rec = record(tmp.path(), "rec.csv");
    let min = f64::MIN_POSITIVE.to_string(); // Rust's own full decimal
    assert!(longest_digits(&min) > 300);
    let cases: [Vec<&str>; 3] = [
        vec![
            "simulate",
            "--seed",
            "1",
            "--pga",
            "0.3",
            "--aspect",
            "2.2250738585072014e-308",
        ],
        vec![
            "simulate",
            "--motion",
            s(&rec),
            "--scale",
            "1e300",
            "--mu-s",
            "0.5",
        ],
        vec![
            "motion",
            "--seed",
            "1",
            "--pga",
            "0.3",
            "--dt",
            "2.2250738585072014e-308",
        ],
    ];
    for (i, args) in cases.iter().enumerate() {
        let o = rockfrag(args);
        let text = format!("{}{}", common::stdout(&o), stderr(&o));
        assert!(longest_digits(&text) <= 20, "{args:?}:\n{text}");
        if i == 0 {
            // the value as given, in its shortest exact form (the range check
            // of H/B names it as `aspect = …`)
            assert!(text.contains("aspect = 2.2250738585072014e-308"), "{text}");
        }
    }
}

/// A folder named in `record_files`, or given as `--motion`, is called a
/// folder, not "not found" nor the system's "Is a directory".
#[test]
fn a_folder_given_as_a_record_is_called_a_folder() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::create_dir(tmp.path().join("rec.AT2")).unwrap();
    let spec = tmp.path().join("s.toml");
    std::fs::write(
        &spec,
        "name = \"d\"\nrecord_files = [\"rec.AT2\"]\n[grid]\naspect = [3]\npga = [0.3]\n",
    )
    .unwrap();
    let o = rockfrag(&["run", s(&spec), "--out", s(&tmp.path().join("o"))]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("record_files[0]") && err.contains("is a folder"),
        "{err}"
    );
    assert!(!err.contains("not found"), "{err}");
    let o = rockfrag(&["simulate", "--motion", s(&tmp.path().join("rec.AT2"))]);
    let err = stderr(&o);
    assert!(err.contains("is a folder, not a file"), "{err}");
}

/// A decimal comma (`DT= 0,02`, `0,02` in a CSV, `;` between columns) is
/// named as such, with the value as it should be written; before, the
/// comma split `0,02` into `0` and "DT = 0 must be positive".
#[test]
fn a_decimal_comma_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let at2 = record(tmp.path(), "rec.AT2");
    let text = std::fs::read_to_string(&at2).unwrap();
    let comma = text.replacen("DT= 0.02 SEC", "DT= 0,02 SEC", 1);
    assert_ne!(comma, text);
    let bad = tmp.path().join("comma.AT2");
    std::fs::write(&bad, comma).unwrap();
    let err = stderr(&rockfrag(&["simulate", "--motion", s(&bad)]));
    assert!(
        err.contains(":4: ") && err.contains("decimal comma") && err.contains("DT= 0.02"),
        "{err}"
    );

    let csv = "t,acc\n0,0\n0,02,0,5\n0,04,-0,25\n";
    let bad = tmp.path().join("comma.csv");
    std::fs::write(&bad, csv).unwrap();
    let err = stderr(&rockfrag(&["simulate", "--motion", s(&bad)]));
    assert!(
        err.contains(":3: ") && err.contains("decimal comma"),
        "{err}"
    );

    let bad = tmp.path().join("semi.csv");
    std::fs::write(&bad, "t;acc\n0;0\n0,02;0,5\n").unwrap();
    let err = stderr(&rockfrag(&["simulate", "--motion", s(&bad)]));
    assert!(
        err.contains(":1: ") && err.contains("separated by ';'"),
        "{err}"
    );
}

/// A negative number where a number is expected reaches the flag's own
/// check, which says what it expects (before: `unknown argument -1`); a
/// whole number says so, not "invalid digit found in string".
#[test]
fn negative_numbers_reach_their_check() {
    for (args, expect) in [
        (
            vec!["simulate", "--seed", "-1", "--pga", "0.3"],
            "--seed <N>: expected a whole number ≥ 0",
        ),
        (
            vec!["figures", "--level", "-1"],
            "--level <X>: expected a number > 0",
        ),
        (
            vec!["simulate", "--seed", "1.5", "--pga", "0.3"],
            "--seed <N>: expected a whole number ≥ 0",
        ),
        (
            vec!["motion", "--seed", "1", "--pga", "0.3", "--index", "-3"],
            "--index <I>: expected a whole number ≥ 0",
        ),
    ] {
        let o = rockfrag(&args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(expect) && !err.contains("unknown argument"),
            "{args:?}: {err}"
        );
    }
    // and a negative value that is valid is taken
    let o = rockfrag(&[
        "simulate", "--seed", "1", "--pga", "0.3", "--theta0", "-0.01", "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// `--out FILE` is refused as a file, not a folder (was `File exists (os
/// error 17)`), and the file is left as it was.
#[test]
fn out_naming_a_file_is_refused_as_a_file() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("notes.txt");
    std::fs::write(&file, "mine\n").unwrap();
    let o = rockfrag(&["run", SMALL, "--out", s(&file)]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("is a file, not a folder") && !err.contains("os error"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine\n");
    let o = rockfrag(&["run", SMALL, "--out", s(&file.join("sub"))]);
    assert!(
        stderr(&o).contains("is a file, not a folder"),
        "{}",
        stderr(&o)
    );
}

/// A shard with no work units (shard 7/8 of a study of 6 units) completes
/// and says so (it failed with `checkpoint.json: No such file or
/// directory`), merges with the others into the unsharded run's bytes; a
/// folder that is no shard's is named with what it lacks.
#[test]
fn empty_shards_complete_and_merge_names_what_a_folder_lacks() {
    let tmp = tempfile::tempdir().unwrap();
    let mut dirs = Vec::new();
    for k in 1..=8 {
        let d = tmp.path().join(format!("s{k}"));
        let o = rockfrag(&["run", SMALL, "--shard", &format!("{k}/8"), "--out", s(&d)]);
        assert!(o.status.success(), "shard {k}: {}", stderr(&o));
        if k > 6 {
            assert!(stderr(&o).contains("has no work"), "{}", stderr(&o));
        }
        dirs.push(d);
    }
    let merged = tmp.path().join("merged");
    let mut args = vec!["merge".to_string()];
    args.extend(dirs.iter().map(|d| s(d).to_string()));
    args.extend(["--out".to_string(), s(&merged).to_string()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = rockfrag(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let whole = tmp.path().join("whole");
    assert!(
        rockfrag(&["run", SMALL, "--out", s(&whole)])
            .status
            .success()
    );
    assert_eq!(
        std::fs::read(merged.join("outcomes.csv")).unwrap(),
        std::fs::read(whole.join("outcomes.csv")).unwrap()
    );

    let empty = tmp.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    let o = rockfrag(&[
        "merge",
        s(&dirs[0]),
        s(&empty),
        "--out",
        s(&tmp.path().join("m2")),
    ]);
    let err = stderr(&o);
    assert!(err.contains("empty: holds no outcomes.csv"), "{err}");
    assert!(!err.contains("No such file"), "{err}");
}

/// A UTF-8 byte-order mark (Excel's "CSV UTF-8") at the start of a survey
/// or a hazard curve is dropped as it is for records: the file reads as
/// without it.
#[test]
fn a_byte_order_mark_is_dropped() {
    let tmp = tempfile::tempdir().unwrap();
    let survey = tmp.path().join("survey.csv");
    let text = "name,width,aspect,count,overturned\nslab,0.3,4,10,3\n";
    std::fs::write(&survey, format!("\u{feff}{text}")).unwrap();
    let parsed = rockfrag::infer::Survey::read(&survey).unwrap();
    let plain = rockfrag::infer::Survey::parse(text, &survey).unwrap();
    assert_eq!(format!("{parsed:?}"), format!("{plain:?}"));

    let hazard = tmp.path().join("hazard.csv");
    let text = "iml,annual_rate\n0.1,0.01\n0.5,0.001\n1.0,0.0001\n";
    std::fs::write(&hazard, format!("\u{feff}{text}")).unwrap();
    let with = rockfrag::risk::read_hazard(&hazard, None).unwrap();
    std::fs::write(&hazard, text).unwrap();
    let without = rockfrag::risk::read_hazard(&hazard, None).unwrap();
    assert_eq!(format!("{with:?}"), format!("{without:?}"));
}

/// `simulate --motion2` refuses what a spec's pair refuses: the same file
/// twice (also as `./file`), and an orientation outside [0, 360).
#[test]
fn simulate_pairs_take_the_specs_checks() {
    let tmp = tempfile::tempdir().unwrap();
    let h1 = record(tmp.path(), "h1.csv");
    let h2 = tmp.path().join("h2.csv");
    std::fs::copy(&h1, &h2).unwrap();
    let dotted = tmp.path().join(".").join("h1.csv");
    let o = rockfrag(&[
        "simulate",
        "--motion",
        s(&h1),
        "--motion2",
        s(&dotted),
        "--orientation",
        "30",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("is the --motion file"),
        "{}",
        stderr(&o)
    );
    for phi in ["400", "-30", "360"] {
        let o = rockfrag(&[
            "simulate",
            "--motion",
            s(&h1),
            "--motion2",
            s(&h2),
            "--orientation",
            phi,
        ]);
        assert_eq!(o.status.code(), Some(2), "{phi}: {}", stderr(&o));
        assert!(stderr(&o).contains("in [0, 360)"), "{}", stderr(&o));
    }
    let o = rockfrag(&[
        "simulate",
        "--motion",
        s(&h1),
        "--motion2",
        s(&h2),
        "--orientation",
        "359.5",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // the spec says the same of the same pair
    let spec = tmp.path().join("p.toml");
    std::fs::write(
        &spec,
        "name = \"p\"\nrecord_files = [[\"h1.csv\", \"./h1.csv\"]]\n[grid]\naspect = [3]\npga = [0.3]\n",
    )
    .unwrap();
    let o = rockfrag(&["run", s(&spec), "--out", s(&tmp.path().join("o"))]);
    assert!(
        stderr(&o).contains("a file other than the first"),
        "{}",
        stderr(&o)
    );
}

/// `figures` on a shard folder is refused unless --partial, which then
/// says the figures show a part; on an infer folder it names the infer
/// command with --format png.
#[test]
fn figures_refuse_shards_and_point_infer_folders_to_infer() {
    let tmp = tempfile::tempdir().unwrap();
    let shard = tmp.path().join("shard");
    assert!(
        rockfrag(&["run", SMALL, "--shard", "1/2", "--out", s(&shard)])
            .status
            .success()
    );
    let o = rockfrag(&["figures", s(&shard)]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("holds shard 1/2") && stderr(&o).contains("--partial"));
    assert!(
        !shard.join("figures").exists(),
        "a refused folder got figures"
    );
    let o = rockfrag(&["figures", s(&shard), "--partial"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("only that part"), "{}", stderr(&o));

    let infer = tmp.path().join("inf");
    std::fs::create_dir(&infer).unwrap();
    std::fs::write(
        infer.join("inference.json"),
        r#"{"spec": "s.toml", "observations": "obs.csv", "prior": "log-uniform", "im": "pga"}"#,
    )
    .unwrap();
    let err = stderr(&rockfrag(&["figures", s(&infer)]));
    assert!(
        err.contains("holds an inference")
            && err.contains("rockfrag infer obs.csv --study s.toml --out ")
            && err.contains("--format png"),
        "{err}"
    );
    // an inference over two IMs: the command names both, or it would redo
    // a one-IM inference and draw no joint figure
    std::fs::write(
        infer.join("inference.json"),
        r#"{"spec": "s.toml", "observations": "obs.csv", "prior": "log-uniform", "im": "pga",
            "two_im": {"im1": "pga", "im2": "pgv"}}"#,
    )
    .unwrap();
    let err = stderr(&rockfrag(&["figures", s(&infer)]));
    assert!(err.contains("--im pga,pgv --format png"), "{err}");
}

/// Ctrl-C during a run: the run stops at the end of its chunk, says it was
/// interrupted and how to resume (exit 130), and running it again resumes
/// and ends with the bytes of a run never interrupted.
#[cfg(unix)]
#[test]
fn ctrl_c_says_how_to_resume_and_resumes() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = tmp.path().join("long.toml");
    let text = std::fs::read_to_string(SMALL)
        .unwrap()
        .replace("records = 3", "records = 1000");
    std::fs::write(&spec, text).unwrap();
    let out = tmp.path().join("out");
    let child = Command::new(env!("CARGO_BIN_EXE_rockfrag"))
        .args(["run", s(&spec), "--out", s(&out), "--threads", "1"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // once the first chunk is checkpointed, Ctrl-C
    let t0 = std::time::Instant::now();
    while !out.join("checkpoint.json").exists() {
        assert!(t0.elapsed().as_secs() < 60, "no checkpoint");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let o = child.wait_with_output().unwrap();
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted: ") && err.contains("run the same command again to resume"),
        "{err}"
    );
    assert!(
        !out.join("outcomes.csv").exists(),
        "an interrupted run looks finished"
    );
    let o = rockfrag(&["run", s(&spec), "--out", s(&out)]);
    assert!(
        o.status.success() && stderr(&o).contains("resumed after"),
        "{}",
        stderr(&o)
    );
    let alone = tmp.path().join("alone");
    assert!(
        rockfrag(&["run", s(&spec), "--out", s(&alone)])
            .status
            .success()
    );
    assert_eq!(
        std::fs::read(out.join("outcomes.csv")).unwrap(),
        std::fs::read(alone.join("outcomes.csv")).unwrap()
    );
}

/// Every column `outcomes.csv` can have is described in docs/outputs.md's
/// `outcomes.csv` section (`uplifted`, `flights`, `liftoff_holds`,
/// `settles`, `stick_holds` were described nowhere), and the block's 2B, 2H
/// and H/B are defined there.
#[test]
fn every_outcomes_column_is_documented() {
    use rockfrag::outcomes_csv::Columns;
    let docs =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/outputs.md")).unwrap();
    let start = docs
        .find("## `outcomes.csv`")
        .expect("an outcomes.csv section");
    let section = &docs[start..start + docs[start + 3..].find("\n## ").unwrap() + 3];
    let all = Columns {
        pgv: true,
        files: true,
        pairs: true,
        scale: true,
        time_in_mode: true,
        stats: true,
        floor: true,
        sensitivity: true,
        stack: true,
        middle: true,
        stack_values: true,
    };
    for column in all.list() {
        let name = format!("`{}`", column.name());
        assert!(
            section.contains(&name),
            "{name} is not described in docs/outputs.md"
        );
    }
    for term in ["**2B**", "**2H**", "**H/B**", "**θc**"] {
        assert!(
            docs.contains(term),
            "docs/outputs.md does not define {term}"
        );
    }
}

/// A floor given by flags is refused naming the flag the user typed
/// (`--floor-period`, `--period (value 2)`), not the spec's field
/// `floor[0].period` that the check shares with studies.
#[test]
fn floor_flags_are_named_as_typed() {
    let o = rockfrag(&[
        "simulate",
        "--seed",
        "1",
        "--pga",
        "0.3",
        "--floor-period",
        "1e300",
        "--floor-damping",
        "0.05",
    ]);
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(err.contains("invalid --floor-period = 1e300"), "{err}");
    assert!(!err.contains("floor[0]"), "{err}");
    let tmp = tempfile::tempdir().unwrap();
    let rec = record(tmp.path(), "r.csv");
    let o = rockfrag(&[
        "floor",
        s(&rec),
        "--period",
        "1",
        "--period",
        "1e-9",
        "--damping",
        "0.05",
    ]);
    let err = stderr(&o);
    assert!(err.contains("invalid --period (value 2) = 1e-9"), "{err}");
}
