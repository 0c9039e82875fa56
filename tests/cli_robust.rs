//! Everyday robustness of the command line (issue 17): a locked output
//! folder, a finished folder of another spec, what a run says before and
//! while it runs, a quiet console, messages that point at the right thing.

mod common;
use common::{rockfrag, run_spec, stderr, stdout};
use std::path::Path;
use std::process::{Command, Stdio};

const SMALL: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/fixtures/specs/small.toml"
);

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rockfrag"))
}

/// A copy of the small spec with `extra` appended and `name` as its name.
fn spec_with(dir: &Path, name: &str, extra: &str) -> String {
    let text = std::fs::read_to_string(SMALL)
        .unwrap()
        .replace("name = \"small\"", &format!("name = \"{name}\""))
        + extra;
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// A second `run` into a folder another run is writing is refused at once
/// (exit 1, naming the holder's pid and host), and the first run's files are
/// untouched: it finishes with the same outcomes.csv as a run alone. The
/// first run is slowed down with 400 records on one thread (about 3 s here)
/// so that the second starts while it runs; before this lock both computed
/// and the second died on the first's partial file.
#[test]
fn second_run_into_a_busy_folder_is_refused_naming_the_holder() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec_with(tmp.path(), "slow", "");
    let text = std::fs::read_to_string(&spec)
        .unwrap()
        .replace("records = 3", "records = 400");
    std::fs::write(&spec, text).unwrap();
    let out = tmp.path().join("out");
    let out_s = out.to_str().unwrap();
    let first = bin()
        .args(["run", &spec, "--out", out_s, "--threads", "1"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let lock = out.join("run.lock");
    let t0 = std::time::Instant::now();
    while !std::fs::read_to_string(&lock).is_ok_and(|t| t.contains("pid=")) {
        assert!(t0.elapsed().as_secs() < 30, "the first run took no lock");
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let pid = first.id();
    let second = rockfrag(&["run", &spec, "--out", out_s, "--threads", "1"]);
    let first_done = first.wait_with_output().unwrap();
    assert_eq!(second.status.code(), Some(1), "{}", stderr(&second));
    let err = stderr(&second);
    assert!(
        err.contains(&format!("pid {pid} on host "))
            && err.contains("another run is writing into this folder"),
        "{err}"
    );
    assert!(
        first_done.status.success(),
        "{}",
        String::from_utf8_lossy(&first_done.stderr)
    );
    assert!(!lock.exists(), "the lock outlived its run");
    let alone = tmp.path().join("alone");
    let o = rockfrag(&["run", &spec, "--out", alone.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let read = |d: &Path| std::fs::read(d.join("outcomes.csv")).unwrap();
    assert_eq!(read(&out), read(&alone));
}

/// A lock file left by a run that died (a pid that is not running on this
/// host) is stale: the next run takes it over and completes.
#[test]
fn a_dead_runs_lock_is_taken_over() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_string())
        .unwrap_or_else(|_| "unknown".into());
    // pid 4194304 is above Linux's largest pid (2^22): never alive.
    std::fs::write(
        out.join("run.lock"),
        format!("pid=4194304\nhost={host}\nstarted_unix=1\ncommand=rockfrag run\n"),
    )
    .unwrap();
    let o = rockfrag(&["run", SMALL, "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.join("outcomes.csv").exists());
}

/// A finished folder of another spec is not overwritten silently: `run`
/// refuses, naming both spec hashes and `--force`, and leaves outcomes.csv
/// as it was; with `--force` it replaces it. Before, the second spec's
/// results replaced the first's without a word.
#[test]
fn finished_folder_of_another_spec_needs_force() {
    let tmp = tempfile::tempdir().unwrap();
    let other = spec_with(tmp.path(), "other", "");
    let text = std::fs::read_to_string(&other)
        .unwrap()
        .replace("seed = 5", "seed = 6");
    std::fs::write(&other, text).unwrap();
    let out = tmp.path().join("out");
    let out_s = out.to_str().unwrap();
    assert!(rockfrag(&["run", SMALL, "--out", out_s]).status.success());
    let before = std::fs::read(out.join("outcomes.csv")).unwrap();
    // The same spec again keeps the finished run's analyses.
    let o = rockfrag(&["run", SMALL, "--out", out_s]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("already finished"), "{}", stderr(&o));
    let o = rockfrag(&["run", &other, "--out", out_s]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(
        err.contains("finished run of other analyses") && err.contains("--force"),
        "{err}"
    );
    assert_eq!(std::fs::read(out.join("outcomes.csv")).unwrap(), before);
    let o = rockfrag(&["run", &other, "--out", out_s, "--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_ne!(std::fs::read(out.join("outcomes.csv")).unwrap(), before);
}

/// Before it starts, a run says how many analyses it will run, and after a
/// pilot (one record per intensity level) how long it expects to take (off
/// a terminal too, as in a batch log). Before, nothing was printed until
/// the end.
#[test]
fn run_announces_its_size_and_an_estimate() {
    let tmp = tempfile::tempdir().unwrap();
    let o = rockfrag(&[
        "run",
        SMALL,
        "--out",
        tmp.path().join("o").to_str().unwrap(),
        "--threads",
        "1",
    ]);
    assert!(o.status.success());
    let err = stderr(&o);
    let first = err.lines().next().unwrap_or("");
    assert_eq!(first, "running 24 analyses on 1 thread", "{err}");
    // With 100 records (200 units of 4 analyses over 2 levels) the pilot
    // solves one unit per level: 8 analyses.
    let spec = spec_with(tmp.path(), "bigger", "");
    let text = std::fs::read_to_string(&spec)
        .unwrap()
        .replace("records = 3", "records = 100");
    std::fs::write(&spec, text).unwrap();
    let o = rockfrag(&[
        "run",
        &spec,
        "--out",
        tmp.path().join("b").to_str().unwrap(),
        "--threads",
        "1",
    ]);
    let err = stderr(&o);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines[0], "running 800 analyses on 1 thread", "{err}");
    assert!(
        lines[1].starts_with("estimate: ")
            && lines[1].contains("from a pilot of 8 analyses, one record per intensity level"),
        "{err}"
    );
}

/// The default console is quiet: a run with a bootstrap fit and figures
/// says one line per step and one line for all the bootstrap notes (at most
/// 10 lines; it was one table row per case plus one note per case), and
/// `--verbose` brings the table and the notes back.
#[test]
fn run_console_is_quiet_unless_verbose() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec_with(
        tmp.path(),
        "quiet",
        "\n[output]\nfigures = true\n\n[fragility]\nbootstrap = 50\n",
    );
    let out = tmp.path().join("out");
    let o = rockfrag(&["run", &spec, "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let all = format!("{}{}", stdout(&o), stderr(&o));
    assert!(all.lines().count() <= 10, "{all}");
    assert!(
        all.contains("fragility: ") && all.contains("curves fitted"),
        "{all}"
    );
    // the table's header (a note may name "the limit state": with the free
    // motion after the record this study's curves are not fitted and say so)
    assert!(!all.contains("median (g)"), "the table is printed: {all}");
    let o = rockfrag(&["run", &spec, "--out", out.to_str().unwrap(), "--verbose"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("median (g)"), "{}", stdout(&o));
}

/// `--bootstrap 0` gives no band, so the table has no `[90%]` heading.
#[test]
fn no_band_heading_without_a_bootstrap() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    assert!(
        rockfrag(&["run", SMALL, "--out", out.to_str().unwrap()])
            .status
            .success()
    );
    let o = rockfrag(&["fragility", out.to_str().unwrap(), "--bootstrap", "0"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("median (g)") && !text.contains('%'), "{text}");
    let o = rockfrag(&["fragility", out.to_str().unwrap(), "--bootstrap", "20"]);
    assert!(stdout(&o).contains("median (g) [90%]"), "{}", stdout(&o));
}

/// μk > μs is a usage error found with the arguments (status 2, naming both
/// flags), not a solver error naming the record (`solving record synthetic
/// seed=1 index=0: invalid mu_k`, status 1, as before).
#[test]
fn mu_k_above_mu_s_is_a_usage_error() {
    let o = rockfrag(&[
        "simulate", "--seed", "1", "--pga", "0.5", "--mu-s", "0.3", "--mu-k", "0.5",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("--mu-k 0.5") && err.contains("--mu-s 0.3") && !err.contains("record"),
        "{err}"
    );
}

#[test]
fn non_ascii_spec_file_name_gives_a_valid_study_name() {
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(SMALL)
        .unwrap()
        .replace("name = \"small\"\n", "");
    let spec = tmp.path().join("stüdy 2.toml");
    std::fs::write(&spec, text).unwrap();
    let out = tmp.path().join("out");
    let o = run_spec(&spec, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let manifest = std::fs::read_to_string(out.join("manifest.json")).unwrap();
    assert!(manifest.contains("\"study\": \"study\""), "{manifest}");
}

/// Writing to a reader that has gone (`rockfrag simulate … | head -1`)
/// ends quietly with status 141, as a tool killed by SIGPIPE, not with a
/// panic (status 101, "failed printing to stdout: Broken pipe"). The pipe's
/// read end is closed before the child starts, so its first write fails
/// whatever the scheduling (closing it after the spawn raced the child's
/// write on a loaded machine: the write went into the pipe's buffer, exit 0).
#[test]
fn broken_pipe_exits_quietly() {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let child = bin()
        .args(["simulate", "--seed", "1", "--pga", "0.5"])
        .stdout(writer)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(141), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// `fragility` on one shard's folder refuses (it would fit a part of the
/// data without a word), naming the shard; `--partial` fits it anyway.
#[test]
fn fragility_on_a_shard_folder_needs_partial() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("shard-1");
    let d = dir.to_str().unwrap();
    assert!(
        rockfrag(&["run", SMALL, "--shard", "1/2", "--out", d])
            .status
            .success()
    );
    let o = rockfrag(&["fragility", d, "--bootstrap", "0"]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(
        err.contains("shard 1/2") && err.contains("--partial"),
        "{err}"
    );
    let o = rockfrag(&["fragility", d, "--bootstrap", "0", "--partial"]);
    assert!(o.status.success(), "{}", stderr(&o));
}
