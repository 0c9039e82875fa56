//! Time envelopes c(t) that modulate the stationary process: ẍg(t) = c(t)·a(t).
//!
//! Only the shape matters: records are scaled to a target PGA afterwards.

use crate::detmath as dm;
use crate::error::{Error, Result};

/// A deterministic time-modulating function c(t), t in seconds from the
/// record's first sample. Serialised with a `kind` tag, e.g.
/// `{ kind = "saragoni_hart", t_peak = 4.0, t_end = 20.0, end_level = 0.05 }`.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Envelope {
    /// The paper's eq. (7) (adapted from Grigoriu et al. 1988), the default:
    /// |c(t)|² = 0.038·exp(−16(t−14.5)²/25) + 0.0073·exp(−16(t−13.5)²/400),
    /// peaking near t = 14.5 s; meant for 30-s records.
    #[default]
    PaperEq7,
    /// c(t) = 1: the stationary process itself.
    Unit,
    /// Piecewise-linear: 0 → 1 on [0, `rise_end`], 1 on [`rise_end`,
    /// `decay_start`], 1 → 0 on [`decay_start`, `end`], 0 afterwards.
    Trapezoid {
        /// End of the linear rise, s.
        rise_end: f64,
        /// Start of the linear decay, s (≥ `rise_end`).
        decay_start: f64,
        /// Time at which c reaches 0, s (≥ `decay_start`).
        end: f64,
    },
    /// Saragoni–Hart (gamma-type) shape c(t) = (t/t_p)^b · exp(b(1 − t/t_p)):
    /// 0 at t = 0, peak 1 at `t_peak`, equal to `end_level` at `t_end`
    /// (b follows from these three).
    SaragoniHart {
        /// Time of the peak, s (> 0).
        t_peak: f64,
        /// Time at which c has decayed to `end_level`, s (> `t_peak`).
        t_end: f64,
        /// Level reached at `t_end`, in (0, 1).
        end_level: f64,
    },
}

impl Envelope {
    /// Checks the parameters; errors name the field as `envelope.<name>`.
    pub fn validate(&self) -> Result<()> {
        let finite = |name: &str, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(Error::invalid(name, v, "a finite number"))
            }
        };
        match *self {
            Envelope::PaperEq7 | Envelope::Unit => Ok(()),
            Envelope::Trapezoid {
                rise_end,
                decay_start,
                end,
            } => {
                finite("envelope.rise_end", rise_end)?;
                finite("envelope.decay_start", decay_start)?;
                finite("envelope.end", end)?;
                if rise_end < 0.0 {
                    return Err(Error::invalid("envelope.rise_end", rise_end, "≥ 0 s"));
                }
                if decay_start < rise_end {
                    return Err(Error::invalid(
                        "envelope.decay_start",
                        decay_start,
                        "≥ envelope.rise_end",
                    ));
                }
                if end < decay_start {
                    return Err(Error::invalid(
                        "envelope.end",
                        end,
                        "≥ envelope.decay_start",
                    ));
                }
                if end <= 0.0 {
                    return Err(Error::invalid("envelope.end", end, "> 0 s"));
                }
                Ok(())
            }
            Envelope::SaragoniHart {
                t_peak,
                t_end,
                end_level,
            } => {
                finite("envelope.t_peak", t_peak)?;
                finite("envelope.t_end", t_end)?;
                if t_peak <= 0.0 {
                    return Err(Error::invalid("envelope.t_peak", t_peak, "> 0 s"));
                }
                if t_end <= t_peak {
                    return Err(Error::invalid("envelope.t_end", t_end, "> envelope.t_peak"));
                }
                if !(end_level > 0.0 && end_level < 1.0) {
                    return Err(Error::invalid("envelope.end_level", end_level, "in (0, 1)"));
                }
                Ok(())
            }
        }
    }

    /// c(t) at time `t` (s). Assumes valid parameters (see [`Envelope::validate`]).
    ///
    /// ```
    /// use rockfrag::motion::Envelope;
    /// let c = Envelope::PaperEq7.value(14.5);
    /// assert!((c * c - (0.038 + 0.0073 * (-16.0_f64 / 400.0).exp())).abs() < 1e-15);
    /// assert_eq!(Envelope::Unit.value(3.0), 1.0);
    /// ```
    pub fn value(&self, t: f64) -> f64 {
        match *self {
            Envelope::PaperEq7 => {
                let a = 0.038 * dm::exp(-16.0 * dm::powi(t - 14.5, 2) / 25.0);
                let b = 0.0073 * dm::exp(-16.0 * dm::powi(t - 13.5, 2) / 400.0);
                (a + b).sqrt()
            }
            Envelope::Unit => 1.0,
            Envelope::Trapezoid {
                rise_end,
                decay_start,
                end,
            } => {
                if t < 0.0 || t >= end {
                    0.0
                } else if t < rise_end {
                    t / rise_end
                } else if t <= decay_start {
                    1.0
                } else {
                    (end - t) / (end - decay_start)
                }
            }
            Envelope::SaragoniHart {
                t_peak,
                t_end,
                end_level,
            } => {
                if t <= 0.0 {
                    return 0.0;
                }
                let x_end = t_end / t_peak;
                let b = dm::ln(end_level) / (dm::ln(x_end) + 1.0 - x_end);
                let x = t / t_peak;
                dm::exp(b * (dm::ln(x) + 1.0 - x))
            }
        }
    }

    /// Samples c(k·dt) for k = 0..n.
    pub fn sample(&self, dt: f64, n: usize) -> Vec<f64> {
        (0..n).map(|k| self.value(k as f64 * dt)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn saragoni_hart_hits_its_three_conditions() {
        let e = Envelope::SaragoniHart {
            t_peak: 4.0,
            t_end: 20.0,
            end_level: 0.05,
        };
        e.validate().unwrap();
        assert_eq!(e.value(0.0), 0.0);
        assert!((e.value(4.0) - 1.0).abs() < 1e-15);
        assert!((e.value(20.0) - 0.05).abs() < 1e-14);
        assert!(e.value(3.9) < 1.0 && e.value(4.1) < 1.0);
    }

    #[test]
    fn trapezoid_shape() {
        let e = Envelope::Trapezoid {
            rise_end: 2.0,
            decay_start: 10.0,
            end: 14.0,
        };
        e.validate().unwrap();
        assert_eq!(e.value(1.0), 0.5);
        assert_eq!(e.value(5.0), 1.0);
        assert_eq!(e.value(12.0), 0.5);
        assert_eq!(e.value(14.0), 0.0);
    }

    #[test]
    fn serde_round_trip_and_unknown_fields() {
        let e = Envelope::SaragoniHart {
            t_peak: 4.0,
            t_end: 20.0,
            end_level: 0.05,
        };
        let s = serde_json::to_string(&e).unwrap();
        assert_eq!(serde_json::from_str::<Envelope>(&s).unwrap(), e);
        let unit: Envelope = serde_json::from_str(r#"{"kind":"unit"}"#).unwrap();
        assert_eq!(unit, Envelope::Unit);
        let bad = r#"{"kind":"trapezoid","rise_end":1,"decay_start":2,"end":3,"oops":1}"#;
        assert!(serde_json::from_str::<Envelope>(bad).is_err());
    }

    #[test]
    fn rejects_bad_parameters() {
        let e = Envelope::SaragoniHart {
            t_peak: 4.0,
            t_end: 2.0,
            end_level: 0.05,
        };
        assert!(
            e.validate()
                .unwrap_err()
                .to_string()
                .contains("envelope.t_end")
        );
    }
}
