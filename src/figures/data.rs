//! The study results the figures read: `outcomes.csv` (one row per analysis)
//! and, optionally, `fragility_curves.csv` (fitted curves with their band).
//!
//! Columns are found by header name, so column order and extra columns do
//! not matter. Rows whose `status` column (when present) is not `ok` are
//! skipped: a failed analysis has no outcome. Rows are sorted once after
//! reading, so every figure sees the same order whatever order the study (or
//! a merge of its shards) wrote them in, and the figures are byte-identical.

use std::cmp::Ordering;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::solver::Friction;

/// One analysis as the figures need it: the case, the intensity and the
/// outcome quantities that are plotted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutcomeRow {
    /// The block and its contact (aspect, width, e, friction).
    pub case: Case,
    /// Peak ground acceleration of the record (g).
    pub pga: f64,
    /// Record index in the ensemble.
    pub record: u64,
    /// |θ| reached π/2.
    pub overturned: bool,
    /// N reached 0 during rock at least once (the paper stopped such runs).
    pub uplifted: bool,
    /// Peak |θ|/θc.
    pub theta_max_over_theta_c: f64,
    /// Peak |F|/N while rocking, μ_mot (0 if the block never rocked).
    pub mu_motion: f64,
    /// Peak |P_t/P_n| over impacts, μ_imp (meaningless if `impacts` is 0).
    pub mu_impact: f64,
    /// Number of corner impacts.
    pub impacts: u64,
}

/// One point of a fitted fragility curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvePoint {
    /// The block and its contact.
    pub case: Case,
    /// Intensity measure, PGA (g).
    pub im: f64,
    /// Fitted probability of overturning.
    pub p: f64,
    /// Lower bound of the 90 % band.
    pub p_lo: f64,
    /// Upper bound of the 90 % band.
    pub p_hi: f64,
}

/// A block with its contact properties: what one curve or one series is
/// drawn for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Case {
    /// Aspect ratio H/B.
    pub aspect: f64,
    /// Base width 2B (m).
    pub width: f64,
    /// Coefficient of restitution e.
    pub restitution: f64,
    /// Friction model.
    pub friction: Friction,
}

impl Case {
    /// Total order: aspect, width, restitution, then friction (infinite
    /// first, then Coulomb by μs, μk).
    pub fn cmp_key(&self, other: &Case) -> Ordering {
        self.aspect
            .total_cmp(&other.aspect)
            .then(self.width.total_cmp(&other.width))
            .then(self.restitution.total_cmp(&other.restitution))
            .then(cmp_friction(&self.friction, &other.friction))
    }
}

/// Total order on friction models: infinite first, then Coulomb by (μs, μk).
pub fn cmp_friction(a: &Friction, b: &Friction) -> Ordering {
    let key = |f: &Friction| match *f {
        Friction::Infinite => (0, 0.0, 0.0),
        Friction::Coulomb { mu_s, mu_k } => (1, mu_s, mu_k),
    };
    let (ka, kb) = (key(a), key(b));
    ka.0.cmp(&kb.0)
        .then(ka.1.total_cmp(&kb.1))
        .then(ka.2.total_cmp(&kb.2))
}

/// A friction model for legends: `μ = ∞` or `μₛ = 0.7, μₖ = 0.6`.
pub fn friction_label(f: &Friction) -> String {
    match *f {
        Friction::Infinite => "μ = ∞".to_string(),
        Friction::Coulomb { mu_s, mu_k } => format!(
            "μₛ = {}, μₖ = {}",
            super::style::tick_label(mu_s),
            super::style::tick_label(mu_k)
        ),
    }
}

/// What the figures read from a study folder.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StudyData {
    /// Successful analyses, sorted by case, PGA and record.
    pub outcomes: Vec<OutcomeRow>,
    /// Fitted fragility curves, sorted by case and IM; `None` when the folder
    /// has no `fragility_curves.csv`.
    pub curves: Option<Vec<CurvePoint>>,
}

impl StudyData {
    /// Reads `dir/outcomes.csv` and, if present, `dir/fragility_curves.csv`.
    pub fn load(dir: &Path) -> Result<StudyData> {
        let outcomes = read_outcomes(&dir.join("outcomes.csv"))?;
        let curves_path = dir.join("fragility_curves.csv");
        let curves = if curves_path.exists() {
            Some(read_fragility_curves(&curves_path)?)
        } else {
            None
        };
        Ok(StudyData { outcomes, curves })
    }
}

