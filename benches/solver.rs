//! Criterion benchmarks of one 30-s analysis (H/B = 4, 2B = 0.5 m, PGA 0.6 g),
//! e = 0 and e = 0.9; the nonlinear model by each integrator (Taylor, the
//! default, and Dormand–Prince) and the linearised model, at the default
//! tolerances, and Taylor following every impact at e = 0.9 (the cascade
//! rules off). `solver/ensemble` solves 10 records per iteration (throughput in
//! analyses per second); `solver/single` one record.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use rockfrag::motion::{G_STANDARD as G, SynthesisSettings, Synthesizer};
use rockfrag::solver::{Analysis, Block, Integrator, Model, SolverSettings, simulate};
use std::hint::black_box;

fn bench_solver(c: &mut Criterion) {
    let mut syn = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let records: Vec<_> = (0..10)
        .map(|i| syn.generate(1, i, 0.6 * G).unwrap())
        .collect();
    let block = Block::new(0.5, 4.0, G).unwrap();
    let mut single = c.benchmark_group("solver/single");
    for (name, model, integrator) in [
        ("taylor", Model::Nonlinear, Integrator::Taylor),
        ("dopri5", Model::Nonlinear, Integrator::Dopri5),
        ("linear", Model::Linear, Integrator::Taylor),
    ] {
        let set = SolverSettings {
            model,
            integrator,
            ..SolverSettings::default()
        };
        for e in [0.0, 0.9] {
            let an = Analysis::new(block, e);
            single.bench_with_input(BenchmarkId::new(name, format!("e={e}")), &an, |b, an| {
                b.iter(|| simulate(black_box(an), &records[0], &set, None).unwrap())
            });
        }
    }
    // every impact followed (the cascade rules off), on the bouncy case the
    // chatter rule is for
    let follow = SolverSettings {
        settle_cascades: false,
        ..SolverSettings::default()
    };
    single.bench_with_input(
        BenchmarkId::new("taylor-follow", "e=0.9"),
        &Analysis::new(block, 0.9),
        |b, an| b.iter(|| simulate(black_box(an), &records[0], &follow, None).unwrap()),
    );
    single.finish();
    let mut ens = c.benchmark_group("solver/ensemble");
    ens.throughput(Throughput::Elements(records.len() as u64));
    ens.sample_size(20);
    for e in [0.0, 0.9] {
        let an = Analysis::new(block, e);
        let set = SolverSettings::default();
        ens.bench_with_input(
            BenchmarkId::new("taylor", format!("e={e}")),
            &an,
            |b, an| {
                b.iter(|| {
                    for r in &records {
                        black_box(simulate(an, r, &set, None).unwrap());
                    }
                })
            },
        );
    }
    ens.finish();
}

criterion_group!(benches, bench_solver);
criterion_main!(benches);
