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
//! RotD50. Compare with one analysis, `solver/single/*` in benches/solver.rs.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use rockfrag::motion::{
    Baseline, Floor, Mode, Oscillator, Pair, SynthesisSettings, Synthesizer, floor_into,
    floor_record, rotd,
};

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
