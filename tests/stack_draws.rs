//! Drawn properties of a stack's bodies and interfaces
//! (`[uncertainty.stack.NAME.BODY]`, issue 40 item 3): read and refused as a
//! user mistypes them, drawn from their distributions (statistical tests
//! with stated tolerances) and written per row, degenerate draws giving the
//! fixed stack's outputs exactly, and the draws the same whatever the
//! thread count.

use rockfrag::pipeline;
use rockfrag::spec::Study;
use rockfrag::study::RunOptions;
use rockfrag::uncertainty::{StackProperty, Value};
use std::collections::HashMap;
use std::path::Path;

/// Writes `text` as `dir/name` and loads it as a study.
fn load(dir: &Path, name: &str, text: &str) -> rockfrag::error::Result<Study> {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    Study::load(&path)
}

fn run(study: &Study, dir: &Path, threads: usize) {
    let opts = RunOptions {
        threads,
        ..RunOptions::new(dir)
    };
    assert!(pipeline::run(study, &opts).unwrap().run.complete);
}

/// The `outcomes.csv` rows of `dir` as maps from column name to field.
fn rows(dir: &Path) -> Vec<HashMap<String, String>> {
    let mut r = csv::Reader::from_path(dir.join("outcomes.csv")).unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    r.records()
        .map(|rec| {
            let rec = rec.unwrap();
            header
                .iter()
                .cloned()
                .zip(rec.iter().map(String::from))
                .collect()
        })
        .collect()
}

fn num(row: &HashMap<String, String>, column: &str) -> f64 {
    row[column]
        .parse()
        .unwrap_or_else(|_| panic!("{column} = {:?}", row[column]))
}

/// The statue on its pedestal, under `records` records at `pga` g.
fn statue(records: usize, pga: &str, duration: f64, interfaces: &str) -> String {
    format!(
        "name = \"drawn\"\nseed = 40\nrecords = {records}\n[motion]\nduration = {duration}\n\
         [grid]\npga = [{pga}]\n[[grid.stack]]\nname = \"statue\"\n\
         blocks = [{{ width = 0.6, height = 1.0 }}, {{ width = 0.3, height = 1.2 }}]\n\
         interfaces = {interfaces}\n[output]\nfigures = false\n[fragility]\nbootstrap = 0\n\
         [[fragility.limit_state]]\nname = \"statue-falls\"\nmeasure = \"top.overturned\"\n"
    )
}

const INF: &str = "[{ restitution = 0.0 }, { restitution = 0.0 }]";

const DRAWS: &str = "[uncertainty.stack.statue.top]\n\
    width = { dist = \"normal\", mean = 0.3, sd = 0.01, min = 0.27, max = 0.33 }\n\
    mu_s = { dist = \"lognormal\", median = 0.6, beta = 0.15 }\n\
    mu_k_over_mu_s = 0.85\n\
    [uncertainty.stack.statue.base]\n\
    density = { dist = \"uniform\", min = 0.8, max = 1.2 }\n";

