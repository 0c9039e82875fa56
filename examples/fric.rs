use rockfrag::motion::{SynthesisSettings, Synthesizer};
use rockfrag::solver::*;
fn main() {
    let mut syn = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let g = 9.81;
    for (mu_s, mu_k) in [
        (0.7, 0.6),
        (0.4, 0.4),
        (100.0, 100.0),
        (0.3, 0.3),
        (0.5, 0.5),
    ] {
        for aspect in [2.0, 4.0] {
            for e in [0.0, 0.9] {
                let bl = Block::new(0.5, aspect, g).unwrap();
                let mut an = Analysis::new(bl, e);
                an.friction = Friction::Coulomb { mu_s, mu_k };
                let set = SolverSettings {
                    audit_energy: true,
                    impact: ImpactLaw::Energetic,
                    ..Default::default()
                };
                let (mut ot, mut sl, mut tm, mut res, mut ev, mut gains) =
                    (0, 0.0f64, [0.0; 5], 0.0f64, 0, 0);
                let t0 = std::time::Instant::now();
                for i in 0..10 {
                    let rec = syn.generate(1, i, 0.9 * g).unwrap();
                    match simulate(&an, &rec, &set, None) {
                        Ok(o) => {
                            if o.overturned {
                                ot += 1
                            };
                            sl = sl.max(o.slip_max);
                            for k in 0..5 {
                                tm[k] += o.time_in_mode[k]
                            }
                            res = res.max(o.energy_residual.unwrap());
                            ev += o.stats.events;
                            gains += o.energy_gains;
                        }
                        Err(err) => println!("  ERR mu {mu_s} H/B {aspect} e {e} rec {i}: {err}"),
                    }
                }
                println!(
                    "mu {mu_s}/{mu_k} H/B {aspect} e {e}: OT {ot} slipmax {sl:.3} modes {:?} resid {res:.1e} events {ev} gains {gains} {:?}",
                    tm.map(|x| (x * 10.0f64).round() / 10.0),
                    t0.elapsed()
                );
            }
        }
    }
}
