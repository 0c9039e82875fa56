//! Reading a stage file back: the one place that finds columns by header
//! name, parses the case columns, tells failed rows apart and words the
//! errors. Each stage file's row type (`outcomes.csv`'s
//! [`OutcomeRow`](crate::outcomes_csv::OutcomeRow), `fragility.csv`'s, …)
//! reads its rows through a [`Table`].
//!
//! - Columns are found by header name: order and extra columns do not matter.
//!   Headers and fields are trimmed.
//! - The case is the six columns of [`CASE_COLUMNS`], read into a fitted
//!   [`Case`] ([`Case::parse`]) or an analysis's [`CaseValues`]
//!   ([`CaseValues::parse`]).
//! - A row is failed ([`Row::failed`]) when its `status` column, if any, is
//!   not `ok`, or its `error` column, if any, is not empty: its outcome
//!   columns are empty and must not be read.
//! - Every error is an [`Error::Parse`] naming the file and line; for a bad
//!   value, the message names the column and quotes the value.

use std::path::{Path, PathBuf};

use crate::case::{CASE_COLUMNS, Case, CaseValues};
use crate::error::{Error, Result};

/// A CSV stage file keyed by the case columns (`outcomes.csv`,
/// `fragility.csv`, …), read row by row with line numbers for errors.
pub struct Table {
    path: PathBuf,
    reader: csv::Reader<std::fs::File>,
    header: Vec<String>,
    case: [usize; 6],
    /// A `case_id` column (files of fitted cases), which names a stack
    /// (`stack_NAME`, [`crate::case::StackName::from_case_id`]).
    case_id: Option<usize>,
    status: Option<usize>,
    error: Option<usize>,
    record: csv::StringRecord,
}

impl Table {
    /// Opens `path` and finds the case columns and `columns` in its header;
    /// returns the reader and the indices of `columns`, in order.
    ///
    /// Errors: [`Error::Io`] if the file cannot be opened; [`Error::Parse`]
    /// at line 1 for an unreadable header or naming every missing column
    /// and what needs them (`purpose`, e.g. "the fragility fit").
    pub fn open<const N: usize, C: AsRef<str>>(
        path: &Path,
        columns: [C; N],
        purpose: &str,
    ) -> Result<(Table, [usize; N])> {
        let names: Vec<&str> = columns.iter().map(AsRef::as_ref).collect();
        let (table, indices) = Table::open_dyn(path, &names, purpose)?;
        Ok((table, std::array::from_fn(|i| indices[i])))
    }

    /// As [`Table::open`], for a list of columns known at run time.
    pub fn open_dyn(path: &Path, columns: &[&str], purpose: &str) -> Result<(Table, Vec<usize>)> {
        let file = std::fs::File::open(path).map_err(Error::io(path))?;
        let mut reader = csv::ReaderBuilder::new()
            // fields are trimmed as they are read ([`Row::field`]): the
            // reader's own trim rebuilds every record, a third of the cost
            // of reading 100,000 rows
            .trim(csv::Trim::Headers)
            .from_reader(file);
        let header: Vec<String> = reader
            .headers()
            .map_err(|e| parse_error(path, 1, format!("cannot read the header: {e}")))?
            .iter()
            .map(str::to_string)
            .collect();
        let find = |name: &str| header.iter().position(|h| h == name);
        let missing: Vec<String> = CASE_COLUMNS
            .iter()
            .chain(columns)
            .filter(|n| find(n).is_none())
            .map(|n| format!("`{n}`"))
            .collect();
        if !missing.is_empty() {
            return Err(parse_error(
                path,
                1,
                format!(
                    "no column {} in the header (needed for {purpose})",
                    missing.join(", ")
                ),
            ));
        }
        let case = CASE_COLUMNS.map(|n| find(n).expect("checked above"));
        let indices = columns
            .iter()
            .map(|n| find(n).expect("checked above"))
            .collect();
        let (status, error, case_id) = (find("status"), find("error"), find("case_id"));
        let table = Table {
            path: path.to_path_buf(),
            reader,
            header,
            case,
            case_id,
            status,
            error,
            record: csv::StringRecord::new(),
        };
        Ok((table, indices))
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The header's column names, in the file's order.
    pub fn header(&self) -> &[String] {
        &self.header
    }

    /// An error at `line` of this file.
    pub fn error_at(&self, line: usize, message: String) -> Error {
        parse_error(&self.path, line, message)
    }

    /// The index of an optional column.
    pub fn column(&self, name: impl AsRef<str>) -> Option<usize> {
        self.header.iter().position(|h| h == name.as_ref())
    }

    /// An error at line 1 (the header) of this file.
    pub fn header_error(&self, message: String) -> Error {
        parse_error(&self.path, 1, message)
    }

    /// The next row, `None` at the end of the file.
    ///
    /// Errors: [`Error::Parse`] for malformed CSV (e.g. a row with a
    /// different number of fields than the header).
    pub fn next_row(&mut self) -> Result<Option<Row<'_>>> {
        match self.reader.read_record(&mut self.record) {
            Ok(false) => Ok(None),
            Ok(true) => Ok(Some(Row {
                table: self,
                line: self.record.position().map_or(0, |p| p.line() as usize),
            })),
            Err(e) => {
                let line = e.position().map_or(0, |p| p.line() as usize);
                Err(parse_error(&self.path, line, e.to_string()))
            }
        }
    }
}

