use rockfrag::motion::{SynthesisSettings, Synthesizer};
use rockfrag::solver::*;
fn main() {
    let mut syn = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let g = 9.81;
    // ring-down convergence
    for e in [0.6, 0.9] {
        for eps in [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8] {
            let bl = Block::new(0.5, 4.0, g).unwrap();
            let set = SolverSettings {
                settle_tol: eps,
                ..Default::default()
            };
            let (mut ot, mut th, mut mu, mut n, mut ev) = (0, 0.0, 0.0, 0, 0);
            let t0 = std::time::Instant::now();
            for i in 0..25 {
                let rec = syn.generate(1, i, 0.6 * g).unwrap();
                let o = simulate(&Analysis::new(bl, e), &rec, &set, None).unwrap();
                ev += o.stats.events;
                if o.overturned {
                    ot += 1
                } else {
                    th += o.theta_max_over_theta_c;
                    mu += o.mu_motion;
                    n += 1
                }
            }
            println!(
                "e {e} eps {eps:e}: OT {ot} thmax {:.6} mu {:.6} events {ev} {:?}",
                th / n as f64,
                mu / n as f64,
                t0.elapsed()
            );
        }
    }
    // linear vs nonlinear
    for i in 0..10 {
        for pga in [0.26, 0.28, 0.3] {
            let bl = Block::new(0.5, 4.0, g).unwrap();
            let rec = syn.generate(1, i, pga * g).unwrap();
            let a = simulate(
                &Analysis::new(bl, 0.0),
                &rec,
                &SolverSettings::default(),
                None,
            )
            .unwrap();
            let b = simulate(
                &Analysis::new(bl, 0.0),
                &rec,
                &SolverSettings {
                    model: Model::Linear,
                    ..Default::default()
                },
                None,
            )
            .unwrap();
            if a.theta_max_over_theta_c > 0.0 && a.theta_max_over_theta_c < 0.05 {
                println!(
                    "rec {i} pga {pga}: nl {:.6e} lin {:.6e} rel {:.3e}",
                    a.theta_max_over_theta_c,
                    b.theta_max_over_theta_c,
                    (b.theta_max_over_theta_c / a.theta_max_over_theta_c - 1.0)
                );
            }
        }
    }
}
