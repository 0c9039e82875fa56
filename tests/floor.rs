//! The floor filter (issue 32): a linear building's floor motion from the
//! ground record by the Nigam–Jennings recurrence. Each test opens with the
//! physical fact it checks and why its tolerance is what it is.
//!
//! Run with `--nocapture` to see the measured errors.

use std::f64::consts::TAU;

use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use realfft::num_complex::Complex;
use rockfrag::Error;
use rockfrag::motion::{
    Floor, Mode, Oscillator, OscillatorState, Record, floor_into, floor_record,
};

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0_f64, |m, v| m.max(v.abs()))
}

/// max |x − y| / max |y|
fn rel_to_peak(x: &[f64], y: &[f64]) -> f64 {
    assert_eq!(x.len(), y.len());
    let d = x
        .iter()
        .zip(y)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    d / max_abs(y)
}

/// A ground record a_k = sin(2π k/n_per), `periods` whole periods long (the
/// phase reduced exactly to one period, so every period has the same samples).
fn sine(n_per: usize, periods: usize, dt: f64) -> Record {
    let acc = (0..n_per * periods + 1)
        .map(|k| (TAU * ((k % n_per) as f64 / n_per as f64)).sin())
        .collect();
    Record::from_acc("sine", dt, acc).unwrap()
}

/// Least-squares fit of y_k ≈ c₁ sin(2πk/n) + c₂ cos(2πk/n) over the last
/// `window` whole periods of `y` (n samples each). On whole periods of a
/// uniform grid sin and cos are exactly orthogonal (and orthogonal to a
/// constant), so the fit is the projection c = (2/M) Σ y·(sin, cos), exact
/// up to rounding: the sampling does not limit it. The recurrence is a
/// linear time-invariant map of the sample sequence, so in steady state its
/// output samples are exactly a sinusoid of the input's frequency.
fn fit(y: &[f64], n: usize, window: usize) -> Complex<f64> {
    let m = n * window;
    let start = y.len() - 1 - m; // the record holds whole periods plus one sample
    assert_eq!(start % n, 0);
    let (mut s, mut c) = (0.0, 0.0);
    for (k, v) in y[start..start + m].iter().enumerate() {
        let (sn, cs) = (TAU * ((k % n) as f64 / n as f64)).sin_cos();
        s += v * sn;
        c += v * cs;
    }
    Complex::new(2.0 * s / m as f64, 2.0 * c / m as f64)
}

/// Whole input periods for the oscillator's transient to fall below
/// `residue` of the response: e^{−ζωt}·(1/2ζ) < residue (1/2ζ bounds the
/// transient's amplitude relative to the input's, at resonance).
fn settling_periods(zeta: f64, r: f64, residue: f64) -> usize {
    // t in oscillator periods (T = 1): ζ·2π·t = ln(1/(2ζ·residue))
    let t = (1.0 / (2.0 * zeta * residue)).ln() / (zeta * TAU);
    (t * r).ceil() as usize
}