/// A good spec is read (and its canonical text reads back as the same
/// study); each mistake a user makes is refused naming the file, the field
/// and the value.
#[test]
fn stack_draws_are_read_and_mistakes_refused_by_field() {
    let dir = tempfile::tempdir().unwrap();
    let good = format!("{}{DRAWS}", statue(2, "0.3", 2.0, INF));
    let study = load(dir.path(), "good.toml", &good).unwrap();
    let name = study.stacks[0].name;
    let draws = study.stack_draws(name).expect("the statue draws");
    assert!(draws.bodies[1][StackProperty::Width.index()].is_some_and(|v| v.is_drawn()));
    assert_eq!(
        draws.bodies[1][StackProperty::MuKOverMuS.index()],
        Some(Value::Fixed(0.85))
    );
    assert!(draws.bodies[0][StackProperty::Density.index()].is_some());
    let again = Study::from_toml(&study.to_toml(), &dir.path().join("good.toml")).unwrap();
    assert_eq!(again, study, "{}", study.to_toml());
    // a stack of three names its middle body
    let three = "name = \"t\"\nseed = 1\nrecords = 2\n[grid]\npga = [0.3]\n[[grid.stack]]\n\
         name = \"tomb\"\nblocks = [{ width = 0.8, height = 0.3 }, { width = 0.6, height = 1.0 }, \
         { width = 0.6, height = 0.1 }]\n\
         interfaces = [{ restitution = 0 }, { restitution = 0 }, { restitution = 0 }]\n\
         [uncertainty.stack.tomb.middle]\nheight = { dist = \"uniform\", min = 0.9, max = 1.1 }\n";
    let s3 = load(dir.path(), "three.toml", three).unwrap();
    let d3 = s3.stack_draws(s3.stacks[0].name).unwrap();
    assert!(d3.bodies[1][StackProperty::Height.index()].is_some());

    let base = statue(2, "0.3", 2.0, INF);
    let table = "[uncertainty.stack.statue.top]\n";
    let cases: [(&str, String, &[&str]); 9] = [
        (
            "unknown stack",
            "[uncertainty.stack.statu.top]\nwidth = { dist = \"uniform\", min = 0.2, max = 0.3 }\n"
                .into(),
            &["bad.toml:", "uncertainty.stack.statu", "\"statu\"", "statue"],
        ),
        (
            "unknown body",
            "[uncertainty.stack.statue.die]\nwidth = { dist = \"uniform\", min = 0.2, max = 0.3 }\n"
                .into(),
            &["uncertainty.stack.statue.die", "\"die\"", "base, top"],
        ),
        (
            "a middle a stack of two has not",
            "[uncertainty.stack.statue.middle]\nwidth = { dist = \"uniform\", min = 0.2, max = 0.3 }\n"
                .into(),
            &["uncertainty.stack.statue.middle", "base, top"],
        ),
        (
            "negative width",
            format!("{table}width = {{ dist = \"uniform\", min = -0.2, max = 0.3 }}\n"),
            &["uncertainty.stack.statue.top.width.min", "-0.2", "> 0"],
        ),
        (
            "a property that does not exist",
            format!("{table}depth = {{ dist = \"uniform\", min = 0.2, max = 0.3 }}\n"),
            &["uncertainty.stack.statue.top.depth", "unknown field", "width"],
        ),
        (
            "a fixed width",
            format!("{table}width = 0.3\n"),
            &["uncertainty.stack.statue.top.width", "0.3", "blocks[1].width"],
        ),
        (
            "a mass in a stack of densities",
            format!("{table}mass = {{ dist = \"uniform\", min = 0.2, max = 0.3 }}\n"),
            &["uncertainty.stack.statue.top.mass", "density"],
        ),
        (
            "an offset that leaves the face below",
            format!("{table}offset = {{ dist = \"uniform\", min = 0.4, max = 0.5 }}\n"),
            &["uncertainty.stack.statue", "footprint", "0.45"],
        ),
        (
            "mu_s without its ratio",
            format!("{table}mu_s = {{ dist = \"uniform\", min = 0.4, max = 0.5 }}\n"),
            &["uncertainty.stack.statue.top.mu_k_over_mu_s", "missing"],
        ),
    ];
    for (what, text, needles) in cases {
        let err = load(dir.path(), "bad.toml", &format!("{base}{text}"))
            .unwrap_err()
            .to_string();
        for n in needles {
            assert!(err.contains(n), "{what}: {n:?} not in {err}");
        }
        // the line is found (not 0), so the user can go to it
        assert!(!err.contains("bad.toml:0:"), "{what}: {err}");
    }
}

