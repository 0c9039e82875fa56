//! Closed-form checks of the infinite-friction solver (issue 3, items 1–4, 8).
//! Each test states the physical fact it checks and why its tolerance.

mod common;

use common::reference::{
    constant_record, free_rocking_first_impact_time, next_amplitude, quiet_record,
    rock_impact_velocity,
};
use rockfrag::motion::Record;
use rockfrag::outcome::Mode;
use rockfrag::solver::{Analysis, Block, History, Initial, SolverSettings, simulate};
use rockfrag::solver::{ImpactLaw, corner_impact, rock_impact_mu, rock_impact_ratio};

const G: f64 = 9.81;

fn block(aspect: f64) -> Block {
    Block::new(0.5, aspect, G).unwrap()
}

/// Check 1: Rock impact, no slip: ω₂/ω₁ = 1 − 1.5(1+e)sin²θc and |P_t/P_n| =
/// 3cosθc sinθc/(1+3cos²θc) (the paper's eq. 8), for both impact laws (they
/// coincide when the striking corner has no tangential velocity, as here).
/// Tolerance 1e-12: a 2×2 linear solve in double precision.
#[test]
fn rock_impact_matches_housner_ratio_and_eq8() {
    for aspect in [2.0, 4.0, 6.0] {
        let bl = block(aspect);
        for e in [0.0, 0.3, 0.6, 0.9] {
            for law in [ImpactLaw::Newton, ImpactLaw::Energetic] {
                let omega1 = -1.7;
                let v = rock_impact_velocity(&bl, omega1);
                // the striking corner is the right one, offset (B, −H) at θ = 0
                let r = corner_impact(&bl, &v, bl.b, -bl.h, e, law);
                let ratio = r.after.omega / omega1;
                let delta = rock_impact_ratio(&bl, e);
                assert!(
                    (ratio - delta).abs() < 1e-12,
                    "H/B {aspect} e {e}: {ratio} vs {delta}"
                );
                let mu = (r.p_t / r.p_n).abs();
                assert!(
                    (mu - rock_impact_mu(&bl)).abs() < 1e-12,
                    "H/B {aspect} e {e}: mu {mu}"
                );
            }
        }
    }
    // the paper's quoted values of eq. (8)
    assert!((rock_impact_mu(&block(2.0)) - 0.353).abs() < 5e-4);
    assert!((rock_impact_mu(&block(4.0)) - 0.185).abs() < 5e-4);
    assert!((rock_impact_mu(&block(6.0)) - 0.124).abs() < 5e-4);
}

/// Check 1b: The same through the whole solver: free rocking with e = 0, the
/// angular velocity across the first impact drops by δ and the recorded
/// mu_impact is eq. (8). Tolerance 1e-12 (the impact map is applied exactly
/// to the located state).
#[test]
fn solver_applies_rock_impact_exactly() {
    let bl = block(4.0);
    let mut an = Analysis::new(bl, 0.0);
    an.initial = Initial {
        theta: 0.5 * bl.theta_c,
        ..Initial::default()
    };
    let mut hist = History::default();
    let out = simulate(
        &an,
        &quiet_record(0.01, 1.0),
        &SolverSettings::default(),
        Some(&mut hist),
    )
    .unwrap();
    let t1 = out.first_impact_time.expect("an impact within 1 s");
    let at: Vec<_> = hist.rows.iter().filter(|r| r.event && r.t == t1).collect();
    assert_eq!(at.len(), 2, "one row before and one after the impact");
    let ratio = at[1].theta_dot / at[0].theta_dot;
    assert!(
        (ratio - rock_impact_ratio(&bl, 0.0)).abs() < 1e-12,
        "{ratio}"
    );
    assert!((out.mu_impact - rock_impact_mu(&bl)).abs() < 1e-12);
}

