//! Two IMs at once (`rockfrag infer --im pga,pgv`): the joint posterior
//! over (IM1, IM2) of the shaking the site had.
//!
//! The simulations of a one-IM inference already hold everything: record
//! r scaled to IM1 = x has a definite IM2 = y_r(x) (measured on the scaled
//! record; every record is scaled linearly, so y_r(x) = ρ_r x with ρ_r the
//! record's IM2/IM1), and the survey's likelihood under it is Π_j ℓ_j(x, r).
//! The posterior over (x, r) is
//!
//! ```text
//! p(x, r | survey) ∝ prior(x) · (1/R) · Π_j ℓ_j(x, r)
//! ```
//!
//! and mapping (x, r) to (x, y_r(x)) gives the joint posterior in the
//! (IM1, IM2) plane. Summed over r it is the one-IM posterior of IM1
//! (nothing is solved again). A second IM adds a posterior over the
//! record, i.e. over its spectral shape (PGV/PGA, Sa(1.0)/PGA): its prior
//! is the ensemble's spread of IM2/IM1, each record 1/R, and the posterior
//! cannot leave it. [`PairPosterior::ratio`] compares the posterior of
//! IM2/IM1 with that prior and says whether the survey informs it beyond
//! the Monte Carlo error (a bootstrap over records and draws, as the
//! one-IM bounds').
//!
//! **Density.** The posterior is a set of point masses, R per grid point of
//! IM1 (on a line of slope 1 in the log–log plane per record). For the
//! density, its credible regions and its figure each mass is spread over
//! ln IM2 by a Gaussian of width h = 1.06 σ N^(−1/5) (Silverman's rule on
//! the records' ln IM2/IM1, σ their standard deviation, N the effective
//! number of records the posterior rests on, (Σ w_r)²/Σ w_r²), normalised on the
//! IM2 nodes so that summing the density over IM2 (trapezoid rule) gives
//! the one-IM posterior of IM1 at every grid point to rounding. The
//! credible regions are highest-density regions in (ln IM1, ln IM2); the
//! medians, intervals and correlation are read from the point masses
//! themselves (no smoothing).

use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;
use serde::Serialize;

use super::likelihood::{Brackets, Grid, record_terms, scaled};
use super::posterior::{Summary, replicate_seed, resample_picks};
use super::simulate::{Im, Table, inferable};
use super::survey::Survey;
use crate::detmath as dm;
use crate::error::{Error, Result};
use crate::im::{At, Felt, ImPair, Measure};
use crate::spec::Study;
use crate::study::Source;

/// Intervals of the joint grid's IM2 axis.
pub const IM2_INTERVALS: usize = 120;
/// The credible regions drawn and described (highest density).
pub const REGIONS: [f64; 2] = [0.5, 0.9];
/// A record at the edge of the ensemble's IM2/IM1 carrying at least this
/// share of the posterior (and twice its prior share) presses the
/// posterior against the ensemble's edge.
pub const EDGE_SHARE: f64 = 0.05;
/// How many Monte Carlo standard deviations a shift or narrowing of the
/// posterior of IM2/IM1 must exceed for the survey to inform it.
pub const INFORMED_SIGMAS: f64 = 2.0;

/// `pair` if `infer` can give its joint posterior: the first an IM a
/// one-IM inference can be of ([`inferable`]), the second an IM of the
/// ground record that scales with it (pga, pgv, sa(T), sa-avg(T1,T2));
/// else what it can be.
pub fn inferable_pair(pair: ImPair) -> std::result::Result<ImPair, String> {
    inferable(pair.first()).map_err(|e| format!("a first IM of {e}"))?;
    let second = pair.second();
    let scales = matches!(
        second.measure(),
        Measure::Pga | Measure::Pgv | Measure::Sa { .. } | Measure::SaAvg { .. }
    );
    if second.at() != At::Ground || !scales {
        return Err(format!(
            "a second IM of the ground record that scales with it (pga, pgv, sa(T), \
             sa-avg(T1,T2)), not {second}"
        ));
    }
    Ok(pair)
}

