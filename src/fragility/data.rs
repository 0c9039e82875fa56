//! Reading a study's `outcomes.csv` into cases: one block configuration with
//! its analyses, each at a stripe (PGA level) under one record.

use std::collections::HashMap;
use std::path::Path;

use super::fit::Observation;
use super::options::{FragilityOptions, LimitState, RecordIms};
use crate::case::{Case, Field};
use crate::error::{Error, Result};
use crate::im::{At, Im, Measure};
use crate::outcomes_csv::{Column, MeasureKind, OutcomesFile};

/// One successful analysis of a case, as the fit sees it: a binomial trial
/// at its intensity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trial {
    /// The record, as an index into [`CaseData::records`].
    pub record: usize,
    /// The intensity level the analysis was run at, in the levels' own
    /// measure (PGA or PGV, a pair's RotD50, or a scale factor): analyses
    /// with the same level form a stripe ([`level_column`]).
    pub level: f64,
    /// The intensity measure of this analysis (> 0, in the IM's unit).
    pub im: f64,
    /// Whether the block overturned.
    pub overturned: bool,
    /// Which limit states the analysis exceeded: bit k for limit state k of
    /// [`Outcomes::limit_states`] (overturning alone: bit 0 = `overturned`).
    pub exceeded: u64,
}

impl Trial {
    /// Whether the analysis exceeded limit state `k`.
    pub fn exceeds(&self, k: usize) -> bool {
        self.exceeded >> k & 1 == 1
    }
}

/// All analyses of one case.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseData {
    /// The case (drawn or pooled parameters marked drawn).
    pub key: Case,
    /// Record names as they appear in `outcomes.csv`, in order of first appearance.
    pub records: Vec<String>,
    /// The successful analyses.
    pub trials: Vec<Trial>,
    /// Rows of this case skipped because the analysis failed (`error` not
    /// empty or `status` not `ok`).
    pub failed: usize,
}

impl CaseData {
    /// Number of distinct records with at least one successful analysis.
    pub fn n_records(&self) -> usize {
        let mut seen = vec![false; self.records.len()];
        for a in &self.trials {
            seen[a.record] = true;
        }
        seen.iter().filter(|&&s| s).count()
    }

    /// The analyses grouped by equal intensity, in increasing intensity:
    /// trials and exceedances of limit state `k` at each (what is fitted).
    pub fn observations(&self, k: usize) -> Vec<Observation> {
        let mut sorted = self.trials.clone();
        sorted.sort_by(|x, y| x.im.total_cmp(&y.im));
        let mut observations: Vec<Observation> = Vec::new();
        for a in &sorted {
            let exceeded = u64::from(a.exceeds(k));
            match observations.last_mut() {
                Some(o) if o.im == a.im => {
                    o.trials += 1;
                    o.overturned += exceeded;
                }
                _ => observations.push(Observation {
                    im: a.im,
                    trials: 1,
                    overturned: exceeded,
                }),
            }
        }
        observations
    }

    /// Number of stripes (distinct intensity levels, [`Trial::level`]) with
    /// at least one successful analysis.
    pub fn n_stripes(&self) -> usize {
        let mut levels: Vec<u64> = self.trials.iter().map(|a| a.level.to_bits()).collect();
        levels.sort_unstable();
        levels.dedup();
        levels.len()
    }
}

/// The cases of an `outcomes.csv`, in order of first appearance.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcomes {
    /// The intensity measure stored in [`Trial::im`].
    pub im: Im,
    /// The limit states whose exceedance [`Trial::exceeded`] records, in
    /// order of increasing severity.
    pub limit_states: Vec<LimitState>,
    /// One entry per case.
    pub cases: Vec<CaseData>,
}

/// Reads `outcomes.csv` ([`OutcomesFile`]), keeping what the fragility fit
/// needs: `pga`, `record`, `overturned` (and `pgv` for the PGV intensity
/// measure). A failed analysis is skipped and counted in
/// [`CaseData::failed`].
pub fn read_outcomes(path: &Path, im: Im) -> Result<Outcomes> {
    let options = FragilityOptions::default();
    let measured = measured_for(&options, im)?;
    read_outcomes_with(path, im, &[LimitState::overturning()], &[], measured)
}

