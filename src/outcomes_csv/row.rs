//! One row of `outcomes.csv`, [`OutcomeRow`]: its writer
//! ([`Columns::write_row`]) and its reader ([`OutcomesFile`]) side by side,
//! so that a column is added in one place and every consumer — the study's
//! summary, the fragility fit, the figures, `merge`, Python — reads the
//! same type.

use std::path::Path;

use super::columns::{CASE, Column, Columns};
use crate::case::{Case, CaseValues};
use crate::error::{Error, Result};
use crate::im::{Im, ImValues};
use crate::outcome::Outcome;
use crate::table::Table;
use std::fmt::Write;

/// One analysis: its block, its record and its outcome.
#[derive(Clone, Debug, PartialEq)]
pub struct OutcomeRow {
    /// The analysis's own block (drawn values as drawn).
    pub case: CaseValues,
    /// The record's intensity measures that have a column in the file
    /// ([`Column::Im`]), each in its unit: the level of the study in its
    /// measure's column, the scaled record's measured values in the others
    /// (`pga`, `pgv`; a pair's `pga_rotd50`, `pgv_rotd50`; the floor's
    /// `pfa`, `pfv`). None when the record failed.
    pub ims: ImValues,
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
    /// A stack's bodies as simulated, by slot (drawn values as drawn;
    /// `None` for a block, or a stack whose values are not written: see
    /// [`Columns::stack_values`]).
    pub bodies: Option<crate::case::StackValues>,
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

    /// The row's value of an intensity column: an IM's ([`Column::Im`])
    /// or `scale` (`None` when absent, or for any other column).
    pub fn intensity(&self, column: Column) -> Option<f64> {
        match column {
            Column::Im(im) => self.ims.get(im),
            Column::Scale => self.scale,
            _ => None,
        }
    }

    /// The row's value of intensity measure `im`, when the file holds it.
    pub fn im(&self, im: Im) -> Option<f64> {
        self.ims.get(im)
    }
}

/// What the study runner knows of a row's record.
#[derive(Clone, Copy, Debug)]
pub struct RecordInfo<'a> {
    /// Ensemble index.
    pub index: usize,
    /// The intensity level (g for PGA, m/s for PGV, a factor for scale).
    pub level: f64,
    /// The intensity measures of the scaled record (of [`Im::COLUMNS`]:
    /// the ground's peaks, a pair's RotD50, the floor's peaks; empty if the
    /// record failed).
    pub measured: &'a ImValues,
    /// The direction the block faces, degrees from the pair's H1 (`None`
    /// without pairs).
    pub phi: Option<f64>,
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
        case: CaseValues,
        record: &RecordInfo,
        result: std::result::Result<Outcome, String>,
    ) -> OutcomeRow {
        let level = record.level;
        let mut ims = ImValues::new();
        let mut scale = None;
        let level_column = self.level();
        for column in self.list() {
            let Column::Im(im) = column else { continue };
            match (column == level_column, record.measured.get(im)) {
                (true, _) => ims.set(im, level),
                (false, Some(v)) => ims.set(im, v),
                (false, None) => {}
            }
        }
        if level_column == Column::Scale {
            scale = Some(level);
        }
        OutcomeRow {
            case,
            ims,
            record: record.index,
            record_file: record.file.filter(|_| self.files).map(str::to_string),
            phi: record.phi.filter(|_| self.pairs),
            scale,
            result,
            sensitive: None,
            bodies: None,
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
        let case = Case::from(self.case);
        match column {
            Column::Aspect => param(out, Some(case.aspect)),
            Column::Width => param(out, Some(case.width)),
            Column::Restitution => param(out, Some(case.restitution)),
            Column::Friction => out.push_str(case.friction_name()),
            Column::MuS => param(out, case.mu_s()),
            Column::MuK => param(out, case.mu_k()),
            Column::Stack => out.push_str(self.case.stack.as_ref().map_or("", |s| s.as_str())),
            Column::Im(im) => num(out, self.ims.get(im)),
            Column::Phi => num(out, self.phi),
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
            Column::BodyValue(slot, field) => {
                num(
                    out,
                    self.bodies
                        .and_then(|b| b[slot.index()])
                        .and_then(|b| field.of(&b)),
                );
            }
            c => {
                if let Ok(o) = &self.result {
                    c.write_value(o, out);
                }
            }
        }
    }
}

