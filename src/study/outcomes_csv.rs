//! The `outcomes.csv` format: one row per analysis, in the canonical order
//! of units and cases (see [`super::plan`]).
//!
//! Columns, in order (the bracketed ones only when the study uses them):
//!
//! ```text
//! aspect,width,restitution,friction,mu_s,mu_k,pga,pgv,record,[record_file],
//! status,overturned,overturn_time,uplifted,moved,theta_max_over_theta_c,
//! mu_motion,mu_impact,impacts,flights,uplifts,liftoff_holds,energy_gains,
//! settles,slip_max,slip_final,stick_holds,end_time,first_impact_time,
//! [t_rest,t_slide,t_rock,t_slide_rock,t_flight],
//! [rhs_calls,steps_accepted,steps_rejected,events],error
//! ```
//!
//! - `friction` is `inf` or `coulomb` (then `mu_s`, `mu_k` are set, else empty);
//! - `pga` (g) and `pgv` (m/s): one is the study's intensity level, the
//!   other the scaled record's measured peak (PGV for PGA studies, PGA for
//!   PGV studies), so that fragility can be fitted against either;
//! - `record` is the ensemble index (0-based); `record_file` the spec's path;
//! - `status` is `ok` or `failed`; a failed analysis leaves the outcome
//!   columns empty and says why in `error`;
//! - absent times (no overturn, no impact) are empty;
//! - floats use Rust's shortest round-trip form, so the file holds the exact
//!   `f64` values, and the same run gives the same bytes.
//!
//! The file is read back with [`super::outcomes_read`].

use super::plan::Case;
use crate::outcome::Outcome;
use crate::solver::Friction;
use crate::spec::{Intensity, Motions, Study};
use std::fmt::Write;

/// Which optional columns a study's `outcomes.csv` has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Columns {
    /// The levels are PGV (else PGA).
    pub pgv: bool,
    /// Recorded motions (`record_file` column).
    pub files: bool,
    /// Time in each mode.
    pub time_in_mode: bool,
    /// Solver work counters.
    pub stats: bool,
}

/// What a row says about its record.
#[derive(Clone, Copy, Debug)]
pub struct RecordInfo<'a> {
    /// Ensemble index.
    pub index: usize,
    /// The intensity level (g for PGA, m/s for PGV).
    pub level: f64,
    /// Measured PGA of the scaled record, g (`None` if the record failed).
    pub pga_g: Option<f64>,
    /// Measured PGV of the scaled record, m/s (`None` if the record failed).
    pub pgv: Option<f64>,
    /// The record file as written in the spec.
    pub file: Option<&'a str>,
}

impl Columns {
    /// The columns of `study`.
    pub fn of(study: &Study) -> Columns {
        Columns {
            pgv: matches!(study.intensity, Intensity::Pgv(_)),
            files: matches!(study.motions, Motions::Files(_)),
            time_in_mode: study.output.time_in_mode,
            stats: study.output.stats,
        }
    }

