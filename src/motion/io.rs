//! Reading and writing records: PEER NGA `.AT2` (acceleration in g) and CSV
//! (`t,acc[,vel,disp]`, SI units).
//!
//! Floats are written in Rust's shortest round-trip form, so a written file
//! reads back bit for bit. Files are written to a temporary file in the same
//! directory and renamed into place: a reader never sees a half-written file.
//!
//! Every parse error names the file and the 1-based line
//! ([`Error::Parse`]).

use crate::detmath as dm;
use std::io::Write;
use std::path::Path;

use super::record::{Record, integrate_linear};
use crate::error::{Error, Result};

/// Relative tolerance (of Δt) on the times of a CSV record, beyond the
/// rounding of the digits written, when checking that it is uniformly
/// sampled.
pub const DT_REL_TOL: f64 = 1e-6;

/// Largest distance of a CSV record's time from its uniform grid, as a
/// fraction of Δt, whatever the rounding of its digits: a missing or extra
/// sample moves some time by Δt/2 or more, well beyond it.
pub const DT_MAX_OFF: f64 = 0.1;

/// The content of a PEER NGA `.AT2` file: three free header lines, then
/// `NPTS= n, DT= dt SEC`, then the accelerations in g, several per line.
#[derive(Clone, Debug, PartialEq)]
pub struct At2 {
    /// The three free-text header lines (database, event and station, units).
    pub header: [String; 3],
    /// Sample interval Δt, s.
    pub dt: f64,
    /// Ground acceleration, in g.
    pub acc_g: Vec<f64>,
}

fn parse_err(path: &Path, line: usize, message: impl Into<String>) -> Error {
    Error::Parse {
        path: path.to_path_buf(),
        line,
        message: message.into(),
    }
}

fn io_err(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The largest record file read: 512 MiB. A record of
/// [`MAX_SAMPLES`](super::MAX_SAMPLES) samples as CSV with its four columns
/// at full precision takes 406 MB (97 bytes a sample); a bigger file
/// (a 2 GB file of zeros, a link to `/dev/zero`) is refused before it is
/// read, not after it has filled the memory.
pub const MAX_RECORD_BYTES: u64 = 512 << 20;

/// The bytes of a record file, refused above [`MAX_RECORD_BYTES`]
/// ([`crate::io_util::read_limited`]).
pub fn read_record_bytes(path: &Path) -> Result<Vec<u8>> {
    crate::io_util::read_limited(path, MAX_RECORD_BYTES, "a record file")
        .map_err(|e| io_err(path, e))
}

fn read_text(path: &Path) -> Result<String> {
    crate::io_util::read_text_limited(path, MAX_RECORD_BYTES, "a record file")
        .map_err(|e| io_err(path, e))
}

/// Parses a float, also accepting a Fortran `D` exponent; rejects NaN and ±∞.
/// A number written with a decimal comma (`0,01`, as a European locale
/// writes it) is refused as such.
fn parse_value(token: &str) -> std::result::Result<f64, String> {
    let v =
        token
            .replace(['D', 'd'], "E")
            .parse::<f64>()
            .map_err(|_| match decimal_comma(token) {
                Some(point) => format!(
                    "'{token}' is written with a decimal comma: write it with a decimal point \
                 ('{point}')"
                ),
                None => format!("cannot read '{token}' as a number"),
            })?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("value '{token}' is not finite"))
    }
}

/// `token` with its one comma made a decimal point, if that makes a number
/// (`0,01` → `0.01`, `-2,5E-3` → `-2.5E-3`): a number written with a
/// decimal comma.
fn decimal_comma(token: &str) -> Option<String> {
    let t = token.trim();
    let point = t.replace(',', ".");
    (t.matches(',').count() == 1
        && t.split(',').all(|s| s.chars().any(|c| c.is_ascii_digit()))
        && point.replace(['D', 'd'], "E").parse::<f64>().is_ok())
    .then_some(point)
}

