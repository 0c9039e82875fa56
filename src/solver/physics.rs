//! The physics of each mode as plain functions (per unit mass, relative to the
//! moving ground). Every formula names the equation it implements; see
//! `shared/physics.md` for the derivations.

use super::block::Block;
use crate::detmath as dm;

/// Angular acceleration in rock about the corner on side −s (s = sign θ):
/// I_O θ̈ = mR cos(θc−|θ|) ẍg − S mR sin(θc−|θ|)(g+ÿg), paper eq. (1), I_O = 4mR²/3.
#[inline]
pub fn rock_accel(bl: &Block, s: f64, theta: f64, ax: f64, ay: f64) -> f64 {
    let (sp, cp) = bl.phi_sin_cos(s * theta);
    rock_accel_sc(bl, s, sp, cp, ax, ay)
}

/// [`rock_accel`] from sin φ and cos φ, φ = θc − |θ|, already known.
#[inline]
pub fn rock_accel_sc(bl: &Block, s: f64, sp: f64, cp: f64, ax: f64, ay: f64) -> f64 {
    s * (0.75 / bl.r) * (cp * (s * ax) - sp * (bl.g + ay)) // eq. (1)
}

/// Everything the rock events need at one state, from one sine and cosine:
/// θ̈ (eq. 1), the reactions F and N, and the release indicator q.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RockContact {
    /// Angular acceleration θ̈ (rad/s²).
    pub alpha: f64,
    /// Horizontal reaction per unit mass (m/s²).
    pub f: f64,
    /// Normal reaction per unit mass (m/s²).
    pub n: f64,
    /// The part of N without θ̈: q = g + ÿg − R cosφ θ̇². If the pivot were
    /// released, its vertical acceleration in flight would be −q, so lift-off
    /// is consistent only when q < 0 (physics.md, "Lift-off under infinite
    /// friction").
    pub q: f64,
}

/// θ̈ (eq. 1) and the contact reactions at one rock state (physics.md,
/// checked): F = ẍg − R cosφ θ̈ − S R sinφ θ̇², N = q + S R sinφ θ̈ with
/// q = g + ÿg − R cosφ θ̇², φ = θc − |θ|.
#[inline]
pub fn rock_contact(bl: &Block, s: f64, theta: f64, omega: f64, ax: f64, ay: f64) -> RockContact {
    let (sp, cp) = bl.phi_sin_cos(s * theta);
    rock_contact_sc(bl, s, sp, cp, omega, ax, ay)
}

/// [`rock_contact`] from sin φ and cos φ, φ = θc − |θ|, already known (the
/// Taylor integrator carries them as series).
#[inline]
pub fn rock_contact_sc(
    bl: &Block,
    s: f64,
    sp: f64,
    cp: f64,
    omega: f64,
    ax: f64,
    ay: f64,
) -> RockContact {
    let alpha = rock_accel_sc(bl, s, sp, cp, ax, ay);
    let w2 = omega * omega;
    let q = bl.g + ay - bl.r * cp * w2;
    RockContact {
        alpha,
        f: ax - bl.r * cp * alpha - s * bl.r * sp * w2,
        n: q + s * bl.r * sp * alpha,
        q,
    }
}

/// Centre-of-mass position and velocity (x, ẋ, y, ẏ) relative to its rest
/// position while rocking: x = S(R sinφ − B), y = R cosφ − H,
/// ẋ = −R cosφ θ̇, ẏ = S R sinφ θ̇.
#[inline]
pub fn rock_kinematics(bl: &Block, s: f64, theta: f64, omega: f64) -> [f64; 4] {
    let (sp, cp) = bl.phi_sin_cos(s * theta);
    [
        s * (bl.r * sp - bl.b),
        -bl.r * cp * omega,
        bl.r * cp - bl.h,
        s * bl.r * sp * omega,
    ]
}

