//! Finite Coulomb friction (issue 4): sliding, slide-rock, stick–slip and
//! frictional impacts. Each test states the fact it checks and its tolerance.

use rockfrag::motion::{G_STANDARD as G, Record, SynthesisSettings, Synthesizer};
use rockfrag::outcome::{Mode, Outcome};
use rockfrag::solver::{Analysis, Block, Friction, History, ImpactLaw, SolverSettings, simulate};

fn records(seed: u64, n: u64, pga_g: f64) -> Vec<Record> {
    let mut syn = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    (0..n)
        .map(|i| syn.generate(seed, i, pga_g * G).unwrap())
        .collect()
}

fn coulomb(aspect: f64, e: f64, mu_s: f64, mu_k: f64) -> Analysis {
    let mut an = Analysis::new(Block::new(0.5, aspect, G).unwrap(), e);
    an.friction = Friction::Coulomb { mu_s, mu_k };
    an
}

fn time_in(o: &Outcome, m: Mode) -> f64 {
    o.time_in_mode[m.index()]
}

/// Check 1: a rigid block with μs < B/H under an acceleration pulse a > μk g
/// slides and never rocks, and its total slip is the closed form. A
/// piecewise-linear record cannot jump, so the pulse is a for t ≤ t_d and
/// ramps to 0 over one sample h; its exact slip is
/// S = (a−μk g)t_d²/2 + [u₁h + (a−μk g)h²/2 − a h²/6] + u₂²/(2μk g), with
/// u₁ = (a−μk g)t_d and u₂ = u₁ + (a−μk g)h − a h/2. Tolerance 1e-8 relative.
/// As h → 0 this is the (a−μk g)t_d²/2 + ((a−μk g)t_d)²/(2μk g),
/// and the gap shrinks in proportion to h (checked over h = 1e-2 … 1e-4).
#[test]
fn sliding_pulse_slip_matches_closed_form() {
    let (mu, a, t_d) = (0.3, 0.5 * G, 0.5);
    let formula = (a - mu * G) * t_d * t_d / 2.0 + ((a - mu * G) * t_d).powi(2) / (2.0 * mu * G);
    let mut gaps = vec![];
    for h in [1e-2, 1e-3, 1e-4] {
        let k = (t_d / h).round() as usize;
        let n = k + (3.0 / h) as usize;
        let acc: Vec<f64> = (0..n).map(|i| if i <= k { a } else { 0.0 }).collect();
        let rec = Record::from_acc("pulse", h, acc).unwrap();
        let o = simulate(
            &coulomb(2.0, 0.0, mu, mu),
            &rec,
            &SolverSettings::default(),
            None,
        )
        .unwrap();
        assert_eq!(
            time_in(&o, Mode::Rock) + time_in(&o, Mode::SlideRock) + time_in(&o, Mode::Flight),
            0.0
        );
        let u1 = (a - mu * G) * t_d;
        let u2 = u1 + (a - mu * G) * h - a * h / 2.0;
        let exact = (a - mu * G) * t_d * t_d / 2.0 + u1 * h + (a - mu * G) * h * h / 2.0
            - a * h * h / 6.0
            + u2 * u2 / (2.0 * mu * G);
        // the block slides backwards (opposite to the ground's acceleration)
        assert!(o.slip_final < 0.0);
        let slip = -o.slip_final;
        assert!(
            ((slip - exact) / exact).abs() < 1e-8,
            "h {h}: {slip} vs {exact}"
        );
        assert!((o.slip_max - slip).abs() < 1e-12);
        gaps.push(((slip - formula) / formula).abs());
    }
    assert!(
        gaps[1] < gaps[0] / 5.0 && gaps[2] < gaps[1] / 5.0,
        "{gaps:?}"
    );
}

/// Check 1b: frictionless ground (μs = μk = 0): the block stays put in space,
/// so its slip relative to the ground is exactly −(xg(t) − xg(0) − ẋg(0)t)
/// (the ground's own displacement; the block starts with the ground's
/// velocity). The slide mode is integrated in closed form: 1e-9 relative.
#[test]
fn frictionless_block_stays_put_in_space() {
    for rec in records(21, 3, 0.5) {
        let o = simulate(
            &coulomb(4.0, 0.0, 0.0, 0.0),
            &rec,
            &SolverSettings::default(),
            None,
        )
        .unwrap();
        let n = rec.len() - 1;
        let expected = -(rec.disp[n] - rec.disp[0] - rec.vel[0] * rec.duration());
        assert!(
            ((o.slip_final - expected) / expected).abs() < 1e-9,
            "{} vs {expected}",
            o.slip_final
        );
        assert_eq!(time_in(&o, Mode::Rock), 0.0);
    }
}