/// IM `im` of every record of `record_ids` at every level of `study`, at
/// `l · records + r` (as [`Table::im`]): the records are made again (as the
/// simulations made them), not solved.
///
/// Errors: as [`Source::record`]; an IM the record does not give.
pub fn measure_second(study: &Study, im: Im, record_ids: &[usize]) -> Result<Vec<f64>> {
    let levels = study.intensity.levels();
    let source = Source::new(study)?;
    let n = record_ids.len();
    let tasks: Vec<(usize, usize)> = (0..levels.len())
        .flat_map(|l| (0..n).map(move |r| (l, r)))
        .collect();
    let values: Vec<Result<f64>> = tasks
        .par_iter()
        .map_init(
            || source.clone(),
            |src, &(l, r)| {
                let rec = src.record(&study.intensity, levels[l], record_ids[r], study.g)?;
                let felt = Felt {
                    ground: &rec,
                    floor: None,
                    pair: None,
                    g: study.g,
                };
                im.on(&felt)
                    .filter(|v| v.is_finite() && *v > 0.0)
                    .ok_or_else(|| {
                        Error::invalid(
                            "--im",
                            im,
                            &format!(
                                "an IM record {} gives at level {} (it gives none, or 0)",
                                record_ids[r], levels[l]
                            ),
                        )
                    })
            },
        )
        .collect();
    values.into_iter().collect()
}

/// Three quantiles: 5 %, 50 %, 95 %.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Quantiles {
    /// Median.
    pub median: f64,
    /// 5th percentile.
    pub p05: f64,
    /// 95th percentile.
    pub p95: f64,
}

/// The Monte Carlo error of the comparison of the posterior of IM2/IM1 with
/// its prior (bootstrap standard deviations).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RatioMc {
    /// Of [`Ratio::shift`].
    pub shift: f64,
    /// Of [`Ratio::spread`].
    pub spread: f64,
    /// Replicates behind it.
    pub replicates: usize,
}

/// A record at an edge of the ensemble's IM2/IM1 that carries much of the
/// posterior.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Edge {
    /// The highest IM2/IM1 of the ensemble (else the lowest).
    pub high: bool,
    /// Its IM2/IM1.
    pub ratio: f64,
    /// Its share of the posterior.
    pub share: f64,
}

/// The posterior of the records' IM2/IM1 against its prior (the ensemble's
/// spread, each record 1/R).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Ratio {
    /// Its unit (`(m/s)/g`, `1`, …).
    pub unit: String,
    /// Over the records, equally weighted.
    pub prior: Quantiles,
    /// Over the records, weighted by their posterior shares.
    pub posterior: Quantiles,
    /// (posterior mean − prior mean) of ln IM2/IM1, in prior standard
    /// deviations.
    pub shift: f64,
    /// Posterior standard deviation of ln IM2/IM1 over the prior's.
    pub spread: f64,
    /// Their Monte Carlo error (`None` without a bootstrap).
    pub mc_error: Option<RatioMc>,
    /// Whether the shift or the narrowing exceeds
    /// [`INFORMED_SIGMAS`] Monte Carlo standard deviations (`None`: not
    /// assessed, no bootstrap).
    pub informed: Option<bool>,
    /// A record at the ensemble's edge carrying much of the posterior.
    pub edge: Option<Edge>,
}

/// The joint posterior over (IM1, IM2) (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct PairPosterior {
    /// The two IMs.
    pub ims: ImPair,
    /// IM1 nodes (the inference's grid).
    pub x: Vec<f64>,
    /// IM2 nodes, ascending, geometric.
    pub y: Vec<f64>,
    /// Density per unit ln IM1 and ln IM2 at node (i, k), at
    /// `i · y.len() + k`.
    pub density: Vec<f64>,
    /// The smallest highest-density credible level whose region holds the
    /// node, at the same place.
    pub credible: Vec<f64>,
    /// The joint density summed over IM2, per unit ln IM1 on `x`.
    pub marginal_first: Vec<f64>,
    /// Summed over IM1, per unit ln IM2 on `y`.
    pub marginal_second: Vec<f64>,
    /// IM1's bounds: the one-IM posterior's.
    pub first: Summary,
    /// IM2's, from the point masses (its mode from `marginal_second`).
    pub second: Summary,
    /// Correlation of ln IM1 and ln IM2 under the posterior.
    pub correlation: f64,
    /// The Gaussian's width h in ln IM2.
    pub bandwidth: f64,
    /// Records.
    pub records: usize,
    /// Each record's IM2/IM1 and its posterior share, by record.
    pub shares: Vec<(f64, f64)>,
    /// The posterior of IM2/IM1 against its prior.
    pub ratio: Ratio,
}