/// The value of `DT` on an AT2 header line if it is written with a decimal
/// comma (`DT= 0,01 SEC`), which the header's commas would otherwise split
/// into `0` and `01`.
fn dt_with_comma(line: &str) -> Option<(String, String)> {
    let upper = line.to_ascii_uppercase();
    let at = upper.find("DT")? + 2;
    let rest = upper[at..].trim_start_matches([' ', '=', ':', '\t']);
    let token: String = rest
        .chars()
        .take_while(|c| c.is_ascii_digit() || matches!(c, '.' | ',' | '+' | '-' | 'E' | 'D'))
        .collect();
    let token = token.trim_end_matches(',');
    decimal_comma(token).map(|point| (token.to_string(), point))
}

/// Reads `NPTS` and `DT` from the fourth AT2 header line, in either the NGA
/// form `NPTS=  5590, DT= .0050 SEC` (any spacing, commas, case) or the older
/// `5590   .0050   NPTS, DT` form.
fn parse_npts_dt(line: &str) -> std::result::Result<(usize, f64), String> {
    if let Some((comma, point)) = dt_with_comma(line) {
        return Err(format!(
            "DT = '{comma}' in '{}' is written with a decimal comma: write it with a decimal \
             point (DT= {point})",
            line.trim()
        ));
    }
    let upper = line.to_ascii_uppercase().replace([',', '=', ':', ';'], " ");
    let tokens: Vec<&str> = upper
        .split_whitespace()
        .map(|t| {
            ["SECONDS", "SECS", "SEC"]
                .iter()
                .find_map(|u| t.strip_suffix(u))
                .unwrap_or(t)
        })
        .filter(|t| !t.is_empty() && *t != "S")
        .collect();
    let expected = "expected 'NPTS= n, DT= dt SEC' or 'n dt NPTS, DT'";
    let label = |name: &str| tokens.iter().position(|t| *t == name);
    let (Some(ip), Some(id)) = (label("NPTS"), label("DT")) else {
        return Err(format!("no NPTS and DT in '{}': {expected}", line.trim()));
    };
    let numeric = |t: &&str| t.parse::<f64>().is_ok();
    let (npts, dt) =
        if tokens.get(ip + 1).is_some_and(numeric) && tokens.get(id + 1).is_some_and(numeric) {
            (tokens[ip + 1], tokens[id + 1])
        } else {
            // Older form: the numbers come first, in the order of the labels.
            let numbers: Vec<&str> = tokens[..ip.min(id)]
                .iter()
                .copied()
                .filter(numeric)
                .collect();
            if numbers.len() != 2 {
                return Err(format!(
                    "cannot find the values of NPTS and DT in '{}': {expected}",
                    line.trim()
                ));
            }
            if ip < id {
                (numbers[0], numbers[1])
            } else {
                (numbers[1], numbers[0])
            }
        };
    let npts = npts
        .parse::<usize>()
        .map_err(|_| format!("NPTS = '{npts}' is not a whole number of samples"))?;
    let dt = parse_value(dt)?;
    if dt <= 0.0 {
        return Err(format!(
            "DT = {} must be positive",
            crate::error::number(dt)
        ));
    }
    Ok((npts, dt))
}

impl At2 {
    /// Reads and parses an `.AT2` file.
    pub fn read(path: impl AsRef<Path>) -> Result<At2> {
        let path = path.as_ref();
        At2::parse(&read_text(path)?, path)
    }

    /// Parses the text of an `.AT2` file; `path` is used in error messages.
    pub fn parse(text: &str, path: &Path) -> Result<At2> {
        let lines: Vec<&str> = text.lines().collect();
        if lines.iter().all(|l| l.trim().is_empty()) {
            return Err(parse_err(
                path,
                1,
                "empty file: expected 4 header lines and the accelerations",
            ));
        }
        if lines.len() < 4 {
            return Err(parse_err(
                path,
                lines.len(),
                format!(
                    "missing header: an AT2 file has 4 header lines (the 4th giving NPTS and DT), found {}",
                    lines.len()
                ),
            ));
        }
        let (npts, dt) = parse_npts_dt(lines[3]).map_err(|m| parse_err(path, 4, m))?;
        if npts < 2 {
            return Err(parse_err(
                path,
                4,
                format!("NPTS = {npts}: at least 2 samples are needed"),
            ));
        }
        // Each value takes at least one byte of text: a huge NPTS must not
        // reserve more memory than the file can fill.
        let mut acc_g = Vec::with_capacity(npts.min(text.len()));
        let mut last_line = 4;
        for (i, line) in lines.iter().enumerate().skip(4) {
            for token in line.split_whitespace() {
                let v = parse_value(token).map_err(|m| parse_err(path, i + 1, m))?;
                if acc_g.len() == npts {
                    return Err(parse_err(
                        path,
                        i + 1,
                        format!("more values than NPTS = {npts} given on line 4"),
                    ));
                }
                acc_g.push(v);
                last_line = i + 1;
            }
        }
        if acc_g.len() < npts {
            return Err(parse_err(
                path,
                last_line,
                format!(
                    "the file ends after {} values; NPTS = {npts} on line 4",
                    acc_g.len()
                ),
            ));
        }
        Ok(At2 {
            header: [lines[0], lines[1], lines[2]].map(|l| l.trim_end().to_string()),
            dt,
            acc_g,
        })
    }

