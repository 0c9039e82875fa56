//! The two-block stack's rocking modes against their equations written out
//! by hand (issue 40, "against published results": the published figures'
//! numbers of Psycharis 1990 and Spanos et al. 2001 were not available, so
//! this checks the equations those papers solve instead, derived here
//! independently of `solver::stack`'s Jacobian chain).
//!
//! Psycharis (1990) writes a two-block assembly rocking on infinite friction
//! in four modes: each block pivots on its left or right corner (the base on
//! the ground, the top on the base's top face), the signs of (φ₁, φ₂) in
//! rockfrag's convention (φ > 0: left corner, counter-clockwise). In each
//! mode the stack has two degrees of freedom, φ₁ (the base's rotation) and
//! φ₂ (the top's, relative to the base), and Lagrange's equations
//! M(φ) φ̈ + (terms in φ̇²) = Q(φ, ẍg) follow from the centres' positions
//! alone. Released at rest the φ̇² terms vanish, so φ̈(0) = M⁻¹Q exactly.

use rockfrag::motion::{G_STANDARD as G, Record};
use rockfrag::solver::stack::{Stack, StackBody, StackHistory, simulate_stack};
use rockfrag::solver::{Integrator, SolverSettings};

/// d/dφ R(φ)r, R(φ) the rotation counter-clockwise by φ.
fn drot(phi: f64, r: [f64; 2]) -> [f64; 2] {
    let (s, c) = phi.sin_cos();
    [-r[0] * s - r[1] * c, r[0] * c - r[1] * s]
}

/// φ̈(0) of a two-block stack released at rest from (φ₁, φ₂) in the mode
/// their signs give, under a constant horizontal ground acceleration `a`
/// (m/s²): base 2B₁ × 2H₁ of mass m₁ pivoting on the ground at (−s₁B₁, 0);
/// top 2B₂ × 2H₂ of mass m₂ pivoting at the base's top-face point
/// (−s₂B₂, H₁) (base frame, from its centre). Centres:
/// c₁ = P₁ + R(φ₁)(s₁B₁, H₁), c₂ = c₁ + R(φ₁)(−s₂B₂, H₁) + R(φ₁+φ₂)(s₂B₂, H₂);
/// M = Σ m Jᵀ J + I aᵀa with I = m(B² + H²)/3 (a rectangle's centroidal
/// inertia) and a = ∂θ/∂φ; Q = Σ Jᵀ(−m a, −m g) (the ground frame's body
/// force and gravity).
fn release_acceleration(dims: [(f64, f64, f64); 2], phi: [f64; 2], a: f64) -> [f64; 2] {
    let [(b1, h1, m1), (b2, h2, m2)] = dims;
    let (s1, s2) = (phi[0].signum(), phi[1].signum());
    let th2 = phi[0] + phi[1];
    let u1 = [s1 * b1, h1];
    let w = [-s2 * b2, h1];
    let u2 = [s2 * b2, h2];
    // Jacobian columns of each centre in (φ₁, φ₂)
    let j1 = [drot(phi[0], u1), [0.0, 0.0]];
    let d2 = drot(th2, u2);
    let dw = drot(phi[0], w);
    let j2 = [[j1[0][0] + dw[0] + d2[0], j1[0][1] + dw[1] + d2[1]], d2];
    let (i1, i2) = (
        m1 * (b1 * b1 + h1 * h1) / 3.0,
        m2 * (b2 * b2 + h2 * h2) / 3.0,
    );
    let rot_of = [[1.0, 0.0], [1.0, 1.0]]; // ∂θ₁/∂φ, ∂θ₂/∂φ
    let mut m = [[0.0; 2]; 2];
    let mut q = [0.0; 2];
    for i in 0..2 {
        for j in 0..2 {
            m[i][j] = m1 * (j1[i][0] * j1[j][0] + j1[i][1] * j1[j][1])
                + m2 * (j2[i][0] * j2[j][0] + j2[i][1] * j2[j][1])
                + i1 * rot_of[0][i] * rot_of[0][j]
                + i2 * rot_of[1][i] * rot_of[1][j];
        }
        q[i] = m1 * (-a * j1[i][0] - G * j1[i][1]) + m2 * (-a * j2[i][0] - G * j2[i][1]);
    }
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    [
        (m[1][1] * q[0] - m[0][1] * q[1]) / det,
        (m[0][0] * q[1] - m[1][0] * q[0]) / det,
    ]
}

