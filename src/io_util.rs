//! Small helpers shared by every writer: nothing half-written is left
//! behind, numbers are written so they read back exactly, and printed
//! numbers have three significant figures.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, SystemTime};

/// What an output path names once its symbolic links are followed.
enum Target {
    /// A regular file, or no file yet: replaced atomically at this path
    /// (the final target of a link, so that the link is kept).
    File(PathBuf),
    /// A device, FIFO or socket (`/dev/stdout`, `/dev/null`, a named
    /// pipe): written into, never replaced.
    Stream,
}

impl Target {
    fn of(path: &Path) -> std::io::Result<Target> {
        match std::fs::metadata(path) {
            Ok(m) if m.is_dir() => Err(std::io::Error::new(
                std::io::ErrorKind::IsADirectory,
                "is a folder: expected a file name",
            )),
            Ok(m) if m.is_file() => {
                let link = std::fs::symlink_metadata(path)?.file_type().is_symlink();
                Ok(Target::File(if link {
                    std::fs::canonicalize(path)?
                } else {
                    path.to_path_buf()
                }))
            }
            Ok(_) => Ok(Target::Stream),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                Ok(Target::File(follow_links(path)?))
            }
            Err(e) => Err(e),
        }
    }
}

/// The path a chain of symbolic links at `path` ends at (`path` itself if
/// it is no link), for a link whose target does not exist yet.
fn follow_links(path: &Path) -> std::io::Result<PathBuf> {
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let to = std::fs::read_link(&p)?;
                p = match p.parent() {
                    Some(dir) if to.is_relative() => dir.join(to),
                    _ => to,
                };
            }
            _ => return Ok(p),
        }
    }
    Err(std::io::Error::other(
        "too many levels of symbolic links (a loop?)",
    ))
}