#[test]
fn steady_state_absolute_acceleration_follows_the_closed_form_transmissibility() {
    // A long sine ground acceleration of frequency Ω = rω (oscillator T = 1 s,
    // Γφ = 1): in steady state the floor's absolute acceleration has the
    // amplitude TR(r) = sqrt((1 + (2ζr)²)/((1 − r²)² + (2ζr)²)) times the
    // ground's. The record is a sampled sine taken linear between samples,
    // not a sine: its harmonic at Ω is smaller by sinc²(ΩΔt/2) ≈ 1 − δ with
    // δ = (ΩΔt)²/12, and the aliases fold back at the samples, so the
    // measured ratio is TR·(1 − O(δ)). With 8000 samples a period δ = 5e-8,
    // 20 times below the tolerance of 1e-6. The amplitude is fitted
    // over the last 20 whole periods (see `fit`), after the transient has
    // decayed below 1e-9.
    let n_per = 8000;
    let mut worst = 0.0_f64;
    for zeta in [0.02, 0.05] {
        for r in [0.5, 1.0, 2.0] {
            let t_in = 1.0 / r;
            let dt = t_in / n_per as f64;
            let periods = settling_periods(zeta, r, 1e-9) + 20;
            let ground = sine(n_per, periods, dt);
            let floor = floor_record(&ground, &Floor::one_mode(1.0, zeta, 1.0)).unwrap();
            let input = fit(&ground.acc, n_per, 20).norm();
            let output = fit(&floor.acc, n_per, 20).norm();
            let two_zr = 2.0 * zeta * r;
            let tr = ((1.0 + two_zr * two_zr) / ((1.0 - r * r).powi(2) + two_zr * two_zr)).sqrt();
            let err = (output / input - tr).abs() / tr;
            eprintln!(
                "ζ = {zeta}, r = {r}: TR = {tr:.9}, measured {:.9}, relative error {err:.2e} \
                 ({} samples)",
                output / input,
                ground.len()
            );
            assert!(err < 1e-6, "ζ {zeta} r {r}: relative error {err:e}");
            worst = worst.max(err);
        }
    }
    eprintln!("worst relative error {worst:.2e}");
}

#[test]
fn the_recurrence_is_exact_for_piecewise_linear_ground_acceleration() {
    // The recurrence is not a discretisation: for a ground acceleration that
    // is linear between samples it is the exact response, at any Δt. A sampled
    // sine interpolated linearly is the sum of the lines Ω_m = Ω + 2πm/Δt
    // with weights K_m = sinc²(Ω_m Δt/2) (the triangle kernel's spectrum,
    // Σ K_m = 1), and at the samples all lines fall on the phase of Ω, so the
    // steady-state complex amplitude of the absolute acceleration is
    // exactly H = Σ_m K_m TR(iΩ_m), TR(iν) = (ω² + 2iζων)/(ω² − ν² + 2iζων).
    // Coarse sampling (4 and 16 samples a period, w = ωΔt from 0.004 to 3.1:
    // both ways of computing the coefficients), where H is far from TR(iΩ).
    // r = 100 is a flexible building whose floor moves 1e-3 as much as the
    // ground: the floor's acceleration keeps its relative precision.
    // Tolerance 1e-10 of |H|: the sum is taken over |m| ≤ 20000 (pairs ±m
    // cancel to O(1/m⁴): tail below 1e-13), the transient decays below 1e-11
    // before the 20 fitted periods.
    let omega = TAU;
    let mut worst = 0.0_f64;
    for n_per in [4, 16] {
        for zeta in [0.02, 0.05] {
            for r in [0.5, 1.0, 2.0, 100.0] {
                let big_omega = r * omega;
                let dt = (TAU / big_omega) / n_per as f64;
                let tr = |nu: f64| {
                    let num = Complex::new(omega * omega, 2.0 * zeta * omega * nu);
                    num / Complex::new(omega * omega - nu * nu, 2.0 * zeta * omega * nu)
                };
                let sinc2 = |x: f64| if x == 0.0 { 1.0 } else { (x.sin() / x).powi(2) };
                let mut h = Complex::new(0.0, 0.0);
                for m in (1..=20_000_i64).rev() {
                    for mm in [m, -m] {
                        let nu = big_omega + mm as f64 * TAU / dt;
                        h += tr(nu) * sinc2(nu * dt / 2.0);
                    }
                }
                h += tr(big_omega) * sinc2(big_omega * dt / 2.0);
                let periods = settling_periods(zeta, r, 1e-11) + 20;
                let ground = sine(n_per, periods, dt);
                let floor = floor_record(&ground, &Floor::one_mode(1.0, zeta, 1.0)).unwrap();
                let measured = fit(&floor.acc, n_per, 20);
                let err = (measured - h).norm() / h.norm();
                eprintln!(
                    "{n_per} samples/period, ζ = {zeta}, r = {r}, w = {:.3}: |H| = {:.6} \
                     (TR = {:.6}), error {err:.1e}",
                    omega * dt,
                    h.norm(),
                    tr(big_omega).norm()
                );
                assert!(err < 1e-10, "n {n_per} ζ {zeta} r {r}: {measured} vs {h}");
                worst = worst.max(err);
            }
        }
    }
    eprintln!("worst relative error {worst:.2e}");
}

