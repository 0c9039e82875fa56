//! One row of `outcomes.csv`, [`OutcomeRow`]: its writer
//! ([`Columns::write_row`]) and its reader ([`OutcomesFile`]) side by side,
//! so that a column is added in one place and every consumer — the study's
//! summary, the fragility fit, the figures, `merge`, Python — reads the
//! same type.

use std::path::Path;

use super::columns::{CASE, Column, Columns};
use crate::case::Case;
use crate::error::{Error, Result};
use crate::outcome::Outcome;
use crate::table::Table;
use std::fmt::Write;

/// One analysis: its block, its record and its outcome.
#[derive(Clone, Debug, PartialEq)]
pub struct OutcomeRow {
    /// The analysis's own block (every parameter fixed: drawn values as
    /// drawn).
    pub case: Case,
    /// Peak ground acceleration, g: the level of a PGA study, else the
    /// scaled record's measured peak (`None` if the record failed).
    pub pga: Option<f64>,
    /// Peak ground velocity, m/s: the level of a PGV study, else the scaled
    /// record's measured peak (`None` if the record failed).
    pub pgv: Option<f64>,
    /// RotD50 PGA of the record pair, g (studies of record pairs; `None`
    /// otherwise, or if the record failed): the level of a PGA study, else
    /// the scaled pair's measured RotD50. `pga` is then the peak of the
    /// component the block feels.
    pub pga_rotd50: Option<f64>,
    /// RotD50 PGV of the record pair, m/s (as `pga_rotd50`).
    pub pgv_rotd50: Option<f64>,
    /// Peak floor acceleration, g: the peak absolute acceleration of the
    /// floor the block stands on (`None` on the ground, or if the record
    /// failed).
    pub pfa: Option<f64>,
    /// Peak floor velocity, m/s (as `pfa`).
    pub pfv: Option<f64>,
    /// Record index in the ensemble (0-based).
    pub record: usize,
    /// The record file as the spec names it (recorded motions only).
    pub record_file: Option<String>,
    /// The direction the block faces, degrees from the pair's first
    /// component (studies of record pairs).
    pub phi: Option<f64>,
    /// The factor the record was multiplied by (`scale_factors` studies).
    pub scale: Option<f64>,
    /// The outcome, or why the analysis failed.
    pub result: std::result::Result<Outcome, String>,
    /// Whether the analysis is sensitive: solved again under its record
    /// scaled by 1 + 1e-9, its outcome changed
    /// ([`crate::solver::sensitivity()`]). `None` when the study did not ask
    /// (`[output] sensitivity`) or either solve failed.
    pub sensitive: Option<bool>,
}

impl OutcomeRow {
    /// The outcome, `None` for a failed analysis.
    pub fn outcome(&self) -> Option<&Outcome> {
        self.result.as_ref().ok()
    }

    /// The row's intensity level: `scale` for scale-factor studies, `pgv`
    /// for PGV studies, else `pga` (the RotD50 of a pair; see
    /// [`Columns::level`]).
    pub fn level(&self, columns: &Columns) -> Option<f64> {
        self.intensity(columns.level())
    }

    /// The row's value of an intensity column: `pga`, `pgv`, `pga_rotd50`,
    /// `pgv_rotd50`, `pfa`, `pfv` or `scale` (`None` when absent, or for
    /// any other column).
    pub fn intensity(&self, column: Column) -> Option<f64> {
        match column {
            Column::Pga => self.pga,
            Column::Pgv => self.pgv,
            Column::PgaRotd50 => self.pga_rotd50,
            Column::PgvRotd50 => self.pgv_rotd50,
            Column::Pfa => self.pfa,
            Column::Pfv => self.pfv,
            Column::Scale => self.scale,
            _ => None,
        }
    }
}

