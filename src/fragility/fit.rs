//! Maximum-likelihood fit of a lognormal fragility to overturning counts: a
//! probit GLM solved by Newton's method on the concave log-likelihood.
//!
//! With u = ln x and η = a + b·u, P(overturn | x) = Φ(η), so θ = exp(−a/b) and
//! β = 1/b. At the intensities xᵢ, zᵢ of nᵢ analyses overturned; the
//! log-likelihood (Baker 2015, eq. 11) is
//!
//! ```text
//! ℓ(a, b) = Σ ln C(nᵢ, zᵢ) + zᵢ ln Φ(ηᵢ) + (nᵢ − zᵢ) ln Φ(−ηᵢ)
//! ```
//!
//! Φ is log-concave, so ℓ is concave in (a, b) and its maximum, when it exists,
//! is unique. It exists exactly when the overturned and surviving analyses
//! overlap in IM; otherwise the data are *separated* and the supremum is
//! approached as β → 0 (or β → −∞ for reversed data), which is reported as an
//! [`Unfit`] reason, never as a number.

use crate::detmath::{self as dm, ln_binomial};

/// Overturning counts at one intensity level.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Observation {
    /// Intensity measure, in the IM's unit (finite and > 0).
    pub im: f64,
    /// Number of analyses at this intensity.
    pub trials: u64,
    /// How many of them overturned (≤ `trials`).
    pub overturned: u64,
}

/// A fitted lognormal fragility P(overturn | x) = Φ(a + b ln x) = Φ(ln(x/θ)/β).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LognormalFit {
    /// Intercept a of the probit model.
    pub a: f64,
    /// Slope b > 0 of the probit model.
    pub b: f64,
    /// Covariance of (a, b): the inverse of the observed information at the
    /// maximum (asymptotic, treating every analysis as independent).
    pub cov: [[f64; 2]; 2],
    /// Maximised log-likelihood, binomial coefficients included.
    pub loglik: f64,
    /// Newton iterations taken.
    pub iterations: u32,
}

impl LognormalFit {
    /// Median capacity θ = exp(−a/b), in the IM's unit.
    pub fn median(&self) -> f64 {
        dm::exp(-self.a / self.b)
    }

    /// Logarithmic standard deviation β = 1/b.
    pub fn beta(&self) -> f64 {
        1.0 / self.b
    }

    /// Probability of overturning at intensity `im` (0 for `im` ≤ 0).
    pub fn probability(&self, im: f64) -> f64 {
        if im <= 0.0 {
            0.0
        } else {
            self.probability_at_ln(dm::ln(im))
        }
    }

    /// Probability of overturning at the intensity whose logarithm is
    /// `ln_im` (Φ(a + b ln IM)), for a caller that evaluates many fits at
    /// one intensity.
    pub fn probability_at_ln(&self, ln_im: f64) -> f64 {
        dm::norm_cdf(self.a + self.b * ln_im)
    }

    /// Standard error of ln θ by the delta method: ∂lnθ/∂a = −1/b, ∂lnθ/∂b = a/b².
    pub fn se_ln_median(&self) -> f64 {
        let g = [-1.0 / self.b, self.a / (self.b * self.b)];
        quadratic_form(&self.cov, g).sqrt()
    }

    /// Standard error of θ by the delta method (θ times that of ln θ).
    pub fn se_median(&self) -> f64 {
        self.median() * self.se_ln_median()
    }

    /// Standard error of β by the delta method: ∂β/∂b = −1/b².
    pub fn se_beta(&self) -> f64 {
        self.cov[1][1].sqrt() / (self.b * self.b)
    }
}

fn quadratic_form(m: &[[f64; 2]; 2], g: [f64; 2]) -> f64 {
    g[0] * (m[0][0] * g[0] + m[0][1] * g[1]) + g[1] * (m[1][0] * g[0] + m[1][1] * g[1])
}

