//! Percentile bootstrap of a case's fit: confidence intervals for θ and β and
//! a pointwise band for the curve.
//!
//! Replicate r draws from its own generator, seeded from (seed, r) alone, and
//! replicates are collected in order: results are bit-identical for any
//! number of threads. The same seed gives the same record draws in every case
//! with the same records (common random numbers across cases).

use crate::detmath as dm;
use std::collections::BTreeMap;

use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;

use super::data::CaseData;
use super::fit::{LognormalFit, Observation, Unfit, fit_common_beta, fit_lognormal};
use super::options::BootstrapUnit;
use super::status::UnfitKind;

/// A two-sided percentile interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// Lower percentile.
    pub lo: f64,
    /// Upper percentile.
    pub hi: f64,
}

/// What the bootstrap of one case found.
#[derive(Clone, Debug, PartialEq)]
pub struct BootstrapSummary {
    /// Replicates drawn.
    pub replicates: usize,
    /// Replicates that could be fitted; the intervals come from these alone.
    pub fitted: usize,
    /// Replicates that could not be fitted, by why (in keyword order).
    pub unfit: BTreeMap<UnfitKind, usize>,
    /// Percentile interval of θ (`None` with fewer than 2 fitted replicates).
    pub median: Option<Interval>,
    /// Percentile interval of β (`None` with fewer than 2 fitted replicates).
    pub beta: Option<Interval>,
    /// Standard deviation of θ over the fitted replicates.
    pub sd_median: Option<f64>,
    /// Standard deviation of β over the fitted replicates.
    pub sd_beta: Option<f64>,
    /// Pointwise lower percentile of the replicate curves on the case's grid
    /// (empty with fewer than 2 fitted replicates).
    pub curve_lo: Vec<f64>,
    /// Pointwise upper percentile of the replicate curves on the case's grid.
    pub curve_hi: Vec<f64>,
    /// Each replicate's fit, in replicate order: (θ, β), or why it could not
    /// be fitted. Written to `fragility_bootstrap.csv` so that quantities
    /// derived from the curve (the annual rate of a risk integral) can carry
    /// the same uncertainty.
    pub replicate_fits: Vec<std::result::Result<(f64, f64), Unfit>>,
}

impl BootstrapSummary {
    /// Replicates that could not be fitted.
    pub fn unfit_total(&self) -> usize {
        self.unfit.values().sum()
    }
}

/// Bootstraps the fit of `case`: `replicates` resamples by `unit`, replicate
/// r seeded from (`seed`, r), intervals at two-sided level `confidence`
/// (e.g. 0.9 → 5th and 95th percentiles), curve bands on `grid`. Fits the
/// case's first limit state ([`Trial::exceeds`](super::Trial::exceeds)`(0)`,
/// overturning unless limit states were given).
pub fn bootstrap(
    case: &CaseData,
    grid: &[f64],
    replicates: usize,
    unit: BootstrapUnit,
    seed: u64,
    confidence: f64,
) -> BootstrapSummary {
    let plan = Plan::new(case, 0);
    let fits: Vec<Result<LognormalFit, Unfit>> = (0..replicates as u64)
        .into_par_iter()
        .map(|r| fit_lognormal(&plan.resample(unit, replicate_seed(seed, r))))
        .collect();
    summarise(fits, grid, replicates, confidence)
}

/// Bootstraps the common-β fit of limit states `limit_states` of `case`
/// ([`fit_common_beta`]): each replicate draws the same records (or
/// analyses) for every limit state, as the one seed makes it, and refits
/// them jointly. One summary per limit state, in the order given.
pub(crate) fn bootstrap_common_beta(
    case: &CaseData,
    limit_states: &[usize],
    grid: &[f64],
    replicates: usize,
    unit: BootstrapUnit,
    seed: u64,
    confidence: f64,
) -> Vec<BootstrapSummary> {
    let plans: Vec<Plan> = limit_states.iter().map(|&k| Plan::new(case, k)).collect();
    let fits: Vec<Result<Vec<LognormalFit>, Unfit>> = (0..replicates as u64)
        .into_par_iter()
        .map(|r| {
            let obs: Vec<Vec<Observation>> = plans
                .iter()
                .map(|p| p.resample(unit, replicate_seed(seed, r)))
                .collect();
            let sets: Vec<&[Observation]> = obs.iter().map(Vec::as_slice).collect();
            fit_common_beta(&sets)
        })
        .collect();
    (0..limit_states.len())
        .map(|j| {
            let one = fits
                .iter()
                .map(|f| f.as_ref().map(|v| v[j]).map_err(|e| *e))
                .collect();
            summarise(one, grid, replicates, confidence)
        })
        .collect()
}

