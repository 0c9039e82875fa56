//! Maximum-likelihood fit of a fragility *surface* in two intensity
//! measures: a probit in ln IM1 and ln IM2,
//!
//! ```text
//! P(LS | x₁, x₂) = Φ(a + b₁ ln x₁ + b₂ ln x₂)
//! ```
//!
//! (Purvance, Anooshehpoor and Brune's surfaces of precariously balanced
//! rocks in PGA and PGV/PGA are of this kind). The log-likelihood over the
//! analyses grouped by equal (x₁, x₂), Σ zᵢ ln Φ(ηᵢ) + (nᵢ − zᵢ) ln Φ(−ηᵢ)
//! plus the binomial constants, is concave in (a, b₁, b₂) as in one IM;
//! Newton's method with step halving on the centred logs finds its maximum,
//! and the inverse observed information at it gives the covariance of the
//! coefficients. A maximum exists only when the exceedances and survivals
//! overlap in the plane: when a straight line in (ln x₁, ln x₂) separates
//! them the coefficients grow without bound ([`SurfaceUnfit::Separated`]);
//! when every analysis lies on one line (one stripe of a stripe IM and
//! records of one PGV/PGA, or two IMs proportional to each other) b₁ and
//! b₂ cannot be told apart ([`SurfaceUnfit::Collinear`]).

use super::fit::{LINE_SEARCH_ABOVE, MAX_ITERATIONS, TOLERANCE};
use super::fit::{cholesky, cholesky_solve, ln_cdf, ln_pdf};
use crate::detmath::{self as dm, ln_binomial};

/// Analyses at one point (x₁, x₂) of the plane and how many exceeded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// IM1, in its unit (finite and > 0).
    pub im1: f64,
    /// IM2, in its unit (finite and > 0).
    pub im2: f64,
    /// Analyses at the point.
    pub trials: u64,
    /// How many exceeded the limit state (≤ `trials`).
    pub exceeded: u64,
}

/// A fitted surface P(LS | x₁, x₂) = Φ(a + b₁ ln x₁ + b₂ ln x₂).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceFit {
    /// Intercept a.
    pub a: f64,
    /// Slope b₁ of ln IM1.
    pub b1: f64,
    /// Slope b₂ of ln IM2.
    pub b2: f64,
    /// Covariance of (a, b₁, b₂): the inverse observed information at the
    /// maximum (every analysis counted independent).
    pub cov: [[f64; 3]; 3],
    /// Maximised log-likelihood, binomial coefficients included.
    pub loglik: f64,
    /// Newton iterations taken.
    pub iterations: u32,
}

impl SurfaceFit {
    /// The coefficients (a, b₁, b₂).
    pub fn coefficients(&self) -> [f64; 3] {
        [self.a, self.b1, self.b2]
    }

    /// Standard errors of (a, b₁, b₂).
    pub fn se(&self) -> [f64; 3] {
        [0, 1, 2].map(|i| self.cov[i][i].sqrt())
    }

    /// Correlation of coefficients `i` and `j` (0: a, 1: b₁, 2: b₂).
    pub fn correlation(&self, i: usize, j: usize) -> f64 {
        self.cov[i][j] / (self.cov[i][i] * self.cov[j][j]).sqrt()
    }

    /// The Wald statistic b₂/SE(b₂): |z| < 2 means IM2 adds nothing the
    /// data can tell from chance.
    pub fn z_b2(&self) -> f64 {
        self.b2 / self.se()[2]
    }

    /// The Wald statistic b₁/SE(b₁).
    pub fn z_b1(&self) -> f64 {
        self.b1 / self.se()[1]
    }

    /// Probability of exceeding the limit state at (x₁, x₂) (0 when either
    /// is ≤ 0).
    pub fn probability(&self, im1: f64, im2: f64) -> f64 {
        if im1 <= 0.0 || im2 <= 0.0 {
            return 0.0;
        }
        dm::norm_cdf(self.a + self.b1 * dm::ln(im1) + self.b2 * dm::ln(im2))
    }

    /// The IM1 at which the probability is `p` at IM2 = `im2` (the
    /// contour's point): `None` unless b₁ > 0 and 0 < p < 1.
    pub fn im1_at(&self, p: f64, im2: f64) -> Option<f64> {
        if !(self.b1 > 0.0 && p > 0.0 && p < 1.0 && im2 > 0.0) {
            return None;
        }
        // a + b₁ u₁ + b₂ u₂ = Φ⁻¹(p)
        Some(dm::exp(
            (dm::norm_inv_cdf(p) - self.a - self.b2 * dm::ln(im2)) / self.b1,
        ))
    }