/// Why a lognormal fragility cannot be fitted to a set of counts. The
/// variants and keywords speak of overturning, the first limit state; for
/// another limit state read "exceeded" (the messages do).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Unfit {
    /// No analyses at all (every row of the case failed or was absent).
    NoData,
    /// No analysis overturned: the median is beyond the data.
    NoneOverturned,
    /// Every analysis overturned: the median is below the data.
    AllOverturned,
    /// All analyses are at one intensity: θ and β cannot be separated.
    SingleLevel {
        /// The only intensity.
        im: f64,
    },
    /// Perfectly separated data: no analysis overturns below `first_overturn`
    /// and every analysis overturns above `last_survival` ≤ `first_overturn`
    /// (when the two are equal, that one intensity is mixed). The likelihood
    /// grows without bound as β → 0.
    Separated {
        /// Largest intensity at which some analysis survived.
        last_survival: f64,
        /// Smallest intensity at which some analysis overturned.
        first_overturn: f64,
    },
    /// Overturning becomes less likely as the intensity grows (fitted b ≤ 0,
    /// or reversed separation): no lognormal fragility describes the data.
    Decreasing,
    /// Newton's method did not converge (should not happen for a concave
    /// likelihood; reported rather than hidden).
    NoConvergence {
        /// Iterations taken.
        iterations: u32,
    },
}

impl std::fmt::Display for Unfit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Unfit::NoData => write!(f, "no successful analyses"),
            Unfit::NoneOverturned => {
                write!(
                    f,
                    "no analysis exceeded the limit state: the median is beyond the data"
                )
            }
            Unfit::AllOverturned => {
                write!(
                    f,
                    "every analysis exceeded the limit state: the median is below the data"
                )
            }
            Unfit::SingleLevel { im } => {
                write!(
                    f,
                    "all analyses at one intensity ({im}): θ and β cannot be told apart"
                )
            }
            Unfit::Separated {
                last_survival,
                first_overturn,
            } if last_survival == first_overturn => write!(
                f,
                "perfectly separated: every analysis below {last_survival} survives and every \
                 one above it exceeds the limit state, both happening only at {last_survival}; \
                 the maximum-likelihood β is 0, no finite fit"
            ),
            Unfit::Separated {
                last_survival,
                first_overturn,
            } => write!(
                f,
                "perfectly separated: the highest intensity with a survivor is {last_survival} \
                 and the lowest with an exceedance is {first_overturn} (every analysis up to \
                 {last_survival} survives, every one from {first_overturn} on exceeds the limit \
                 state); the maximum-likelihood β is 0, no finite fit"
            ),
            Unfit::Decreasing => {
                write!(
                    f,
                    "exceeding the limit state becomes less likely with intensity: not a fragility"
                )
            }
            Unfit::NoConvergence { iterations } => {
                write!(f, "the fit did not converge in {iterations} iterations")
            }
        }
    }
}

/// Relative tolerance on the Newton step that declares convergence.
pub(super) const TOLERANCE: f64 = 1e-12;
/// Iteration cap (Newton on a concave likelihood needs 5–15).
pub(super) const MAX_ITERATIONS: u32 = 100;
/// Steps larger than this (relative) are checked and halved if ℓ drops;
/// smaller ones are in Newton's quadratic regime, where ℓ changes by less
/// than its rounding error and the check would only see noise.
pub(super) const LINE_SEARCH_ABOVE: f64 = 1e-6;

