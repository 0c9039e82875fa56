//! Small helpers shared by every writer: nothing half-written is left
//! behind, numbers are written so they read back exactly, and printed
//! numbers have three significant figures.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Writes a file atomically: `write` fills a temporary file in the same
/// directory (its name keeps `path`'s extension, for writers that choose a
/// format by it), which is synced and renamed over `path` only once it is
/// complete; on failure it is removed and `path` is untouched. The
/// directory is created if missing.
pub fn write_atomic_path(
    path: &Path,
    write: impl FnOnce(&Path) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir)?;
    let tmp = temp_path(dir, path);
    let result = (|| {
        write(&tmp)?;
        std::fs::File::open(&tmp)?.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// [`write_atomic_path`] for a writer of bytes: `write` writes the whole
/// content to a buffered stream.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    write_atomic_path(path, |tmp| {
        let mut w = BufWriter::new(std::fs::File::create(tmp)?);
        write(&mut w)?;
        w.flush()
    })
}

/// A fresh hidden name in `dir` for a temporary copy of `path`:
/// `.name.tmp-<pid>-<n>[.ext]`.
fn temp_path(dir: &Path, path: &Path) -> PathBuf {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let ext = path
        .extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default();
    dir.join(format!(".{name}.tmp-{}-{n}{ext}", std::process::id()))
}

/// `text` without a leading byte-order mark (U+FEFF), which Excel and
/// Notepad write at the start of a UTF-8 CSV file: every reader of a text
/// file a user gives (records, surveys, hazard curves, specs) takes it off,
/// so the first column's name or value reads as written.
pub fn strip_bom(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

/// The text of the file `path` a user gave, without a byte-order mark
/// ([`strip_bom`]). A folder is refused as one (`PATH: is a folder, not a
/// file`), not with the system's bare "Is a directory".
pub fn read_text(path: &Path) -> crate::Result<String> {
    if path.is_dir() {
        return Err(crate::Error::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(
                std::io::ErrorKind::IsADirectory,
                "is a folder, not a file",
            ),
        });
    }
    let text = std::fs::read_to_string(path).map_err(crate::Error::io(path))?;
    Ok(match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_string(),
        None => text,
    })
}

/// Whether `a` and `b` name the same file: the same canonical path (so
/// `a.AT2`, `./a.AT2` and a link to it are one file), or, where either
/// cannot be resolved (a file not yet there), the same path once `.`
/// components are dropped.
pub fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => {
            let plain = |p: &Path| -> PathBuf {
                p.components()
                    .filter(|c| !matches!(c, std::path::Component::CurDir))
                    .collect()
            };
            plain(a) == plain(b)
        }
    }
}

/// Creates the output folder `dir` (and its parents) if missing. A file
/// where the folder or one of its parents should be is refused naming it
/// (`results/vase: is a file, not a folder`), not with the system's bare
/// "File exists".
pub fn create_folder(dir: &Path) -> crate::Result<()> {
    if let Some(file) = dir.ancestors().find(|a| a.exists() && !a.is_dir()) {
        return Err(crate::Error::Io {
            path: file.to_path_buf(),
            source: std::io::Error::new(
                std::io::ErrorKind::NotADirectory,
                if file == dir {
                    "is a file, not a folder: give the folder to write into (it is created if \
                     missing)"
                } else {
                    "is a file, not a folder, so no folder can be made inside it"
                },
            ),
        });
    }
    std::fs::create_dir_all(dir).map_err(crate::Error::io(dir))
}