/// The measured values of `im` in `options`, when it is an IM
/// `outcomes.csv` does not hold; `None` for the others. Errors: none given.
fn measured_for(options: &FragilityOptions, im: Im) -> Result<Option<&RecordIms>> {
    if im.stored() || !im.of_record() {
        return Ok(None);
    }
    match options.measured_of(im) {
        Some(m) => Ok(Some(m)),
        None => Err(Error::invalid(
            "im",
            im,
            &format!(
                "an IM outcomes.csv holds ({}, pga-over-tan): {im} is measured on the records \
                 again, which needs the study folder (rockfrag fragility DIR --im, or \
                 Python's fragility on the folder)",
                Im::COLUMNS.map(Im::name).join(", ")
            ),
        )),
    }
}

/// Reads `outcomes.csv` for the intensity measure and limit states of
/// `options` (see [`read_outcomes`]). An analysis exceeds a limit state when
/// it overturned or its measure is above the threshold (a yes/no measure:
/// is yes); an empty numeric field (e.g. a time that did not occur) is not
/// above any threshold.
pub fn read_outcomes_for(path: &Path, options: &FragilityOptions) -> Result<Outcomes> {
    options.validate()?;
    let measured = measured_for(options, options.im())?;
    read_outcomes_with(
        path,
        options.im(),
        &options.limit_states(),
        &options.pool,
        measured,
    )
}

fn read_outcomes_with(
    path: &Path,
    im: Im,
    limit_states: &[LimitState],
    pool: &[Field],
    measured: Option<&RecordIms>,
) -> Result<Outcomes> {
    let pga_column = Column::Im(Im::PGA);
    let mut required = vec![pga_column, Column::Record, Column::Overturned];
    let im_column = Column::of_im(im);
    if let Some(c) = im_column.filter(|&c| c != pga_column) {
        required.push(c);
    }
    if let Some(m) = measured.filter(|m| !required.contains(&m.level_column)) {
        required.push(m.level_column);
    }
    // The column and kind of each limit state's measure.
    let mut measures = Vec::with_capacity(limit_states.len());
    for ls in limit_states {
        let Some((column, kind)) = ls.column() else {
            return Err(Error::invalid(
                "fragility.limit_state.measure",
                &ls.measure,
                "a numeric or yes/no column of outcomes.csv",
            ));
        };
        measures.push((column, kind, ls.exceeds.unwrap_or(0.0)));
    }
    let purpose = match im.at() {
        At::RotD50 => {
            format!("the fragility fit against {im}, which only studies of record pairs have")
        }
        At::Floor => format!(
            "the fragility fit against {im}, which only studies on a floor ([support]) have"
        ),
        At::Ground => "the fragility fit".to_string(),
    };
    let mut table = OutcomesFile::open(path, &required, &purpose)?;
    for (ls, &(column, _, _)) in limit_states.iter().zip(&measures) {
        if !table.has(column) {
            return Err(table.header_error(format!(
                "no `{}` column, which limit state {:?} needs",
                ls.measure, ls.name
            )));
        }
    }

    let mut out = Outcomes {
        im,
        limit_states: limit_states.to_vec(),
        cases: Vec::new(),
    };
    // Each trial's candidates for its level (see `level_column`), kept
    // beside the trials until the column is known.
    let candidates = level_candidates(&table);
    let mut levels: Vec<Vec<[Option<f64>; 2]>> = Vec::new();
    let mut case_index: HashMap<Case, usize> = HashMap::new();
    let mut record_index: Vec<HashMap<String, usize>> = Vec::new();
    while let Some((line, row)) = table.next_row()? {
        // The analysis's own parameters, and the case it pools into.
        let own = row.case;
        let key = own.pooled(pool);
        let c = *case_index.entry(key).or_insert_with(|| {
            out.cases.push(CaseData {
                key,
                records: Vec::new(),
                trials: Vec::new(),
                failed: 0,
            });
            record_index.push(HashMap::new());
            levels.push(Vec::new());
            out.cases.len() - 1
        });
        let case = &mut out.cases[c];
        let Ok(outcome) = &row.result else {
            case.failed += 1;
            continue;
        };
        let positive = |x: Option<f64>, column: Column| {
            x.filter(|v| v.is_finite() && *v > 0.0).ok_or_else(|| {
                table.error_at(
                    line,
                    format!("column `{column}`: expected a finite number > 0"),
                )
            })
        };
        let pga = positive(row.im(Im::PGA), pga_column)?;
        let value = match (im.measure(), im_column) {
            (Measure::PgaOverTan, _) => pga * own.aspect,
            (_, Some(c)) => positive(row.intensity(c), c)?,
            (_, None) => {
                let m = measured.expect("an IM without a column is measured on the records");
                let level = positive(row.intensity(m.level_column), m.level_column)?;
                m.get(level, row.record).ok_or_else(|| {
                    table.error_at(
                        line,
                        format!("record {} at level {level} was not measured", row.record),
                    )
                })?
            }
        };
        let mut exceeded = 0u64;
        for (k, &(column, kind, threshold)) in measures.iter().enumerate() {
            // a body's limit state is exceeded when that body overturned
            let overturned = match column {
                Column::Body(slot, _) => outcome.body(slot).is_some_and(|b| b.overturned),
                _ => outcome.overturned,
            };
            let above = overturned
                || match (kind, column.measure(outcome)) {
                    (MeasureKind::Flag, v) => v == Some(1.0),
                    (MeasureKind::Number, None) => false,
                    (MeasureKind::Number, Some(v)) => v > threshold,
                };
            exceeded |= u64::from(above) << k;
        }
        let name = row.record.to_string();
        let records = &mut case.records;
        let record = *record_index[c].entry(name.clone()).or_insert_with(|| {
            records.push(name);
            records.len() - 1
        });
        case.trials.push(Trial {
            record,
            level: pga,
            im: value,
            overturned: outcome.overturned,
            exceeded,
        });
        levels[c].push(candidates.map(|col| col.and_then(|col| row.intensity(col))));
    }
    let pick = level_column(&levels);
    for (case, levels) in out.cases.iter_mut().zip(&levels) {
        for (trial, l) in case.trials.iter_mut().zip(levels) {
            if let Some(v) = l[pick] {
                trial.level = v;
            }
        }
    }
    Ok(out)
}

