//! The cascade rules (`SolverSettings::settle_cascades`).
//!
//! e = 0: a cascade of shrinking rock impacts that provably dies out before
//! the ground can lift the block is set to rest at once. It must leave
//! everything after it unchanged, so the peak rotation and overturning are
//! those of the cascade followed impact by impact, bit for bit; and it must
//! save most of the events of an e = 0 analysis (the reason it exists).
//!
//! e > 0 (the chatter rule): the tail of a series of bounces on one corner is
//! closed in one step with its sums. It changes the motion by a fourth-order
//! amount, so it is held to the integrators' own disagreement: θmax/θc within
//! a small tolerance, and no more overturning flips than Taylor against
//! Dormand–Prince. With e > 0 a cascade of rock impacts, each closed by the
//! chatter rule, is set to rest too.
//!
//! Under Coulomb friction both rules apply while nothing can slip (the
//! motion is then that of infinite friction), and are held to the same bars.

mod common;

use common::reference::quiet_record;
use rockfrag::motion::{G_STANDARD as G, Record, SynthesisSettings, Synthesizer};
use rockfrag::outcome::{Mode, Outcome};
use rockfrag::solver::{
    Analysis, Block, Friction, History, HistoryRow, Initial, Integrator, SolverSettings, simulate,
};

/// The study's finite friction (μs = 0.7, μk = 0.6): above every block's
/// B/H here and eq. (8)'s rock-impact demand, so most motions never slip.
const COULOMB: Friction = Friction::Coulomb {
    mu_s: 0.7,
    mu_k: 0.6,
};

fn without_rule() -> SolverSettings {
    SolverSettings {
        settle_cascades: false,
        ..SolverSettings::default()
    }
}

/// A block of 2B = 0.5 m and H/B 4 with restitution `e`, released at rest
/// from θc/2 (the free ring-downs and single series below).
fn released_from_half_tilt(e: f64) -> Analysis {
    let bl = Block::new(0.5, 4.0, G).unwrap();
    let mut an = Analysis::new(bl, e);
    an.initial = Initial {
        theta: 0.5 * bl.theta_c,
        ..Initial::default()
    };
    an
}

/// One analysis (2B = 0.5 m, e = 0, `friction`) with and without the
/// rule; asserts that θmax, overturning (and its time, to rounding under
/// friction), lift-offs and holds agree exactly.
fn both(aspect: f64, friction: Friction, rec: &Record, what: &str) -> (Outcome, Outcome) {
    let mut an = Analysis::new(Block::new(0.5, aspect, G).unwrap(), 0.0);
    an.friction = friction;
    let on = simulate(&an, rec, &SolverSettings::default(), None).unwrap();
    let off = simulate(&an, rec, &without_rule(), None).unwrap();
    assert_eq!(
        on.theta_max_over_theta_c, off.theta_max_over_theta_c,
        "{what}"
    );
    assert_eq!(on.overturned, off.overturned, "{what}");
    if friction == Friction::Infinite {
        assert_eq!(on.overturn_time, off.overturn_time, "{what}");
    } else {
        // under friction the impacts followed one by one stick up to the
        // rounding of their friction law (the footprint moves by ~1e-12 m),
        // which the later motion carries to the last digits of its times
        let (a, b) = (
            on.overturn_time.unwrap_or(0.0),
            off.overturn_time.unwrap_or(0.0),
        );
        assert!(
            (a - b).abs() <= 1e-12 * b.abs(),
            "{what}: overturned at {a} s against {b} s"
        );
    }
    assert_eq!(on.uplifts, off.uplifts, "{what}");
    assert_eq!(on.liftoff_holds, off.liftoff_holds, "{what}");
    (on, off)
}

