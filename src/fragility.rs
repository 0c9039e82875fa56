//! Lognormal overturning fragility curves from a study's outcomes.
//!
//! P(overturn | IM = x) = Φ(ln(x/θ)/β), fitted per case by maximum likelihood
//! over the intensity stripes with a binomial likelihood per stripe (Baker
//! 2015, "Efficient analytical fragility function fitting using dynamic
//! structural analysis", *Earthquake Spectra* 31(1)). The fit is a probit GLM,
//! P = Φ(a + b ln x), θ = exp(−a/b), β = 1/b, solved by Fisher scoring
//! (iteratively reweighted least squares); the log-likelihood is concave, so
//! a few iterations converge, and the Fisher information gives standard errors
//! of θ and β by the delta method. Uncertainty bands come from a seeded
//! bootstrap over records (a record is shared by every stripe, so the same
//! resampled record indices are used in each stripe).
//!
//! A case whose runs all overturn, or none do, or whose stripes are perfectly
//! separated (every stripe 0 % below some intensity and 100 % above it), has
//! no finite maximum-likelihood fit; [`fit_probit`] says which instead of
//! returning a number.

use crate::error::{Error, Result};
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;
use statrs::distribution::{Continuous, ContinuousCDF, Normal};
use std::fmt;

/// One intensity stripe: `k` of `n` analyses overturned at intensity `im`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stripe {
    /// Intensity measure (> 0).
    pub im: f64,
    /// Analyses in the stripe.
    pub n: u32,
    /// Analyses that overturned.
    pub k: u32,
}

/// Why a case cannot be fitted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoFit {
    /// No analysis overturned: the median is above every intensity run.
    NoneOverturned,
    /// Every analysis overturned: the median is below every intensity run.
    AllOverturned,
    /// The stripes are perfectly separated (0 % below, 100 % above): β → 0.
    Separated,
    /// Fewer than two distinct intensities.
    TooFewStripes,
}

impl fmt::Display for NoFit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            NoFit::NoneOverturned => "no analysis overturned",
            NoFit::AllOverturned => "every analysis overturned",
            NoFit::Separated => "stripes perfectly separated (beta -> 0)",
            NoFit::TooFewStripes => "fewer than two intensity levels",
        })
    }
}

/// A fitted lognormal fragility curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    /// Median θ (IM units).
    pub median: f64,
    /// Logarithmic standard deviation β.
    pub beta: f64,
    /// Probit intercept a.
    pub a: f64,
    /// Probit slope b = 1/β.
    pub b: f64,
    /// Log-likelihood at the maximum.
    pub loglik: f64,
    /// Standard error of θ (delta method on the Fisher information).
    pub se_median: f64,
    /// Standard error of β.
    pub se_beta: f64,
    /// Fisher-scoring iterations used.
    pub iterations: usize,
}

impl Fit {
    /// P(overturn | IM = x).
    pub fn probability(&self, x: f64) -> f64 {
        std_normal().cdf((x / self.median).ln() / self.beta)
    }
}

fn std_normal() -> Normal {
    Normal::standard()
}

