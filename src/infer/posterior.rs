//! Prior, posterior and the posterior's Monte Carlo error.
//!
//! On the grid u = ln x the posterior density is prior(u) · L(u)
//! normalised by the trapezoidal rule in u (the density linear in u
//! between points, so the CDF is quadratic there and its quantiles are
//! solved in closed form). Densities are reported per unit IM
//! (density in u divided by x). The 90 % interval is equal-tailed (5 % and
//! 95 %); the mode is the grid point of largest density per unit IM.
//!
//! **Prior.** Log-uniform over the grid: 1/(u_max − u_min) in u. From a
//! hazard curve λ(x): the density of the IM given that shaking above the
//! grid's lowest level occurred, −dλ/dx / λ(x_min), i.e. k(u) λ(u)/λ(x_min)
//! in u with k the hazard's log–log slope; it is truncated at the grid's
//! highest level like the likelihood.
//!
//! **Monte Carlo error.** A bootstrap of the simulations ([`mc_error`]):
//! each replicate draws the study's records with replacement and, for every
//! (kind, level, record), resamples its D draws' outcomes with replacement,
//! then infers again; the standard deviation of each bound over the
//! replicates is its Monte Carlo error (the part of its uncertainty that
//! more records and draws would remove). Replicate b draws from its own
//! stream seeded by (seed, b), so the error is the same on any thread count.

use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;
use serde::Serialize;

use super::likelihood::{Grid, joint, kind_curves, naive};
use super::simulate::{Cell, Table};
use super::survey::Survey;
use crate::detmath as dm;
use crate::risk::HazardCurve;

/// The prior of the IM.
#[derive(Clone, Debug, PartialEq)]
pub enum Prior {
    /// Uniform in ln IM over the grid.
    LogUniform,
    /// From a site's hazard curve (in the IM's unit).
    Hazard(Box<HazardCurve>),
}

impl Prior {
    /// The prior density per unit ln IM at each grid point.
    pub fn density_u(&self, grid: &Grid) -> Vec<f64> {
        let (u0, u1) = (grid.u[0], grid.u[grid.len() - 1]);
        match self {
            Prior::LogUniform => vec![1.0 / (u1 - u0); grid.len()],
            Prior::Hazard(h) => {
                let at_min = h.rate_at(grid.x[0]);
                // The log–log slope by a central difference: the segment's
                // slope inside a segment, the mean of both at a level.
                const H: f64 = 1e-6;
                grid.u
                    .iter()
                    .map(|&u| {
                        let ln_rate = |v: f64| dm::ln(h.rate_at(dm::exp(v)));
                        let slope = (ln_rate(u - H) - ln_rate(u + H)) / (2.0 * H);
                        slope.max(0.0) * h.rate_at(dm::exp(u)) / at_min
                    })
                    .collect()
            }
        }
    }
}

/// A posterior on the grid and what is read from it.
#[derive(Clone, Debug, PartialEq)]
pub struct Posterior {
    /// Density per unit IM at each grid point.
    pub density: Vec<f64>,
    /// Cumulative probability at each grid point.
    pub cdf: Vec<f64>,
    /// The bounds and the mode.
    pub summary: Summary,
    /// Which sides of the intensity the likelihood bounds within the grid.
    pub bounds: Bounds,
}

/// The likelihood at an end of the grid, relative to its peak, at or above
/// which the data do not bound the intensity on that side: there the
/// posterior is cut by the grid's end (the lowest or highest level), not
/// by the data, and the interval's bound on that side is the grid's.
pub const OPEN_EDGE: f64 = 0.05;

/// Which sides of the intensity the data bound: whether the likelihood has
/// fallen below [`OPEN_EDGE`] of its peak at the lowest and at the highest
/// grid point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Bounds {
    /// Both: the interval is the data's.
    Both,
    /// Only from below (e.g. everything overturned): the intensity was at
    /// least the 5 % bound; the median and the 95 % bound are set by the
    /// highest level and the prior.
    LowerOnly,
    /// Only from above (e.g. nothing overturned): the intensity was at most
    /// the 95 % bound; the median and the 5 % bound are set by the lowest
    /// level and the prior.
    UpperOnly,
    /// Neither: the posterior is mostly the prior over the grid.
    Neither,
}

impl Bounds {
    /// From ln L at the grid points.
    pub fn of(ln_l: &[f64]) -> Bounds {
        let top = ln_l
            .iter()
            .copied()
            .filter(|l| l.is_finite())
            .fold(f64::NEG_INFINITY, f64::max);
        let open = |l: f64| l.is_finite() && l - top >= dm::ln(OPEN_EDGE);
        match (open(ln_l[0]), open(ln_l[ln_l.len() - 1])) {
            (false, false) => Bounds::Both,
            (false, true) => Bounds::LowerOnly,
            (true, false) => Bounds::UpperOnly,
            (true, true) => Bounds::Neither,
        }
    }