/// What the study runner knows of a row's record.
#[derive(Clone, Copy, Debug)]
pub struct RecordInfo<'a> {
    /// Ensemble index.
    pub index: usize,
    /// The intensity level (g for PGA, m/s for PGV, a factor for scale).
    pub level: f64,
    /// Measured PGA of the scaled record, g (`None` if the record failed).
    pub pga_g: Option<f64>,
    /// Measured PGV of the scaled record, m/s (`None` if the record failed).
    pub pgv: Option<f64>,
    /// Measured RotD50 PGA of the scaled pair, g (`None` without pairs or
    /// if the record failed).
    pub pga_rotd50_g: Option<f64>,
    /// Measured RotD50 PGV of the scaled pair, m/s (as `pga_rotd50_g`).
    pub pgv_rotd50: Option<f64>,
    /// The direction the block faces, degrees from the pair's H1 (`None`
    /// without pairs).
    pub phi: Option<f64>,
    /// Measured peak floor acceleration, g (`None` on the ground or if the
    /// record failed).
    pub pfa_g: Option<f64>,
    /// Measured peak floor velocity, m/s (as `pfa_g`).
    pub pfv: Option<f64>,
    /// The record file as written in the spec.
    pub file: Option<&'a str>,
}

impl Columns {
    /// The row of one analysis in a file with these columns: the level goes
    /// to its column (`pga`, `pgv`, `pga_rotd50`, `pgv_rotd50` or `scale`),
    /// measured peaks to the others; no sensitivity (the caller sets
    /// [`OutcomeRow::sensitive`]).
    pub fn row(
        &self,
        case: Case,
        record: &RecordInfo,
        result: std::result::Result<Outcome, String>,
    ) -> OutcomeRow {
        let level = Some(record.level);
        let (mut pga, mut pgv) = (record.pga_g, record.pgv);
        let (mut pga_rotd50, mut pgv_rotd50) = (record.pga_rotd50_g, record.pgv_rotd50);
        let mut scale = None;
        match self.level() {
            Column::Scale => scale = level,
            Column::Pgv => pgv = level,
            Column::PgvRotd50 => pgv_rotd50 = level,
            Column::PgaRotd50 => pga_rotd50 = level,
            _ => pga = level,
        }
        OutcomeRow {
            case,
            pga,
            pgv,
            pga_rotd50: pga_rotd50.filter(|_| self.pairs),
            pgv_rotd50: pgv_rotd50.filter(|_| self.pairs),
            pfa: record.pfa_g.filter(|_| self.floor),
            pfv: record.pfv.filter(|_| self.floor),
            record: record.index,
            record_file: record.file.filter(|_| self.files).map(str::to_string),
            phi: record.phi.filter(|_| self.pairs),
            scale,
            result,
            sensitive: None,
        }
    }

    /// Appends `row` to `out`, with its newline: the columns of
    /// [`Columns::list`], in its order, each as [`OutcomeRow::write_field`]
    /// writes it.
    pub fn write_row(&self, out: &mut String, row: &OutcomeRow) {
        for (i, column) in self.list().into_iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            row.write_field(column, out);
        }
        out.push('\n');
    }
}