/// Fits P = Φ(a + b ln x) by maximum likelihood (Fisher scoring).
///
/// ```
/// use rockfrag::fragility::{fit_probit, Stripe};
/// let s = [Stripe { im: 0.2, n: 10, k: 1 }, Stripe { im: 0.5, n: 10, k: 5 }, Stripe { im: 1.0, n: 10, k: 9 }];
/// let fit = fit_probit(&s).unwrap();
/// assert!((fit.median - 0.5).abs() < 0.05);
/// ```
pub fn fit_probit(stripes: &[Stripe]) -> std::result::Result<Fit, NoFit> {
    let stripes: Vec<Stripe> = stripes.iter().copied().filter(|s| s.n > 0).collect();
    let total_n: u32 = stripes.iter().map(|s| s.n).sum();
    let total_k: u32 = stripes.iter().map(|s| s.k).sum();
    let mut ims: Vec<f64> = stripes.iter().map(|s| s.im).collect();
    ims.sort_by(f64::total_cmp);
    ims.dedup();
    if total_k == 0 {
        return Err(NoFit::NoneOverturned);
    }
    if total_k == total_n {
        return Err(NoFit::AllOverturned);
    }
    if ims.len() < 2 {
        return Err(NoFit::TooFewStripes);
    }
    // Separation: every stripe with survivors lies at or below every stripe
    // with overturns, with at most one intensity holding both.
    let max_survivor = stripes
        .iter()
        .filter(|s| s.k < s.n)
        .map(|s| s.im)
        .fold(f64::NEG_INFINITY, f64::max);
    let min_overturn = stripes
        .iter()
        .filter(|s| s.k > 0)
        .map(|s| s.im)
        .fold(f64::INFINITY, f64::min);
    if min_overturn >= max_survivor {
        return Err(NoFit::Separated);
    }
    let nd = std_normal();
    // Start from least squares on the empirical probits (clamped).
    let (mut a, mut b) = (0.0, 1.0);
    {
        let (mut sx, mut sy, mut sxx, mut sxy, mut m) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for s in &stripes {
            let p = ((s.k as f64 + 0.5) / (s.n as f64 + 1.0)).clamp(0.01, 0.99);
            let (x, y) = (s.im.ln(), nd.inverse_cdf(p));
            sx += x;
            sy += y;
            sxx += x * x;
            sxy += x * y;
            m += 1.0;
        }
        let den = m * sxx - sx * sx;
        if den > 0.0 {
            b = ((m * sxy - sx * sy) / den).max(0.1);
            a = (sy - b * sx) / m;
        }
    }
    let loglik = |a: f64, b: f64| -> f64 {
        stripes
            .iter()
            .map(|s| {
                let eta = a + b * s.im.ln();
                let lp = log_phi(eta);
                let lq = log_phi(-eta);
                s.k as f64 * lp + (s.n - s.k) as f64 * lq
            })
            .sum()
    };
    let mut ll = loglik(a, b);
    let mut info = [[0.0; 2]; 2];
    let mut iterations = 0;
    for it in 1..=100 {
        iterations = it;
        // score and Fisher information of the probit GLM
        let (mut g0, mut g1) = (0.0, 0.0);
        info = [[0.0; 2]; 2];
        for s in &stripes {
            let x = s.im.ln();
            let eta = a + b * x;
            let p = nd.cdf(eta).clamp(1e-300, 1.0 - 1e-16);
            let q = (1.0 - p).max(1e-300);
            let d = nd.pdf(eta);
            let n = s.n as f64;
            let r = (s.k as f64 - n * p) * d / (p * q);
            g0 += r;
            g1 += r * x;
            let w = n * d * d / (p * q);
            info[0][0] += w;
            info[0][1] += w * x;
            info[1][1] += w * x * x;
        }
        info[1][0] = info[0][1];
        let det = info[0][0] * info[1][1] - info[0][1] * info[1][0];
        if det.is_nan() || det <= 0.0 {
            return Err(NoFit::Separated);
        }
        let da = (info[1][1] * g0 - info[0][1] * g1) / det;
        let db = (-info[1][0] * g0 + info[0][0] * g1) / det;
        // step halving keeps the likelihood rising
        let mut step = 1.0;
        let (mut na, mut nb, mut nll) = (a + da, b + db, loglik(a + da, b + db));
        while (nll.is_nan() || nll < ll) && step > 1e-10 {
            step *= 0.5;
            na = a + step * da;
            nb = b + step * db;
            nll = loglik(na, nb);
        }
        let converged = (na - a).abs() <= 1e-12 * a.abs().max(1.0)
            && (nb - b).abs() <= 1e-12 * b.abs().max(1.0);
        a = na;
        b = nb;
        ll = nll;
        if converged {
            break;
        }
        if b > 1e6 {
            return Err(NoFit::Separated);
        }
    }
    if b.is_nan() || b <= 0.0 {
        // decreasing fragility: not a physical overturning curve
        return Err(NoFit::Separated);
    }
    let median = (-a / b).exp();
    let beta = 1.0 / b;
    // covariance of (a, b) = information⁻¹; delta method for θ and β
    let det = info[0][0] * info[1][1] - info[0][1] * info[1][0];
    let (vaa, vab, vbb) = (info[1][1] / det, -info[0][1] / det, info[0][0] / det);
    let (dta, dtb) = (-median / b, median * a / (b * b)); // ∂θ/∂a, ∂θ/∂b
    let var_t = dta * dta * vaa + 2.0 * dta * dtb * vab + dtb * dtb * vbb;
    let se_beta = vbb.sqrt() / (b * b); // |∂β/∂b| = 1/b²
    Ok(Fit {
        median,
        beta,
        a,
        b,
        loglik: ll,
        se_median: var_t.max(0.0).sqrt(),
        se_beta,
        iterations,
    })
}