    /// Converts to a record in SI units (acc × `g`), integrating velocity and
    /// displacement from rest by the linear rule.
    pub fn to_record(&self, name: impl Into<String>, g: f64) -> Result<Record> {
        Record::from_acc(name, self.dt, self.acc_g.iter().map(|a| a * g).collect())
    }

    /// Builds the AT2 content of a record (acc ÷ `g`).
    pub fn from_record(record: &Record, g: f64) -> At2 {
        At2 {
            header: [
                "rockfrag ground-motion record".to_string(),
                record.name.replace(['\n', '\r'], " "),
                "ACCELERATION TIME SERIES IN UNITS OF G".to_string(),
            ],
            dt: record.dt,
            acc_g: record.acc.iter().map(|a| a / g).collect(),
        }
    }

    /// Writes the text of the file (five values per line, shortest
    /// round-trip form).
    pub fn write_to<W: Write>(&self, mut w: W) -> std::io::Result<()> {
        for h in &self.header {
            writeln!(w, "{}", h.replace(['\n', '\r'], " "))?;
        }
        writeln!(w, "NPTS= {}, DT= {} SEC", self.acc_g.len(), self.dt)?;
        for chunk in self.acc_g.chunks(5) {
            for v in chunk {
                write!(w, " {v:>24E}")?;
            }
            writeln!(w)?;
        }
        Ok(())
    }

    /// Writes the file atomically (temporary file in the same directory,
    /// then rename).
    pub fn write(&self, path: impl AsRef<Path>) -> Result<()> {
        write_atomic(path.as_ref(), |w| self.write_to(w))
    }
}

/// The file name of `path`, for record names.
fn file_label(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// Reads a PEER NGA `.AT2` file as a record in SI units (acc × `g`, usually
/// [`super::G_STANDARD`], for a file in g; a header `… IN UNITS OF
/// CM/SEC/SEC` or `M/S/S` is converted from those units instead); velocity
/// and displacement are integrated from rest by the linear rule. A header
/// naming a velocity or displacement series is refused at its line. The
/// record is named after the file.
pub fn read_at2(path: impl AsRef<Path>, g: f64) -> Result<Record> {
    let path = path.as_ref();
    let text = read_text(path)?;
    let mut at2 = At2::parse(&text, path)?;
    let (line, units) = at2_units(&at2.header).map_err(|(line, m)| parse_err(path, line, m))?;
    // Values in m/s² or cm/s² are brought to g here, so that times g below
    // they come back to m/s² (to rounding).
    if let Some(si) = units.si_factor() {
        let label = units.label();
        for a in &mut at2.acc_g {
            *a *= si / g;
        }
        if let Some(k) = at2.acc_g.iter().position(|a| !a.is_finite()) {
            return Err(parse_err(
                path,
                at2_value_line(&text, k),
                format!("acceleration is not finite once converted from {label} (line {line})"),
            ));
        }
    }
    if let Some(k) = at2.acc_g.iter().position(|a| !(a * g).is_finite()) {
        return Err(parse_err(
            path,
            at2_value_line(&text, k),
            format!(
                "acceleration {:e} g is too large: in m/s² (times g = {g}) it is not finite",
                at2.acc_g[k]
            ),
        ));
    }
    let acc: Vec<f64> = at2.acc_g.iter().map(|a| a * g).collect();
    let fix = match units {
        At2Units::G => format!(
            "if the values are in cm/s² or m/s², say so in the header's third line \
             (… IN UNITS OF CM/SEC/SEC, or M/S/S; line {line})"
        ),
        _ => format!("check the units the header states (line {line})"),
    };
    let (vel, disp) = integrate_linear(at2.dt, &acc, 0.0, 0.0);
    check_integrated(path, at2.dt, &vel, &disp, |k| at2_value_line(&text, k))?;
    super::units::check_max_peak(path, &acc, units.label(), &fix, |k| {
        at2_value_line(&text, k)
    })?;
    Record::new(file_label(path), at2.dt, acc, vel, disp)
}

/// Units of the accelerations of an `.AT2` file, read from its header.
#[derive(Clone, Copy, Debug, PartialEq)]
enum At2Units {
    /// g (the PEER NGA default, and what a header without units means).
    G,
    /// cm/s² (gal).
    CmPerS2,
    /// m/s².
    MPerS2,
}

impl At2Units {
    /// m/s² per unit; `None` for g (the caller's g applies).
    fn si_factor(self) -> Option<f64> {
        match self {
            At2Units::G => None,
            At2Units::CmPerS2 => Some(0.01),
            At2Units::MPerS2 => Some(1.0),
        }
    }

    fn label(self) -> &'static str {
        match self {
            At2Units::G => "g",
            At2Units::CmPerS2 => "cm/s²",
            At2Units::MPerS2 => "m/s²",
        }
    }
}

