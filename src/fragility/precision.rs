//! A fragility curve to a stated precision: the target (`[fragility]
//! precision`), the band a fit reached, the lattice of levels an adaptive
//! run chooses from, and where the next analyses narrow the band most (the
//! probit fit's Fisher information). The rounds themselves are run by
//! `study::adaptive`; docs/adaptive.md argues the choices.
//!
//! With u = ln x and η = a + b·u (the probit model of [`super::fit_lognormal`]),
//! one analysis at u carries the Fisher information
//!
//! ```text
//! I(a, b) = w(η) [1 u; u u²],   w(η) = φ(η)² / (Φ(η) Φ(−η))
//! ```
//!
//! and the variances of ln θ = −a/b and β = 1/b follow by the delta method,
//! gᵀ I⁻¹ g with g = (−1/b, a/b²) and (0, −1/b²).

use serde::{Deserialize, Serialize};

use crate::detmath as dm;
use crate::error::{Error, Result};

/// The most analyses an adaptive run spends on one case unless
/// `fragility.max_analyses` says otherwise.
pub const DEFAULT_MAX_ANALYSES: usize = 20_000;

/// The fewest analyses after which an adaptive run may stop a case whose
/// band meets its target: a percentile bootstrap over fewer records than
/// this is itself too noisy to trust (docs/adaptive.md).
pub const MIN_ANALYSES: usize = 100;

/// Lattice levels per decade of intensity: adjacent levels 12 % apart, so a
/// level chosen by the information is never more than 6 % from the best
/// one, and levels chosen in different rounds coincide (stripes accumulate).
pub const LATTICE_PER_DECADE: f64 = 20.0;

/// The precision asked for: half-widths of the two-sided band (at
/// `fragility.confidence`, 90 % by default) of the median, relative to the
/// median, and of β, absolute.
///
/// ```toml
/// [fragility]
/// precision = { median = 0.05, beta = 0.25 }
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Precision {
    /// Half-width of the median's band over the median (0.05: ±5 %).
    pub median: f64,
    /// Half-width of β's band (absolute).
    pub beta: f64,
}

impl Precision {
    /// Checks 0.001 ≤ median ≤ 0.5 and 0.001 ≤ beta ≤ 2; errors name
    /// `fragility.precision.median` or `.beta`.
    pub fn validate(&self) -> Result<()> {
        if !(self.median.is_finite() && (0.001..=0.5).contains(&self.median)) {
            return Err(Error::invalid(
                "fragility.precision.median",
                self.median,
                "a half-width relative to the median in [0.001, 0.5] (0.05 is ±5 %)",
            ));
        }
        if !(self.beta.is_finite() && (0.001..=2.0).contains(&self.beta)) {
            return Err(Error::invalid(
                "fragility.precision.beta",
                self.beta,
                "an absolute half-width of β's band in [0.001, 2]",
            ));
        }
        Ok(())
    }
}

/// The levels an adaptive run over [`min`, `max`] chooses from:
/// [`LATTICE_PER_DECADE`] per decade, log-spaced, both ends included. A pure
/// function of the range, so every round, thread count and resumption
/// uses the same levels (and a level's number keys its analyses' draws as
/// in a fixed grid).
pub fn lattice(min: f64, max: f64) -> Vec<f64> {
    let decades = dm::log10(max / min);
    let n = ((decades * LATTICE_PER_DECADE).ceil() as usize).max(1) + 1;
    let (lo, hi) = (dm::ln(min), dm::ln(max));
    (0..n)
        .map(|i| match i {
            0 => min,
            _ if i == n - 1 => max,
            _ => dm::exp(lo + (hi - lo) * i as f64 / (n - 1) as f64),
        })
        .collect()
}

/// What one fit of a case reached: the estimates and their bands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Band {
    /// Fitted median θ.
    pub median: f64,
    /// The bootstrap band of θ.
    pub median_band: (f64, f64),
    /// Fitted β.
    pub beta: f64,
    /// The bootstrap band of β.
    pub beta_band: (f64, f64),
    /// Share of bootstrap replicates that could not be fitted.
    pub unfit_share: f64,
}