    /// Its keyword (`both`, `lower-only`, `upper-only`, `neither`).
    pub fn name(self) -> &'static str {
        match self {
            Bounds::Both => "both",
            Bounds::LowerOnly => "lower-only",
            Bounds::UpperOnly => "upper-only",
            Bounds::Neither => "neither",
        }
    }
}

/// What an inference reports of a posterior (IM unit).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// Median.
    pub median: f64,
    /// 5th percentile.
    pub p05: f64,
    /// 95th percentile.
    pub p95: f64,
    /// Grid point of largest density per unit IM.
    pub mode: f64,
}

impl Posterior {
    /// prior(u) · L(u) normalised (see the [module docs](self)); `None`
    /// when the likelihood is 0 wherever the prior is not.
    pub fn new(grid: &Grid, prior_u: &[f64], ln_l: &[f64]) -> Option<Posterior> {
        let top = ln_l
            .iter()
            .zip(prior_u)
            .filter(|(l, p)| l.is_finite() && **p > 0.0)
            .map(|(l, _)| *l)
            .fold(f64::NEG_INFINITY, f64::max);
        if top == f64::NEG_INFINITY {
            return None;
        }
        let w: Vec<f64> = ln_l
            .iter()
            .zip(prior_u)
            .map(|(&l, &p)| p * dm::exp(l - top))
            .collect();
        let mut cdf = vec![0.0; w.len()];
        for i in 1..w.len() {
            cdf[i] = cdf[i - 1] + 0.5 * (w[i - 1] + w[i]) * (grid.u[i] - grid.u[i - 1]);
        }
        let z = cdf[w.len() - 1];
        if !(z > 0.0 && z.is_finite()) {
            return None;
        }
        let g: Vec<f64> = w.iter().map(|v| v / z).collect();
        cdf.iter_mut().for_each(|c| *c /= z);
        let density: Vec<f64> = g.iter().zip(&grid.x).map(|(d, x)| d / x).collect();
        let mode = density
            .iter()
            .enumerate()
            .fold(0, |best, (i, &d)| if d > density[best] { i } else { best });
        let quantile = |q: f64| quantile(grid, &g, &cdf, q);
        Some(Posterior {
            summary: Summary {
                median: quantile(0.5),
                p05: quantile(0.05),
                p95: quantile(0.95),
                mode: grid.x[mode],
            },
            density,
            cdf,
            bounds: Bounds::of(ln_l),
        })
    }
}

/// The IM at cumulative probability q: the density (per unit u) linear
/// between grid points, the CDF quadratic, solved in closed form.
fn quantile(grid: &Grid, g: &[f64], cdf: &[f64], q: f64) -> f64 {
    let n = cdf.len();
    let i = cdf.partition_point(|&c| c <= q).clamp(1, n - 1) - 1;
    let h = grid.u[i + 1] - grid.u[i];
    // C(t) = C_i + h (g_i t + (g_{i+1} − g_i) t²/2) = q, t ∈ [0, 1].
    let (a, b, c) = (0.5 * h * (g[i + 1] - g[i]), h * g[i], cdf[i] - q);
    let disc = (b * b - 4.0 * a * c).max(0.0);
    let den = b + disc.sqrt();
    let t = if den > 0.0 {
        (-2.0 * c / den).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dm::exp(grid.u[i] + t * h)
}

/// Both methods' summaries of one (resampled) table, `None` where a
/// method's likelihood vanishes.
pub fn summaries(
    table: &Table,
    survey: &Survey,
    grid: &Grid,
    prior_u: &[f64],
) -> (Option<Summary>, Option<Summary>) {
    let (joint, naive) = posteriors(table, survey, grid, prior_u);
    (joint.map(|p| p.summary), naive.map(|p| p.summary))
}

/// Both methods' posteriors of one (resampled) table, `None` where a
/// method's likelihood vanishes.
fn posteriors(
    table: &Table,
    survey: &Survey,
    grid: &Grid,
    prior_u: &[f64],
) -> (Option<Posterior>, Option<Posterior>) {
    let joint = Posterior::new(grid, prior_u, &joint(table, survey, grid));
    let curves = kind_curves(table, survey, grid);
    let naive = Posterior::new(grid, prior_u, &naive(&curves, survey, grid));
    (joint, naive)
}

/// The standard deviations of a method's bounds over the bootstrap.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct McError {
    /// Of the median.
    pub median: f64,
    /// Of the 5th percentile.
    pub p05: f64,
    /// Of the 95th percentile.
    pub p95: f64,
    /// Replicates behind it (those whose likelihood did not vanish).
    pub replicates: usize,
}

