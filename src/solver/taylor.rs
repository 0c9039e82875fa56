//! Taylor-series integration of the rock equation over an interval of linear
//! forcing.
//!
//! In the pivot's frame, ψ = sθ ≥ 0 and φ = θc − ψ, eq. (1) reads
//!
//! ```text
//! ψ̈ = k (s ẍg cos φ − (g + ÿg) sin φ),   k = 3/(4R),
//! ```
//!
//! and on one record sample both accelerations are linear in τ = t − t0. The
//! Taylor coefficients of ψ, sin φ and cos φ then follow from the usual
//! recurrences (automatic differentiation of sin/cos, e.g. Jorba & Zou 2005,
//! *Experimental Mathematics* 14):
//!
//! ```text
//! j S_j = −Σ_{i=1..j} i ψ_i C_{j−i},   j C_j = Σ_{i=1..j} i ψ_i S_{j−i},
//! (j+1)(j+2) ψ_{j+2} = k (s (a0 C_j + a1 C_{j−1}) − (v0 S_j + v1 S_{j−1})),
//! ```
//!
//! with one sine and cosine, at τ = 0, for the whole series. A sample of a
//! rocking block (Δt ≈ 0.01–0.02 s against a rocking time scale 1/p ≈ 0.4 s)
//! is usually one step of order [`ORDER`] accurate to rounding, and the series
//! is its own dense output: events are located on the polynomial, and the
//! contact forces come from the sin φ and cos φ polynomials, with no further
//! trigonometry. The step is cut when the last two terms exceed the tolerance.

/// Order of the series (terms τ⁰ … τ^ORDER).
pub const ORDER: usize = 8;

/// 1/j for j = 0..=ORDER (1/0 unused).
const INV: [f64; ORDER + 1] = {
    let mut t = [0.0; ORDER + 1];
    let mut j = 1;
    while j <= ORDER {
        t[j] = 1.0 / j as f64;
        j += 1;
    }
    t
};

/// The Taylor series of one rock step: ψ, sin φ and cos φ in τ = t − t0.
#[derive(Clone, Copy, Debug)]
pub struct RockSeries {
    /// Coefficients of ψ = sθ.
    pub psi: [f64; ORDER + 1],
    /// Coefficients of sin φ, φ = θc − ψ.
    pub sin: [f64; ORDER + 1],
    /// Coefficients of cos φ.
    pub cos: [f64; ORDER + 1],
    /// Coefficients of ψ̇ ((j+1) ψ_{j+1}; the last is 0).
    pub dpsi: [f64; ORDER + 1],
}

/// Forcing of one step, linear in τ: ẍg = a0 + a1 τ, g + ÿg = v0 + v1 τ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearForcing {
    /// ẍg at τ = 0 (m/s²).
    pub a0: f64,
    /// dẍg/dt (m/s³).
    pub a1: f64,
    /// g + ÿg at τ = 0 (m/s²).
    pub v0: f64,
    /// dÿg/dt (m/s³).
    pub v1: f64,
}

impl RockSeries {
    /// The series from ψ(0) = `psi0`, ψ̇(0) = `dpsi0` for a block of critical
    /// angle `theta_c` and k = 3/(4R), rocking on side `s`, under `forcing`.
    #[inline]
    pub fn new(
        theta_c: f64,
        k: f64,
        s: f64,
        psi0: f64,
        dpsi0: f64,
        forcing: &LinearForcing,
    ) -> RockSeries {
        let mut psi = [0.0; ORDER + 1];
        let mut sin = [0.0; ORDER + 1];
        let mut cos = [0.0; ORDER + 1];
        psi[0] = psi0;
        psi[1] = dpsi0;
        (sin[0], cos[0]) = (theta_c - psi0).sin_cos();
        let (sa0, sa1) = (s * forcing.a0, s * forcing.a1);
        for j in 0..=ORDER {
            if j >= 1 {
                // d/dτ sin φ = cos φ φ′, d/dτ cos φ = −sin φ φ′, φ′ = −ψ′
                let (mut sj, mut cj) = (0.0, 0.0);
                for i in 1..=j {
                    let ip = i as f64 * psi[i];
                    sj -= ip * cos[j - i];
                    cj += ip * sin[j - i];
                }
                sin[j] = sj * INV[j];
                cos[j] = cj * INV[j];
            }
            if j + 2 <= ORDER {
                // eq. (1), coefficient of τ^j
                let (c_prev, s_prev) = if j >= 1 {
                    (cos[j - 1], sin[j - 1])
                } else {
                    (0.0, 0.0)
                };
                let rhs =
                    k * (sa0 * cos[j] + sa1 * c_prev - forcing.v0 * sin[j] - forcing.v1 * s_prev);
                psi[j + 2] = rhs * INV[j + 1] * INV[j + 2];
            }
        }
        let mut dpsi = [0.0; ORDER + 1];
        for j in 0..ORDER {
            dpsi[j] = (j + 1) as f64 * psi[j + 1];
        }
        RockSeries {
            psi,
            sin,
            cos,
            dpsi,
        }
    }