/// Check 2: Free rocking from θ0 = 0.5θc, no ground motion, e = 0: the time to the
/// first impact equals the energy quadrature, and successive amplitudes follow
/// cos(θc−θn+1) − cosθc = δ²[cos(θc−θn) − cosθc]. Tolerance 1e-8 relative at
/// the default rtol = 1e-8 (the requirement; the quadrature itself is
/// accurate to ~1e-14).
#[test]
fn free_rocking_matches_energy_quadrature_and_amplitude_decay() {
    for aspect in [2.0, 4.0, 6.0] {
        let bl = block(aspect);
        let theta0 = 0.5 * bl.theta_c;
        let mut an = Analysis::new(bl, 0.0);
        an.initial = Initial {
            theta: theta0,
            ..Initial::default()
        };
        let mut hist = History::default();
        // the amplitudes of the ring-down itself are checked: follow it impact
        // by impact (the cascade rule would set H/B 2 to rest after two peaks)
        let settings = SolverSettings {
            settle_cascades: false,
            ..SolverSettings::default()
        };
        let out = simulate(&an, &quiet_record(0.02, 8.0), &settings, Some(&mut hist)).unwrap();
        let expected = free_rocking_first_impact_time(&bl, theta0);
        let t1 = out.first_impact_time.unwrap();
        assert!(
            ((t1 - expected) / expected).abs() < 1e-8,
            "H/B {aspect}: {t1} vs {expected}"
        );
        // amplitudes: turning points (event rows with θ̇ ≈ 0 in rock), in order
        let peaks: Vec<f64> = hist
            .rows
            .iter()
            .filter(|r| {
                r.event && r.mode == Mode::Rock && r.theta_dot.abs() < 1e-6 && r.theta != 0.0
            })
            .map(|r| r.theta.abs())
            .collect();
        assert!(
            peaks.len() >= 3,
            "H/B {aspect}: only {} turning points",
            peaks.len()
        );
        let mut prev = theta0;
        for (n, &p) in peaks.iter().take(4).enumerate() {
            let want = next_amplitude(&bl, prev);
            assert!(
                ((p - want) / want).abs() < 1e-8,
                "H/B {aspect} amplitude {n}: {p} vs {want}"
            );
            prev = p;
        }
    }
}

/// Check 3: Static threshold: a constant ẍg just below g·B/H never starts rocking;
/// just above it does (and the rocking starts at t = 0).
#[test]
fn static_threshold_of_rocking() {
    for aspect in [2.0, 4.0, 6.0] {
        let bl = block(aspect);
        let a_c = G / aspect;
        let an = Analysis::new(bl, 0.0);
        let set = SolverSettings::default();
        let below = simulate(&an, &constant_record(0.99 * a_c, 0.02, 2.0), &set, None).unwrap();
        assert!(!below.moved && below.theta_max_over_theta_c == 0.0);
        assert_eq!(below.time_in_mode[Mode::Rest.index()], below.end_time);
        let above = simulate(&an, &constant_record(1.01 * a_c, 0.02, 2.0), &set, None).unwrap();
        assert!(
            above.moved && above.theta_max_over_theta_c > 0.0,
            "H/B {aspect}"
        );
        // no rest before rocking starts; after the record the block comes
        // to rest by a cascade whose duration is moved from rest to rock and
        // the analysis ends there, so rest is 0 to rounding (1e-12 s)
        let rest = above.time_in_mode[Mode::Rest.index()];
        assert!(rest.abs() < 1e-12, "H/B {aspect}: {rest}");
    }
}

/// Check 3b: The start of rocking is located exactly on a linear ramp: ẍg = c·t
/// crosses g·B/H at t* = g/(H/B·c); the block stays at rest exactly until t*.
/// Tolerance 1e-12 s (a linear equation solved in double precision).
#[test]
fn start_of_rocking_is_exact_on_a_ramp() {
    let bl = block(4.0);
    let c = 3.0; // m/s³
    let dt = 0.02;
    let acc: Vec<f64> = (0..=100).map(|k| c * k as f64 * dt).collect();
    let rec = Record::from_acc("ramp", dt, acc).unwrap();
    let out = simulate(
        &Analysis::new(bl, 0.0),
        &rec,
        &SolverSettings::default(),
        None,
    )
    .unwrap();
    let t_star = G / 4.0 / c;
    assert!((out.time_in_mode[Mode::Rest.index()] - t_star).abs() < 1e-12);
}

