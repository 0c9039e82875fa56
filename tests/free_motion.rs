//! The free motion after the record's end (`solver.free_motion_max`): a body
//! still moving when the record ends goes on under still ground until it is
//! at rest or overturns, so no analysis ends undecided. Checked against the
//! closed forms of free rocking (physics.md, check 2: energy and the
//! quadrature of the time), for the single block's solver and the stack's.
//! Each test states its tolerance and why.

use rockfrag::motion::{G_STANDARD as G, Record};
use rockfrag::outcome::Mode;
use rockfrag::solver::stack::{Stack, StackBody, StackHistory, simulate_stack};
use rockfrag::solver::{Analysis, Block, History, Initial, SolverSettings, simulate};

/// `n` samples of still ground every 0.01 s: a record that ends at
/// (n − 1)·0.01 s with nothing in it.
fn still(n: usize) -> Record {
    Record::from_acc("still", 0.01, vec![0.0; n]).unwrap()
}

/// A block released from rest at θ0 on still ground.
fn released(bl: Block, theta0: f64) -> Analysis {
    Analysis {
        initial: Initial {
            theta: theta0,
            ..Initial::default()
        },
        ..Analysis::new(bl, 0.0)
    }
}

/// Time for free rocking (eq. (1) with no ground motion, pivot stuck) to go
/// from rest at θ0 to θ1, both on the same side: the energy gives
/// ½θ̇² = p²[cos(θc − θ0) − cos(θc − θ)], so t = ∫ dθ/θ̇. With θ = θ0 ± u²
/// the integrand is finite at the start; composite Simpson on 20,000
/// intervals (the integrand is smooth: error far below 1e-9 s).
fn free_rock_time(bl: &Block, theta0: f64, theta1: f64) -> f64 {
    let (tc, p2) = (bl.theta_c, bl.p * bl.p);
    let dir = (theta1 - theta0).signum();
    let umax = (theta1 - theta0).abs().sqrt();
    let f = |u: f64| {
        if u == 0.0 {
            // limit of 2u/√(2p² |sin(θ0 − θc)| u²)
            return 2.0 / (2.0 * p2 * (theta0 - tc).sin().abs()).sqrt();
        }
        let th = theta0 + dir * u * u;
        2.0 * u / (2.0 * p2 * ((tc - theta0).cos() - (tc - th).cos())).sqrt()
    };
    let n = 20_000;
    let h = umax / n as f64;
    let mut s = f(0.0) + f(umax);
    for i in 1..n {
        s += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

/// A block released past θc (1.05 θc, H/B 4) on a record of 0.5 s of still
/// ground is still falling when the record ends; it overturns at |θ| = π/2
/// at the time free rocking takes from 1.05 θc to π/2 (about 2 s), to
/// 1e-6 s: the solver integrates the same equation at rtol 1e-8 and locates
/// |θ| = π/2 on its dense output. The old solver stopped at 0.5 s and
/// reported it standing.
#[test]
fn a_block_past_theta_c_at_the_records_end_overturns() {
    let bl = Block::new(0.5, 4.0, G).unwrap();
    let th0 = 1.05 * bl.theta_c;
    let rec = still(51);
    let out = simulate(&released(bl, th0), &rec, &SolverSettings::default(), None).unwrap();
    assert!(out.overturned, "reported standing: {out:?}");
    let t = out.overturn_time.unwrap();
    let expect = free_rock_time(&bl, th0, std::f64::consts::FRAC_PI_2);
    assert!(expect > 1.0, "the fall outlasts the record: {expect}");
    assert!(
        (t - expect).abs() < 1e-6,
        "overturned at {t}, closed form {expect}"
    );
    assert!((out.end_time - t).abs() < 1e-12);
    // stopping at the record's end (free_motion_max = 0) keeps the old answer
    let stop = SolverSettings {
        free_motion_max: 0.0,
        ..SolverSettings::default()
    };
    let old = simulate(&released(bl, th0), &rec, &stop, None).unwrap();
    assert!(!old.overturned && (old.end_time - 0.5).abs() < 1e-12);
}

/// A block driven by 0.3 s of 0.35 g (H/B 4: above g·B/H = 0.25 g) is
/// rocking outward below θc when the record ends. Its peak then follows from
/// energy, cos(θc − θmax) = cos(θc − θe) + θ̇e²/(2p²) with (θe, θ̇e) its state
/// at the record's end (from the history), to 1e-8 in θmax/θc (rtol 1e-8 on
/// the integration, the peak located on the dense output). It comes back,
/// rocks down to rest and the analysis ends at rest, after the record.
#[test]
fn a_block_rocking_at_the_records_end_reaches_its_peak_and_rests() {
    let bl = Block::new(0.5, 4.0, G).unwrap();
    let rec = Record::from_acc("pulse", 0.01, vec![0.35 * G; 31]).unwrap();
    let mut hist = History::default();
    let an = Analysis::new(bl, 0.0);
    let out = simulate(&an, &rec, &SolverSettings::default(), Some(&mut hist)).unwrap();
    let end = hist
        .rows
        .iter()
        .find(|r| (r.t - 0.3).abs() < 1e-12 && !r.event)
        .expect("a row at the record's end");
    let (th, om) = (end.theta, end.theta_dot);
    assert!(end.mode == Mode::Rock && th > 0.0 && om > 0.0, "{end:?}");
    let c = (bl.theta_c - th).cos() + om * om / (2.0 * bl.p * bl.p);
    assert!(c < 1.0, "the pulse is too strong: the block would overturn");
    let peak = (bl.theta_c - c.acos()) / bl.theta_c;
    assert!(
        peak > 1.2 * th / bl.theta_c,
        "the peak comes after the record"
    );
    assert!(!out.overturned);
    assert!(
        (out.theta_max_over_theta_c - peak).abs() < 1e-8,
        "θmax/θc {} against energy {peak}",
        out.theta_max_over_theta_c
    );
    let last = hist.rows.last().unwrap();
    assert_eq!(last.mode, Mode::Rest, "the analysis ends at rest: {last:?}");
    assert!(out.end_time > 0.3 && (last.t - out.end_time).abs() < 1e-12);
    let total: f64 = out.time_in_mode.iter().sum();
    assert!(
        (total - out.end_time).abs() < 1e-9,
        "{total} vs {}",
        out.end_time
    );
}

/// A block released at 0.5 θc on 0.2 s of still ground: the record ends
/// before its first impact. Its peak stays 0.5 (to 1e-12: free rocking from
/// rest never rises above θ0), its first impact comes at the quadrature's
/// time to θ = 0 (1e-6 s, as above), and it ends at rest. The old solver
/// stopped at 0.2 s with the block mid-swing and no impact.
#[test]
fn a_block_released_below_theta_c_keeps_its_peak_and_rests() {
    let bl = Block::new(0.5, 4.0, G).unwrap();
    let th0 = 0.5 * bl.theta_c;
    let mut hist = History::default();
    let out = simulate(
        &released(bl, th0),
        &still(21),
        &SolverSettings::default(),
        Some(&mut hist),
    )
    .unwrap();
    assert!(!out.overturned);
    assert!((out.theta_max_over_theta_c - 0.5).abs() < 1e-12);
    let t1 = out.first_impact_time.expect("an impact after the record");
    let expect = free_rock_time(&bl, th0, 0.0);
    assert!(expect > 0.2);
    assert!(
        (t1 - expect).abs() < 1e-6,
        "first impact {t1}, closed form {expect}"
    );
    assert_eq!(hist.rows.last().unwrap().mode, Mode::Rest);
}

/// An analysis still moving `free_motion_max` after the record is refused
/// with the setting named, not reported as its state then (here a cap of
/// 0.05 s, shorter than the swing to the first impact).
#[test]
fn still_moving_at_the_cap_is_an_error_that_says_so() {
    let bl = Block::new(0.5, 4.0, G).unwrap();
    let set = SolverSettings {
        free_motion_max: 0.05,
        ..SolverSettings::default()
    };
    let err = simulate(&released(bl, 0.5 * bl.theta_c), &still(21), &set, None).unwrap_err();
    assert!(err.to_string().contains("free_motion_max"), "{err}");
    let bad = SolverSettings {
        free_motion_max: f64::INFINITY,
        ..SolverSettings::default()
    };
    let err = bad.validate().unwrap_err().to_string();
    assert!(err.contains("free_motion_max"), "{err}");
}

/// A statue (0.3 × 1.2 m) on a pedestal that cannot move (2 × 0.5 m, 1e12
/// times heavier, infinite friction), released at 1.05 θc on 0.5 s of still
/// ground: it overturns after the record, at the single block's closed-form
/// time (1e-6 s: Dormand–Prince at rtol 1e-8), the pedestal stays. And one
/// released at 0.5 θc keeps its peak and every body ends at rest. The old solver stopped at
/// 0.5 s with the first statue falling and reported it standing.
#[test]
fn a_statue_falling_at_the_records_end_overturns_and_one_rocking_rests() {
    let mut base = StackBody::new(2.0, 0.5);
    base.mass *= 1e12;
    let top = StackBody::new(0.3, 1.2);
    let bl = Block::new(0.3, 4.0, G).unwrap();
    let set = SolverSettings::default();
    let mut stack = Stack::new(vec![base, top], 0.0, G);
    stack.initial_tilt = vec![0.0, 1.05 * bl.theta_c];
    let out = simulate_stack(&stack, &still(51), &set, None).unwrap();
    assert!(out.failure.is_none(), "{:?}", out.failure);
    assert!(
        out.bodies[1].overturned && !out.bodies[0].overturned,
        "{out:?}"
    );
    let t = out.bodies[1].overturn_time.unwrap();
    let expect = free_rock_time(&bl, 1.05 * bl.theta_c, std::f64::consts::FRAC_PI_2);
    assert!(
        (t - expect).abs() < 1e-6,
        "overturned at {t}, closed form {expect}"
    );

    stack.initial_tilt = vec![0.0, 0.5 * bl.theta_c];
    let mut hist = StackHistory::default();
    let out = simulate_stack(&stack, &still(21), &set, Some(&mut hist)).unwrap();
    assert!(out.failure.is_none(), "{:?}", out.failure);
    assert!(!out.bodies[1].overturned);
    // the stack notes its peaks from the end of its first step, not at the
    // release pose, so its peak is the release's to 1e-5 (2e-6 here), never
    // above it (to rounding): free rocking from rest does not rise above θ0
    let peak = out.bodies[1].theta_max_over_theta_c;
    assert!(peak <= 0.5 + 1e-12 && peak > 0.5 - 1e-5, "{peak}");
    let last = hist.rows.last().unwrap();
    assert!(last.mode.iter().all(|m| *m == Mode::Rest), "{last:?}");
    assert!(out.end_time > 0.2 && (last.t - out.end_time).abs() < 1e-12);

    // a cap shorter than its swing: the failure names the setting
    let short = SolverSettings {
        free_motion_max: 0.05,
        ..set
    };
    let out = simulate_stack(&stack, &still(21), &short, None).unwrap();
    let why = out.failure.expect("still moving at the cap");
    assert!(why.contains("free_motion_max"), "{why}");
}

/// A stack on frictionless ground (μs = μk = 0; infinite friction between
/// the bodies) stays put in space while the ground moves under it (physics.md,
/// check 1b, for the single block): after a 0.1 s pulse of 1 m/s² the ground
/// still moves at 0.1 m/s when the 0.5 s record ends, so the stack slides
/// flat on it for ever, a rigid translation that nothing can stop or tip.
/// That is final, as for the single block (its `settled`): the analysis
/// ends at the record's end with the slip then, undecided by no cap. The
/// old stack solver followed the slide for 60 s and failed at the cap. The
/// slip is the ground's displacement at the end, to 1e-9 relative (the
/// relative acceleration is −ẍg, piecewise linear, which Dormand–Prince
/// integrates exactly up to rounding).
#[test]
fn a_stack_sliding_on_frictionless_ground_at_the_records_end_is_final() {
    let mut acc = vec![0.0; 51];
    acc[..=10].fill(1.0);
    let rec = Record::from_acc("pulse", 0.01, acc).unwrap();
    let mut stack = Stack::new(
        vec![StackBody::new(0.6, 1.0), StackBody::new(0.3, 1.2)],
        0.0,
        G,
    );
    stack.interfaces[0].friction = rockfrag::solver::Friction::Coulomb {
        mu_s: 0.0,
        mu_k: 0.0,
    };
    let out = simulate_stack(&stack, &rec, &SolverSettings::default(), None).unwrap();
    assert!(out.failure.is_none(), "{:?}", out.failure);
    assert!(
        (out.end_time - 0.5).abs() < 1e-12,
        "ended at {}",
        out.end_time
    );
    let d_end = rec.disp.last().unwrap().abs();
    assert!(d_end > 0.04, "the ground moved {d_end} m");
    let slip = out.bodies[0].slip_max;
    assert!(
        (slip - d_end).abs() <= 1e-9 * d_end,
        "slip {slip}, ground {d_end}"
    );
    // the statue rides along: no slip, no rotation on its pedestal
    let top = &out.bodies[1];
    assert!(
        top.slip_max == 0.0 && top.theta_max_over_theta_c == 0.0,
        "{top:?}"
    );
    assert!(!out.bodies.iter().any(|b| b.overturned));
}
