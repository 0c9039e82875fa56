//! The spectral intensity measures against closed forms and an independent
//! integration: `sa(T)` of a resonant sine is its steady-state amplitude,
//! `sa(T → 0)` is the PGA, and on a random record the exact recurrence
//! agrees with a fine Runge–Kutta integration of the same piecewise-linear
//! ground acceleration.

use rockfrag::im::{Felt, Im, SA_DAMPING, spectral_acceleration};
use rockfrag::motion::Record;

/// A sine ground acceleration a₀ sin ωt at the oscillator's own frequency
/// drives it, after the transient (e^{−ζωt} < 1e-13 after 100 periods), to
/// the resonant amplitude u = a₀/(2ζω²), so Sa = ω²u = a₀/(2ζ) = 10 a₀.
/// The record samples the sine T/4000 apart: the piecewise-linear forcing
/// and the peak read at the samples differ from the sine's by (ωΔt)²/8 ≈
/// 3e-7 relative, under the 1e-6 asked.
#[test]
fn resonant_sine_gives_the_steady_state_amplitude() {
    for period in [0.2, 1.0, 3.0] {
        let a0 = 2.5;
        let dt = period / 4000.0;
        let n = 4000 * 120;
        let w = std::f64::consts::TAU / period;
        let acc: Vec<f64> = (0..=n).map(|k| a0 * (w * k as f64 * dt).sin()).collect();
        let r = Record::from_acc("sine", dt, acc).unwrap();
        let sa = spectral_acceleration(&r, period).unwrap();
        let want = a0 / (2.0 * SA_DAMPING);
        assert!(
            (sa / want - 1.0).abs() < 1e-6,
            "T = {period}: Sa {sa}, steady state {want}"
        );
    }
}

/// A random record (a fixed LCG, 0.01 s samples, 20 s).
fn random_record() -> Record {
    let mut x = 0x2545_f491_4f6c_dd1d_u64;
    let acc: Vec<f64> = (0..2001)
        .map(|_| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((x >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 6.0
        })
        .collect();
    Record::from_acc("random", 0.01, acc).unwrap()
}

/// A stiff oscillator moves with the ground: u ≈ −ẍg/ω², the first
/// correction 2ζ/ω times the jerk, which for T = 1e-7 s and a jerk of at
/// most 600 m/s³ against a PGA of about 3 m/s² is below 4e-7 of
/// the PGA; so Sa(T → 0) = PGA within 1e-6. (At the shortest period a
/// name takes, 0.01 s, the same record gives Sa within 1 % of PGA.)
#[test]
fn a_very_stiff_oscillator_gives_the_pga() {
    let r = random_record();
    let sa = spectral_acceleration(&r, 1e-7).unwrap();
    assert!((sa / r.pga() - 1.0).abs() < 1e-6, "{sa} vs PGA {}", r.pga());
}

/// The recurrence against classical RK4 on u'' + 2ζωu' + ω²u = −ẍg with
/// ẍg linear between samples, 400 steps per sample (h = 2.5e-5 s; RK4's
/// global error (ωh)⁴ ≈ 1e-15 at T = 0.1 s): the peak |u| at the samples
/// agrees to 1e-9 of the peak, at short, medium and long periods.
#[test]
fn agrees_with_a_fine_independent_integration() {
    let r = random_record();
    for period in [0.1, 0.5, 2.0] {
        let w = std::f64::consts::TAU / period;
        let z = SA_DAMPING;
        let sub = 400;
        let h = r.dt / sub as f64;
        let (mut u, mut v) = (0.0_f64, 0.0_f64);
        let mut peak = 0.0_f64;
        for k in 0..r.acc.len() - 1 {
            let (a0, a1) = (r.acc[k], r.acc[k + 1]);
            let ground = |t: f64| a0 + (a1 - a0) * t / r.dt;
            let f = |t: f64, u: f64, v: f64| (v, -ground(t) - 2.0 * z * w * v - w * w * u);
            for j in 0..sub {
                let t = j as f64 * h;
                let (k1u, k1v) = f(t, u, v);
                let (k2u, k2v) = f(t + h / 2.0, u + h / 2.0 * k1u, v + h / 2.0 * k1v);
                let (k3u, k3v) = f(t + h / 2.0, u + h / 2.0 * k2u, v + h / 2.0 * k2v);
                let (k4u, k4v) = f(t + h, u + h * k3u, v + h * k3v);
                u += h / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
                v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            }
            peak = peak.max(u.abs());
        }
        let want = w * w * peak;
        let sa = spectral_acceleration(&r, period).unwrap();
        assert!(
            (sa - want).abs() < 1e-9 * want,
            "T = {period}: recurrence {sa}, RK4 {want}"
        );
    }
}

/// `sa(T)` through the IM type: in g, the same number as the function;
/// `sa-avg` over a flat band is that band's Sa; `pgv/pga` in s.
#[test]
fn the_im_type_measures_the_new_measures() {
    let r = random_record();
    let g = 9.81;
    let felt = Felt {
        ground: &r,
        floor: None,
        pair: None,
        g,
    };
    let sa: Im = "SA(0.5)".parse().unwrap();
    assert_eq!(sa.name(), "sa(0.5)");
    assert_eq!(
        sa.on(&felt),
        Some(spectral_acceleration(&r, 0.5).unwrap() / g)
    );
    let avg: Im = "sa-avg(0.2, 1.0)".parse().unwrap();
    assert_eq!(avg.name(), "sa-avg(0.2,1.0)");
    let v = avg.on(&felt).unwrap();
    let (lo, hi) = [0.2, 0.5, 1.0]
        .iter()
        .map(|&t| spectral_acceleration(&r, t).unwrap() / g)
        .fold((f64::INFINITY, 0.0_f64), |(a, b), x| (a.min(x), b.max(x)));
    assert!(
        v.is_finite() && v > 0.0 && v > lo * 0.5 && v < hi * 2.0,
        "{v}"
    );
    let ratio: Im = "pgv/pga".parse().unwrap();
    assert_eq!(ratio.on(&felt), Some(r.pgv() / r.pga()));
    assert_eq!(ratio.unit(), "s");
    assert!("sa(0)".parse::<Im>().is_err() && "sa-avg(1.0,0.5)".parse::<Im>().is_err());
    assert!("sa(1.0)-floor".parse::<Im>().unwrap().on(&felt).is_none());
}