/// Writes a file atomically: `write` fills a temporary file in the same
/// directory (its name keeps `path`'s extension, for writers that choose a
/// format by it), which is synced and renamed over `path` only once it is
/// complete; on failure it is removed and `path` is untouched. The
/// directory is created if missing.
///
/// Every output goes through here, and nothing the user did not name is
/// replaced: a symbolic link is written through (its target is replaced
/// atomically, the link kept), and a device, FIFO or socket (`/dev/stdout`,
/// `/dev/null`, a named pipe) is written into, its content made first in a
/// temporary file of the system's temporary folder; a write error there
/// (`/dev/full`: no space left on device) is returned. Temporary files of
/// `path` that a killed writer left are removed ([`remove_stale_temps`]).
pub fn write_atomic_path(
    path: &Path,
    write: impl FnOnce(&Path) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let path = match Target::of(path)? {
        Target::File(p) => p,
        Target::Stream => {
            let tmp = temp_path(&std::env::temp_dir(), path);
            let result = (|| {
                write(&tmp)?;
                let mut out = std::fs::OpenOptions::new().write(true).open(path)?;
                std::io::copy(&mut std::fs::File::open(&tmp)?, &mut out)?;
                out.flush()
            })();
            let _ = std::fs::remove_file(&tmp);
            return result;
        }
    };
    let dir = parent(&path);
    std::fs::create_dir_all(dir)?;
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
    remove_stale_temps(dir, STALE_TEMP_AGE, name.as_deref());
    let tmp = temp_path(dir, &path);
    let result = (|| {
        write(&tmp)?;
        std::fs::File::open(&tmp)?.sync_all()?;
        std::fs::rename(&tmp, &path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// [`write_atomic_path`] for a writer of bytes: `write` writes the whole
/// content to a buffered stream (straight into a device or FIFO).
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    if let Target::Stream = Target::of(path)? {
        let mut w = BufWriter::new(std::fs::OpenOptions::new().write(true).open(path)?);
        write(&mut w)?;
        return w.flush();
    }
    write_atomic_path(path, |tmp| {
        let mut w = BufWriter::new(std::fs::File::create(tmp)?);
        write(&mut w)?;
        w.flush()
    })
}

/// Moves a finished file `from` (a temporary or partial file of ours) to
/// `to`, keeping [`write_atomic_path`]'s promise: a plain rename when `to`
/// is a regular file or absent, but a symbolic link at `to` is written
/// through (its target replaced atomically, the link kept) and a device or
/// pipe is written into, `from` then removed.
pub fn move_into(from: &Path, to: &Path) -> std::io::Result<()> {
    let plain = match std::fs::symlink_metadata(to) {
        Ok(m) => m.file_type().is_file(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => true,
        Err(e) => return Err(e),
    };
    if plain {
        return std::fs::rename(from, to);
    }
    write_atomic_path(to, |tmp| std::fs::copy(from, tmp).map(|_| ()))?;
    std::fs::remove_file(from)
}

/// A text field for a CSV line joined by commas (RFC 4180): quoted, its
/// quotes doubled, when it holds a comma, quote or line break (an IM
/// named `sa-avg(0.2,2.0)`), else as it is.
pub fn csv_field(text: String) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text
    }
}

/// The folder of `path` (`.` for a bare file name).
fn parent(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
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
    // 64 MiB: a survey or table of 10⁵ rows is a few MB
    read_text_limited(path, 64 << 20, "a text file").map_err(crate::Error::io(path))
}

/// How long a temporary file of a dead writer is left alone by a write
/// into its folder: a writer on another host of a shared file system (whose
/// pid means nothing here) keeps its temporary file fresher than this.
pub const STALE_TEMP_AGE: Duration = Duration::from_secs(120);

/// The pid in a temporary file's name `.name.tmp-<pid>-<n>[.ext]`
/// ([`write_atomic_path`]'s), `None` for any other name.
fn temp_pid(name: &str) -> Option<u32> {
    let rest = name.strip_prefix('.')?;
    let at = rest.rfind(".tmp-")?;
    let tail = &rest[at + 5..];
    let (pid, rest) = tail.split_once('-')?;
    let n = rest.split('.').next()?;
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    (digits(pid) && digits(n) && at > 0).then(|| pid.parse().ok())?
}

/// Removes the temporary files ([`write_atomic_path`]'s
/// `.name.tmp-<pid>-<n>`) in `dir` that a killed writer left behind (of the
/// file named `only`, if given: a write into a folder of the user's touches
/// no other name): those whose process is gone, or whose pid now belongs to
/// a process started after the file was last written (the pid was reused),
/// and that were not modified for `min_age`. Only where `/proc` tells
/// whether a process lives; best effort (a file that cannot be removed is
/// left). Returns how many were removed.
pub fn remove_stale_temps(dir: &Path, min_age: Duration, only: Option<&str>) -> usize {
    let prefix = only.map(|name| format!(".{name}.tmp-"));
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    let now = SystemTime::now();
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(name) = name.to_str() else {
            continue;
        };
        if prefix
            .as_ref()
            .is_some_and(|p| !name.starts_with(p.as_str()))
        {
            continue;
        }
        let Some(pid) = temp_pid(name) else {
            continue;
        };
        let Ok(meta) = entry.metadata() else {
            continue;
        };
        let Ok(modified) = meta.modified() else {
            continue;
        };
        let age = now.duration_since(modified).unwrap_or(Duration::ZERO);
        if !meta.is_file() || age < min_age || pid == std::process::id() {
            continue;
        }
        let gone = match pid_alive(pid) {
            Some(false) => true,
            Some(true) => {
                process_started(pid).is_some_and(|t| t > modified + Duration::from_secs(2))
            }
            None => false,
        };
        if gone && std::fs::remove_file(entry.path()).is_ok() {
            removed += 1;
        }
    }
    removed
}

/// Whether process `pid` of this host is alive: `Some` where `/proc` says,
/// `None` where it cannot be known.
pub fn pid_alive(pid: u32) -> Option<bool> {
    if Path::new("/proc/self").exists() {
        Some(Path::new(&format!("/proc/{pid}")).exists())
    } else {
        None
    }
}

/// When process `pid` started, from `/proc/<pid>/stat` (its start time in
/// clock ticks of 1/100 s since boot, the kernel's fixed `USER_HZ`) and
/// `/proc/stat` (the boot time); `None` where they cannot be read.
fn process_started(pid: u32) -> Option<SystemTime> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // the fields after the command name, which is in parentheses: state is
    // field 3, the start time field 22
    let after = &stat[stat.rfind(')')? + 1..];
    let ticks: u64 = after.split_whitespace().nth(19)?.parse().ok()?;
    let boot: u64 = std::fs::read_to_string("/proc/stat")
        .ok()?
        .lines()
        .find_map(|l| l.strip_prefix("btime "))?
        .trim()
        .parse()
        .ok()?;
    Some(SystemTime::UNIX_EPOCH + Duration::from_secs(boot) + Duration::from_millis(ticks * 10))
}

