//! The fragility surface P(LS | IM1, IM2) = Φ(a + b1 ln IM1 + b2 ln IM2)
//! (issue 38, item 4): the fit recovers a known surface within its
//! standard errors, a study asks for it in its spec or on the command line
//! after the run, and bad pairs of IMs are refused naming the file, field
//! and value.

mod common;

use std::path::Path;

use common::{rockfrag, run_spec, stderr};
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use rockfrag::detmath as dm;
use rockfrag::fragility::{SurfacePoint, fit_surface, read_surface_csv};

/// The true surface of the synthetic data sets: b1 = b2 = 1.5 (PGA and
/// PGV count alike), the median PGA at PGV/PGA = 0.1 s about 0.6 g.
const TRUTH: [f64; 3] = [5.0, 1.5, 1.5];

/// One synthetic stripe study: 8 PGA stripes from 0.2 to 1.6 g, 50 records
/// each with its own PGV/PGA (lognormal, median 0.1, σ_ln 0.5), scaled to
/// every stripe; each analysis exceeds with probability Φ(a + b1 ln PGA +
/// b2 ln PGV).
fn synthetic(seed: u64) -> Vec<SurfacePoint> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let ratios: Vec<f64> = (0..50)
        .map(|_| 0.1 * dm::exp(0.5 * dm::norm_inv_cdf(rng.random::<f64>())))
        .collect();
    let mut points = Vec::new();
    for s in 0..8 {
        let pga = 0.2 * dm::exp(dm::ln(8.0) * s as f64 / 7.0);
        for r in &ratios {
            let pgv = pga * r;
            let p = dm::norm_cdf(TRUTH[0] + TRUTH[1] * dm::ln(pga) + TRUTH[2] * dm::ln(pgv));
            points.push(SurfacePoint {
                im1: pga,
                im2: pgv,
                trials: 1,
                exceeded: u64::from(rng.random::<f64>() < p),
            });
        }
    }
    points
}

/// Over 200 synthetic data sets of 400 analyses from a known surface,
/// each coefficient lies within one standard error of the truth in 68.3 %
/// of the fits and within two in 95.4 %, within 3 binomial standard
/// deviations (√(p(1−p)/200): ±0.099 and ±0.044), and its z = (estimate −
/// truth)/SE has mean 0 within 3/√200 = 0.21 plus 0.1 for the MLE's
/// O(1/n) bias. The standard errors from the observed information are
/// then the spread of the estimates, not just numbers.
#[test]
fn the_fit_recovers_a_known_surface_within_its_standard_errors() {
    let sets = 200;
    let mut z: Vec<[f64; 3]> = Vec::new();
    for seed in 0..sets {
        let fit = fit_surface(&synthetic(seed)).unwrap_or_else(|e| panic!("set {seed}: {e}"));
        let c = fit.coefficients();
        let se = fit.se();
        z.push([0, 1, 2].map(|i| (c[i] - TRUTH[i]) / se[i]));
    }
    let n = sets as f64;
    for (i, name) in ["a", "b1", "b2"].iter().enumerate() {
        let within = |k: f64| z.iter().filter(|z| z[i].abs() < k).count() as f64 / n;
        let (one, two) = (within(1.0), within(2.0));
        let mean = z.iter().map(|z| z[i]).sum::<f64>() / n;
        eprintln!("{name}: within 1 SE {one}, within 2 SE {two}, mean z {mean:.3}");
        let tol = |p: f64| 3.0 * (p * (1.0 - p) / n).sqrt();
        assert!(
            (one - 0.683).abs() < tol(0.683),
            "{name}: {one} within 1 SE"
        );
        assert!(
            (two - 0.954).abs() < tol(0.954),
            "{name}: {two} within 2 SE"
        );
        assert!(mean.abs() < 3.0 / n.sqrt() + 0.1, "{name}: mean z {mean}");
    }
}