    /// The IM2 at which the probability is `p` at IM1 = `im1`: `None`
    /// unless b₂ ≠ 0 and 0 < p < 1.
    pub fn im2_at(&self, p: f64, im1: f64) -> Option<f64> {
        if self.b2 == 0.0 || !(p > 0.0 && p < 1.0 && im1 > 0.0) {
            return None;
        }
        Some(dm::exp(
            (dm::norm_inv_cdf(p) - self.a - self.b1 * dm::ln(im1)) / self.b2,
        ))
    }

    /// The one-IM curve in IM1 this surface implies over records whose
    /// IM2 given IM1 is lognormal, ln x₂ = α + γ ln x₁ + ε, ε ~ N(0, σ²)
    /// (`relation` = (α, γ, σ)): P(LS | x₁) = Φ((a + b₂α + (b₁ + b₂γ) ln
    /// x₁)/√(1 + b₂²σ²)), so its median θ = exp(−(a + b₂α)/(b₁ + b₂γ)) and
    /// β = √(1 + b₂²σ²)/(b₁ + b₂γ). `None` when b₁ + b₂γ ≤ 0.
    pub fn equivalent(&self, (alpha, gamma, sigma): (f64, f64, f64)) -> Option<(f64, f64)> {
        let slope = self.b1 + self.b2 * gamma;
        if slope.is_nan() || slope <= 0.0 {
            return None;
        }
        let median = dm::exp(-(self.a + self.b2 * alpha) / slope);
        let beta = (1.0 + self.b2 * self.b2 * sigma * sigma).sqrt() / slope;
        Some((median, beta))
    }
}

/// Why no surface could be fitted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfaceUnfit {
    /// No successful analysis.
    NoData,
    /// No analysis exceeded the limit state.
    NoneExceeded,
    /// Every analysis exceeded it.
    AllExceeded,
    /// Every analysis lies on one line of the (ln IM1, ln IM2) plane: the
    /// two slopes cannot be told apart.
    Collinear,
    /// A line of the plane separates exceedances from survivals: the
    /// maximum-likelihood surface is a step, no finite fit.
    Separated,
    /// Newton's method did not converge.
    NoConvergence {
        /// Iterations taken.
        iterations: u32,
    },
}

impl SurfaceUnfit {
    /// Its keyword in `fragility_surface.csv`'s `status` column (those
    /// shared with the one-IM fit read the same).
    pub fn status(&self) -> &'static str {
        match self {
            SurfaceUnfit::NoData => "no-data",
            SurfaceUnfit::NoneExceeded => "none-overturned",
            SurfaceUnfit::AllExceeded => "all-overturned",
            SurfaceUnfit::Collinear => "collinear",
            SurfaceUnfit::Separated => "separated",
            SurfaceUnfit::NoConvergence { .. } => "no-convergence",
        }
    }
}

impl std::fmt::Display for SurfaceUnfit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SurfaceUnfit::NoData => "no successful analysis",
            SurfaceUnfit::NoneExceeded => "no analysis exceeded the limit state",
            SurfaceUnfit::AllExceeded => "every analysis exceeded the limit state",
            SurfaceUnfit::Collinear => {
                "every analysis lies on one line of the (ln IM1, ln IM2) plane, so the two \
                 slopes cannot be told apart"
            }
            SurfaceUnfit::Separated => {
                "a straight line of the (ln IM1, ln IM2) plane separates the analyses that \
                 exceeded the limit state from those that did not: the surface is a step, no \
                 finite fit"
            }
            SurfaceUnfit::NoConvergence { .. } => "the fit did not converge",
        })
    }
}

/// A group of analyses at one point, in centred logs.
#[derive(Clone, Copy, Debug)]
struct Group {
    /// (1, ln x₁ − ū₁, ln x₂ − ū₂): the regressors.
    x: [f64; 3],
    n: f64,
    z: f64,
}

