//! Uncertain block parameters (`[uncertainty]`, issue 14): a study of
//! recorded motions scaled by factors, with a drawn coefficient of
//! restitution and three limit states, runs to the same bytes on any thread
//! count and shard split; its draws are in range and differ per analysis;
//! its fitted medians rise with severity. And the spec's rules for the table.

mod common;

use rockfrag::case::Field;
use rockfrag::fragility::{fit_cases, read_outcomes_for};
use rockfrag::im::Im;
use rockfrag::motion::{At2, G_STANDARD as G, SynthesisSettings, Synthesizer};
use rockfrag::outcomes_csv::{Column, OutcomesFile};
use rockfrag::solver::Friction;
use rockfrag::spec::Study;
use rockfrag::study::{self, RunOptions, Shard, files};
use std::path::{Path, PathBuf};

const RECORDS: usize = 16;

/// Writes `RECORDS` synthetic records (PGA 0.25 to 0.55 g) as PEER `.AT2` files into
/// `dir/rec/` and a spec using them as recorded motions, scaled by six
/// factors, with e drawn from U(0, 0.9) and three limit states.
fn recorded_spec(dir: &Path, extra: &str) -> PathBuf {
    std::fs::create_dir_all(dir.join("rec")).unwrap();
    let mut syn = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let mut files = Vec::new();
    for i in 0..RECORDS {
        let rec = syn
            .generate(21, i as u64, (0.25 + 0.02 * i as f64) * G)
            .unwrap();
        let name = format!("rec/r{i}.AT2");
        At2::from_record(&rec, G).write(dir.join(&name)).unwrap();
        files.push(format!("\"{name}\""));
    }
    let text = format!(
        r#"name = "uncertain"
record_files = [{}]

[grid]
aspect = [4]
scale_factors = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0]

[uncertainty]
seed = 11
restitution = {{ dist = "uniform", min = 0.0, max = 0.9 }}
{extra}
[fragility]
bootstrap = 50

[[fragility.limit_state]]
name = "rocks-third"
measure = "theta_max_over_theta_c"
exceeds = 0.3

[[fragility.limit_state]]
name = "rocks-two-thirds"
measure = "theta_max_over_theta_c"
exceeds = 0.67

[[fragility.limit_state]]
name = "overturning"
measure = "overturned"
"#,
        files.join(", ")
    );
    let path = dir.join("uncertain.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn run(study: &Study, dir: &Path, threads: usize, shard: Shard) {
    let opts = RunOptions {
        threads,
        shard,
        chunk_analyses: 7,
        ..RunOptions::new(dir)
    };
    assert!(rockfrag::pipeline::run(study, &opts).unwrap().run.complete);
}

