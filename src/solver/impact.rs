//! Corner impacts: impulse–momentum with no slip (infinite friction).
//!
//! At the striking corner c with offset r = (r_x, r_y) from G, the corner
//! velocity is u = v + ω × r = (v_x − ω r_y, v_y + ω r_x). An impulse
//! P = (P_t, P_n) changes it by Δu = K⁻¹ P with the corner's inverse-mass
//! matrix (per unit mass, I = R²/3):
//!
//! ```text
//! K⁻¹ = [[1 + r_y²/I, −r_x r_y/I], [−r_x r_y/I, 1 + r_x²/I]]
//! ```
//!
//! Two laws are offered:
//! - **Newton** (the paper's, after Kane & Levinson): u_n⁺ = −e u_n⁻ and
//!   u_t⁺ = 0 (no slip). It can *add* kinetic energy when the tangential and
//!   normal responses are coupled; such gains are counted by the solver.
//! - **Energetic** (energy-consistent): Poisson's hypothesis applied to the
//!   perfectly plastic sticking impulse P_c (the one that brings the corner to
//!   rest): P = (1 + e) P_c, hence u⁺ = −e u⁻. The kinetic energy change is
//!   −½(1 − e²) u⁻ᵀ K u⁻ ≤ 0: it never adds energy. When u_t⁻ = 0, as at every
//!   rock impact, it coincides with Newton's law.

use super::block::Block;

/// Impact law for corner impacts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum ImpactLaw {
    /// Newton restitution with no slip (the paper's law).
    #[default]
    Newton,
    /// Poisson restitution of the plastic sticking impulse: never adds energy.
    Energetic,
}

crate::io_util::named!(ImpactLaw, "impact" { Newton => "newton", Energetic => "energetic" });

/// Rigid-body velocity relative to the ground (per unit mass).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Velocity {
    /// Horizontal velocity of G (m/s).
    pub vx: f64,
    /// Vertical velocity of G (m/s).
    pub vy: f64,
    /// Angular velocity (rad/s), counter-clockwise positive.
    pub omega: f64,
}

/// Result of one corner impact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactResult {
    /// Velocity after the impact.
    pub after: Velocity,
    /// Tangential impulse P_t per unit mass (m/s).
    pub p_t: f64,
    /// Normal impulse P_n per unit mass (m/s).
    pub p_n: f64,
    /// Change of kinetic energy per unit mass (J/kg); > 0 is an energy gain.
    pub delta_kinetic: f64,
}

impl ImpactResult {
    /// Friction needed to prevent sliding during the impact, |P_t/P_n|
    /// (0 when there is no normal impulse).
    #[inline]
    pub fn friction_demand(&self) -> f64 {
        if self.p_n > 0.0 {
            (self.p_t / self.p_n).abs()
        } else {
            0.0
        }
    }
}

/// Velocity (u_t, u_n) of the point at offset (rx, ry) from G.
#[inline]
pub fn point_velocity(v: &Velocity, rx: f64, ry: f64) -> (f64, f64) {
    (v.vx - v.omega * ry, v.vy + v.omega * rx)
}

/// Applies a no-slip corner impact with restitution `e` at the corner with
/// offset (rx, ry) from G (a corner: rx² + ry² = R²).
#[inline]
pub fn corner_impact(
    block: &Block,
    v: &Velocity,
    rx: f64,
    ry: f64,
    e: f64,
    law: ImpactLaw,
) -> ImpactResult {
    let inv_i = 1.0 / block.inertia;
    // K⁻¹ = [[a, b], [b, c]] (impulse-momentum at the corner)
    let a = 1.0 + ry * ry * inv_i;
    let b = -rx * ry * inv_i;
    let c = 1.0 + rx * rx * inv_i;
    let (ut, un) = point_velocity(v, rx, ry);
    let (dut, dun) = match law {
        ImpactLaw::Newton => (-ut, -(1.0 + e) * un), // u_t⁺ = 0, u_n⁺ = −e u_n⁻
        ImpactLaw::Energetic => (-(1.0 + e) * ut, -(1.0 + e) * un), // u⁺ = −e u⁻
    };
    // P = K Δu, K = (K⁻¹)⁻¹; det K⁻¹ = ac − b² = 1 + (rx² + ry²)/I = I_O/I
    // for a corner, a constant of the block (off the impact's critical path)
    let inv_det = block.inertia / block.inertia_corner();
    let p_t = (c * dut - b * dun) * inv_det;
    let p_n = (-b * dut + a * dun) * inv_det;
    let after = Velocity {
        vx: v.vx + p_t,
        vy: v.vy + p_n,
        omega: v.omega + (rx * p_n - ry * p_t) * inv_i,
    };
    // Kelvin: ΔT = P · (u⁻ + u⁺)/2
    let delta_kinetic = 0.5 * (p_t * (2.0 * ut + dut) + p_n * (2.0 * un + dun));
    ImpactResult {
        after,
        p_t,
        p_n,
        delta_kinetic,
    }
}