/// ℓ without the binomial constants, its gradient and the observed
/// information at the centred coefficients `p`.
fn evaluate(groups: &[Group], p: [f64; 3]) -> (f64, [f64; 3], [[f64; 3]; 3]) {
    let mut loglik = 0.0;
    let mut score = [0.0; 3];
    let mut info = [[0.0; 3]; 3];
    for g in groups {
        let eta = p[0] * g.x[0] + p[1] * g.x[1] + p[2] * g.x[2];
        let (mut s, mut w) = (0.0, 0.0);
        if g.z > 0.0 {
            let lc = ln_cdf(eta);
            let r = dm::exp(ln_pdf(eta) - lc); // φ/Φ
            loglik += g.z * lc;
            s += g.z * r;
            w += g.z * r * (eta + r);
        }
        let m = g.n - g.z;
        if m > 0.0 {
            let lc = ln_cdf(-eta);
            let r = dm::exp(ln_pdf(eta) - lc); // φ/(1 − Φ)
            loglik += m * lc;
            s -= m * r;
            w += m * r * (r - eta);
        }
        for (i, row) in info.iter_mut().enumerate() {
            score[i] += s * g.x[i];
            for (j, cell) in row.iter_mut().enumerate() {
                *cell += w * g.x[i] * g.x[j];
            }
        }
    }
    (loglik, score, info)
}

fn rows(m: &[[f64; 3]; 3]) -> Vec<Vec<f64>> {
    m.iter().map(|r| r.to_vec()).collect()
}

/// Relative spread below which the points are taken to lie on one line:
/// the correlation of ln x₁ and ln x₂ is within this of ±1 (or one of them
/// does not vary).
const COLLINEAR: f64 = 1e-9;

