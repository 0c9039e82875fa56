//! The fitted fragility a risk integral needs: `fragility.csv` (θ, β per case
//! and limit state) and, if present, `fragility_bootstrap.csv` (each
//! bootstrap replicate's θ, β), read by header name.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::outcomes_csv::{CaseKey, OutcomesReader};

/// One row of `fragility.csv`: a case and limit state and its fit.
#[derive(Clone, Debug, PartialEq)]
pub struct FittedCurve {
    /// The block configuration.
    pub key: CaseKey,
    /// The limit state's name.
    pub limit_state: String,
    /// The IM the curve was fitted against (`pga`, `pgv`, `pga-over-tan`).
    pub im: String,
    /// Its unit (`g`, `m/s`, `1`).
    pub im_unit: String,
    /// (θ, β), `None` when the case could not be fitted.
    pub fit: Option<(f64, f64)>,
    /// `ok` or the fit's reason for having no curve.
    pub status: String,
    /// The (θ, β) of every fitted bootstrap replicate, in replicate order.
    pub replicates: Vec<(f64, f64)>,
    /// Bootstrap replicates that could not be fitted.
    pub replicates_unfit: usize,
}

/// A study's fitted fragility, as [`read_fragility`] found it.
#[derive(Clone, Debug, PartialEq)]
pub struct FittedFragility {
    /// `fragility.csv`.
    pub path: PathBuf,
    /// Its rows, in its order.
    pub curves: Vec<FittedCurve>,
    /// `fragility_bootstrap.csv`, if it exists.
    pub bootstrap: Option<PathBuf>,
}

impl FittedFragility {
    /// The IM of the fit (every row has the same: one fit writes one IM).
    pub fn im(&self) -> &str {
        self.curves.first().map_or("pga", |c| c.im.as_str())
    }

    /// The IM's unit.
    pub fn im_unit(&self) -> &str {
        self.curves.first().map_or("g", |c| c.im_unit.as_str())
    }
}

/// Reads `dir/fragility.csv` and, if it exists, `dir/fragility_bootstrap.csv`.
///
/// Errors: [`Error::Io`]; [`Error::Parse`] naming the file, line, column and
/// value of anything unreadable, a file without rows, or rows with
/// different IMs; [`Error::Conflict`] when the bootstrap file's rows do not
/// name the case and limit state of the `fragility.csv` row they point to
/// (it was written by another fit).
pub fn read_fragility(dir: &Path) -> Result<FittedFragility> {
    let path = dir.join("fragility.csv");
    let (mut table, [ls, im, median, beta, status]) = OutcomesReader::open(
        &path,
        ["limit_state", "im", "median", "beta", "status"],
        "the risk integral",
    )?;
    let unit = table.column("im_unit");
    let mut curves: Vec<FittedCurve> = Vec::new();
    while let Some(row) = table.next_row()? {
        let status_text = row.text(status)?.to_string();
        let fit = if status_text == "ok" {
            Some((row.positive(median)?, row.positive(beta)?))
        } else {
            None
        };
        let curve = FittedCurve {
            key: row.case()?,
            limit_state: row.text(ls)?.to_string(),
            im: row.text(im)?.to_string(),
            im_unit: unit.map_or("", |u| row.field(u)).to_string(),
            fit,
            status: status_text,
            replicates: Vec::new(),
            replicates_unfit: 0,
        };
        if let Some(first) = curves.first().filter(|c| c.im != curve.im) {
            return Err(row.error(
                im,
                &format!("the IM of the file's first row ({})", first.im),
            ));
        }
        curves.push(curve);
    }
    if curves.is_empty() {
        return Err(Error::Parse {
            path,
            line: 2,
            message: "no rows: fit the study first (rockfrag fragility DIR)".into(),
        });
    }
    let boot_path = dir.join("fragility_bootstrap.csv");
    let bootstrap = if boot_path.exists() {
        read_replicates(&boot_path, &mut curves)?;
        Some(boot_path)
    } else {
        None
    };
    Ok(FittedFragility {
        path,
        curves,
        bootstrap,
    })
}

/// Adds the replicates of `fragility_bootstrap.csv` to `curves`.
fn read_replicates(path: &Path, curves: &mut [FittedCurve]) -> Result<()> {
    let (mut table, [case, ls, median, beta, status]) = OutcomesReader::open(
        path,
        ["case", "limit_state", "median", "beta", "status"],
        "the risk integral's bootstrap band",
    )?;
    while let Some(row) = table.next_row()? {
        let i = row.integer(case)? as usize;
        let Some(curve) = curves.get_mut(i) else {
            return Err(row.error(
                case,
                &format!("a row of fragility.csv (0 to {})", curves.len() - 1),
            ));
        };
        if row.case()? != curve.key || row.field(ls) != curve.limit_state {
            return Err(Error::Conflict {
                path: path.to_path_buf(),
                message: format!(
                    "line {}: case {i} is {} {} here but {} {} in fragility.csv: the two \
                     files come from different fits; rerun rockfrag fragility",
                    row.line(),
                    row.case()?,
                    row.field(ls),
                    curve.key,
                    curve.limit_state
                ),
            });
        }
        if row.text(status)? == "ok" {
            curve
                .replicates
                .push((row.positive(median)?, row.positive(beta)?));
        } else {
            curve.replicates_unfit += 1;
        }
    }
    Ok(())
}
