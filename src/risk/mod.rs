//! Risk at a site: the annual rate of each limit state, the fitted fragility
//! integrated over the site's hazard curve.
//!
//! ```text
//! fragility.csv (θ, β) ─┐
//! fragility_bootstrap.csv ─┼─▶ integrate ─▶ risk.csv, summary.md ## Risk,
//! hazard curve (OpenQuake CSV or iml,annual_rate) ─┘     figures/risk.svg,
//!                                                        risk_hazard.csv
//! ```
//!
//! `risk_hazard.csv` ([`USED_HAZARD`]) is the hazard curve as integrated
//! (levels in the fit's unit, those left out at the ends not in it): with
//! the study's fit it is all `rockfrag figures` needs to draw the risk
//! figure again, in SVG or PNG.
//!
//! ## The integral
//!
//! With λ(im) the annual rate of exceeding intensity im and
//! P(LS | im) = Φ(ln(im/θ)/β) the fitted fragility,
//!
//! ```text
//! λ_LS = ∫ P(LS | im) |dλ/dim| dim = ∫ Φ((u − ln θ)/β) (−dλ/du) du,   u = ln im.
//! ```
//!
//! The hazard curve is interpolated log–log: between levels i and i+1 it is
//! the power law λ = λᵢ (im/imᵢ)^(−kᵢ), so −dλ/du = kᵢ λ(u) and the
//! integrand on each segment is Φ times an exponential: smooth (analytic)
//! inside a segment, with jumps in slope kᵢ at the levels. The integral is
//! taken segment by segment with globally adaptive Gauss–Kronrod 7–15
//! quadrature in u: the subinterval with the largest error estimate
//! |K15 − G7| is halved until the summed estimate is below
//! [`RELATIVE_TOLERANCE`] (10⁻¹⁰) of the rate. Against the closed form for a
//! power-law hazard λ = k₀ a^(−k) and a lognormal fragility,
//! λ_LS = k₀ θ^(−k) exp(k²β²/2), the result agrees to about 10⁻¹² (tests/risk.rs).
//! The quadrature is thus not what limits the accuracy; the interpolation of
//! the hazard between its levels is (a curve bending in log–log space between
//! widely spaced levels).
//!
//! The IM that drives the rate (`peak_im`) is where the integrand peaks.
//! Because the interpolant's slope jumps at the levels, so does the
//! integrand, and its maximum would sit on whichever level the hazard
//! steepens at; the peak is therefore located on the integrand with the
//! log-slope varying linearly between the segments' midpoints (the same
//! hazard values, a continuous slope).
//!
//! ## The ends
//!
//! A hazard curve covers a finite range of levels. Below its lowest level
//! the fragility is usually negligible; above its highest the hazard is.
//! Both ends are integrated explicitly rather than dropped: the first
//! segment's power law is extended downward (to where Φ has made the
//! integrand e^(−72) of its peak) and the last segment's upward (to where
//! the hazard has fallen by e^(−40)). The parts of λ_LS from beyond each end
//! are reported (`share_below`, `share_above`) and flagged above 1 %: the
//! result then depends on an extrapolation, and the curve needs levels
//! further out. OpenQuake levels at the low end with poe = 1 (an infinite
//! rate) or so close to 1 that the file's 7 digits fix the rate to worse
//! than 0.1 % ([`MIN_RATE_PRECISION`]; poe above about 1 − 5·10⁻⁴ — their
//! slope would steer the lower extension) and levels with rate 0 at the
//! high end are left out; beyond a zero the
//! power-law extension overstates the hazard, so `share_above` is then an
//! upper bound on what that end contributes.
//!
//! A flat segment (equal rates at two levels: no shaking with an intensity
//! between them) contributes 0. A flat *last* segment has no power law to
//! extend: it says that λ_top of shaking exceeds the highest level, not how
//! far, so that shaking is counted at the highest level, λ_top·P(LS | im_top)
//! ([`RiskIntegral::flat_top`]), a lower bound, and warned about. A rate of
//! 0 has an infinite return period (`never`).
//!
//! ## Uncertainty
//!
//! `rockfrag fragility` writes each bootstrap replicate's (θ, β) to
//! `fragility_bootstrap.csv`; the integral is repeated for every fitted
//! replicate and the 5th–95th percentiles of the rates form the 90 % band
//! of `annual_rate`. It is the fit's uncertainty only: the hazard curve is
//! taken as exact (a mean hazard curve already averages its epistemic
//! branches).
//!
//! ## Units
//!
//! The hazard's IM must be the fit's: OpenQuake's `PGA` (g) for a fit
//! against `pga`, `PGV` (cm/s, converted to m/s) against `pgv`; anything
//! else is an error naming both. A plain `iml,annual_rate` file is taken to
//! be in the fit's unit.
//!
//! ## References
//! - Cornell, C. A., Jalayer, F., Hamburger, R. O. and Foutch, D. A. (2002).
//!   Probabilistic basis for 2000 SAC/FEMA steel moment frame guidelines.
//!   *J. Struct. Eng.* 128(4), 526–533 (the closed form for a power-law
//!   hazard).
//! - Piessens, R. et al. (1983). *QUADPACK*. Springer (Gauss–Kronrod 7–15).
//! - GEM Foundation. OpenQuake engine manual, *Hazard curves* (CSV outputs).

mod assess;
mod hazard;
mod input;
mod integrate;
mod output;

pub use assess::{RiskOptions, RiskRow, assess, standing_rows};
pub use hazard::{
    HazardCurve, HazardSource, MAX_ANNUAL_RATE, MIN_RATE_PRECISION, USED_HAZARD, read_hazard,
    write_used_hazard,
};
pub use input::{FittedCurve, FittedFragility, read_fragility};
pub use integrate::{
    RELATIVE_TOLERANCE, RiskIntegral, annual_rate, deaggregation, deaggregation_smoothed,
    risk_integral,
};
pub use output::{
    RISK_HEADER, RiskCsvRow, describe_hazard, read_risk_csv, summary_section, survival_cell,
    write_risk_csv,
};
