//! The likelihood of a survey at each intensity of the grid, two ways.
//!
//! **Joint** (every object at the site felt the same motion): for record r
//! at intensity x, kind j's D draws give the fractions p_o(x, r) that
//! overturned and p_s(x, r) that slid (standing), and the probability of
//! the survey's (k_j, s_j) of n_j under the record is averaged over the
//! records:
//!
//! ```text
//! L(x) = (1/R) Σ_r Π_j ℓ_j(x, r)
//! ```
//!
//! The fractions are known at the study's levels and interpolated linearly
//! in ln x between a record's levels: a record's ℓ(x) is sharp (many
//! objects pin down the scaling at which it gives the survey) and would
//! fall between levels, while its fractions change smoothly. The grid has
//! [`InferSettings::refine`](crate::spec::InferSettings::refine) points per
//! level interval.
//!
//! ℓ_j is the probability of the counts *given what the D draws showed*:
//! with the fraction p known only from D draws (Jeffreys prior, p ~
//! Beta(D p + ½, D (1 − p) + ½)), the counts are beta-binomial
//! (Dirichlet-multinomial with slides),
//!
//! ```text
//! ℓ = C(n, k) B(k + α, n − k + β) / B(α, β),   α = D p + ½,  β = D (1 − p) + ½,
//! ```
//!
//! which tends to the binomial C(n, k) p^k (1 − p)^(n − k) as D grows.
//! Plugging the estimated fraction into the binomial instead makes each
//! record's ℓ too sharp when D is not much larger than n, and the posterior
//! overconfident. A kind with nothing drawn has exact fractions (0 or 1)
//! and takes the binomial.
//!
//! **Naive** (each object its own earthquake): each kind's fragility curve
//! is fitted over all its analyses (probit MLE, [`fit_lognormal`]), and
//!
//! ```text
//! L_naive(x) = Π_j Binomial(k_j | n_j, Φ(ln(x/θ_j)/β_j))
//! ```
//!
//! (with slides, the multinomial with P(slid, standing) = F_slide − F_o).
//! A kind whose curve cannot be fitted (e.g. no property uncertainty: its
//! stripes are separated) uses its pooled stripe fractions instead.
//!
//! **Grid.** When the study's levels are in the inferred IM, every record
//! has the level's IM and the grid is the levels, refined. Otherwise
//! (scale factors, or PGV inferred on PGA levels) each record has its own
//! IM at each level; the grid then spans the range every record covers.

use super::simulate::{Cell, Table};
use super::survey::{Kind, Survey};
use crate::detmath::{self as dm, ln_binomial};
use crate::error::{Error, Result};
use crate::fragility::{LognormalFit, Observation, Unfit, fit_lognormal};

/// Where the posterior is evaluated.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Intensities, ascending.
    pub x: Vec<f64>,
    /// Their logarithms.
    pub u: Vec<f64>,
    /// Whether the grid is the levels, refined (every record at a level has
    /// its IM).
    pub exact: bool,
}

/// The spec's level indices by increasing level.
fn order(levels: &[f64]) -> Vec<usize> {
    let mut o: Vec<usize> = (0..levels.len()).collect();
    o.sort_by(|&a, &b| levels[a].total_cmp(&levels[b]));
    o
}