/// Check 4: Free flight: a block thrown straight up, flat, with speed v lands flat at
/// t = 2v/g (G follows a parabola, θ̇ = 0). Tolerance 1e-10 s: the landing is
/// located by root finding on the exact closed form.
#[test]
fn thrown_block_lands_at_the_analytical_time() {
    let bl = block(3.0);
    for v in [0.05, 0.5, 2.0] {
        for e in [0.0, 0.5] {
            let mut an = Analysis::new(bl, e);
            an.initial = Initial {
                y_dot: v,
                ..Initial::default()
            };
            // the landing is flat, so the block bounces flat and comes to
            // rest: the motion after the record (if any) is physical too
            let set = SolverSettings::default();
            let out = simulate(&an, &quiet_record(0.01, 1.0), &set, None).unwrap();
            let t = out.first_impact_time.unwrap();
            assert!((t - 2.0 * v / G).abs() < 1e-10, "v {v} e {e}: {t}");
            // a flat landing strikes both corners (two-contact rule)
            assert!(out.impacts >= 2);
            assert!(!out.overturned);
        }
    }
}

/// Check 4b: A flat landing (θ = 0, θ̇ = 0, both corners strike at once) on
/// still ground is symmetric, so it must not turn the block: the two-contact
/// impact gives a vertical rebound at e·v (1e-12 relative: a 3×3 solve), no
/// rotation (θmax exactly 0: nothing breaks the symmetry), no overturning, no
/// energy gain at any impact (1e-9 relative), and with e = 0 rest at once.
/// The sequential rule (one corner first) turned such a landing into rocking
/// (θmax/θc 0.19 at 2 m/s, e = 0) and, at e = 0.5, overturned it after the record.
#[test]
fn flat_landing_stays_flat() {
    let bl = Block::new(0.4, 3.0, G).unwrap();
    for v in [0.5, 1.0, 2.0] {
        for e in [0.0, 0.3, 0.5] {
            let mut an = Analysis::new(bl, e);
            an.initial = Initial {
                y_dot: v,
                ..Initial::default()
            };
            let set = SolverSettings {
                audit_energy: true,
                ..SolverSettings::default()
            };
            let mut hist = History::default();
            let out = simulate(&an, &quiet_record(0.01, 1.0), &set, Some(&mut hist)).unwrap();
            let tag = format!("v {v} e {e}");
            assert!(!out.overturned, "{tag}");
            assert_eq!(out.theta_max_over_theta_c, 0.0, "{tag}");
            assert_eq!(out.energy_gains, 0, "{tag}");
            assert!(
                hist.rows
                    .iter()
                    .all(|r| r.theta == 0.0 && r.theta_dot == 0.0 && r.x_dot == 0.0),
                "{tag}"
            );
            // kinetic energy across every impact (two rows at one instant)
            let kin = |r: &rockfrag::solver::HistoryRow| bl.kinetic(r.x_dot, r.y_dot, r.theta_dot);
            for w in hist.rows.windows(2) {
                if w[0].t == w[1].t {
                    assert!(
                        kin(&w[1]) <= kin(&w[0]) * (1.0 + 1e-9),
                        "{tag} at t {}",
                        w[0].t
                    );
                }
            }
            let t_land = 2.0 * v / G;
            let first = hist.rows.iter().position(|r| r.event && r.t > 0.0).unwrap();
            let after = &hist.rows[first + 1];
            assert!((after.t - t_land).abs() < 1e-10, "{tag}");
            assert!(
                (after.y_dot - e * v).abs() <= 1e-12 * v,
                "{tag}: {}",
                after.y_dot
            );
            if e == 0.0 {
                // rest from the landing to the record's end
                assert_eq!(after.mode, Mode::Rest, "{tag}");
                let rest = out.time_in_mode[Mode::Rest.index()];
                assert!((rest - (1.0 - t_land)).abs() < 1e-9, "{tag}: {rest}");
            }
            // and the analysis ends at rest, not moving
            assert_eq!(hist.rows.last().unwrap().mode, Mode::Rest, "{tag}");
        }
    }
}

