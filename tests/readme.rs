//! The README's commands and every documentation link cannot rot.
//!
//! A new user copies the README's shell blocks line by line; a renamed flag,
//! subcommand or example file would break them without any other test
//! noticing. So every command line of every `sh` block of README.md is
//! checked against the real binary (`CARGO_BIN_EXE_rockfrag`):
//!
//! - every `rockfrag …` line (and `cargo run --release -- …`, which is the
//!   same binary) names subcommands that exist, uses only flags that its
//!   subcommand's `--help` lists, and names files under `studies/` that exist;
//! - the cheap ones are then *run*, in order, in a temporary folder (with
//!   `studies/…` arguments pointing into this repository): the built-in
//!   default study (about 0.5 s), the vase (about 2 s), its figures as PNG,
//!   its risk, both exports, a `simulate`, the hospital study (about 1.5 s)
//!   and `rockfrag --help`; each must exit 0. Only `rockfrag infer` (about
//!   20 s on two cores, over this test's budget) is checked for flags and
//!   files without being run (`tests/infer.rs` runs inference itself);
//! - `cargo test --release` is the README's second command and exactly the
//!   test command of `.ci/run`; `cargo install --locked --path .` installs
//!   this package's `rockfrag` binary with Cargo.lock's versions (every
//!   `cargo install` in README.md and docs/ says `--locked`: without it
//!   cargo takes the newest versions the manifest allows, issue 37);
//! - any other command (a program the test does not know) fails the test,
//!   so a new command in the README needs a check here.
//!
//! Not checked: the Python block beyond its function names (which must be
//! in the package's `__all__`; `python/tests` runs the package), the numbers
//! the prose quotes, and `text` blocks (synopses, formulas).
//!
//! Links: every relative Markdown link in README.md, studies/README.md and
//! docs/*.md must point to an existing file (anchors are not checked).

use std::path::{Path, PathBuf};
use std::process::Command;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");
const BIN: &str = env!("CARGO_BIN_EXE_rockfrag");

/// Subcommands the test checks for flags but does not run (too slow).
const NOT_RUN: &[&str] = &["infer"];