/// Fits P(LS | x₁, x₂) = Φ(a + b₁ ln x₁ + b₂ ln x₂) by maximum likelihood
/// (see the module's documentation). Points without trials are ignored.
///
/// # Panics
/// If an intensity is not finite and > 0, or `exceeded > trials`.
///
/// ```
/// use rockfrag::detmath::{ln, norm_cdf};
/// use rockfrag::fragility::{SurfacePoint, fit_surface};
/// // P = Φ(1 + 2 ln x₁ + ln x₂) on a 5 × 5 grid, 1000 analyses a point
/// let mut points = Vec::new();
/// for i in 0..5 {
///     for j in 0..5 {
///         let (x1, x2) = (0.25 * (i + 1) as f64, 0.5 * (j + 1) as f64);
///         let p = norm_cdf(1.0 + 2.0 * ln(x1) + ln(x2));
///         points.push(SurfacePoint { im1: x1, im2: x2, trials: 1000, exceeded: (1000.0 * p).round() as u64 });
///     }
/// }
/// let fit = fit_surface(&points).unwrap();
/// assert!((fit.b1 - 2.0).abs() < 0.05 && (fit.b2 - 1.0).abs() < 0.05 && (fit.a - 1.0).abs() < 0.05);
/// ```
pub fn fit_surface(points: &[SurfacePoint]) -> Result<SurfaceFit, SurfaceUnfit> {
    let used: Vec<&SurfacePoint> = points.iter().filter(|p| p.trials > 0).collect();
    for p in &used {
        assert!(
            p.im1.is_finite() && p.im1 > 0.0 && p.im2.is_finite() && p.im2 > 0.0,
            "intensities must be finite and > 0, got ({}, {})",
            p.im1,
            p.im2
        );
        assert!(p.exceeded <= p.trials, "exceeded > trials");
    }
    let n: f64 = used.iter().map(|p| p.trials as f64).sum();
    let z: f64 = used.iter().map(|p| p.exceeded as f64).sum();
    if n == 0.0 {
        return Err(SurfaceUnfit::NoData);
    }
    if z == 0.0 {
        return Err(SurfaceUnfit::NoneExceeded);
    }
    if z == n {
        return Err(SurfaceUnfit::AllExceeded);
    }
    let logs: Vec<(f64, f64)> = used
        .iter()
        .map(|p| (dm::ln(p.im1), dm::ln(p.im2)))
        .collect();
    let mean = |f: fn(&(f64, f64)) -> f64| {
        logs.iter()
            .zip(&used)
            .map(|(l, p)| p.trials as f64 * f(l))
            .sum::<f64>()
            / n
    };
    let (m1, m2) = (mean(|l| l.0), mean(|l| l.1));
    let groups: Vec<Group> = logs
        .iter()
        .zip(&used)
        .map(|(&(u1, u2), p)| Group {
            x: [1.0, u1 - m1, u2 - m2],
            n: p.trials as f64,
            z: p.exceeded as f64,
        })
        .collect();
    // the weighted covariance of (u₁, u₂): collinear when singular
    let (mut s11, mut s22, mut s12) = (0.0, 0.0, 0.0);
    for g in &groups {
        s11 += g.n * g.x[1] * g.x[1];
        s22 += g.n * g.x[2] * g.x[2];
        s12 += g.n * g.x[1] * g.x[2];
    }
    if !(s11 > 0.0 && s22 > 0.0) || 1.0 - s12 * s12 / (s11 * s22) < COLLINEAR {
        return Err(SurfaceUnfit::Collinear);
    }

    let mut p = [dm::norm_inv_cdf((z + 0.5) / (n + 1.0)), 0.0, 0.0];
    let (mut loglik, mut score, mut info) = evaluate(&groups, p);
    let mut iterations = 0;
    let converged = loop {
        if iterations == MAX_ITERATIONS {
            break false;
        }
        iterations += 1;
        let Some(l) = cholesky(&rows(&info)) else {
            break false;
        };
        let step = cholesky_solve(&l, &score);
        let rel = (0..3)
            .map(|i| step[i].abs() / p[i].abs().max(1.0))
            .fold(0.0, f64::max);
        let mut t = 1.0;
        let mut next = [0, 1, 2].map(|i| p[i] + step[i]);
        let mut e = evaluate(&groups, next);
        // step halving: ℓ is concave and the step an ascent direction
        let mut halvings = 0;
        while rel > LINE_SEARCH_ABOVE && (e.0 < loglik || e.0.is_nan()) {
            halvings += 1;
            if halvings > 60 {
                break;
            }
            t *= 0.5;
            next = [0, 1, 2].map(|i| p[i] + t * step[i]);
            e = evaluate(&groups, next);
        }
        if halvings > 60 {
            break false;
        }
        p = next;
        (loglik, score, info) = e;
        if rel <= TOLERANCE {
            break true;
        }
    };
    let cov_c = cholesky(&rows(&info)).map(|l| {
        let col = |k: usize| cholesky_solve(&l, &[0, 1, 2].map(|i| f64::from(u8::from(i == k))));
        let c = [col(0), col(1), col(2)];
        [0, 1, 2].map(|i| [0, 1, 2].map(|j| c[j][i]))
    });
    let (true, Some(cov_c)) = (converged && loglik.is_finite(), cov_c) else {
        // Separated data drive the coefficients off to infinity along a
        // direction that classifies every pure point: say so when the last
        // iterate's line does.
        let separates = groups.iter().all(|g| {
            let eta = p[0] + p[1] * g.x[1] + p[2] * g.x[2];
            (g.z == 0.0 && eta <= 0.0) || (g.z == g.n && eta >= 0.0) || (g.z > 0.0 && g.z < g.n)
        });
        return Err(if separates {
            SurfaceUnfit::Separated
        } else {
            SurfaceUnfit::NoConvergence { iterations }
        });
    };
    // (a, b₁, b₂) = T (c, b₁, b₂), T = [[1, −ū₁, −ū₂], [0, 1, 0], [0, 0, 1]]
    let t = [[1.0, -m1, -m2], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut cov = [[0.0; 3]; 3];
    for (i, row) in cov.iter_mut().enumerate() {
        for (j, c) in row.iter_mut().enumerate() {
            for k in 0..3 {
                for l in 0..3 {
                    *c += t[i][k] * cov_c[k][l] * t[j][l];
                }
            }
        }
    }
    let constant: f64 = used.iter().map(|p| ln_binomial(p.trials, p.exceeded)).sum();
    Ok(SurfaceFit {
        a: p[0] - p[1] * m1 - p[2] * m2,
        b1: p[1],
        b2: p[2],
        cov,
        loglik: loglik + constant,
        iterations,
    })
}

/// How far a fitted surface can be read, for `fragility_surface.csv`'s
/// status: `ok`, or which slope the data cannot tell from zero (Wald |z| <
/// 2, about the 95 % level), or that ln IM1 lowers the probability.
pub fn surface_status(fit: &SurfaceFit) -> &'static str {
    let (z1, z2) = (fit.z_b1(), fit.z_b2());
    match (z1.abs() >= 2.0, z2.abs() >= 2.0) {
        (false, false) => "imprecise",
        (true, _) if fit.b1 < 0.0 => "decreasing-in-im1",
        (true, false) => "second-im-adds-nothing",
        (false, true) => "first-im-adds-nothing",
        (true, true) => "ok",
    }
}

