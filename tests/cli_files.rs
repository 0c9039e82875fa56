//! Files are never clobbered (issue 37, "Files"): outputs are written
//! through symbolic links and into devices and pipes, never renamed over
//! them; an input is not overwritten by the output made from it; orphan
//! temporary files of killed writers are removed; `merge` respects another
//! study's folder and its lock; `run --force` replaces a study whole; the
//! files of one fragility fit are read as one set or not at all.

mod common;
use common::{rockfrag, stderr, stdout};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, SystemTime};

const SMALL: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/fixtures/specs/small.toml"
);

/// A study whose overturning curve can be fitted: 20 records at 10 PGA
/// levels, one slender block (200 analyses of 10 s, well under a second).
const FITTED: &str = r#"name = "fitted"
seed = 5
records = 20
[motion]
duration = 10.0
[grid]
width = [0.5]
aspect = [3]
restitution = [0.0]
friction = ["inf"]
pga = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 1.0, 1.2]
[fragility]
bootstrap = 50
"#;

const HAZARD: &str = "iml,annual_rate\n0.05,0.1\n0.1,0.01\n0.5,0.001\n1.0,0.0001\n";

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn write(path: &Path, text: &str) -> PathBuf {
    std::fs::write(path, text).unwrap();
    path.to_path_buf()
}

fn is_link(p: &Path) -> bool {
    std::fs::symlink_metadata(p).is_ok_and(|m| m.file_type().is_symlink())
}

