use rockfrag::motion::Record;
use rockfrag::solver::*;
fn main() {
    let dt = 0.02;
    let n = 1501;
    let acc: Vec<f64> = (0..n)
        .map(|k| {
            let t = k as f64 * dt;
            let env = (-(t - 10.0f64).powi(2) / 20.0).exp();
            9.81 * 0.6 * env * ((2.0 * 3.1 * t).sin() + 0.5 * (2.0 * 7.3 * t + 1.0).sin())
        })
        .collect();
    let rec = Record::from_acc("smoke", dt, acc).unwrap();
    for aspect in [2.0, 4.0, 6.0] {
        for e in [0.0, 0.3, 0.6, 0.9] {
            let b = Block::new(0.5, aspect, 9.81).unwrap();
            let mut set = SolverSettings::default();
            set.audit_energy = true;
            let t0 = std::time::Instant::now();
            let out = simulate(&Analysis::new(b, e), &rec, &set, None);
            let el = t0.elapsed();
            match out {
                Ok(o) => println!(
                    "H/B {aspect} e {e}: ot {} up {} th {:.4} mum {:.3} mui {:.3} imp {} fl {} upl {} holds {} gains {} settles {} end {:.3} resid {:?} steps {} rej {} {:?}",
                    o.overturned,
                    o.uplifted,
                    o.theta_max_over_theta_c,
                    o.mu_motion,
                    o.mu_impact,
                    o.impacts,
                    o.flights,
                    o.uplifts,
                    o.liftoff_holds,
                    o.energy_gains,
                    o.settles,
                    o.end_time,
                    o.energy_residual,
                    o.stats.steps_accepted,
                    o.stats.steps_rejected,
                    el
                ),
                Err(e) => println!("err {e}"),
            }
        }
    }
}