/// Result of a simultaneous impact of both corners (a flat landing).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoCornerImpact {
    /// Velocity after the impact.
    pub after: Velocity,
    /// Total tangential impulse P_t per unit mass (m/s), applied at the
    /// middle of the base.
    pub p_t: f64,
    /// Normal impulse at the left corner per unit mass (m/s).
    pub p_left: f64,
    /// Normal impulse at the right corner per unit mass (m/s).
    pub p_right: f64,
    /// Change of kinetic energy per unit mass (J/kg); > 0 is an energy gain.
    pub delta_kinetic: f64,
}

impl TwoCornerImpact {
    /// Friction needed to prevent sliding during the impact,
    /// |P_t|/(P_left + P_right) (0 when there is no normal impulse).
    #[inline]
    pub fn friction_demand(&self) -> f64 {
        let p_n = self.p_left + self.p_right;
        if p_n > 0.0 {
            (self.p_t / p_n).abs()
        } else {
            0.0
        }
    }
}

/// Simultaneous no-slip impact of both corners, at offsets `left` and
/// `right` from G (a flat landing: both on the ground at once), with
/// restitution `e` at each: u_n⁺ = −e u_n⁻ at both corners, and at the
/// middle of the base u_t⁺ = 0 (Newton) or −e u_t⁻ (energetic, which then
/// gives u⁺ = −e u⁻ for all three contact velocities, so ΔT = −(1 − e²)T⁻ of
/// the contact motion and never a gain). The three targets fix the velocity
/// after; the impulses follow from momentum. A symmetric landing (ω = 0,
/// v_x = 0) rebounds straight up at e·v_y and never turns: the sequential
/// rule, one corner first, would turn it. Valid (an impact) only when both
/// normal impulses are ≥ 0, which the caller checks.
pub fn two_corner_impact(
    block: &Block,
    v: &Velocity,
    left: (f64, f64),
    right: (f64, f64),
    e: f64,
    law: ImpactLaw,
) -> TwoCornerImpact {
    let (rxl, ryl) = left;
    let (rxr, ryr) = right;
    let (rxm, rym) = (0.5 * (rxl + rxr), 0.5 * (ryl + ryr));
    let unl = point_velocity(v, rxl, ryl).1;
    let unr = point_velocity(v, rxr, ryr).1;
    let utm = point_velocity(v, rxm, rym).0;
    // targets: Newton's restitution at each corner, stick (or −e u_t) mid-base
    let (tl, tr) = (-e * unl, -e * unr);
    let tt = match law {
        ImpactLaw::Newton => 0.0,
        ImpactLaw::Energetic => -e * utm,
    };
    // u_n = v_y + ω r_x at each corner, u_t = v_x − ω r_y mid-base, inverted
    let omega = (tr - tl) / (rxr - rxl);
    let vy = tl - omega * rxl;
    let vx = tt + omega * rym;
    let after = Velocity { vx, vy, omega };
    let (p_t, p_n) = (vx - v.vx, vy - v.vy);
    // I Δω = r_xl P_l + r_xr P_r − r_ym P_t, with P_l + P_r = P_n
    let p_right = (block.inertia * (omega - v.omega) + rym * p_t - rxl * p_n) / (rxr - rxl);
    let p_left = p_n - p_right;
    let delta_kinetic = block.kinetic(vx, vy, omega) - block.kinetic(v.vx, v.vy, v.omega);
    TwoCornerImpact {
        after,
        p_t,
        p_left,
        p_right,
        delta_kinetic,
    }
}

