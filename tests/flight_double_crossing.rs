//! A corner landing missed by the one-minimum search of free flight: a block
//! thrown from its flat pose, spinning just fast enough that the centripetal
//! pull on its lower corner (ω²R) exceeds g while that on the corner's depth
//! below G (ω²H) does not. The corner leaves the ground at 1e-6 m/s, falls
//! back below it and rises again, all within the first record sample: its
//! height h(τ) is concave, then convex (h″ = −g + ω²R cos(ωτ − θc) grows with
//! ωτ), so h′ changes sign twice inside one search piece and both its ends
//! are above the ground. The one-minimum search (`scan::first_descent`, the
//! flight driver's search before `scan::first_descent_bounded`) sees no dip;
//! the bounded one finds the landing.

use rockfrag::motion::{G_STANDARD as G, Record};
use rockfrag::solver::{Analysis, Block, History, Initial, SolverSettings, simulate};

#[test]
fn a_spinning_throw_lands_its_grazing_corner() {
    let block = Block::new(0.5, 4.0, G).unwrap();
    let (b, h) = (block.b, block.h);
    // ω² (H + δ) = g: ω²H falls short of g by δω², ω²R exceeds it
    let delta = 0.002;
    let omega = (G / (h + delta)).sqrt();
    assert!(omega * omega * block.r > G);
    // the left corner (side −1, going down for ω > 0) leaves at ε
    let eps = 1e-6;
    let vy = b * omega + eps;
    let mut an = Analysis::new(block, 0.0);
    an.initial = Initial {
        theta: 0.0,
        theta_dot: omega,
        y_dot: vy,
        x_dot: 0.0,
    };
    let rec = Record::from_acc("still", 0.01, vec![0.0; 100]).unwrap();
    // the left corner's height in the flight's closed form (still ground):
    // y = vy τ − gτ²/2, θ = ωτ, corner at G + (−B cos θ + H sin θ, −B sin θ − H cos θ)
    let height = |tau: f64| {
        let u = omega * tau;
        vy * tau - 0.5 * G * tau * tau + h - b * u.sin() - h * u.cos()
    };
    // its first descent through 0, by a fine scan and bisection; the dip
    // ends (h back above 0) before the first sample's end
    let mut lo = 1e-7;
    while height(lo + 1e-7) > 0.0 {
        lo += 1e-7;
    }
    let mut hi = lo + 1e-7;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if height(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let landing = hi;
    assert!(landing < 0.001, "{landing}");
    assert!(height(0.009) > 0.0 && height(0.01) > 0.0);
    let mut hist = History::default();
    simulate(&an, &rec, &SolverSettings::default(), Some(&mut hist)).unwrap();
    let first = hist
        .rows
        .iter()
        .find(|r| r.event && r.t > 0.0)
        .expect("an event");
    assert!(
        (first.t - landing).abs() < 1e-9,
        "first event at {} s, the corner lands at {landing} s",
        first.t
    );
}
