//! The module graph is one-way (issue 12).
//!
//! Expectation: `src/lib.rs` declares the top-level modules so that each
//! uses only modules declared above it, so no module imports one that
//! (directly or through others) imports it back; inside every folder module
//! the files import each other without cycles too (a child that imports an
//! item defined in its folder's `mod.rs` counts as importing `mod.rs`). The
//! check reads the sources: every `crate::NAME` and `super::NAME` path
//! outside comments and outside `#[cfg(test)]` modules is an import.
//!
//! It also pins the size limit the issue set: no file in `src/` over 1,000
//! lines.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// The code of a file: comment lines and `#[cfg(test)]` modules removed.
fn code(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let text = match text.find("#[cfg(test)]\nmod tests") {
        Some(i) => &text[..i],
        None => &text[..],
    };
    text.lines()
        .map(|l| match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Every identifier that follows `prefix` (e.g. `crate::`) in `code`, also
/// inside grouped imports such as `crate::{a::X, b}`.
fn paths_after(code: &str, prefix: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut rest = code;
    while let Some(i) = rest.find(prefix) {
        let before = rest[..i].chars().next_back();
        rest = &rest[i + prefix.len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        if let Some(group) = rest.strip_prefix('{') {
            // `crate::{a::X, b, c::{..}}`: the first segment of each item.
            let mut depth = 1;
            let mut item = String::new();
            let mut at_start = true;
            for c in group.chars() {
                if depth == 1 && at_start {
                    if c.is_alphanumeric() || c == '_' {
                        item.push(c);
                    } else if !item.is_empty() {
                        out.insert(std::mem::take(&mut item));
                        at_start = false;
                    }
                }
                match c {
                    '{' => depth += 1,
                    '}' => depth -= 1,
                    ',' if depth == 1 => at_start = true,
                    _ => {}
                }
                if depth == 0 {
                    break;
                }
            }
            if !item.is_empty() {
                out.insert(item);
            }
            continue;
        }
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        if !name.is_empty() {
            out.insert(name);
        }
    }
    out
}

/// Every identifier directly followed by `::` (the head of a path).
fn path_heads(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut ident = String::new();
    let mut prev = ' ';
    let mut chars = code.chars().peekable();
    while let Some(c) = chars.next() {
        if c.is_alphanumeric() || c == '_' {
            if ident.is_empty() && prev == ':' {
                // the middle of a path, not its head
                ident.push('\0');
            }
            ident.push(c);
        } else {
            if c == ':'
                && chars.peek() == Some(&':')
                && !ident.is_empty()
                && !ident.starts_with('\0')
            {
                out.insert(std::mem::take(&mut ident));
            }
            ident.clear();
        }
        prev = c;
    }
    out
}

/// The `.rs` files of a module: `src/NAME.rs`, or every file under `src/NAME/`.
fn files_of(path: &Path) -> Vec<PathBuf> {
    if path.is_dir() {
        let mut v = Vec::new();
        for entry in std::fs::read_dir(path).unwrap() {
            v.extend(files_of(&entry.unwrap().path()));
        }
        v
    } else if path.extension().is_some_and(|e| e == "rs") {
        vec![path.to_path_buf()]
    } else {
        Vec::new()
    }
}

/// Top-level modules in the order `lib.rs` declares them.
fn declared_modules() -> Vec<String> {
    std::fs::read_to_string(src().join("lib.rs"))
        .unwrap()
        .lines()
        .filter_map(|l| {
            let l = l.trim();
            let l = l.strip_prefix("pub ").unwrap_or(l);
            l.strip_prefix("mod ")?
                .strip_suffix(';')
                .map(str::to_string)
        })
        .collect()
}

fn module_path(name: &str) -> PathBuf {
    let dir = src().join(name);
    if dir.is_dir() {
        dir
    } else {
        src().join(format!("{name}.rs"))
    }
}

#[test]
fn each_top_level_module_uses_only_modules_declared_above_it() {
    let order = declared_modules();
    assert!(order.len() >= 10, "lib.rs declares {order:?}");
    let mut violations = Vec::new();
    for (i, module) in order.iter().enumerate() {
        for file in files_of(&module_path(module)) {
            for used in paths_after(&code(&file), "crate::") {
                let Some(j) = order.iter().position(|m| *m == used) else {
                    continue; // a re-exported item such as `crate::Error`
                };
                if j > i {
                    violations.push(format!(
                        "{} uses crate::{used}, declared after {module}",
                        file.strip_prefix(src()).unwrap().display()
                    ));
                }
            }
        }
    }
    assert!(violations.is_empty(), "{}", violations.join("\n"));
}

/// Import edges between the files of folder module `dir`: sibling `a`
/// imports sibling `b` (`mod` stands for `mod.rs`).
fn sibling_edges(dir: &Path, top: &str) -> BTreeMap<String, BTreeSet<String>> {
    let name_of = |p: &Path| -> String {
        if p.is_dir() {
            p.file_name().unwrap().to_string_lossy().into_owned()
        } else {
            p.file_stem().unwrap().to_string_lossy().into_owned()
        }
    };
    let children: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir() || p.extension().is_some_and(|e| e == "rs"))
        .collect();
    let names: BTreeSet<String> = children.iter().map(|p| name_of(p)).collect();
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for child in &children {
        let me = name_of(child);
        let mut used = BTreeSet::new();
        for file in files_of(child) {
            let code = code(&file);
            let in_child_dir = file.parent() != Some(dir);
            if me == "mod" {
                // mod.rs uses a child through `child::…` paths (`pub use`, calls).
                for n in path_heads(&code) {
                    if n != "mod" && names.contains(&n) {
                        used.insert(n);
                    }
                }
            } else if !in_child_dir {
                for s in paths_after(&code, "super::") {
                    used.insert(if names.contains(&s) { s } else { "mod".into() });
                }
            }
            // `crate::top::sibling` from anywhere below the folder.
            if !top.is_empty() {
                for s in paths_after(&code, &format!("crate::{top}::")) {
                    if names.contains(&s) && s != me {
                        used.insert(s);
                    }
                }
            }
        }
        used.remove(&me);
        edges.insert(me, used);
    }
    edges
}

fn find_cycle(edges: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        n: &str,
        edges: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        match state.get(n) {
            Some(2) => return None,
            Some(1) => {
                let i = stack.iter().position(|s| s == n).unwrap();
                let mut cycle = stack[i..].to_vec();
                cycle.push(n.to_string());
                return Some(cycle);
            }
            _ => {}
        }
        state.insert(n.to_string(), 1);
        stack.push(n.to_string());
        for m in edges.get(n).into_iter().flatten() {
            if let Some(c) = visit(m, edges, state, stack) {
                return Some(c);
            }
        }
        stack.pop();
        state.insert(n.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for n in edges.keys() {
        if let Some(c) = visit(n, edges, &mut state, &mut Vec::new()) {
            return Some(c);
        }
    }
    None
}

#[test]
fn the_files_of_each_folder_module_import_each_other_one_way() {
    let mut dirs = Vec::new();
    let mut stack = vec![(src(), String::new())];
    while let Some((dir, top)) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                let t = if top.is_empty() {
                    p.file_name().unwrap().to_string_lossy().into_owned()
                } else {
                    String::new() // deeper folders: `super::` only
                };
                stack.push((p.clone(), t.clone()));
                dirs.push((p, t));
            }
        }
    }
    assert!(dirs.len() >= 6, "{dirs:?}");
    let mut cycles = Vec::new();
    for (dir, top) in dirs {
        let edges = sibling_edges(&dir, &top);
        if let Some(cycle) = find_cycle(&edges) {
            cycles.push(format!(
                "import cycle among the files of {}: {}",
                dir.display(),
                cycle.join(" → ")
            ));
        }
    }
    assert!(cycles.is_empty(), "{}", cycles.join("\n"));
}