/// Whether `a` and `b` name the same file: the same device and inode
/// (links followed) where both exist, so `a.AT2`, `./a.AT2`, a link to it
/// and a hard link are one file; where either does not exist yet, the same
/// path once `.` components are dropped.
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
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

/// Refuses an output `out` (given as `flag`, e.g. `--out`) that is the
/// input `input` (`what`, e.g. "the input record") itself, by
/// [`same_file`]: writing it would replace the data it is made from.
pub fn refuse_overwriting_input(
    out: &Path,
    flag: &str,
    input: &Path,
    what: &str,
) -> crate::error::Result<()> {
    if same_file(out, input) {
        return Err(crate::error::Error::Conflict {
            path: out.to_path_buf(),
            message: format!(
                "{flag} names {what} {} itself: writing there would replace the data it is \
                 made from; name another file",
                input.display()
            ),
        });
    }
    Ok(())
}

/// Reads the whole of the text input at `path` (a record, a spec, a hazard
/// curve: `what` names it in the messages, "a record file"), refusing one of
/// more than `limit` bytes: a regular file by its size, before reading it;
/// anything else (a device, a pipe) once it has given that many. A NUL byte
/// ends the read at once, as no text holds one: a link to `/dev/zero`, a
/// sparse or binary file, a UTF-16 text. The error is an I/O error of kind
/// `InvalidData` that says what was found, the limit and why.
pub fn read_limited(path: &Path, limit: u64, what: &str) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let invalid = |message: String| std::io::Error::new(std::io::ErrorKind::InvalidData, message);
    let mut file = std::fs::File::open(path)?;
    let meta = file.metadata()?;
    if meta.is_dir() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::IsADirectory,
            format!("is a folder, not a file: expected {what}"),
        ));
    }
    if meta.is_file() && meta.len() > limit {
        return Err(invalid(format!(
            "is {}, more than the {} {what} may have: refused before reading it (is it the file \
             you meant?)",
            bytes_text(meta.len()),
            bytes_text(limit)
        )));
    }
    let mut bytes = Vec::with_capacity(if meta.is_file() {
        meta.len() as usize
    } else {
        0
    });
    let mut chunk = vec![0u8; 1 << 16];
    loop {
        let n = match file.read(&mut chunk) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        if let Some(i) = chunk[..n].iter().position(|&b| b == 0) {
            return Err(invalid(format!(
                "holds a NUL byte (byte {}): expected {what} as text, not a binary or UTF-16 \
                 file, nor a device such as /dev/zero",
                bytes.len() + i
            )));
        }
        if (bytes.len() + n) as u64 > limit {
            return Err(invalid(format!(
                "is not a regular file (a device or a pipe) and gave more than the {} {what} \
                 may have: refused",
                bytes_text(limit)
            )));
        }
        bytes.extend_from_slice(&chunk[..n]);
    }
    Ok(bytes)
}