/// Fits P(overturn | x) = Φ(a + b ln x) by maximum likelihood.
///
/// Groups with no trials are ignored; several groups may share an intensity.
/// Returns the reason when no finite fit exists (see [`Unfit`]).
///
/// # Panics
/// If an intensity is not finite and > 0, or `overturned > trials`.
///
/// ```
/// use rockfrag::fragility::{Observation, fit_lognormal};
/// let obs: Vec<Observation> = [(0.2, 1), (0.4, 4), (0.6, 7), (0.8, 9)]
///     .iter()
///     .map(|&(im, z)| Observation { im, trials: 10, overturned: z })
///     .collect();
/// let fit = fit_lognormal(&obs).unwrap();
/// assert!(fit.median() > 0.4 && fit.median() < 0.6);
/// ```
pub fn fit_lognormal(observations: &[Observation]) -> Result<LognormalFit, Unfit> {
    let groups: Vec<Group> = observations
        .iter()
        .filter(|o| o.trials > 0)
        .map(|o| {
            assert!(
                o.im.is_finite() && o.im > 0.0,
                "intensity must be finite and > 0, got {}",
                o.im
            );
            assert!(o.overturned <= o.trials, "overturned > trials");
            Group {
                im: o.im,
                u: dm::ln(o.im),
                n: o.trials as f64,
                z: o.overturned as f64,
            }
        })
        .collect();
    check_identifiable(&groups)?;

    // Centre ln x on its mean so that the two parameters are nearly
    // uncorrelated: η = c + b (u − ū), a = c − b ū.
    let n_total: f64 = groups.iter().map(|g| g.n).sum();
    let u_bar = groups.iter().map(|g| g.n * g.u).sum::<f64>() / n_total;
    let mut p = start(&groups, u_bar);
    let mut eval = evaluate(&groups, p, u_bar);
    let mut iterations = 0;
    let converged = loop {
        if iterations == MAX_ITERATIONS {
            break false;
        }
        iterations += 1;
        let Some(step) = solve(&eval.info, eval.score) else {
            return Err(Unfit::NoConvergence { iterations });
        };
        let scale = |i: usize| p[i].abs().max(1.0);
        let rel = (step[0].abs() / scale(0)).max(step[1].abs() / scale(1));
        let mut next = [p[0] + step[0], p[1] + step[1]];
        let mut next_eval = evaluate(&groups, next, u_bar);
        if rel > LINE_SEARCH_ABOVE {
            let mut t = 1.0;
            // Step halving: ℓ is concave and the step is an ascent direction,
            // so a short enough step increases it.
            let mut halvings = 0;
            while next_eval.loglik < eval.loglik || next_eval.loglik.is_nan() {
                halvings += 1;
                if halvings > 60 {
                    return Err(Unfit::NoConvergence { iterations });
                }
                t *= 0.5;
                next = [p[0] + t * step[0], p[1] + t * step[1]];
                next_eval = evaluate(&groups, next, u_bar);
            }
        }
        p = next;
        eval = next_eval;
        // Converged when the full Newton step is negligible (a short halved
        // step says nothing about being at the maximum).
        if rel <= TOLERANCE {
            break true;
        }
    };
    if !converged || !eval.loglik.is_finite() {
        return Err(Unfit::NoConvergence { iterations });
    }
    let [c, b] = p;
    if b <= 0.0 {
        return Err(Unfit::Decreasing);
    }
    let Some(cov_c) = invert(&eval.info) else {
        return Err(Unfit::NoConvergence { iterations });
    };
    // (a, b) = (c − ū b, b): cov = T cov_c Tᵀ with T = [[1, −ū], [0, 1]].
    let var_a = cov_c[0][0] - 2.0 * u_bar * cov_c[0][1] + u_bar * u_bar * cov_c[1][1];
    let cov_ab = cov_c[0][1] - u_bar * cov_c[1][1];
    let constant: f64 = observations
        .iter()
        .filter(|o| o.trials > 0)
        .map(|o| ln_binomial(o.trials, o.overturned))
        .sum();
    Ok(LognormalFit {
        a: c - b * u_bar,
        b,
        cov: [[var_a, cov_ab], [cov_ab, cov_c[1][1]]],
        loglik: eval.loglik + constant,
        iterations,
    })
}