impl OutcomeRow {
    /// Appends this row's field of `column` to `out`, as `outcomes.csv`
    /// holds it: numbers in their shortest round-trip form (case values as
    /// [`Case::fields`]), an absent value as an empty field, text quoted
    /// when it holds a comma, a quote or a line break. A failed analysis's
    /// outcome columns are empty.
    pub fn write_field(&self, column: Column, out: &mut String) {
        use crate::case::Param;
        let num = |out: &mut String, x: Option<f64>| {
            if let Some(v) = x {
                let _ = write!(out, "{v}");
            }
        };
        let param = |out: &mut String, p: Option<Param<f64>>| {
            out.push_str(&p.map_or(String::new(), Param::field));
        };
        match column {
            Column::Aspect => param(out, Some(self.case.aspect)),
            Column::Width => param(out, Some(self.case.width)),
            Column::Restitution => param(out, Some(self.case.restitution)),
            Column::Friction => out.push_str(self.case.friction_name()),
            Column::MuS => param(out, self.case.mu_s()),
            Column::MuK => param(out, self.case.mu_k()),
            Column::Pga => num(out, self.pga),
            Column::Pgv => num(out, self.pgv),
            Column::PgaRotd50 => num(out, self.pga_rotd50),
            Column::PgvRotd50 => num(out, self.pgv_rotd50),
            Column::Phi => num(out, self.phi),
            Column::Pfa => num(out, self.pfa),
            Column::Pfv => num(out, self.pfv),
            Column::Scale => num(out, self.scale),
            Column::Record => {
                let _ = write!(out, "{}", self.record);
            }
            Column::RecordFile => push_field(out, self.record_file.as_deref().unwrap_or("")),
            Column::Status => out.push_str(if self.result.is_ok() { "ok" } else { "failed" }),
            Column::Error => push_field(out, self.result.as_ref().err().map_or("", String::as_str)),
            Column::Sensitive => {
                if let Some(b) = self.sensitive {
                    let _ = write!(out, "{b}");
                }
            }
            c => {
                if let Ok(o) = &self.result {
                    c.write_value(o, out);
                }
            }
        }
    }
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

/// `outcomes.csv` read back, row by row, as [`OutcomeRow`]s.
///
/// Columns are found by header name (order and unknown columns do not
/// matter); the case columns and the columns a consumer names as required
/// must be there, any other column of [`Column`] is read when present and
/// left at its default ([`Outcome::default`], `None`) when not, so that a
/// file written before a column existed still reads.
pub struct OutcomesFile {
    table: Table,
    /// (column, index in the file) of every known column present.
    present: Vec<(Column, usize)>,
}

impl OutcomesFile {
    /// Opens `path`, checking that the case columns and `required` are in
    /// its header (the error names every missing one and what needs it,
    /// `purpose`).
    pub fn open(path: &Path, required: &[Column], purpose: &str) -> Result<OutcomesFile> {
        let names: Vec<&str> = required.iter().map(|c| c.name()).collect();
        let (table, _) = Table::open_dyn(path, &names, purpose)?;
        let present = Columns::ALL
            .list()
            .into_iter()
            .filter(|c| !CASE.contains(c))
            .filter_map(|c| table.column(c.name()).map(|i| (c, i)))
            .collect();
        Ok(OutcomesFile { table, present })
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        self.table.path()
    }

    /// The header's column names, in the file's order.
    pub fn header(&self) -> &[String] {
        self.table.header()
    }

    /// Whether the file has `column`.
    pub fn has(&self, column: Column) -> bool {
        self.present.iter().any(|&(c, _)| c == column)
    }

    /// The known columns of the file, in the file's order.
    pub fn columns(&self) -> Vec<Column> {
        let mut v = self.present.clone();
        v.sort_by_key(|&(_, i)| i);
        CASE.into_iter()
            .chain(v.into_iter().map(|(c, _)| c))
            .collect()
    }

    /// An error at `line` of this file.
    pub fn error_at(&self, line: usize, message: String) -> Error {
        self.table.error_at(line, message)
    }

    /// An error at the header (line 1) of this file.
    pub fn header_error(&self, message: String) -> Error {
        self.table.header_error(message)
    }