/// The posterior's point masses: record r at grid point i has mass
/// `mass[r · g + i]` (summing to 1 with the trapezoid weights in ln IM1
/// folded in) at ln IM2 = `ln_y[r · g + i]`; `density[r · g + i]` is the
/// mass per unit ln IM1 (before the weights).
struct Points {
    density: Vec<f64>,
    mass: Vec<f64>,
    ln_y: Vec<f64>,
}

/// Trapezoid weights of the points `u` (Σ w_i f_i is the trapezoid rule).
fn trapezoid(u: &[f64]) -> Vec<f64> {
    let n = u.len();
    (0..n)
        .map(|i| {
            let lo = if i > 0 { u[i] - u[i - 1] } else { 0.0 };
            let hi = if i + 1 < n { u[i + 1] - u[i] } else { 0.0 };
            0.5 * (lo + hi)
        })
        .collect()
}

fn points(
    table: &Table,
    second: &[f64],
    survey: &Survey,
    grid: &Grid,
    prior_u: &[f64],
) -> Option<Points> {
    let g = grid.len();
    let (s, m) = scaled(&record_terms(table, survey, grid));
    if m == f64::NEG_INFINITY {
        return None;
    }
    let brackets = Brackets::new(table, grid);
    let w = trapezoid(&grid.u);
    let n = table.records as f64;
    let mut density = vec![0.0; s.len()];
    let mut z = 0.0;
    for r in 0..table.records {
        for i in 0..g {
            let d = prior_u[i] * s[r * g + i] / n;
            density[r * g + i] = d;
            z += d * w[i];
        }
    }
    if !(z > 0.0 && z.is_finite()) {
        return None;
    }
    density.iter_mut().for_each(|d| *d /= z);
    let mass = (0..s.len()).map(|p| density[p] * w[p % g]).collect();
    let ln_y = (0..s.len())
        .map(|p| {
            let (r, i) = (p / g, p % g);
            let ln = |l: usize| dm::ln(second[l * table.records + r]);
            brackets.value(r, i, ln)
        })
        .collect();
    Some(Points {
        density,
        mass,
        ln_y,
    })
}

/// Weighted quantiles of `values` (weights summing to 1): the CDF linear
/// between the values' midpoints of mass.
fn quantiles(values: &[f64], weights: &[f64]) -> Quantiles {
    let mut o: Vec<usize> = (0..values.len()).filter(|&p| weights[p] > 0.0).collect();
    o.sort_by(|&a, &b| values[a].total_cmp(&values[b]).then(a.cmp(&b)));
    let total: f64 = o.iter().map(|&p| weights[p]).sum();
    let mut mids = Vec::with_capacity(o.len());
    let mut c = 0.0;
    for &p in &o {
        mids.push((c + 0.5 * weights[p]) / total);
        c += weights[p];
    }
    let at = |q: f64| {
        let k = mids.partition_point(|&m| m < q);
        if k == 0 {
            values[o[0]]
        } else if k >= o.len() {
            values[o[o.len() - 1]]
        } else {
            let (a, b) = (mids[k - 1], mids[k]);
            let t = if b > a { (q - a) / (b - a) } else { 0.0 };
            values[o[k - 1]] + t * (values[o[k]] - values[o[k - 1]])
        }
    };
    Quantiles {
        median: at(0.5),
        p05: at(0.05),
        p95: at(0.95),
    }
}

/// Weighted mean and standard deviation.
fn mean_sd(values: &[f64], weights: &[f64]) -> (f64, f64) {
    let total: f64 = weights.iter().sum();
    let mean = values.iter().zip(weights).map(|(v, w)| v * w).sum::<f64>() / total;
    let var = values
        .iter()
        .zip(weights)
        .map(|(v, w)| w * (v - mean) * (v - mean))
        .sum::<f64>()
        / total;
    (mean, var.max(0.0).sqrt())
}

