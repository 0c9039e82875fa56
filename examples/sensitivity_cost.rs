//! The cost of the sensitivity check (`rockfrag::solver::sensitivity`): two
//! stripes of the bench ensemble (`rockfrag bench`: 25 records of seed 1991
//! of the default motion model at 0.6 and 1.2 g; H/B 2, 4, 6; e 0 and 0.9;
//! infinite friction and μs = 0.7, μk = 0.6; 600 analyses) solved on one thread with the default settings,
//! without and with the check, in alternating passes. Prints the minimum and
//! median time per analysis of each, and their ratio.
//!
//! `cargo run --release --example sensitivity_cost [PASSES]`

use rockfrag::motion::{G_STANDARD as G, SynthesisSettings, Synthesizer};
use rockfrag::solver::{Analysis, Block, Friction, SolverSettings, sensitivity, simulate};
use std::hint::black_box;
use std::time::Instant;

fn main() {
    let passes: usize = std::env::args()
        .nth(1)
        .map_or(7, |a| a.parse().expect("PASSES: a count"));
    let synth = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let set = SolverSettings::default();
    let records: Vec<_> = [0.6, 1.2]
        .into_iter()
        .flat_map(|pga| (0..25).map(move |i| (pga, i)))
        .map(|(pga, i)| synth.clone().generate(1991, i, pga * G).unwrap())
        .collect();
    let mut analyses = Vec::new();
    for aspect in [2.0, 4.0, 6.0] {
        for e in [0.0, 0.9] {
            for friction in [
                Friction::Infinite,
                Friction::Coulomb {
                    mu_s: 0.7,
                    mu_k: 0.6,
                },
            ] {
                let mut an = Analysis::new(Block::new(0.5, aspect, G).unwrap(), e);
                an.friction = friction;
                analyses.push(an);
            }
        }
    }
    let n = (analyses.len() * records.len()) as f64;
    let (mut plain, mut with, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..passes {
        let start = Instant::now();
        for an in &analyses {
            for r in &records {
                black_box(simulate(an, r, &set, None).unwrap());
            }
        }
        let a = start.elapsed().as_secs_f64() / n;
        let start = Instant::now();
        for an in &analyses {
            for r in &records {
                let out = simulate(an, r, &set, None).unwrap();
                black_box(sensitivity(an, r, &set, &out).unwrap());
            }
        }
        let b = start.elapsed().as_secs_f64() / n;
        plain.push(a);
        with.push(b);
        ratios.push(b / a);
    }
    for v in [&mut plain, &mut with, &mut ratios] {
        v.sort_by(f64::total_cmp);
    }
    let median = |v: &[f64]| v[v.len() / 2];
    println!("{n} analyses, one thread, {passes} alternating passes, per analysis:");
    println!(
        "without the check  min {:.1} µs, median {:.1} µs",
        plain[0] * 1e6,
        median(&plain) * 1e6
    );
    println!(
        "with the check     min {:.1} µs, median {:.1} µs",
        with[0] * 1e6,
        median(&with) * 1e6
    );
    println!(
        "ratio              {:.2} (minima), {:.2} (median of the passes' ratios)",
        with[0] / plain[0],
        median(&ratios)
    );
}