/// ln Φ(x), accurate in the far tails.
fn log_phi(x: f64) -> f64 {
    if x > -30.0 {
        std_normal().cdf(x).max(f64::MIN_POSITIVE).ln()
    } else {
        // Mills ratio asymptote: Φ(x) ≈ φ(x)/|x|
        -0.5 * x * x - (-x).ln() - 0.5 * (2.0 * std::f64::consts::PI).ln()
    }
}

/// Per-record outcomes of one case: `overturned[stripe][record]`, with the
/// stripes' intensities. Records are shared across stripes.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseData {
    /// Intensity of each stripe.
    pub im: Vec<f64>,
    /// `overturned[i][r]`: record r at stripe i overturned (None: failed or missing).
    pub overturned: Vec<Vec<Option<bool>>>,
}

impl CaseData {
    /// The stripes, counting the records present.
    pub fn stripes(&self) -> Vec<Stripe> {
        self.im
            .iter()
            .zip(&self.overturned)
            .map(|(&im, runs)| Stripe {
                im,
                n: runs.iter().filter(|r| r.is_some()).count() as u32,
                k: runs.iter().filter(|r| **r == Some(true)).count() as u32,
            })
            .collect()
    }
}

/// Percentile bootstrap over records.
#[derive(Clone, Debug, PartialEq)]
pub struct Bootstrap {
    /// 5 % and 95 % quantiles of θ.
    pub median: (f64, f64),
    /// 5 % and 95 % quantiles of β.
    pub beta: (f64, f64),
    /// Replicates that could be fitted.
    pub fitted: usize,
    /// Replicates that could not (e.g. separated by chance).
    pub unfitted: usize,
    /// The fitted replicates (θ, β), in replicate order.
    pub replicates: Vec<(f64, f64)>,
}

/// Bootstraps a case over records: replicate r resamples the record indices
/// with replacement from a Xoshiro256++ stream seeded by (seed, r), the same
/// indices in every stripe; results do not depend on the thread count.
pub fn bootstrap(data: &CaseData, replicates: usize, seed: u64) -> Bootstrap {
    let n_rec = data.overturned.iter().map(|r| r.len()).max().unwrap_or(0);
    let fits: Vec<Option<(f64, f64)>> = (0..replicates)
        .into_par_iter()
        .map(|r| {
            let mut rng =
                Xoshiro256PlusPlus::seed_from_u64(crate::motion::record_seed(seed, r as u64));
            let pick: Vec<usize> = (0..n_rec).map(|_| rng.random_range(0..n_rec)).collect();
            let stripes: Vec<Stripe> = data
                .im
                .iter()
                .zip(&data.overturned)
                .map(|(&im, runs)| {
                    let (mut n, mut k) = (0, 0);
                    for &i in &pick {
                        if let Some(Some(o)) = runs.get(i) {
                            n += 1;
                            k += *o as u32;
                        }
                    }
                    Stripe { im, n, k }
                })
                .collect();
            fit_probit(&stripes).ok().map(|f| (f.median, f.beta))
        })
        .collect();
    let replicates_ok: Vec<(f64, f64)> = fits.iter().flatten().copied().collect();
    let mut t: Vec<f64> = replicates_ok.iter().map(|r| r.0).collect();
    let mut b: Vec<f64> = replicates_ok.iter().map(|r| r.1).collect();
    Bootstrap {
        median: (quantile(&mut t, 0.05), quantile(&mut t, 0.95)),
        beta: (quantile(&mut b, 0.05), quantile(&mut b, 0.95)),
        fitted: replicates_ok.len(),
        unfitted: fits.len() - replicates_ok.len(),
        replicates: replicates_ok,
    }
}

/// Pointwise 5 %–95 % band of the bootstrap curves at intensity x.
pub fn band(boot: &Bootstrap, x: f64) -> (f64, f64) {
    let nd = std_normal();
    let mut p: Vec<f64> = boot
        .replicates
        .iter()
        .map(|&(t, b)| nd.cdf((x / t).ln() / b))
        .collect();
    (quantile(&mut p, 0.05), quantile(&mut p, 0.95))
}