impl Band {
    /// Half-width of the median's band relative to the median.
    pub fn median_half(&self) -> f64 {
        relative_half_width(self.median, self.median_band)
    }

    /// Half-width of β's band.
    pub fn beta_half(&self) -> f64 {
        0.5 * (self.beta_band.1 - self.beta_band.0)
    }
}

/// (hi − lo) / (2 θ): the half-width of a band relative to its estimate.
pub fn relative_half_width(estimate: f64, (lo, hi): (f64, f64)) -> f64 {
    0.5 * (hi - lo) / estimate
}

/// One limit state the next round must narrow: its current probit fit
/// (a, b) and the standard errors its targets ask for (a band half-width
/// over the normal quantile of the confidence).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Design {
    /// Probit intercept a.
    pub a: f64,
    /// Probit slope b = 1/β.
    pub b: f64,
    /// Standard error of ln θ asked for (`None`: met, no weight).
    pub se_ln_median: Option<f64>,
    /// Standard error of β asked for (`None`: met, no weight).
    pub se_beta: Option<f64>,
}

/// w(η) = φ(η)²/(Φ(η)Φ(−η)): the Fisher information of one binary probit
/// trial about η (Baker 2015, eq. 11 differentiated twice in expectation).
fn weight(eta: f64) -> f64 {
    // beyond |η| = 8 an analysis says nothing a double can hold
    if eta.abs() > 8.0 {
        return 0.0;
    }
    let phi = dm::exp(-0.5 * eta * eta) / (2.0 * std::f64::consts::PI).sqrt();
    let (p, q) = (dm::norm_cdf(eta), dm::norm_cdf(-eta));
    phi * phi / (p * q)
}

/// The information matrix of `counts[i]` analyses at ln-levels `u[i]`
/// under probit (a, b), plus a tiny ridge so that a design of one level
/// still inverts.
fn information(d: &Design, u: &[f64], counts: &[usize]) -> [[f64; 2]; 2] {
    let mut m = [[1e-9, 0.0], [0.0, 1e-9]];
    for (&ui, &n) in u.iter().zip(counts) {
        let w = n as f64 * weight(d.a + d.b * ui);
        m[0][0] += w;
        m[0][1] += w * ui;
        m[1][1] += w * ui * ui;
    }
    m[1][0] = m[0][1];
    m
}

/// The criterion a design minimises: Σ over the limit states of Var(ln θ)
/// and Var(β) (delta method on I⁻¹), each over the variance its target
/// asks for; a met target weighs nothing.
fn criterion(designs: &[Design], u: &[f64], counts: &[usize]) -> f64 {
    designs
        .iter()
        .map(|d| {
            let m = information(d, u, counts);
            let det = m[0][0] * m[1][1] - m[0][1] * m[0][1];
            let inv = [
                [m[1][1] / det, -m[0][1] / det],
                [-m[0][1] / det, m[0][0] / det],
            ];
            let q = |g: [f64; 2]| {
                g[0] * (inv[0][0] * g[0] + inv[0][1] * g[1])
                    + g[1] * (inv[1][0] * g[0] + inv[1][1] * g[1])
            };
            let vm = q([-1.0 / d.b, d.a / (d.b * d.b)]);
            let vb = q([0.0, -1.0 / (d.b * d.b)]);
            d.se_ln_median.map_or(0.0, |s| vm / (s * s)) + d.se_beta.map_or(0.0, |s| vb / (s * s))
        })
        .sum()
}