/// Each record's ln IM2/IM1 at grid point `i` and its posterior share.
fn records_at(points: &Points, records: usize, grid: &Grid, i: usize) -> (Vec<f64>, Vec<f64>) {
    let g = grid.len();
    let ln_ratio = (0..records)
        .map(|r| points.ln_y[r * g + i] - grid.u[i])
        .collect();
    let shares = (0..records)
        .map(|r| points.mass[r * g..(r + 1) * g].iter().sum())
        .collect();
    (ln_ratio, shares)
}

/// (shift, spread) of the posterior of ln IM2/IM1 against its prior.
fn shift_spread(ln_ratio: &[f64], shares: &[f64]) -> (f64, f64) {
    let (m0, s0) = mean_sd(ln_ratio, &vec![1.0; ln_ratio.len()]);
    let (m1, s1) = mean_sd(ln_ratio, shares);
    ((m1 - m0) / s0, s1 / s0)
}

/// The standard deviation of `v` (n − 1).
fn sd(v: &[f64]) -> f64 {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    (v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0)).sqrt()
}

/// The unit of IM2/IM1.
fn ratio_unit(ims: ImPair) -> String {
    match (ims.second().unit(), ims.first().unit()) {
        (a, b) if a == b => "1".into(),
        (a, b) => {
            let wrap = |u: &str| {
                if u.contains('/') {
                    format!("({u})")
                } else {
                    u.to_string()
                }
            };
            format!("{}/{}", wrap(a), wrap(b))
        }
    }
}