/// Data without IM2's effect (b2 = 0): the fit says IM2 adds nothing in
/// most data sets (|z| < 2 in about 95 %), and never calls it `ok` when
/// |b2| is within 2 SE.
#[test]
fn a_second_im_without_effect_is_said_to_add_nothing() {
    let mut nothing = 0;
    for seed in 0..50 {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(1000 + seed);
        let points: Vec<SurfacePoint> = synthetic(seed)
            .iter()
            .map(|p| {
                let prob = dm::norm_cdf(3.0 + 3.0 * dm::ln(p.im1));
                SurfacePoint {
                    exceeded: u64::from(rng.random::<f64>() < prob),
                    ..*p
                }
            })
            .collect();
        let fit = fit_surface(&points).unwrap();
        let status = rockfrag::fragility::surface_status(&fit);
        if fit.z_b2().abs() < 2.0 {
            assert_eq!(status, "second-im-adds-nothing", "seed {seed}");
            nothing += 1;
        } else {
            assert_eq!(status, "ok");
        }
    }
    // 95 % expected: at least 42 of 50 (binomial, 3 standard deviations)
    assert!(nothing >= 42, "{nothing} of 50");
}

fn small_spec(dir: &Path, im: &str) -> std::path::PathBuf {
    let text = format!(
        "name = \"small\"\nseed = 5\nrecords = 12\n\n[motion]\nduration = 10.0\n\n[grid]\n\
         width = [0.5]\naspect = [6]\nrestitution = [0.0, 0.6]\nfriction = [\"inf\"]\n\
         pga = [0.2, 0.35, 0.5, 0.8, 1.2]\n\n[fragility]\nim = {im}\nbootstrap = 20\n"
    );
    let path = dir.join(format!("spec{}.toml", im.len()));
    std::fs::write(&path, text).unwrap();
    path
}