/// The series kind and units of an `.AT2` file from its three header lines,
/// and the 1-based line that says so (0 if none does: then g, as PEER NGA
/// files are). The PEER layouts: NGA-West2 `ACCELERATION TIME SERIES IN
/// UNITS OF G`, the older `ACCELERATION TIME HISTORY IN UNITS OF G` (at times
/// followed by `. FILTER POINTS: …`), and the velocity and displacement files
/// of the same layout, `VELOCITY TIME SERIES IN UNITS OF CM/S` and
/// `DISPLACEMENT TIME SERIES IN UNITS OF CM`, which are refused. Units
/// understood: G; CM/SEC/SEC, CM/S/S, CM/S^2, CM/S2, CM/S**2, CM/SEC^2, GAL;
/// M/SEC/SEC, M/S/S, M/S^2, M/S2 (any case, with or without spaces).
fn at2_units(header: &[String; 3]) -> std::result::Result<(usize, At2Units), (usize, String)> {
    for (i, line) in header.iter().enumerate() {
        let upper = line.to_uppercase();
        let describes = upper.contains("TIME SERIES")
            || upper.contains("TIME HISTORY")
            || upper.contains("UNITS OF")
            || upper.contains("UNITS:");
        if !describes {
            continue;
        }
        let words: Vec<&str> = upper
            .split(|c: char| !c.is_ascii_alphabetic())
            .filter(|w| !w.is_empty())
            .collect();
        let kind = words
            .iter()
            .find(|w| ["ACCELERATION", "VELOCITY", "DISPLACEMENT"].contains(w));
        if let Some(kind @ (&"VELOCITY" | &"DISPLACEMENT")) = kind {
            return Err((
                i + 1,
                format!(
                    "header line {} '{}' says this is a {} series: rockfrag reads ground \
                     acceleration (a PEER .AT2 file, 'ACCELERATION TIME SERIES IN UNITS OF G')",
                    i + 1,
                    line.trim(),
                    kind.to_lowercase()
                ),
            ));
        }
        let Some(at) = upper
            .find("UNITS OF")
            .map(|k| k + 8)
            .or_else(|| upper.find("UNITS:").map(|k| k + 6))
        else {
            continue;
        };
        let unit: String = upper[at..]
            .trim_start()
            .split(|c: char| c.is_whitespace() || c == ',' || c == ';' || c == '(' || c == '[')
            .next()
            .unwrap_or("")
            .trim_end_matches(['.', ':'])
            .replace('²', "^2")
            .replace("**", "^");
        let units = match unit.as_str() {
            "G" => At2Units::G,
            "CM/SEC/SEC" | "CM/S/S" | "CM/S^2" | "CM/S2" | "CM/SEC^2" | "CM/SEC2" | "GAL"
            | "GALS" => At2Units::CmPerS2,
            "M/SEC/SEC" | "M/S/S" | "M/S^2" | "M/S2" | "M/SEC^2" | "M/SEC2" => At2Units::MPerS2,
            _ => {
                return Err((
                    i + 1,
                    format!(
                        "header line {} '{}': units '{}' not understood: expected G, \
                         CM/SEC/SEC (or CM/S/S, CM/S^2, GAL) or M/SEC/SEC (or M/S/S, M/S^2)",
                        i + 1,
                        line.trim(),
                        unit
                    ),
                ));
            }
        };
        return Ok((i + 1, units));
    }
    Ok((0, At2Units::G))
}