/// Mechanical energy per unit mass in the ground frame: ½(ẋ²+ẏ²) + ½Iθ̇² + g y.
#[inline]
pub fn energy(bl: &Block, vx: f64, vy: f64, omega: f64, y: f64) -> f64 {
    bl.kinetic(vx, vy, omega) + bl.g * y
}

/// Rate of work of the ground's inertial forces per unit mass: −ẍg ẋ − ÿg ẏ.
#[inline]
pub fn ground_power(ax: f64, ay: f64, vx: f64, vy: f64) -> f64 {
    -ax * vx - ay * vy
}

/// Linearised rock about θ = 0 (tangent to eq. (1) in θ, the θ·ẍg term
/// dropped): θ̈ = λ²θ + (3/4R)(cosθc ẍg − S g sinθc), λ² = p² cosθc.
/// Returns (λ², c0, c1) for ẍg = a0 + a1 τ: θ̈ = λ²θ + c0 + c1 τ.
#[inline]
pub fn linear_coeffs(bl: &Block, s: f64, a0: f64, a1: f64) -> (f64, f64, f64) {
    let k = 0.75 / bl.r;
    (
        bl.p * bl.p * bl.cos_c,
        k * (bl.cos_c * a0 - s * bl.g * bl.sin_c),
        k * bl.cos_c * a1,
    )
}

/// Slide-rock: rocking about the corner on side −s while it slips with
/// direction σ = sign(ẋp) under kinetic friction μk. With φ = θc − sθ,
/// q = g + ÿg − R cosφ θ̇² and c = s sinφ + μk σ cosφ, the two force
/// equations and the moment equation about G,
///
/// ```text
/// ẍp − R cosφ θ̈ − S R sinφ θ̇² = −ẍg + F       (horizontal, F = −μk σ N)
/// S R sinφ θ̈ − R cosφ θ̇²       = −(g + ÿg) + N  (vertical)
/// I θ̈ = −S R sinφ N + R cosφ F                 (moment about G, I = R²/3)
/// ```
///
/// give θ̈ = −R c q / (I + S c R² sinφ), N = q + S R sinφ θ̈ = q·I/(I + S c R² sinφ),
/// and the pivot's slip acceleration ẍp = −ẍg + F + R cosφ θ̈ + S R sinφ θ̇².
/// A non-positive denominator is Painlevé's inconsistency (no slipping solution).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlideRockAccel {
    /// Angular acceleration θ̈ (rad/s²).
    pub alpha: f64,
    /// Slip acceleration of the pivot ẍp (m/s²).
    pub xp_acc: f64,
    /// Normal reaction per unit mass (m/s²).
    pub n: f64,
    /// Friction per unit mass (m/s²), −μk σ N.
    pub f: f64,
    /// The denominator I + S c R² sinφ (m²); ≤ 0 means no slipping solution.
    pub den: f64,
}

/// Accelerations of slide-rock (see [`SlideRockAccel`]).
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn slide_rock_accel(
    bl: &Block,
    s: f64,
    sigma: f64,
    mu_k: f64,
    theta: f64,
    omega: f64,
    ax: f64,
    ay: f64,
) -> SlideRockAccel {
    let (sp, cp) = bl.phi_sin_cos(s * theta);
    let r = bl.r;
    let w2 = omega * omega;
    let q = bl.g + ay - r * cp * w2;
    let c = s * sp + mu_k * sigma * cp;
    let den = bl.inertia + s * c * r * r * sp;
    let alpha = -r * c * q / den;
    let n = q + s * r * sp * alpha;
    let f = -mu_k * sigma * n;
    SlideRockAccel {
        alpha,
        xp_acc: -ax + f + r * cp * alpha + s * r * sp * w2,
        n,
        f,
        den,
    }
}

