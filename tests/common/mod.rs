//! Helpers shared by the CLI tests: run the built binary, capture its output.
#![allow(dead_code)] // each test binary uses a different subset of the helpers

pub mod reference;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A spec that uses most fields: recorded motions, widths, friction in its
/// three forms (`inf`, table, pair), PGV levels, solver and output options.
pub const RICH_SPEC: &str = r#"name = "rich"
g = 9.80665
record_files = ["record-a.csv"]
[grid]
width = [0.3, 0.5]
aspect = [3]
restitution = [0.5]
friction = ["inf", { mu_s = 0.7, mu_k = 0.6 }, [0.5, 0.5]]
pgv = [0.25, 0.5]
[solver]
model = "linear"
impact = "energetic"
[output]
time_in_mode = true
stats = true
"#;

/// The figures every synthetic study folder gets, in the order they are
/// drawn.
pub const FIGURES: [&str; 6] = [
    "motion",
    "spectrum",
    "history",
    "fragility",
    "friction_demand",
    "restitution",
];

/// `rockfrag run SPEC --out OUT`.
pub fn run_spec(spec: &Path, out: &Path) -> Output {
    rockfrag(&[
        "run",
        spec.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ])
}

/// The binomial log-likelihood of lognormal fragility Φ(a + b ln x) for
/// `obs` (im, trials, overturned), without its constant: what a fit
/// maximises, for checks that a nudge of (a, b) lowers it.
pub fn loglik(obs: &[rockfrag::fragility::Observation], a: f64, b: f64) -> f64 {
    use statrs::distribution::{ContinuousCDF, Normal};
    let n = Normal::standard();
    obs.iter()
        .map(|o| {
            let p = n.cdf(a + b * o.im.ln());
            let z = o.overturned as f64;
            let m = (o.trials - o.overturned) as f64;
            (if z > 0.0 { z * p.ln() } else { 0.0 })
                + if m > 0.0 { m * (1.0 - p).ln() } else { 0.0 }
        })
        .sum()
}

/// Runs `rockfrag` with the given arguments.
pub fn rockfrag(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rockfrag"))
        .args(args)
        .output()
        .expect("run rockfrag")
}

/// Standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Standard output as text.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The small study the inference calibration tests draw their synthetic
/// events on (tests/infer.rs, tests/infer_pair.rs): 20 records at 7 PGA
/// levels, e and μ drawn, 16 draws per kind, seating 0.3.
pub const CALIBRATION_STUDY: &str = r#"name = "calibration"
seed = 31
records = 20
[motion]
duration = 10.0
[grid]
pga = [0.15, 0.2, 0.3, 0.45, 0.6, 0.85, 1.2]
[uncertainty]
restitution = { dist = "uniform", min = 0.0, max = 0.4 }
mu_s = { dist = "lognormal", median = 0.6, beta = 0.15, min = 0.3, max = 1.2 }
mu_k_over_mu_s = { dist = "uniform", min = 0.75, max = 0.95 }
[infer]
draws = 16
seating = 0.3
"#;

/// A small inference study with drawn properties for the run-level tests
/// (tests/infer.rs, tests/infer_pair.rs): 4 records of 8 s, 5 levels, 6
/// draws per kind, a 20-replicate bootstrap.
pub const INFER_SMALL_STUDY: &str = r#"name = "infer-small"
seed = 9
records = 4
[motion]
duration = 8.0
[grid]
pga = [0.15, 0.25, 0.4, 0.65, 1.0]
[uncertainty]
restitution = { dist = "uniform", min = 0.0, max = 0.4 }
mu_s = { dist = "lognormal", median = 0.6, beta = 0.15, min = 0.3, max = 1.2 }
mu_k_over_mu_s = { dist = "uniform", min = 0.75, max = 0.95 }
[infer]
draws = 6
seating = 0.3
bootstrap = 20
"#;

/// Writes `text` to `dir/name` and returns its path.
pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}