/// 180 analyses (H/B 2, 4, 6; PGA 0.3, 0.6, 1.0 g; 20 records each; e = 0,
/// infinite friction), with and without the rule: θmax, the overturning
/// outcome and time, and the lift-offs agree exactly, since after a settled
/// cascade both runs are at rest until the same instant. μ_mot agrees to
/// 1e-6 (the rule takes the cascade's demand at its window's ends, to O(u²)).
/// The time in rock agrees to 1e-2 s (the settled cascades' closed-form
/// durations take the ground as frozen at their start; measured: median
/// 3.7e-4 s, largest 7.0e-3 s, where counting the cascades as rest was off by
/// up to 0.87 s). The rule must remove at least 40 % of all events;
/// measured: 51 % (11,748 against 24,075).
#[test]
fn cascade_rule_changes_no_later_motion() {
    cascade_population(Friction::Infinite);
}

/// The same 180 analyses under Coulomb friction (μs = 0.7, μk = 0.6), to the
/// same bars: the rule applies while the cascade cannot slip (its rock
/// impacts ask for eq. (8)'s 0.19 at H/B 4, its bounces' μs N − |F| and the
/// rest's μs (g + ÿg) − |ẍg| stay positive over the window), and then the
/// motion is that of infinite friction. Before the rule applied under
/// friction the events were the same with it and without it. Measured:
/// 11,768 events against 24,859 (47 %).
#[test]
fn cascade_rule_under_coulomb_friction() {
    cascade_population(COULOMB);
}

/// 180 analyses with and without the rule under `friction` (see
/// `cascade_rule_changes_no_later_motion`).
fn cascade_population(friction: Friction) {
    let mut syn = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let (mut events_on, mut events_off) = (0, 0);
    for pga in [0.3, 0.6, 1.0] {
        for i in 0..20 {
            let rec = syn.generate(41, i, pga * G).unwrap();
            for aspect in [2.0, 4.0, 6.0] {
                let what = format!("H/B {aspect}, {pga} g, record {i}");
                let (on, off) = both(aspect, friction, &rec, &what);
                if !off.overturned {
                    let rel = (on.mu_motion - off.mu_motion).abs() / off.mu_motion.max(1e-300);
                    assert!(
                        rel < 1e-6,
                        "{what}: μ_mot {} vs {}",
                        on.mu_motion,
                        off.mu_motion
                    );
                }
                let rock = |o: &Outcome| o.time_in_mode[Mode::Rock.index()];
                assert!(
                    (rock(&on) - rock(&off)).abs() < 1e-2,
                    "{what}: {} s in rock against {} s",
                    rock(&on),
                    rock(&off)
                );
                assert!(on.stats.events <= off.stats.events, "{what}");
                events_on += on.stats.events;
                events_off += off.stats.events;
            }
        }
    }
    assert!(
        10 * events_on <= 6 * events_off,
        "{events_on} events with the rule against {events_off} without"
    );
}

/// Free rocking on still ground from θ = θc/2 (H/B 4, e = 0): each impact
/// keeps η = 1 − 1.5 sin²θc ≈ 0.91 of the angular velocity, so without the
/// rule the ε threshold (1e-6·√(gR)) ends the cascade only after 124 impacts.
/// With it the block settles once the bounds close (measured: after 21
/// impacts; at most 40 allowed), with the same peak rotation, the release
/// angle, and the same time in rock to 2e-4 s: the settled cascade counts as
/// rock for its closed-form duration on still ground, exact to O(u⁵), while
/// the ε threshold cuts the followed cascade's last 8e-5 s (measured:
/// 6.6e-5 s; counted as rest, as it was, the cascade's 1.06 s was off).
#[test]
fn free_ring_down_settles_in_a_few_impacts() {
    let an = released_from_half_tilt(0.0);
    let rec = quiet_record(0.02, 10.0);
    let on = simulate(&an, &rec, &SolverSettings::default(), None).unwrap();
    let off = simulate(&an, &rec, &without_rule(), None).unwrap();
    assert!(
        off.impacts > 100,
        "{} impacts without the rule",
        off.impacts
    );
    assert!(on.impacts <= 40, "{} impacts with the rule", on.impacts);
    assert_eq!(on.settles, 1);
    assert_eq!(on.theta_max_over_theta_c, off.theta_max_over_theta_c);
    assert!((on.theta_max_over_theta_c - 0.5).abs() < 1e-12);
    // both end at rest, after the same time in rock
    let time = |o: &Outcome, m: Mode| o.time_in_mode[m.index()];
    assert!(time(&off, Mode::Rest) > 0.0);
    assert!(
        (time(&on, Mode::Rock) - time(&off, Mode::Rock)).abs() < 2e-4,
        "{} s in rock against {} s",
        time(&on, Mode::Rock),
        time(&off, Mode::Rock)
    );
}