/// One oscillator's (u, u̇) at the samples by classical RK4 with `sub`
/// steps per sample, the ground acceleration linear within each sample
/// interval (the same forcing as the recurrence's).
fn rk4(acc: &[f64], dt: f64, period: f64, zeta: f64, sub: usize) -> Vec<(f64, f64)> {
    let omega = TAU / period;
    let h = dt / sub as f64;
    let f = |u: f64, v: f64, a: f64| (v, -a - 2.0 * zeta * omega * v - omega * omega * u);
    let (mut u, mut v) = (0.0, 0.0);
    let mut out = vec![(u, v)];
    for pair in acc.windows(2) {
        let ag = |tau: f64| pair[0] + (pair[1] - pair[0]) * (tau / dt);
        for j in 0..sub {
            let t0 = j as f64 * h;
            let (a0, am, a1) = (ag(t0), ag(t0 + h / 2.0), ag(t0 + h));
            let k1 = f(u, v, a0);
            let k2 = f(u + h / 2.0 * k1.0, v + h / 2.0 * k1.1, am);
            let k3 = f(u + h / 2.0 * k2.0, v + h / 2.0 * k2.1, am);
            let k4 = f(u + h * k3.0, v + h * k3.1, a1);
            u += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            v += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        }
        out.push((u, v));
    }
    out
}

