//! `fragility_surface.csv`: the fragility surface P(LS | IM1, IM2) of each
//! case and limit state ([`SurfaceRow`], its writer and reader side by
//! side), fitted from the analyses of the same `outcomes.csv` read against
//! each IM ([`fit_surfaces`]), and the observed fractions a figure of it
//! marks ([`observed_bins`]).

use std::collections::BTreeMap;
use std::path::Path;

use super::data::{CaseData, Outcomes};
use super::fit::fit_lognormal;
use super::surface::{SurfacePoint, fit_surface, surface_status};
use crate::case::Case;
use crate::detmath::{self as dm, ln_binomial};
use crate::error::{Error, Result};
use crate::im::{Im, ImPair};
use crate::io_util::{csv_field, number, write_atomic};
use crate::table::Table;

/// The file's name, beside `fragility.csv`.
pub const SURFACE_FILE: &str = "fragility_surface.csv";

/// Header of `fragility_surface.csv`, one row per case and limit state, in
/// `fragility.csv`'s order. P(LS | x₁, x₂) = Φ(a + b1 ln x₁ + b2 ln x₂),
/// x₁ of `im1` and x₂ of `im2` in their units (`im1_unit`, `im2_unit`).
/// `se_*` are the standard errors from the observed information (every
/// analysis independent), `corr_*` the correlations of the coefficients,
/// `z_b2` = b2/se_b2. `n_points` counts the distinct (IM1, IM2) of the
/// analyses. `loglik` is the surface's maximum, `loglik_im1` that of the
/// one-IM curve against IM1 fitted alone to the same analyses, both of
/// the analyses as Bernoulli trials (without the binomial coefficients of
/// a grouping, which differ between the two, so that they compare; add
/// them back for `fragility.csv`'s `loglik`), `lr_chi2` = 2 (loglik − loglik_im1), the
/// likelihood-ratio statistic of IM2 (χ² with 1 degree of freedom: 3.84 at
/// the 5 % level). `im2_median` is the median IM2 of the analyses;
/// `median_im1_at_im2_median` the IM1 at which the surface gives 0.5
/// there, and `beta_im1_given_im2` = 1/b1 the dispersion of the curve in
/// IM1 at any fixed IM2. `median_im1_alone`, `beta_im1_alone`: the one-IM
/// curve fitted alone; `median_im1_equivalent`, `beta_im1_equivalent`: the
/// one-IM curve the surface implies over the records' own IM2 given IM1
/// (ln IM2 regressed on ln IM1 over the analyses; see
/// [`super::SurfaceFit::equivalent`]), which should be near the alone one
/// when the surface describes the data. `status`: `ok`,
/// `second-im-adds-nothing`, `first-im-adds-nothing`, `imprecise`,
/// `decreasing-in-im1` (numbers written), or why there is no surface
/// (`none-overturned`, `all-overturned`, `collinear`, `separated`,
/// `no-convergence`, `no-data`; numbers empty).
pub const SURFACE_HEADER: &str = "case_id,aspect,width,restitution,friction,mu_s,mu_k,\
limit_state,im1,im2,im1_unit,im2_unit,a,b1,b2,se_a,se_b1,se_b2,corr_a_b1,corr_a_b2,corr_b1_b2,\
z_b2,n_analyses,n_exceeded,n_points,loglik,loglik_im1,lr_chi2,im2_median,\
median_im1_at_im2_median,beta_im1_given_im2,median_im1_alone,beta_im1_alone,\
median_im1_equivalent,beta_im1_equivalent,iterations,status";

/// One row of `fragility_surface.csv` (see [`SURFACE_HEADER`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceRow {
    /// The case.
    pub case: Case,
    /// The limit state.
    pub limit_state: String,
    /// The two IMs.
    pub ims: ImPair,
    /// (a, b1, b2), `None` when not fitted.
    pub coefficients: Option<[f64; 3]>,
    /// Their standard errors.
    pub se: Option<[f64; 3]>,
    /// Correlations of (a, b1), (a, b2), (b1, b2).
    pub correlation: Option<[f64; 3]>,
    /// b2 / SE(b2).
    pub z_b2: Option<f64>,
    /// Successful analyses.
    pub n_analyses: usize,
    /// Analyses that exceeded the limit state.
    pub n_exceeded: usize,
    /// Distinct (IM1, IM2).
    pub n_points: usize,
    /// The surface's maximised log-likelihood.
    pub loglik: Option<f64>,
    /// The one-IM fit's, against IM1 alone.
    pub loglik_im1: Option<f64>,
    /// 2 (loglik − loglik_im1).
    pub lr_chi2: Option<f64>,
    /// Median IM2 of the analyses.
    pub im2_median: Option<f64>,
    /// IM1 at P = 0.5 at the median IM2.
    pub median_im1_at_im2_median: Option<f64>,
    /// 1/b1.
    pub beta_im1_given_im2: Option<f64>,
    /// The one-IM curve against IM1 fitted alone: (θ, β).
    pub alone: Option<(f64, f64)>,
    /// The one-IM curve the surface implies: (θ, β).
    pub equivalent: Option<(f64, f64)>,
    /// Newton iterations.
    pub iterations: Option<u32>,
    /// `ok`, a caveat, or why not fitted (see [`SURFACE_HEADER`]).
    pub status: String,
}