/// Fits K limit states' counts with one β and a median each, by maximum
/// likelihood: P(exceed k | x) = Φ(a_k + b ln x), so θ_k = exp(−a_k/b) and a
/// common β = 1/b. The log-likelihood is the sum of the K binomial ones;
/// it is concave in (a_1 … a_K, b), and Newton's method with step halving
/// finds its maximum as for one limit state. Curves with one β never cross.
///
/// Each set must be fittable alone (else its [`Unfit`] is returned). Each
/// returned fit's `cov` is the (a_k, b) block of the joint covariance, its
/// `loglik` that limit state's term at the joint maximum (the terms sum to
/// the joint maximum), `iterations` the joint count.
///
/// # Panics
/// As [`fit_lognormal`]; also if `sets` is empty.
pub fn fit_common_beta(sets: &[&[Observation]]) -> Result<Vec<LognormalFit>, Unfit> {
    assert!(!sets.is_empty(), "no limit states to fit");
    let mut groups = Vec::with_capacity(sets.len());
    let mut starts = Vec::with_capacity(sets.len());
    for obs in sets {
        // Each alone first: identifiability, and the starting point.
        starts.push(fit_lognormal(obs)?);
        groups.push(
            obs.iter()
                .filter(|o| o.trials > 0)
                .map(|o| Group {
                    im: o.im,
                    u: dm::ln(o.im),
                    n: o.trials as f64,
                    z: o.overturned as f64,
                })
                .collect::<Vec<_>>(),
        );
    }
    let k = sets.len();
    let n_total: f64 = groups.iter().flatten().map(|g| g.n).sum();
    let u_bar = groups.iter().flatten().map(|g| g.n * g.u).sum::<f64>() / n_total;
    // Start from the separate fits: the mean slope, intercepts re-centred.
    let b0 = starts.iter().map(|f| f.b).sum::<f64>() / k as f64;
    let mut p: Vec<f64> = starts.iter().map(|f| f.a + b0 * u_bar).collect();
    p.push(b0);
    let joint = |p: &[f64]| -> (f64, Vec<f64>, Vec<Vec<f64>>) {
        let mut loglik = 0.0;
        let mut score = vec![0.0; k + 1];
        let mut info = vec![vec![0.0; k + 1]; k + 1];
        for (j, g) in groups.iter().enumerate() {
            let e = evaluate(g, [p[j], p[k]], u_bar);
            loglik += e.loglik;
            score[j] += e.score[0];
            score[k] += e.score[1];
            info[j][j] += e.info[0][0];
            info[j][k] += e.info[0][1];
            info[k][j] += e.info[0][1];
            info[k][k] += e.info[1][1];
        }
        (loglik, score, info)
    };
    let (mut loglik, mut score, mut info) = joint(&p);
    let mut iterations = 0;
    loop {
        if iterations == MAX_ITERATIONS {
            return Err(Unfit::NoConvergence { iterations });
        }
        iterations += 1;
        let Some(step) = cholesky(&info).map(|l| cholesky_solve(&l, &score)) else {
            return Err(Unfit::NoConvergence { iterations });
        };
        let rel = step
            .iter()
            .zip(&p)
            .map(|(d, x)| d.abs() / x.abs().max(1.0))
            .fold(0.0, f64::max);
        let mut t = 1.0;
        let mut halvings = 0;
        let mut next: Vec<f64> = p.iter().zip(&step).map(|(x, d)| x + d).collect();
        let mut next_eval = joint(&next);
        // Step halving, as in `fit_lognormal`.
        while rel > LINE_SEARCH_ABOVE && (next_eval.0 < loglik || next_eval.0.is_nan()) {
            halvings += 1;
            if halvings > 60 {
                return Err(Unfit::NoConvergence { iterations });
            }
            t *= 0.5;
            next = p.iter().zip(&step).map(|(x, d)| x + t * d).collect();
            next_eval = joint(&next);
        }
        p = next;
        (loglik, score, info) = next_eval;
        if rel <= TOLERANCE {
            break;
        }
    }
    let b = p[k];
    if !loglik.is_finite() || b.is_nan() {
        return Err(Unfit::NoConvergence { iterations });
    }
    if b <= 0.0 {
        return Err(Unfit::Decreasing);
    }
    let Some(l) = cholesky(&info) else {
        return Err(Unfit::NoConvergence { iterations });
    };
    // Columns j and k of the inverse information.
    let unit = |i: usize| {
        (0..=k)
            .map(|r| f64::from(u8::from(r == i)))
            .collect::<Vec<_>>()
    };
    let inv_b = cholesky_solve(&l, &unit(k));
    Ok((0..k)
        .map(|j| {
            let inv_j = cholesky_solve(&l, &unit(j));
            let cov_c = [[inv_j[j], inv_j[k]], [inv_b[j], inv_b[k]]];
            let var_a = cov_c[0][0] - 2.0 * u_bar * cov_c[0][1] + u_bar * u_bar * cov_c[1][1];
            let cov_ab = cov_c[0][1] - u_bar * cov_c[1][1];
            let constant: f64 = sets[j]
                .iter()
                .filter(|o| o.trials > 0)
                .map(|o| ln_binomial(o.trials, o.overturned))
                .sum();
            LognormalFit {
                a: p[j] - b * u_bar,
                b,
                cov: [[var_a, cov_ab], [cov_ab, cov_c[1][1]]],
                loglik: evaluate(&groups[j], [p[j], b], u_bar).loglik + constant,
                iterations,
            }
        })
        .collect())
}

/// Probabilities within this of 0 or 1 are too close to tell curves apart:
/// a crossing there does not count ([`curves_cross`]).
pub(crate) const CROSSING_TOLERANCE: f64 = 1e-3;