/// A surface status ([`SurfaceUnfit::status`], [`surface_status`]) in
/// words a user reads, naming the two IMs.
pub fn surface_words(status: &str, im1: &str, im2: &str) -> String {
    match status {
        "ok" => format!("both {im1} and {im2} matter (each slope beyond 2 standard errors)"),
        "second-im-adds-nothing" => format!(
            "{im2} adds nothing discernible to {im1}: its slope b2 is within 2 standard errors \
             of 0, so use the one-IM curve against {im1}"
        ),
        "first-im-adds-nothing" => format!(
            "{im1} adds nothing discernible once {im2} is known: its slope b1 is within 2 \
             standard errors of 0, so a curve against {im2} alone says as much"
        ),
        "imprecise" => "neither slope is told from 0 (both within 2 standard errors): the \
                        standard errors are too large to read the surface; run more records"
            .to_string(),
        "decreasing-in-im1" => format!(
            "the probability falls as {im1} grows at a fixed {im2}: not a fragility surface in \
             {im1}; no median is given"
        ),
        "no-data" => "no successful analysis".to_string(),
        "none-overturned" => "no analysis exceeded the limit state: not fitted".to_string(),
        "all-overturned" => "every analysis exceeded the limit state: not fitted".to_string(),
        "collinear" => format!(
            "not fitted: every analysis lies on one line of the (ln {im1}, ln {im2}) plane, so \
             the two slopes cannot be told apart (records of more varied {im2} at each \
             {im1}, or another pair of IMs)"
        ),
        "separated" => format!(
            "not fitted: a straight line of the (ln {im1}, ln {im2}) plane separates the \
             analyses that exceeded the limit state from the others, so the surface is a step; \
             run more records or stripes near that line"
        ),
        "no-convergence" => "not fitted: the fit did not converge".to_string(),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The analytic score and information match central differences of ℓ.
    #[test]
    fn score_and_information_match_finite_differences() {
        let groups: Vec<Group> = [
            (-1.0, 0.3, 10.0, 2.0),
            (0.2, -0.5, 8.0, 5.0),
            (0.7, 0.9, 6.0, 6.0),
            (-0.4, -1.2, 5.0, 0.0),
            (1.1, 0.1, 9.0, 7.0),
        ]
        .iter()
        .map(|&(x1, x2, n, z)| Group {
            x: [1.0, x1, x2],
            n,
            z,
        })
        .collect();
        let p = [0.2, 1.3, -0.6];
        let (_, score, info) = evaluate(&groups, p);
        let h = 1e-5;
        for i in 0..3 {
            let (mut pp, mut pm) = (p, p);
            pp[i] += h;
            pm[i] -= h;
            let (ep, em) = (evaluate(&groups, pp), evaluate(&groups, pm));
            let d = (ep.0 - em.0) / (2.0 * h);
            assert!((d - score[i]).abs() < 1e-6 * score[i].abs().max(1.0));
            for (j, &cell) in info[i].iter().enumerate() {
                let dd = -(ep.1[j] - em.1[j]) / (2.0 * h);
                assert!((dd - cell).abs() < 1e-6 * cell.abs().max(1.0));
            }
        }
    }

    /// Points on one line, data separated by a line, and all-or-nothing
    /// data are refused with their reason, never fitted.
    #[test]
    fn unfittable_data_say_why() {
        let pt = |im1: f64, im2: f64, trials: u64, exceeded: u64| SurfacePoint {
            im1,
            im2,
            trials,
            exceeded,
        };
        // IM2 = 2 IM1 everywhere: one line
        let line: Vec<SurfacePoint> = (1..6)
            .map(|i| pt(0.2 * i as f64, 0.4 * i as f64, 10, i as u64))
            .collect();
        assert_eq!(fit_surface(&line), Err(SurfaceUnfit::Collinear));
        // exceeded exactly where ln x₁ + ln x₂ > 0
        let mut sep = Vec::new();
        for i in 0..6 {
            for j in 0..6 {
                let (x1, x2) = (0.3 * (i + 1) as f64, 0.35 * (j + 1) as f64);
                let over = dm::ln(x1) + dm::ln(x2) > 0.0;
                sep.push(pt(x1, x2, 5, if over { 5 } else { 0 }));
            }
        }
        assert_eq!(fit_surface(&sep), Err(SurfaceUnfit::Separated));
        let none: Vec<SurfacePoint> = sep.iter().map(|p| pt(p.im1, p.im2, 5, 0)).collect();
        assert_eq!(fit_surface(&none), Err(SurfaceUnfit::NoneExceeded));
        let all: Vec<SurfacePoint> = sep.iter().map(|p| pt(p.im1, p.im2, 5, 5)).collect();
        assert_eq!(fit_surface(&all), Err(SurfaceUnfit::AllExceeded));
        assert_eq!(fit_surface(&[]), Err(SurfaceUnfit::NoData));
    }
}