/// Percentile intervals and bands from the replicates' fits.
fn summarise(
    fits: Vec<Result<LognormalFit, Unfit>>,
    grid: &[f64],
    replicates: usize,
    confidence: f64,
) -> BootstrapSummary {
    let mut unfit = BTreeMap::new();
    let mut ok = Vec::with_capacity(fits.len());
    let replicate_fits = fits
        .iter()
        .map(|f| f.as_ref().map(|x| (x.median(), x.beta())).map_err(|e| *e))
        .collect();
    for f in fits {
        match f {
            Ok(fit) => ok.push(fit),
            Err(reason) => *unfit.entry(reason.kind()).or_insert(0) += 1,
        }
    }
    let q = [(1.0 - confidence) / 2.0, (1.0 + confidence) / 2.0];
    let interval = |mut v: Vec<f64>| {
        (v.len() >= 2).then(|| Interval {
            lo: select_percentile(&mut v, q[0]),
            hi: select_percentile(&mut v, q[1]),
        })
    };
    let medians: Vec<f64> = ok.iter().map(LognormalFit::median).collect();
    let betas: Vec<f64> = ok.iter().map(LognormalFit::beta).collect();
    let (mut curve_lo, mut curve_hi) = (Vec::new(), Vec::new());
    if ok.len() >= 2 {
        let mut p = vec![0.0; ok.len()];
        for &x in grid {
            // ln x once a point, not once a replicate (the same bits as
            // `fit.probability(x)`)
            let ln_x = if x <= 0.0 { None } else { Some(dm::ln(x)) };
            for (pi, fit) in p.iter_mut().zip(&ok) {
                *pi = ln_x.map_or(0.0, |l| fit.probability_at_ln(l));
            }
            curve_lo.push(select_percentile(&mut p, q[0]));
            curve_hi.push(select_percentile(&mut p, q[1]));
        }
    }
    BootstrapSummary {
        replicates,
        fitted: ok.len(),
        unfit,
        sd_median: std_dev(&medians),
        sd_beta: std_dev(&betas),
        median: interval(medians),
        beta: interval(betas),
        curve_lo,
        curve_hi,
        replicate_fits,
    }
}