#[test]
fn the_checker_sees_a_cycle_when_there_is_one() {
    // The checker itself must be able to fail: a → b → c → a.
    let mut edges = BTreeMap::new();
    for (a, b) in [("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")] {
        edges
            .entry(a.to_string())
            .or_insert_with(BTreeSet::new)
            .insert(b.to_string());
    }
    assert_eq!(
        find_cycle(&edges).unwrap(),
        ["a", "b", "c", "a"].map(String::from)
    );
    let grouped = paths_after(
        "use crate::{solver::X, motion, fragility::{A, B}};",
        "crate::",
    );
    assert_eq!(
        grouped,
        ["fragility", "motion", "solver"].map(String::from).into()
    );
}

/// The seed paper is a layer on top (issue 27): the modules declared
/// before `paper` in `lib.rs` (the generic pipeline: spec, motion, solver,
/// study, fragility, risk, figures, …) never import it, and no file
/// outside `src/paper/` and the CLI names the paper's tables, its published
/// rows or its study test — the paper layer alone knows the paper exists.
#[test]
fn generic_modules_do_not_know_the_paper() {
    let order = declared_modules();
    let paper = order
        .iter()
        .position(|m| m == "paper")
        .expect("lib.rs declares the paper layer");
    for generic in [
        "spec",
        "study",
        "fragility",
        "figures",
        "risk",
        "outcomes_csv",
    ] {
        let i = order.iter().position(|m| m == generic).unwrap();
        assert!(i < paper, "{generic} is declared after paper: {order:?}");
    }
    let mut named = Vec::new();
    for file in files_of(&src()) {
        let rel = file.strip_prefix(src()).unwrap();
        if rel.starts_with("paper") || rel.starts_with("cli") {
            continue;
        }
        let code = code(&file);
        for name in [
            "TABLES",
            "is_papers",
            "PaperRow",
            "PaperTables",
            "paper::tables",
        ] {
            if code.contains(name) {
                named.push(format!("{} names {name}", rel.display()));
            }
        }
        let generic = order[..paper]
            .iter()
            .any(|m| rel.starts_with(m) || rel == Path::new(&format!("{m}.rs")));
        if generic && paths_after(&code, "crate::").contains("paper") {
            named.push(format!("{} imports crate::paper", rel.display()));
        }
    }
    assert!(named.is_empty(), "{}", named.join("\n"));
}