/// Whether two fitted curves cross where it matters: two lognormal curves
/// with β₁ ≠ β₂ meet once, where (u − ln θ₁)/β₁ = (u − ln θ₂)/β₂, i.e.
/// u* = (β₂ ln θ₁ − β₁ ln θ₂)/(β₂ − β₁); curves with equal β never cross.
/// A meeting within the stripes' range `im_range` (weakest to strongest)
/// always counts, however small the probabilities there: the data are
/// there, and OpenQuake and pelicun, which take P(DSₖ) = P(LSₖ) − P(LSₖ₊₁),
/// would give a damage state a negative probability. Below the weakest
/// stripe (where the curves are extrapolated) a meeting counts when the
/// common probability is in (10⁻³, 1 − 10⁻³); above the strongest it does
/// not (nothing is fitted there).
pub fn curves_cross(first: &LognormalFit, second: &LognormalFit, im_range: (f64, f64)) -> bool {
    let (b1, b2) = (first.beta(), second.beta());
    if b1 == b2 {
        return false;
    }
    let (m1, m2) = (dm::ln(first.median()), dm::ln(second.median()));
    let u_star = (b2 * m1 - b1 * m2) / (b2 - b1);
    let p = first.probability(dm::exp(u_star));
    u_star.is_finite()
        && u_star <= dm::ln(im_range.1)
        && (u_star >= dm::ln(im_range.0)
            || (p > CROSSING_TOLERANCE && p < 1.0 - CROSSING_TOLERANCE))
}

/// Lower-triangular Cholesky factor of a symmetric positive-definite matrix.
pub(super) fn cholesky(m: &[Vec<f64>]) -> Option<Vec<Vec<f64>>> {
    let n = m.len();
    let mut l = vec![vec![0.0; n]; n];
    for i in 0..n {
        for j in 0..=i {
            let s: f64 = (0..j).map(|r| l[i][r] * l[j][r]).sum();
            if i == j {
                let d = m[i][i] - s;
                if !(d > 0.0 && d.is_finite()) {
                    return None;
                }
                l[i][i] = d.sqrt();
            } else {
                l[i][j] = (m[i][j] - s) / l[j][j];
            }
        }
    }
    Some(l)
}

/// Solves L Lᵀ x = g.
pub(super) fn cholesky_solve(l: &[Vec<f64>], g: &[f64]) -> Vec<f64> {
    let n = l.len();
    let mut y = vec![0.0; n];
    for i in 0..n {
        y[i] = (g[i] - (0..i).map(|r| l[i][r] * y[r]).sum::<f64>()) / l[i][i];
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        x[i] = (y[i] - (i + 1..n).map(|r| l[r][i] * x[r]).sum::<f64>()) / l[i][i];
    }
    x
}

#[derive(Clone, Copy, Debug)]
struct Group {
    /// The intensity, as given (for messages: e^ln x need not give x back).
    im: f64,
    /// ln of the intensity.
    u: f64,
    n: f64,
    z: f64,
}

/// Checks that a finite maximum exists before iterating.
fn check_identifiable(groups: &[Group]) -> Result<(), Unfit> {
    let n: f64 = groups.iter().map(|g| g.n).sum();
    let z: f64 = groups.iter().map(|g| g.z).sum();
    if n == 0.0 {
        return Err(Unfit::NoData);
    }
    if z == 0.0 {
        return Err(Unfit::NoneOverturned);
    }
    if z == n {
        return Err(Unfit::AllOverturned);
    }
    let u_min = groups.iter().map(|g| g.u).fold(f64::INFINITY, f64::min);
    let u_max = groups.iter().map(|g| g.u).fold(f64::NEG_INFINITY, f64::max);
    // the intensity of a group at u, as the data gave it
    let im_at = |u: f64| groups.iter().find(|g| g.u == u).map_or(f64::NAN, |g| g.im);
    if u_min == u_max {
        return Err(Unfit::SingleLevel { im: im_at(u_min) });
    }
    // Largest / smallest u with a survivor, and with an overturn.
    let surv = groups.iter().filter(|g| g.z < g.n).map(|g| g.u);
    let over = groups.iter().filter(|g| g.z > 0.0).map(|g| g.u);
    let last_survival = surv.clone().fold(f64::NEG_INFINITY, f64::max);
    let first_survival = surv.fold(f64::INFINITY, f64::min);
    let first_overturn = over.clone().fold(f64::INFINITY, f64::min);
    let last_overturn = over.fold(f64::NEG_INFINITY, f64::max);
    if last_survival <= first_overturn {
        return Err(Unfit::Separated {
            last_survival: im_at(last_survival),
            first_overturn: im_at(first_overturn),
        });
    }
    if last_overturn <= first_survival {
        return Err(Unfit::Decreasing);
    }
    Ok(())
}