/// One row of an [`Table`]; its accessors take column indices from
/// [`Table::open`] or [`Table::column`].
pub struct Row<'a> {
    table: &'a Table,
    line: usize,
}

impl Row<'_> {
    /// The 1-based line of the row in the file.
    pub fn line(&self) -> usize {
        self.line
    }

    /// The (trimmed) text of column `i`; empty if the row has no such field.
    pub fn field(&self, i: usize) -> &str {
        // as `Trim::All` would (csv's `StringRecord::trim` is `str::trim`)
        self.table.record.get(i).unwrap_or("").trim()
    }

    /// Whether the analysis failed: `status` (if present) is not `ok`, or
    /// `error` (if present) is not empty.
    pub fn failed(&self) -> bool {
        let t = self.table;
        t.status
            .is_some_and(|i| !self.field(i).eq_ignore_ascii_case("ok"))
            || t.error.is_some_and(|i| !self.field(i).is_empty())
    }

    /// The fitted case of this row ([`Case::parse`]): drawn parameters are
    /// empty fields.
    pub fn case(&self) -> Result<Case> {
        let fields = self.table.case.map(|i| self.field(i));
        let mut case = Case::parse(fields)
            .map_err(|(k, expected)| self.error(self.table.case[k], expected))?;
        case.stack = self.stack();
        Ok(case)
    }

    /// The analysis's own values of this row ([`CaseValues::parse`]):
    /// every field a value.
    pub fn values(&self) -> Result<CaseValues> {
        let fields = self.table.case.map(|i| self.field(i));
        let mut values = CaseValues::parse(fields)
            .map_err(|(k, expected)| self.error(self.table.case[k], expected))?;
        values.stack = self.stack();
        Ok(values)
    }

    /// The stack a row's case is, named by its id (outcomes.csv names it in
    /// its `stack` column, read by its own reader).
    fn stack(&self) -> Option<crate::case::StackName> {
        self.table
            .case_id
            .and_then(|i| crate::case::StackName::from_case_id(self.field(i)))
    }

    /// An error at this row's line of the file.
    pub fn line_error(&self, message: String) -> Error {
        parse_error(&self.table.path, self.line, message)
    }

    /// An error naming the file, the line, column `i` and its value, and
    /// what was `expected` there.
    pub fn error(&self, i: usize, expected: &str) -> Error {
        let name = self.table.header.get(i).map_or("?", String::as_str);
        parse_error(
            &self.table.path,
            self.line,
            format!("column `{name}` = {:?}: expected {expected}", self.field(i)),
        )
    }

    /// Column `i` as a number (`inf` and `NaN` included).
    pub fn number(&self, i: usize) -> Result<f64> {
        self.field(i).parse().map_err(|_| self.error(i, "a number"))
    }

    /// Column `i` as a finite number.
    pub fn finite(&self, i: usize) -> Result<f64> {
        self.field(i)
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| self.error(i, "a finite number"))
    }

    /// Column `i` as a finite number > 0.
    pub fn positive(&self, i: usize) -> Result<f64> {
        self.field(i)
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite() && *x > 0.0)
            .ok_or_else(|| self.error(i, "a finite number > 0"))
    }

    /// Column `i` as a whole number ≥ 0.
    pub fn integer(&self, i: usize) -> Result<u64> {
        self.field(i)
            .parse()
            .map_err(|_| self.error(i, "a whole number ≥ 0"))
    }

    /// Column `i` as a flag: `true`/`1` or `false`/`0`.
    pub fn boolean(&self, i: usize) -> Result<bool> {
        match self.field(i) {
            "true" | "1" => Ok(true),
            "false" | "0" => Ok(false),
            _ => Err(self.error(i, "true or false")),
        }
    }

    /// Column `i` as text that is not empty.
    pub fn text(&self, i: usize) -> Result<&str> {
        match self.field(i) {
            "" => Err(self.error(i, "a value")),
            s => Ok(s),
        }
    }
}