    /// The next row and its line, `None` at the end of the file. A failed
    /// row (`status` not `ok`, or an `error`) has `result` = `Err(error)`
    /// and no outcome columns read.
    ///
    /// Errors: [`Error::Parse`] naming the file, line, column and value.
    pub fn next_row(&mut self) -> Result<Option<(usize, OutcomeRow)>> {
        let Some(row) = self.table.next_row()? else {
            return Ok(None);
        };
        let line = row.line();
        let case = row.case(false)?;
        let mut out = OutcomeRow {
            case,
            pga: None,
            pgv: None,
            pga_rotd50: None,
            pgv_rotd50: None,
            pfa: None,
            pfv: None,
            record: 0,
            record_file: None,
            phi: None,
            scale: None,
            result: Ok(Outcome::default()),
            sensitive: None,
        };
        let failed = row.failed();
        let mut error = String::new();
        for &(column, i) in &self.present {
            let text = row.field(i);
            let opt = || -> Result<Option<f64>> {
                if text.is_empty() {
                    Ok(None)
                } else {
                    row.number(i).map(Some)
                }
            };
            match column {
                Column::Pga => out.pga = opt()?,
                Column::Pgv => out.pgv = opt()?,
                Column::PgaRotd50 => out.pga_rotd50 = opt()?,
                Column::PgvRotd50 => out.pgv_rotd50 = opt()?,
                Column::Phi => out.phi = opt()?,
                Column::Pfa => out.pfa = opt()?,
                Column::Pfv => out.pfv = opt()?,
                Column::Scale => out.scale = opt()?,
                Column::Record => out.record = row.integer(i)? as usize,
                Column::RecordFile => {
                    out.record_file = (!text.is_empty()).then(|| text.to_string())
                }
                Column::Error => error = text.to_string(),
                Column::Status => {}
                Column::Sensitive => {
                    out.sensitive = match text {
                        "" => None,
                        "true" => Some(true),
                        "false" => Some(false),
                        _ => return Err(row.error(i, "true, false or empty")),
                    }
                }
                c if !failed => {
                    if let Ok(o) = out.result.as_mut() {
                        c.read_value(o, text).map_err(|e| row.error(i, e))?;
                    }
                }
                _ => {}
            }
        }
        if failed {
            out.result = Err(error);
        }
        Ok(Some((line, out)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::Friction;

    fn case() -> Case {
        Case::fixed(
            4.0,
            0.5,
            0.3,
            Friction::Coulomb {
                mu_s: 0.7,
                mu_k: 0.6,
            },
        )
    }

    /// Every row has as many fields as the header, and reads back as the
    /// row written.
    #[test]
    fn rows_round_trip() {
        for cols in [
            Columns {
                pgv: false,
                files: false,
                pairs: false,
                scale: false,
                time_in_mode: false,
                stats: false,
                floor: false,
                sensitivity: false,
            },
            Columns::ALL,
        ] {
            let n = cols.names().len();
            let rec = RecordInfo {
                index: 3,
                level: 0.3,
                pga_g: Some(0.5),
                pgv: Some(0.4),
                pga_rotd50_g: Some(0.45),
                pgv_rotd50: Some(0.35),
                phi: Some(37.5),
                pfa_g: Some(0.9),
                pfv: Some(0.7),
                file: Some("a,b.csv"),
            };
            let mut outcome = Outcome {
                overturned: true,
                overturn_time: Some(3.25),
                theta_max_over_theta_c: 2.0,
                impacts: 7,
                ..Outcome::default()
            };
            if cols.time_in_mode {
                outcome.time_in_mode = [1.0, 2.0, 3.0, 4.0, 5.0];
            }
            if cols.stats {
                outcome.stats.events = 11;
            }
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join("outcomes.csv");
            let mut rows = [
                cols.row(case(), &rec, Ok(outcome)),
                cols.row(case(), &rec, Err("solver failed, \"x\"".to_string())),
            ];
            if cols.sensitivity {
                rows[0].sensitive = Some(true);
            }
            let mut s = cols.header();
            for row in &rows {
                let mut line = String::new();
                cols.write_row(&mut line, row);
                let mut r = csv::ReaderBuilder::new()
                    .has_headers(false)
                    .from_reader(line.as_bytes());
                assert_eq!(r.records().next().unwrap().unwrap().len(), n, "{line}");
                s.push_str(&line);
            }
            std::fs::write(&path, s).unwrap();
            let mut file = OutcomesFile::open(&path, &[Column::Pga], "the test").unwrap();
            for want in &rows {
                let (_, got) = file.next_row().unwrap().unwrap();
                assert_eq!(&got, want);
            }
            assert!(file.next_row().unwrap().is_none());
        }
    }
}