/// The issue's must-show: byte-identical on 1 and 2 threads and on a
/// 3-shard split merged; the drawn e in [0, 0.9] and different in every
/// analysis (96 draws of a continuous distribution: a repeat would mean a
/// shared stream); each analysis's IM is its own measured PGA; the medians
/// of the three limit states rise with severity.
#[test]
fn recorded_scaled_drawn_restitution_three_limit_states() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = recorded_spec(tmp.path(), "");
    let study = Study::load(&spec).unwrap();
    assert_eq!(study.drawn(), [Field::Restitution]);

    let (one, two) = (tmp.path().join("one"), tmp.path().join("two"));
    run(&study, &one, 1, Shard::WHOLE);
    run(&study, &two, 2, Shard::WHOLE);
    let outcomes = std::fs::read(one.join(files::OUTCOMES)).unwrap();
    assert_eq!(outcomes, std::fs::read(two.join(files::OUTCOMES)).unwrap());
    assert_eq!(
        std::fs::read(one.join(files::SUMMARY)).unwrap(),
        std::fs::read(two.join(files::SUMMARY)).unwrap()
    );
    let shards: Vec<PathBuf> = (1..=3)
        .map(|k| {
            let d = tmp.path().join(format!("shard-{k}"));
            run(&study, &d, 2, Shard::new(k, 3).unwrap());
            d
        })
        .collect();
    let merged = tmp.path().join("merged");
    study::merge(&shards, &merged).unwrap();
    assert_eq!(
        outcomes,
        std::fs::read(merged.join(files::OUTCOMES)).unwrap()
    );

    // The draws, and each analysis's own IM.
    let mut table = OutcomesFile::open(
        &one.join(files::OUTCOMES),
        &[Column::Im(Im::PGA)],
        "the test",
    )
    .unwrap();
    let (mut es, mut pgas) = (Vec::new(), Vec::new());
    while let Some((_, row)) = table.next_row().unwrap() {
        assert!(row.result.is_ok(), "every analysis finishes");
        es.push(row.case.restitution);
        pgas.push(row.im(Im::PGA).unwrap());
    }
    assert_eq!(es.len(), RECORDS * 6);
    assert!(es.iter().all(|e| (0.0..=0.9).contains(e)), "{es:?}");
    let mut distinct = es.clone();
    distinct.sort_by(f64::total_cmp);
    distinct.dedup();
    assert_eq!(distinct.len(), es.len(), "every analysis draws its own e");
    // U(0, 0.9) over 96 draws: mean 0.45 ± 4 standard errors (0.26/√96).
    let mean = es.iter().sum::<f64>() / es.len() as f64;
    assert!(
        (mean - 0.45).abs() < 4.0 * 0.26 / (es.len() as f64).sqrt(),
        "{mean}"
    );
    // Records scaled by factors: the PGAs are measured, not 6 stripes.
    let mut levels = pgas.clone();
    levels.sort_by(f64::total_cmp);
    levels.dedup();
    assert!(levels.len() > 6 * 2, "{} distinct PGAs", levels.len());

    // One pooled case, three fitted limit states, medians rising.
    let options = study.fragility.clone().unwrap();
    let data = read_outcomes_for(&one.join(files::OUTCOMES), &options).unwrap();
    assert_eq!(data.cases.len(), 1, "the draws pool into one case");
    assert_eq!(data.cases[0].trials.len(), RECORDS * 6);
    let fits = fit_cases(&data, &options).unwrap();
    let medians: Vec<f64> = fits
        .iter()
        .map(|f| {
            f.fit
                .as_ref()
                .unwrap_or_else(|e| panic!("{}: {e}", f.limit_state))
                .median()
        })
        .collect();
    let names: Vec<&str> = fits.iter().map(|f| f.limit_state.as_str()).collect();
    assert_eq!(names, ["rocks-third", "rocks-two-thirds", "overturning"]);
    assert!(
        medians.windows(2).all(|w| w[0] < w[1]),
        "medians must rise with severity: {medians:?}"
    );
}

/// The draws follow (seed, record, level, case) alone: another `[uncertainty]`
/// seed gives other draws; adding a drawn μs (with μk/μs) leaves e's draws
/// as they were (one uniform per parameter, in a fixed order), and μk ≤ μs
/// in every analysis.
#[test]
fn draws_depend_on_their_key_and_not_on_other_parameters() {
    let tmp = tempfile::tempdir().unwrap();
    let read_e = |dir: &Path, extra: &str| {
        let spec = recorded_spec(dir, extra);
        let study = Study::load(&spec).unwrap();
        let out = dir.join("out");
        run(&study, &out, 2, Shard::WHOLE);
        let mut t = OutcomesFile::open(&out.join(files::OUTCOMES), &[], "the test").unwrap();
        let mut rows = Vec::new();
        while let Some((_, r)) = t.next_row().unwrap() {
            let (s, k) = match r.case.friction {
                Friction::Coulomb { mu_s, mu_k } => (Some(mu_s), Some(mu_k)),
                _ => (None, None),
            };
            rows.push((r.case.restitution, s, k));
        }
        rows
    };
    let base = read_e(&tmp.path().join("a"), "");
    let friction = read_e(
        &tmp.path().join("b"),
        "mu_s = { dist = \"lognormal\", median = 0.6, beta = 0.15 }\n\
         mu_k_over_mu_s = { dist = \"uniform\", min = 0.7, max = 1.0 }\n",
    );
    for ((e0, ..), (e1, s, k)) in base.iter().zip(&friction) {
        assert_eq!(e0, e1, "e's draws do not depend on whether μs is drawn");
        let (s, k) = (s.unwrap(), k.unwrap());
        assert!(k <= s && k >= 0.7 * s * (1.0 - 1e-15), "μs {s}, μk {k}");
    }
}

fn spec_error(body: &str) -> String {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("s.toml");
    std::fs::write(&path, body).unwrap();
    Study::load(&path).unwrap_err().to_string()
}

