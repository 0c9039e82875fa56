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
#[serde(rename_all = "lowercase")]
pub enum ImpactLaw {
    /// Newton restitution with no slip (the paper's law).
    #[default]
    Newton,
    /// Poisson restitution of the plastic sticking impulse: never adds energy.
    Energetic,
}

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

/// Velocity (u_t, u_n) of the point at offset (rx, ry) from G.
#[inline]
pub fn point_velocity(v: &Velocity, rx: f64, ry: f64) -> (f64, f64) {
    (v.vx - v.omega * ry, v.vy + v.omega * rx)
}

/// Applies a no-slip corner impact with restitution `e` at the corner with
/// offset (rx, ry) from G.
pub fn corner_impact(
    block: &Block,
    v: &Velocity,
    rx: f64,
    ry: f64,
    e: f64,
    law: ImpactLaw,
) -> ImpactResult {
    let i = block.inertia;
    // K⁻¹ = [[a, b], [b, c]] (impulse-momentum at the corner)
    let a = 1.0 + ry * ry / i;
    let b = -rx * ry / i;
    let c = 1.0 + rx * rx / i;
    let (ut, un) = point_velocity(v, rx, ry);
    let (dut, dun) = match law {
        ImpactLaw::Newton => (-ut, -(1.0 + e) * un), // u_t⁺ = 0, u_n⁺ = −e u_n⁻
        ImpactLaw::Energetic => (-(1.0 + e) * ut, -(1.0 + e) * un), // u⁺ = −e u⁻
    };
    // P = K Δu, K = (K⁻¹)⁻¹
    let det = a * c - b * b;
    let p_t = (c * dut - b * dun) / det;
    let p_n = (-b * dut + a * dun) / det;
    let after = Velocity {
        vx: v.vx + p_t,
        vy: v.vy + p_n,
        omega: v.omega + (rx * p_n - ry * p_t) / i,
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