    /// (ψ, ψ̇) at τ (Horner).
    #[inline]
    pub fn at(&self, tau: f64) -> (f64, f64) {
        // dpsi[ORDER] = 0, so one loop serves both (two independent chains)
        let (mut p, mut d) = (self.psi[ORDER], 0.0);
        for j in (0..ORDER).rev() {
            p = p * tau + self.psi[j];
            d = d * tau + self.dpsi[j];
        }
        (p, d)
    }

    /// (ψ, ψ̇, sin φ, cos φ) at τ.
    #[inline]
    pub fn full_at(&self, tau: f64) -> (f64, f64, f64, f64) {
        let (p, d) = self.at(tau);
        let mut sn = self.sin[ORDER];
        let mut cs = self.cos[ORDER];
        for j in (0..ORDER).rev() {
            sn = sn * tau + self.sin[j];
            cs = cs * tau + self.cos[j];
        }
        (p, d, sn, cs)
    }

    /// Bounds (lower, upper) of ψ over τ ∈ [0, h]: ψ0 ∓ Σ_{j≥1} |ψ_j| h^j
    /// (plus the truncation tolerance the step was chosen for, `tol`).
    #[inline]
    pub fn psi_bounds(&self, h: f64, tol: f64) -> (f64, f64) {
        let mut r = 0.0;
        for j in (1..=ORDER).rev() {
            r = r * h + self.psi[j].abs();
        }
        let r = r * h + tol;
        (self.psi[0] - r, self.psi[0] + r)
    }

    /// The largest step h ≤ `h_max` whose truncation error, estimated by the
    /// last two terms of ψ and of ψ̇, is within `tol_psi` and `tol_dpsi`.
    #[inline]
    pub fn step(&self, h_max: f64, tol_psi: f64, tol_dpsi: f64) -> f64 {
        let fits = |h: f64| {
            let (a, b) = (self.psi[ORDER].abs(), self.psi[ORDER - 1].abs());
            let hk1 = h.powi(ORDER as i32 - 1);
            let e_psi = a * hk1 * h + b * hk1;
            let e_dpsi = (ORDER as f64 * a * h + (ORDER - 1) as f64 * b) * hk1 / h;
            e_psi <= tol_psi && e_dpsi <= tol_dpsi
        };
        if fits(h_max) {
            return h_max;
        }
        // each term bounded separately: |c_j| h^j ≤ tol/2 and j|c_j| h^(j−1) ≤ tol/2
        let mut h = h_max;
        for j in [ORDER - 1, ORDER] {
            let c = self.psi[j].abs();
            if c > 0.0 {
                let jf = j as f64;
                h = h.min((0.5 * tol_psi / c).powf(1.0 / jf));
                h = h.min((0.5 * tol_dpsi / (jf * c)).powf(1.0 / (jf - 1.0)));
            }
        }
        0.9 * h
    }

    /// Series of the ground's work per unit mass, W(τ) = ∫ −ẍg ẋ − ÿg ẏ dτ
    /// (W(0) = 0), for a block of radius `r` rocking on side `s`: with
    /// ẋ = −s R cos φ ψ̇ and ẏ = R sin φ ψ̇ (the rock kinematics).
    pub fn work(&self, r: f64, s: f64, forcing: &LinearForcing, g: f64) -> [f64; ORDER + 1] {
        // D = ψ̇, CD = cos φ ψ̇, SD = sin φ ψ̇, truncated at τ^(ORDER−1)
        let mut d = [0.0; ORDER];
        for (j, dj) in d.iter_mut().enumerate() {
            *dj = (j + 1) as f64 * self.psi[j + 1];
        }
        let mut w = [0.0; ORDER + 1];
        let (ay0, ay1) = (forcing.v0 - g, forcing.v1);
        let (mut cd_prev, mut sd_prev) = (0.0, 0.0);
        for j in 0..ORDER {
            let (mut cd, mut sd) = (0.0, 0.0);
            for i in 0..=j {
                cd += self.cos[i] * d[j - i];
                sd += self.sin[i] * d[j - i];
            }
            // power −ẍg ẋ − ÿg ẏ = R (s ẍg cos φ − ÿg sin φ) ψ̇, coefficient of τ^j
            let p = r * (s * (forcing.a0 * cd + forcing.a1 * cd_prev) - (ay0 * sd + ay1 * sd_prev));
            w[j + 1] = p / (j + 1) as f64;
            (cd_prev, sd_prev) = (cd, sd);
        }
        w
    }
}

