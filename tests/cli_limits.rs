//! Inputs that crashed or hung are refused at once with a message naming
//! the flag or field, the value and the limit (issue 37, "Inputs that crash
//! or hang"): sizes that aborted on an allocation, blocks and hazard rates
//! that made a loop run for ever, thread counts that ran the machine out of
//! process ids, record files without end, a run too big for its disk. Every
//! command here runs under a time limit, so that a regression fails the
//! test instead of hanging it.

mod common;
use common::{stderr, stdout};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

const SMALL: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/fixtures/specs/small.toml"
);

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn write(path: &Path, text: &str) -> PathBuf {
    std::fs::write(path, text).unwrap();
    path.to_path_buf()
}

/// Runs rockfrag with `args`, killed after `limit`: `None` if it had to be.
fn within(limit: Duration, args: &[&str]) -> Option<Output> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_rockfrag"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // drain the pipes while waiting, so a chatty child cannot block
    let out = child.stdout.take().unwrap();
    let err = child.stderr.take().unwrap();
    let read = |mut r: Box<dyn std::io::Read + Send>| {
        std::thread::spawn(move || {
            let mut v = Vec::new();
            let _ = r.read_to_end(&mut v);
            v
        })
    };
    let (out, err) = (read(Box::new(out)), read(Box::new(err)));
    let t0 = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break Some(status);
        }
        if t0.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let (stdout, stderr) = (out.join().unwrap(), err.join().unwrap());
    status.map(|status| Output {
        status,
        stdout,
        stderr,
    })
}

/// `within` 20 s, which every case here needs at most a fraction of.
fn quick(args: &[&str]) -> Output {
    within(Duration::from_secs(20), args)
        .unwrap_or_else(|| panic!("rockfrag {args:?} ran for more than 20 s"))
}

/// Asserts a refusal (exit 1, or 2 for a flag clap refuses) whose message
/// holds every one of `words`.
fn refused(o: &Output, words: &[&str]) {
    let err = stderr(o);
    assert!(
        matches!(o.status.code(), Some(1 | 2)),
        "status {:?}: {err}",
        o.status
    );
    for w in words {
        assert!(err.contains(w), "{w:?} not in: {err}");
    }
}

/// `motion --duration 1e9` and `--dt 1e-9` (5·10¹⁰ and 3·10¹⁰ samples),
/// and `[motion] duration = 1e9` in a spec, are refused naming the field,
/// the value and the limit of 2²² samples; the spec before its output
/// folder or lock is made. `fragility --bootstrap 1000000000` is refused
/// naming the limit of 100000. Before, each aborted on an allocation of
/// hundreds of GB, and the spec's run left run.lock behind.
#[test]
fn sizes_that_aborted_on_an_allocation_are_refused() {
    let o = quick(&["motion", "--seed", "1", "--pga", "0.3", "--duration", "1e9"]);
    refused(&o, &["duration", "1000000000", "4194304 samples"]);
    let o = quick(&["motion", "--seed", "1", "--pga", "0.3", "--dt", "1e-9"]);
    refused(&o, &["dt = 1e-9", "4194304 samples"]);

    let tmp = tempfile::tempdir().unwrap();
    let spec = std::fs::read_to_string(SMALL)
        .unwrap()
        .replace("duration = 10.0", "duration = 1e9");
    let spec = write(&tmp.path().join("long.toml"), &spec);
    let out = tmp.path().join("out");
    let o = quick(&["run", s(&spec), "--out", s(&out)]);
    refused(&o, &["long.toml:", "motion.duration", "4194304 samples"]);
    assert!(!out.exists(), "the refused run made its folder");

    let fitted = tmp.path().join("fitted");
    assert!(quick(&["run", SMALL, "--out", s(&fitted)]).status.success());
    let o = quick(&["fragility", s(&fitted), "--bootstrap", "1000000000"]);
    refused(&o, &["--bootstrap", "1000000000", "100000"]);
    let spec = std::fs::read_to_string(SMALL).unwrap() + "[fragility]\nbootstrap = 1000000000\n";
    let spec = write(&tmp.path().join("boot.toml"), &spec);
    let o = quick(&["run", s(&spec), "--out", s(&tmp.path().join("b"))]);
    refused(&o, &["fragility.bootstrap", "100000"]);
    assert!(!fitted.join("run.lock").exists() && !tmp.path().join("b").exists());
}