/// Check 8a: Lift-off with a consistent release: a block spinning fast enough that
/// the centripetal demand exceeds gravity (R cosφ θ̇² > g) loses contact at
/// once: counted as an uplift, then flies.
#[test]
fn fast_spin_lifts_off_into_flight() {
    let bl = Block::new(0.5, 1.0, G).unwrap();
    let mut an = Analysis::new(bl, 0.0);
    an.initial = Initial {
        theta: 0.2 * bl.theta_c,
        theta_dot: 9.0,
        ..Initial::default()
    };
    let out = simulate(
        &an,
        &quiet_record(0.01, 0.5),
        &SolverSettings::default(),
        None,
    )
    .unwrap();
    assert!(out.uplifted && out.uplifts >= 1, "{out:?}");
    assert!(out.time_in_mode[Mode::Flight.index()] > 0.0);
}

/// Check 8b: Lift-off without a consistent release: a strong ground pull back
/// towards θ = 0 drives N to zero while the released pivot would not rise
/// (q > 0). The documented rule holds the pivot (counted in liftoff_holds)
/// rather than entering flight.
#[test]
fn inconsistent_liftoff_holds_the_pivot() {
    let bl = Block::new(1.0, 1.0, G).unwrap();
    let mut an = Analysis::new(bl, 0.0);
    an.initial = Initial {
        theta: 0.5 * bl.theta_c,
        ..Initial::default()
    };
    // ramp from 0 to −6 g in 0.5 s: N falls through zero while θ̇ is still small
    let rec = Record::from_acc("pull", 0.5, vec![0.0, -6.0 * G, -6.0 * G]).unwrap();
    let mut hist = History::default();
    let out = simulate(&an, &rec, &SolverSettings::default(), Some(&mut hist)).unwrap();
    assert!(out.liftoff_holds >= 1, "{out:?}");
    // the hold starts where N crosses zero: the event row has |N| ≪ g, the
    // block is still rocking on both sides of it, and it never flew before
    let i = hist
        .rows
        .iter()
        .position(|r| r.event && r.mode == Mode::Rock && r.n.abs() < 1e-9 * G)
        .expect("the N = 0 crossing is located to 1e-9 g");
    assert_eq!(hist.rows[i + 1].mode, Mode::Rock);
    assert!(hist.rows[..i].iter().all(|r| r.mode != Mode::Flight));
    // while held, the contact is in tension (N < 0) at the next sample
    assert!(
        hist.rows[i + 2..]
            .iter()
            .take(1)
            .all(|r| r.n < 0.0 || r.event)
    );
}

