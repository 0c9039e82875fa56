//! Every fitted curve of a study integrated over one hazard curve, with the
//! bootstrap band of the rate.

use crate::detmath as dm;
use rayon::prelude::*;

use super::hazard::HazardCurve;
use super::input::{FittedCurve, FittedFragility};
use super::integrate::{RiskIntegral, annual_rate, risk_integral};
use crate::error::{Error, Result};
use crate::fragility::{Interval, percentile};

/// Settings of a risk assessment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RiskOptions {
    /// Exposure time N (years) of the probability of exceedance
    /// 1 − exp(−λN).
    pub years: f64,
    /// Two-sided level of the bootstrap band on the rate (0.9: 5th–95th
    /// percentiles, as the fragility bands).
    pub confidence: f64,
    /// Share of the rate from beyond either end of the hazard curve above
    /// which a result is flagged ([`RiskRow::tail_warning`]).
    pub tail_warning: f64,
}

impl Default for RiskOptions {
    /// 50 years, 90 % band, warn above 1 %.
    fn default() -> Self {
        RiskOptions {
            years: 50.0,
            confidence: 0.9,
            tail_warning: 0.01,
        }
    }
}

impl RiskOptions {
    /// Checks the settings.
    ///
    /// Errors: [`Error::InvalidParameter`] naming the setting.
    pub fn validate(&self) -> Result<()> {
        if !(self.years.is_finite() && self.years > 0.0) {
            return Err(Error::invalid(
                "--years",
                self.years,
                "a number of years > 0",
            ));
        }
        if !(self.confidence > 0.0 && self.confidence < 1.0) {
            return Err(Error::invalid("confidence", self.confidence, "in (0, 1)"));
        }
        Ok(())
    }
}

/// The risk of one case and limit state.
#[derive(Clone, Debug, PartialEq)]
pub struct RiskRow {
    /// The fitted curve (with its replicates).
    pub curve: FittedCurve,
    /// The integral, `None` when the case has no fitted curve.
    pub integral: Option<RiskIntegral>,
    /// Percentile band of the rate over the bootstrap replicates (`None`
    /// with fewer than 2 fitted replicates).
    pub band: Option<Interval>,
}

impl RiskRow {
    /// Annual rate λ_LS (1/yr).
    pub fn rate(&self) -> Option<f64> {
        self.integral.map(|i| i.rate)
    }

    /// Return period 1/λ_LS (years): +∞ for a rate of 0 (never).
    pub fn return_period(&self) -> Option<f64> {
        self.rate()
            .map(|r| if r > 0.0 { 1.0 / r } else { f64::INFINITY })
    }

    /// The peak IM as tables print it: `-` for a rate of 0 (nothing drives it).
    pub fn peak_text(&self) -> String {
        match self.integral {
            Some(i) if i.rate > 0.0 => crate::io_util::sig3(i.peak_im),
            _ => "-".to_string(),
        }
    }

    /// The return period as tables print it: `never` for a rate of 0.
    pub fn return_period_text(&self) -> Option<String> {
        self.return_period().map(|t| {
            if t.is_finite() {
                crate::io_util::sig3(t)
            } else {
                "never".to_string()
            }
        })
    }

    /// Probability of exceeding the limit state at least once in `years`,
    /// 1 − exp(−λN) (Poisson occurrence).
    pub fn poe(&self, years: f64) -> Option<f64> {
        self.rate().map(|r| -dm::exp_m1(-r * years))
    }

    /// Probability of not exceeding the limit state in `years`, exp(−λN)
    /// (Poisson occurrence): for an object still standing after N years
    /// (a precariously balanced rock), how likely the hazard curve makes
    /// that; a small value argues against the hazard curve (or the
    /// fragility).
    pub fn survival(&self, years: f64) -> Option<f64> {
        self.rate().map(|r| dm::exp(-r * years))
    }

    /// The bootstrap band of [`RiskRow::survival`]: exp(−λN) at the rate
    /// band's ends (the high rate gives the low survival).
    pub fn survival_band(&self, years: f64) -> Option<Interval> {
        self.band.map(|b| Interval {
            lo: dm::exp(-b.hi * years),
            hi: dm::exp(-b.lo * years),
        })
    }

    /// Shares of the rate from below and above the hazard curve's ends
    /// (0 when the rate is 0).
    pub fn shares(&self) -> Option<(f64, f64)> {
        self.integral.map(|i| {
            if i.rate > 0.0 {
                (i.share_below(), i.share_above())
            } else {
                (0.0, 0.0)
            }
        })
    }

    /// A sentence when either end carries more than `limit` of the rate.
    pub fn tail_warning(&self, limit: f64) -> Option<String> {
        let (below, above) = self.shares()?;
        let pct = |x: f64| format!("{:.1} %", 100.0 * x);
        let mut parts = Vec::new();
        if below > limit {
            parts.push(format!(
                "{} of the rate comes from below the hazard curve's lowest level \
                 (extrapolated; give the curve lower levels)",
                pct(below)
            ));
        }
        let flat_top = self.integral.map_or(0.0, |i| i.flat_top);
        if above > limit && flat_top > 0.0 {
            parts.push(format!(
                "{} comes from the shaking above the hazard curve's highest level, which \
                 its flat last segment does not distribute: counted at that level, a lower \
                 bound (give the curve levels where its rate falls)",
                pct(above)
            ));
        } else if above > limit {
            parts.push(format!(
                "{} comes from above its highest level (extrapolated as the last \
                 segment's power law; give the curve higher levels)",
                pct(above)
            ));
        }
        (!parts.is_empty()).then(|| {
            format!(
                "{} {}: {}",
                self.curve.key,
                self.curve.limit_state,
                parts.join("; ")
            )
        })
    }
}

/// One row per case (in the order the cases first appear) for
/// [`RiskRow::survival`]: the case's limit state named `overturning`, else
/// its last (most severe) one.
pub fn standing_rows(rows: &[RiskRow]) -> Vec<&RiskRow> {
    let mut out: Vec<&RiskRow> = Vec::new();
    for r in rows {
        match out.iter_mut().find(|o| o.curve.key == r.curve.key) {
            None => out.push(r),
            Some(o) if o.curve.limit_state != OVERTURNING => *o = r,
            Some(_) => {}
        }
    }
    out
}

/// The limit state whose survival [`standing_rows`] prefers.
const OVERTURNING: &str = "overturning";

/// Integrates every fitted curve of `fragility` over `hazard` (levels in the
/// fit's unit: see [`HazardCurve::in_unit_of`]), each bootstrap replicate
/// too for the band (in parallel; the result does not depend on the number
/// of threads).
pub fn assess(
    fragility: &FittedFragility,
    hazard: &HazardCurve,
    options: &RiskOptions,
) -> Result<Vec<RiskRow>> {
    options.validate()?;
    let q = [
        (1.0 - options.confidence) / 2.0,
        (1.0 + options.confidence) / 2.0,
    ];
    Ok(fragility
        .curves
        .iter()
        .map(|curve| {
            let integral = curve.fit.map(|(m, b)| risk_integral(hazard, m, b));
            let band = (integral.is_some() && curve.replicates.len() >= 2).then(|| {
                let mut rates: Vec<f64> = curve
                    .replicates
                    .par_iter()
                    .map(|&(m, b)| annual_rate(hazard, m, b))
                    .collect();
                rates.sort_by(f64::total_cmp);
                Interval {
                    lo: percentile(&rates, q[0]),
                    hi: percentile(&rates, q[1]),
                }
            });
            RiskRow {
                curve: curve.clone(),
                integral,
                band,
            }
        })
        .collect())
}