impl PairPosterior {
    /// The joint posterior of `ims` from `table` (the simulations, in IM1),
    /// `second` (IM2 of every record at every level, [`measure_second`]),
    /// the survey, the grid and the prior of IM1 (per unit ln IM1); the
    /// comparison of IM2/IM1 with its prior carries a Monte Carlo error
    /// from `bootstrap` replicates (the one-IM bootstrap's, seed `seed`).
    /// `first` is the one-IM posterior's summary of IM1 (the joint's
    /// marginal; its median is where each record's IM2/IM1 is read).
    ///
    /// Errors: [`Error::InvalidParameter`] when every record has the same
    /// IM2/IM1 (IM2 is then IM1 times a constant); [`Error::Conflict`]
    /// when the likelihood vanishes on the grid.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ims: ImPair,
        table: &Table,
        second: &[f64],
        survey: &Survey,
        grid: &Grid,
        prior_u: &[f64],
        first: Summary,
        bootstrap: usize,
        seed: u64,
    ) -> Result<PairPosterior> {
        let (g, n) = (grid.len(), table.records);
        let pts = points(table, second, survey, grid, prior_u).ok_or_else(|| Error::Conflict {
            path: survey.path.clone(),
            message: "no intensity of the grid can give these counts under any record".into(),
        })?;
        // Where the records' IM2/IM1 are read: the grid point nearest the
        // IM1 median (the records are scaled linearly, so any point gives
        // the same ratios).
        let at = dm::ln(first.median);
        let i_med = (0..g)
            .min_by(|&a, &b| (grid.u[a] - at).abs().total_cmp(&(grid.u[b] - at).abs()))
            .unwrap_or(0);
        let (ln_ratio, shares) = records_at(&pts, n, grid, i_med);
        let (_, sigma) = mean_sd(&ln_ratio, &vec![1.0; n]);
        if sigma.is_nan() || sigma <= 1e-9 {
            return Err(Error::invalid(
                "--im",
                ims.to_string(),
                &format!(
                    "records whose {} differ: all {n} records of the study have {} = {}, so \
                     {} is {} times {} and a joint posterior adds nothing; infer {} alone \
                     (--im {}), or give the study more records",
                    ratio_name(ims),
                    ratio_name(ims),
                    crate::io_util::sig3(dm::exp(ln_ratio[0])),
                    ims.second().name().to_uppercase(),
                    crate::io_util::sig3(dm::exp(ln_ratio[0])),
                    ims.first().name().to_uppercase(),
                    ims.first().name().to_uppercase(),
                    ims.first(),
                ),
            ));
        }
        // Silverman's rule on the records' ln IM2/IM1 with the number of
        // records the posterior rests on: a posterior carried by a few
        // records knows the site's IM2/IM1 only to about the ensemble's
        // spread, not to those records' values.
        let total: f64 = shares.iter().sum();
        let squares: f64 = shares.iter().map(|s| s * s).sum();
        let n_eff = if squares > 0.0 {
            (total * total / squares).clamp(1.0, n as f64)
        } else {
            n as f64
        };
        let h = 1.06 * sigma * dm::powf(n_eff, -0.2);
        // IM2 nodes over the points that carry mass, ±5 h.
        let top = pts.density.iter().copied().fold(0.0, f64::max);
        let carried = |p: usize| pts.density[p] > 1e-9 * top;
        let (lo, hi) = (0..pts.ln_y.len())
            .filter(|&p| carried(p))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(pts.ln_y[p]), b.max(pts.ln_y[p]))
            });
        let (v0, v1) = (lo - 5.0 * h, hi + 5.0 * h);
        let ny = IM2_INTERVALS + 1;
        let v: Vec<f64> = (0..ny)
            .map(|k| v0 + (v1 - v0) * k as f64 / IM2_INTERVALS as f64)
            .collect();
        let w1 = trapezoid(&grid.u);
        let w2 = trapezoid(&v);
        let mut density = vec![0.0; g * ny];
        let mut kernel = vec![0.0; ny];
        for p in (0..pts.ln_y.len()).filter(|&p| carried(p)) {
            let (c, i) = (pts.ln_y[p], p % g);
            let mut norm = 0.0;
            for k in 0..ny {
                let t = (v[k] - c) / h;
                // Gaussian kernel exp(−t²/2), cut at 6 h.
                kernel[k] = if t.abs() < 6.0 {
                    dm::exp(-0.5 * t * t)
                } else {
                    0.0
                };
                norm += kernel[k] * w2[k];
            }
            let d = pts.density[p] / norm;
            for k in 0..ny {
                density[i * ny + k] += d * kernel[k];
            }
        }
        let marginal_first: Vec<f64> = (0..g)
            .map(|i| (0..ny).map(|k| density[i * ny + k] * w2[k]).sum())
            .collect();
        let marginal_second: Vec<f64> = (0..ny)
            .map(|k| (0..g).map(|i| density[i * ny + k] * w1[i]).sum())
            .collect();
        // Highest-density levels: cells by decreasing density, cumulated.
        let cell = |q: usize| density[q] * w1[q / ny] * w2[q % ny];
        let mut order: Vec<usize> = (0..density.len()).collect();
        order.sort_by(|&a, &b| density[b].total_cmp(&density[a]).then(a.cmp(&b)));
        let total: f64 = (0..density.len()).map(cell).sum();
        let mut credible = vec![1.0; density.len()];
        let mut c = 0.0;
        for &q in &order {
            c += cell(q);
            credible[q] = (c / total).min(1.0);
        }
        // IM2's bounds and the correlation from the point masses.
        let u1: Vec<f64> = (0..pts.mass.len()).map(|p| grid.u[p % g]).collect();
        let q2 = quantiles(&pts.ln_y, &pts.mass);
        let (m1, s1) = mean_sd(&u1, &pts.mass);
        let (m2, s2) = mean_sd(&pts.ln_y, &pts.mass);
        let cov: f64 = (0..pts.mass.len())
            .map(|p| pts.mass[p] * (u1[p] - m1) * (pts.ln_y[p] - m2))
            .sum::<f64>()
            / pts.mass.iter().sum::<f64>();
        let correlation = if s1 > 0.0 && s2 > 0.0 {
            (cov / (s1 * s2)).clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let y: Vec<f64> = v.iter().map(|&t| dm::exp(t)).collect();
        let mode_of = |xs: &[f64], d: &[f64]| {
            // largest density per unit IM, as the one-IM mode
            (0..xs.len())
                .max_by(|&a, &b| (d[a] / xs[a]).total_cmp(&(d[b] / xs[b])).then(b.cmp(&a)))
                .map_or(f64::NAN, |i| xs[i])
        };
        let summary = |q: Quantiles, mode: f64| Summary {
            median: dm::exp(q.median),
            p05: dm::exp(q.p05),
            p95: dm::exp(q.p95),
            mode,
        };
        let second_summary = summary(q2, mode_of(&y, &marginal_second));
        let ratio = ratio_of(
            ims,
            &ln_ratio,
            &shares,
            (table, second, survey, grid, prior_u, i_med),
            bootstrap,
            seed,
        );
        Ok(PairPosterior {
            ims,
            x: grid.x.clone(),
            y,
            density,
            credible,
            marginal_first,
            marginal_second,
            first,
            second: second_summary,
            correlation,
            bandwidth: h,
            records: n,
            shares: ln_ratio
                .iter()
                .zip(&shares)
                .map(|(&l, &s)| (dm::exp(l), s))
                .collect(),
            ratio,
        })
    }

    /// The smallest highest-density credible level whose region holds
    /// (`x`, `y`): the mass of the nodes denser than the density there
    /// (bilinear in ln IM1, ln IM2); 1 outside the grid. `x` lies in the
    /// 90 % region when this is at most 0.9.
    pub fn credible_at(&self, x: f64, y: f64) -> f64 {
        let (g, ny) = (self.x.len(), self.y.len());
        let (u, v) = (dm::ln(x), dm::ln(y));
        let ux: Vec<f64> = self.x.iter().map(|&t| dm::ln(t)).collect();
        let vy: Vec<f64> = self.y.iter().map(|&t| dm::ln(t)).collect();
        if !(u >= ux[0] && u <= ux[g - 1] && v >= vy[0] && v <= vy[ny - 1]) {
            return 1.0;
        }
        let bracket = |xs: &[f64], t: f64| {
            let i = xs.partition_point(|&a| a <= t).clamp(1, xs.len() - 1) - 1;
            (i, ((t - xs[i]) / (xs[i + 1] - xs[i])).clamp(0.0, 1.0))
        };
        let ((i, a), (k, b)) = (bracket(&ux, u), bracket(&vy, v));
        let d = |i: usize, k: usize| self.density[i * ny + k];
        let here = (1.0 - a) * ((1.0 - b) * d(i, k) + b * d(i, k + 1))
            + a * ((1.0 - b) * d(i + 1, k) + b * d(i + 1, k + 1));
        if here.is_nan() || here <= 0.0 {
            return 1.0;
        }
        // The credible level of the least dense node at least as dense.
        (0..self.density.len())
            .filter(|&q| self.density[q] >= here)
            .map(|q| self.credible[q])
            .fold(0.0, f64::max)
    }
}