/// Sets `field` of the body at `slot` of `row` to `x` (as
/// [`OutcomeRow::write_field`] wrote it: μs and μk make Coulomb friction,
/// infinite friction writes neither).
fn read_body_value(
    row: &mut OutcomeRow,
    slot: crate::outcome::Slot,
    field: super::columns::ValueField,
    x: f64,
) {
    use super::columns::ValueField as V;
    use crate::solver::Friction;
    let body =
        row.bodies.get_or_insert([None; 3])[slot.index()].get_or_insert(crate::case::BodyValues {
            width: f64::NAN,
            height: f64::NAN,
            mass: f64::NAN,
            offset: f64::NAN,
            restitution: f64::NAN,
            friction: Friction::Infinite,
        });
    let (mu_s, mu_k) = match body.friction {
        Friction::Coulomb { mu_s, mu_k } => (mu_s, mu_k),
        Friction::Infinite => (f64::NAN, f64::NAN),
    };
    match field {
        V::Width => body.width = x,
        V::Height => body.height = x,
        V::Mass => body.mass = x,
        V::Offset => body.offset = x,
        V::Restitution => body.restitution = x,
        V::MuS => body.friction = Friction::Coulomb { mu_s: x, mu_k },
        V::MuK => body.friction = Friction::Coulomb { mu_s, mu_k: x },
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
        let names: Vec<String> = required.iter().map(|c| c.name().into_owned()).collect();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
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
        let case = row.values()?;
        let mut out = OutcomeRow {
            case,
            ims: ImValues::new(),
            record: 0,
            record_file: None,
            phi: None,
            scale: None,
            result: Ok(Outcome::default()),
            sensitive: None,
            bodies: None,
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
                Column::Im(im) => {
                    if let Some(v) = opt()? {
                        out.ims.set(im, v);
                    }
                }
                Column::Phi => out.phi = opt()?,
                Column::Scale => out.scale = opt()?,
                Column::Record => out.record = row.integer(i)? as usize,
                Column::RecordFile => {
                    out.record_file = (!text.is_empty()).then(|| text.to_string())
                }
                Column::Error => error = text.to_string(),
                Column::Status => {}
                Column::Stack if !text.is_empty() => {
                    let name = crate::case::StackName::new(text).ok_or_else(|| {
                        row.error(i, "a stack's name (letters, digits, _) or empty")
                    })?;
                    out.case.stack = Some(name);
                    if let Ok(o) = out.result.as_mut() {
                        o.stack = Some(Default::default());
                    }
                }
                Column::Stack => {}
                Column::BodyValue(slot, field) => {
                    if let Some(x) = opt()? {
                        read_body_value(&mut out, slot, field, x);
                    }
                }
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

    fn case() -> CaseValues {
        CaseValues::block(
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
                stack: false,
                middle: false,
                stack_values: false,
            },
            Columns::ALL,
        ] {
            let n = cols.names().len();
            let mut measured = ImValues::new();
            for (im, v) in Im::COLUMNS
                .into_iter()
                .zip([0.5, 0.4, 0.45, 0.35, 0.9, 0.7])
            {
                measured.set(im, v);
            }
            let rec = RecordInfo {
                index: 3,
                level: 0.3,
                measured: &measured,
                phi: Some(37.5),
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
            let mut file = OutcomesFile::open(&path, &[Column::Im(Im::PGA)], "the test").unwrap();
            for want in &rows {
                let (_, got) = file.next_row().unwrap().unwrap();
                assert_eq!(&got, want);
            }
            assert!(file.next_row().unwrap().is_none());
        }
    }
}