/// Starting point: weighted least squares of the probits of the smoothed
/// fractions Φ⁻¹((z + ½)/(n + 1)) on u − ū; a flat slope if that is not > 0.
fn start(groups: &[Group], u_bar: f64) -> [f64; 2] {
    let (mut sw, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0);
    for g in groups {
        let x = g.u - u_bar;
        let y = dm::norm_inv_cdf((g.z + 0.5) / (g.n + 1.0));
        sw += g.n;
        sy += g.n * y;
        sxx += g.n * x * x;
        sxy += g.n * x * y;
    }
    let c = sy / sw;
    let b = sxy / sxx;
    if b.is_finite() && b > 0.0 {
        [c, b]
    } else {
        [c, 1.0 / (sxx / sw).sqrt()]
    }
}

struct Evaluation {
    loglik: f64,
    score: [f64; 2],
    info: [[f64; 2]; 2],
}

/// ℓ (without the binomial constants), its gradient and the observed
/// information −∇²ℓ at (c, b).
fn evaluate(groups: &[Group], [c, b]: [f64; 2], u_bar: f64) -> Evaluation {
    let mut e = Evaluation {
        loglik: 0.0,
        score: [0.0; 2],
        info: [[0.0; 2]; 2],
    };
    for g in groups {
        let x = g.u - u_bar;
        let eta = c + b * x;
        let (mut s, mut w) = (0.0, 0.0);
        if g.z > 0.0 {
            let lc = ln_cdf(eta);
            let r = dm::exp(ln_pdf(eta) - lc); // φ/Φ, the inverse Mills ratio
            e.loglik += g.z * lc;
            s += g.z * r;
            w += g.z * r * (eta + r);
        }
        let m = g.n - g.z;
        if m > 0.0 {
            let lc = ln_cdf(-eta);
            let r = dm::exp(ln_pdf(eta) - lc); // φ/(1 − Φ)
            e.loglik += m * lc;
            s -= m * r;
            w += m * r * (r - eta);
        }
        e.score[0] += s;
        e.score[1] += s * x;
        e.info[0][0] += w;
        e.info[0][1] += w * x;
        e.info[1][1] += w * x * x;
    }
    e.info[1][0] = e.info[0][1];
    e
}

fn solve(m: &[[f64; 2]; 2], g: [f64; 2]) -> Option<[f64; 2]> {
    let inv = invert(m)?;
    let d = [
        inv[0][0] * g[0] + inv[0][1] * g[1],
        inv[1][0] * g[0] + inv[1][1] * g[1],
    ];
    (d[0].is_finite() && d[1].is_finite()).then_some(d)
}

/// Inverse of a symmetric positive-definite 2×2 matrix.
fn invert(m: &[[f64; 2]; 2]) -> Option<[[f64; 2]; 2]> {
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    if !(det > 0.0 && m[0][0] > 0.0 && det.is_finite()) {
        return None;
    }
    Some([
        [m[1][1] / det, -m[0][1] / det],
        [-m[1][0] / det, m[0][0] / det],
    ])
}

/// ln φ(x).
pub(super) fn ln_pdf(x: f64) -> f64 {
    const LN_SQRT_2PI: f64 = 0.918_938_533_204_672_7;
    -0.5 * x * x - LN_SQRT_2PI
}