/// Check 2: with μs = μk = 100 the finite-friction solver reproduces the
/// infinite-friction results on 25 records to 1e-6 (overturning, θmax,
/// μ_mot) — wherever the infinite-friction demand stayed below 100. Where the
/// demand exceeded 100 (F/N → ∞ as N → 0 near lift-off or overturning, also
/// between the step ends where μ_mot is sampled), the finite-friction block
/// must slip there, and the overturning outcome agrees.
#[test]
fn very_high_friction_reproduces_infinite_friction() {
    let mut compared = 0;
    for (aspect, pga) in [(4.0, 0.6), (2.0, 0.9)] {
        for rec in records(2, 25, pga) {
            let inf = simulate(
                &Analysis::new(Block::new(0.5, aspect, G).unwrap(), 0.0),
                &rec,
                &SolverSettings::default(),
                None,
            )
            .unwrap();
            let fin = simulate(
                &coulomb(aspect, 0.0, 100.0, 100.0),
                &rec,
                &SolverSettings::default(),
                None,
            )
            .unwrap();
            assert_eq!(inf.overturned, fin.overturned, "{}", rec.name);
            // μ_mot is sampled at step ends, and just before overturning
            // F/N → ∞ between samples: the finite-friction run may meet μ = 100
            // there while the sampled demand is lower (92.7 for seed 2, index 2)
            let slipped = time_in(&fin, Mode::SlideRock) > 0.0 || fin.stick_holds > 0;
            let steep = inf.overturned || inf.uplifted;
            if inf.mu_motion < 100.0 && inf.mu_impact < 100.0 && !(slipped && steep) {
                let rel = |a: f64, b: f64| (a - b).abs() / a.abs().max(1e-300);
                assert!(
                    rel(inf.theta_max_over_theta_c, fin.theta_max_over_theta_c) < 1e-6,
                    "{}",
                    rec.name
                );
                assert!(rel(inf.mu_motion, fin.mu_motion) < 1e-6, "{}", rec.name);
                assert!(fin.slip_max < 1e-12, "slip {} m", fin.slip_max); // rounding only
                compared += 1;
            } else {
                assert!(
                    time_in(&fin, Mode::SlideRock) > 0.0 || fin.stick_holds > 0,
                    "{}",
                    rec.name
                );
            }
        }
    }
    assert!(compared >= 40, "only {compared} of 50 runs compared");
}

/// Check 3: energy. Through every impact kinetic energy never increases (the
/// energetic law for sticking impacts, Stronge's for slipping ones: no gains
/// counted); between events the energy changes by the ground's work minus the
/// friction's, checked by the audit to 1e-7 of the run's energy scale.
#[test]
fn friction_never_adds_energy() {
    let set = SolverSettings {
        audit_energy: true,
        impact: ImpactLaw::Energetic,
        ..SolverSettings::default()
    };
    for rec in records(23, 6, 0.9) {
        for aspect in [2.0, 4.0] {
            for (e, mu_s, mu_k) in [(0.0, 0.7, 0.6), (0.6, 0.5, 0.4), (0.9, 0.3, 0.3)] {
                let o = simulate(&coulomb(aspect, e, mu_s, mu_k), &rec, &set, None).unwrap();
                assert_eq!(o.energy_gains, 0, "{} H/B {aspect} e {e}", rec.name);
                let r = o.energy_residual.unwrap();
                assert!(
                    r < 1e-7,
                    "{} H/B {aspect} e {e} μ {mu_s}: residual {r:e}",
                    rec.name
                );
            }
        }
    }
}