/// Empirical quantile (linear interpolation between order statistics); NaN if empty.
fn quantile(v: &mut [f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let h = q * (v.len() - 1) as f64;
    let (i, f) = (h.floor() as usize, h - h.floor());
    if i + 1 < v.len() {
        v[i] * (1.0 - f) + v[i + 1] * f
    } else {
        v[i]
    }
}

/// OpenQuake's continuous lognormal fragility stores the arithmetic mean and
/// standard deviation of the IM: mean = θ·exp(β²/2), sd = mean·√(exp(β²) − 1).
pub fn to_nrml_moments(median: f64, beta: f64) -> (f64, f64) {
    let mean = median * (0.5 * beta * beta).exp();
    (mean, mean * (beta * beta).exp_m1().sqrt())
}

/// Inverse of [`to_nrml_moments`]: β² = ln(1 + (sd/mean)²), θ = mean·exp(−β²/2).
pub fn from_nrml_moments(mean: f64, sd: f64) -> (f64, f64) {
    let b2 = (sd / mean).powi(2).ln_1p();
    (mean * (-0.5 * b2).exp(), b2.sqrt())
}

/// One fitted case for output.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseFit {
    /// Case label columns (aspect, width, restitution, friction, mu_s, mu_k), as text.
    pub key: [String; 6],
    /// Records per stripe (largest).
    pub n_records: usize,
    /// Stripes.
    pub stripes: Vec<Stripe>,
    /// The fit, or why there is none.
    pub fit: std::result::Result<Fit, NoFit>,
    /// Bootstrap bands (when fitted).
    pub boot: Option<Bootstrap>,
}

/// Reads `outcomes.csv` and groups the runs by case (aspect, width,
/// restitution, friction, mu_s, mu_k) and stripe. `im` is `pga`, or
/// `pga-over-tan` (PGA/(g·tanθc) = pga·aspect, dimensionless).
pub fn read_cases(path: &std::path::Path, im: &str) -> Result<Vec<([String; 6], CaseData)>> {
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut rdr = csv::Reader::from_path(path).map_err(|e| match e.into_kind() {
        csv::ErrorKind::Io(err) => io(err),
        other => Error::Parse {
            path: path.to_path_buf(),
            line: 0,
            message: format!("{other:?}"),
        },
    })?;
    let headers = rdr
        .headers()
        .map_err(|e| Error::Parse {
            path: path.to_path_buf(),
            line: 1,
            message: e.to_string(),
        })?
        .clone();
    let col = |name: &str| {
        headers
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| Error::Parse {
                path: path.to_path_buf(),
                line: 1,
                message: format!("missing column `{name}`"),
            })
    };
    let keys = ["aspect", "width", "restitution", "friction", "mu_s", "mu_k"].map(&col);
    let mut kc = [0usize; 6];
    for (i, k) in keys.into_iter().enumerate() {
        kc[i] = k?;
    }
    let (c_pga, c_rec, c_ot) = (col("pga")?, col("record")?, col("overturned")?);
    let c_status = headers.iter().position(|h| h == "status");
    let mut groups: Vec<([String; 6], Vec<Run>)> = Vec::new();
    for (line, row) in rdr.records().enumerate() {
        let row = row.map_err(|e| Error::Parse {
            path: path.to_path_buf(),
            line: line + 2,
            message: e.to_string(),
        })?;
        let key: [String; 6] = kc.map(|c| row[c].to_string());
        let num = |c: usize, what: &str| -> Result<f64> {
            row[c].parse::<f64>().map_err(|_| Error::Parse {
                path: path.to_path_buf(),
                line: line + 2,
                message: format!("bad {what} `{}`", &row[c]),
            })
        };
        let pga = num(c_pga, "pga")?;
        let x = match im {
            "pga" => pga,
            "pga-over-tan" => pga * num(kc[0], "aspect")?,
            other => return Err(Error::invalid("im", other, "pga or pga-over-tan")),
        };
        let rec = num(c_rec, "record")? as usize;
        let ok = c_status.is_none_or(|c| &row[c] == "ok");
        let ot = if ok { Some(&row[c_ot] == "true") } else { None };
        match groups.iter_mut().find(|g| g.0 == key) {
            Some(g) => g.1.push((x, rec, ot)),
            None => groups.push((key, vec![(x, rec, ot)])),
        }
    }
    Ok(groups
        .into_iter()
        .map(|(key, runs)| {
            let mut im: Vec<f64> = runs.iter().map(|r| r.0).collect();
            im.sort_by(f64::total_cmp);
            im.dedup();
            let n_rec = runs.iter().map(|r| r.1 + 1).max().unwrap_or(0);
            let mut overturned = vec![vec![None; n_rec]; im.len()];
            for (x, rec, ot) in runs {
                let i = im.iter().position(|&v| v == x).expect("stripe exists");
                overturned[i][rec] = ot;
            }
            (key, CaseData { im, overturned })
        })
        .collect())
}