impl Grid {
    /// The grid of `table`: its levels when `exact`, else the range every
    /// record covers; `refine` intervals (geometric) per level interval.
    ///
    /// Errors: [`Error::InvalidParameter`] with fewer than two distinct
    /// levels, or records whose IMs share no range.
    pub fn new(table: &Table, exact: bool, refine: usize) -> Result<Grid> {
        let refine = refine.max(1);
        let o = order(&table.levels);
        if o.len() < 2
            || o.windows(2)
                .any(|w| table.levels[w[0]] >= table.levels[w[1]])
        {
            return Err(Error::invalid(
                "grid levels",
                format!("{:?}", table.levels),
                "at least two distinct intensity levels for an inference",
            ));
        }
        let geometric = |lo: f64, hi: f64, n: usize| -> Vec<f64> {
            let (a, b) = (dm::ln(lo), dm::ln(hi));
            (0..n)
                .map(|i| match i {
                    0 => lo,
                    i => dm::exp(a + (b - a) * i as f64 / n as f64),
                })
                .collect()
        };
        let x: Vec<f64> = if exact {
            let levels: Vec<f64> = o.iter().map(|&l| table.levels[l]).collect();
            let mut x: Vec<f64> = levels
                .windows(2)
                .flat_map(|w| geometric(w[0], w[1], refine))
                .collect();
            x.push(levels[levels.len() - 1]);
            x
        } else {
            let (first, last) = (o[0], o[o.len() - 1]);
            let lo = (0..table.records)
                .map(|r| table.im(first, r))
                .fold(0.0, f64::max);
            let hi = (0..table.records)
                .map(|r| table.im(last, r))
                .fold(f64::INFINITY, f64::min);
            if !(lo > 0.0 && hi > lo) {
                return Err(Error::invalid(
                    "grid levels",
                    format!("{:?}", table.levels),
                    &format!(
                        "levels whose records share a range of measured IM (every record's \
                         lowest is at most {lo}, its highest at least {hi}): widen the levels"
                    ),
                ));
            }
            let mut x = geometric(lo, hi, refine * (o.len() - 1));
            x.push(hi);
            x
        };
        Ok(Grid {
            u: x.iter().map(|&v| dm::ln(v)).collect(),
            x,
            exact,
        })
    }

    /// Points.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether the grid has no points (never, once built).
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }
}

/// Where grid point i falls among record r's levels: levels a and b and
/// the weight t of b (ln-linear), for every (record, point).
pub(super) struct Brackets {
    /// (a, b, t) of record r at grid point i, at `r · points + i`.
    pub(super) at: Vec<(usize, usize, f64)>,
    points: usize,
}

impl Brackets {
    pub(super) fn new(table: &Table, grid: &Grid) -> Brackets {
        let o = order(&table.levels);
        let mut at = Vec::with_capacity(table.records * grid.len());
        for r in 0..table.records {
            let xs: Vec<f64> = o.iter().map(|&l| table.im(l, r)).collect();
            for &x in &grid.x {
                let i = xs.partition_point(|&v| v <= x).clamp(1, xs.len() - 1) - 1;
                let (a, b) = (xs[i], xs[i + 1]);
                let t = if x <= a {
                    0.0
                } else if x >= b {
                    1.0
                } else {
                    (dm::ln(x) - dm::ln(a)) / (dm::ln(b) - dm::ln(a))
                };
                at.push((o[i], o[i + 1], t));
            }
        }
        Brackets {
            at,
            points: grid.len(),
        }
    }

    /// `values[level]` of record r interpolated at grid point i.
    pub(super) fn value(&self, r: usize, i: usize, values: impl Fn(usize) -> f64) -> f64 {
        let (a, b, t) = self.at[r * self.points + i];
        if t == 0.0 {
            values(a)
        } else if t == 1.0 {
            values(b)
        } else {
            (1.0 - t) * values(a) + t * values(b)
        }
    }
}

/// k · ln p, with 0 · ln 0 = 0.
fn k_ln(k: u64, p: f64) -> f64 {
    if k == 0 { 0.0 } else { k as f64 * dm::ln(p) }
}

/// The fractions (overturned, slid and standing) of a cell's draws,
/// `None` when every draw failed.
fn fractions(c: Cell) -> Option<(f64, f64)> {
    let v = f64::from(c.valid());
    (v > 0.0).then(|| (f64::from(c.overturned) / v, f64::from(c.slid) / v))
}

/// ln of the multinomial probability of (k overturned, s slid, the rest
/// standing) of n with probabilities p_o and p_s.
fn multinomial(n: u64, k: u64, s: u64, p_o: f64, p_s: f64) -> f64 {
    let rest = n - k - s;
    ln_binomial(n, k)
        + ln_binomial(n - k, s)
        + k_ln(k, p_o)
        + k_ln(s, p_s)
        + k_ln(rest, (1.0 - p_o - p_s).max(0.0))
}

