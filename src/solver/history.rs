//! Full time history of one analysis, produced only on request.

use crate::error::{Error, Result};
use crate::outcome::Mode;
use std::path::Path;

/// One row of the history: the state at an event or at a record sample.
/// Positions are of the centre of mass relative to its rest position on the
/// moving ground (m); reactions are per unit mass (N/kg).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HistoryRow {
    /// Time (s).
    pub t: f64,
    /// Mode after this instant.
    pub mode: Mode,
    /// Rotation θ (rad).
    pub theta: f64,
    /// Angular velocity θ̇ (rad/s).
    pub theta_dot: f64,
    /// Horizontal displacement x (m).
    pub x: f64,
    /// Horizontal velocity ẋ (m/s).
    pub x_dot: f64,
    /// Vertical displacement y (m).
    pub y: f64,
    /// Vertical velocity ẏ (m/s).
    pub y_dot: f64,
    /// Normal reaction per unit mass N/m (m/s²); 0 in flight.
    pub n: f64,
    /// Horizontal reaction per unit mass F/m (m/s²); 0 in flight.
    pub f: f64,
    /// True if the row marks an event rather than a record sample.
    pub event: bool,
}

/// A time history: rows in time order (events and record samples).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct History {
    /// The rows.
    pub rows: Vec<HistoryRow>,
}

impl History {
    /// Writes CSV with header `t,mode,theta,theta_dot,x,x_dot,y,y_dot,N,F`
    /// to a temporary file beside `path`, then renames it into place.
    pub fn write_csv(&self, path: &Path) -> Result<()> {
        crate::io_util::write_atomic(path, |w| {
            writeln!(w, "t,mode,theta,theta_dot,x,x_dot,y,y_dot,N,F")?;
            for r in &self.rows {
                writeln!(
                    w,
                    "{},{},{},{},{},{},{},{},{},{}",
                    r.t,
                    r.mode.name(),
                    r.theta,
                    r.theta_dot,
                    r.x,
                    r.x_dot,
                    r.y,
                    r.y_dot,
                    r.n,
                    r.f
                )?;
            }
            Ok(())
        })
        .map_err(Error::io(path))
    }
}