/// The columns an outcomes file's levels can be in: `scale` alone in a
/// scale-factor study; else `pga` and `pgv` (`pga_rotd50` and `pgv_rotd50`
/// for record pairs), one of which holds the level exactly while the other
/// is each scaled record's own measured peak.
fn level_candidates(table: &OutcomesFile) -> [Option<Column>; 2] {
    if table.has(Column::Scale) {
        [Some(Column::Scale), None]
    } else if table.has(Column::Im(Im::PGA_ROTD50)) {
        [
            Some(Column::Im(Im::PGA_ROTD50)),
            Some(Column::Im(Im::PGV_ROTD50)),
        ]
    } else {
        [Some(Column::Im(Im::PGA)), Some(Column::Im(Im::PGV))]
    }
}

/// Which of the candidates (`levels[case][trial]`) is the levels' column:
/// the one with fewer distinct values over the file (the level is written
/// exactly, the same for every record of a stripe; a measured peak differs
/// per record, if only in its last bits), the first on a tie or when the
/// second is missing. An outcomes.csv holds nothing else that names the
/// study's levels' measure (issue 37: stripes were counted by the measured
/// PGA, 440 for 11 levels of record pairs, 100 for 5 PGV levels).
fn level_column(levels: &[Vec<[Option<f64>; 2]>]) -> usize {
    let distinct = |k: usize| -> Option<usize> {
        let mut bits = Vec::new();
        for l in levels.iter().flatten() {
            bits.push(l[k]?.to_bits());
        }
        bits.sort_unstable();
        bits.dedup();
        Some(bits.len())
    };
    match (distinct(0), distinct(1)) {
        (Some(a), Some(b)) if b < a => 1,
        (None, Some(_)) => 1,
        _ => 0,
    }
}