/// Housner's angular velocity ratio at a rock impact with no slip:
/// ω₂/ω₁ = 1 − 1.5(1+e) sin²θc (see `physics.md`, checked).
pub fn rock_impact_ratio(block: &Block, e: f64) -> f64 {
    1.0 - 1.5 * (1.0 + e) * block.sin_c * block.sin_c
}

/// The paper's eq. (8): impulse ratio |P_t/P_n| at a rock impact,
/// 3 cosθc sinθc / (1 + 3 cos²θc), independent of e.
pub fn rock_impact_mu(block: &Block) -> f64 {
    3.0 * block.cos_c * block.sin_c / (1.0 + 3.0 * block.cos_c * block.cos_c)
}

/// The paper's eq. (5): the friction needed to prevent sliding during a
/// corner impact, as the paper's program evaluated it from the pre-impact
/// velocities (Newton restitution, no slip), whatever law the solver applies.
///
/// # Reconstruction
///
/// The extracted text of eqs. (3) and (5) lost two multiplications. In the
/// paper's symbols (θ̇₁, ẋ₁, ẏ₁ the pre-impact rates of θ and of G,
/// S = sin(θc − |θ|), C = cos(θc − |θ|), S_θ = sign θ, λx = ẋ₁/(R C θ̇₁),
/// λy = ẏ₁/(R S θ̇₁)) they must read
///
/// ```text
/// δi = 1 − ¾C²(1 + λx) − ¾S²(1 + e)(1 − S_θ λy)                      (3)
/// μs ≥ | (C/S)(δi + λx) / (S_θ(δi + e) − (1 + e) λy) |               (5)
/// ```
///
/// (the text has `1 − S_θ − λy` and `S_θ − (δi + e)`). Derivation: G sits at
/// (X, Y) = (S_θ R S, R C) from the striking corner. With the corner stuck
/// after the impact (u_t⁺ = 0) and u_n⁺ = −e u_n⁻, the impulse–momentum
/// equations P = Δv, (R²/3) Δθ̇ = Y P_x − X P_y give θ̇₂ = δi θ̇₁ with δi as
/// above, and
///
/// ```text
/// P_x = −(ẋ₁ + R C θ̇₂)                    = −R S θ̇₁ · (C/S)(δi + λx)
/// P_y = X(θ̇₂ + e θ̇₁) − (1 + e) ẏ₁        =  R S θ̇₁ · (S_θ(δi + e) − (1 + e) λy)
/// ```
///
/// so eq. (5) is |P_x/P_y|, the tangential-to-normal ratio of the sticking
/// Newton impulse. Check: at a rock impact (θ = 0, λx = −1, λy = −S_θ)
/// δi = 1 − 1.5(1 + e) sin²θc and eq. (5) is 3 cosθc sinθc/(1 + 3 cos²θc),
/// the paper's eq. (8), for every e (the literal text gives
/// 1.5 CS/(1 + 1.5 S²) at e = 0 instead, 0.46 for H/B = 2, not the table's 0.353).
///
/// It is evaluated here multiplied through by R S θ̇₁, with S_θ S = X/R, so
/// that neither θ̇₁ = 0 (a landing without spin) nor S = 0 divides by zero.
///
/// # How it differs from `mu_impact`
///
/// The ratio is the same as the solver's `mu_impact` for a Newton sticking
/// impulse, with two differences that matter only at landings after free
/// flight: the absolute value is taken whatever the sign of P_y, where
/// `mu_impact` counts 0 when the sticking impulse would pull the corner down
/// (P_y ≤ 0); and it uses Newton's law even when the solver applies the
/// energetic one. The denominator P_y vanishes when stopping the corner's
/// slip alone would already reverse its approach: with the corner's
/// inverse-mass matrix [[a, b], [b, c]] in (t, n), P_y ∝ b u_t − a(1 + e) u_n,
/// zero at u_n = b u_t/(a(1 + e)). That line lies among slow (grazing)
/// landings with a sideways corner velocity, which ground motion during a
/// short flight produces, so near it eq. (5) is unbounded. A rock impact
/// (u_t = 0 before) never comes near it.
///
/// Returns 0 when the corner has no velocity (0/0); +∞ if the denominator is
/// exactly 0 with a non-zero numerator.
pub fn eq5_mu(block: &Block, v: &Velocity, rx: f64, ry: f64, e: f64) -> f64 {
    let inv_r = 1.0 / block.r;
    // G from the striking corner: X = S_θ R S, Y = R C
    let (xg, yg) = (-rx, -ry);
    let (sx, c) = (xg * inv_r, yg * inv_r); // S_θ S, C
    // eq. (3) times θ̇₁: θ̇₂ = δi θ̇₁
    let omega2 = v.omega
        - 0.75 * c * (c * v.omega + v.vx * inv_r)
        - 0.75 * (1.0 + e) * sx * (sx * v.omega - v.vy * inv_r);
    // eq. (5), numerator and denominator times R S θ̇₁
    let num = v.vx + yg * omega2;
    let den = xg * (omega2 + e * v.omega) - (1.0 + e) * v.vy;
    if num == 0.0 { 0.0 } else { (num / den).abs() }
}