/// One analysis as read: (intensity, record index, overturned or None if failed).
type Run = (f64, usize, Option<bool>);

/// Fits every case of an outcomes file, with `replicates` bootstrap samples.
pub fn fit_outcomes(
    path: &std::path::Path,
    im: &str,
    replicates: usize,
    seed: u64,
) -> Result<Vec<CaseFit>> {
    let cases = read_cases(path, im)?;
    Ok(cases
        .into_iter()
        .map(|(key, data)| {
            let stripes = data.stripes();
            let fit = fit_probit(&stripes);
            let boot = fit.is_ok().then(|| bootstrap(&data, replicates, seed));
            let n_records = data.overturned.iter().map(|r| r.len()).max().unwrap_or(0);
            CaseFit {
                key,
                n_records,
                stripes,
                fit,
                boot,
            }
        })
        .collect())
}

/// `fragility.csv`: one row per case.
pub fn fragility_csv(fits: &[CaseFit], im: &str) -> String {
    let mut s = String::from(
        "aspect,width,restitution,friction,mu_s,mu_k,im,median,beta,median_lo,median_hi,beta_lo,beta_hi,se_median,se_beta,n_records,n_stripes,loglik,status\n",
    );
    for c in fits {
        let key = c.key.join(",");
        match (&c.fit, &c.boot) {
            (Ok(f), Some(b)) => s.push_str(&format!(
                "{key},{im},{},{},{},{},{},{},{},{},{},{},{},ok\n",
                f.median,
                f.beta,
                b.median.0,
                b.median.1,
                b.beta.0,
                b.beta.1,
                f.se_median,
                f.se_beta,
                c.n_records,
                c.stripes.len(),
                f.loglik
            )),
            (fit, _) => {
                let why = fit
                    .as_ref()
                    .err()
                    .map_or("not fitted".to_string(), |e| e.to_string());
                s.push_str(&format!(
                    "{key},{im},,,,,,,,,{},{},,{why}\n",
                    c.n_records,
                    c.stripes.len()
                ));
            }
        }
    }
    s
}

/// The fitted curves as an OpenQuake NRML 0.5 fragility model (continuous,
/// lognormal CDF; one limit state, `overturning`), IM in g.
pub fn nrml(fits: &[CaseFit], imt: &str) -> String {
    let mut s = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<nrml xmlns=\"http://openquake.org/xmlns/nrml/0.5\">\n  <fragilityModel id=\"rockfrag\" assetCategory=\"buildings\" lossCategory=\"structural\">\n    <description>Overturning of free-standing rigid blocks (rockfrag)</description>\n    <limitStates>overturning</limitStates>\n",
    );
    for c in fits {
        if let Ok(f) = &c.fit {
            let (mean, sd) = to_nrml_moments(f.median, f.beta);
            let lo = c.stripes.iter().map(|s| s.im).fold(f64::INFINITY, f64::min);
            let hi = c.stripes.iter().map(|s| s.im).fold(0.0, f64::max);
            let id = format!(
                "aspect={} width={} e={} friction={}{}",
                c.key[0],
                c.key[1],
                c.key[2],
                c.key[3],
                if c.key[3] == "coulomb" {
                    format!(" mu_s={} mu_k={}", c.key[4], c.key[5])
                } else {
                    String::new()
                }
            );
            s.push_str(&format!(
                "    <fragilityFunction id=\"{id}\" format=\"continuous\" shape=\"logncdf\">\n      <imls imt=\"{imt}\" noDamageLimit=\"{lo}\" minIML=\"{lo}\" maxIML=\"{hi}\"/>\n      <params ls=\"overturning\" mean=\"{mean}\" stddev=\"{sd}\"/>\n    </fragilityFunction>\n"
            ));
        }
    }
    s.push_str("  </fragilityModel>\n</nrml>\n");
    s
}
