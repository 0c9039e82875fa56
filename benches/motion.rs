//! Speed of the stochastic ground-motion generator.
//!
//! `record_30s_filtered` is the figure of merit: one 30-s record at the
//! defaults (Δt = 0.02 s, 499 components, eq. (7) envelope, 0.07-Hz order-4
//! high-pass with 43 s of padding each side, integration, PGA scaling), with
//! plans and buffers reused as an ensemble loop would. Target: median ≤ 50 µs.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use rockfrag::motion::{Baseline, SynthesisSettings, Synthesizer};

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

criterion_group! {
    name = benches;
    // No plots: they need system fonts, and the numbers are what we report.
    config = Criterion::default().without_plots();
    targets = generator
}
criterion_main!(benches);