/// With vertical ground motion too (ÿg = 0.5·ẍg of another record of the
/// ensemble), which moves both the restoring accelerations and N: 60
/// analyses with and without the rule agree exactly in θmax, overturning and
/// lift-offs.
#[test]
fn cascade_rule_with_vertical_motion() {
    let mut syn = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let mut settled = 0;
    for i in 0..20 {
        let mut rec = syn.generate(43, i, 0.6 * G).unwrap();
        let other = syn.generate(43, i + 100, 0.6 * G).unwrap();
        rec.acc_v = Some(other.acc.iter().map(|a| 0.5 * a).collect());
        for aspect in [3.0, 4.0, 6.0] {
            let (on, off) = both(
                aspect,
                Friction::Infinite,
                &rec,
                &format!("H/B {aspect}, record {i}"),
            );
            settled += (on.stats.events < off.stats.events) as usize;
        }
    }
    // the rule did act in this ensemble (measured: in 50 of 60 analyses)
    assert!(
        settled >= 30,
        "the rule shortened only {settled} of 60 analyses"
    );
}

// ---- The chatter rule (e > 0) ----

/// Free rocking on still ground from θc/2 (H/B 4) at e = 0.5 and 0.9: after
/// each rock impact the block bounces on the new corner dozens of times
/// before the ε rule sets it rocking on that corner. The rule closes each
/// series once its rebound is below 1e-3·√(gR) and its bounds hold: the same
/// peak (the release angle), the same time at rest to 1 ms, the footprint to
/// 1 µm, no energy gained, and at most a third of the flights (measured: 138
/// against 960 at e = 0.5 and 1,028 against 6,470 at e = 0.9; time at rest
/// within 0.5 ms, footprint within 6e-11 m).
#[test]
fn chatter_free_ring_down() {
    ring_down(Friction::Infinite);
}

/// The same ring-downs under Coulomb friction (μs = 0.7, μk = 0.6): every
/// impact of these series sticks (their impulse ratios stay below μs) and
/// rock about the new corner does not slip, so the rule closes them as under
/// infinite friction, to the same bars. Before it applied under friction
/// every bounce was followed (the same flights with the rule as without).
/// Measured: 138 flights against 960 at e = 0.5, 1,028 against 6,466 at
/// e = 0.9.
#[test]
fn chatter_under_coulomb_friction() {
    ring_down(COULOMB);
}

/// The free ring-downs of `chatter_free_ring_down` under `friction`.
fn ring_down(friction: Friction) {
    for e in [0.5, 0.9] {
        let mut an = released_from_half_tilt(e);
        an.friction = friction;
        let rec = quiet_record(0.02, 10.0);
        let on = simulate(&an, &rec, &SolverSettings::default(), None).unwrap();
        let off = simulate(&an, &rec, &without_rule(), None).unwrap();
        assert!(off.flights > 500, "e = {e}: {} flights", off.flights);
        assert!(
            3 * on.flights <= off.flights,
            "e = {e}: {} flights with the rule against {}",
            on.flights,
            off.flights
        );
        assert_eq!(on.theta_max_over_theta_c, off.theta_max_over_theta_c);
        assert!((on.theta_max_over_theta_c - 0.5).abs() < 1e-12);
        assert!(!on.overturned && !on.uplifted && !off.uplifted);
        let rest = |o: &Outcome| o.time_in_mode[Mode::Rest.index()];
        assert!(
            (rest(&on) - rest(&off)).abs() < 1e-3 && rest(&off) > 0.0,
            "e = {e}: at rest {} s against {} s",
            rest(&on),
            rest(&off)
        );
        assert!(
            (on.slip_final - off.slip_final).abs() < 1e-6,
            "e = {e}: footprint {} against {}",
            on.slip_final,
            off.slip_final
        );
        assert_eq!(on.energy_gains, 0);
    }
}

