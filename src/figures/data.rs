//! The study results the figures read: `outcomes.csv` (one row per analysis)
//! and, optionally, `fragility_curves.csv` (fitted curves with their band).
//!
//! Both are read with [`OutcomesReader`] (columns by header name, the case
//! columns as a [`CaseKey`]); failed analyses are skipped, having no
//! outcome. Rows are sorted once after reading, so every figure sees the
//! same order whatever order the study (or a merge of its shards) wrote them
//! in, and the figures are byte-identical.

use std::path::Path;

use crate::error::Result;
pub use crate::outcomes_csv::same;
use crate::outcomes_csv::{CaseKey, Column, OutcomesReader, Pooled, cmp_friction, same_friction};
use crate::solver::Friction;

/// One analysis as the figures need it: the case, the intensity and the
/// outcome quantities that are plotted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutcomeRow {
    /// The block and its contact (aspect, width, e, friction).
    pub case: CaseKey,
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
    /// Peak of the paper's eq. (5) over impacts; `None` for a file written
    /// before the column existed.
    pub mu_impact_eq5: Option<f64>,
    /// Number of corner impacts.
    pub impacts: u64,
}

/// One point of a fitted fragility curve.
#[derive(Clone, Debug, PartialEq)]
pub struct CurvePoint {
    /// The block and its contact.
    pub case: CaseKey,
    /// The limit state (`overturning` for a file without a `limit_state`
    /// column, which predates limit states).
    pub limit_state: String,
    /// Intensity measure, PGA (g).
    pub im: f64,
    /// Fitted probability of overturning.
    pub p: f64,
    /// Lower bound of the 90 % band.
    pub p_lo: f64,
    /// Upper bound of the 90 % band.
    pub p_hi: f64,
}

/// A friction model for legends: `μ = ∞` or `μₛ = 0.7, μₖ = 0.6` (`μₛ, μₖ
/// drawn` when drawn per analysis).
pub fn friction_label(f: &Friction) -> String {
    match *f {
        Friction::Infinite => "μ = ∞".to_string(),
        Friction::Coulomb { mu_s, .. } if mu_s.is_nan() => "μₛ, μₖ drawn".to_string(),
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
        StudyData::load_pooled(dir, Pooled::default())
    }

    /// As [`StudyData::load`], with each analysis in the case that pools
    /// the parameters `pooled` (those the study draws per analysis).
    pub fn load_pooled(dir: &Path, pooled: Pooled) -> Result<StudyData> {
        let mut outcomes = read_outcomes(&dir.join("outcomes.csv"))?;
        if pooled.any() {
            for row in &mut outcomes {
                row.case = row.case.pooled(pooled);
            }
            outcomes.sort_by(|a, b| {
                a.case
                    .total_cmp(&b.case)
                    .then(a.pga.total_cmp(&b.pga))
                    .then(a.record.cmp(&b.record))
            });
        }
        let curves_path = dir.join("fragility_curves.csv");
        let curves = if curves_path.exists() {
            Some(read_fragility_curves(&curves_path)?)
        } else {
            None
        };
        Ok(StudyData { outcomes, curves })
    }
}