/// A parameter on the grid and drawn, a missing partner of μs, a
/// distribution reaching outside the parameter's range, a fixed width and
/// an unknown distribution are errors naming the field, its line and what
/// would be accepted.
#[test]
fn spec_rules_of_the_uncertainty_table() {
    let e = spec_error(
        "[grid]\nrestitution = [0.3]\n[uncertainty]\nrestitution = { dist = \"uniform\", min = 0.0, max = 0.9 }\n",
    );
    assert!(
        e.contains(":4:") && e.contains("uncertainty.restitution") && e.contains("not both"),
        "{e}"
    );
    let e =
        spec_error("[uncertainty]\nmu_s = { dist = \"lognormal\", median = 0.6, beta = 0.15 }\n");
    assert!(e.contains("uncertainty.mu_k_over_mu_s"), "{e}");
    let e = spec_error(
        "[grid]\nfriction = [\"inf\"]\n[uncertainty]\nmu_s = 0.6\nmu_k_over_mu_s = 0.8\n",
    );
    assert!(
        e.contains("uncertainty.mu_s") && e.contains("grid.friction"),
        "{e}"
    );
    let e =
        spec_error("[uncertainty]\n\nrestitution = { dist = \"uniform\", min = 0.0, max = 1.2 }\n");
    assert!(
        e.contains(":3:") && e.contains("uncertainty.restitution.max") && e.contains("1.2"),
        "{e}"
    );
    let e = spec_error("[uncertainty]\nwidth = { dist = \"normal\", mean = 0.5, sd = 0.02 }\n");
    assert!(e.contains("uncertainty.width") && e.contains("min"), "{e}");
    let e = spec_error("[uncertainty]\nwidth = 0.5\n");
    assert!(e.contains("grid.width = [0.5]"), "{e}");
    let e = spec_error("[uncertainty]\nrestitution = { dist = \"beta\", a = 1 }\n");
    assert!(
        e.contains("uncertainty.restitution") && e.contains("lognormal"),
        "{e}"
    );
}

/// The canonical spec text of a study with `[uncertainty]` reads back to
/// the same study (the manifest's spec is how `rockfrag fragility` and
/// `figures` learn what was drawn), and leaves the drawn lists off the grid.
#[test]
fn canonical_spec_round_trips() {
    let text = "[grid]\naspect = [2, 4]\n[uncertainty]\nseed = 3\n\
                restitution = { dist = \"normal\", mean = 0.5, sd = 0.2, min = 0.0, max = 1.0 }\n\
                mu_s = { dist = \"lognormal\", median = 0.6, beta = 0.15 }\n\
                mu_k_over_mu_s = 0.85\n";
    let study = Study::from_toml(text, Path::new("x.toml")).unwrap();
    let canonical = study.to_toml();
    assert!(!canonical.contains("restitution = ["), "{canonical}");
    assert!(!canonical.contains("friction"), "{canonical}");
    let back = Study::from_toml(&canonical, Path::new("x.toml")).unwrap();
    assert!(back.uncertainty == study.uncertainty && back.aspects == study.aspects);
    assert_eq!(back.hash(), study.hash());
}

/// `rockfrag fragility DIR` learns from the study's manifest which
/// parameters were drawn and pools them: one row per limit state for the
/// pooled case (e column empty), not one per analysis; `--limit-state`
/// flags replace the study's limit states, in the order given; a malformed
/// flag is refused naming the expected form.
#[test]
fn fragility_command_pools_drawn_parameters_and_takes_limit_states() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = tmp.path().join("u.toml");
    std::fs::write(
        &spec,
        "name = \"u\"\nseed = 4\nrecords = 6\n[grid]\naspect = [4]\n\
         pga = [0.2, 0.4, 0.6, 0.8, 1.0]\n[uncertainty]\n\
         restitution = { dist = \"uniform\", min = 0.0, max = 0.9 }\n",
    )
    .unwrap();
    let dir = tmp.path().join("out");
    let d = dir.to_str().unwrap();
    let o = common::rockfrag(&["run", spec.to_str().unwrap(), "--out", d]);
    assert!(o.status.success(), "{}", common::stderr(&o));

    let rows = |args: &[&str]| {
        let o = common::rockfrag(args);
        assert!(o.status.success(), "{}", common::stderr(&o));
        let text = std::fs::read_to_string(dir.join("fragility.csv")).unwrap();
        text.lines()
            .skip(1)
            .map(|l| {
                // case_id, aspect, width, restitution, …, limit_state
                let f: Vec<&str> = l.split(',').collect();
                (f[3].to_string(), f[7].to_string())
            })
            .collect::<Vec<_>>()
    };
    let pooled = rows(&["fragility", d, "--bootstrap", "0"]);
    assert_eq!(pooled, [(String::new(), "overturning".to_string())]);
    let two = rows(&[
        "fragility",
        d,
        "--bootstrap",
        "0",
        "--limit-state",
        "rocks-third=theta_max_over_theta_c>0.3",
        "--limit-state",
        "overturning=overturned",
    ]);
    let names: Vec<&str> = two.iter().map(|r| r.1.as_str()).collect();
    assert_eq!(names, ["rocks-third", "overturning"]);
    assert!(two.iter().all(|r| r.0.is_empty()), "e pooled: {two:?}");

    let o = common::rockfrag(&["fragility", d, "--limit-state", "rocks"]);
    assert!(!o.status.success());
    assert!(
        common::stderr(&o).contains("NAME=MEASURE"),
        "{}",
        common::stderr(&o)
    );
}

