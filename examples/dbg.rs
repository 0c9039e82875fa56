use rockfrag::motion::{SynthesisSettings, Synthesizer};
use rockfrag::solver::*;
fn main() {
    let mut syn = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let g = 9.81;
    let bl = Block::new(0.5, 4.0, g).unwrap();
    let rec = syn.generate(1, 9, 0.3 * g).unwrap();
    let t = 15.037530397297456f64;
    let k = (t / rec.dt) as usize;
    println!(
        "k {k} acc {} {} t_k {}",
        rec.acc[k],
        rec.acc[k + 1],
        k as f64 * rec.dt
    );
    let mut h = History::default();
    let r = simulate(
        &Analysis::new(bl, 0.0),
        &rec,
        &SolverSettings {
            model: Model::Linear,
            max_events: 30,
            ..Default::default()
        },
        Some(&mut h),
    );
    println!("{:?}", r.err());
    let n = h.rows.len();
    for r in &h.rows[n - 30..n - 20] {
        println!(
            "{} {:?} th {:e} om {:e} F {}",
            r.t, r.mode, r.theta, r.theta_dot, r.f
        );
    }
}
