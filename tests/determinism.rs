//! Same spec, same bits, on every platform (issue 33).
//!
//! Expectation: no code in `src/` (nor the Python bindings) calls the
//! platform's math library: every transcendental function goes through
//! `src/detmath.rs` (libm, pure Rust), so `f64::sin`, `x.exp()`, `x.powf(y)`,
//! `mul_add`, … appear nowhere else, and neither do `statrs` and `libm`
//! themselves. A planted `x.sin()` in the solver fails here, naming its file
//! and line. The vendored RustFFT and RealFFT compute their twiddles with
//! libm and have no SIMD code. `scripts/check-platforms.sh` checks the
//! outcome itself: a glibc and a musl build give byte-identical outputs.

use std::path::{Path, PathBuf};

/// `f64` methods that call the platform's math library (or fuse a
/// multiply–add); `sqrt` is correctly rounded everywhere and allowed.
const FORBIDDEN_METHODS: &[&str] = &[
    "sin", "cos", "tan", "sin_cos", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh",
    "asinh", "acosh", "atanh", "exp", "exp2", "exp_m1", "ln", "log", "log2", "log10", "ln_1p",
    "powf", "powi", "hypot", "cbrt", "mul_add", "gamma", "ln_gamma",
];

/// Paths that reach a platform-dependent implementation directly.
const FORBIDDEN_PATHS: &[&str] = &["statrs::", "libm::"];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The code of a line: nothing of a comment line, and the part before `//`
/// otherwise (string literals with `//` are rare enough to ignore).
fn code(line: &str) -> &str {
    let t = line.trim_start();
    if t.starts_with("//") {
        return "";
    }
    match line.find("//") {
        Some(i) => &line[..i],
        None => line,
    }
}

/// Each forbidden call in `line`: `.name(` as a method, `f64::name` or
/// `f32::name` as a path (`.map(f64::exp)`), or a forbidden crate path.
fn violations(line: &str) -> Vec<String> {
    let code = code(line);
    let mut found = Vec::new();
    for name in FORBIDDEN_METHODS {
        let method = format!(".{name}(");
        if code.contains(&method) {
            found.push(format!("`{method}`"));
        }
        for ty in ["f64::", "f32::"] {
            let path = format!("{ty}{name}");
            let mut rest = code;
            while let Some(i) = rest.find(&path) {
                let after = rest[i + path.len()..].chars().next();
                if !after.is_some_and(|c| c.is_alphanumeric() || c == '_') {
                    found.push(format!("`{path}`"));
                }
                rest = &rest[i + path.len()..];
            }
        }
    }
    for path in FORBIDDEN_PATHS {
        if code.contains(path) {
            found.push(format!("`{path}`"));
        }
    }
    found
}

#[test]
fn the_scanner_catches_what_it_should() {
    assert!(!violations("    let (s, c) = (theta_c - p).sin_cos();").is_empty());
    assert!(!violations("let y = x.exp() * 2.0;").is_empty());
    assert!(!violations(".map(f64::ln)").is_empty());
    assert!(!violations("let s = f64::sin(x);").is_empty());
    assert!(!violations("let z = a.mul_add(b, c);").is_empty());
    assert!(!violations("use statrs::distribution::Normal;").is_empty());
    assert!(violations("let y = dm::exp(x) + x.sqrt();").is_empty());
    assert!(violations("    // x.sin() in a comment").is_empty());
    assert!(violations("let e = x.exponent(); // not .exp(").is_empty());
    assert!(violations("let m = f64::max(a, b); f64::EPSILON").is_empty());
}

#[test]
fn no_platform_math_outside_detmath() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    rust_files(&root.join("python/src"), &mut files);
    files.sort();
    let allowed = root.join("src/detmath.rs");
    let mut report = Vec::new();
    for file in files.iter().filter(|f| **f != allowed) {
        let text = std::fs::read_to_string(file).unwrap();
        for (n, line) in text.lines().enumerate() {
            for v in violations(line) {
                let rel = file.strip_prefix(root).unwrap().display();
                report.push(format!("{rel}:{}: {v} in `{}`", n + 1, line.trim()));
            }
        }
    }
    assert!(
        report.is_empty(),
        "platform math outside src/detmath.rs (use `detmath::…`, which is the same on \
         every platform):\n{}",
        report.join("\n")
    );
}

/// The vendored FFT crates compute their twiddles with libm and carry no
/// SIMD code (whose FMA and per-CPU plans would change the bits).
#[test]
fn vendored_fft_is_deterministic() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).unwrap();
    assert!(manifest.contains("rustfft = { path = \"vendor/rustfft\" }"));
    assert!(manifest.contains("realfft = { path = \"vendor/realfft\" }"));
    for simd in ["avx", "sse", "neon", "wasm_simd"] {
        assert!(
            !root.join("vendor/rustfft/src").join(simd).exists(),
            "{simd}"
        );
    }
    let mut files = Vec::new();
    rust_files(&root.join("vendor"), &mut files);
    let mut report = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for (n, line) in text.lines().enumerate() {
            let code = code(line);
            if [".cos()", ".sin()", ".sin_cos()", ".mul_add("]
                .iter()
                .any(|m| code.contains(m))
            {
                report.push(format!("{}:{}: {}", file.display(), n + 1, line.trim()));
            }
        }
    }
    assert!(report.is_empty(), "{}", report.join("\n"));
}

/// Every planner gives the same transform, to the bit, as the scalar one.
#[test]
fn fft_planner_is_scalar() {
    use rustfft::num_complex::Complex;
    for len in [8, 1000, 1024, 2048, 3001, 4096] {
        let data: Vec<Complex<f64>> = (0..len)
            .map(|k| Complex::new((k as f64 * 0.37) % 1.0 - 0.5, (k as f64 * 0.11) % 0.7))
            .collect();
        let mut a = data.clone();
        rustfft::FftPlanner::new()
            .plan_fft_forward(len)
            .process(&mut a);
        let mut b = data;
        rustfft::FftPlannerScalar::new()
            .plan_fft_forward(len)
            .process(&mut b);
        assert!(a == b, "length {len}: the planner is not the scalar one");
    }
}