impl SurfaceRow {
    /// Whether the row has a surface (its numbers are written).
    pub fn is_fitted(&self) -> bool {
        self.coefficients.is_some()
    }

    /// The row's line, without its newline.
    pub fn line(&self) -> String {
        let o = |x: Option<f64>| x.filter(|v| !v.is_nan()).map_or(String::new(), number);
        let three = |x: Option<[f64; 3]>| [0, 1, 2].map(|i| o(x.map(|v| v[i])));
        let mut fields = vec![
            self.case.id(),
            self.case.fields(),
            self.limit_state.clone(),
            csv_field(self.ims.first().name()),
            csv_field(self.ims.second().name()),
            self.ims.first().unit().to_string(),
            self.ims.second().unit().to_string(),
        ];
        fields.extend(three(self.coefficients));
        fields.extend(three(self.se));
        fields.extend(three(self.correlation));
        fields.extend([
            o(self.z_b2),
            self.n_analyses.to_string(),
            self.n_exceeded.to_string(),
            self.n_points.to_string(),
            o(self.loglik),
            o(self.loglik_im1),
            o(self.lr_chi2),
            o(self.im2_median),
            o(self.median_im1_at_im2_median),
            o(self.beta_im1_given_im2),
            o(self.alone.map(|x| x.0)),
            o(self.alone.map(|x| x.1)),
            o(self.equivalent.map(|x| x.0)),
            o(self.equivalent.map(|x| x.1)),
            self.iterations.map_or(String::new(), |n| n.to_string()),
            self.status.clone(),
        ]);
        fields.join(",")
    }
}

/// The columns [`read_surface_csv`] reads, after the case's.
const COLUMNS: [&str; 30] = [
    "limit_state",
    "im1",
    "im2",
    "a",
    "b1",
    "b2",
    "se_a",
    "se_b1",
    "se_b2",
    "corr_a_b1",
    "corr_a_b2",
    "corr_b1_b2",
    "z_b2",
    "n_analyses",
    "n_exceeded",
    "n_points",
    "loglik",
    "loglik_im1",
    "lr_chi2",
    "im2_median",
    "median_im1_at_im2_median",
    "beta_im1_given_im2",
    "median_im1_alone",
    "beta_im1_alone",
    "median_im1_equivalent",
    "beta_im1_equivalent",
    "iterations",
    "status",
    "im1_unit",
    "im2_unit",
];

/// Reads `fragility_surface.csv`.
///
/// Errors: [`Error::Io`]; [`Error::Parse`] naming the file, line, column
/// and value of anything unreadable.
pub fn read_surface_csv(path: &Path) -> Result<Vec<SurfaceRow>> {
    let (mut table, c) = Table::open_dyn(path, &COLUMNS, "reading fragility_surface.csv")?;
    let mut rows = Vec::new();
    while let Some(row) = table.next_row()? {
        let opt = |i: usize| -> Result<Option<f64>> {
            match row.field(c[i]) {
                "" => Ok(None),
                _ => row.number(c[i]).map(Some),
            }
        };
        let three = |i: usize| -> Result<Option<[f64; 3]>> {
            Ok(match (opt(i)?, opt(i + 1)?, opt(i + 2)?) {
                (Some(x), Some(y), Some(z)) => Some([x, y, z]),
                _ => None,
            })
        };
        let both = |i: usize| -> Result<Option<(f64, f64)>> { Ok(opt(i)?.zip(opt(i + 1)?)) };
        let im = |i: usize| {
            row.field(c[i])
                .parse::<Im>()
                .map_err(|e| row.error(c[i], &e))
        };
        let ims = ImPair::new(im(1)?, im(2)?).map_err(|e| row.error(c[2], &e))?;
        let count = |i: usize| row.integer(c[i]).map(|n| n as usize);
        rows.push(SurfaceRow {
            case: row.case()?,
            limit_state: row.text(c[0])?.to_string(),
            ims,
            coefficients: three(3)?,
            se: three(6)?,
            correlation: three(9)?,
            z_b2: opt(12)?,
            n_analyses: count(13)?,
            n_exceeded: count(14)?,
            n_points: count(15)?,
            loglik: opt(16)?,
            loglik_im1: opt(17)?,
            lr_chi2: opt(18)?,
            im2_median: opt(19)?,
            median_im1_at_im2_median: opt(20)?,
            beta_im1_given_im2: opt(21)?,
            alone: both(22)?,
            equivalent: both(24)?,
            iterations: match row.field(c[26]) {
                "" => None,
                _ => Some(row.integer(c[26])? as u32),
            },
            status: row.text(c[27])?.to_string(),
        });
    }
    Ok(rows)
}

