//! Power spectral density of the stationary ground acceleration: the modified
//! Kanai–Tajimi (Clough–Penzien) filter, paper eq. (6).
//!
//! ```text
//!            1 + (2ξg f/fg)²                        (f/f2)⁴
//! S(f) = S0 ─────────────────────────────── · ───────────────────────────────
//!          (1 − (f/fg)²)² + (2ξg f/fg)²       (1 − (f/f2)²)² + (2ξ2 f/f2)²
//! ```
//!
//! f in Hz; S is **one-sided** in Hz: the variance of the process is
//! ∫₀^∞ S(f) df, in (m/s²)².

use crate::detmath as dm;
use crate::error::{Error, Result};

/// Parameters of the Clough–Penzien spectrum, eq. (6). Defaults: the paper's
/// "firm soil" (Kung and Pecknold 1982).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CloughPenzien {
    /// White-noise level S0 of the one-sided PSD, (m/s²)²/Hz (default: 1.0).
    /// Synthetic records are scaled to a target PGA afterwards, so S0 only sets
    /// the level of the unscaled process.
    pub s0: f64,
    /// Ground-filter damping ratio ξg, dimensionless (default: 0.62).
    pub xi_g: f64,
    /// Ground-filter frequency fg, Hz (default: 2.46).
    pub f_g: f64,
    /// Second (high-pass) filter damping ratio ξ2, dimensionless (default: 0.62).
    pub xi_2: f64,
    /// Second (high-pass) filter frequency f2, Hz (default: 0.28).
    pub f_2: f64,
}

impl Default for CloughPenzien {
    fn default() -> Self {
        CloughPenzien {
            s0: 1.0,
            xi_g: 0.62,
            f_g: 2.46,
            xi_2: 0.62,
            f_2: 0.28,
        }
    }
}

impl CloughPenzien {
    /// One-sided PSD S(f) at frequency `f` (Hz), in (m/s²)²/Hz.
    ///
    /// ```
    /// use rockfrag::motion::CloughPenzien;
    /// let psd = CloughPenzien::default();
    /// assert_eq!(psd.density(0.0), 0.0);
    /// assert!(psd.density(2.0) > psd.density(20.0));
    /// ```
    pub fn density(&self, f: f64) -> f64 {
        let rg = f / self.f_g;
        let r2 = f / self.f_2;
        let dg = dm::powi(2.0 * self.xi_g * rg, 2);
        let d2 = dm::powi(2.0 * self.xi_2 * r2, 2);
        let kanai_tajimi = (1.0 + dg) / (dm::powi(1.0 - rg * rg, 2) + dg);
        let high_pass = dm::powi(r2, 4) / (dm::powi(1.0 - r2 * r2, 2) + d2);
        self.s0 * kanai_tajimi * high_pass
    }

    /// Checks that every parameter is positive and finite; errors name the
    /// field as `psd.<name>`.
    pub fn validate(&self) -> Result<()> {
        for (name, v) in [
            ("psd.s0", self.s0),
            ("psd.xi_g", self.xi_g),
            ("psd.f_g", self.f_g),
            ("psd.xi_2", self.xi_2),
            ("psd.f_2", self.f_2),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::invalid(name, v, "a positive finite number"));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn density_at_the_filter_frequencies() {
        // At f = fg the ground factor is (1 + 4ξg²)/(4ξg²); the high-pass factor
        // tends to 1 for f ≫ f2.
        let psd = CloughPenzien {
            f_2: 1e-6,
            ..Default::default()
        };
        let x = 4.0 * 0.62 * 0.62;
        let s = psd.density(2.46);
        assert!((s - (1.0 + x) / x).abs() < 1e-9, "{s}");
    }

    #[test]
    fn rejects_nonpositive_parameters() {
        let psd = CloughPenzien {
            f_g: 0.0,
            ..Default::default()
        };
        let e = psd.validate().unwrap_err().to_string();
        assert!(e.contains("psd.f_g"), "{e}");
    }
}