/// A study whose spec asks for a surface (`im = ["pga", "pgv"]`) writes
/// `fragility_surface.csv` (one row per case and limit state, in the set
/// file) and a `## Fragility surface` section, while its one-IM files are
/// byte for byte those of the same study with `im = "pga"`. A refit with
/// `--im pga` removes the surface (file, set entry and section); `--im
/// pga,pgv` on the finished folder writes the same surface again without
/// running anything (outcomes.csv keeps its bytes and mtime).
#[test]
fn a_study_fits_its_surface_and_a_refit_adds_or_removes_it() {
    let dir = tempfile::tempdir().unwrap();
    let (two, one) = (dir.path().join("two"), dir.path().join("one"));
    let o = run_spec(&small_spec(dir.path(), "[\"pga\", \"PGV\"]"), &two);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("fragility_surface.csv"),
        "{}",
        stderr(&o)
    );
    let o = run_spec(&small_spec(dir.path(), "\"pga\""), &one);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in [
        "fragility.csv",
        "fragility_curves.csv",
        "fragility_bootstrap.csv",
        "fragility.xml",
        "outcomes.csv",
    ] {
        assert_eq!(
            std::fs::read(two.join(f)).unwrap(),
            std::fs::read(one.join(f)).unwrap(),
            "{f}"
        );
    }
    assert!(!one.join("fragility_surface.csv").exists());
    let surface = two.join("fragility_surface.csv");
    let rows = read_surface_csv(&surface).unwrap();
    assert_eq!(rows.len(), 2, "two cases, overturning");
    for r in &rows {
        assert_eq!(r.ims.to_string(), "pga,pgv");
        assert_eq!(r.n_analyses, 60);
        assert!(!r.status.is_empty());
        // the one-IM curve the surface implies is near the one fitted alone
        if let (Some(alone), Some(eq)) = (r.alone, r.equivalent) {
            assert!((alone.0 / eq.0 - 1.0).abs() < 0.1, "{alone:?} {eq:?}");
        }
    }
    let set = std::fs::read_to_string(two.join("fragility_set.json")).unwrap();
    assert!(set.contains("\"fragility_surface.csv\""), "{set}");
    let summary = std::fs::read_to_string(two.join("summary.md")).unwrap();
    assert!(summary.contains("## Fragility surface"), "{summary}");
    let one_summary = std::fs::read_to_string(one.join("summary.md")).unwrap();
    assert!(!one_summary.contains("## Fragility surface"));

    let outcomes = two.join("outcomes.csv");
    let before = (
        std::fs::read(&outcomes).unwrap(),
        std::fs::metadata(&outcomes).unwrap().modified().unwrap(),
    );
    let written = std::fs::read(&surface).unwrap();
    let refit = |im: &str| {
        let o = rockfrag(&[
            "fragility",
            two.to_str().unwrap(),
            "--im",
            im,
            "--bootstrap",
            "20",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
    };
    refit("pga");
    assert!(
        !surface.exists(),
        "a refit without a surface left the old one"
    );
    let set = std::fs::read_to_string(two.join("fragility_set.json")).unwrap();
    assert!(!set.contains("surface"), "{set}");
    let summary = std::fs::read_to_string(two.join("summary.md")).unwrap();
    assert!(!summary.contains("## Fragility surface"), "{summary}");
    assert_eq!(
        std::fs::read(two.join("fragility.csv")).unwrap(),
        std::fs::read(one.join("fragility.csv")).unwrap()
    );
    refit("pga,pgv");
    assert_eq!(std::fs::read(&surface).unwrap(), written);
    let summary = std::fs::read_to_string(two.join("summary.md")).unwrap();
    assert!(summary.contains("## Fragility surface"), "{summary}");
    rockfrag::fragility::check_set(&two).unwrap();
    // `rockfrag figures` draws one surface figure per row
    let figures = dir.path().join("figures");
    let o = rockfrag(&[
        "figures",
        two.to_str().unwrap(),
        "--out",
        figures.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("surface: skipped"), "{}", stderr(&o));
    for r in &rows {
        let svg = figures.join(format!("surface_{}_{}.svg", r.case.id(), r.limit_state));
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(text.contains("P = 0.5"), "{}", svg.display());
    }
    let after = (
        std::fs::read(&outcomes).unwrap(),
        std::fs::metadata(&outcomes).unwrap().modified().unwrap(),
    );
    assert!(before == after, "outcomes.csv was rewritten");
}

/// A pair written with an IM whose name holds a comma
/// (`sa-avg(0.5,2)`) is read as two IMs on the command line, and the
/// surface against it is written with the name quoted.
#[test]
fn a_pair_with_a_comma_inside_a_name_is_two_ims() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("one");
    let o = run_spec(&small_spec(dir.path(), "\"pga\""), &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = rockfrag(&[
        "fragility",
        out.to_str().unwrap(),
        "--im",
        "pga, sa-avg(0.5,2)",
        "--bootstrap",
        "0",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(out.join("fragility_surface.csv")).unwrap();
    assert!(text.contains(",pga,\"sa-avg(0.5,2.0)\",g,g,"), "{text}");
    let rows = read_surface_csv(&out.join("fragility_surface.csv")).unwrap();
    assert_eq!(rows[0].ims.second().name(), "sa-avg(0.5,2.0)");
}

/// Three IMs, one IM twice, an unknown name and a surface in an adaptive
/// run are refused in the spec before anything runs, naming the file, the
/// field and the value; on the command line, naming the flag and value.
#[test]
fn bad_pairs_are_refused_naming_file_field_and_value() {
    let dir = tempfile::tempdir().unwrap();
    for (im, says) in [
        ("[\"pga\", \"pgv\", \"pfa\"]", "not 3 (pga, pgv, pfa)"),
        ("[\"pga\", \"PGA\"]", "not pga twice"),
        ("[\"pga\", \"pgq\"]", "`pgq` is not"),
        ("[\"pga\"]", "not 1 (pga)"),
        ("[\"pga\", \"pfv\"]", "pfv needs a study on a floor"),
    ] {
        let spec = small_spec(dir.path(), im);
        let out = dir.path().join("never");
        let o = run_spec(&spec, &out);
        let e = stderr(&o);
        assert!(!o.status.success(), "{im}");
        let file = spec.file_name().unwrap().to_str().unwrap();
        assert!(
            e.contains(file) && e.contains("fragility.im") && e.contains(says),
            "{im}: {e}"
        );
        assert!(!out.join("outcomes.csv").exists());
    }
    let out = dir.path().join("one");
    assert!(
        run_spec(&small_spec(dir.path(), "\"pga\""), &out)
            .status
            .success()
    );
    let fragility = std::fs::read(out.join("fragility.csv")).unwrap();
    for (im, says) in [
        ("pga,pgv,pfa", "not 3"),
        ("pga,pga", "not pga twice"),
        ("pga,pgq", "`pgq` is not"),
    ] {
        let o = rockfrag(&["fragility", out.to_str().unwrap(), "--im", im]);
        assert!(!o.status.success());
        let e = stderr(&o);
        assert!(
            e.contains("--im") && e.contains(im) && e.contains(says),
            "{e}"
        );
    }
    let o = rockfrag(&[
        "fragility",
        out.to_str().unwrap(),
        "--im",
        "pgv",
        "--im",
        "pga,pgv",
    ]);
    assert!(!o.status.success() && stderr(&o).contains("goes first"));
    assert_eq!(std::fs::read(out.join("fragility.csv")).unwrap(), fragility);
}