/// Check 4: stick–slip chatter. A sinusoidal ground acceleration whose peak is
/// just above μs g (by 0.1 %) makes the block slip briefly twice per cycle.
/// The run must finish, and every transition must be exactly where Coulomb's
/// law puts it: each rest → slide where |ẍg| crosses μs g (to 1e-9 relative,
/// so none is missed or late), each slide → rest with zero slip velocity and
/// |ẍg| ≤ μs g. The count must be two per cycle.
#[test]
fn stick_slip_chatter_is_resolved_exactly() {
    let (mu_s, mu_k) = (0.3, 0.25);
    let (amp, f, dt) = (1.001 * mu_s * G, 2.0, 0.005);
    let acc: Vec<f64> = (0..=2000)
        .map(|k| amp * (2.0 * std::f64::consts::PI * f * k as f64 * dt).sin())
        .collect();
    let rec = Record::from_acc("sine", dt, acc).unwrap();
    let mut hist = History::default();
    let o = simulate(
        &coulomb(2.0, 0.0, mu_s, mu_k),
        &rec,
        &SolverSettings::default(),
        Some(&mut hist),
    )
    .unwrap();
    assert_eq!(o.end_time, 10.0);
    let ax_at = |t: f64| {
        let k = ((t / dt) as usize).min(rec.len() - 2);
        let w = (t - k as f64 * dt) / dt;
        rec.acc[k] * (1.0 - w) + rec.acc[k + 1] * w
    };
    let rows = &hist.rows;
    let (mut starts, mut stops) = (0, 0);
    for w in rows.windows(2) {
        if w[0].t == w[1].t && w[0].mode == Mode::Rest && w[1].mode == Mode::Slide {
            starts += 1;
            let r = (ax_at(w[0].t).abs() - mu_s * G) / (mu_s * G);
            assert!(r.abs() < 1e-9, "slide started at |ẍg|/μs g − 1 = {r:e}");
        }
        if w[0].t == w[1].t && w[0].mode == Mode::Slide && w[1].mode == Mode::Rest {
            stops += 1;
            assert_eq!(w[0].x_dot, 0.0);
            assert!(ax_at(w[0].t).abs() <= mu_s * G);
        }
    }
    assert_eq!(
        o.transitions[Mode::Rest.index()][Mode::Slide.index()],
        starts
    );
    // 20 cycles: 2 slips per cycle (the first half-cycle starts at rest)
    assert!((38..=40).contains(&starts), "{starts} slips");
    assert!(stops >= starts - 1);
    assert!(o.slip_max > 0.0 && o.slip_max < 1e-3, "slip {}", o.slip_max);
}

/// Check 5: H/B = 2 (B/H = 0.5), PGA 0.6 g. With μs = μk = 0.4 < B/H the
/// block slides and never rocks (Shenton 1996); with μs = 0.8 > B/H it rocks.
/// Slide-rock: H/B = 4 with μs = μk = 0.3 rocks from rest (0.3 > B/H = 0.25),
/// but rocking at 0.9 g needs |F|/N ≈ 0.35 (the paper's Table 2, μ_mot), more
/// than 0.3: the pivot slips, so slide-rock appears.
#[test]
fn slide_rock_and_slide_regimes() {
    let recs = records(25, 10, 0.6);
    for rec in &recs {
        let low = simulate(
            &coulomb(2.0, 0.0, 0.4, 0.4),
            rec,
            &SolverSettings::default(),
            None,
        )
        .unwrap();
        assert!(
            time_in(&low, Mode::Slide) > 0.0 && low.slip_max > 0.0,
            "{}",
            rec.name
        );
        assert_eq!(
            time_in(&low, Mode::Rock) + time_in(&low, Mode::SlideRock),
            0.0,
            "{}",
            rec.name
        );
    }
    let rocked = recs
        .iter()
        .filter(|rec| {
            let high = simulate(
                &coulomb(2.0, 0.0, 0.8, 0.8),
                rec,
                &SolverSettings::default(),
                None,
            )
            .unwrap();
            assert_eq!(time_in(&high, Mode::Slide), 0.0);
            time_in(&high, Mode::Rock) > 0.0
        })
        .count();
    assert!(rocked >= 8, "only {rocked} of 10 rocked with μs = 0.8");
    let slide_rock = records(26, 10, 0.9)
        .iter()
        .filter(|rec| {
            let o = simulate(
                &coulomb(4.0, 0.0, 0.3, 0.3),
                rec,
                &SolverSettings::default(),
                None,
            )
            .unwrap();
            time_in(&o, Mode::SlideRock) > 0.0
        })
        .count();
    assert!(
        slide_rock >= 5,
        "slide-rock in only {slide_rock} of 10 runs"
    );
}

/// Check 6: hard cases finish with finite numbers: ice (μk → 0), μs = B/H
/// exactly (the documented tie: the block slides), and e = 0.9 with μ = 0.3.
#[test]
fn friction_hard_cases_finish() {
    let set = SolverSettings::default();
    for rec in records(27, 3, 1.2) {
        for an in [
            coulomb(4.0, 0.0, 0.05, 1e-6),
            coulomb(2.0, 0.0, 0.5, 0.5),
            coulomb(4.0, 0.9, 0.3, 0.3),
            coulomb(2.0, 0.9, 0.3, 0.3),
        ] {
            let o = simulate(&an, &rec, &set, None).unwrap();
            assert!(
                o.theta_max_over_theta_c.is_finite() && o.slip_max.is_finite(),
                "{o:?}"
            );
            let total: f64 = o.time_in_mode.iter().sum();
            assert!((total - o.end_time).abs() < 1e-9 * o.end_time.max(1.0));
        }
        // μs = B/H exactly: the tie slides (no rocking from rest)
        let tie = simulate(&coulomb(2.0, 0.0, 0.5, 0.5), &rec, &set, None).unwrap();
        assert!(time_in(&tie, Mode::Slide) > 0.0);
        assert_eq!(tie.transitions[Mode::Rest.index()][Mode::Rock.index()], 0);
    }
}