/// One bounce series under a steady push (ẍg = 0.1 g, H/B 4, e = 0.9, from
/// θc/2): the first rock impact starts a series on the new corner, which the
/// rule closes; at the first sample after both runs are back in rock, θ and
/// θ̇ with the rule match every bounce followed to 3e-11 rad and 1e-10
/// rad/s. The push makes the corner drift, so the correction's carrying back
/// from the drift's centroid to the closing impact is exercised: measured
/// 4.4e-12 rad and 4.5e-13 rad/s; the correction applied at the impact with
/// the impact's ρ and θ̇, not carried back, errs by 8.6e-11 rad and 1.0e-8
/// rad/s.
#[test]
fn chatter_series_under_a_steady_push() {
    let an = released_from_half_tilt(0.9);
    let rec = common::reference::constant_record(0.1 * G, 0.01, 3.0);
    let (mut h_on, mut h_off) = (History::default(), History::default());
    simulate(&an, &rec, &SolverSettings::default(), Some(&mut h_on)).unwrap();
    simulate(&an, &rec, &without_rule(), Some(&mut h_off)).unwrap();
    let first_flight = h_off
        .rows
        .iter()
        .find(|r| r.mode == Mode::Flight)
        .unwrap()
        .t;
    let back_in_rock = |h: &History| {
        h.rows
            .iter()
            .find(|r| r.t > first_flight && r.mode == Mode::Rock)
            .unwrap()
            .t
    };
    let ts = back_in_rock(&h_on).max(back_in_rock(&h_off));
    let a = h_on.rows.iter().find(|r| !r.event && r.t > ts).unwrap();
    let b = h_off.rows.iter().find(|r| !r.event && r.t == a.t).unwrap();
    assert!(a.mode == Mode::Rock && b.mode == Mode::Rock);
    let (dth, dom) = ((a.theta - b.theta).abs(), (a.theta_dot - b.theta_dot).abs());
    assert!(
        dth < 3e-11 && dom < 1e-10,
        "t = {}: Δθ {dth:e}, Δθ̇ {dom:e}",
        a.t
    );
}

/// A strong ground pulse during the first bounce series (ẍg alternating
/// between ±0.2 g from sample to sample, 0.45–0.8 s; the series starts at the
/// rock impact at 0.494 s): the bounds on the corner's fall and on θ̈ fail,
/// so every bounce is followed while the pulse lasts. The histories with and
/// without the rule are identical, row for row, until the pulse ends; after
/// it the rule acts (fewer rows).
#[test]
fn chatter_falls_back_when_the_bounds_fail() {
    let (t_on, t_off) = (0.45, 0.8);
    let an = released_from_half_tilt(0.9);
    let dt = 0.01;
    let mut rec = quiet_record(dt, 3.0);
    for (k, a) in rec.acc.iter_mut().enumerate() {
        let t = k as f64 * dt;
        if t > t_on && t < t_off {
            *a = if k % 2 == 0 { 0.2 * G } else { -0.2 * G };
        }
    }
    let mut h_on = History::default();
    let mut h_off = History::default();
    simulate(&an, &rec, &SolverSettings::default(), Some(&mut h_on)).unwrap();
    simulate(&an, &rec, &without_rule(), Some(&mut h_off)).unwrap();
    let upto = |h: &History| -> Vec<HistoryRow> {
        h.rows.iter().filter(|r| r.t <= t_off).copied().collect()
    };
    let (a, b) = (upto(&h_on), upto(&h_off));
    let flights = b
        .iter()
        .filter(|r| r.event && r.mode == Mode::Flight && r.t > 0.5)
        .count();
    assert!(flights > 10, "{flights} flight rows in the pulse");
    let first = a.iter().zip(&b).position(|(x, y)| x != y);
    assert!(
        first.is_none() && a.len() == b.len(),
        "histories differ from row {first:?} (t = {:?})",
        first.map(|i| a[i].t)
    );
    assert!(h_on.rows.len() < h_off.rows.len());
}