/// Replaces the section of the markdown file at `path` that starts with
/// the line `heading` (e.g. `## Risk`) and runs to the next `## ` heading
/// with `section`; a file without it gets `section` before the first of
/// the headings `before` it has, else at its end. Atomic.
pub fn replace_section(
    path: &Path,
    heading: &str,
    section: &str,
    before: &[&str],
) -> std::io::Result<()> {
    let text = std::fs::read_to_string(path)?;
    let lines: Vec<&str> = text.lines().collect();
    let is = |l: &str, h: &str| l.trim_end() == h;
    let new: Vec<&str> = section.trim_end().lines().collect();
    let (keep_to, resume_at) = match lines.iter().position(|l| is(l, heading)) {
        Some(i) => {
            let end = lines[i + 1..]
                .iter()
                .position(|l| l.starts_with("## "))
                .map_or(lines.len(), |j| i + 1 + j);
            (i, end)
        }
        None => {
            let at = lines
                .iter()
                .position(|l| before.iter().any(|h| is(l, h)))
                .unwrap_or(lines.len());
            (at, at)
        }
    };
    let mut head: Vec<&str> = lines[..keep_to].to_vec();
    while head.last().is_some_and(|l| l.trim().is_empty()) {
        head.pop();
    }
    let mut out: Vec<&str> = head;
    if !out.is_empty() {
        out.push("");
    }
    out.extend(new);
    if resume_at < lines.len() {
        out.push("");
        out.extend(&lines[resume_at..]);
    }
    write_atomic(path, |w| {
        for l in &out {
            writeln!(w, "{l}")?;
        }
        Ok(())
    })
}

/// The shortest text that reads back as exactly `x`, with an exponent for
/// tiny and huge values: the one rule of files and messages, defined with
/// the messages in [`crate::error::number`].
pub use crate::error::number;

/// Three significant figures, for tables people read: plain from 10⁻³ to
/// 10⁶ (`0.148`, `12.3`, `5480`), in scientific notation outside
/// (`3.42e-41`, a graze's θmax/θc; `1.47e-4`, an annual rate), `0` for zero.
///
/// ```
/// use rockfrag::io_util::sig3;
/// assert_eq!(sig3(0.1483), "0.148");
/// assert_eq!(sig3(5480.2), "5480");
/// assert_eq!(sig3(1.4712e-4), "1.47e-4");
/// assert_eq!(sig3(0.0), "0");
/// ```
pub fn sig3(x: f64) -> String {
    if x == 0.0 {
        return "0".to_string();
    }
    if !x.is_finite() {
        return x.to_string();
    }
    if !(1e-3..1e6).contains(&x.abs()) {
        return format!("{x:.2e}");
    }
    let decimals = (2 - crate::detmath::log10(x.abs()).floor() as i32).max(0) as usize;
    format!("{x:.decimals$}")
}

/// A plain-text table: every column but the last padded to its widest cell
/// plus two spaces, one row a line.
pub fn aligned(rows: &[Vec<String>]) -> String {
    let columns = rows.first().map_or(0, Vec::len);
    let widths: Vec<usize> = (0..columns)
        .map(|c| rows.iter().map(|r| r[c].chars().count()).max().unwrap_or(0))
        .collect();
    let mut text = String::new();
    for r in rows {
        for (c, cell) in r.iter().enumerate() {
            text.push_str(cell);
            if c + 1 < columns {
                text.push_str(&" ".repeat(widths[c] - cell.chars().count() + 2));
            }
        }
        text.push('\n');
    }
    text
}