/// [`read_limited`] as text (UTF-8, a leading byte-order mark removed).
pub fn read_text_limited(path: &Path, limit: u64, what: &str) -> std::io::Result<String> {
    let mut bytes = read_limited(path, limit, what)?;
    if bytes.starts_with("\u{feff}".as_bytes()) {
        bytes.drain(..3);
    }
    String::from_utf8(bytes).map_err(|e| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "not UTF-8 text (byte {}): expected {what}",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

/// A byte count for people: `512 MiB`, `4.2 GB`, `873 bytes`.
pub fn bytes_text(n: u64) -> String {
    const UNITS: [(u64, &str); 4] = [
        (1 << 40, "TiB"),
        (1 << 30, "GiB"),
        (1 << 20, "MiB"),
        (1 << 10, "KiB"),
    ];
    for (size, unit) in UNITS {
        if n >= size {
            let x = n as f64 / size as f64;
            return if n.is_multiple_of(size) {
                format!("{} {unit}", n / size)
            } else {
                format!("{} {unit}", sig3(x))
            };
        }
    }
    format!("{n} bytes")
}

/// FNV-1a, 64 bits: a small stable hash for provenance (not for security).
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
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

/// Removes the section of the markdown file at `path` that starts with
/// the line `heading` and runs to the next `## ` heading, with the blank
/// lines before it; a file without it is left as it is. Atomic.
pub fn remove_section(path: &Path, heading: &str) -> std::io::Result<()> {
    let text = std::fs::read_to_string(path)?;
    let lines: Vec<&str> = text.lines().collect();
    let Some(i) = lines.iter().position(|l| l.trim_end() == heading) else {
        return Ok(());
    };
    let end = lines[i + 1..]
        .iter()
        .position(|l| l.starts_with("## "))
        .map_or(lines.len(), |j| i + 1 + j);
    let mut head = lines[..i].to_vec();
    while head.last().is_some_and(|l| l.trim().is_empty()) {
        head.pop();
    }
    let mut out = head;
    if end < lines.len() {
        if !out.is_empty() {
            out.push("");
        }
        out.extend(&lines[end..]);
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

    /// Only the temporary names of `write_atomic_path` are taken for
    /// temporary files (a user's `notes.tmp-1-2.txt` is not), with their pid.
    #[test]
    fn temporary_names_are_recognised() {
        assert_eq!(temp_pid(".outcomes.csv.tmp-123-4"), Some(123));
        assert_eq!(temp_pid(".motion.svg.tmp-77-0.svg"), Some(77));
        assert_eq!(temp_pid(".a.tmp-b.tmp-9-1"), Some(9));
        for name in [
            "notes.tmp-1-2.txt",
            ".tmp-1-2",
            ".a.tmp-x-2",
            ".a.tmp-1-",
            ".a.csv",
        ] {
            assert_eq!(temp_pid(name), None, "{name}");
        }
    }

    /// A file above the limit is refused by its size without being read; one
    /// within it reads whole; text loses its byte-order mark.
    #[test]
    fn reads_are_limited() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("r.csv");
        std::fs::write(&path, "\u{feff}t,acc\n").unwrap();
        assert_eq!(
            read_text_limited(&path, 100, "a record").unwrap(),
            "t,acc\n"
        );
        let err = read_limited(&path, 4, "a record").unwrap_err();
        assert_eq!(err.kind(), std::io::ErrorKind::InvalidData);
        assert!(
            err.to_string()
                .contains("is 9 bytes, more than the 4 bytes a record"),
            "{err}"
        );
        std::fs::write(&path, b"t,acc\n\0\0").unwrap();
        let err = read_limited(&path, 100, "a record").unwrap_err();
        assert!(
            err.to_string().contains("holds a NUL byte (byte 6)"),
            "{err}"
        );
        assert_eq!(bytes_text(256 << 20), "256 MiB");
        assert_eq!(bytes_text(3 << 40), "3 TiB");
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
