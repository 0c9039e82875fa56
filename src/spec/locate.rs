//! Where a field is written: the line numbers of spec errors
//! (`file:line: field: message`), found in the spec's text.

use crate::error::{Error, Shown};
use std::path::Path;

/// The spec being validated, as its errors name it: its text (to find the
/// line of a field) and its path.
pub(super) struct Origin<'a> {
    /// The spec's text.
    pub(super) text: &'a str,
    /// The spec's path.
    pub(super) origin: &'a Path,
}

impl Origin<'_> {
    /// A bad value: the field's path in the spec, the value as given and what
    /// would have been accepted.
    pub(super) fn bad(&self, field: &str, value: &dyn Shown, expected: &str) -> Error {
        Error::Spec {
            path: self.origin.to_path_buf(),
            line: locate(self.text, field),
            field: field.to_string(),
            value: value.shown(),
            expected: expected.to_string(),
        }
    }

    /// Re-labels an error of an embedded settings struct, whose field is
    /// named relative to its table, with `prefix` (`"solver."`, or `""` when
    /// the field is already a full spec path) and the spec's file and line.
    pub(super) fn nested(&self, prefix: &str, err: Error) -> Error {
        match err {
            Error::InvalidParameter {
                field,
                value,
                expected,
            } => self.bad(&format!("{prefix}{field}"), &value, &expected),
            other => other,
        }
    }
}

/// Line index (0-based) of the `nth` (0-based) header `[a.b]` or `[[a.b]]`
/// of `table` in `lines`, or `None`.
fn header_line(lines: &[&str], table: &str, nth: usize) -> Option<usize> {
    lines
        .iter()
        .enumerate()
        .filter(|(_, l)| {
            let t = l.trim();
            t.strip_prefix('[')
                .and_then(|t| t.split(']').next())
                .map(|h| h.trim().trim_start_matches('[').trim() == table)
                .unwrap_or(false)
        })
        .nth(nth)
        .map(|(i, _)| i)
}

/// Whether `line` assigns `key` (`key = …` or `key.sub = …`).
fn assigns(line: &str, key: &str) -> bool {
    line.trim_start()
        .strip_prefix(key)
        .map(|rest| {
            let rest = rest.trim_start();
            rest.starts_with('=') || rest.starts_with('.')
        })
        .unwrap_or(false)
}

/// Best-effort line of a field path such as `grid.friction[1].mu_k` in the
/// spec text: the line assigning the deepest key found under its table
/// header, else the header itself; 0 if not written.
fn locate(text: &str, field: &str) -> usize {
    let lines: Vec<&str> = text.lines().collect();
    // The index of each part, `[i]`, if any: for an array of tables
    // (`fragility.limit_state[1].name`) it picks the table's i-th header.
    let index: Vec<usize> = field
        .split('.')
        .map(|p| {
            p.split_once('[')
                .and_then(|(_, i)| i.trim_end_matches(']').parse().ok())
                .unwrap_or(0)
        })
        .collect();
    let parts: Vec<&str> = field
        .split('.')
        .map(|p| p.split('[').next().unwrap_or(p))
        .collect();
    // a field that is a table written only as deeper headers
    // (`uncertainty.stack.NAME` of `[uncertainty.stack.NAME.top]`): its
    // first header
    let whole = parts.join(".");
    if let Some(h) = lines.iter().position(|l| {
        let t = l.trim().trim_start_matches('[').trim_start();
        t.strip_prefix(whole.as_str())
            .is_some_and(|rest| rest.starts_with(['.', ']']))
            && l.trim().starts_with('[')
    }) && index.iter().all(|&i| i == 0)
        && !lines.iter().any(|l| assigns(l, parts[parts.len() - 1]))
    {
        return h + 1;
    }
    for split in (0..parts.len()).rev() {
        let table = parts[..split].join(".");
        let (start, header) = if table.is_empty() {
            (0, None)
        } else {
            match header_line(&lines, &table, index[split - 1]) {
                Some(h) => (h + 1, Some(h)),
                None => continue,
            }
        };
        let end = lines[start..]
            .iter()
            .position(|l| l.trim_start().starts_with('['))
            .map_or(lines.len(), |p| start + p);
        let key = parts[split];
        if let Some(p) = lines[start..end].iter().position(|l| assigns(l, key)) {
            return start + p + 1;
        }
        if let Some(h) = header {
            return h + 1;
        }
    }
    0
}

/// The line (1-based) of byte `offset` and the dotted key path written there
/// (its table header plus the key on that line), for TOML errors.
pub(super) fn key_at(text: &str, offset: usize) -> (usize, String) {
    let offset = offset.min(text.len());
    let before = &text[..offset];
    let line_no = before.matches('\n').count() + 1;
    let mut table = String::new();
    for l in before.lines() {
        let t = l.trim();
        if let Some(h) = t.strip_prefix('[') {
            table = h
                .trim_start_matches('[')
                .split(']')
                .next()
                .unwrap_or("")
                .trim()
                .to_string();
        }
    }
    let line = text.lines().nth(line_no - 1).unwrap_or("");
    let key = line
        .split_once('=')
        .map(|(k, _)| k.trim())
        .filter(|k| !k.is_empty() && !k.starts_with('['))
        .unwrap_or("");
    let path = match (table.is_empty(), key.is_empty()) {
        (true, _) => key.to_string(),
        (false, true) => table,
        (false, false) => format!("{table}.{key}"),
    };
    (line_no, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locate_finds_keys_under_their_table() {
        let text = "name = \"x\"\n[grid]\nwidth = [1]\naspect = [2, -1]\n[solver]\nrtol = 2\n";
        assert_eq!(locate(text, "name"), 1);
        assert_eq!(locate(text, "grid.aspect[1]"), 4);
        assert_eq!(locate(text, "solver.rtol"), 6);
        assert_eq!(locate(text, "solver.atol"), 5);
        assert_eq!(locate(text, "records"), 0);
        let tables = "[[f.ls]]\nname = \"a\"\n[[f.ls]]\nname = \"a\"\n";
        assert_eq!(locate(tables, "f.ls[1].name"), 4);
        assert_eq!(locate(tables, "f.ls[0].name"), 2);
        // a table written as deeper headers only
        let deep = "[u]\nseed = 1\n[u.stack.s.top]\nwidth = 1\n";
        assert_eq!(locate(deep, "u.stack.s"), 3);
        assert_eq!(locate(deep, "u.stack.s.top"), 3);
        assert_eq!(locate(deep, "u.stack.s.top.width"), 4);
    }

    #[test]
    fn key_at_names_table_and_key() {
        let text = "[grid]\naspct = [2]\n";
        let off = text.find("aspct").unwrap();
        assert_eq!(key_at(text, off), (2, "grid.aspct".to_string()));
    }
}