fn parse_error(path: &Path, line: usize, message: String) -> Error {
    Error::Parse {
        path: path.to_path_buf(),
        line,
        message,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::Param;
    use crate::solver::Friction;
    use std::cmp::Ordering;

    const HEADER: &str = "aspect,width,restitution,friction,mu_s,mu_k,pga,status,error\n";

    fn read(text: &str) -> Result<Vec<(bool, Result<Case>)>> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("outcomes.csv");
        std::fs::write(&path, text).unwrap();
        let (mut t, [_pga]) = Table::open(&path, ["pga"], "the test")?;
        let mut out = Vec::new();
        while let Some(row) = t.next_row()? {
            out.push((row.failed(), row.values().map(Case::from)));
        }
        Ok(out)
    }

    #[test]
    fn cases_and_failed_rows() {
        let rows = read(&format!(
            "{HEADER}4,0.5,0,inf,,,0.3,ok,\n 6 ,0.5,0.2,coulomb,0.7,inf,0.3,OK,\n\
             4,0.5,0,inf,,,0.3,failed,boom\n4,0.5,0,inf,,,0.3,ok,boom\n"
        ))
        .unwrap();
        let flags: Vec<bool> = rows.iter().map(|r| r.0).collect();
        assert_eq!(flags, [false, false, true, true]);
        let key = rows[1].1.as_ref().unwrap();
        assert_eq!(
            key.friction,
            Param::Fixed(Friction::Coulomb {
                mu_s: 0.7,
                mu_k: f64::INFINITY
            })
        );
        assert_eq!(key.to_string(), "H/B=6 2B=0.5 e=0.2 coulomb μs=0.7 μk=inf");
        assert_eq!(
            rows[0].1.as_ref().unwrap().to_string(),
            "H/B=4 2B=0.5 e=0 inf"
        );
        assert_eq!(
            key.total_cmp(rows[0].1.as_ref().unwrap()),
            Ordering::Greater
        );
    }

    #[test]
    fn bad_case_values_name_file_line_column_and_value() {
        for (row, column, value) in [
            ("0,0.5,0,inf,,,0.3,ok,", "aspect", "\"0\""),
            ("4,wide,0,inf,,,0.3,ok,", "width", "\"wide\""),
            ("4,0.5,NaN,inf,,,0.3,ok,", "restitution", "\"NaN\""),
            ("4,0.5,0,dry,,,0.3,ok,", "friction", "\"dry\""),
            ("4,0.5,0,coulomb,0.7,,0.3,ok,", "mu_k", "\"\""),
            ("4,0.5,0,inf,0.7,,0.3,ok,", "mu_s", "\"0.7\""),
        ] {
            let rows = read(&format!("{HEADER}4,0.5,0,inf,,,0.3,ok,\n{row}\n")).unwrap();
            let err = rows[1].1.as_ref().unwrap_err().to_string();
            assert!(err.contains("outcomes.csv:3:"), "{err}");
            assert!(err.contains(&format!("`{column}` = {value}")), "{err}");
        }
    }

    #[test]
    fn missing_columns_are_all_named() {
        let err = read("aspect,width\n4,0.5\n").err().unwrap().to_string();
        assert!(err.contains("outcomes.csv:1:"), "{err}");
        assert!(err.contains("`restitution`, `friction`"), "{err}");
        assert!(err.contains("`pga`") && err.contains("the test"), "{err}");
    }
}