#[test]
fn no_source_file_is_over_a_thousand_lines() {
    let long: Vec<String> = files_of(&src())
        .into_iter()
        .filter_map(|f| {
            let n = std::fs::read_to_string(&f).unwrap().lines().count();
            (n > 1000).then(|| format!("{}: {n} lines", f.display()))
        })
        .collect();
    assert!(long.is_empty(), "{}", long.join("\n"));
}

/// A message split over source lines without a `\` continuation keeps the
/// next line's indentation inside the sentence ("to place its
/// <18 spaces>levels in"): no string literal in src/ has a run of six or
/// more spaces between a word and a lower-case word after the first word
/// (a one-word label aligned before its value stays allowed).
#[test]
fn no_message_carries_a_source_line_indentation() {
    let mut bad = Vec::new();
    for file in files_of(&src()) {
        let text = std::fs::read_to_string(&file).unwrap();
        for (n, line) in text.lines().enumerate() {
            let chars: Vec<char> = line.chars().collect();
            let mut quoted = false;
            let mut opened = 0;
            let mut i = 0;
            while i < chars.len() {
                let c = chars[i];
                if c == '"' && (i == 0 || chars[i - 1] != '\\') {
                    quoted = !quoted;
                    opened = i;
                } else if quoted
                    && c == ' '
                    && i > 0
                    && !chars[i - 1].is_whitespace()
                    && chars[opened..i].contains(&' ')
                {
                    let run = chars[i..].iter().take_while(|&&s| s == ' ').count();
                    let next = chars.get(i + run).copied().unwrap_or(' ');
                    if run >= 6 && (next.is_lowercase() || next == '…' || next == '[') {
                        bad.push(format!("{}:{}: {}", file.display(), n + 1, line.trim()));
                    }
                    i += run;
                    continue;
                }
                i += 1;
            }
        }
    }
    assert!(
        bad.is_empty(),
        "indentation inside messages:\n{}",
        bad.join("\n")
    );
}
