//! Reading a study's `outcomes.csv` into cases: one block configuration with
//! its analyses, each at a stripe (PGA level) under one record.

use std::collections::HashMap;
use std::path::Path;

use super::IntensityMeasure;
use crate::error::{Error, Result};

/// One block configuration: what a fragility curve is fitted for.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseKey {
    /// Aspect ratio H/B.
    pub aspect: f64,
    /// Base width 2B (m).
    pub width: f64,
    /// Coefficient of restitution e.
    pub restitution: f64,
    /// Friction model, as in `outcomes.csv`: `inf` or `coulomb`.
    pub friction: String,
    /// Static friction coefficient μs (absent under infinite friction).
    pub mu_s: Option<f64>,
    /// Kinetic friction coefficient μk (absent under infinite friction).
    pub mu_k: Option<f64>,
}

impl std::fmt::Display for CaseKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "H/B={} 2B={} e={} {}",
            self.aspect, self.width, self.restitution, self.friction
        )?;
        if let Some(mu) = self.mu_s {
            write!(f, " μs={mu}")?;
        }
        if let Some(mu) = self.mu_k {
            write!(f, " μk={mu}")?;
        }
        Ok(())
    }
}

/// One successful analysis of a case.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Analysis {
    /// The record, as an index into [`CaseData::records`].
    pub record: usize,
    /// The stripe's PGA (g): analyses with the same PGA form a stripe.
    pub pga: f64,
    /// The intensity measure of this analysis (> 0, in the IM's unit).
    pub im: f64,
    /// Whether the block overturned.
    pub overturned: bool,
}

/// All analyses of one case.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseData {
    /// The block configuration.
    pub key: CaseKey,
    /// Record names as they appear in `outcomes.csv`, in order of first appearance.
    pub records: Vec<String>,
    /// The successful analyses.
    pub analyses: Vec<Analysis>,
    /// Rows of this case skipped because the analysis failed (`error` not
    /// empty or `status` not `ok`).
    pub failed: usize,
}

impl CaseData {
    /// Number of distinct records with at least one successful analysis.
    pub fn n_records(&self) -> usize {
        let mut seen = vec![false; self.records.len()];
        for a in &self.analyses {
            seen[a.record] = true;
        }
        seen.iter().filter(|&&s| s).count()
    }

    /// Number of stripes (distinct PGA levels) with at least one successful analysis.
    pub fn n_stripes(&self) -> usize {
        let mut levels: Vec<u64> = self.analyses.iter().map(|a| a.pga.to_bits()).collect();
        levels.sort_unstable();
        levels.dedup();
        levels.len()
    }
}

/// The cases of an `outcomes.csv`, in order of first appearance.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcomes {
    /// The intensity measure stored in [`Analysis::im`].
    pub im: IntensityMeasure,
    /// One entry per case.
    pub cases: Vec<CaseData>,
    /// Failed rows whose case could not be read (counted, not attributed).
    pub failed_unattributed: usize,
}

/// Columns needed for every intensity measure.
const REQUIRED: [&str; 9] = [
    "aspect",
    "width",
    "restitution",
    "friction",
    "mu_s",
    "mu_k",
    "pga",
    "record",
    "overturned",
];