/// `rock_impact = "rock"` (a reading of the paper's program, not the physics):
/// free rocking from θ0 = 0.5θc, no ground motion, e = 0.6. Every rock impact
/// keeps the block rocking with θ̇2 = δ(e)θ̇1, δ(e) = 1 − 1.5(1+e)sin²θc, so
/// energy gives cos(θc−θn+1) − cosθc = δ(e)²[cos(θc−θn) − cosθc] and there is
/// no flight. Under the default (`bounce`) the block flies after each rock
/// impact and the ring-down on the new corner conserves the angular momentum
/// about it, so its amplitudes follow Housner's δ(0) instead (for H/B 2,
/// δ(0.6)² = 0.27 against δ(0)² = 0.49): the amplitude check fails there.
/// Tolerance 1e-8 relative, as in the e = 0 amplitude check (rtol = 1e-8).
#[test]
fn rock_impact_rule_rock_decays_with_delta_of_e() {
    use rockfrag::solver::RockImpact;
    let e = 0.6;
    for aspect in [2.0, 4.0, 6.0] {
        let bl = block(aspect);
        let tc = bl.theta_c;
        let theta0 = 0.5 * tc;
        let mut an = Analysis::new(bl, e);
        an.initial = Initial {
            theta: theta0,
            ..Initial::default()
        };
        let settings = SolverSettings {
            rock_impact: RockImpact::Rock,
            ..SolverSettings::default()
        };
        let mut hist = History::default();
        let out = simulate(&an, &quiet_record(0.02, 8.0), &settings, Some(&mut hist)).unwrap();
        assert_eq!(out.flights, 0, "H/B {aspect}: the rule allows no flight");
        assert_eq!(out.energy_gains, 0);
        let peaks: Vec<f64> = hist
            .rows
            .iter()
            .filter(|r| {
                r.event && r.mode == Mode::Rock && r.theta_dot.abs() < 1e-6 && r.theta != 0.0
            })
            .map(|r| r.theta.abs())
            .collect();
        assert!(
            peaks.len() >= 3,
            "H/B {aspect}: {} turning points",
            peaks.len()
        );
        let delta = rock_impact_ratio(&bl, e);
        let mut prev = theta0;
        for (n, &p) in peaks.iter().take(3).enumerate() {
            // energy between impacts and θ̇2 = δ(e)θ̇1 at each impact
            let c = tc.cos() + delta * delta * ((tc - prev).cos() - tc.cos());
            let want = tc - c.acos();
            assert!(
                ((p - want) / want).abs() < 1e-8,
                "H/B {aspect} amplitude {n}: {p} vs {want}"
            );
            prev = p;
        }
    }
}

/// Issue 30: the friction demand of an overturning run is finite. Pushed
/// over by a constant ẍg = 0.5 g (H/B 4, twice the uplift threshold g·B/H),
/// the block tips past θc and falls; as it falls N → 0 (it is held at N = 0
/// once) and |F|/N grows without bound (the peak over the whole fall was
/// 44.6, and 4e13–5e15 in the studies' overturned runs). `mu_motion`
/// leaves out the final excursion beyond θc: it is the peak |F|/N at the
/// ends of the rock steps that end within θc, which here are the record's
/// samples, so it equals the peak over the history's sample rows in rock
/// with |θ| ≤ θc (1e-12 relative for the rounding of the contact forces,
/// computed from the series' sine and cosine in the solver and afresh in the
/// history), while the rows beyond θc reach above 10.
#[test]
fn overturning_run_friction_demand_leaves_out_the_fall() {
    let bl = block(4.0);
    let rec = constant_record(0.5 * G, 0.01, 3.0);
    let mut h = History::default();
    let set = SolverSettings::default();
    let out = simulate(&Analysis::new(bl, 0.0), &rec, &set, Some(&mut h)).unwrap();
    assert!(out.overturned && out.liftoff_holds == 1);
    let demand = |within: bool| {
        h.rows
            .iter()
            .filter(|r| r.mode == Mode::Rock && !r.event && r.n > 0.0)
            .filter(|r| (r.theta.abs() <= bl.theta_c) == within)
            .map(|r| r.f.abs() / r.n)
            .fold(0.0_f64, f64::max)
    };
    let (within, beyond) = (demand(true), demand(false));
    assert!(
        (out.mu_motion - within).abs() <= 1e-12 * within,
        "μ_mot {} against the peak within θc {within}",
        out.mu_motion
    );
    assert!(
        out.mu_motion < 1.0 && beyond > 10.0,
        "μ_mot {}, beyond θc {beyond}",
        out.mu_motion
    );
}