/// `simulate --width 1e200`, `--aspect 1e160` and a spec's `grid.width =
/// [1e300]` are refused naming the field and the physical range (1 mm to
/// 1 km, H/B 10⁻³ to 10³). Before, the landing search of free flight never
/// ended (R² overflows from 2B ≈ 10¹⁵⁴ m).
#[test]
fn blocks_beyond_physics_are_refused_not_hung() {
    let o = quick(&[
        "simulate", "--seed", "1", "--pga", "0.5", "--width", "1e200",
    ]);
    refused(&o, &["invalid width = 1e200", "from 0.001 to 1000"]);
    let o = quick(&[
        "simulate", "--seed", "1", "--pga", "0.5", "--aspect", "1e160",
    ]);
    refused(&o, &["invalid aspect = 1e160", "from 0.001 to 1000"]);
    let tmp = tempfile::tempdir().unwrap();
    let spec = std::fs::read_to_string(SMALL)
        .unwrap()
        .replace("width = [0.5]", "width = [1e300]");
    let spec = write(&tmp.path().join("wide.toml"), &spec);
    let o = quick(&["run", s(&spec), "--out", s(&tmp.path().join("out"))]);
    refused(&o, &["wide.toml:", "grid.width[0]", "from 0.001 to 1000"]);
    // the ends of the ranges run
    let o = quick(&[
        "simulate", "--seed", "1", "--pga", "0.5", "--width", "1000", "--aspect", "1000",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// A hazard curve with rates of 10²⁰⁰ a year and more is refused naming the
/// line, the level and the limit (1000 a year). Before, `risk` hung in the
/// figure's axis (an infinite bound looped over 2³¹ decades), and took 2 s
/// at 10²⁵⁰.
#[test]
fn hazard_rates_beyond_any_site_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = std::fs::read_to_string(SMALL)
        .unwrap()
        .replace("records = 3", "records = 20")
        .replace("aspect = [4, 6]", "aspect = [3]")
        .replace("restitution = [0.0, 0.6]", "restitution = [0.0]")
        .replace(
            "pga = [0.4, 0.8]",
            "pga = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 1.0, 1.2]",
        )
        + "[fragility]\nbootstrap = 20\n";
    let spec = write(&tmp.path().join("fit.toml"), &spec);
    let out = tmp.path().join("out");
    let o = quick(&["run", s(&spec), "--out", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    for top in ["1e200", "1.7e308"] {
        let hazard = write(
            &tmp.path().join("hazard.csv"),
            &format!("iml,annual_rate\n0.05,{top}\n0.1,1e100\n0.5,1e-3\n1.0,1e-4\n"),
        );
        let o = quick(&["risk", s(&out), "--hazard", s(&hazard)]);
        refused(
            &o,
            &["hazard.csv:2", "intensity level 0.05", "annual rate ≤ 1000"],
        );
    }
    let hazard = write(
        &tmp.path().join("hazard.csv"),
        "iml,annual_rate\n0.05,1000\n0.1,1\n0.5,1e-3\n1.0,1e-4\n",
    );
    let o = quick(&["risk", s(&out), "--hazard", s(&hazard)]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// `run --threads 10000` uses at most 4 threads per available core, says
/// so, and writes the same bytes as one thread. Before, it started all
/// 10000 (80 s instead of 0.5 s; `--threads 1000000` ran the machine out of
/// process ids).
#[test]
fn thread_counts_are_capped_per_core() {
    let tmp = tempfile::tempdir().unwrap();
    let (many, one) = (tmp.path().join("many"), tmp.path().join("one"));
    let o = quick(&["run", SMALL, "--out", s(&many), "--threads", "10000"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    assert!(
        stderr(&o).contains(&format!("10000 threads asked for, {} used", 4 * cores)),
        "{}",
        stderr(&o)
    );
    assert!(
        quick(&["run", SMALL, "--out", s(&one), "--threads", "1"])
            .status
            .success()
    );
    let read = |d: &Path| std::fs::read(d.join("outcomes.csv")).unwrap();
    assert_eq!(read(&many), read(&one));
}

/// `bench --records 0` is a usage error naming the flag. Before, it
/// panicked ("the reference ran every case").
#[test]
fn bench_without_records_is_a_usage_error() {
    let o = quick(&["bench", "--records", "0"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--records"), "{}", stderr(&o));
}

/// A 600 MiB record file (sparse: it takes no disk) is refused by its size
/// before it is read, naming the limit, and a link to `/dev/zero` at its
/// first byte (no text holds a NUL); a study with such a record leaves no file in its
/// folder. Before, a 2 GB file took 4.2 GB of memory before it was
/// refused, `/dev/zero` was read without end, and a run left its partial
/// outcomes behind.
#[test]
fn huge_and_endless_record_files_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let big = tmp.path().join("big.csv");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(600 << 20)
        .unwrap();
    let o = quick(&["simulate", "--motion", s(&big)]);
    refused(&o, &["big.csv", "is 600 MiB", "512 MiB a record file"]);
    let zero = tmp.path().join("zero.csv");
    std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
    let o = quick(&["simulate", "--motion", s(&zero)]);
    refused(&o, &["zero.csv", "holds a NUL byte (byte 0)", "/dev/zero"]);

    let spec = write(
        &tmp.path().join("rec.toml"),
        "name = \"rec\"\nrecord_files = [\"big.csv\"]\n[grid]\nwidth = [0.5]\naspect = [4]\n\
         restitution = [0.0]\nfriction = [\"inf\"]\npga = [0.3]\n",
    );
    let out = tmp.path().join("out");
    let o = quick(&["run", s(&spec), "--out", s(&out)]);
    refused(&o, &["big.csv", "512 MiB"]);
    let left: Vec<_> = std::fs::read_dir(&out)
        .map(|d| d.map(|e| e.unwrap().file_name()).collect())
        .unwrap_or_default();
    assert!(left.is_empty(), "left behind: {left:?}");
}

/// A grid of 2·10¹⁰ analyses (some 4 TB of outcomes.csv) says the size it
/// will take and the free space after its pilot, and is refused there when
/// the disk cannot hold it, leaving no partial file; with
/// `--no-space-check` it would start. Before, it started without a word.
#[test]
fn a_run_too_big_for_its_disk_is_refused_after_the_pilot() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = write(
        &tmp.path().join("big.toml"),
        "name = \"big\"\nrecords = 10000000\n[motion]\nduration = 2.0\n[grid]\n\
         width = [0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1]\n\
         aspect = [2, 3, 4, 5, 6, 7, 8, 9, 10, 11]\n\
         restitution = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]\n\
         friction = [\"inf\", [0.5, 0.5]]\npga = [0.3]\n",
    );
    let out = tmp.path().join("out");
    let o = within(
        Duration::from_secs(60),
        &["run", s(&spec), "--out", s(&out)],
    )
    .expect("the run started its 10^10 analyses");
    let err = stderr(&o);
    assert!(err.contains("outcomes.csv: about"), "{err}");
    assert!(err.contains("20000000000 analyses"), "{err}");
    refused(&o, &["not enough disk space", "--no-space-check"]);
    assert!(!out.join("outcomes.csv.partial").exists());
    assert!(!out.join("run.lock").exists());
    assert!(stdout(&o).is_empty());
}