/// Reads `outcomes.csv` by header name; skips rows whose `status` is not
/// `ok`; returns the rows sorted by case, PGA and record.
///
/// Errors: [`Error::Io`] if the file cannot be read, [`Error::Parse`] naming
/// the line for a missing column or an unreadable value.
pub fn read_outcomes(path: &Path) -> Result<Vec<OutcomeRow>> {
    let mut table = Table::open(path)?;
    let status = table.optional("status");
    let [
        aspect,
        width,
        restitution,
        friction,
        mu_s,
        mu_k,
        pga,
        record,
        overturned,
        uplifted,
        theta,
        mu_mot,
        mu_imp,
        impacts,
    ] = table.columns([
        "aspect",
        "width",
        "restitution",
        "friction",
        "mu_s",
        "mu_k",
        "pga",
        "record",
        "overturned",
        "uplifted",
        "theta_max_over_theta_c",
        "mu_motion",
        "mu_impact",
        "impacts",
    ])?;
    let case_cols = CaseColumns {
        aspect,
        width,
        restitution,
        friction,
        mu_s,
        mu_k,
    };
    let mut rows = Vec::new();
    while let Some(rec) = table.next_record()? {
        if let Some(s) = status
            && rec.field(s).trim() != "ok"
        {
            continue;
        }
        rows.push(OutcomeRow {
            case: rec.case(&case_cols)?,
            pga: rec.number(pga)?,
            record: rec.integer(record)?,
            overturned: rec.boolean(overturned)?,
            uplifted: rec.boolean(uplifted)?,
            theta_max_over_theta_c: rec.number(theta)?,
            mu_motion: rec.number(mu_mot)?,
            mu_impact: rec.number(mu_imp)?,
            impacts: rec.integer(impacts)?,
        });
    }
    rows.sort_by(|a, b| {
        a.case
            .cmp_key(&b.case)
            .then(a.pga.total_cmp(&b.pga))
            .then(a.record.cmp(&b.record))
    });
    Ok(rows)
}

/// Reads `fragility_curves.csv` (as written by [`crate::fragility`]) by
/// header name (`aspect, width, restitution, friction, mu_s, mu_k, im,
/// im_value, p, p_lo, p_hi`): the fitted probability and its 90 % band on an
/// IM grid. Only curves fitted against PGA (`im` = `pga`) are kept, since the
/// figure draws them over the PGA stripes; an empty band (no bootstrap) reads
/// as the curve itself. Returns the points sorted by case and IM.
///
/// This is the one place that knows the fragility file's layout.
pub fn read_fragility_curves(path: &Path) -> Result<Vec<CurvePoint>> {
    let mut table = Table::open(path)?;
    let [
        aspect,
        width,
        restitution,
        friction,
        mu_s,
        mu_k,
        im_name,
        im,
        p,
        lo,
        hi,
    ] = table.columns([
        "aspect",
        "width",
        "restitution",
        "friction",
        "mu_s",
        "mu_k",
        "im",
        "im_value",
        "p",
        "p_lo",
        "p_hi",
    ])?;
    let case_cols = CaseColumns {
        aspect,
        width,
        restitution,
        friction,
        mu_s,
        mu_k,
    };
    let mut points = Vec::new();
    while let Some(rec) = table.next_record()? {
        if rec.field(im_name).trim() != "pga" {
            continue;
        }
        let p = rec.number(p)?;
        let band = |i: usize| {
            if rec.field(i).trim().is_empty() {
                Ok(p)
            } else {
                rec.number(i)
            }
        };
        points.push(CurvePoint {
            case: rec.case(&case_cols)?,
            im: rec.number(im)?,
            p,
            p_lo: band(lo)?,
            p_hi: band(hi)?,
        });
    }
    points.sort_by(|a, b| a.case.cmp_key(&b.case).then(a.im.total_cmp(&b.im)));
    Ok(points)
}

/// Column indices of the case columns.
struct CaseColumns {
    aspect: usize,
    width: usize,
    restitution: usize,
    friction: usize,
    mu_s: usize,
    mu_k: usize,
}

/// A CSV file with a header, read record by record with line numbers for
/// errors.
struct Table {
    path: PathBuf,
    reader: csv::Reader<std::fs::File>,
    columns: HashMap<String, usize>,
    record: csv::StringRecord,
}

/// One record of a [`Table`].
struct Row<'a> {
    path: &'a Path,
    line: usize,
    record: &'a csv::StringRecord,
    header: &'a HashMap<String, usize>,
}

impl Table {
    fn open(path: &Path) -> Result<Table> {
        let file = std::fs::File::open(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let mut reader = csv::ReaderBuilder::new().flexible(false).from_reader(file);
        let headers = reader
            .headers()
            .map_err(|e| parse_error(path, 1, e.to_string()))?;
        let columns = headers
            .iter()
            .enumerate()
            .map(|(i, h)| (h.trim().to_string(), i))
            .collect();
        Ok(Table {
            path: path.to_path_buf(),
            reader,
            columns,
            record: csv::StringRecord::new(),
        })
    }

    fn optional(&self, name: &str) -> Option<usize> {
        self.columns.get(name).copied()
    }

    /// The indices of `names`; an error listing every missing one.
    fn columns<const N: usize>(&self, names: [&str; N]) -> Result<[usize; N]> {
        let missing: Vec<String> = names
            .iter()
            .filter(|n| self.optional(n).is_none())
            .map(|n| format!("`{n}`"))
            .collect();
        if !missing.is_empty() {
            return Err(parse_error(
                &self.path,
                1,
                format!("no column {} in the header", missing.join(", ")),
            ));
        }
        Ok(names.map(|n| self.optional(n).expect("checked above")))
    }

    fn next_record(&mut self) -> Result<Option<Row<'_>>> {
        match self.reader.read_record(&mut self.record) {
            Ok(false) => Ok(None),
            Ok(true) => Ok(Some(Row {
                path: &self.path,
                line: self.record.position().map_or(0, |p| p.line() as usize),
                record: &self.record,
                header: &self.columns,
            })),
            Err(e) => {
                let line = e.position().map_or(0, |p| p.line() as usize);
                Err(parse_error(&self.path, line, e.to_string()))
            }
        }
    }
}