/// Ensembles with horizontal, and horizontal and vertical ground motion
/// (ÿg = 0.5·ẍg of another record), e = 0.3, 0.6, 0.9, H/B 4 and 6, 10
/// records each at 0.6 g: the rule against every bounce followed, and, for
/// scale, Taylor against Dormand–Prince (both following every bounce).
/// The rule must flip no more overturning outcomes than the integrators do
/// (plus one, for a count this small), keep θmax/θc within 1e-3 in at least
/// 95 % of the runs where neither overturns, and remove at least 3 flights in
/// 4. Measured: 53,223 flights against 322,761; θmax/θc within 1e-3 in 67
/// of 69; no flip (nor between the integrators).
#[test]
fn chatter_ensembles() {
    ensembles(Friction::Infinite);
}

/// The same ensembles under Coulomb friction (μs = 0.7, μk = 0.6), to the
/// same bars: where a series' impacts or the rock under it might slip the
/// rules stand aside, elsewhere they close the series and settle the
/// cascades as under infinite friction. Measured: 53,156 flights against
/// 323,090; θmax/θc within 1e-3 in 67 of 69; no flip (nor between the
/// integrators).
#[test]
fn chatter_ensembles_under_coulomb_friction() {
    ensembles(COULOMB);
}

/// The ensembles of `chatter_ensembles` under `friction`.
fn ensembles(friction: Friction) {
    let mut syn = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let dopri = SolverSettings {
        integrator: Integrator::Dopri5,
        ..without_rule()
    };
    let (mut flights_on, mut flights_off, mut close, mut compared) = (0, 0, 0, 0);
    let (mut flips, mut flips_integrators) = (0, 0);
    for vertical in [false, true] {
        for i in 0..10 {
            let mut rec = syn.generate(47, i, 0.6 * G).unwrap();
            if vertical {
                let other = syn.generate(47, i + 100, 0.6 * G).unwrap();
                rec.acc_v = Some(other.acc.iter().map(|a| 0.5 * a).collect());
            }
            for e in [0.3, 0.6, 0.9] {
                for aspect in [4.0, 6.0] {
                    let mut an = Analysis::new(Block::new(0.5, aspect, G).unwrap(), e);
                    an.friction = friction;
                    let on = simulate(&an, &rec, &SolverSettings::default(), None).unwrap();
                    let off = simulate(&an, &rec, &without_rule(), None).unwrap();
                    let alt = simulate(&an, &rec, &dopri, None).unwrap();
                    flights_on += on.flights;
                    flights_off += off.flights;
                    flips += (on.overturned != off.overturned) as usize;
                    flips_integrators += (alt.overturned != off.overturned) as usize;
                    if !on.overturned && !off.overturned {
                        compared += 1;
                        close += ((on.theta_max_over_theta_c - off.theta_max_over_theta_c).abs()
                            < 1e-3) as usize;
                    }
                }
            }
        }
    }
    let summary = format!(
        "flights {flights_on} with the rule against {flights_off}; θmax within 1e-3 in {close} \
         of {compared}; overturning flips {flips} (integrators {flips_integrators}) of 120"
    );
    assert!(4 * flights_on <= flights_off, "{summary}");
    assert!(100 * close >= 95 * compared, "{summary}");
    assert!(flips <= flips_integrators + 1, "{summary}");
}