/// The exact CDF of a standard normal truncated to [lo, hi] with lo ≥ 1 (or
/// its mirror), at z, by Simpson's rule on the density relative to the
/// bound's, exp(−s (lo + s/2)) for s = z − lo (40 e-folds of its scale 1/lo
/// on 4,000 intervals: relative error ~1e-10), independent of the sampler's
/// continued fraction and Newton iteration.
fn far_tail_cdf(z: f64, lo: f64, hi: f64) -> f64 {
    let mass = |t: f64| {
        let t = t.min(40.0 / lo);
        let n = 4_000;
        let h = t / n as f64;
        let f = |s: f64| (-s * (lo + 0.5 * s)).exp();
        let inner: f64 = (1..n)
            .map(|i| if i % 2 == 1 { 4.0 } else { 2.0 } * f(i as f64 * h))
            .sum();
        h / 3.0 * (f(0.0) + inner + f(t))
    };
    mass(z - lo) / mass(hi - lo)
}

/// A truncation far in a tail (issue 37: `mean = 0.5, sd = 0.01, min = 0.9,
/// max = 1.0`, bounds 40σ and 50σ out, drew 1.0 every time): the draws
/// follow the truncated distribution, piled against the near bound with the
/// tail's exponential scale σ/40. For a normal in the upper tail, a
/// lognormal with no upper bound, and a normal in the lower tail: the
/// quantile at u is the exact truncated CDF's to 1e-9 (F(x(u)) = u), and
/// 4,000 draws of the analyses' uniforms pass a Kolmogorov–Smirnov test
/// against it at the 1 % level (D < 1.63/√n).
#[test]
fn far_tail_truncations_follow_the_truncated_distribution() {
    use rockfrag::uncertainty::{Distribution, analysis_seed, uniforms};
    type ToZ = Box<dyn Fn(f64) -> f64>;
    // (distribution, z of a value, bounds in z, sign: −1 for the lower
    // tail, whose mirror the CDF is computed on)
    let cases: Vec<(Distribution, ToZ, f64, f64, f64)> = vec![
        (
            Distribution::Normal {
                mean: 0.5,
                sd: 0.01,
                min: Some(0.9),
                max: Some(1.0),
            },
            Box::new(|x| (x - 0.5) / 0.01),
            40.0,
            50.0,
            1.0,
        ),
        (
            Distribution::Lognormal {
                median: 0.5,
                beta: 0.01,
                min: Some(0.9),
                max: None,
            },
            Box::new(|x: f64| (x / 0.5).ln() / 0.01),
            (0.9f64 / 0.5).ln() / 0.01,
            f64::INFINITY,
            1.0,
        ),
        (
            Distribution::Normal {
                mean: 0.5,
                sd: 0.01,
                min: Some(0.0),
                max: Some(0.1),
            },
            Box::new(|x| (x - 0.5) / 0.01),
            -50.0,
            -40.0,
            -1.0,
        ),
    ];
    for (d, to_z, lo, hi, sign) in &cases {
        // CDF of the value in the distribution's own direction.
        let cdf = |x: f64| {
            let z = to_z(x);
            if *sign > 0.0 {
                far_tail_cdf(z, *lo, *hi)
            } else {
                1.0 - far_tail_cdf(-z, -hi, -lo)
            }
        };
        for i in 1..100 {
            let u = i as f64 / 100.0;
            let x = d.quantile(u);
            let f = cdf(x);
            assert!((f - u).abs() < 1e-9, "{d:?}: u = {u}: x = {x}, F(x) = {f}");
        }
        let n = 4_000;
        let mut f: Vec<f64> = (0..n)
            .map(|i| cdf(d.quantile(uniforms(analysis_seed(5, i, 0, 0))[2])))
            .collect();
        f.sort_by(f64::total_cmp);
        let ks = f
            .iter()
            .enumerate()
            .map(|(i, &v)| (v - i as f64 / n as f64).max((i + 1) as f64 / n as f64 - v))
            .fold(0.0, f64::max);
        assert!(ks < 1.63 / (n as f64).sqrt(), "{d:?}: KS distance {ks}");
    }
}