/// Corner impact with Coulomb friction (static μs, kinetic μk).
///
/// First the sticking impulse of `law` is tried; it is accepted if
/// |P_t| ≤ μs P_n. Otherwise the corner slips during the impact and the
/// impact is resolved with **Stronge's energetic restitution** with slip-state
/// tracking: the impulse grows along the normal impulse p, with
/// dP_t/dp = −μk σ while slipping in direction σ, and dP_t/dp = −b/a while
/// stuck (possible once the slip stops if |b/a| ≤ μs; otherwise the slip
/// reverses). Compression ends when u_n = 0 having done normal work W_c < 0;
/// restitution ends when the normal work of restitution is −e² W_c. This law
/// never adds kinetic energy (Stronge 2000, *Impact Mechanics*, ch. 5).
///
/// The returned `p_t/p_n` of the *sticking* attempt is the friction needed to
/// prevent sliding (`mu_impact`); it is returned as the second value.
#[allow(clippy::too_many_arguments)]
// (always inlined: out of line it read the caller's velocity, stored field by
// field, back in pairs, stalling store forwarding on every impact: −8.6 % at
// e = 0.9 under finite friction)
#[inline(always)]
pub fn corner_impact_friction(
    block: &Block,
    v: &Velocity,
    rx: f64,
    ry: f64,
    e: f64,
    law: ImpactLaw,
    mu_s: f64,
    mu_k: f64,
) -> (ImpactResult, f64) {
    let stick = corner_impact(block, v, rx, ry, e, law);
    let demand = stick.friction_demand();
    if stick.p_t.abs() <= mu_s * stick.p_n {
        return (stick, demand);
    }
    let i = block.inertia;
    let a = 1.0 + ry * ry / i;
    let b = -rx * ry / i;
    let c = 1.0 + rx * rx / i;
    let (ut0, un0) = point_velocity(v, rx, ry);
    match stronge(a, b, c, ut0, un0, e, mu_s, mu_k) {
        Some((p_t, p_n)) => {
            let after = Velocity {
                vx: v.vx + p_t,
                vy: v.vy + p_n,
                omega: v.omega + (rx * p_n - ry * p_t) / i,
            };
            let (ut1, un1) = point_velocity(&after, rx, ry);
            // Kelvin: ΔT = P · (u⁻ + u⁺)/2
            let delta_kinetic = 0.5 * (p_t * (ut0 + ut1) + p_n * (un0 + un1));
            (
                ImpactResult {
                    after,
                    p_t,
                    p_n,
                    delta_kinetic,
                },
                demand,
            )
        }
        // A jam (the normal velocity cannot be stopped while slipping):
        // fall back to the sticking impulse.
        None => (stick, demand),
    }
}