#[test]
fn the_floor_matches_a_fine_step_integration_on_a_random_record() {
    // A 30-s record of uniform random accelerations in ±1 m/s² (Δt = 0.01 s,
    // linear between samples) through four modes: long (T = 3 s) and short
    // (T = 0.05 s, w = ωΔt = 1.26, the closed-form coefficients), undamped
    // (ζ = 0, no decay: phase errors accumulate over the whole record) and
    // damped, positive and negative participations. The reference is RK4
    // with ωh ≤ 5e-4 on the same forcing: its phase error over ωt ≤ 3800 rad
    // is ~ωt(ωh)⁴/120 ≈ 2e-12, and doubling its step changes it by < 1e-10
    // of the peak (checked: 16 times its own error). Floor acceleration,
    // velocity and displacement and each mode's (u, u̇) agree to 1e-9 of
    // their peaks, the tolerance; rounding in either method is
    // ~1e-13.
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(32);
    let dt = 0.01;
    let acc: Vec<f64> = (0..3001).map(|_| 2.0 * rng.random::<f64>() - 1.0).collect();
    let ground = Record::from_acc("noise", dt, acc).unwrap();
    let modes = [
        (0.8, 0.05, 1.3),
        (0.25, 0.02, -0.4),
        (0.05, 0.0, 0.1),
        (3.0, 0.1, 0.2),
    ];
    let floor = Floor {
        modes: modes
            .iter()
            .map(|&(period, damping, participation)| Mode {
                period,
                damping,
                participation,
            })
            .collect(),
    };
    let got = floor_record(&ground, &floor).unwrap();
    let n = ground.len();
    let mut want_acc = ground.acc.clone();
    let mut want_vel = ground.vel.clone();
    let mut want_disp = ground.disp.clone();
    let mut worst = 0.0_f64;
    for &(period, zeta, gamma) in &modes {
        let omega = TAU / period;
        let sub = 2 * ((omega * dt / 1e-3).ceil() as usize).max(10);
        let reference = rk4(&ground.acc, dt, period, zeta, sub);
        let coarser = rk4(&ground.acc, dt, period, zeta, sub / 2);
        let (ru, rv): (Vec<f64>, Vec<f64>) = reference.iter().copied().unzip();
        let (cu, cv): (Vec<f64>, Vec<f64>) = coarser.iter().copied().unzip();
        let self_err = rel_to_peak(&cu, &ru).max(rel_to_peak(&cv, &rv));
        assert!(
            self_err < 1e-10,
            "T {period}: RK4 step halving changes {self_err:e}"
        );
        // the recurrence, mode by mode
        let osc = Oscillator::new(period, zeta, dt).unwrap();
        let mut s = OscillatorState::default();
        let (mut u, mut v) = (vec![0.0], vec![0.0]);
        for pair in ground.acc.windows(2) {
            s = osc.step(s, pair[0], pair[1]);
            u.push(s.disp);
            v.push(s.vel);
        }
        let (eu, ev) = (rel_to_peak(&u, &ru), rel_to_peak(&v, &rv));
        eprintln!(
            "T = {period}, ζ = {zeta}: w = {:.3}, RK4 {sub} steps/sample (self {self_err:.1e}); \
             u {eu:.1e}, u̇ {ev:.1e}",
            omega * dt
        );
        assert!(eu < 1e-9 && ev < 1e-9, "T {period}: u {eu:e}, u̇ {ev:e}");
        worst = worst.max(eu).max(ev);
        for k in 0..n {
            let rel_acc = -ground.acc[k] - 2.0 * zeta * omega * rv[k] - omega * omega * ru[k];
            want_acc[k] += gamma * rel_acc;
            want_vel[k] += gamma * rv[k];
            want_disp[k] += gamma * ru[k];
        }
    }
    let ea = rel_to_peak(&got.acc, &want_acc);
    let ev = rel_to_peak(&got.vel, &want_vel);
    let ed = rel_to_peak(&got.disp, &want_disp);
    eprintln!("floor: acc {ea:.1e}, vel {ev:.1e}, disp {ed:.1e} (relative to peak)");
    assert!(ea < 1e-9 && ev < 1e-9 && ed < 1e-9);
    eprintln!("worst relative error {:.2e}", worst.max(ea).max(ev).max(ed));
}

fn ground_with_signed_zeros() -> Record {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    let mut acc: Vec<f64> = (0..500).map(|_| rng.random::<f64>() - 0.5).collect();
    acc[0] = -0.0;
    acc[10] = 0.0;
    acc[11] = -0.0;
    let mut r = Record::from_acc("signed zeros", 0.005, acc).unwrap();
    r.acc_v = Some(vec![0.25; r.len()]);
    r
}

#[test]
fn zero_participation_gives_the_ground_record_bit_for_bit() {
    // No mode, or only modes with Γφ = 0: the floor is the ground, the same
    // bits (also negative zeros, the name, Δt and the vertical component).
    let ground = ground_with_signed_zeros();
    let zero = Mode {
        period: 0.8,
        damping: 0.05,
        participation: 0.0,
    };
    for floor in [
        Floor::ground(),
        Floor::one_mode(0.8, 0.05, 0.0),
        Floor::one_mode(0.8, 0.05, -0.0),
        Floor {
            modes: vec![zero; 3],
        },
    ] {
        assert!(floor.is_ground());
        let got = floor_record(&ground, &floor).unwrap();
        assert_eq!(got, ground);
        for (a, b) in got.acc.iter().zip(&ground.acc) {
            assert_eq!(a.to_bits(), b.to_bits());
        }
    }
    // a zero-participation mode beside others changes nothing either
    let roof = Floor::one_mode(0.6, 0.05, 1.3);
    let mut with_zero = roof.clone();
    with_zero.modes.insert(0, zero);
    with_zero.modes.push(zero);
    assert!(!with_zero.is_ground());
    assert_eq!(
        floor_record(&ground, &with_zero).unwrap(),
        floor_record(&ground, &roof).unwrap()
    );
}