impl Row<'_> {
    fn field(&self, i: usize) -> &str {
        self.record.get(i).unwrap_or("")
    }

    fn name(&self, i: usize) -> &str {
        self.header
            .iter()
            .find(|&(_, &j)| j == i)
            .map_or("?", |(n, _)| n.as_str())
    }

    fn error(&self, i: usize, expected: &str) -> Error {
        parse_error(
            self.path,
            self.line,
            format!(
                "column `{}` = {:?}: expected {expected}",
                self.name(i),
                self.field(i)
            ),
        )
    }

    fn number(&self, i: usize) -> Result<f64> {
        match self.field(i).trim() {
            "inf" => Ok(f64::INFINITY),
            s => s.parse().map_err(|_| self.error(i, "a number")),
        }
    }

    fn integer(&self, i: usize) -> Result<u64> {
        self.field(i)
            .trim()
            .parse()
            .map_err(|_| self.error(i, "a whole number ≥ 0"))
    }

    fn boolean(&self, i: usize) -> Result<bool> {
        match self.field(i).trim() {
            "true" => Ok(true),
            "false" => Ok(false),
            _ => Err(self.error(i, "true or false")),
        }
    }

    fn case(&self, c: &CaseColumns) -> Result<Case> {
        let friction = match self.field(c.friction).trim() {
            "inf" => Friction::Infinite,
            "coulomb" => Friction::Coulomb {
                mu_s: self.number(c.mu_s)?,
                mu_k: self.number(c.mu_k)?,
            },
            _ => return Err(self.error(c.friction, "inf or coulomb")),
        };
        Ok(Case {
            aspect: self.number(c.aspect)?,
            width: self.number(c.width)?,
            restitution: self.number(c.restitution)?,
            friction,
        })
    }
}

fn parse_error(path: &Path, line: usize, message: String) -> Error {
    Error::Parse {
        path: path.to_path_buf(),
        line,
        message,
    }
}

/// The distinct values of `values`, sorted (values equal as `f64` are one).
pub fn distinct(values: impl IntoIterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = values.into_iter().collect();
    v.sort_by(f64::total_cmp);
    v.dedup();
    v
}

/// The distinct friction models of `values`, infinite first.
pub fn distinct_friction(values: impl IntoIterator<Item = Friction>) -> Vec<Friction> {
    let mut v: Vec<Friction> = values.into_iter().collect();
    v.sort_by(cmp_friction);
    v.dedup();
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_by_header_name_skips_failed_rows_and_sorts() {
        // Columns in any order, unknown columns ignored, failed rows skipped,
        // rows sorted whatever order they came in.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("outcomes.csv");
        std::fs::write(
            &path,
            "extra,record,pga,aspect,width,restitution,friction,mu_s,mu_k,status,overturned,\
             uplifted,theta_max_over_theta_c,mu_motion,mu_impact,impacts,error\n\
             x,1,0.6,4,0.5,0,coulomb,0.7,0.6,ok,true,false,2.5,0.3,0.2,4,\n\
             x,0,0.6,4,0.5,0,inf,,,failed,,,,,,,boom\n\
             x,0,0.6,4,0.5,0,inf,,,ok,false,true,0.5,0.3,0.185,12,\n",
        )
        .unwrap();
        let rows = read_outcomes(&path).unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].case.friction, Friction::Infinite);
        assert!(rows[0].uplifted && !rows[0].overturned);
        assert_eq!(
            rows[1].case.friction,
            Friction::Coulomb {
                mu_s: 0.7,
                mu_k: 0.6
            }
        );
        assert_eq!(rows[1].impacts, 4);
    }

    #[test]
    fn a_missing_column_is_named() {
        // The error names the file, line 1 and every missing column.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("outcomes.csv");
        std::fs::write(&path, "aspect,width\n4,0.5\n").unwrap();
        let err = read_outcomes(&path).unwrap_err().to_string();
        assert!(err.contains("outcomes.csv:1:"), "{err}");
        assert!(err.contains("`restitution`, `friction`"), "{err}");
        assert!(err.contains("`pga`"), "{err}");
    }
}
