//! Small exact and asymptotic tests on counts, for comparing overturning
//! counts with the paper's and for trends over a factor such as e.
//!
//! - [`fisher_exact`]: two-sided Fisher exact test of a 2×2 table (k₁ of n₁
//!   against k₂ of n₂), the test for one cell of 25 runs against the paper's
//!   25 (Agresti 2002, §3.5.1);
//! - [`cochran_armitage`]: the Cochran–Armitage test for a linear trend in
//!   proportions over ordered groups with scores (Agresti 2002, §5.3.5);
//! - [`binomial_log_likelihood`]: ln P(k | n, p), the per-cell score of how
//!   probable a published count is under a simulated rate.
//!
//! References: Agresti, A. (2002). *Categorical Data Analysis*, 2nd ed. Wiley.

use crate::detmath::{self as dm, ln_binomial};

/// Two-sided p-value of Fisher's exact test for the 2×2 table
/// (k1 of n1 successes against k2 of n2).
///
/// Conditional on the margins, k1 is hypergeometric; the p-value sums the
/// probabilities of every table no more probable than the observed one
/// (the usual two-sided rule, with a 1e-7 relative tolerance for ties).
///
/// ```
/// // 0 of 25 against 8 of 25: a clear difference.
/// let p = rockfrag::stats::fisher_exact(0, 25, 8, 25);
/// assert!((p - 0.0040).abs() < 1e-4);
/// ```
pub fn fisher_exact(k1: u64, n1: u64, k2: u64, n2: u64) -> f64 {
    assert!(k1 <= n1 && k2 <= n2, "counts above their totals");
    let (k, n) = (k1 + k2, n1 + n2);
    // ln P(X = x): X ~ Hypergeometric(population n, successes k, draws n1).
    let ln_p = |x: u64| ln_binomial(k, x) + ln_binomial(n - k, n1 - x) - ln_binomial(n, n1);
    let lo = k.saturating_sub(n2);
    let hi = k.min(n1);
    let observed = ln_p(k1);
    let p: f64 = (lo..=hi)
        .map(ln_p)
        .filter(|&l| l <= observed + 1e-7)
        .map(dm::exp)
        .sum();
    p.min(1.0)
}

/// The result of a [`cochran_armitage`] trend test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trend {
    /// The standardised statistic Z: positive when the proportion rises
    /// with the score.
    pub z: f64,
    /// Two-sided p-value, from the normal approximation.
    pub p: f64,
    /// Least-squares slope of the proportion against the score (per unit
    /// score), the size of the trend.
    pub slope: f64,
}

/// Cochran–Armitage test for a linear trend in the proportions
/// `successes[i] / trials[i]` over groups with `scores[i]` (e.g. e = 0, 0.3,
/// 0.6, 0.9).
///
/// T = Σ sᵢ (xᵢ − nᵢ p̄), Var T = p̄(1 − p̄)[Σ nᵢ sᵢ² − (Σ nᵢ sᵢ)²/N],
/// Z = T/√Var T (Agresti 2002, eq. 5.17). Returns `None` when the test is
/// undefined: fewer than two groups with trials, all scores equal, or every
/// trial a success (or none).
///
/// ```
/// use rockfrag::stats::cochran_armitage;
/// // 159, 160, 138, 127 of 300: the paper's overturn counts over e.
/// let t = cochran_armitage(&[159, 160, 138, 127], &[300; 4], &[0.0, 0.3, 0.6, 0.9]).unwrap();
/// assert!(t.z < -2.0 && t.p < 0.05);
/// ```
pub fn cochran_armitage(successes: &[u64], trials: &[u64], scores: &[f64]) -> Option<Trend> {
    assert!(successes.len() == trials.len() && trials.len() == scores.len());
    let n: f64 = trials.iter().map(|&t| t as f64).sum();
    let x: f64 = successes.iter().map(|&s| s as f64).sum();
    if n == 0.0 {
        return None;
    }
    let pbar = x / n;
    let (mut t, mut sn, mut ssn) = (0.0, 0.0, 0.0);
    for ((&xi, &ni), &si) in successes.iter().zip(trials).zip(scores) {
        let (xi, ni) = (xi as f64, ni as f64);
        t += si * (xi - ni * pbar);
        sn += ni * si;
        ssn += ni * si * si;
    }
    let spread = ssn - sn * sn / n; // Σ nᵢ (sᵢ − s̄)²
    let var = pbar * (1.0 - pbar) * spread;
    if var.is_nan() || var <= 0.0 {
        return None;
    }
    let z = t / var.sqrt();
    let p = (2.0 * dm::norm_sf(z.abs())).min(1.0);
    Some(Trend {
        z,
        p,
        slope: t / spread,
    })
}