impl McError {
    fn of(summaries: &[Summary]) -> Option<McError> {
        let sd = |f: fn(&Summary) -> f64| {
            let n = summaries.len() as f64;
            let mean = summaries.iter().map(f).sum::<f64>() / n;
            (summaries
                .iter()
                .map(|s| (f(s) - mean) * (f(s) - mean))
                .sum::<f64>()
                / (n - 1.0))
                .sqrt()
        };
        (summaries.len() >= 2).then(|| McError {
            median: sd(|s| s.median),
            p05: sd(|s| s.p05),
            p95: sd(|s| s.p95),
            replicates: summaries.len(),
        })
    }
}

/// splitmix64 finaliser.
fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The seed of bootstrap replicate `b`.
pub(super) fn replicate_seed(seed: u64, b: u64) -> u64 {
    // "rockfrag:infer:bootstrap" domain tag (an arbitrary odd constant).
    splitmix64(splitmix64(seed ^ 0xB007_57A9_1AF3_0001) ^ splitmix64(b))
}

/// `table` with its records drawn with replacement and every cell's draws
/// resampled with replacement, from `rng`.
fn resample(table: &Table, rng: &mut Xoshiro256PlusPlus) -> Table {
    resample_picks(table, rng).0
}

/// [`resample`], and the records drawn (replicate record s is the table's
/// record `picks[s]`).
pub(super) fn resample_picks(table: &Table, rng: &mut Xoshiro256PlusPlus) -> (Table, Vec<usize>) {
    let (n, nl) = (table.records, table.levels.len());
    let picks: Vec<usize> = (0..n)
        .map(|_| ((rng.random::<f64>() * n as f64) as usize).min(n - 1))
        .collect();
    let mut im = vec![0.0; nl * n];
    for l in 0..nl {
        for (s, &r) in picks.iter().enumerate() {
            im[l * n + s] = table.im(l, r);
        }
    }
    let mut cells = Vec::with_capacity(table.cells.len());
    for j in 0..table.kinds {
        for l in 0..nl {
            for &r in &picks {
                let c = table.cell(j, l, r);
                let v = c.valid();
                let (po, ps) = if v == 0 {
                    (0.0, 0.0)
                } else {
                    (
                        f64::from(c.overturned) / f64::from(v),
                        f64::from(c.overturned + c.slid) / f64::from(v),
                    )
                };
                let mut out = Cell {
                    overturned: 0,
                    slid: 0,
                    ..c
                };
                // A cell of one outcome (e.g. a kind with nothing drawn) stays.
                let one_outcome = ps == 0.0 || po == 1.0 || (po == 0.0 && ps == 1.0);
                if v == 0 || one_outcome {
                    out.overturned = c.overturned;
                    out.slid = c.slid;
                } else {
                    for _ in 0..v {
                        let x = rng.random::<f64>();
                        if x < po {
                            out.overturned += 1;
                        } else if x < ps {
                            out.slid += 1;
                        }
                    }
                }
                cells.push(out);
            }
        }
    }
    let t = Table {
        kinds: table.kinds,
        levels: table.levels.clone(),
        records: n,
        im,
        cells,
        fixed: table.fixed.clone(),
    };
    (t, picks)
}

/// The Monte Carlo error of both methods' bounds from `replicates`
/// bootstrap replicates (see the [module docs](self)); `None` for a method
/// with fewer than two usable replicates. Also the joint posterior's
/// pointwise Monte Carlo band ([`McBand`]).
pub fn mc_error(
    table: &Table,
    survey: &Survey,
    grid: &Grid,
    prior_u: &[f64],
    replicates: usize,
    seed: u64,
) -> (Option<McError>, Option<McError>, Option<McBand>) {
    let results: Vec<(Option<Posterior>, Option<Summary>)> = (0..replicates as u64)
        .into_par_iter()
        .map(|b| {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(replicate_seed(seed, b));
            let t = resample(table, &mut rng);
            let (joint, naive) = posteriors(&t, survey, grid, prior_u);
            (joint, naive.map(|p| p.summary))
        })
        .collect();
    let joint: Vec<Summary> = results
        .iter()
        .filter_map(|r| r.0.as_ref().map(|p| p.summary))
        .collect();
    let naive: Vec<Summary> = results.iter().filter_map(|r| r.1).collect();
    let densities: Vec<&[f64]> = results
        .iter()
        .filter_map(|r| r.0.as_ref().map(|p| p.density.as_slice()))
        .collect();
    (
        McError::of(&joint),
        McError::of(&naive),
        McBand::of(&densities, grid.len()),
    )
}