/// The drawn values written per row follow their distributions. 600
/// analyses at 0.02 g (the stack stays at rest: cheap); each test is at a
/// level where a correct sampler fails it about once in 10⁴ runs or less:
/// - the base's density (its mass / (0.6 × 1.0)), U(0.8, 1.2):
///   Kolmogorov–Smirnov distance below 1.95/√n (α = 0.001);
/// - the statue's width, N(0.3, 0.01) truncated at ±3σ: mean within
///   4 standard errors of 0.3 (symmetric truncation), the sample standard
///   deviation within 10 % of the truncated one, 0.01·√(1 − 6φ(3)/(2Φ(3) −
///   1)) = 0.009866 (10 % is 3.5 standard errors of a sample standard
///   deviation at n = 600, σ/√(2n)), every draw within
///   the bounds;
/// - ln μs of the statue's interface, ln N(ln 0.6, 0.15): mean within 4
///   standard errors;
/// - what follows from them exactly: μk = 0.85 μs, the statue's height
///   fixed at 1.2 m, its mass (density 1) width × height.
#[test]
fn drawn_values_follow_their_distributions() {
    let dir = tempfile::tempdir().unwrap();
    let spec = format!("{}{DRAWS}", statue(600, "0.02", 1.0, INF));
    let study = load(dir.path(), "draws.toml", &spec).unwrap();
    let out = dir.path().join("out");
    run(&study, &out, 2);
    let rows = rows(&out);
    let n = rows.len();
    assert_eq!(n, 600);
    let sqrt_n = (n as f64).sqrt();
    // the case columns keep the stack's own (nominal) top values
    assert!(
        rows.iter()
            .all(|r| r["width"] == "0.3" && r["friction"] == "inf")
    );

    let mut density: Vec<f64> = rows
        .iter()
        .map(|r| num(r, "base.mass") / (num(r, "base.width") * num(r, "base.height")))
        .collect();
    density.sort_by(f64::total_cmp);
    let ks = density
        .iter()
        .enumerate()
        .map(|(i, &d)| {
            let f = (d - 0.8) / 0.4;
            (f - i as f64 / n as f64)
                .abs()
                .max(((i + 1) as f64 / n as f64 - f).abs())
        })
        .fold(0.0, f64::max);
    println!(
        "base density: KS distance {ks:.4} (bound {:.4})",
        1.95 / sqrt_n
    );
    assert!(ks < 1.95 / sqrt_n, "KS {ks}");

    let width: Vec<f64> = rows.iter().map(|r| num(r, "top.width")).collect();
    assert!(width.iter().all(|w| (0.27..=0.33).contains(w)));
    let mean = width.iter().sum::<f64>() / n as f64;
    let sd = (width.iter().map(|w| (w - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt();
    let sd_truncated = 0.01 * (1.0f64 - 6.0 * 0.004_431_848 / 0.997_300_2).sqrt();
    println!(
        "statue width: mean {mean:.5} (0.3 ± {:.5}), sd {sd:.5} ({sd_truncated:.5})",
        4.0 * 0.01 / sqrt_n
    );
    assert!((mean - 0.3).abs() < 4.0 * 0.01 / sqrt_n, "{mean}");
    assert!((sd / sd_truncated - 1.0).abs() < 0.10, "{sd}");

    let ln_mu: Vec<f64> = rows.iter().map(|r| num(r, "top.mu_s").ln()).collect();
    let m = ln_mu.iter().sum::<f64>() / n as f64;
    println!(
        "statue ln μs: mean {m:.4} ({:.4} ± {:.4})",
        0.6f64.ln(),
        4.0 * 0.15 / sqrt_n
    );
    assert!((m - 0.6f64.ln()).abs() < 4.0 * 0.15 / sqrt_n, "{m}");

    for r in &rows {
        let (mu_s, mu_k) = (num(r, "top.mu_s"), num(r, "top.mu_k"));
        assert_eq!(mu_k, mu_s * 0.85);
        assert_eq!(num(r, "top.height"), 1.2);
        assert_eq!(num(r, "top.mass"), num(r, "top.width") * 1.2);
        // not drawn: the ground's interface keeps its infinite friction
        assert_eq!(r["base.mu_s"], "");
        assert_eq!(num(r, "base.width"), 0.6);
    }
    // the draws differ from analysis to analysis
    let distinct: std::collections::BTreeSet<u64> = width.iter().map(|w| w.to_bits()).collect();
    assert_eq!(distinct.len(), n);
}

/// A stack whose every property is "drawn" at one value (a zero spread:
/// `Value::Fixed`, which the spec refuses for these properties, set
/// through the API) gives exactly the fixed stack's rows and curves: the
/// draws go through the same arithmetic as `[[grid.stack]]`.
#[test]
fn degenerate_draws_give_the_fixed_stack_exactly() {
    use StackProperty as P;
    let dir = tempfile::tempdir().unwrap();
    let interfaces = "[{ restitution = 0.3 }, { restitution = 0.3, mu_s = 0.6, mu_k = 0.3 }]";
    let fixed_text = statue(6, "0.3, 0.6, 0.9", 6.0, interfaces);
    let fixed = load(dir.path(), "fixed.toml", &fixed_text).unwrap();
    let drawn_text = format!(
        "{fixed_text}[uncertainty.stack.statue.top]\nwidth = {{ dist = \"uniform\", min = 0.2, max = 0.4 }}\n"
    );
    let mut drawn = load(dir.path(), "drawn.toml", &drawn_text).unwrap();
    let u = drawn.uncertainty.as_mut().unwrap();
    let nominal = [
        // base: 0.6 × 1.0, density 1, on the ground at e = 0.3, infinite friction
        [
            (P::Width, 0.6),
            (P::Height, 1.0),
            (P::Density, 1.0),
            (P::Restitution, 0.3),
        ]
        .to_vec(),
        // statue: 0.3 × 1.2, density 1, offset 0, μs 0.6, μk = 0.5 μs = 0.3
        [
            (P::Width, 0.3),
            (P::Height, 1.2),
            (P::Density, 1.0),
            (P::Offset, 0.0),
            (P::Restitution, 0.3),
            (P::MuS, 0.6),
            (P::MuKOverMuS, 0.5),
        ]
        .to_vec(),
    ];
    for (body, values) in u.stacks[0].bodies.iter_mut().zip(nominal) {
        for (p, x) in values {
            body[p.index()] = Some(Value::Fixed(x));
        }
    }
    let (a, b) = (dir.path().join("fixed"), dir.path().join("drawn"));
    run(&fixed, &a, 2);
    run(&drawn, &b, 2);
    let (ra, rb) = (rows(&a), rows(&b));
    assert_eq!(ra.len(), 18);
    assert!(
        ra.iter().any(|r| r["top.overturned"] == "true"),
        "some overturn"
    );
    assert!(
        ra.iter().any(|r| r["top.overturned"] == "false"),
        "some stand"
    );
    for (x, y) in ra.iter().zip(&rb) {
        for (column, value) in x {
            assert_eq!(&y[column], value, "column {column}");
        }
        assert_eq!(y["top.mu_k"], "0.3");
    }
    for f in ["fragility.csv", "fragility_curves.csv"] {
        assert_eq!(
            std::fs::read_to_string(a.join(f)).unwrap(),
            std::fs::read_to_string(b.join(f)).unwrap(),
            "{f}"
        );
    }
}

/// The draws of an analysis depend on (seed, record, level, case) only:
/// one thread or two give the same `outcomes.csv`, byte for byte.
#[test]
fn stack_draws_are_the_same_whatever_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let spec = format!("{}{DRAWS}", statue(8, "0.3, 0.6", 4.0, INF));
    let study = load(dir.path(), "t.toml", &spec).unwrap();
    let (one, two) = (dir.path().join("one"), dir.path().join("two"));
    run(&study, &one, 1);
    run(&study, &two, 2);
    let a = std::fs::read(one.join("outcomes.csv")).unwrap();
    assert_eq!(a, std::fs::read(two.join("outcomes.csv")).unwrap());
    assert!(String::from_utf8(a).unwrap().contains("top.width"));
}

/// The history figure of a stack that draws solves the row's own drawn
/// stack, not the study's nominal one: each body's drawn peak |φ|/θc is
/// the row's `outcomes.csv` value to 1e-9 (relative; the same solve, whose
/// history has a row at every peak). It drew the nominal stack before.
#[test]
fn the_history_figure_of_a_drawn_stack_is_the_rows_analysis() {
    use rockfrag::figures::{FigureOptions, HistoryChoice, StudyFigures};
    let dir = tempfile::tempdir().unwrap();
    let spec = format!("{}{DRAWS}", statue(3, "0.4, 0.8", 8.0, INF));
    let study = load(dir.path(), "h.toml", &spec).unwrap();
    let out = dir.path().join("out");
    run(&study, &out, 2);
    let mut compared = 0;
    for row in rows(&out).iter().filter(|r| r["status"] == "ok") {
        let mut options = FigureOptions::for_folder(&out).unwrap();
        options.history = HistoryChoice::At {
            case: Some("stack_statue".to_string()),
            level: Some(num(row, "pga")),
            record: Some(num(row, "record") as u64),
        };
        let figures = StudyFigures::compute(&out, &options).unwrap();
        let fig = figures.stack_history.expect("a stack's history figure");
        for (body, name) in fig.bodies.iter().zip(["base", "top"]) {
            let want = num(row, &format!("{name}.theta_max_over_theta_c"));
            let peak = body.phi.iter().fold(0.0_f64, |m, p| m.max(p.1.abs()));
            assert!(
                (peak - want).abs() <= 1e-9 * want.max(1e-300),
                "{name}: peak {peak} against the row's {want}"
            );
            compared += 1;
        }
    }
    assert!(compared >= 8, "{compared}");
}