/// Σ c_j τ^j (Horner).
#[inline]
pub fn eval(c: &[f64; ORDER + 1], tau: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &cj| acc * tau + cj)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference: ψ̈ from eq. (1) integrated by classical RK4 with a tiny step.
    fn rk4(theta_c: f64, k: f64, s: f64, y: (f64, f64), f: &LinearForcing, t: f64) -> (f64, f64) {
        let acc = |tau: f64, p: f64| {
            let (sp, cp) = (theta_c - p).sin_cos();
            k * (s * (f.a0 + f.a1 * tau) * cp - (f.v0 + f.v1 * tau) * sp)
        };
        let n = 20_000;
        let h = t / n as f64;
        let (mut p, mut d) = y;
        for i in 0..n {
            let tau = i as f64 * h;
            let k1 = (d, acc(tau, p));
            let k2 = (d + 0.5 * h * k1.1, acc(tau + 0.5 * h, p + 0.5 * h * k1.0));
            let k3 = (d + 0.5 * h * k2.1, acc(tau + 0.5 * h, p + 0.5 * h * k2.0));
            let k4 = (d + h * k3.1, acc(tau + h, p + h * k3.0));
            p += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            d += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        }
        (p, d)
    }

    /// Over a sample of strong forcing (1 g, jerk 50 g/s), the step the
    /// control accepts for tolerance tol is accurate to tol against a fine
    /// RK4 solution (exact to ~1e-15 here), for tol from 1e-6 to 1e-12, and
    /// the sin/cos polynomials agree with sin/cos of θc − ψ to 10·tol.
    #[test]
    fn accepted_steps_meet_their_tolerance() {
        let g = 9.81;
        let (theta_c, r) = (0.25_f64.atan(), (0.25_f64 * 0.25 + 1.0).sqrt());
        let k = 0.75 / r;
        let f = LinearForcing {
            a0: 1.0 * g,
            a1: 50.0 * g,
            v0: g,
            v1: 0.0,
        };
        for tol in [1e-6, 1e-9, 1e-12] {
            for (s, y) in [(1.0, (0.05, 0.3)), (-1.0, (0.1, -0.2)), (1.0, (0.0, 0.0))] {
                let series = RockSeries::new(theta_c, k, s, y.0, y.1, &f);
                let h = series.step(0.02, tol, tol);
                assert!(h > 0.002, "step {h} for tol {tol}");
                let (p, d) = series.at(h);
                let (pr, dr) = rk4(theta_c, k, s, y, &f, h);
                assert!((p - pr).abs() <= tol, "tol {tol}: ψ {p} vs {pr}");
                assert!((d - dr).abs() <= tol, "tol {tol}: ψ̇ {d} vs {dr}");
                let (_, _, sn, cs) = series.full_at(h);
                let (se, ce) = (theta_c - p).sin_cos();
                assert!((sn - se).abs() <= 10.0 * tol && (cs - ce).abs() <= 10.0 * tol);
            }
        }
    }

    /// The step control cuts a step when the series is asked to go too far:
    /// over 1 s (about 2.6/p) the accepted step is shorter and still accurate
    /// to 1e-11, while a 0.02-s sample at the default tolerance (1e-8 of
    /// θc ≈ 2.4e-9 rad) is taken whole.
    #[test]
    fn step_is_cut_when_the_tail_is_large() {
        let g = 9.81;
        let (theta_c, r) = (0.25_f64.atan(), (0.25_f64 * 0.25 + 1.0).sqrt());
        let f = LinearForcing {
            a0: 0.5 * g,
            a1: 0.0,
            v0: g,
            v1: 0.0,
        };
        let series = RockSeries::new(theta_c, 0.75 / r, 1.0, 0.1, 0.5, &f);
        assert_eq!(series.step(0.02, 2.4e-9, 2.4e-9), 0.02);
        let h = series.step(1.0, 1e-12, 1e-12);
        assert!(h < 0.5, "{h}");
        let (p, _) = series.at(h);
        let (pr, _) = rk4(theta_c, 0.75 / r, 1.0, (0.1, 0.5), &f, h);
        assert!((p - pr).abs() < 1e-11, "{p} vs {pr}");
    }
}