/// ln ℓ of kind `kind`'s counts under exact fractions (p_o, p_s): the
/// multinomial (slides count as standing when the kind has no slide count).
pub fn ln_term(kind: &Kind, p_o: f64, p_s: f64) -> f64 {
    match kind.slid {
        Some(s) => multinomial(kind.count, kind.overturned, s, p_o, p_s),
        None => multinomial(kind.count, kind.overturned, 0, p_o, 0.0),
    }
}

/// ln ℓ of kind `kind`'s counts under fractions (p_o, p_s) estimated from
/// `draws` draws: the Dirichlet-multinomial with α = draws · p + ½ per
/// category (the beta-binomial without slides).
pub fn ln_term_estimated(kind: &Kind, p_o: f64, p_s: f64, draws: f64) -> f64 {
    let (n, k) = (kind.count, kind.overturned);
    let (counts, fractions): (Vec<u64>, Vec<f64>) = match kind.slid {
        Some(s) => (vec![k, s, n - k - s], vec![p_o, p_s, 1.0 - p_o - p_s]),
        None => (vec![k, n - k], vec![p_o, 1.0 - p_o]),
    };
    let alpha: Vec<f64> = fractions
        .iter()
        .map(|&p| draws * p.max(0.0) + 0.5)
        .collect();
    let a: f64 = alpha.iter().sum();
    let mut ln = dm::ln_factorial(n) + dm::ln_gamma(a) - dm::ln_gamma(n as f64 + a);
    for (&x, &al) in counts.iter().zip(&alpha) {
        ln += dm::ln_gamma(x as f64 + al) - dm::ln_gamma(al) - dm::ln_factorial(x);
    }
    ln
}

/// ln Π_j ℓ_j(x_i, r) for every record r and grid point i, at `r · points + i`.
pub(super) fn record_terms(table: &Table, survey: &Survey, grid: &Grid) -> Vec<f64> {
    let nl = table.levels.len();
    let brackets = Brackets::new(table, grid);
    let g = grid.len();
    // The fractions of every (kind, level, record) and their draws.
    let f: Vec<Option<(f64, f64)>> = table.cells.iter().map(|&c| fractions(c)).collect();
    let valid = |j: usize, l: usize, r: usize| f64::from(table.cell(j, l, r).valid());
    // ln Π_j ℓ_j(x_i, r), record-major.
    let mut terms = vec![0.0; table.records * g];
    for r in 0..table.records {
        for i in 0..g {
            let (a, b, t) = brackets.at[r * g + i];
            terms[r * g + i] = survey
                .kinds
                .iter()
                .enumerate()
                .map(|(j, kind)| {
                    let at = |l: usize| f[(j * nl + l) * table.records + r];
                    match (at(a), at(b)) {
                        (Some(fa), Some(fb)) => {
                            let mix = |x: f64, y: f64| {
                                if t == 0.0 {
                                    x
                                } else if t == 1.0 {
                                    y
                                } else {
                                    (1.0 - t) * x + t * y
                                }
                            };
                            let (p_o, p_s) = (mix(fa.0, fb.0), mix(fa.1, fb.1));
                            if table.fixed[j] {
                                ln_term(kind, p_o, p_s)
                            } else {
                                let d = mix(valid(j, a, r), valid(j, b, r));
                                ln_term_estimated(kind, p_o, p_s, d)
                            }
                        }
                        // No outcome at a level: no information from it.
                        _ => 0.0,
                    }
                })
                .sum();
        }
    }
    terms
}