/// Reads `outcomes.csv` with [`OutcomesReader`]; skips failed rows; returns
/// the rows sorted by case, PGA and record.
///
/// Errors: [`Error::Io`](crate::Error::Io) if the file cannot be read,
/// [`Error::Parse`](crate::Error::Parse) naming the line for a missing
/// column, or the line, column and value for an unreadable value.
pub fn read_outcomes(path: &Path) -> Result<Vec<OutcomeRow>> {
    let (
        mut table,
        [
            pga,
            record,
            overturned,
            uplifted,
            theta,
            mu_mot,
            mu_imp,
            impacts,
        ],
    ) = OutcomesReader::open(
        path,
        [
            Column::Pga,
            Column::Record,
            Column::Overturned,
            Column::Uplifted,
            Column::ThetaMaxOverThetaC,
            Column::MuMotion,
            Column::MuImpact,
            Column::Impacts,
        ],
        "the figures",
    )?;
    // optional: files written before the column existed lack it
    let mu_eq5 = table.column(Column::MuImpactEq5);
    let mut rows = Vec::new();
    while let Some(row) = table.next_row()? {
        if row.failed() {
            continue;
        }
        rows.push(OutcomeRow {
            case: row.case()?,
            pga: row.number(pga)?,
            record: row.integer(record)?,
            overturned: row.boolean(overturned)?,
            uplifted: row.boolean(uplifted)?,
            theta_max_over_theta_c: row.number(theta)?,
            mu_motion: row.number(mu_mot)?,
            mu_impact: row.number(mu_imp)?,
            mu_impact_eq5: mu_eq5.map(|i| row.number(i)).transpose()?,
            impacts: row.integer(impacts)?,
        });
    }
    rows.sort_by(|a, b| {
        a.case
            .total_cmp(&b.case)
            .then(a.pga.total_cmp(&b.pga))
            .then(a.record.cmp(&b.record))
    });
    Ok(rows)
}

/// Reads `fragility_curves.csv` (as written by [`crate::fragility`]) by
/// header name (the case columns and `im, im_value, p, p_lo, p_hi`): the
/// fitted probability and its 90 % band on an IM grid. Only curves fitted
/// against PGA (`im` = `pga`) are kept, since the figure draws them over the
/// PGA stripes; an empty band (no bootstrap) reads as the curve itself.
/// Returns the points sorted by case, limit state (in the file's order:
/// a case's limit states in order of severity) and IM.
///
/// This is the one place that reads the fragility file's layout.
pub fn read_fragility_curves(path: &Path) -> Result<Vec<CurvePoint>> {
    let (mut table, [im_name, im, p, lo, hi]) = OutcomesReader::open(
        path,
        ["im", "im_value", "p", "p_lo", "p_hi"],
        "the fragility figure",
    )?;
    let limit_state = table.column("limit_state");
    let mut points = Vec::new();
    while let Some(row) = table.next_row()? {
        if row.field(im_name) != "pga" {
            continue;
        }
        let p = row.number(p)?;
        let band = |i: usize| {
            if row.field(i).is_empty() {
                Ok(p)
            } else {
                row.number(i)
            }
        };
        points.push(CurvePoint {
            case: row.case()?,
            limit_state: limit_state
                .map_or("overturning", |i| row.field(i))
                .to_string(),
            im: row.number(im)?,
            p,
            p_lo: band(lo)?,
            p_hi: band(hi)?,
        });
    }
    // Limit states keep the file's order (a case's, in order of severity).
    let mut order: Vec<String> = Vec::new();
    for p in &points {
        if !order.contains(&p.limit_state) {
            order.push(p.limit_state.clone());
        }
    }
    let rank = |ls: &str| order.iter().position(|o| o == ls);
    points.sort_by(|a, b| {
        a.case
            .total_cmp(&b.case)
            .then_with(|| rank(&a.limit_state).cmp(&rank(&b.limit_state)))
            .then(a.im.total_cmp(&b.im))
    });
    Ok(points)
}

/// The distinct values of `values`, sorted (values equal as `f64` are one,
/// and so are NaNs: the placeholder of a drawn parameter).
pub fn distinct(values: impl IntoIterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = values.into_iter().collect();
    v.sort_by(f64::total_cmp);
    v.dedup_by(|a, b| same(*a, *b));
    v
}

/// The distinct friction models of `values`, infinite first.
pub fn distinct_friction(values: impl IntoIterator<Item = Friction>) -> Vec<Friction> {
    let mut v: Vec<Friction> = values.into_iter().collect();
    v.sort_by(cmp_friction);
    v.dedup_by(|a, b| same_friction(a, b));
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
        // a file from before the eq. (5) column reads, without it
        assert!(rows.iter().all(|r| r.mu_impact_eq5.is_none()));
    }
}
