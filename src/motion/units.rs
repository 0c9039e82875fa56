//! Checks that a record file's numbers are in the units it declares: a
//! CSV record is SI (`t` s, `acc` m/s², `vel` m/s, `disp` m), a PEER `.AT2`
//! record states its units in its header (g when it does not). A record in
//! the wrong unit is not an error the solver can see: scaled to a PGA level
//! it even gives the right answer, but run as recorded (`scale_factors`),
//! scaled to PGV, or with a `vel` column from another unit than `acc`'s, it
//! is 9.81 or 100 times too strong or too weak, and the outcomes say so
//! only in absurd peaks (a PGV of 23.5 m/s). So the readers refuse:
//!
//! - a peak acceleration above [`MAX_PGA`] (50 m/s², 5.1 g; the largest
//!   ever recorded is about 4.4 g): a file in cm/s² (or m/s²) read as m/s²
//!   (as g);
//! - a CSV record whose peak acceleration is below [`MIN_CSV_PGA`]
//!   (0.05 m/s², 0.005 g, about what a person can feel): a file in g read
//!   as m/s² (a 0.3 g record becomes 0.03 g, and a weaker one falls below
//!   the threshold);
//! - a CSV record whose `vel` (`disp`) column is not the integral of its
//!   `acc` (`vel`) column: the slope of the best fit of its steps to
//!   Δt·(aₖ + aₖ₊₁)/2 must be within a factor 2 of 1 ([`RATIO_TOLERANCE`];
//!   a step-by-step comparison, so a record whose integral drifts is not
//!   refused); 100 is a `vel` in cm/s, 0.01 an `acc` in cm/s², 9.81 an
//!   `acc` in g.
//!
//! Each message names the file, the column and the value, and how to state
//! the unit.

use std::path::Path;

use crate::error::{Error, Result};
use crate::io_util::sig3;

/// Largest peak acceleration a record may have (m/s²): 50 m/s² ≈ 5.1 g,
/// above any recorded ground motion (Iwate–Miyagi 2008, about 4.4 g).
pub const MAX_PGA: f64 = 50.0;

/// Smallest peak acceleration a CSV record (declared in m/s²) may have:
/// 0.05 m/s² ≈ 0.005 g, at the threshold of human perception and far
/// below anything that rocks a block; a record in g read as m/s² is 9.81
/// times too weak.
pub const MIN_CSV_PGA: f64 = 0.05;

/// How far from 1 the ratio of a CSV record's `vel` steps to its `acc`
/// integral (and of `disp` to `vel`) may be: a factor 2 either way, far
/// outside what integration rules or filtering change, far inside the unit
/// errors (9.81, 100).
pub const RATIO_TOLERANCE: f64 = 2.0;

/// Standard gravity for the messages' g (the checks are in m/s²).
const G: f64 = 9.81;

fn err(path: &Path, line: usize, message: String) -> Error {
    Error::Parse {
        path: path.to_path_buf(),
        line,
        message,
    }
}

