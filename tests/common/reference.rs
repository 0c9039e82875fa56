#![allow(dead_code)] // each test binary uses a different subset of the problems
//! Reference problems with known answers, shared by tests and benchmarks.

use rockfrag::detmath as dm;
use rockfrag::motion::Record;
use rockfrag::solver::Block;
use rockfrag::solver::Velocity;

/// Time for a block released from rest at θ0 (0 < θ0 < θc), with no ground
/// motion, to reach θ = 0, from the energy integral
/// ½ I_O θ̇² = mgR [cos(θc−θ0) − cos(θc−θ)]:
/// t = ∫₀^θ0 dθ / √(2p² [cos(θc−θ0) − cos(θc−θ)]).
///
/// Computed with θ = θ0(1 − v²), which removes the inverse-square-root
/// singularity at θ0, and composite Simpson's rule on 20,000 panels
/// (error ~1e-15 relative for a smooth integrand).
pub fn free_rocking_first_impact_time(block: &Block, theta0: f64) -> f64 {
    let tc = block.theta_c;
    let p2 = block.p * block.p;
    let integrand = |v: f64| {
        let th = theta0 * (1.0 - v * v);
        // cos(θc−θ0) − cos(θc−θ) = 2 sin(θc − (θ0+θ)/2) sin((θ0−θ)/2), no cancellation
        let f = 2.0 * dm::sin(tc - 0.5 * (theta0 + th)) * dm::sin(0.5 * (theta0 - th));
        if v == 0.0 {
            // limit v → 0: f ≈ sin(θc−θ0)·θ0 v²/… ⇒ 2θ0 v/√(2p² f) → 2θ0/√(2p² sin(θc−θ0) θ0)
            2.0 * theta0 / (2.0 * p2 * dm::sin(tc - theta0) * theta0).sqrt()
        } else {
            2.0 * theta0 * v / (2.0 * p2 * f).sqrt()
        }
    };
    let n = 20_000;
    let h = 1.0 / n as f64;
    let mut sum = integrand(0.0) + integrand(1.0);
    for i in 1..n {
        let w = if i % 2 == 1 { 4.0 } else { 2.0 };
        sum += w * integrand(i as f64 * h);
    }
    sum * h / 3.0
}

/// Amplitude after one plastic (e = 0) rock impact from amplitude θn:
/// cos(θc−θn+1) − cosθc = δ² [cos(θc−θn) − cosθc], δ = 1 − 1.5 sin²θc.
pub fn next_amplitude(block: &Block, theta_n: f64) -> f64 {
    let tc = block.theta_c;
    let delta = 1.0 - 1.5 * block.sin_c * block.sin_c;
    let c = dm::cos(tc) + delta * delta * (dm::cos(tc - theta_n) - dm::cos(tc));
    tc - dm::acos(c)
}

/// Rigid-body velocity just before a rock impact: rotating at ω1 about the
/// left corner (ω1 < 0 brings θ > 0 back to 0): v = ω × r_G with
/// r_G = (B, H) from the pivot, so v_x = −H ω1, v_y = B ω1.
pub fn rock_impact_velocity(block: &Block, omega1: f64) -> Velocity {
    Velocity {
        vx: -block.h * omega1,
        vy: block.b * omega1,
        omega: omega1,
    }
}

/// A record of constant ground acceleration `acc` (m/s²) lasting `duration` s.
pub fn constant_record(acc: f64, dt: f64, duration: f64) -> Record {
    let n = (duration / dt).round() as usize + 1;
    Record::from_acc(format!("constant {acc} m/s²"), dt, vec![acc; n])
        .expect("valid constant record")
}

/// A quiet record (no ground motion) lasting `duration` s.
pub fn quiet_record(dt: f64, duration: f64) -> Record {
    constant_record(0.0, dt, duration)
}
