use rockfrag::motion::{SynthesisSettings, Synthesizer};
use rockfrag::solver::*;
fn main() {
    let mut syn = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let g = 9.81;
    let bl = Block::new(0.5, 4.0, g).unwrap();
    let rec = syn.generate(1, 0, 0.9 * g).unwrap();
    let mut an = Analysis::new(bl, 0.0);
    an.friction = Friction::Coulomb {
        mu_s: 100.0,
        mu_k: 100.0,
    };
    let mut h = History::default();
    let r = simulate(
        &an,
        &rec,
        &SolverSettings {
            max_events: 200,
            ..Default::default()
        },
        Some(&mut h),
    );
    println!("{:?}", r.err());
    let n = h.rows.len();
    for r in &h.rows[n - 14..] {
        println!(
            "{:.15} {:?} th {:.6e} om {:.6e} x {:.3e} vx {:.3e} N {:.4e} F {:.4e}",
            r.t, r.mode, r.theta, r.theta_dot, r.x, r.x_dot, r.n, r.f
        );
    }
}
