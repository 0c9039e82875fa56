//! The fitted fragility a risk integral needs: `fragility.csv` (θ, β per case
//! and limit state) and, if present, `fragility_bootstrap.csv` (each
//! bootstrap replicate's θ, β), read through their row types
//! ([`FragilityRow`], [`crate::fragility::BootstrapRow`]).

use std::path::{Path, PathBuf};

use crate::case::Case;
use crate::error::{Error, Result};
use crate::fragility::{FitStatus, FragilityRow, read_bootstrap_csv, read_fragility_csv};
use crate::im::Im;

/// One row of `fragility.csv`: a case and limit state and its fit.
#[derive(Clone, Debug, PartialEq)]
pub struct FittedCurve {
    /// The case.
    pub key: Case,
    /// The limit state's name.
    pub limit_state: String,
    /// The IM the curve was fitted against.
    pub im: Im,
    /// (θ, β), `None` when the case could not be fitted.
    pub fit: Option<(f64, f64)>,
    /// `ok`, a caveat, or the fit's reason for having no curve.
    pub status: FitStatus,
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
    pub fn im(&self) -> Im {
        self.curves.first().map_or(Im::PGA, |c| c.im)
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
    if !path.exists() {
        // An unfinished run or another folder: say so, not "No such file".
        crate::study::require_finished(dir)?;
    }
    crate::fragility::check_set(dir)?;
    let rows = read_fragility_csv(&path)?;
    let Some(first) = rows.first() else {
        return Err(Error::Parse {
            path,
            line: 2,
            message: "no rows: fit the study first (rockfrag fragility DIR)".into(),
        });
    };
    if let Some((i, other)) = rows.iter().enumerate().find(|(_, r)| r.im != first.im) {
        return Err(Error::Parse {
            path,
            line: i + 2,
            message: format!(
                "column `im` = {:?}: expected the IM of the file's first row ({})",
                other.im.name(),
                first.im.name()
            ),
        });
    }
    let mut curves: Vec<FittedCurve> = rows.iter().map(FittedCurve::from_row).collect();
    let boot_path = dir.join("fragility_bootstrap.csv");
    let bootstrap = if boot_path.exists() {
        for (b, line) in read_bootstrap_csv(&boot_path)?.into_iter().zip(2usize..) {
            let Some(curve) = curves.get_mut(b.index) else {
                return Err(Error::Parse {
                    path: boot_path.clone(),
                    line,
                    message: format!(
                        "column `case` = \"{}\": expected a row of fragility.csv (0 to {})",
                        b.index,
                        rows.len() - 1
                    ),
                });
            };
            if b.case != curve.key || b.limit_state != curve.limit_state || b.im != curve.im {
                return Err(Error::Conflict {
                    path: boot_path.clone(),
                    message: format!(
                        "line {line}: case {} is {} {} ({}) here but {} {} ({}) in fragility.csv: \
                         the two files come from different fits; rerun rockfrag fragility",
                        b.index,
                        b.case,
                        b.limit_state,
                        b.im,
                        curve.key,
                        curve.limit_state,
                        curve.im
                    ),
                });
            }
            match b.fit {
                Ok(fit) => curve.replicates.push(fit),
                Err(_) => curve.replicates_unfit += 1,
            }
        }
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

impl FittedCurve {
    /// The curve of a `fragility.csv` row, without its replicates.
    pub fn from_row(row: &FragilityRow) -> FittedCurve {
        FittedCurve {
            key: row.case,
            limit_state: row.limit_state.clone(),
            im: row.im,
            fit: row.fit(),
            status: row.status,
            replicates: Vec::new(),
            replicates_unfit: 0,
        }
    }
}