/// (sin x, cos x) for |x| ≤ 0.25 by their Maclaurin series to x¹¹ and x¹²
/// (truncation below 3e-18), else by the library; flight rotates by ωτ from a
/// known angle, and ring-down flights are short, so most calls take the series.
/// Below |x| = 0.02 the series stop at x⁷ and x⁸ (truncation below 7e-20
/// relative), below 2e-3 at x⁵ and x⁶ (below 2e-20): the rotations of a
/// bounce series' flights mostly fall there.
// (always inlined: it sits on the landing → impact chain of every bounce,
// and left out of line it cost 1.4 % at e = 0.9)
#[inline(always)]
pub fn sin_cos_small(x: f64) -> (f64, f64) {
    let ax = x.abs();
    if ax > 0.25 {
        return dm::sin_cos(x);
    }
    let x2 = x * x;
    if ax <= 2e-3 {
        let s = x * (1.0 - x2 * (1.0 / 6.0) * (1.0 - x2 * (1.0 / 20.0)));
        let c = 1.0 - x2 * 0.5 * (1.0 - x2 * (1.0 / 12.0) * (1.0 - x2 * (1.0 / 30.0)));
        return (s, c);
    }
    if ax <= 0.02 {
        let s =
            x * (1.0 - x2 * (1.0 / 6.0) * (1.0 - x2 * (1.0 / 20.0) * (1.0 - x2 * (1.0 / 42.0))));
        let c = 1.0
            - x2 * 0.5
                * (1.0 - x2 * (1.0 / 12.0) * (1.0 - x2 * (1.0 / 30.0) * (1.0 - x2 * (1.0 / 56.0))));
        return (s, c);
    }
    // Horner in x²: sin x = x(1 − x²/3!(1 − x²/(4·5)(1 − …))), likewise cos;
    // reciprocals are constants so that no division is left at run time
    const S: [f64; 5] = [1.0 / 6.0, 1.0 / 20.0, 1.0 / 42.0, 1.0 / 72.0, 1.0 / 110.0];
    const C: [f64; 6] = [
        1.0 / 2.0,
        1.0 / 12.0,
        1.0 / 30.0,
        1.0 / 56.0,
        1.0 / 90.0,
        1.0 / 132.0,
    ];
    let mut s = 1.0;
    for k in S.iter().rev() {
        s = 1.0 - x2 * k * s;
    }
    let mut c = 1.0;
    for k in C.iter().rev() {
        c = 1.0 - x2 * k * c;
    }
    let s = x * s;
    (s, c)
}

#[cfg(test)]
mod tests {
    use super::sin_cos_small;
    use crate::detmath as dm;

    /// The series agree with the library's sin and cos to 3e-16 (about one
    /// ulp of cos near 1) on the range they are used for, and fall back to
    /// the library outside it.
    #[test]
    fn small_angle_series_match_the_library() {
        for k in -1000..=1000 {
            let x = 0.25 * k as f64 / 1000.0;
            let (s, c) = sin_cos_small(x);
            let (se, ce) = dm::sin_cos(x);
            assert!((s - se).abs() <= 3e-16, "sin {x}: {s} vs {se}");
            assert!((c - ce).abs() <= 3e-16, "cos {x}: {c} vs {ce}");
        }
        assert_eq!(sin_cos_small(1.0), dm::sin_cos(1.0));
        // the shorter series for small x: sin to two ulps relative (rounding
        // of the series and of the library), across the tiers' edges
        for k in 0..=240 {
            for x in [dm::powf(10.0, -k as f64 / 20.0) / 4.0, 2e-3, 0.02] {
                for x in [x, -x, x * (1.0 + 1e-12), x * (1.0 - 1e-12)] {
                    let (s, c) = sin_cos_small(x);
                    let (se, ce) = dm::sin_cos(x);
                    assert!((s - se).abs() <= 2.3e-16 * se.abs(), "sin {x}: {s} vs {se}");
                    assert!((c - ce).abs() <= 3e-16, "cos {x}: {c} vs {ce}");
                }
            }
        }
    }
}