/// In each of Psycharis' four two-block rocking modes, with and without a
/// ground acceleration, the stack solver's angular accelerations at release
/// equal M⁻¹Q of the hand-written Lagrangian to 1e-6 (relative to the
/// larger). Measured as φ̇(t)/t at the first row of the history, the
/// integrator's first step (t ≤ 1e-4 s, the record's first sample): released at rest, φ̇(t) = φ̈(0) t + O(t³) (the
/// t² term is d/dt φ̈, which is linear in φ̇ = 0 there), so the truncation is
/// about (p t)²/6 ≈ 1e-8 for p² = 3g/4R of these blocks; the integrator's
/// (rtol 1e-11) is far below. A wrong inertia, lever arm, mass ratio or sign
/// of the ground's force moves φ̈ by far more than 1e-6.
#[test]
fn released_stack_accelerates_as_the_two_block_equations_say() {
    // the statue-on-pedestal stack, and a heavier top on a narrower base
    let stacks = [
        ((0.6, 1.0), (0.3, 1.2), None),
        ((0.5, 1.5), (0.4, 0.8), Some(3.0)),
    ];
    let set = SolverSettings {
        integrator: Integrator::Dopri5,
        rtol: 1e-11,
        atol: 1e-12,
        ..SolverSettings::default()
    };
    let mut worst: f64 = 0.0;
    let mut checked = 0;
    for &((w1, hh1), (w2, hh2), top_mass) in &stacks {
        let mut bodies = vec![StackBody::new(w1, hh1), StackBody::new(w2, hh2)];
        if let Some(m) = top_mass {
            bodies[1].mass = m * bodies[0].mass;
        }
        let dims = [
            (w1 / 2.0, hh1 / 2.0, bodies[0].mass),
            (w2 / 2.0, hh2 / 2.0, bodies[1].mass),
        ];
        for a_g in [0.0, 0.1, -0.1] {
            let a = a_g * G;
            // a constant ground acceleration (the record's samples all a)
            let record = Record::from_acc("constant", 1e-4, vec![a; 4]).unwrap();
            for phi in [[0.04, 0.07], [0.04, -0.07], [-0.04, 0.07], [-0.04, -0.07]] {
                let mut stack = Stack::new(bodies.clone(), 0.0, G);
                stack.initial_tilt = phi.to_vec();
                let mut h = StackHistory::default();
                let o = simulate_stack(&stack, &record, &set, Some(&mut h)).unwrap();
                assert!(o.failure.is_none(), "{:?}", o.failure);
                let row = h
                    .rows
                    .iter()
                    .find(|r| r.t > 0.0 && !r.event)
                    .expect("a row after release");
                assert!(row.t <= 1e-4, "first row at {} s", row.t);
                let modes = format!("{:?}", row.mode);
                let want = release_acceleration(dims, phi, a);
                let got = [row.phi_dot[0] / row.t, row.phi_dot[1] / row.t];
                let scale = want[0].abs().max(want[1].abs());
                let err = (got[0] - want[0]).abs().max((got[1] - want[1]).abs()) / scale;
                println!(
                    "{w1}x{hh1} + {w2}x{hh2}, a {a_g:+} g, φ {phi:?} ({modes}): φ̈ {want:?} \
                     solver {got:?}, rel. error {err:.1e}"
                );
                // both blocks rock in the mode of their signs from release
                assert_eq!(
                    row.phi[0].signum() * row.phi[1].signum(),
                    phi[0].signum() * phi[1].signum(),
                    "{modes}"
                );
                assert!(err < 1e-6, "φ̈ {got:?} against {want:?}: {err:e}");
                worst = worst.max(err);
                checked += 1;
            }
        }
    }
    println!("worst relative error {worst:.1e} over {checked} releases");
}

/// The whole stack's static onset with the top off-centre and heavier than
/// its density gives, in both directions (Psycharis 1990's static condition
/// with the top's centre at offset d from the base's axis): under a ground
/// acceleration a the stack tips as one about the base's trailing corner when
/// a/g = (m₁B₁ + m₂(B₁ ± d)) / (m₁H₁ + m₂(2H₁ + H₂)), "+" when the top's
/// offset is away from that corner. Ramps ẍg = ±k t (k = 0.05 g/s): the
/// onset (time at rest × k) matches to 1e-9 g, as the centred stack's does
/// in tests/stack.rs (the event is located by Brent's method on contact
/// forces affine in ẍg). An offset applied with the wrong sign or ignored
/// moves each onset by m₂d/(m₁H₁ + m₂(2H₁ + H₂)) = 0.020 g.
#[test]
fn off_centre_top_shifts_the_stacks_onset_by_its_lever_arm() {
    let k = 0.05 * G;
    let (b1, h1, b2, h2, d) = (0.3, 0.9, 0.2, 0.2, 0.05);
    let mut bodies = vec![
        StackBody::new(2.0 * b1, 2.0 * h1),
        StackBody::new(2.0 * b2, 2.0 * h2),
    ];
    bodies[0].mass = 1.0;
    bodies[1].mass = 2.0;
    bodies[1].offset = d;
    let (m1, m2) = (1.0, 2.0);
    let set = SolverSettings::default();
    for sign in [1.0, -1.0] {
        let ramp = Record::from_acc(
            "ramp",
            0.01,
            (0..3001).map(|i| sign * k * i as f64 * 0.01).collect(),
        )
        .unwrap();
        // a > 0 pushes the bodies left: the stack tips about the base's
        // left corner, and the top's centre (at +d) is d further from it
        let arm = b1 + sign * d;
        let whole = (m1 * b1 + m2 * arm) / (m1 * h1 + m2 * (2.0 * h1 + h2));
        assert!(whole < b2 / h2, "the stack, not the top, tips first");
        let stack = Stack::new(bodies.clone(), 0.0, G);
        let o = simulate_stack(&stack, &ramp, &set, None).unwrap();
        let onset = o.bodies[0].time_in_mode[0] * k / G;
        println!("ẍg sign {sign:+}: onset {onset:.12} g, statics {whole:.12} g");
        assert!((onset - whole).abs() < 1e-9, "{onset} vs {whole}");
        // the top rides on the base: still at rest on it when the stack tips
        assert!(o.bodies[1].time_in_mode[0] * k / G > whole + 1e-3);
    }
}
