//! Reading a study's `outcomes.csv` into cases: one block configuration with
//! its analyses, each at a stripe (PGA level) under one record.

use std::collections::HashMap;
use std::path::Path;

use super::fit::Observation;
use super::options::{FragilityOptions, IntensityMeasure, LimitState};
use crate::error::{Error, Result};
use crate::outcomes_csv::{CaseKey, Column, MeasureKind, OutcomesReader, Pooled};
use crate::solver::Friction;

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
    /// Which limit states the analysis exceeded: bit k for limit state k of
    /// [`Outcomes::limit_states`] (overturning alone: bit 0 = `overturned`).
    pub exceeded: u64,
}

impl Analysis {
    /// Whether the analysis exceeded limit state `k`.
    pub fn exceeds(&self, k: usize) -> bool {
        self.exceeded >> k & 1 == 1
    }
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

    /// The analyses grouped by equal intensity, in increasing intensity:
    /// trials and exceedances of limit state `k` at each (what is fitted).
    pub fn observations(&self, k: usize) -> Vec<Observation> {
        let mut sorted = self.analyses.clone();
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
    /// The limit states whose exceedance [`Analysis::exceeded`] records, in
    /// order of increasing severity.
    pub limit_states: Vec<LimitState>,
    /// One entry per case.
    pub cases: Vec<CaseData>,
    /// Failed rows whose case could not be read (counted, not attributed).
    pub failed_unattributed: usize,
}

/// Reads `outcomes.csv` with [`OutcomesReader`], keeping what the fragility
/// fit needs: `pga`, `record`, `overturned` (and `pgv` for the PGV intensity
/// measure). A failed analysis (see [`Row::failed`](crate::outcomes_csv::Row::failed))
/// is skipped and counted in [`CaseData::failed`], or in
/// [`Outcomes::failed_unattributed`] if its case cannot be read.
pub fn read_outcomes(path: &Path, im: IntensityMeasure) -> Result<Outcomes> {
    read_outcomes_with(path, im, &[LimitState::overturning()], Pooled::default())
}

/// Reads `outcomes.csv` for the intensity measure and limit states of
/// `options` (see [`read_outcomes`]). An analysis exceeds a limit state when
/// it overturned or its measure is above the threshold (a yes/no measure:
/// is yes); an empty numeric field (e.g. a time that did not occur) is not
/// above any threshold.
pub fn read_outcomes_for(path: &Path, options: &FragilityOptions) -> Result<Outcomes> {
    options.validate()?;
    read_outcomes_with(path, options.im, &options.limit_states(), options.pool)
}

fn read_outcomes_with(
    path: &Path,
    im: IntensityMeasure,
    limit_states: &[LimitState],
    pool: Pooled,
) -> Result<Outcomes> {
    let (mut table, [pga_col, record_col, overturned_col]) = OutcomesReader::open(
        path,
        [Column::Pga, Column::Record, Column::Overturned],
        "the fragility fit",
    )?;
    let pgv = table.column(Column::Pgv);
    if im == IntensityMeasure::Pgv && pgv.is_none() {
        return Err(
            table.header_error("no `pgv` column, which the PGV intensity measure needs".into())
        );
    }

    // (column index, kind, threshold) of each limit state's measure.
    let mut measures = Vec::with_capacity(limit_states.len());
    for ls in limit_states {
        let Some((column, kind)) = ls.column() else {
            return Err(Error::invalid(
                "fragility.limit_state.measure",
                &ls.measure,
                "a numeric or yes/no column of outcomes.csv",
            ));
        };
        let Some(i) = table.column(column) else {
            return Err(table.header_error(format!(
                "no `{}` column, which limit state {:?} needs",
                ls.measure, ls.name
            )));
        };
        measures.push((i, kind, ls.exceeds.unwrap_or(0.0)));
    }

    let mut out = Outcomes {
        im,
        limit_states: limit_states.to_vec(),
        cases: Vec::new(),
        failed_unattributed: 0,
    };
    let mut case_index: HashMap<KeyBits, usize> = HashMap::new();
    let mut record_index: Vec<HashMap<String, usize>> = Vec::new();
    while let Some(row) = table.next_row()? {
        let failed = row.failed();
        // The analysis's own parameters, and the case it pools into.
        let own = match row.case() {
            Ok(key) => key,
            Err(_) if failed => {
                out.failed_unattributed += 1;
                continue;
            }
            Err(e) => return Err(e),
        };
        let key = own.pooled(pool);
        let c = *case_index.entry(KeyBits::of(&key)).or_insert_with(|| {
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
        let pga = row.positive(pga_col)?;
        let value = match im {
            IntensityMeasure::Pga => pga,
            IntensityMeasure::PgaOverTan => pga * own.aspect,
            IntensityMeasure::Pgv => row.positive(pgv.expect("checked above"))?,
        };
        let overturned = row.boolean(overturned_col)?;
        let mut exceeded = 0u64;
        for (k, &(i, kind, threshold)) in measures.iter().enumerate() {
            let above = overturned
                || match kind {
                    MeasureKind::Flag => row.boolean(i)?,
                    MeasureKind::Number if row.field(i).is_empty() => false,
                    MeasureKind::Number => row.number(i)? > threshold,
                };
            exceeded |= u64::from(above) << k;
        }
        let name = row.text(record_col)?;
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
            exceeded,
        });
    }
    Ok(out)
}

/// Hashable identity of a case (bit patterns of its numbers; + 0.0 turns
/// −0.0 into 0.0, so the two are one case).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct KeyBits([u64; 3], Option<[u64; 2]>);

impl KeyBits {
    fn of(k: &CaseKey) -> Self {
        let bits = |x: f64| (x + 0.0).to_bits();
        KeyBits(
            [bits(k.aspect), bits(k.width), bits(k.restitution)],
            match k.friction {
                Friction::Infinite => None,
                Friction::Coulomb { mu_s, mu_k } => Some([bits(mu_s), bits(mu_k)]),
            },
        )
    }
}