/// The seed of replicate r: SplitMix64's finaliser applied to (seed, r), so
/// neighbouring replicates get unrelated streams.
pub(crate) fn replicate_seed(seed: u64, replicate: u64) -> u64 {
    const GOLDEN: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut z = seed
        .wrapping_add(GOLDEN)
        .wrapping_add(replicate.wrapping_mul(0xD1B5_4A32_D192_ED03));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The 100·q-th percentile of sorted `v` (linear interpolation between order
/// statistics, Hyndman & Fan type 7).
pub fn percentile(sorted: &[f64], q: f64) -> f64 {
    let h = (sorted.len() - 1) as f64 * q.clamp(0.0, 1.0);
    let i = h.floor() as usize;
    match sorted.get(i + 1) {
        Some(&next) => sorted[i] + (h - i as f64) * (next - sorted[i]),
        None => sorted[i],
    }
}

/// [`percentile`] of `v` as if sorted by `f64::total_cmp`, without sorting
/// it: the one or two order statistics it interpolates are selected (the
/// same values, bit for bit: elements equal under `total_cmp` have the same
/// bits), in O(n) instead of a sort's O(n log n). `v` is reordered. The
/// bootstrap's bands take two percentiles of the replicates at every point
/// of a case's grid, where the sorts were most of the bootstrap's cost.
fn select_percentile(v: &mut [f64], q: f64) -> f64 {
    let h = (v.len() - 1) as f64 * q.clamp(0.0, 1.0);
    let i = h.floor() as usize;
    let (_, &mut at, above) = v.select_nth_unstable_by(i, f64::total_cmp);
    match above.iter().copied().min_by(f64::total_cmp) {
        Some(next) => at + (h - i as f64) * (next - at),
        None => at,
    }
}

fn std_dev(v: &[f64]) -> Option<f64> {
    (v.len() >= 2).then(|| {
        let n = v.len() as f64;
        let mean = v.iter().sum::<f64>() / n;
        (v.iter().map(|x| dm::powi(x - mean, 2)).sum::<f64>() / (n - 1.0)).sqrt()
    })
}

/// A case's analyses arranged for resampling: each as (IM group, exceeded
/// the limit state).
struct Plan {
    /// Distinct intensities, ascending.
    levels: Vec<f64>,
    /// Analyses of each record that has any.
    by_record: Vec<Vec<(usize, bool)>>,
    /// Analyses of each stripe (intensity level).
    by_stripe: Vec<Vec<(usize, bool)>>,
}

impl Plan {
    fn new(case: &CaseData, limit_state: usize) -> Self {
        let mut levels: Vec<f64> = case.trials.iter().map(|a| a.im).collect();
        levels.sort_by(f64::total_cmp);
        levels.dedup();
        let mut stripes: Vec<f64> = case.trials.iter().map(|a| a.level).collect();
        stripes.sort_by(f64::total_cmp);
        stripes.dedup();
        let mut by_record = vec![Vec::new(); case.records.len()];
        let mut by_stripe = vec![Vec::new(); stripes.len()];
        for a in &case.trials {
            let g = levels.partition_point(|&x| x < a.im);
            let s = stripes.partition_point(|&x| x < a.level);
            by_record[a.record].push((g, a.exceeds(limit_state)));
            by_stripe[s].push((g, a.exceeds(limit_state)));
        }
        by_record.retain(|r| !r.is_empty());
        Plan {
            levels,
            by_record,
            by_stripe,
        }
    }

    /// The counts of one resample drawn from a generator seeded with `seed`.
    fn resample(&self, unit: BootstrapUnit, seed: u64) -> Vec<Observation> {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        let mut trials = vec![0u64; self.levels.len()];
        let mut overturned = vec![0u64; self.levels.len()];
        let mut add = |&(g, o): &(usize, bool)| {
            trials[g] += 1;
            overturned[g] += u64::from(o);
        };
        match unit {
            BootstrapUnit::Records => {
                let k = self.by_record.len();
                for _ in 0..k {
                    self.by_record[rng.random_range(0..k)]
                        .iter()
                        .for_each(&mut add);
                }
            }
            BootstrapUnit::Analyses => {
                for stripe in &self.by_stripe {
                    let m = stripe.len();
                    for _ in 0..m {
                        add(&stripe[rng.random_range(0..m)]);
                    }
                }
            }
        }
        self.levels
            .iter()
            .zip(trials.iter().zip(&overturned))
            .filter(|(_, (n, _))| **n > 0)
            .map(|(&im, (&trials, &overturned))| Observation {
                im,
                trials,
                overturned,
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Type-7 percentiles: the ends are the extremes, the middle interpolates.
    #[test]
    fn percentile_interpolates_between_order_statistics() {
        let v = [1.0, 2.0, 3.0, 4.0, 5.0];
        assert_eq!(percentile(&v, 0.0), 1.0);
        assert_eq!(percentile(&v, 1.0), 5.0);
        assert_eq!(percentile(&v, 0.5), 3.0);
        assert!((percentile(&v, 0.05) - 1.2).abs() < 1e-15);
        assert_eq!(percentile(&[7.0], 0.3), 7.0);
    }

    #[test]
    fn selected_percentiles_are_the_sorted_ones_bit_for_bit() {
        // The bands select order statistics instead of sorting: the same
        // bits as `percentile` of the sorted values, at every q, for values
        // with ties, signed zeros, and the 0/1 probabilities of a steep fit.
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for n in [1_usize, 2, 3, 7, 40, 201, 1000] {
            let v: Vec<f64> = (0..n)
                .map(|_| match next() % 6 {
                    0 => 0.0,
                    1 => -0.0,
                    2 => 1.0,
                    3 => 0.25,
                    _ => (next() >> 11) as f64 / (1u64 << 53) as f64,
                })
                .collect();
            let mut sorted = v.clone();
            sorted.sort_by(f64::total_cmp);
            for q in [0.0, 0.025, 0.05, 0.1, 0.5, 0.9, 0.95, 0.975, 1.0] {
                let mut w = v.clone();
                let a = select_percentile(&mut w, q);
                let b = percentile(&sorted, q);
                assert_eq!(a.to_bits(), b.to_bits(), "n {n}, q {q}: {a} vs {b}");
                // a second percentile of the reordered values, as the bands take
                let c = select_percentile(&mut w, 1.0 - q);
                let d = percentile(&sorted, 1.0 - q);
                assert_eq!(c.to_bits(), d.to_bits(), "n {n}, q {}: {c} vs {d}", 1.0 - q);
            }
        }
    }
}
