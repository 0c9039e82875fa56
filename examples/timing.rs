use rockfrag::motion::{SynthesisSettings, Synthesizer};
use rockfrag::solver::*;
fn main() {
    let mut syn = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let g = 9.81;
    let recs: Vec<_> = (0..25)
        .map(|i| syn.generate(1, i, 0.6 * g).unwrap())
        .collect();
    for model in [Model::Nonlinear, Model::Linear] {
        for e in [0.0, 0.9] {
            let bl = Block::new(0.5, 4.0, g).unwrap();
            let set = SolverSettings {
                model,
                ..Default::default()
            };
            let mut times = vec![];
            let mut ev = 0;
            let mut steps = 0;
            for r in &recs {
                let t0 = std::time::Instant::now();
                let mut o = None;
                for _ in 0..20 {
                    o = Some(simulate(&Analysis::new(bl, e), r, &set, None).unwrap());
                }
                times.push(t0.elapsed().as_secs_f64() / 20.0);
                let o = o.unwrap();
                ev += o.stats.events;
                steps += o.stats.steps_accepted;
            }
            times.sort_by(|a, b| a.partial_cmp(b).unwrap());
            println!(
                "{model:?} e {e}: median {:.1} µs, max {:.1} µs, events/run {}, steps/run {}",
                times[12] * 1e6,
                times[24] * 1e6,
                ev / 25,
                steps / 25
            );
        }
    }
}