/// Where `batches` batches of `batch` analyses each go: greedily, each to
/// the level of `levels` (g, ascending) whose batch lowers [`criterion`]
/// most given the analyses already at each level (`counts`) and those
/// placed before it, never past `cap` analyses at a level. Returns the
/// analyses to add at each level. Deterministic: ties go to the lower level.
pub fn place(
    levels: &[f64],
    counts: &[usize],
    designs: &[Design],
    batches: usize,
    batch: usize,
    cap: usize,
) -> Vec<usize> {
    let u: Vec<f64> = levels.iter().map(|&x| dm::ln(x)).collect();
    let mut now = counts.to_vec();
    for _ in 0..batches {
        let mut best: Option<(f64, usize)> = None;
        for i in 0..levels.len() {
            if now[i] + batch > cap {
                continue;
            }
            now[i] += batch;
            let c = criterion(designs, &u, &now);
            now[i] -= batch;
            if best.is_none_or(|(b, _)| c < b) {
                best = Some((c, i));
            }
        }
        match best {
            Some((_, i)) => now[i] += batch,
            None => break,
        }
    }
    now.iter().zip(counts).map(|(n, c)| n - c).collect()
}

/// Records per level a fixed grid needs for a band of half-width `target`
/// (relative), from a pilot of `pilot` records per level whose band had
/// half-width `half`: a fixed design's band narrows as 1/√n, so
/// n = pilot · (half/target)², rounded up, and never below the pilot.
pub fn records_for(pilot: usize, half: f64, target: f64) -> usize {
    let r = half / target;
    let n = pilot as f64 * r * r;
    (n.ceil() as usize).max(pilot)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Halving a band takes four times the records.
    #[test]
    fn records_scale_as_the_inverse_square_of_the_band() {
        assert_eq!(records_for(10, 0.10, 0.05), 40);
        assert_eq!(records_for(10, 0.12, 0.05), 58); // 57.6 rounded up
        assert_eq!(records_for(10, 0.03, 0.05), 10);
    }

    #[test]
    fn lattice_is_log_spaced_with_exact_ends() {
        let l = lattice(0.05, 3.0);
        // log10(60) = 1.778 decades → 36 steps
        assert_eq!(l.len(), 37);
        assert_eq!((l[0], l[36]), (0.05, 3.0));
        let r = l[1] / l[0];
        for w in l.windows(2) {
            assert!((w[1] / w[0] - r).abs() < 1e-12, "ratio {}", w[1] / w[0]);
        }
    }

    /// The median alone is best learnt at the median: every batch goes to
    /// the lattice level nearest θ (Fisher information of a probit trial
    /// peaks at η = 0).
    #[test]
    fn median_target_places_at_the_median() {
        let levels = lattice(0.1, 1.0);
        let (theta, beta): (f64, f64) = (0.4, 0.3);
        let d = Design {
            a: -dm::ln(theta) / beta,
            b: 1.0 / beta,
            se_ln_median: Some(0.03),
            se_beta: None,
        };
        // a spread-out start so the slope is known
        let counts: Vec<usize> = (0..levels.len())
            .map(|i| usize::from(i % 5 == 0) * 5)
            .collect();
        let add = place(&levels, &counts, &[d], 10, 5, 1000);
        let nearest = (0..levels.len())
            .min_by(|&i, &j| {
                let d = |k: usize| dm::ln(levels[k] / theta).abs();
                d(i).total_cmp(&d(j))
            })
            .unwrap();
        let at: usize = (nearest.saturating_sub(1)..=nearest + 1)
            .map(|i| add[i])
            .sum();
        assert!(at >= 40, "{add:?}: most of 50 within one lattice step of θ");
    }

    /// β is learnt away from the median: its batches go to both sides.
    #[test]
    fn beta_target_places_on_both_sides() {
        let levels = lattice(0.1, 1.0);
        let (theta, beta): (f64, f64) = (0.4, 0.3);
        let d = Design {
            a: -dm::ln(theta) / beta,
            b: 1.0 / beta,
            se_ln_median: None,
            se_beta: Some(0.02),
        };
        let counts = vec![5; levels.len()];
        let add = place(&levels, &counts, &[d], 20, 5, 1000);
        let below: usize = (0..levels.len())
            .filter(|&i| levels[i] < theta * 0.9)
            .map(|i| add[i])
            .sum();
        let above: usize = (0..levels.len())
            .filter(|&i| levels[i] > theta * 1.1)
            .map(|i| add[i])
            .sum();
        assert!(below >= 30 && above >= 30, "{add:?}");
    }
}