/// The joint posterior's pointwise Monte Carlo band: at each grid point,
/// the 5th and 95th percentiles of the bootstrap replicates' densities (per
/// unit IM). A posterior made of a few records' bumps moves from replicate
/// to replicate, and its band is wide where it does.
#[derive(Clone, Debug, PartialEq)]
pub struct McBand {
    /// 5th percentile of the density at each grid point.
    pub lo: Vec<f64>,
    /// 95th percentile.
    pub hi: Vec<f64>,
    /// Replicates behind it.
    pub replicates: usize,
}

impl McBand {
    fn of(densities: &[&[f64]], points: usize) -> Option<McBand> {
        if densities.len() < 2 {
            return None;
        }
        let mut lo = Vec::with_capacity(points);
        let mut hi = Vec::with_capacity(points);
        let mut column = vec![0.0; densities.len()];
        for i in 0..points {
            for (c, d) in column.iter_mut().zip(densities) {
                *c = d[i];
            }
            column.sort_by(f64::total_cmp);
            lo.push(sorted_quantile(&column, 0.05));
            hi.push(sorted_quantile(&column, 0.95));
        }
        Some(McBand {
            lo,
            hi,
            replicates: densities.len(),
        })
    }
}

/// The `q`-quantile of `sorted` (ascending, not empty), linear between
/// order statistics.
fn sorted_quantile(sorted: &[f64], q: f64) -> f64 {
    let h = q * (sorted.len() - 1) as f64;
    let (i, t) = (h.floor() as usize, h - h.floor());
    match sorted.get(i + 1) {
        Some(next) => sorted[i] + t * (next - sorted[i]),
        None => sorted[i],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(x: &[f64]) -> Grid {
        Grid {
            x: x.to_vec(),
            u: x.iter().map(|&v| dm::ln(v)).collect(),
            exact: true,
        }
    }

    /// A flat prior times a flat likelihood: the quantiles of a log-uniform,
    /// exactly.
    #[test]
    fn log_uniform_quantiles() {
        let g = grid(&[0.1, 0.2, 0.4, 0.8, 1.6]);
        let prior = Prior::LogUniform.density_u(&g);
        let p = Posterior::new(&g, &prior, &[0.0; 5]).unwrap();
        let span = dm::ln(16.0);
        for (q, got) in [
            (0.05, p.summary.p05),
            (0.5, p.summary.median),
            (0.95, p.summary.p95),
        ] {
            let want = 0.1 * dm::exp(q * span);
            assert!((got / want - 1.0).abs() < 1e-12, "{q}: {got} {want}");
        }
        assert!((p.cdf[4] - 1.0).abs() < 1e-15);
    }

    /// The likelihood's ends against its peak: below 5 % at both ends is
    /// bounded; a likelihood still at its peak at the highest level (all
    /// overturned) bounds the intensity from below only, and the mirror
    /// from above only.
    #[test]
    fn bounds_follow_the_likelihood_at_the_grid_ends() {
        let ln = |v: &[f64]| v.iter().map(|&x| dm::ln(x)).collect::<Vec<_>>();
        assert_eq!(Bounds::of(&ln(&[0.01, 1.0, 0.04])), Bounds::Both);
        assert_eq!(Bounds::of(&ln(&[0.0, 0.5, 1.0])), Bounds::LowerOnly);
        assert_eq!(Bounds::of(&ln(&[1.0, 0.3, 0.06])), Bounds::Neither);
        assert_eq!(Bounds::of(&ln(&[0.9, 1.0, 0.049])), Bounds::UpperOnly);
    }

    /// A likelihood that is 0 below a level and 1 from it: the posterior is
    /// the prior restricted there, the median in the middle of the ramp's
    /// mass as the trapezoid rule gives it.
    #[test]
    fn a_step_restricts_the_prior() {
        let g = grid(&[0.1, 0.2, 0.4, 0.8]);
        let prior = Prior::LogUniform.density_u(&g);
        let ln_l = [f64::NEG_INFINITY, f64::NEG_INFINITY, 0.0, 0.0];
        let p = Posterior::new(&g, &prior, &ln_l).unwrap();
        assert_eq!(p.density[0], 0.0);
        assert_eq!(p.density[1], 0.0);
        // Equal density per unit ln IM at the two points where L = 1.
        assert!((p.density[2] * 0.4 / (p.density[3] * 0.8) - 1.0).abs() < 1e-14);
        assert!(p.summary.p05 > 0.2 && p.summary.p95 <= 0.8);
        assert!(Posterior::new(&g, &prior, &[f64::NEG_INFINITY; 4]).is_none());
    }
}