/// ln Φ(x), accurate in both tails: ln(1 − Φ(−x)) for x > 0 and the
/// asymptotic series Φ(x) = φ(x)/|x| (1 − 1/x² + 3/x⁴ − …) below −30, where
/// Φ(x) < 5e-198 nears underflow.
pub(super) fn ln_cdf(x: f64) -> f64 {
    if x > 0.0 {
        dm::ln_1p(-dm::norm_cdf(-x))
    } else if x >= -30.0 {
        dm::ln(dm::norm_cdf(x))
    } else {
        let y = 1.0 / (x * x);
        // Σ (−1)ᵏ (2k−1)!! yᵏ, k = 0..6: the next term is < 2e-17 at x = −30.
        let series = 1.0
            - y * (1.0
                - 3.0 * y * (1.0 - 5.0 * y * (1.0 - 7.0 * y * (1.0 - 9.0 * y * (1.0 - 11.0 * y)))));
        ln_pdf(x) - dm::ln(-x) + dm::ln(series)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The separation message says which intensity had the last survivor and
    /// which the first exceedance; it used to read "none … below 0.6, all …
    /// above 0.3", which sounds like a contradiction.
    #[test]
    fn separation_message_names_last_survivor_and_first_exceedance() {
        let text = Unfit::Separated {
            last_survival: 0.3,
            first_overturn: 0.6,
        }
        .to_string();
        assert!(
            text.contains("highest intensity with a survivor is 0.3")
                && text.contains("lowest with an exceedance is 0.6"),
            "{text}"
        );
    }

    /// ln Φ is continuous across the switch to the asymptotic series at −30
    /// (relative jump < 1e-12) and matches ln(1 − Φ(−x)) for x > 0.
    #[test]
    fn ln_cdf_is_continuous_at_the_series_switch() {
        let below = ln_cdf(-30.0 - 1e-12);
        let above = ln_cdf(-30.0);
        assert!(
            (below - above).abs() < 1e-12 * above.abs(),
            "{below} {above}"
        );
        assert!((ln_cdf(1.0) - dm::ln(dm::norm_cdf(1.0))).abs() < 1e-15);
        assert!(ln_cdf(-1000.0).is_finite());
    }

    /// The analytic score and information match central differences of ℓ to 1e-6 relative.
    #[test]
    fn score_and_information_match_finite_differences() {
        let groups = [
            Group {
                im: dm::exp(-1.5),
                u: -1.5,
                n: 10.0,
                z: 1.0,
            },
            Group {
                im: dm::exp(-0.7),
                u: -0.7,
                n: 10.0,
                z: 5.0,
            },
            Group {
                im: dm::exp(0.2),
                u: 0.2,
                n: 8.0,
                z: 8.0,
            },
            Group {
                im: dm::exp(0.5),
                u: 0.5,
                n: 3.0,
                z: 0.0,
            },
        ];
        let p = [0.3, 1.7];
        let e = evaluate(&groups, p, -0.4);
        let h = 1e-5;
        for i in 0..2 {
            let mut pp = p;
            let mut pm = p;
            pp[i] += h;
            pm[i] -= h;
            let (ep, em) = (evaluate(&groups, pp, -0.4), evaluate(&groups, pm, -0.4));
            let d = (ep.loglik - em.loglik) / (2.0 * h);
            assert!((d - e.score[i]).abs() < 1e-6 * e.score[i].abs().max(1.0));
            for j in 0..2 {
                let dd = -(ep.score[j] - em.score[j]) / (2.0 * h);
                assert!((dd - e.info[i][j]).abs() < 1e-6 * e.info[i][j].abs().max(1.0));
            }
        }
    }

    /// Nearly separated data (a single analysis out of order) still have a
    /// finite maximum: the fit converges to a small β with a zero score.
    #[test]
    fn nearly_separated_data_converge() {
        let obs = [
            (0.1, 10, 0),
            (0.2, 10, 0),
            (0.3, 10, 1),
            (0.32, 10, 9),
            (0.5, 10, 10),
        ]
        .map(|(im, trials, overturned)| Observation {
            im,
            trials,
            overturned,
        });
        let fit = fit_lognormal(&obs).unwrap();
        assert!(fit.beta() > 0.0 && fit.beta() < 0.1, "β {}", fit.beta());
        assert!(
            fit.median() > 0.3 && fit.median() < 0.32,
            "θ {}",
            fit.median()
        );
        assert!(fit.iterations < MAX_ITERATIONS);
        let groups: Vec<Group> = obs
            .iter()
            .map(|o| Group {
                im: o.im,
                u: dm::ln(o.im),
                n: o.trials as f64,
                z: o.overturned as f64,
            })
            .collect();
        let e = evaluate(&groups, [fit.a, fit.b], 0.0);
        assert!(
            e.score[0].abs() < 1e-6 && e.score[1].abs() < 1e-6,
            "{:?}",
            e.score
        );
    }
}
