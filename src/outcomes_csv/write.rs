//! Writing `outcomes.csv` rows: one per analysis, the columns of
//! [`Columns::list`] in its order (see the [format](super)).

use super::case::CaseKey;
use super::columns::Columns;
use crate::outcome::Outcome;
use crate::solver::Friction;
use std::fmt::Write;

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
    /// Appends the row of one analysis to `out`, with its newline: the
    /// columns of [`Columns::list`], in its order.
    pub fn write_row(
        &self,
        out: &mut String,
        case: &CaseKey,
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
        if self.scale {
            let _ = write!(w, "{},{},", opt(record.pga_g), opt(record.pgv));
        } else if self.pgv {
            let _ = write!(w, "{},{},", opt(record.pga_g), record.level);
        } else {
            let _ = write!(w, "{},{},", record.level, opt(record.pgv));
        }
        let _ = write!(w, "{},", record.index);
        if self.files {
            push_field(w, record.file.unwrap_or(""));
            w.push(',');
        }
        if self.scale {
            let _ = write!(w, "{},", record.level);
        }
        match result {
            Ok(o) => {
                w.push_str("ok");
                for column in self.outcome() {
                    w.push(',');
                    column.write_value(o, w);
                }
                w.push_str(",\n");
            }
            Err(message) => {
                w.push_str("failed");
                for _ in self.outcome() {
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

    fn case() -> CaseKey {
        CaseKey {
            aspect: 4.0,
            width: 0.5,
            restitution: 0.3,
            friction: Friction::Coulomb {
                mu_s: 0.7,
                mu_k: 0.6,
            },
        }
    }

    #[test]
    fn rows_have_as_many_fields_as_the_header() {
        for cols in [
            Columns {
                pgv: false,
                files: false,
                scale: false,
                time_in_mode: false,
                stats: false,
            },
            Columns {
                pgv: true,
                files: true,
                scale: true,
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
