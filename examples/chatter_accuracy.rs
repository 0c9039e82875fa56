//! The chatter rule's accuracy and speed against every bounce followed, and,
//! for scale, Taylor against Dormand–Prince (both following every bounce):
//! 100 synthetic records at 0.6 g (seed 41; PGA in g as the second argument),
//! 2B = 0.5 m, H/B 2, 4, 6, e = 0.3,
//! 0.6, 0.9, infinite friction, one thread. Prints, per e, the overturning
//! flips of each pair over 300 runs, the median and largest |Δθmax/θc| over
//! runs that overturn in neither, and the cost per analysis.
//!
//! `cargo run --release --example chatter_accuracy [RECORDS] [PGA]`

use rockfrag::motion::{G_STANDARD as G, Record, SynthesisSettings, Synthesizer};
use rockfrag::outcome::Outcome;
use rockfrag::solver::{Analysis, Block, Integrator, SolverSettings, simulate};
use std::time::Instant;

fn main() {
    let n: u64 = std::env::args()
        .nth(1)
        .map_or(100, |a| a.parse().expect("RECORDS: a count"));
    let pga: f64 = std::env::args()
        .nth(2)
        .map_or(0.6, |a| a.parse().expect("PGA: in g"));
    let mut syn = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let recs: Vec<Record> = (0..n)
        .map(|i| syn.generate(41, i, pga * G).unwrap())
        .collect();
    let rule = SolverSettings::default();
    let follow = SolverSettings {
        settle_cascades: false,
        ..SolverSettings::default()
    };
    let dopri = SolverSettings {
        integrator: Integrator::Dopri5,
        ..follow
    };
    println!(
        "| e | flips rule/follow | flips taylor/dopri5 | median, max |Δθmax/θc| rule | the same, dopri5 | µs per analysis: rule, follow |"
    );
    println!("|---|---|---|---|---|---|");
    for e in [0.3, 0.6, 0.9] {
        let mut runs: [Vec<Outcome>; 3] = Default::default();
        let mut secs = [0.0; 3];
        for aspect in [2.0, 4.0, 6.0] {
            let an = Analysis::new(Block::new(0.5, aspect, G).unwrap(), e);
            for (j, set) in [&rule, &follow, &dopri].into_iter().enumerate() {
                let t0 = Instant::now();
                runs[j].extend(recs.iter().map(|r| simulate(&an, r, set, None).unwrap()));
                secs[j] += t0.elapsed().as_secs_f64();
            }
        }
        let flips = |a: &[Outcome], b: &[Outcome]| {
            a.iter()
                .zip(b)
                .filter(|(x, y)| x.overturned != y.overturned)
                .count()
        };
        let dth = |a: &[Outcome], b: &[Outcome]| {
            let mut d: Vec<f64> = a
                .iter()
                .zip(b)
                .filter(|(x, y)| !x.overturned && !y.overturned)
                .map(|(x, y)| (x.theta_max_over_theta_c - y.theta_max_over_theta_c).abs())
                .collect();
            d.sort_by(f64::total_cmp);
            (d[d.len() / 2], d[d.len() - 1])
        };
        let (m1, x1) = dth(&runs[0], &runs[1]);
        let (m2, x2) = dth(&runs[2], &runs[1]);
        let per = |s: f64| s / (3 * n) as f64 * 1e6;
        println!(
            "| {e} | {} | {} | {m1:.1e}, {x1:.1e} | {m2:.1e}, {x2:.1e} | {:.0}, {:.0} |",
            flips(&runs[0], &runs[1]),
            flips(&runs[2], &runs[1]),
            per(secs[0]),
            per(secs[1])
        );
    }
}