/// The terms scaled by their largest, and that largest (−∞ when every term
/// is).
pub(super) fn scaled(terms: &[f64]) -> (Vec<f64>, f64) {
    let m = terms
        .iter()
        .copied()
        .filter(|t| t.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    if m == f64::NEG_INFINITY {
        return (vec![0.0; terms.len()], m);
    }
    (terms.iter().map(|&t| dm::exp(t - m)).collect(), m)
}

/// ln L(x) of the joint method at every grid point (−∞ where the survey
/// is impossible under every record).
pub fn joint(table: &Table, survey: &Survey, grid: &Grid) -> Vec<f64> {
    let g = grid.len();
    let (scaled, m) = scaled(&record_terms(table, survey, grid));
    if m == f64::NEG_INFINITY {
        return vec![f64::NEG_INFINITY; g];
    }
    (0..g)
        .map(|i| {
            let sum: f64 = (0..table.records).map(|r| scaled[r * g + i]).sum();
            dm::ln(sum / table.records as f64) + m
        })
        .collect()
}

/// How many of the records the joint posterior effectively rests on:
/// (Σ w_r)²/Σ w_r², w_r the posterior mass record r contributes (its
/// likelihood times the prior, integrated over the grid). R when every
/// record explains the survey equally well, 1 when one record carries it:
/// a small number means a posterior made of a few records' bumps, whose
/// Monte Carlo error is large.
pub fn effective_records(table: &Table, survey: &Survey, grid: &Grid, prior_u: &[f64]) -> f64 {
    let g = grid.len();
    let (scaled, m) = scaled(&record_terms(table, survey, grid));
    if m == f64::NEG_INFINITY {
        return 0.0;
    }
    let w: Vec<f64> = (0..table.records)
        .map(|r| {
            (1..g)
                .map(|i| {
                    let f = |i: usize| scaled[r * g + i] * prior_u[i];
                    0.5 * (f(i - 1) + f(i)) * (grid.u[i] - grid.u[i - 1])
                })
                .sum()
        })
        .collect();
    let (s1, s2) = w.iter().fold((0.0, 0.0), |(a, b), &x| (a + x, b + x * x));
    if s2 > 0.0 { s1 * s1 / s2 } else { 0.0 }
}

/// One kind's fragility as the simulations give it.
#[derive(Clone, Debug, PartialEq)]
pub struct KindCurve {
    /// The lognormal fit of its overturning (θ, β), or why there is none.
    pub fit: std::result::Result<LognormalFit, Unfit>,
    /// The fit of its sliding limit state (overturned or slid), when the
    /// survey counts slides for it.
    pub slide_fit: Option<std::result::Result<LognormalFit, Unfit>>,
    /// Fraction of its draws overturned at each grid point, pooled over the
    /// records.
    pub pooled: Vec<f64>,
    /// The same for overturned or slid.
    pub pooled_slide: Vec<f64>,
    /// Its stripes: (IM, analyses, overturned) per level (per level and
    /// record when records have their own IMs).
    pub stripes: Vec<Observation>,
}

impl KindCurve {
    /// P(overturned) and P(slid, standing) at grid point i: the fits, or
    /// the pooled fractions where a curve could not be fitted.
    pub fn probabilities(&self, grid: &Grid, i: usize) -> (f64, f64) {
        let x = grid.x[i];
        let p_o = match &self.fit {
            Ok(f) => f.probability(x),
            Err(_) => self.pooled[i],
        };
        let p_s = match &self.slide_fit {
            None => 0.0,
            Some(Ok(f)) => f.probability(x),
            Some(Err(_)) => self.pooled_slide[i],
        };
        (p_o, (p_s - p_o).clamp(0.0, 1.0 - p_o))
    }
}

/// Each kind's fragility: the fits of the naive method and the pooled
/// fractions on the grid.
pub fn kind_curves(table: &Table, survey: &Survey, grid: &Grid) -> Vec<KindCurve> {
    let brackets = Brackets::new(table, grid);
    let nl = table.levels.len();
    survey
        .kinds
        .iter()
        .enumerate()
        .map(|(j, kind)| {
            let stripes = |slide: bool| -> Vec<Observation> {
                let count = |c: Cell| u64::from(c.overturned + if slide { c.slid } else { 0 });
                if grid.exact {
                    (0..nl)
                        .map(|l| {
                            let cells = (0..table.records).map(|r| table.cell(j, l, r));
                            Observation {
                                im: table.levels[l],
                                trials: cells.clone().map(|c| u64::from(c.valid())).sum(),
                                overturned: cells.map(count).sum(),
                            }
                        })
                        .collect()
                } else {
                    (0..nl)
                        .flat_map(|l| (0..table.records).map(move |r| (l, r)))
                        .map(|(l, r)| {
                            let c = table.cell(j, l, r);
                            Observation {
                                im: table.im(l, r),
                                trials: u64::from(c.valid()),
                                overturned: count(c),
                            }
                        })
                        .collect()
                }
            };
            let pooled = |slide: bool| -> Vec<f64> {
                let fraction = |l: usize, r: usize| {
                    let c = table.cell(j, l, r);
                    let k = c.overturned + if slide { c.slid } else { 0 };
                    if c.valid() == 0 {
                        0.0
                    } else {
                        f64::from(k) / f64::from(c.valid())
                    }
                };
                (0..grid.len())
                    .map(|i| {
                        (0..table.records)
                            .map(|r| brackets.value(r, i, |l| fraction(l, r)))
                            .sum::<f64>()
                            / table.records as f64
                    })
                    .collect()
            };
            let overturning = stripes(false);
            let counts_slides = kind.slid.is_some();
            KindCurve {
                fit: fit_lognormal(&overturning),
                slide_fit: counts_slides.then(|| fit_lognormal(&stripes(true))),
                pooled: pooled(false),
                pooled_slide: if counts_slides {
                    pooled(true)
                } else {
                    Vec::new()
                },
                stripes: overturning,
            }
        })
        .collect()
}

/// ln L(x) of the naive method at every grid point.
pub fn naive(curves: &[KindCurve], survey: &Survey, grid: &Grid) -> Vec<f64> {
    (0..grid.len())
        .map(|i| {
            survey
                .kinds
                .iter()
                .zip(curves)
                .map(|(kind, c)| {
                    let (p_o, p_s) = c.probabilities(grid, i);
                    multinomial(
                        kind.count,
                        kind.overturned,
                        kind.slid.unwrap_or(0),
                        p_o,
                        p_s,
                    )
                })
                .sum()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kind(n: u64, k: u64, slid: Option<u64>) -> Kind {
        Kind {
            name: "k".into(),
            line: 2,
            width: 0.4,
            aspect: 4.0,
            restitution: None,
            mu_s: None,
            mu_k: None,
            count: n,
            overturned: k,
            slid,
        }
    }

    /// The multinomial: with no slide count, a binomial; with one, three
    /// categories; impossible counts give −∞.
    #[test]
    fn terms_are_the_multinomial() {
        let t = dm::exp(ln_term(&kind(4, 1, None), 0.3, 0.5));
        assert!((t - 4.0 * 0.3 * 0.7 * 0.7 * 0.7).abs() < 1e-14, "{t}");
        // 4!/(1! 1! 2!) 0.3 · 0.2 · 0.5² = 12 · 0.015.
        let t = dm::exp(ln_term(&kind(4, 1, Some(1)), 0.3, 0.2));
        assert!((t - 12.0 * 0.3 * 0.2 * 0.25).abs() < 1e-14, "{t}");
        assert_eq!(ln_term(&kind(4, 1, None), 0.0, 0.0), f64::NEG_INFINITY);
        assert_eq!(ln_term(&kind(4, 4, None), 1.0, 0.0), 0.0);
    }

    /// The beta-binomial (and the Dirichlet-multinomial) is a distribution
    /// over the counts, wider than the binomial at few draws and equal to
    /// it in the limit.
    #[test]
    fn estimated_terms_sum_to_one_and_tend_to_the_binomial() {
        for slid in [false, true] {
            let mut total = 0.0;
            for k in 0..=6 {
                for s in 0..=(if slid { 6 - k } else { 0 }) {
                    let kd = kind(6, k, slid.then_some(s));
                    total += dm::exp(ln_term_estimated(&kd, 0.3, 0.2, 10.0));
                }
            }
            assert!((total - 1.0).abs() < 1e-12, "{total}");
        }
        let kd = kind(6, 2, None);
        let exact = ln_term(&kd, 0.3, 0.0);
        let few = ln_term_estimated(&kd, 0.3, 0.0, 10.0);
        let many = ln_term_estimated(&kd, 0.3, 0.0, 1e7);
        assert!(
            few < exact && (many - exact).abs() < 1e-6,
            "{few} {exact} {many}"
        );
    }
}