    /// Column names, in order.
    pub fn names(&self) -> Vec<&'static str> {
        let mut v = vec![
            "aspect",
            "width",
            "restitution",
            "friction",
            "mu_s",
            "mu_k",
            "pga",
            "pgv",
            "record",
        ];
        if self.files {
            v.push("record_file");
        }
        v.extend([
            "status",
            "overturned",
            "overturn_time",
            "uplifted",
            "moved",
            "theta_max_over_theta_c",
            "mu_motion",
            "mu_impact",
            "impacts",
            "flights",
            "uplifts",
            "liftoff_holds",
            "energy_gains",
            "settles",
            "slip_max",
            "slip_final",
            "stick_holds",
            "end_time",
            "first_impact_time",
        ]);
        if self.time_in_mode {
            v.extend(["t_rest", "t_slide", "t_rock", "t_slide_rock", "t_flight"]);
        }
        if self.stats {
            v.extend(["rhs_calls", "steps_accepted", "steps_rejected", "events"]);
        }
        v.push("error");
        v
    }

    /// The header line, with its newline.
    pub fn header(&self) -> String {
        let mut s = self.names().join(",");
        s.push('\n');
        s
    }

    /// Appends the row of one analysis to `out`, with its newline.
    pub fn write_row(
        &self,
        out: &mut String,
        case: &Case,
        record: &RecordInfo,
        result: &std::result::Result<Outcome, String>,
    ) {
        let w = &mut *out;
        let (name, mu_s, mu_k) = match case.friction {
            Friction::Infinite => ("inf", String::new(), String::new()),
            Friction::Coulomb { mu_s, mu_k } => ("coulomb", mu_s.to_string(), mu_k.to_string()),
        };
        let _ = write!(
            w,
            "{},{},{},{name},{mu_s},{mu_k},",
            case.aspect, case.width, case.restitution
        );
        if self.pgv {
            let _ = write!(w, "{},{},", opt(record.pga_g), record.level);
        } else {
            let _ = write!(w, "{},{},", record.level, opt(record.pgv));
        }
        let _ = write!(w, "{},", record.index);
        if self.files {
            push_field(w, record.file.unwrap_or(""));
            w.push(',');
        }
        match result {
            Ok(o) => {
                let _ = write!(
                    w,
                    "ok,{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                    o.overturned,
                    opt(o.overturn_time),
                    o.uplifted,
                    o.moved,
                    o.theta_max_over_theta_c,
                    o.mu_motion,
                    o.mu_impact,
                    o.impacts,
                    o.flights,
                    o.uplifts,
                    o.liftoff_holds,
                    o.energy_gains,
                    o.settles,
                    o.slip_max,
                    o.slip_final,
                    o.stick_holds,
                    o.end_time,
                    opt(o.first_impact_time),
                );
                if self.time_in_mode {
                    for t in o.time_in_mode {
                        let _ = write!(w, ",{t}");
                    }
                }
                if self.stats {
                    let s = &o.stats;
                    let _ = write!(
                        w,
                        ",{},{},{},{}",
                        s.rhs_calls, s.steps_accepted, s.steps_rejected, s.events
                    );
                }
                w.push_str(",\n");
            }
            Err(message) => {
                w.push_str("failed");
                let empty = 18 + 5 * self.time_in_mode as usize + 4 * self.stats as usize;
                for _ in 0..empty {
                    w.push(',');
                }
                w.push(',');
                push_field(w, message);
                w.push('\n');
            }
        }
    }
}

fn opt(x: Option<f64>) -> String {
    x.map_or(String::new(), |v| v.to_string())
}

/// Appends a CSV field, quoted when it holds a comma, a quote or a line break.
fn push_field(out: &mut String, s: &str) {
    if s.contains([',', '"', '\n', '\r']) {
        out.push('"');
        out.push_str(&s.replace('"', "\"\""));
        out.push('"');
    } else {
        out.push_str(s);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::{Analysis, Block};

    fn case() -> Case {
        let block = Block::new(0.5, 4.0, 9.81).unwrap();
        Case {
            aspect: 4.0,
            width: 0.5,
            restitution: 0.3,
            friction: Friction::Coulomb {
                mu_s: 0.7,
                mu_k: 0.6,
            },
            index: [0; 4],
            analysis: Analysis::new(block, 0.3),
        }
    }

    #[test]
    fn rows_have_as_many_fields_as_the_header() {
        for cols in [
            Columns {
                pgv: false,
                files: false,
                time_in_mode: false,
                stats: false,
            },
            Columns {
                pgv: true,
                files: true,
                time_in_mode: true,
                stats: true,
            },
        ] {
            let n = cols.names().len();
            let rec = RecordInfo {
                index: 3,
                level: 0.3,
                pga_g: Some(0.5),
                pgv: Some(0.4),
                file: Some("a,b.csv"),
            };
            for result in [
                Ok(Outcome::default()),
                Err("solver failed, \"x\"".to_string()),
            ] {
                let mut s = String::new();
                cols.write_row(&mut s, &case(), &rec, &result);
                let mut r = csv::ReaderBuilder::new()
                    .has_headers(false)
                    .from_reader(s.as_bytes());
                let rec = r.records().next().unwrap().unwrap();
                assert_eq!(rec.len(), n, "{s}");
            }
        }
    }
}