/// The 1-based line of value `k` (0-based) of the text of a parsed `.AT2`
/// file (the values start on line 5).
fn at2_value_line(text: &str, k: usize) -> usize {
    let mut seen = 0;
    for (i, line) in text.lines().enumerate().skip(4) {
        seen += line.split_whitespace().count();
        if seen > k {
            return i + 1;
        }
    }
    0
}

/// Errors, at the line of the first bad sample (`line_of(k)`), if the
/// velocity or displacement integrated from a record's accelerations is not
/// finite: accelerations or a time step so large that the integral
/// overflows.
fn check_integrated(
    path: &Path,
    dt: f64,
    vel: &[f64],
    disp: &[f64],
    line_of: impl Fn(usize) -> usize,
) -> Result<()> {
    match vel
        .iter()
        .zip(disp)
        .position(|(v, d)| !(v.is_finite() && d.is_finite()))
    {
        Some(k) => Err(parse_err(
            path,
            line_of(k),
            format!(
                "the velocity or displacement integrated from the accelerations is not finite \
                 at sample {k} (t = {}): the accelerations or the time step are too large",
                k as f64 * dt
            ),
        )),
        None => Ok(()),
    }
}

/// The time fields (first column) of the CSV rows at `lines` (1-based) of
/// `text`, as written.
fn text_times<'a>(text: &'a str, lines: &[usize]) -> Vec<&'a str> {
    let all: Vec<&str> = text.lines().collect();
    lines
        .iter()
        .map(|&l| all[l - 1].split(',').next().unwrap_or("").trim())
        .collect()
}

/// Half a unit in the last digit of a number as written (`0.003333` →
/// 5e-7, `3.33e-3` → 5e-6): how far a value rounded to those digits can be
/// from the value the writer meant. A number written without a decimal point
/// or exponent (`0`, `12`) is taken as exact: writers drop the `.0` of whole
/// numbers.
fn rounding_of(token: &str) -> f64 {
    let t = token.trim().trim_start_matches(['+', '-']);
    let (mantissa, exponent) = match t.find(['e', 'E', 'd', 'D']) {
        Some(i) => (&t[..i], t[i + 1..].parse::<i32>().unwrap_or(0)),
        None => (t, 0),
    };
    match mantissa.find('.') {
        Some(i) => {
            let decimals = (mantissa.len() - i - 1) as i32;
            0.5 * dm::powi(10.0, exponent - decimals)
        }
        None if exponent != 0 => 0.5 * dm::powi(10.0, exponent),
        None => 0.0,
    }
}