/// The largest |x|.
fn peak(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// Refuses a record whose peak acceleration (m/s², `acc`) is above
/// [`MAX_PGA`]; `declared` names the unit the file's values were read in
/// and `fix` what to do, `line` where the peak is.
pub fn check_max_peak(
    path: &Path,
    acc: &[f64],
    declared: &str,
    fix: &str,
    line_of: impl Fn(usize) -> usize,
) -> Result<()> {
    let Some(k) = acc.iter().position(|a| a.abs() > MAX_PGA) else {
        return Ok(());
    };
    let p = peak(acc);
    let at = acc.iter().position(|a| a.abs() == p).unwrap_or(k);
    Err(err(
        path,
        line_of(at),
        format!(
            "peak acceleration {} m/s² ({} g), read in {declared}, is above {MAX_PGA} m/s² \
             ({} g), more than any earthquake has been recorded with: {fix}",
            sig3(p),
            sig3(p / G),
            sig3(MAX_PGA / G)
        ),
    ))
}

/// Refuses a CSV record (m/s²) whose peak acceleration is below
/// [`MIN_CSV_PGA`] (`line`: the header's, for the column).
pub fn check_min_peak_csv(path: &Path, acc: &[f64], line: usize) -> Result<()> {
    let p = peak(acc);
    if p >= MIN_CSV_PGA {
        return Ok(());
    }
    Err(err(
        path,
        line,
        format!(
            "column 'acc': peak acceleration {} m/s² ({} g) is below {MIN_CSV_PGA} m/s² \
             ({} g), too weak to be a record in m/s²: a CSV record's acc is in m/s²; if these \
             values are in g, multiply them by 9.81, or write the record as a PEER .AT2 file, \
             whose header states its units (IN UNITS OF G)",
            sig3(p),
            sig3(p / G),
            sig3(MIN_CSV_PGA / G)
        ),
    ))
}

/// The slope s of the best fit (through 0) of `y`'s steps to
/// Δt·(xₖ + xₖ₊₁)/2, the trapezoidal integral of `x`: 1 when `y` is the
/// integral of `x` in the same units. `None` when `x` is zero throughout.
fn integral_ratio(dt: f64, x: &[f64], y: &[f64]) -> Option<f64> {
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for k in 0..x.len().saturating_sub(1) {
        let step = 0.5 * dt * (x[k] + x[k + 1]);
        sxy += step * (y[k + 1] - y[k]);
        sxx += step * step;
    }
    (sxx > 0.0).then(|| sxy / sxx)
}

/// The unit mistake a ratio looks like, in words, or "".
fn likely(ratio: f64, column: &str) -> &'static str {
    let near = |x: f64| (ratio / x - 1.0).abs() < 0.2;
    match column {
        "vel" if near(100.0) => " (vel in cm/s?)",
        "vel" if near(0.01) => " (acc in cm/s²?)",
        "vel" if near(G) => " (acc in g?)",
        "vel" if near(100.0 * G) => " (acc in g and vel in cm/s?)",
        "vel" if near(1.0 / G) => " (vel in units of g·s?)",
        "disp" if near(100.0) => " (disp in cm?)",
        "disp" if near(0.01) => " (vel in cm/s?)",
        _ => "",
    }
}

/// Refuses a CSV record whose `vel` is not the integral of its `acc`, or
/// whose `disp` is not the integral of its `vel`, within
/// [`RATIO_TOLERANCE`] (`line`: the header's).
pub fn check_integrals(
    path: &Path,
    line: usize,
    dt: f64,
    acc: &[f64],
    vel: &[f64],
    disp: &[f64],
) -> Result<()> {
    for (column, of, x, y) in [("vel", "acc", acc, vel), ("disp", "vel", vel, disp)] {
        let Some(ratio) = integral_ratio(dt, x, y) else {
            continue;
        };
        if ratio.abs() < 1.0 / RATIO_TOLERANCE || ratio.abs() > RATIO_TOLERANCE || ratio < 0.0 {
            return Err(err(
                path,
                line,
                format!(
                    "column '{column}' is {} times the integral of column '{of}' (the best fit \
                     of its steps to Δt times the mean of '{of}'; expected 1 within a factor \
                     {RATIO_TOLERANCE}){}: a CSV record is t in s, acc in m/s², vel in m/s, \
                     disp in m. Convert the columns, or give only 't,acc' to have vel and disp \
                     integrated from acc",
                    sig3(ratio),
                    likely(ratio, column)
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ratio of a trapezoidal integral is 1 exactly, of the same in
    /// cm/s 100, of a drifting integral (an offset in x) still about 1.
    #[test]
    fn ratios_of_integrals() {
        let dt = 0.01;
        let x: Vec<f64> = (0..1000)
            .map(|k| crate::detmath::sin(k as f64 * 0.05) + 0.3)
            .collect();
        let mut y = vec![0.0];
        for k in 0..x.len() - 1 {
            let next = y[k] + 0.5 * dt * (x[k] + x[k + 1]);
            y.push(next);
        }
        assert!((integral_ratio(dt, &x, &y).unwrap() - 1.0).abs() < 1e-12);
        let cm: Vec<f64> = y.iter().map(|v| 100.0 * v).collect();
        assert!((integral_ratio(dt, &x, &cm).unwrap() - 100.0).abs() < 1e-9);
        assert_eq!(likely(100.0, "vel"), " (vel in cm/s?)");
        assert_eq!(integral_ratio(dt, &[0.0; 4], &[1.0; 4]), None);
    }
}