#[test]
fn the_floor_keeps_the_grounds_name_step_and_vertical_and_reuses_buffers() {
    // floor_into writes the same record as floor_record whatever `out` held;
    // on an error it leaves `out` as it was.
    let ground = ground_with_signed_zeros();
    let floor = Floor {
        modes: vec![
            Mode {
                period: 0.9,
                damping: 0.05,
                participation: 1.25,
            },
            Mode {
                period: 0.3,
                damping: 0.05,
                participation: -0.3,
            },
        ],
    };
    let want = floor_record(&ground, &floor).unwrap();
    assert_eq!((want.name.as_str(), want.dt), ("signed zeros", 0.005));
    assert_eq!(want.acc_v, ground.acc_v);
    assert_ne!(want.acc, ground.acc);
    let mut out = sine(10, 100, 0.1);
    floor_into(&ground, &floor, &mut out).unwrap();
    assert_eq!(out, want);
    let before = out.clone();
    let bad = Floor::one_mode(0.9, 1.0, 1.0);
    assert!(floor_into(&ground, &bad, &mut out).is_err());
    assert_eq!(out, before);
}

fn message(e: Error) -> String {
    e.to_string()
}

#[test]
fn bad_periods_and_dampings_are_refused_with_the_field_named() {
    // T ≤ 0 or not finite, ζ outside [0, 1) (ζ ≥ 1 is not an underdamped
    // mode: the recurrence's sin(ω√(1−ζ²)Δt)/√(1−ζ²) has no meaning there),
    // a non-finite participation, and a bad Δt for the oscillator.
    let ground = ground_with_signed_zeros();
    for (period, damping, participation, field) in [
        (0.0, 0.05, 1.0, "floor[0].period"),
        (-1.0, 0.05, 1.0, "floor[0].period"),
        (f64::NAN, 0.05, 1.0, "floor[0].period"),
        (f64::INFINITY, 0.05, 1.0, "floor[0].period"),
        (1e-320, 0.05, 1.0, "floor[0].period"),
        (1.0, 1.0, 1.0, "floor[0].damping"),
        (1.0, 2.0, 1.0, "floor[0].damping"),
        (1.0, -0.01, 1.0, "floor[0].damping"),
        (1.0, f64::NAN, 1.0, "floor[0].damping"),
        (1.0, 0.05, f64::NAN, "floor[0].participation"),
        (1.0, 0.05, f64::INFINITY, "floor[0].participation"),
    ] {
        let floor = Floor::one_mode(period, damping, participation);
        let err = message(floor_record(&ground, &floor).unwrap_err());
        assert!(err.contains(field), "{err}");
        assert!(floor.validate().is_err());
    }
    // a bad mode is refused even with zero participation: it is a typo
    assert!(floor_record(&ground, &Floor::one_mode(-1.0, 0.05, 0.0)).is_err());
    // the second mode is named as such
    let mut two = Floor::one_mode(1.0, 0.05, 1.0);
    two.modes.push(Mode {
        period: 0.3,
        damping: 1.5,
        participation: 0.2,
    });
    assert!(message(two.validate().unwrap_err()).contains("floor[1].damping"));
    for (period, damping, dt, field) in [
        (0.0, 0.05, 0.01, "period"),
        (1.0, 1.0, 0.01, "damping"),
        (1.0, 0.05, 0.0, "dt"),
        (1.0, 0.05, f64::NAN, "dt"),
    ] {
        let err = message(Oscillator::new(period, damping, dt).unwrap_err());
        assert!(err.starts_with(&format!("invalid {field} = ")), "{err}");
    }
    // ζ = 0 (undamped) is accepted, and so is ζ just below 1
    assert!(Oscillator::new(1.0, 0.0, 0.01).is_ok());
    assert!(Oscillator::new(1.0, 1.0 - 1e-12, 0.01).is_ok());
}