/// The time step of a CSV record's time column `t` (rows at file `lines`,
/// `times` as written), refusing gaps and jitter.
///
/// Times written with rounding are accepted, however they were written
/// (`%.6f` at Δt = 1/300 s; `%g` or Python's `repr`, which drop trailing
/// zeros, so `0.01` stands among `0.00333333`): Δt = (t_last − t_0)/(n − 1),
/// and each time must lie within its rounding (half a unit in its last
/// written digit, plus the larger of the first's and the last's, which fix
/// Δt) plus [`DT_REL_TOL`]·Δt of t_0 + k·Δt, that bound never exceeding
/// [`DT_MAX_OFF`]·Δt. A missing or extra sample moves some time by at least
/// Δt/2 from the grid, so it cannot hide in the bound and is refused,
/// naming its line. When every step equals the first to [`DT_REL_TOL`]
/// relative, Δt is the first step (so a file written by [`write_csv`] reads
/// back bit for bit).
fn uniform_step(path: &Path, t: &[f64], times: &[&str], lines: &[usize]) -> Result<f64> {
    let n = t.len();
    let dt_first = t[1] - t[0];
    let exact = (2..n).all(|k| ((t[k] - t[k - 1]) - dt_first).abs() <= DT_REL_TOL * dt_first);
    if exact {
        return Ok(dt_first);
    }
    let dt = (t[n - 1] - t[0]) / (n - 1) as f64;
    let ends = rounding_of(times[0]).max(rounding_of(times[n - 1]));
    let bound = |k: usize| (rounding_of(times[k]) + ends + DT_REL_TOL * dt).min(DT_MAX_OFF * dt);
    if !(dt.is_finite() && dt > 0.0) {
        return Err(parse_err(
            path,
            lines[n - 1],
            format!(
                "time column from {} to {}: no positive time step",
                crate::error::number(t[0]),
                crate::error::number(t[n - 1])
            ),
        ));
    }
    for k in 1..n - 1 {
        let expected = t[0] + k as f64 * dt;
        let off = t[k] - expected;
        if off.abs() > bound(k) {
            // Name the gap where it is: the first step that differs from the
            // typical (median) step by more than two times' rounding.
            let mut steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
            steps.sort_by(f64::total_cmp);
            let typical = steps[steps.len() / 2];
            let odd =
                (1..n).find(|&j| ((t[j] - t[j - 1]) - typical).abs() > bound(j) + bound(j - 1));
            if let Some(j) = odd {
                return Err(parse_err(
                    path,
                    lines[j],
                    format!(
                        "non-uniform time step: t = {} follows {} (step {:e} s, but the typical \
                         step is {typical:e} s): a gap, an extra sample or jitter in the time column",
                        times[j],
                        times[j - 1],
                        t[j] - t[j - 1]
                    ),
                ));
            }
            return Err(parse_err(
                path,
                lines[k],
                format!(
                    "non-uniform time step: t = {} is {off:+e} s from t_0 + k·Δt = {expected} \
                     (row {k} after the first; Δt = (t_last − t_0)/(n − 1) = {dt}), more than \
                     the rounding of the digits written allows ({:e} s): a gap, an extra sample or \
                     jitter in the time column",
                    times[k],
                    bound(k)
                ),
            ));
        }
    }
    Ok(dt)
}