/// Reads `outcomes.csv`, keeping what the fragility fit needs. Columns are
/// found by header name; unknown columns are ignored. A row whose `error`
/// column is not empty, or whose `status` column is present and not `ok`, is a
/// failed analysis: it is skipped and counted in [`CaseData::failed`].
pub fn read_outcomes(path: &Path, im: IntensityMeasure) -> Result<Outcomes> {
    let file = std::fs::File::open(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(std::io::BufReader::new(file));
    let parse_err = |line: usize, message: String| Error::Parse {
        path: path.to_path_buf(),
        line,
        message,
    };
    let headers = reader
        .headers()
        .map_err(|e| parse_err(1, format!("cannot read the header: {e}")))?
        .clone();
    let column = |name: &str| headers.iter().position(|h| h == name);
    let mut index = HashMap::new();
    for name in REQUIRED {
        let i = column(name).ok_or_else(|| {
            parse_err(
                1,
                format!("missing column `{name}` (needed for the fragility fit)"),
            )
        })?;
        index.insert(name, i);
    }
    let pgv = column("pgv");
    if im == IntensityMeasure::Pgv && pgv.is_none() {
        return Err(parse_err(
            1,
            "no `pgv` column, which the PGV intensity measure needs".into(),
        ));
    }
    let status = column("status");
    let error = column("error");

    let mut out = Outcomes {
        im,
        cases: Vec::new(),
        failed_unattributed: 0,
    };
    let mut case_index: HashMap<KeyBits, usize> = HashMap::new();
    let mut record_index: Vec<HashMap<String, usize>> = Vec::new();
    for row in reader.records() {
        let row = row.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line() as usize);
            parse_err(line, e.to_string())
        })?;
        let line = row.position().map_or(0, |p| p.line() as usize);
        let field = |name: &str| row.get(index[name]).unwrap_or("");
        let failed = status.is_some_and(|i| !row.get(i).unwrap_or("").eq_ignore_ascii_case("ok"))
            || error.is_some_and(|i| !row.get(i).unwrap_or("").is_empty());
        let key = match parse_key(field) {
            Ok(key) => key,
            Err(_) if failed => {
                out.failed_unattributed += 1;
                continue;
            }
            Err(message) => return Err(parse_err(line, message)),
        };
        let bits = KeyBits::of(&key);
        let c = *case_index.entry(bits).or_insert_with(|| {
            out.cases.push(CaseData {
                key,
                records: Vec::new(),
                analyses: Vec::new(),
                failed: 0,
            });
            record_index.push(HashMap::new());
            out.cases.len() - 1
        });
        let case = &mut out.cases[c];
        if failed {
            case.failed += 1;
            continue;
        }
        let pga = positive(field("pga"), "pga").map_err(|m| parse_err(line, m))?;
        let value = match im {
            IntensityMeasure::Pga => pga,
            IntensityMeasure::PgaOverTan => pga * case.key.aspect,
            IntensityMeasure::Pgv => {
                let text = pgv.and_then(|i| row.get(i)).unwrap_or("");
                positive(text, "pgv").map_err(|m| parse_err(line, m))?
            }
        };
        let overturned = match field("overturned") {
            "true" | "1" => true,
            "false" | "0" => false,
            other => {
                return Err(parse_err(
                    line,
                    format!("overturned = `{other}`: expected true or false"),
                ));
            }
        };
        let name = field("record");
        if name.is_empty() {
            return Err(parse_err(line, "empty `record`".into()));
        }
        let records = &mut case.records;
        let record = *record_index[c].entry(name.to_string()).or_insert_with(|| {
            records.push(name.to_string());
            records.len() - 1
        });
        case.analyses.push(Analysis {
            record,
            pga,
            im: value,
            overturned,
        });
    }
    Ok(out)
}

fn parse_key<'a>(field: impl Fn(&str) -> &'a str) -> std::result::Result<CaseKey, String> {
    let aspect = positive(field("aspect"), "aspect")?;
    let width = positive(field("width"), "width")?;
    let restitution = number(field("restitution"), "restitution")?;
    let friction = match field("friction") {
        f @ ("inf" | "coulomb") => f.to_string(),
        other => return Err(format!("friction = `{other}`: expected inf or coulomb")),
    };
    let optional = |name: &str| -> std::result::Result<Option<f64>, String> {
        match field(name) {
            "" => Ok(None),
            text => text
                .parse::<f64>()
                .ok()
                .filter(|x| !x.is_nan())
                .map(Some)
                .ok_or_else(|| format!("{name} = `{text}`: expected a number, inf or empty")),
        }
    };
    Ok(CaseKey {
        aspect,
        width,
        restitution,
        friction,
        mu_s: optional("mu_s")?,
        mu_k: optional("mu_k")?,
    })
}

fn number(text: &str, name: &str) -> std::result::Result<f64, String> {
    text.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| format!("{name} = `{text}`: expected a finite number"))
}

fn positive(text: &str, name: &str) -> std::result::Result<f64, String> {
    let x = number(text, name)?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err(format!("{name} = `{text}`: expected a number > 0"))
    }
}

/// Hashable identity of a case (bit patterns of its numbers).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct KeyBits([u64; 3], String, Option<u64>, Option<u64>);

impl KeyBits {
    fn of(k: &CaseKey) -> Self {
        // + 0.0 turns −0.0 into 0.0, so the two are one case.
        let bits = |x: f64| (x + 0.0).to_bits();
        KeyBits(
            [bits(k.aspect), bits(k.width), bits(k.restitution)],
            k.friction.clone(),
            k.mu_s.map(bits),
            k.mu_k.map(bits),
        )
    }
}