/// What `rockfrag motion --seed 1 --pga 0.3` prints: the bytes every
/// output of these tests must hold.
fn motion_csv() -> Vec<u8> {
    let o = rockfrag(&["motion", "--seed", "1", "--pga", "0.3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    o.stdout
}

fn mkfifo(path: &Path) {
    let ok = Command::new("mkfifo").arg(path).status().unwrap().success();
    assert!(ok, "mkfifo {}", path.display());
}

/// A pid that is not running: a child that has exited.
fn dead_pid() -> u32 {
    let mut child = Command::new("true").spawn().unwrap();
    let pid = child.id();
    child.wait().unwrap();
    pid
}

/// An output named through a symbolic link is written to the link's
/// target, the link kept; through a link that does not resolve yet, the
/// target is created. Before, the link was replaced by a regular file
/// (`--out so` with `so -> /proc/self/fd/1` became a file).
#[test]
fn outputs_are_written_through_symbolic_links() {
    let tmp = tempfile::tempdir().unwrap();
    let expected = motion_csv();
    let target = write(&tmp.path().join("target.csv"), "old\n");
    let link = tmp.path().join("link.csv");
    std::os::unix::fs::symlink("target.csv", &link).unwrap();
    let o = rockfrag(&["motion", "--seed", "1", "--pga", "0.3", "--out", s(&link)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(is_link(&link), "the link was replaced");
    assert_eq!(std::fs::read(&target).unwrap(), expected);
    // a link to a file not yet there: the file is created, the link kept
    std::fs::create_dir(tmp.path().join("sub")).unwrap();
    let ahead = tmp.path().join("ahead.csv");
    std::os::unix::fs::symlink("sub/new.csv", &ahead).unwrap();
    let o = rockfrag(&["motion", "--seed", "1", "--pga", "0.3", "--out", s(&ahead)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(is_link(&ahead));
    assert_eq!(
        std::fs::read(tmp.path().join("sub/new.csv")).unwrap(),
        expected
    );
    // a figure (written by path, PNG by its extension) through a link
    let png = write(&tmp.path().join("plot.png"), "old");
    let plot = tmp.path().join("plot-link.png");
    std::os::unix::fs::symlink(&png, &plot).unwrap();
    let o = rockfrag(&["motion", "--seed", "1", "--pga", "0.3", "--plot", s(&plot)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(is_link(&plot));
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    // nothing temporary is left beside them
    let names: Vec<String> = std::fs::read_dir(tmp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp-"))
        .collect();
    assert!(names.is_empty(), "{names:?}");
}

/// A named pipe, `/dev/null` and `/dev/full` (each reached through a link
/// in a temporary folder, so that a regression cannot touch /dev) are
/// written into: the pipe's reader gets every byte, the pipe and the links
/// stay as they were, and `/dev/full`'s "no space left" is an error that
/// says so. Before, each was replaced by a regular file (as root,
/// `--out /dev/full` turned the device into a CSV file).
#[test]
fn pipes_and_devices_are_written_into_not_replaced() {
    let tmp = tempfile::tempdir().unwrap();
    let expected = motion_csv();
    let fifo = tmp.path().join("pipe.csv");
    mkfifo(&fifo);
    let reader = {
        let fifo = fifo.clone();
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || tx.send(std::fs::read(&fifo).unwrap()).unwrap());
        rx
    };
    let o = rockfrag(&["motion", "--seed", "1", "--pga", "0.3", "--out", s(&fifo)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let still_a_pipe = {
        use std::os::unix::fs::FileTypeExt;
        std::fs::symlink_metadata(&fifo)
            .unwrap()
            .file_type()
            .is_fifo()
    };
    assert!(still_a_pipe, "the pipe was replaced by a file");
    let got = reader
        .recv_timeout(Duration::from_secs(20))
        .expect("the pipe's reader got nothing");
    assert_eq!(got, expected);

    let null = tmp.path().join("null.csv");
    std::os::unix::fs::symlink("/dev/null", &null).unwrap();
    let o = rockfrag(&["motion", "--seed", "1", "--pga", "0.3", "--out", s(&null)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(is_link(&null));
    // the history of simulate, another writer, into the same device
    let o = rockfrag(&[
        "simulate",
        "--seed",
        "1",
        "--pga",
        "0.3",
        "--history",
        s(&null),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(is_link(&null));

    if Path::new("/dev/full").exists() {
        let full = tmp.path().join("full.csv");
        std::os::unix::fs::symlink("/dev/full", &full).unwrap();
        let o = rockfrag(&["motion", "--seed", "1", "--pga", "0.3", "--out", s(&full)]);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        assert!(
            stderr(&o).contains("No space left on device"),
            "{}",
            stderr(&o)
        );
        assert!(is_link(&full));
    }
}

/// `floor X --out X` and `simulate --motion X --history X` refuse to
/// write over their input (also through another name for it), which is
/// left as it was. Before, the floor's motion replaced the ground record
/// it was computed from.
#[test]
fn an_output_never_replaces_its_input() {
    let tmp = tempfile::tempdir().unwrap();
    let record = tmp.path().join("ground.csv");
    std::fs::write(&record, motion_csv()).unwrap();
    let before = std::fs::read(&record).unwrap();
    let alias = tmp.path().join("alias.csv");
    std::os::unix::fs::symlink(&record, &alias).unwrap();
    for out in [&record, &alias] {
        let o = rockfrag(&[
            "floor",
            s(&record),
            "--period",
            "0.5",
            "--damping",
            "0.05",
            "--out",
            s(out),
        ]);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        assert!(
            stderr(&o).contains("--out names the ground record"),
            "{}",
            stderr(&o)
        );
        assert_eq!(std::fs::read(&record).unwrap(), before);
    }
    let o = rockfrag(&["simulate", "--motion", s(&record), "--history", s(&alias)]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--history names the --motion record"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read(&record).unwrap(), before);
    // another file is fine
    let floor = tmp.path().join("floor.csv");
    let o = rockfrag(&[
        "floor",
        s(&record),
        "--period",
        "0.5",
        "--damping",
        "0.05",
        "--out",
        s(&floor),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// Temporary files that a killed writer left (`.NAME.tmp-PID-N`, PID gone)
/// are removed: at the start of a run in its folder and its figures/ at
/// once, and by a later write of the same file once they are two minutes
/// old.
/// A live process's temporary file and other files are kept. Before, they
/// stayed for ever.
#[test]
fn orphan_temporary_files_are_removed() {
    let tmp = tempfile::tempdir().unwrap();
    let dead = dead_pid();
    let me = std::process::id();
    let out = tmp.path().join("out");
    std::fs::create_dir_all(out.join("figures")).unwrap();
    let orphans = [
        out.join(format!(".outcomes.csv.tmp-{dead}-0")),
        out.join(format!(".summary.md.tmp-{dead}-3")),
        out.join(format!("figures/.motion.svg.tmp-{dead}-7.svg")),
    ];
    let kept = [
        out.join(format!(".other.csv.tmp-{me}-0")),
        out.join("notes.tmp-1-2.txt"),
    ];
    for p in orphans.iter().chain(&kept) {
        write(p, "partial");
    }
    let o = rockfrag(&["run", SMALL, "--out", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    for p in &orphans {
        assert!(!p.exists(), "{} was left", p.display());
    }
    for p in &kept {
        assert!(p.exists(), "{} was removed", p.display());
    }

    // a write of m.csv into a folder: a dead writer's temporary m.csv two
    // minutes old goes; a fresh one (perhaps a writer on another host) stays
    // for now, and so does another file's
    let dir = tmp.path().join("motions");
    std::fs::create_dir(&dir).unwrap();
    let old = write(&dir.join(format!(".m.csv.tmp-{dead}-1")), "partial");
    let fresh = write(&dir.join(format!(".m.csv.tmp-{dead}-2")), "partial");
    let other = write(&dir.join(format!(".other.csv.tmp-{dead}-3")), "partial");
    let hour_ago = SystemTime::now() - Duration::from_secs(3600);
    for p in [&old, &other] {
        std::fs::File::options()
            .write(true)
            .open(p)
            .unwrap()
            .set_modified(hour_ago)
            .unwrap();
    }
    let o = rockfrag(&[
        "motion",
        "--seed",
        "1",
        "--pga",
        "0.3",
        "--out",
        s(&dir.join("m.csv")),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!old.exists(), "an hour-old orphan was left");
    assert!(fresh.exists(), "a fresh temporary file was removed");
    assert!(other.exists(), "another file's temporary file was removed");
}

/// Runs the shards 1/2 and 2/2 of the small study into `dir`/s1, s2.
fn shards(dir: &Path) -> [PathBuf; 2] {
    let dirs = [dir.join("s1"), dir.join("s2")];
    for (k, d) in dirs.iter().enumerate() {
        let shard = format!("{}/2", k + 1);
        let o = rockfrag(&["run", SMALL, "--out", s(d), "--shard", &shard]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    dirs
}

/// `merge --out` into the finished folder of another study is refused as
/// `run` refuses it (exit 1, naming the study and --force), leaving it as it
/// was; `--force` replaces it whole (the other study's fit goes with it).
/// A folder another process holds the lock of is refused too. Before, the
/// merge overwrote the other study's outcomes and ignored its lock.
#[test]
fn merge_respects_another_studys_folder_and_its_lock() {
    let tmp = tempfile::tempdir().unwrap();
    let [s1, s2] = shards(tmp.path());
    let spec = write(&tmp.path().join("fitted.toml"), FITTED);
    let other = tmp.path().join("other");
    let o = rockfrag(&["run", s(&spec), "--out", s(&other)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let before = std::fs::read(other.join("outcomes.csv")).unwrap();
    assert!(other.join("fragility.csv").exists());

    let o = rockfrag(&["merge", s(&s1), s(&s2), "--out", s(&other)]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("finished run of other analyses")
            && err.contains("'fitted'")
            && err.contains("--force"),
        "{err}"
    );
    assert_eq!(std::fs::read(other.join("outcomes.csv")).unwrap(), before);

    let o = rockfrag(&["merge", s(&s1), s(&s2), "--out", s(&other), "--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let whole = tmp.path().join("whole");
    assert!(
        rockfrag(&["run", SMALL, "--out", s(&whole)])
            .status
            .success()
    );
    assert_eq!(
        std::fs::read(other.join("outcomes.csv")).unwrap(),
        std::fs::read(whole.join("outcomes.csv")).unwrap()
    );
    // the small study has no [fragility]: the other study's fit is gone
    assert!(!other.join("fragility.csv").exists());
    assert!(
        !std::fs::read_to_string(other.join("summary.md"))
            .unwrap()
            .contains("## Fragility")
    );

    // a folder locked by a live process (this test, holding run.lock)
    let busy = tmp.path().join("busy");
    std::fs::create_dir(&busy).unwrap();
    let mut lock = std::fs::File::options()
        .read(true)
        .write(true)
        .create(true)
        .truncate(true)
        .open(busy.join("run.lock"))
        .unwrap();
    lock.lock().unwrap();
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap_or_default();
    write!(
        lock,
        "pid={}\nhost={}\nstarted_unix=1\ncommand=test\n",
        std::process::id(),
        host.trim()
    )
    .unwrap();
    let o = rockfrag(&["merge", s(&s1), s(&s2), "--out", s(&busy)]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("another run is writing into this folder"),
        "{}",
        stderr(&o)
    );
    assert!(!busy.join("outcomes.csv").exists());
}

/// `run --force` with a different spec replaces the folder's study whole:
/// the old fit, risk files and summary are removed with its outcomes, so the
/// new summary reports no fit it did not make; a file of the user's in the
/// folder is kept. Before, the old fit stayed and the new summary.md
/// reported it.
#[test]
fn force_replaces_the_previous_study_whole() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = write(&tmp.path().join("fitted.toml"), FITTED);
    let hazard = write(&tmp.path().join("hazard.csv"), HAZARD);
    let out = tmp.path().join("out");
    assert!(
        rockfrag(&["run", s(&spec), "--out", s(&out)])
            .status
            .success()
    );
    let o = rockfrag(&["risk", s(&out), "--hazard", s(&hazard)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mine = write(&out.join("my-notes.txt"), "mine");
    for f in [
        "fragility.csv",
        "fragility_bootstrap.csv",
        "risk.csv",
        "figures/risk.svg",
    ] {
        assert!(out.join(f).exists(), "{f}");
    }
    assert!(
        std::fs::read_to_string(out.join("summary.md"))
            .unwrap()
            .contains("## Risk")
    );

    let o = rockfrag(&["run", SMALL, "--out", s(&out), "--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in [
        "fragility.csv",
        "fragility_curves.csv",
        "fragility_bootstrap.csv",
        "fragility.xml",
        "risk.csv",
        "risk_hazard.csv",
        "figures/risk.svg",
    ] {
        assert!(!out.join(f).exists(), "{f} of the old study was left");
    }
    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(
        !summary.contains("## Fragility") && !summary.contains("## Risk"),
        "{summary}"
    );
    assert!(mine.exists());
}

/// The files of one fit are read as a set: a PGV `fragility.csv` beside the
/// PGA `fragility_bootstrap.csv` of the fit before it (what a refit killed
/// between its files leaves) is refused by `risk`, `export` and `figures`,
/// naming the file and saying to rerun `rockfrag fragility`; so is a fit
/// whose writing was interrupted; refitting makes a whole set again. Before,
/// `risk` combined them into a band that excluded its own estimate.
#[test]
fn files_of_two_fits_are_never_combined() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = write(&tmp.path().join("fitted.toml"), FITTED);
    let hazard = write(&tmp.path().join("hazard.csv"), HAZARD);
    let out = tmp.path().join("out");
    assert!(
        rockfrag(&["run", s(&spec), "--out", s(&out)])
            .status
            .success()
    );
    let pga_boot = std::fs::read(out.join("fragility_bootstrap.csv")).unwrap();
    let o = rockfrag(&["fragility", s(&out), "--im", "pgv", "--bootstrap", "50"]);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::write(out.join("fragility_bootstrap.csv"), &pga_boot).unwrap();
    let oq = tmp.path().join("oq");
    for args in [
        vec!["risk", s(&out), "--hazard", s(&hazard)],
        vec![
            "export",
            "openquake",
            s(&out),
            "--hazard",
            s(&hazard),
            "--out",
            s(&oq),
        ],
        vec!["figures", s(&out)],
    ] {
        let o = rockfrag(&args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(
            err.contains("fragility_bootstrap.csv") && err.contains("rerun `rockfrag fragility"),
            "{args:?}: {err}"
        );
    }
    // an interrupted fit's set file says so, and is refused whatever its files
    let o = rockfrag(&["fragility", s(&out), "--bootstrap", "50"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        rockfrag(&["risk", s(&out), "--hazard", s(&hazard)])
            .status
            .success()
    );
    std::fs::write(
        out.join("fragility_set.json"),
        "{\"status\": \"writing\"}\n",
    )
    .unwrap();
    let o = rockfrag(&["risk", s(&out), "--hazard", s(&hazard)]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("interrupted"), "{}", stderr(&o));
    let o = rockfrag(&["fragility", s(&out), "--bootstrap", "50"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = rockfrag(&["risk", s(&out), "--hazard", s(&hazard)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("overturning"), "{}", stdout(&o));
}

/// `outcomes.csv` named by a symbolic link in the study folder (a user
/// keeping the big file on another disk) is written through: its target
/// gets the rows, the link stays. Before, the finished partial file was
/// renamed over the link (the last clobbering case of issue 37's notes).
#[test]
fn outcomes_through_a_link_keep_the_link() {
    let tmp = tempfile::tempdir().unwrap();
    let study = tmp.path().join("study");
    let big = tmp.path().join("big");
    std::fs::create_dir_all(&study).unwrap();
    std::fs::create_dir_all(&big).unwrap();
    let link = study.join("outcomes.csv");
    std::os::unix::fs::symlink("../big/outcomes.csv", &link).unwrap();
    let o = rockfrag(&["run", SMALL, "--out", s(&study)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        is_link(&link),
        "outcomes.csv was replaced by a regular file"
    );
    let rows = std::fs::read_to_string(big.join("outcomes.csv")).unwrap();
    // small.toml: 24 analyses, one header line
    assert_eq!(rows.lines().count(), 25, "{rows}");
    // the same study into a plain folder gives the same bytes
    let plain = tmp.path().join("plain");
    let o = rockfrag(&["run", SMALL, "--out", s(&plain)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        rows,
        std::fs::read_to_string(plain.join("outcomes.csv")).unwrap()
    );
}