/// Reads a CSV record with header `t,acc` or `t,acc,vel,disp` (s, m/s², m/s,
/// m), as written by [`write_csv`]. The time step must be uniform, up to the
/// rounding of the digits written (Δt from the first and last times, each
/// time within its rounding of t_0 + k·Δt); sample k is taken
/// at k·Δt from the first row.
/// Without `vel`/`disp` columns they are integrated from rest by the linear
/// rule. Blank lines are skipped.
pub fn read_csv(path: impl AsRef<Path>) -> Result<Record> {
    let path = path.as_ref();
    let text = read_text(path)?;
    let mut rows = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty());
    let Some((header_line, header)) = rows.next() else {
        return Err(parse_err(
            path,
            1,
            "empty file: expected the header 't,acc' or 't,acc,vel,disp'",
        ));
    };
    let names: Vec<String> = header
        .split(',')
        .map(|s| s.trim().to_ascii_lowercase())
        .collect();
    let ncol = match names.iter().map(String::as_str).collect::<Vec<_>>()[..] {
        ["t", "acc"] => 2,
        ["t", "acc", "vel", "disp"] => 4,
        _ => {
            let what = if names.first().is_some_and(|n| n.parse::<f64>().is_ok()) {
                "missing header"
            } else {
                "unrecognised header"
            };
            let hint = if header.contains(';') && !header.contains(',') {
                " (its columns are separated by ';', as a spreadsheet in a locale with a \
                 decimal comma writes CSV: rockfrag reads columns separated by ',' and numbers \
                 with a decimal point)"
            } else {
                ""
            };
            return Err(parse_err(
                path,
                header_line,
                format!("{what} '{header}': expected 't,acc' or 't,acc,vel,disp'{hint}"),
            ));
        }
    };
    let mut cols: [Vec<f64>; 4] = Default::default();
    let mut lines = Vec::new();
    for (line_no, line) in rows {
        let fields: Vec<&str> = line.split(',').collect();
        if fields.len() != ncol {
            // `0,02,-0,0065` is two numbers with decimal commas, not four
            let hint = if fields.len() > ncol && !line.contains('.') {
                " (are the numbers written with a decimal comma, e.g. 0,02? write them with a \
                 decimal point: 0.02)"
            } else {
                ""
            };
            return Err(parse_err(
                path,
                line_no,
                format!("{} fields, expected {ncol} ({header}){hint}", fields.len()),
            ));
        }
        for (c, f) in fields.iter().enumerate() {
            let v = parse_value(f.trim())
                .map_err(|m| parse_err(path, line_no, format!("column '{}': {m}", names[c])))?;
            cols[c].push(v);
        }
        lines.push(line_no);
    }
    let [t, acc, vel, disp] = cols;
    let last = lines.last().copied().unwrap_or(header_line);
    if t.len() < 2 {
        return Err(parse_err(
            path,
            last,
            format!("{} samples: at least 2 are needed", t.len()),
        ));
    }
    let dt_first = t[1] - t[0];
    // Both times are finite, so dt_first is not NaN.
    if dt_first <= 0.0 {
        return Err(parse_err(
            path,
            lines[1],
            format!(
                "time step t = {} after {} is not positive",
                crate::error::number(t[1]),
                crate::error::number(t[0])
            ),
        ));
    }
    if !dt_first.is_finite() {
        return Err(parse_err(
            path,
            lines[1],
            format!("time step t = {:e} after {:e} is not finite", t[1], t[0]),
        ));
    }
    let times: Vec<&str> = text_times(&text, &lines);
    let dt = uniform_step(path, &t, &times, &lines)?;
    let name = file_label(path);
    let (vel, disp) = if ncol == 4 {
        (vel, disp)
    } else {
        let (vel, disp) = integrate_linear(dt, &acc, 0.0, 0.0);
        check_integrated(path, dt, &vel, &disp, |k| lines[k])?;
        (vel, disp)
    };
    super::units::check_max_peak(
        path,
        &acc,
        "m/s²",
        "a CSV record's acc is in m/s²; if these values are in cm/s², divide them by 100",
        |k| lines[k],
    )?;
    super::units::check_min_peak_csv(path, &acc, header_line)?;
    if ncol == 4 {
        super::units::check_integrals(path, header_line, dt, &acc, &vel, &disp)?;
    }
    Record::new(name, dt, acc, vel, disp)
}

/// Reads a record by extension: `.at2` (any case) with [`read_at2`] and
/// gravity `g`, `.csv` with [`read_csv`].
pub fn read_record(path: impl AsRef<Path>, g: f64) -> Result<Record> {
    let path = path.as_ref();
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("at2") => read_at2(path, g),
        Some("csv") => read_csv(path),
        _ => Err(parse_err(
            path,
            0,
            "unknown record format: expected a .AT2 or .csv file",
        )),
    }
}

/// Writes a record as CSV with header exactly `t,acc,vel,disp` (s, m/s², m/s,
/// m), t = k·Δt, every value in shortest round-trip form.
pub fn write_csv_to<W: Write>(mut w: W, record: &Record) -> std::io::Result<()> {
    writeln!(w, "t,acc,vel,disp")?;
    for k in 0..record.len() {
        writeln!(
            w,
            "{},{},{},{}",
            k as f64 * record.dt,
            record.acc[k],
            record.vel[k],
            record.disp[k]
        )?;
    }
    Ok(())
}

/// Writes a record as CSV (see [`write_csv_to`]) atomically: to a temporary
/// file in the same directory, then renamed onto `path`.
///
/// ```
/// use rockfrag::motion::{Record, read_csv, write_csv};
/// let dir = std::env::temp_dir().join(format!("rockfrag-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let r = Record::from_acc("x", 0.01, vec![0.0, 0.1, -0.3]).unwrap();
/// let path = dir.join("x.csv");
/// write_csv(&path, &r).unwrap();
/// let back = read_csv(&path).unwrap();
/// assert_eq!((back.acc, back.vel, back.disp), (r.acc, r.vel, r.disp));
/// std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn write_csv(path: impl AsRef<Path>, record: &Record) -> Result<()> {
    write_atomic(path.as_ref(), |w| write_csv_to(w, record))
}