/// One table of names for a fieldless enum (a setting or a choice): its
/// name in a spec, on the command line, from Python and in CSV files. It
/// implements `ALL`, `name`, `names`, [`std::str::FromStr`],
/// [`std::fmt::Display`], and the `String` conversions that serde uses
/// (`#[serde(try_from = "String", into = "String")]`), so that no other
/// place lists the names.
macro_rules! named {
    ($ty:ident, $what:literal { $($variant:ident => $name:literal),+ $(,)? }) => {
        impl $ty {
            /// Every value, in order.
            pub const ALL: &'static [$ty] = &[$($ty::$variant),+];

            /// The value's name (spec, command line, Python, CSV files).
            pub fn name(self) -> &'static str {
                match self {
                    $($ty::$variant => $name),+
                }
            }

            /// Every name, in order.
            pub fn names() -> Vec<&'static str> {
                Self::ALL.iter().map(|v| v.name()).collect()
            }
        }

        impl std::str::FromStr for $ty {
            type Err = $crate::error::Error;

            fn from_str(s: &str) -> std::result::Result<$ty, Self::Err> {
                Self::ALL.iter().copied().find(|v| v.name() == s).ok_or_else(|| {
                    $crate::error::Error::invalid(
                        $what,
                        format!("'{s}'"),
                        &format!("one of {}", Self::names().join(", ")),
                    )
                })
            }
        }

        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }

        impl From<$ty> for String {
            fn from(v: $ty) -> String {
                v.name().to_string()
            }
        }

        impl TryFrom<String> for $ty {
            type Error = String;

            /// Serde's message for an unknown name.
            fn try_from(s: String) -> std::result::Result<$ty, String> {
                Self::ALL.iter().copied().find(|v| v.name() == s).ok_or_else(|| {
                    let names: Vec<String> =
                        Self::names().iter().map(|n| format!("`{n}`")).collect();
                    format!("unknown variant `{s}`, expected one of {}", names.join(", "))
                })
            }
        }
    };
}
pub(crate) use named;

#[cfg(test)]
mod tests {
    use super::*;

    /// A second update replaces the first section instead of adding another,
    /// the sections after it survive, and a missing section goes before the
    /// heading named (or at the end).
    #[test]
    fn replace_section_replaces_or_inserts() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("summary.md");
        let read = || std::fs::read_to_string(&path).unwrap();
        std::fs::write(&path, "# Study\n\ntext\n\n## Tables\n\nrow\n").unwrap();
        replace_section(&path, "## Risk", "## Risk\n\nfirst\n", &[]).unwrap();
        replace_section(&path, "## Risk", "## Risk\n\nsecond\n", &[]).unwrap();
        assert_eq!(
            read(),
            "# Study\n\ntext\n\n## Tables\n\nrow\n\n## Risk\n\nsecond\n"
        );
        std::fs::write(&path, "# S\n\n## Risk\n\nold\n\n## After\n\nkept\n").unwrap();
        replace_section(&path, "## Risk", "## Risk\n\nnew\n", &[]).unwrap();
        assert_eq!(read(), "# S\n\n## Risk\n\nnew\n\n## After\n\nkept\n");
        replace_section(&path, "## Fit", "## Fit\n\nx\n", &["## Nope", "## After"]).unwrap();
        assert_eq!(
            read(),
            "# S\n\n## Risk\n\nnew\n\n## Fit\n\nx\n\n## After\n\nkept\n"
        );
    }

    /// Three significant figures; small and large numbers in scientific
    /// notation.
    #[test]
    fn sig3_keeps_three_figures() {
        assert_eq!(sig3(0.148_3), "0.148");
        assert_eq!(sig3(12.345), "12.3");
        assert_eq!(sig3(0.0155), "0.0155");
        assert_eq!(sig3(0.001_234), "0.00123");
        assert_eq!(sig3(0.000_123_4), "1.23e-4");
        assert_eq!(sig3(3.42e-41), "3.42e-41");
        assert_eq!(sig3(14.93), "14.9");
        assert_eq!(sig3(5480.2), "5480");
        assert_eq!(sig3(4.2e13), "4.20e13");
        assert_eq!(sig3(-0.5244), "-0.524");
        assert_eq!(sig3(0.0), "0");
    }

    /// An atomic write leaves the whole content, and a failed one leaves
    /// the old file and no temporary file.
    #[test]
    fn atomic_writes_are_all_or_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.csv");
        write_atomic(&path, |w| w.write_all(b"one\n")).unwrap();
        let failed = write_atomic(&path, |w| {
            w.write_all(b"half")?;
            Err(std::io::Error::other("boom"))
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "one\n");
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1);
    }
}