/// Integrates the impulse along the normal impulse p for Stronge's energetic
/// restitution with Coulomb friction; returns (P_t, P_n), or `None` if the
/// compression cannot end (u_n does not increase along p). [[a, b], [b, c]]
/// is the contact's inverse-mass matrix in (t, n): a corner's on the ground
/// here, a contact's effective one in the stack solver.
#[allow(clippy::too_many_arguments)]
pub(super) fn stronge(
    a: f64,
    b: f64,
    c: f64,
    ut0: f64,
    un0: f64,
    e: f64,
    mu_s: f64,
    mu_k: f64,
) -> Option<(f64, f64)> {
    let (mut ut, mut un, mut pt, mut pn, mut work) = (ut0, un0, 0.0, 0.0, 0.0);
    let mut compressing = un < 0.0;
    let mut target = 0.0; // total normal work at the end (set when compression ends)
    let can_stick = b.abs() <= mu_s * a;
    let mut sigma = if ut != 0.0 { ut.signum() } else { b.signum() };
    let mut stuck = ut == 0.0 && can_stick;
    if !compressing {
        return Some((0.0, 0.0));
    }
    for _ in 0..8 {
        // rates per unit normal impulse in this phase
        let (dpt, dut) = if stuck {
            (-b / a, 0.0)
        } else {
            (-mu_k * sigma, b - a * mu_k * sigma)
        };
        let dun = b * dpt + c;
        if dun <= 0.0 && compressing {
            return None;
        }
        // length of this phase: until slip stops, compression ends, or work target
        let mut dp = f64::INFINITY;
        let mut ends_slip = false;
        if !stuck && dut * ut < 0.0 {
            dp = -ut / dut;
            ends_slip = true;
        }
        let mut ends_compression = false;
        if compressing {
            let d = -un / dun;
            if d <= dp {
                dp = d;
                ends_slip = false;
                ends_compression = true;
            }
        } else {
            // ½ dun Δ² + un Δ = target − work
            let need = target - work;
            let d = if dun.abs() < 1e-300 {
                need / un
            } else {
                (-un + (un * un + 2.0 * dun * need).sqrt()) / dun
            };
            if d <= dp {
                dp = d;
                ends_slip = false;
            }
        }
        // advance
        work += un * dp + 0.5 * dun * dp * dp;
        pn += dp;
        pt += dpt * dp;
        un += dun * dp;
        ut += dut * dp;
        if ends_compression {
            un = 0.0;
            compressing = false;
            target = (1.0 - e * e) * work; // W_c + W_r with W_r = −e² W_c
            if e == 0.0 {
                return Some((pt, pn));
            }
            continue;
        }
        if ends_slip {
            ut = 0.0;
            if can_stick {
                stuck = true;
            } else {
                sigma = b.signum(); // slip resumes in the direction the coupling drives it
            }
            continue;
        }
        if !compressing {
            return Some((pt, pn));
        }
    }
    Some((pt, pn))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sliding_impact_never_gains_energy_and_respects_the_cone() {
        // A landing with a large tangential velocity on a low-friction floor:
        // the impulse lies in the friction cone and kinetic energy drops (with
        // the energetic law for the sticking attempt; Newton's can gain).
        let bl = Block::new(0.5, 2.0, 9.81).unwrap();
        let (rx, ry) = bl.corner_offset(1.0, -0.1);
        for e in [0.0, 0.5, 0.9] {
            for (vx, om) in [(1.0, 0.0), (-1.0, 2.0), (0.2, -3.0)] {
                let v = Velocity {
                    vx,
                    vy: -1.0,
                    omega: om,
                };
                let (r, _) =
                    corner_impact_friction(&bl, &v, rx, ry, e, ImpactLaw::Energetic, 0.3, 0.3);
                assert!(r.delta_kinetic <= 1e-12, "e {e}: gain {}", r.delta_kinetic);
                assert!(
                    r.p_t.abs() <= 0.3 * r.p_n * (1.0 + 1e-12),
                    "outside the cone"
                );
                let (_, un) = point_velocity(&r.after, rx, ry);
                assert!(un >= -1e-12, "corner still approaching: {un}");
            }
        }
    }
}
