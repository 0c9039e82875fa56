//! Speed of the stochastic ground-motion generator.
//!
//! `record_30s_filtered` is the figure of merit: one 30-s record at the
//! defaults (Δt = 0.02 s, 499 components, eq. (7) envelope, 0.07-Hz order-4
//! high-pass with 43 s of padding each side, integration, PGA scaling), with
//! plans and buffers reused as an ensemble loop would. Target: median ≤ 50 µs.
//!
//! `floor/*` times the floor filter on that record (1 501 samples): one mode
//! (the roof of a mid-rise building) and three, buffers reused; the
//! per-mode coefficient setup; a record pair's rotation to one angle and its
//! RotD50; and, for scale, `floor/analysis_on_roof`: one analysis of the
//! hospital example's cabinet on that roof (a study filters each record
//! once per unit and shares it among the unit's cases, so one_mode over
//! analysis_on_roof bounds the floor's share of a study's cost).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use rockfrag::motion::{
    Baseline, Floor, Mode, Oscillator, Pair, SynthesisSettings, Synthesizer, floor_into,
    floor_record, rotd,
};
use rockfrag::solver::{Analysis, Block, Friction, SolverSettings, simulate};

fn generator(c: &mut Criterion) {
    let settings = SynthesisSettings::default();
    let mut synth = Synthesizer::new(&settings).expect("default settings are valid");
    let mut record = synth.generate(0, 0, 1.0).expect("record");
    let mut index = 0;
    c.bench_function("record_30s_filtered", |b| {
        b.iter(|| {
            index += 1;
            synth
                .generate_into(black_box(1), black_box(index), 4.905, &mut record)
                .expect("record");
            black_box(&record);
        })
    });
    c.bench_function("record_30s_filtered_alloc", |b| {
        b.iter(|| {
            black_box(
                synth
                    .generate(black_box(1), black_box(7), 4.905)
                    .expect("record"),
            )
        })
    });
    c.bench_function("stationary_period", |b| {
        b.iter(|| {
            index += 1;
            black_box(synth.stationary(black_box(1), black_box(index)));
        })
    });
    let unfiltered = SynthesisSettings {
        baseline: Baseline {
            highpass_hz: 0.0,
            ..Baseline::default()
        },
        ..SynthesisSettings::default()
    };
    let mut synth = Synthesizer::new(&unfiltered).expect("valid settings");
    c.bench_function("record_30s_unfiltered", |b| {
        b.iter(|| {
            index += 1;
            synth
                .generate_into(black_box(1), black_box(index), 4.905, &mut record)
                .expect("record");
            black_box(&record);
        })
    });
    c.bench_function("synthesizer_new", |b| {
        b.iter(|| black_box(Synthesizer::new(black_box(&settings)).expect("valid")))
    });
}

fn floor(c: &mut Criterion) {
    let mut synth = Synthesizer::new(&SynthesisSettings::default()).expect("valid");
    let ground = synth.generate(1, 0, 0.6 * 9.81).expect("record");
    let other = synth.generate(1, 1, 0.6 * 9.81).expect("record");
    let roof = Floor::one_mode(0.8, 0.05, 1.3);
    let three = Floor {
        modes: [(0.8, 0.05, 1.3), (0.27, 0.05, -0.4), (0.16, 0.05, 0.15)]
            .map(|(period, damping, participation)| Mode {
                period,
                damping,
                participation,
            })
            .to_vec(),
    };
    let mut out = floor_record(&ground, &roof).expect("floor");
    let mut g = c.benchmark_group("floor");
    g.bench_function("one_mode", |b| {
        b.iter(|| floor_into(black_box(&ground), black_box(&roof), &mut out).expect("floor"))
    });
    g.bench_function("three_modes", |b| {
        b.iter(|| floor_into(black_box(&ground), black_box(&three), &mut out).expect("floor"))
    });
    g.bench_function("oscillator_new", |b| {
        b.iter(|| Oscillator::new(black_box(0.8), black_box(0.05), black_box(0.02)).expect("valid"))
    });
    // one analysis on the roof, for scale: the hospital example's cabinet
    // (2B 0.6 m, H/B 3, e 0.4, μs 0.5, μk 0.45) under the roof's record
    let block = Block::new(0.6, 3.0, 9.81).expect("block");
    let mut analysis = Analysis::new(block, 0.4);
    analysis.friction = Friction::Coulomb {
        mu_s: 0.5,
        mu_k: 0.45,
    };
    let on_roof = floor_record(&ground, &roof).expect("floor");
    let settings = SolverSettings::default();
    g.bench_function("analysis_on_roof", |b| {
        b.iter(|| simulate(black_box(&analysis), &on_roof, &settings, None).expect("solve"))
    });
    let pair = Pair::new(ground, other).expect("pair");
    g.bench_function("rotate_30deg", |b| {
        b.iter(|| pair.rotate_into(black_box(30.0), &mut out).expect("rotate"))
    });
    g.bench_function("rotd50", |b| {
        b.iter(|| rotd(black_box(&pair), 50.0).expect("rotd"))
    });
    g.finish();
}

criterion_group! {
    name = benches;
    // No plots: they need system fonts, and the numbers are what we report.
    config = Criterion::default().without_plots();
    targets = generator, floor
}
criterion_main!(benches);
