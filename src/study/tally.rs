//! The counts of a study's outcomes: [`Tally`] reads `outcomes.csv` back,
//! checks every row is the analysis expected at its place, and counts per
//! case and intensity level the runs, failures, overturns, uplifts and the
//! means of the response measures. `summary.md`, `manifest.json` and the
//! paper's tables are written from it.

use super::plan::{self, Shard};
use crate::error::Result;
use crate::outcomes_csv::{Column, OutcomesFile};
use crate::spec::Study;
use std::path::Path;

/// Counts over all analyses of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Counts {
    /// Analyses in `outcomes.csv`.
    pub analyses: u64,
    /// Analyses the solver could not finish (status `failed`).
    pub failed: u64,
    /// Runs that reached |θ| = π/2.
    pub overturned: u64,
    /// Runs that lifted off from rock at least once.
    pub uplifted: u64,
    /// Runs overturned or uplifted (the paper's convention).
    pub overturned_or_uplifted: u64,
}

/// Means of θmax/θc, μ_mot, μ_imp (impulse ratio) and μ_imp by eq. (5)
/// over some runs of a cell.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Means {
    n: u64,
    /// Sums of θmax/θc, μ_mot, μ_imp (impulse ratio), μ_imp by eq. (5).
    sums: [f64; 4],
}

impl Means {
    fn add(&mut self, values: [f64; 4]) {
        self.n += 1;
        for (s, v) in self.sums.iter_mut().zip(values) {
            *s += v;
        }
    }

    /// The means, `None` over no run.
    pub(crate) fn get(&self) -> Option<[f64; 4]> {
        let n = self.n as f64;
        (self.n > 0).then(|| self.sums.map(|s| s / n))
    }
}

/// The analyses of one case at one intensity level.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Cell {
    /// Analyses that finished.
    pub(crate) ok: u64,
    /// Analyses that failed.
    pub(crate) failed: u64,
    /// Runs that overturned.
    pub(crate) overturned: u64,
    /// Runs that lifted off from rock.
    pub(crate) uplifted: u64,
    /// Runs that left rest.
    pub(crate) moved: u64,
    /// Runs that overturned or lifted off (the seed paper's convention).
    pub(crate) overturned_or_uplifted: u64,
    /// Means over the runs that did not overturn.
    pub(crate) strict: Means,
    /// Means over the runs that neither overturned nor lifted off.
    pub(crate) paper: Means,
    /// Runs with a sensitivity (`[output] sensitivity`; both solves done).
    pub(crate) sensitivity_known: u64,
    /// Of those, runs that are sensitive.
    pub(crate) sensitive: u64,
}

/// Statistics of a run read back from its `outcomes.csv`: per case (in
/// canonical order) and intensity level.
#[derive(Clone, Debug)]
pub struct Tally {
    pub(crate) cells: Vec<Cell>,
    pub(crate) counts: Counts,
    pub(crate) levels: usize,
}

impl Tally {
    /// Reads `outcomes.csv` of `study` (shard `shard`) through
    /// [`OutcomesFile`], checking that its header is the study's, that
    /// every row is the analysis expected at its place (case, level,
    /// record), and the count.
    pub fn read(path: &Path, study: &Study, shard: Shard) -> Result<Tally> {
        let cols = plan::columns(study);
        let mut table = OutcomesFile::open(
            path,
            &[
                cols.level(),
                Column::Record,
                Column::Status,
                Column::Overturned,
                Column::Uplifted,
                Column::ThetaMaxOverThetaC,
                Column::MuMotion,
                Column::MuImpact,
                Column::MuImpactEq5,
            ],
            "the study's summary",
        )?;
        let names = cols.names();
        if table.header().iter().ne(names.iter().map(|n| n.as_ref())) {
            return Err(table.header_error(format!(
                "header is not the study's: expected {}",
                names.join(",")
            )));
        }

        let cases = plan::cases(study);
        let drawn = study.drawn();
        let total = plan::unit_count(study);
        let levels = study.intensity.levels();
        let mut tally = Tally {
            cells: vec![Cell::default(); cases.len() * levels.len()],
            counts: Counts::default(),
            levels: levels.len(),
        };
        let mut units = shard.units(total);
        let mut unit = None;
        let mut rows = 0usize;
        while let Some((line, row)) = table.next_row()? {
            let at = |message: String| table.error_at(line, message);
            let ci = rows % cases.len();
            if ci == 0 {
                unit = units.next().map(|u| plan::unit(study, u));
            }
            let Some(u) = unit else {
                return Err(at("more rows than the study has analyses".into()));
            };
            let case = &cases[ci];
            let key = row.case.pooled(&drawn);
            if key != *case {
                return Err(at(format!(
                    "case {key} where the study's order puts {case}"
                )));
            }
            let level = row.level(&cols);
            if level != Some(levels[u.level]) {
                return Err(at(format!(
                    "{} = {} where the study's order puts {}",
                    cols.level(),
                    level.map_or(String::new(), |x| x.to_string()),
                    levels[u.level]
                )));
            }
            if row.record != u.record {
                return Err(at(format!(
                    "record = {} where the study's order puts {}",
                    row.record, u.record
                )));
            }
            let cell = &mut tally.cells[ci * tally.levels + u.level];
            tally.counts.analyses += 1;
            match &row.result {
                Ok(o) => {
                    let (ot, up) = (o.overturned, o.uplifted);
                    let values = [
                        o.theta_max_over_theta_c,
                        o.mu_motion,
                        o.mu_impact,
                        o.mu_impact_eq5,
                    ];
                    cell.ok += 1;
                    cell.uplifted += up as u64;
                    cell.moved += o.moved as u64;
                    tally.counts.overturned += ot as u64;
                    tally.counts.uplifted += up as u64;
                    tally.counts.overturned_or_uplifted += (ot || up) as u64;
                    if ot {
                        cell.overturned += 1;
                    } else {
                        cell.strict.add(values);
                    }
                    if ot || up {
                        cell.overturned_or_uplifted += 1;
                    } else {
                        cell.paper.add(values);
                    }
                    if let Some(sensitive) = row.sensitive {
                        cell.sensitivity_known += 1;
                        cell.sensitive += sensitive as u64;
                    }
                }
                Err(_) => {
                    cell.failed += 1;
                    tally.counts.failed += 1;
                }
            }
            rows += 1;
        }
        let expected = shard.unit_count(total) * cases.len();
        if rows != expected {
            return Err(table.error_at(
                rows + 1,
                format!("{rows} analyses where the study (shard {shard}) has {expected}"),
            ));
        }
        Ok(tally)
    }

    /// Counts over every analysis read.
    pub fn counts(&self) -> Counts {
        self.counts
    }
}
