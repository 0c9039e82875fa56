//! Error at the level of the fit: each case's lognormal fragility fitted to a
//! setting's overturning outcomes, against the fit to the reference's, in
//! units of the reference fit's own 90 % bootstrap band (records resampled).
//!
//! A setting's error over the ensemble is the largest, over cases, of
//! |Δθ|/w_θ and |Δβ|/w_β, where Δ is the setting's fitted median θ (or β)
//! less the reference's and w the width of the reference's 90 % interval
//! (5th to 95th percentile of 1000 replicates). A setting whose error is
//! below 0.1 moves no curve by more than a tenth of what the records alone
//! leave uncertain. A setting with the reference's outcome in every analysis
//! has the same counts, so the same fit: an error of exactly 0.

use rockfrag::case::Case;
use rockfrag::fragility::{
    CaseData, FragilityOptions, Interval, LognormalFit, Trial, Unfit, fit_case,
};
use rockfrag::outcome::Outcome;

/// One case (block configuration) of the ensemble and its analyses.
#[derive(Clone, Debug)]
pub struct CaseGroup {
    /// The configuration.
    pub key: Case,
    /// Short label, e.g. `H/B 4, e 0.9, μ 0.7/0.6`.
    pub label: String,
    /// Each analysis of the case: (index into the ensemble's outcomes,
    /// record index within its stripe, the stripe's PGA in g).
    pub analyses: Vec<(usize, usize, f64)>,
}

/// The reference's fit of one case and its 90 % band.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceFit {
    /// The fit, or why there is none.
    pub fit: Result<LognormalFit, Unfit>,
    /// Bootstrap intervals of θ and β (none when unfitted or too few
    /// replicates could be fitted).
    pub bands: Option<(Interval, Interval)>,
    /// Bootstrap replicates that could not be fitted.
    pub unfit_replicates: usize,
}

/// A setting's fragility error over the cases it ran.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct FragilityError {
    /// Cases compared (those the setting ran whose reference has a band).
    pub compared: usize,
    /// Of those, cases the setting's outcomes could not be fitted.
    pub unfit: usize,
    /// Largest |Δθ|/w_θ and |Δβ|/w_β over the cases.
    pub theta_bands: f64,
    /// See `theta_bands`.
    pub beta_bands: f64,
    /// Largest |Δθ| (g) and |Δβ| over the cases.
    pub theta_abs: f64,
    /// See `theta_abs`.
    pub beta_abs: f64,
    /// The case of the largest error in bands.
    pub worst_case: String,
}

impl FragilityError {
    /// The largest error over cases, in units of the 90 % band; infinite if
    /// a case could not be fitted.
    pub fn bands(&self) -> f64 {
        if self.unfit > 0 {
            f64::INFINITY
        } else {
            self.theta_bands.max(self.beta_bands)
        }
    }
}

/// The overturning counts of `group` under `outcomes` (an analysis the
/// setting did not run is `None`), as the fit reads them.
fn case_data(group: &CaseGroup, outcomes: &[Option<Outcome>], records: usize) -> Option<CaseData> {
    let trials: Vec<Trial> = group
        .analyses
        .iter()
        .filter_map(|&(i, record, pga)| {
            outcomes[i].as_ref().map(|o| Trial {
                record,
                level: pga,
                im: pga,
                overturned: o.overturned,
                exceeded: u64::from(o.overturned),
            })
        })
        .collect();
    (!trials.is_empty()).then(|| CaseData {
        key: group.key,
        records: (0..records).map(|r| r.to_string()).collect(),
        trials,
        failed: 0,
    })
}