/// Writes `fragility_surface.csv` (header [`SURFACE_HEADER`]).
pub(crate) fn write_surface_csv(path: &Path, rows: &[SurfaceRow]) -> Result<()> {
    write_atomic(path, |w| {
        writeln!(w, "{SURFACE_HEADER}")?;
        for r in rows {
            writeln!(w, "{}", r.line())?;
        }
        Ok(())
    })
    .map_err(Error::io(path))
}

/// Each analysis of a case as (IM1, IM2), from the case read against each
/// IM (the same rows of the same file, in order). Errors: the two reads
/// disagree on the analyses.
fn paired(first: &CaseData, second: &CaseData) -> Result<Vec<(f64, f64)>> {
    let same = first.key == second.key
        && first.trials.len() == second.trials.len()
        && first
            .trials
            .iter()
            .zip(&second.trials)
            .all(|(x, y)| x.level == y.level && x.record == y.record);
    if !same {
        return Err(Error::invalid(
            "fragility.im",
            first.key.id(),
            "the same analyses read against both IMs of the surface",
        ));
    }
    Ok(first
        .trials
        .iter()
        .zip(&second.trials)
        .map(|(x, y)| (x.im, y.im))
        .collect())
}

/// The analyses of case `i` of `first` and `second` grouped by equal
/// (IM1, IM2), with the exceedances of limit state `k`.
fn points(first: &CaseData, pairs: &[(f64, f64)], k: usize) -> Vec<SurfacePoint> {
    let mut grouped: BTreeMap<(u64, u64), (u64, u64)> = BTreeMap::new();
    for (t, &(x1, x2)) in first.trials.iter().zip(pairs) {
        let e = grouped.entry((x1.to_bits(), x2.to_bits())).or_default();
        e.0 += 1;
        e.1 += u64::from(t.exceeds(k));
    }
    grouped
        .into_iter()
        .map(|((b1, b2), (trials, exceeded))| SurfacePoint {
            im1: f64::from_bits(b1),
            im2: f64::from_bits(b2),
            trials,
            exceeded,
        })
        .collect()
}

/// The median of `values` (of logs: the mean of the two middle ones for
/// an even count); `None` when empty.
fn median(mut values: Vec<f64>) -> Option<f64> {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(values[n / 2]),
        _ => Some(0.5 * (values[n / 2 - 1] + values[n / 2])),
    }
}

/// ln IM2 = α + γ ln IM1 + ε over the analyses, least squares: (α, γ, σ)
/// with σ the residuals' standard deviation; `None` with fewer than 3
/// analyses or one IM1.
fn relation(pairs: &[(f64, f64)]) -> Option<(f64, f64, f64)> {
    let n = pairs.len() as f64;
    if pairs.len() < 3 {
        return None;
    }
    let logs: Vec<(f64, f64)> = pairs.iter().map(|&(x, y)| (dm::ln(x), dm::ln(y))).collect();
    let mx = logs.iter().map(|l| l.0).sum::<f64>() / n;
    let my = logs.iter().map(|l| l.1).sum::<f64>() / n;
    let sxx: f64 = logs.iter().map(|l| (l.0 - mx) * (l.0 - mx)).sum();
    if sxx.is_nan() || sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = logs.iter().map(|l| (l.0 - mx) * (l.1 - my)).sum();
    let gamma = sxy / sxx;
    let rss: f64 = logs
        .iter()
        .map(|l| {
            let e = l.1 - my - gamma * (l.0 - mx);
            e * e
        })
        .sum();
    Some((my - gamma * mx, gamma, (rss / (n - 2.0)).sqrt()))
}