/// A p-value as text: three significant figures, or e-notation below 0.001
/// (`0.679`, `0.00230` is `2.3e-3`).
pub fn p_text(p: f64) -> String {
    if p < 0.001 {
        format!("{p:.1e}")
    } else {
        let decimals = (2 - dm::log10(p).floor() as i32).max(0) as usize;
        format!("{p:.decimals$}")
    }
}

/// ln P(K = k) for K ~ Binomial(n, p); p is clamped to [1e-12, 1 − 1e-12]
/// so that a count the rate calls impossible scores very low, not −∞.
pub fn binomial_log_likelihood(k: u64, n: u64, p: f64) -> f64 {
    let p = p.clamp(1e-12, 1.0 - 1e-12);
    ln_binomial(n, k) + k as f64 * dm::ln(p) + (n - k) as f64 * dm::ln(1.0 - p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fisher_matches_tables_computed_by_hand() {
        // Identical counts: nothing is less probable than the observed
        // table's mode → p = 1.
        assert!((fisher_exact(10, 25, 10, 25) - 1.0).abs() < 1e-12);
        // 0/25 vs 8/25: margins k = 8 of 50. P(X=0) = C(25,8)/C(50,8), and by
        // symmetry the two tails are equal: p = 2·C(25,8)/C(50,8).
        let c = |n: f64, r: f64| dm::exp(ln_binomial(n as u64, r as u64));
        let expected = 2.0 * c(25.0, 8.0) / c(50.0, 8.0);
        assert!((fisher_exact(0, 25, 8, 25) - expected).abs() < 1e-12);
        // Symmetric in the two groups.
        assert!((fisher_exact(3, 25, 9, 25) - fisher_exact(9, 25, 3, 25)).abs() < 1e-12);
        // The classic tea-tasting table (Fisher 1935): 3 of 4 vs 1 of 4,
        // two-sided p = 34/70.
        assert!((fisher_exact(3, 4, 1, 4) - 34.0 / 70.0).abs() < 1e-12);
    }

    #[test]
    fn cochran_armitage_sign_size_and_flat_case() {
        let s = [0.0, 0.3, 0.6, 0.9];
        // Equal proportions: Z = 0, p = 1.
        let flat = cochran_armitage(&[10, 10, 10, 10], &[25; 4], &s).unwrap();
        assert!(flat.z.abs() < 1e-12 && (flat.p - 1.0).abs() < 1e-12);
        // Z by hand for two groups (scores 0, 1): it is the two-proportion
        // z-test with pooled variance: 20/50 vs 30/50 → p̄ = 0.5,
        // Z = (0.6 − 0.4)/√(0.25·(1/50 + 1/50)) = 2.
        let two = cochran_armitage(&[20, 30], &[50, 50], &[0.0, 1.0]).unwrap();
        assert!((two.z - 2.0).abs() < 1e-12, "{}", two.z);
        assert!((two.slope - 0.2).abs() < 1e-12);
        assert!((two.p - 0.0455).abs() < 1e-4);
        // Undefined without variation.
        assert!(cochran_armitage(&[0, 0], &[5, 5], &[0.0, 1.0]).is_none());
        assert!(cochran_armitage(&[1, 2], &[5, 5], &[1.0, 1.0]).is_none());
    }

    #[test]
    fn p_values_print_in_three_figures_or_e_notation() {
        assert_eq!(p_text(0.6794), "0.679");
        assert_eq!(p_text(0.0023), "0.00230");
        assert_eq!(p_text(1.0), "1.00");
        assert_eq!(p_text(1.2e-12), "1.2e-12");
    }

    #[test]
    fn binomial_log_likelihood_is_a_distribution() {
        let total: f64 = (0..=25)
            .map(|k| dm::exp(binomial_log_likelihood(k, 25, 0.37)))
            .sum();
        assert!((total - 1.0).abs() < 1e-12);
        assert!(binomial_log_likelihood(3, 25, 0.0).is_finite());
    }
}