/// `PGV/PGA`: IM2/IM1 in words.
pub fn ratio_name(ims: ImPair) -> String {
    format!(
        "{}/{}",
        ims.second().name().to_uppercase(),
        ims.first().name().to_uppercase()
    )
}

/// The inputs of one posterior: table, IM2 values, survey, grid, prior, and
/// the grid point where ratios are read.
type Inputs<'a> = (&'a Table, &'a [f64], &'a Survey, &'a Grid, &'a [f64], usize);

fn ratio_of(
    ims: ImPair,
    ln_ratio: &[f64],
    shares: &[f64],
    inputs: Inputs,
    bootstrap: usize,
    seed: u64,
) -> Ratio {
    let n = ln_ratio.len();
    let (table, second, survey, grid, prior_u, i_med) = inputs;
    let exp = |q: Quantiles| Quantiles {
        median: dm::exp(q.median),
        p05: dm::exp(q.p05),
        p95: dm::exp(q.p95),
    };
    let prior = exp(quantiles(ln_ratio, &vec![1.0 / n as f64; n]));
    let posterior = exp(quantiles(ln_ratio, shares));
    let (shift, spread) = shift_spread(ln_ratio, shares);
    // The bootstrap's replicates: the same resampling of records and draws
    // as the one-IM Monte Carlo error.
    let replicates: Vec<(f64, f64)> = (0..bootstrap as u64)
        .into_par_iter()
        .filter_map(|b| {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(replicate_seed(seed, b));
            let (t, picks) = resample_picks(table, &mut rng);
            let nl = table.levels.len();
            let mut sec = vec![0.0; second.len()];
            for l in 0..nl {
                for (s, &r) in picks.iter().enumerate() {
                    sec[l * n + s] = second[l * n + r];
                }
            }
            let pts = points(&t, &sec, survey, grid, prior_u)?;
            let (lr, sh) = records_at(&pts, n, grid, i_med);
            let (s, p) = shift_spread(&lr, &sh);
            (s.is_finite() && p.is_finite()).then_some((s, p))
        })
        .collect();
    let mc_error = (replicates.len() >= 2).then(|| RatioMc {
        shift: sd(&replicates.iter().map(|r| r.0).collect::<Vec<_>>()),
        spread: sd(&replicates.iter().map(|r| r.1).collect::<Vec<_>>()),
        replicates: replicates.len(),
    });
    let informed = mc_error.map(|m| {
        shift.abs() > INFORMED_SIGMAS * m.shift || (1.0 - spread).abs() > INFORMED_SIGMAS * m.spread
    });
    // The records at the ensemble's edges and their shares.
    let lowest = (0..n).min_by(|&a, &b| ln_ratio[a].total_cmp(&ln_ratio[b]).then(a.cmp(&b)));
    let highest = (0..n).max_by(|&a, &b| ln_ratio[a].total_cmp(&ln_ratio[b]).then(b.cmp(&a)));
    let pressing = |r: usize| shares[r] >= EDGE_SHARE.max(2.0 / n as f64);
    let edge = [(highest, true), (lowest, false)]
        .into_iter()
        .filter_map(|(r, high)| r.map(|r| (r, high)))
        .filter(|&(r, _)| pressing(r))
        .max_by(|a, b| shares[a.0].total_cmp(&shares[b.0]))
        .map(|(r, high)| Edge {
            high,
            ratio: dm::exp(ln_ratio[r]),
            share: shares[r],
        });
    Ratio {
        unit: ratio_unit(ims),
        prior,
        posterior,
        shift,
        spread,
        mc_error,
        informed,
        edge,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Weighted quantiles: equal weights on 1..=5 put the median on 3; all
    /// the weight on one value puts every quantile there.
    #[test]
    fn weighted_quantiles() {
        let v = [1.0, 2.0, 3.0, 4.0, 5.0];
        let q = quantiles(&v, &[0.2; 5]);
        assert!((q.median - 3.0).abs() < 1e-12, "{q:?}");
        assert_eq!(q.p05, 1.0);
        assert_eq!(q.p95, 5.0);
        let q = quantiles(&v, &[0.0, 0.0, 0.0, 1.0, 0.0]);
        assert_eq!((q.p05, q.median, q.p95), (4.0, 4.0, 4.0));
    }

    /// The trapezoid weights integrate a linear function exactly.
    #[test]
    fn trapezoid_weights() {
        let u = [0.0, 0.5, 2.0, 2.25];
        let w = trapezoid(&u);
        let integral: f64 = u.iter().zip(&w).map(|(x, w)| (1.0 + 3.0 * x) * w).sum();
        assert!((integral - (2.25 + 1.5 * 2.25 * 2.25)).abs() < 1e-12);
    }

    /// Which pairs infer takes: pga or pgv first, a scaling IM of the
    /// ground second.
    #[test]
    fn pairs_infer_takes() {
        let pair = |s: &str| ImPair::parse(s).unwrap().unwrap();
        assert!(inferable_pair(pair("pga,pgv")).is_ok());
        assert!(inferable_pair(pair("pgv,sa(1.0)")).is_ok());
        let e = inferable_pair(pair("pga,pfa")).unwrap_err();
        assert!(e.contains("not pfa"), "{e}");
        let e = inferable_pair(pair("pga,pgv/pga")).unwrap_err();
        assert!(e.contains("not pgv/pga"), "{e}");
        let e = inferable_pair(pair("sa(1.0),pga")).unwrap_err();
        assert!(e.contains("not sa(1.0)"), "{e}");
    }
}