/// Fits the surface of every case and limit state of `first` (read
/// against IM1) and `second` (the same file read against IM2), in the
/// order of `fragility.csv` (case by case, limit states in order).
///
/// Errors: the two reads are of different analyses.
pub fn fit_surfaces(first: &Outcomes, second: &Outcomes) -> Result<Vec<SurfaceRow>> {
    let ims = ImPair::new(first.im, second.im)
        .map_err(|e| Error::invalid("fragility.im", first.im, &e))?;
    let mut rows = Vec::new();
    for (c1, c2) in first.cases.iter().zip(&second.cases) {
        let pairs = paired(c1, c2)?;
        for (k, ls) in first.limit_states.iter().enumerate() {
            let pts = points(c1, &pairs, k);
            let fit = fit_surface(&pts);
            let observations = c1.observations(k);
            let alone = fit_lognormal(&observations).ok();
            // each analysis a Bernoulli trial: the log-likelihoods without
            // their groupings' binomial coefficients, so that they compare
            let ln_c = |groups: &mut dyn Iterator<Item = (u64, u64)>| -> f64 {
                groups.map(|(n, z)| ln_binomial(n, z)).sum()
            };
            let surface_c = ln_c(&mut pts.iter().map(|p| (p.trials, p.exceeded)));
            let alone_c = ln_c(&mut observations.iter().map(|o| (o.trials, o.overturned)));
            let im2_median = median(pairs.iter().map(|p| dm::ln(p.1)).collect()).map(dm::exp);
            let mut row = SurfaceRow {
                case: c1.key,
                limit_state: ls.name.clone(),
                ims,
                coefficients: None,
                se: None,
                correlation: None,
                z_b2: None,
                n_analyses: c1.trials.len(),
                n_exceeded: c1.trials.iter().filter(|t| t.exceeds(k)).count(),
                n_points: pts.len(),
                loglik: None,
                loglik_im1: alone.map(|f| f.loglik - alone_c),
                lr_chi2: None,
                im2_median,
                median_im1_at_im2_median: None,
                beta_im1_given_im2: None,
                alone: alone.map(|f| (f.median(), f.beta())),
                equivalent: None,
                iterations: None,
                status: String::new(),
            };
            match fit {
                Ok(f) => {
                    row.coefficients = Some(f.coefficients());
                    row.se = Some(f.se());
                    row.correlation = Some([
                        f.correlation(0, 1),
                        f.correlation(0, 2),
                        f.correlation(1, 2),
                    ]);
                    row.z_b2 = Some(f.z_b2());
                    row.loglik = Some(f.loglik - surface_c);
                    row.lr_chi2 = row
                        .loglik
                        .zip(row.loglik_im1)
                        .map(|(l2, l1)| 2.0 * (l2 - l1));
                    row.median_im1_at_im2_median = im2_median.and_then(|m| f.im1_at(0.5, m));
                    row.beta_im1_given_im2 = (f.b1 > 0.0).then(|| 1.0 / f.b1);
                    row.equivalent = relation(&pairs).and_then(|r| f.equivalent(r));
                    row.iterations = Some(f.iterations);
                    row.status = surface_status(&f).to_string();
                }
                Err(reason) => row.status = reason.status().to_string(),
            }
            rows.push(row);
        }
    }
    Ok(rows)
}

/// Analyses of one bin of the plane and how many exceeded, at the
/// geometric means of their IM1 and IM2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObservedBin {
    /// Geometric mean IM1 of the bin's analyses.
    pub im1: f64,
    /// Geometric mean IM2.
    pub im2: f64,
    /// Analyses.
    pub trials: usize,
    /// Those that exceeded the limit state.
    pub exceeded: usize,
}

/// The observed fractions of case `case` against limit state `k`, in bins
/// of the plane: each stripe (intensity level) split into up to four bins
/// of IM2 with equal counts (one bin per ten analyses of the stripe, at
/// least one), each bin at the geometric means of its analyses' IM1 and
/// IM2.
pub fn observed_bins(first: &CaseData, second: &CaseData, k: usize) -> Result<Vec<ObservedBin>> {
    let pairs = paired(first, second)?;
    let mut stripes: BTreeMap<u64, Vec<(f64, f64, bool)>> = BTreeMap::new();
    for (t, &(x1, x2)) in first.trials.iter().zip(&pairs) {
        stripes
            .entry(t.level.to_bits())
            .or_default()
            .push((x1, x2, t.exceeds(k)));
    }
    let mut bins = Vec::new();
    for (_, mut stripe) in stripes {
        stripe.sort_by(|a, b| a.1.total_cmp(&b.1));
        let n = stripe.len();
        let count = (n / 10).clamp(1, 4);
        for b in 0..count {
            let part = &stripe[b * n / count..(b + 1) * n / count];
            let m = part.len() as f64;
            let mean_ln = |f: fn(&(f64, f64, bool)) -> f64| {
                dm::exp(part.iter().map(|p| dm::ln(f(p))).sum::<f64>() / m)
            };
            bins.push(ObservedBin {
                im1: mean_ln(|p| p.0),
                im2: mean_ln(|p| p.1),
                trials: part.len(),
                exceeded: part.iter().filter(|p| p.2).count(),
            });
        }
    }
    Ok(bins)
}