/// Writes through `f` atomically ([`crate::io_util::write_atomic`]),
/// naming `path` in an error.
fn write_atomic(path: &Path, f: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<()> {
    crate::io_util::write_atomic(path, f).map_err(|e| io_err(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_npts_dt_forms() {
        assert_eq!(
            parse_npts_dt("NPTS=  5590, DT=   .0050 SEC").unwrap(),
            (5590, 0.005)
        );
        assert_eq!(
            parse_npts_dt("npts=5590,dt=.005sec").unwrap(),
            (5590, 0.005)
        );
        assert_eq!(
            parse_npts_dt("NPTS = 10 , DT = 0.01 s").unwrap(),
            (10, 0.01)
        );
        assert_eq!(
            parse_npts_dt("  5590   .0050   NPTS, DT").unwrap(),
            (5590, 0.005)
        );
        assert_eq!(parse_npts_dt("DT= .01 SEC, NPTS= 7").unwrap(), (7, 0.01));
        assert!(parse_npts_dt("5590 .0050").is_err());
        assert!(parse_npts_dt("NPTS= 55.5, DT= .01").is_err());
    }

    #[test]
    fn at2_layout() {
        let at2 = At2 {
            header: ["a".into(), "b".into(), "c".into()],
            dt: 0.005,
            acc_g: vec![0.1, -2.5e-7, 3.0],
        };
        let mut out = Vec::new();
        at2.write_to(&mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[3], "NPTS= 3, DT= 0.005 SEC");
        let values: Vec<&str> = lines[4].split_whitespace().collect();
        assert_eq!(values, ["1E-1", "-2.5E-7", "3E0"]);
        assert_eq!(At2::parse(&text, Path::new("x.at2")).unwrap(), at2);
    }

    /// Reads `text` as the record file `name` in a fresh folder; returns the
    /// result and the file's path.
    fn read_text_as(name: &str, text: &str) -> (Result<Record>, std::path::PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        (read_record(&path, 9.80665), path)
    }

    /// Values that overflow only once scaled or integrated are reported at
    /// the line holding the sample, like every other parse error, and a
    /// huge NPTS is an error, not an allocation failure.
    #[test]
    fn overflows_and_huge_npts_name_the_line() {
        let header = "a\nb\nc\n";
        let cases = [
            // 1e308 g × g overflows: the value is on line 6.
            (
                "x.AT2",
                format!("{header}NPTS= 4, DT= .01\n0 0\n1e308 0\n"),
                6,
                "too large",
            ),
            // DT so large that the velocity overflows at sample 1 (line 5).
            (
                "x.AT2",
                format!("{header}NPTS= 3, DT= 1e308\n0 1\n1\n"),
                5,
                "integrated",
            ),
            // Reserving 2³² + 1 samples used to abort the process.
            (
                "x.AT2",
                format!("{header}NPTS= 4294967297, DT= .01\n0 1\n"),
                5,
                "ends after 2",
            ),
            // The displacement overflows at sample 1 (line 3).
            (
                "x.csv",
                "t,acc\n0,1e308\n0.02,0.5\n".to_string(),
                3,
                "integrated",
            ),
            // t₁ − t₀ overflows.
            (
                "x.csv",
                "t,acc\n-1e308,0\n1e308,0\n".to_string(),
                3,
                "not finite",
            ),
        ];
        for (name, text, line, what) in cases {
            let (result, path) = read_text_as(name, &text);
            let err = result.unwrap_err().to_string();
            let at = format!("{}:{line}: ", path.display());
            assert!(
                err.starts_with(&at) && err.contains(what),
                "{text:?}: {err}"
            );
        }
    }

    #[test]
    fn fortran_exponents() {
        assert_eq!(parse_value(".1234E-02").unwrap(), 0.001234);
        assert_eq!(parse_value("-.5D+01").unwrap(), -5.0);
        assert!(parse_value("NaN").is_err());
    }
}