/// The reference's fit of every case, with its bootstrap over records
/// (`bootstrap` replicates, seed 1, 90 %).
pub fn reference_fits(
    groups: &[CaseGroup],
    outcomes: &[Option<Outcome>],
    records: usize,
    bootstrap: usize,
) -> Vec<ReferenceFit> {
    let options = FragilityOptions {
        bootstrap,
        ..FragilityOptions::default()
    };
    groups
        .iter()
        .map(|g| {
            let data = case_data(g, outcomes, records).expect("the reference ran every case");
            let fit = fit_case(&data, &options).remove(0);
            let boot = fit.bootstrap.as_ref();
            ReferenceFit {
                bands: boot.and_then(|b| b.median.zip(b.beta)),
                unfit_replicates: boot.map_or(0, |b| b.unfit_total()),
                fit: fit.fit,
            }
        })
        .collect()
}

/// The fragility error of a setting whose outcomes are `outcomes`, against
/// the reference's fits.
pub fn fragility_error(
    groups: &[CaseGroup],
    outcomes: &[Option<Outcome>],
    records: usize,
    reference: &[ReferenceFit],
) -> FragilityError {
    let options = FragilityOptions {
        bootstrap: 0,
        ..FragilityOptions::default()
    };
    let mut err = FragilityError::default();
    let mut worst = -1.0;
    for (g, r) in groups.iter().zip(reference) {
        let (Ok(rf), Some((band_t, band_b))) = (&r.fit, r.bands) else {
            continue;
        };
        let Some(data) = case_data(g, outcomes, records) else {
            continue;
        };
        err.compared += 1;
        let Ok(f) = fit_case(&data, &options).remove(0).fit else {
            err.unfit += 1;
            err.worst_case = g.label.clone();
            continue;
        };
        let (dt, db) = (f.median() - rf.median(), f.beta() - rf.beta());
        let (wt, wb) = (band_t.hi - band_t.lo, band_b.hi - band_b.lo);
        let (et, eb) = (dt.abs() / wt, db.abs() / wb);
        err.theta_bands = err.theta_bands.max(et);
        err.beta_bands = err.beta_bands.max(eb);
        err.theta_abs = err.theta_abs.max(dt.abs());
        err.beta_abs = err.beta_abs.max(db.abs());
        if err.unfit == 0 && et.max(eb) > worst {
            worst = et.max(eb);
            err.worst_case = g.label.clone();
        }
    }
    err
}

#[cfg(test)]
mod tests {
    use super::*;
    use rockfrag::solver::Friction;

    /// A case of 25 records at 5 stripes whose record r overturns from
    /// stripe r mod 5 + 1 up (mixed counts at every stripe but the first).
    fn ensemble() -> (Vec<CaseGroup>, Vec<Option<Outcome>>) {
        let mut analyses = Vec::new();
        let mut outcomes = Vec::new();
        for s in 0..5 {
            for r in 0..25 {
                analyses.push((outcomes.len(), r, 0.2 * (s + 1) as f64));
                outcomes.push(Some(Outcome {
                    overturned: s > r % 5 && !(s == 4 && r == 0),
                    ..Outcome::default()
                }));
            }
        }
        let key = Case::fixed(4.0, 0.5, 0.0, Friction::Infinite);
        let label = "H/B 4".to_string();
        (
            vec![CaseGroup {
                key,
                label,
                analyses,
            }],
            outcomes,
        )
    }

    /// The same outcomes give the same counts, so the same fit: error 0
    /// exactly. One outcome flipped moves the fit by a positive amount,
    /// below the band (one analysis of 125).
    #[test]
    fn same_outcomes_give_zero_error_and_a_flip_a_small_one() {
        let (groups, outcomes) = ensemble();
        let reference = reference_fits(&groups, &outcomes, 25, 200);
        assert!(reference[0].bands.is_some(), "{reference:?}");
        let same = fragility_error(&groups, &outcomes, 25, &reference);
        assert_eq!((same.compared, same.bands()), (1, 0.0));
        let mut flipped = outcomes.clone();
        flipped[60] = Some(Outcome {
            overturned: !outcomes[60].as_ref().unwrap().overturned,
            ..Outcome::default()
        });
        let e = fragility_error(&groups, &flipped, 25, &reference);
        assert!(e.bands() > 0.0 && e.bands() < 1.0, "{e:?}");
    }
}