fn read(rel: &str) -> String {
    std::fs::read_to_string(Path::new(ROOT).join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// The contents of the fenced blocks of `md` whose info string is `lang`.
fn blocks(md: &str, lang: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut current: Option<String> = None;
    for line in md.lines() {
        let t = line.trim_start();
        if let Some(info) = t.strip_prefix("```") {
            match current.take() {
                Some(b) => out.push(b),
                None if info.trim() == lang => current = Some(String::new()),
                None => current = Some(String::from("\u{0}skip")),
            }
            continue;
        }
        if let Some(b) = current.as_mut() {
            b.push_str(line);
            b.push('\n');
        }
    }
    out.retain(|b| !b.starts_with('\u{0}'));
    out
}

/// The command lines of the README's sh blocks, continuation lines joined,
/// comments dropped, split into words (the README uses no quoting).
fn readme_commands() -> Vec<Vec<String>> {
    let mut cmds = Vec::new();
    for block in blocks(&read("README.md"), "sh") {
        let joined = block.replace("\\\n", " ");
        for line in joined.lines() {
            let line = line.split(" #").next().unwrap().trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            cmds.push(line.split_whitespace().map(String::from).collect());
        }
    }
    cmds
}

/// The rockfrag arguments of a command line, or None if it is not one.
fn rockfrag_args(cmd: &[String]) -> Option<Vec<String>> {
    match cmd {
        [first, rest @ ..] if first == "rockfrag" => Some(rest.to_vec()),
        [c, r, rel, dd, rest @ ..]
            if c == "cargo" && r == "run" && rel == "--release" && dd == "--" =>
        {
            Some(rest.to_vec())
        }
        _ => None,
    }
}

fn help(path: &[&str]) -> String {
    let out = Command::new(BIN).args(path).arg("--help").output().unwrap();
    assert!(
        out.status.success(),
        "rockfrag {} --help failed",
        path.join(" ")
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The subcommand path of `args` (e.g. `export openquake`): leading words
/// that `--help` lists under "Commands:".
fn subcommands(args: &[String]) -> Vec<String> {
    let mut path: Vec<String> = Vec::new();
    for a in args {
        if a.starts_with('-') {
            break;
        }
        let refs: Vec<&str> = path.iter().map(String::as_str).collect();
        let h = help(&refs);
        let Some(cmds) = h.split("Commands:").nth(1) else {
            break;
        };
        let cmds = cmds.split("\n\n").next().unwrap();
        let listed = cmds
            .lines()
            .any(|l| l.split_whitespace().next() == Some(a.as_str()));
        if !listed {
            break;
        }
        path.push(a.clone());
    }
    path
}

/// The first two commands are the ones issue 29 asks to keep: the default
/// study, then the tests; and the test command is exactly CI's.
#[test]
fn readme_starts_with_run_and_test_and_ci_runs_the_same_tests() {
    let cmds = readme_commands();
    let words = |c: &Vec<String>| c.join(" ");
    assert_eq!(words(&cmds[0]), "cargo run --release -- run");
    assert_eq!(words(&cmds[1]), "cargo test --release");
    assert!(
        read(".ci/run")
            .lines()
            .any(|l| l.trim() == "cargo test --release"),
        ".ci/run must run the README's test command, `cargo test --release`"
    );
}

/// Every `cargo install` the README and the docs show (in code blocks and
/// inline) builds with Cargo.lock's versions: `--locked`.
#[test]
fn every_install_line_is_locked() {
    let mut files = vec!["README.md".to_string(), "studies/README.md".to_string()];
    for e in std::fs::read_dir(Path::new(ROOT).join("docs")).unwrap() {
        let name = e.unwrap().file_name().into_string().unwrap();
        if name.ends_with(".md") {
            files.push(format!("docs/{name}"));
        }
    }
    let mut installs = 0;
    for f in &files {
        // lines joined, so an install split over two lines is one
        let text = read(f).replace('\n', " ");
        for (i, _) in text.match_indices("cargo install") {
            let rest = &text[i..text.len().min(i + 40)];
            assert!(
                rest.starts_with("cargo install --locked"),
                "{f}: `{rest}…` without --locked"
            );
            installs += 1;
        }
    }
    assert!(installs >= 2, "the README installs rockfrag");
}

/// Every command line of the README is one the test knows how to check, its
/// subcommands and flags exist (so renaming a flag fails here), and the
/// files it names exist.
#[test]
fn every_readme_command_names_existing_subcommands_flags_and_files() {
    let cmds = readme_commands();
    assert!(
        cmds.len() >= 8,
        "expected the README's commands, found {cmds:?}"
    );
    for cmd in &cmds {
        let line = cmd.join(" ");
        if line == "cargo test --release" {
            continue;
        }
        if line == "cargo install --locked --path ." {
            assert!(
                read("Cargo.toml").contains("name = \"rockfrag\""),
                "the package is rockfrag"
            );
            assert!(
                Path::new(ROOT).join("src/main.rs").exists(),
                "the package has a binary"
            );
            continue;
        }
        let args = rockfrag_args(cmd)
            .unwrap_or_else(|| panic!("the README runs `{line}`, which no test checks"));
        let path = subcommands(&args);
        if let Some(first) = args.first().filter(|a| !a.starts_with('-')) {
            assert!(
                !path.is_empty(),
                "`{line}`: `{first}` is not a subcommand of rockfrag"
            );
        }
        let refs: Vec<&str> = path.iter().map(String::as_str).collect();
        let h = help(&refs);
        for a in &args[path.len()..] {
            if a.starts_with("--") {
                let flag = a.split('=').next().unwrap();
                let listed = h
                    .split(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
                    .any(|w| w == flag);
                assert!(
                    listed,
                    "`{line}`: {flag} is not a flag of `rockfrag {}`",
                    path.join(" ")
                );
            } else if a.starts_with("studies/") {
                assert!(
                    Path::new(ROOT).join(a).exists(),
                    "`{line}`: {a} does not exist"
                );
            }
        }
    }
}

/// The README's commands, run in order as a user would (each after the one
/// before it), except the slow ones named in `NOT_RUN`.
#[test]
fn readme_commands_run() {
    let dir = tempfile::tempdir().unwrap();
    for cmd in readme_commands() {
        let Some(args) = rockfrag_args(&cmd) else {
            continue;
        };
        if args.first().is_some_and(|a| NOT_RUN.contains(&a.as_str())) {
            continue;
        }
        let args: Vec<String> = args
            .iter()
            .map(|a| match a.starts_with("studies/") {
                true => Path::new(ROOT).join(a).display().to_string(),
                false => a.clone(),
            })
            .collect();
        let out = Command::new(BIN)
            .args(&args)
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "`{}` failed: {}",
            cmd.join(" "),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    for f in [
        "results/vase/summary.md",
        "results/vase/figures/fragility.png",
        "results/vase/risk.csv",
    ] {
        assert!(
            dir.path().join(f).exists(),
            "the README's walk-through writes {f}"
        );
    }
}

/// The vase spec the README shows is the file it runs: every setting line of
/// the README's toml block is a line of `studies/vase.toml`.
#[test]
fn readme_vase_excerpt_matches_the_study_file() {
    let spec = read("studies/vase.toml");
    let spec_lines: Vec<&str> = spec
        .lines()
        .map(|l| l.split('#').next().unwrap().trim())
        .collect();
    for block in blocks(&read("README.md"), "toml") {
        for line in block.lines() {
            let setting = line.split('#').next().unwrap().trim();
            if !setting.is_empty() {
                assert!(
                    spec_lines.contains(&setting),
                    "README's `{setting}` is not in studies/vase.toml"
                );
            }
        }
    }
}

/// The Python block calls only functions the package exports.
#[test]
fn readme_python_calls_exported_functions() {
    let init = read("python/rockfrag/__init__.py");
    // `__all__ = [ ... ]`, on one line or several.
    let start = init.find("\n__all__").expect("__all__ in the package");
    let all = &init[start..start + init[start..].find(']').expect("__all__'s closing ]")];
    for block in blocks(&read("README.md"), "python") {
        for part in block.split("rockfrag.").skip(1) {
            let name: String = part
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            assert!(
                all.contains(&format!("\"{name}\"")),
                "README calls rockfrag.{name}, not in __all__"
            );
        }
    }
}

/// Relative links `](target)` of a Markdown file, without anchors.
fn links(md: &str) -> Vec<String> {
    md.split("](")
        .skip(1)
        .filter_map(|s| s.split(')').next())
        .map(|t| t.split_whitespace().next().unwrap_or("").to_string())
        .filter(|t| {
            !t.is_empty() && !t.contains("://") && !t.starts_with('#') && !t.starts_with("mailto:")
        })
        .map(|t| t.split('#').next().unwrap().to_string())
        .collect()
}

/// Every relative link of README.md, studies/README.md and docs/*.md points
/// to a file that exists, so moving a document or figure cannot leave a dead link.
#[test]
fn every_relative_link_points_to_an_existing_file() {
    let mut files = vec![
        PathBuf::from("README.md"),
        PathBuf::from("studies/README.md"),
    ];
    for e in std::fs::read_dir(Path::new(ROOT).join("docs")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "md") {
            files.push(Path::new("docs").join(p.file_name().unwrap()));
        }
    }
    let mut checked = 0;
    for f in &files {
        let md = read(f.to_str().unwrap());
        let base = Path::new(ROOT).join(f.parent().unwrap());
        for l in links(&md) {
            assert!(
                base.join(&l).exists(),
                "{}: link to {l}, which does not exist",
                f.display()
            );
            checked += 1;
        }
    }
    assert!(
        checked > 20,
        "only {checked} links found: the link parser is broken"
    );
}
