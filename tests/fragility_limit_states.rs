//! Limit states of the fragility fit: one lognormal curve per case and limit
//! state, recovered from simulated exceedances; curves of one case that
//! cross are refitted with one β and then do not cross; and a small study
//! with three limit states whose fitted medians rise with severity.

mod common;

use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use rockfrag::case::Case;
use rockfrag::fragility::{
    BetaModel, CaseData, CaseFit, Caveat, FitStatus, FragilityOptions, FragilityRow, LimitState,
    LognormalFit, Trial, curves_cross, fit_case, fit_common_beta, fit_lognormal, nrml_string,
    read_outcomes_for,
};
use rockfrag::solver::Friction;
use statrs::distribution::{ContinuousCDF, Normal};

/// The three limit states of the issue, in order of severity.
fn limit_states() -> Vec<LimitState> {
    let ls = |name: &str, measure: &str, exceeds| LimitState {
        name: name.into(),
        measure: measure.into(),
        exceeds,
    };
    vec![
        ls("uplift", "theta_max_over_theta_c", Some(0.0)),
        ls("slides-5cm", "slip_max", Some(0.05)),
        ls("overturning", "overturned", None),
    ]
}

/// A case whose analyses exceed limit state k with probability
/// Φ(ln(x/θ_k)/β_k), nested through one uniform draw per analysis (exceeding
/// k means U < P_k(x)), every analysis its own record. `ims` gives each
/// analysis its intensity (stripes: repeated levels; continuous: all distinct).
fn simulated_case(curves: &[(f64, f64)], ims: &[f64], seed: u64) -> CaseData {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let normal = Normal::standard();
    let mut case = CaseData {
        key: Case::fixed(4.0, 0.5, 0.0, Friction::Infinite),
        records: Vec::new(),
        trials: Vec::new(),
        failed: 0,
    };
    for &x in ims {
        let u: f64 = rng.random();
        let mut exceeded = 0u64;
        for (k, &(theta, beta)) in curves.iter().enumerate() {
            exceeded |= u64::from(u < normal.cdf((x / theta).ln() / beta)) << k;
        }
        case.trials.push(Trial {
            record: case.records.len(),
            level: x,
            im: x,
            overturned: exceeded >> (curves.len() - 1) & 1 == 1,
            exceeded,
        });
        case.records.push(case.records.len().to_string());
    }
    case
}

/// 20 stripes, 0.05 … 1.0 g, `per` analyses each.
fn stripes(per: usize) -> Vec<f64> {
    (1..=20)
        .flat_map(|i| std::iter::repeat_n(0.05 * i as f64, per))
        .collect()
}

/// `n` intensities drawn log-uniformly in [0.05, 1] g: no two alike.
fn continuous(n: usize, seed: u64) -> Vec<f64> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    (0..n)
        .map(|_| (0.05f64.ln() + rng.random::<f64>() * 20f64.ln()).exp())
        .collect()
}

fn options(bootstrap: usize) -> FragilityOptions {
    FragilityOptions {
        bootstrap,
        limit_state: limit_states(),
        ..FragilityOptions::default()
    }
}

/// True (θ, β) of uplift, sliding and overturning: β falls with severity, so
/// the curves meet only beyond 2 g, outside the data (no common β needed).
const NESTED: [(f64, f64); 3] = [(0.15, 0.5), (0.3, 0.4), (0.5, 0.3)];

/// From 6000 simulated analyses, on stripes and at continuous intensities,
/// each limit state's separate fit recovers its θ and β within 4 of its
/// delta-method standard errors (those being below 6 % of the value, so the
/// check has teeth); the fits are separate and their medians rise.
#[test]
fn each_limit_state_recovers_its_median_and_beta() {
    for (label, ims) in [
        ("stripes", stripes(300)),
        ("continuous", continuous(6000, 7)),
    ] {
        let case = simulated_case(&NESTED, &ims, 11);
        let fits = fit_case(&case, &options(0));
        assert_eq!(fits.len(), 3);
        let mut last_median = 0.0;
        for (f, (ls, &(theta, beta))) in fits.iter().zip(limit_states().iter().zip(&NESTED)) {
            assert_eq!(f.limit_state, ls.name);
            assert_eq!(f.beta_model, BetaModel::Separate, "{label} {}", ls.name);
            let fit = f.fit.as_ref().unwrap();
            eprintln!(
                "{label} {}: θ = {:.4} ± {:.4} (true {theta}), β = {:.4} ± {:.4} (true {beta})",
                ls.name,
                fit.median(),
                fit.se_median(),
                fit.beta(),
                fit.se_beta()
            );
            assert!(fit.se_median() < 0.06 * fit.median());
            assert!(fit.se_beta() < 0.06 * fit.beta());
            assert!((fit.median() - theta).abs() < 4.0 * fit.se_median());
            assert!((fit.beta() - beta).abs() < 4.0 * fit.se_beta());
            assert!(fit.median() > last_median);
            last_median = fit.median();
        }
        assert_eq!(fits[2].n_exceeded, fits[2].n_overturned);
        assert!(fits[0].n_exceeded > fits[1].n_exceeded);
    }
}

/// Two limit states whose separate fits cross (the severe one much wider:
/// true θ, β = 0.3 g, 0.3 and 0.4 g, 0.8, meeting at 0.25 g where P ≈ 0.28)
/// are refitted with one β: both say `common`, their β are one number, the
/// medians keep their order, the more severe curve never lies above the
/// other on the grid, and the joint fit is the constrained maximum (a nudge
/// of any parameter lowers the summed log-likelihood, which is below the
/// separate fits' sum). Its bootstrap refits jointly: every replicate has
/// one β, so the two β intervals are the same.
#[test]
fn crossing_curves_are_refitted_with_one_beta() {
    let truth = [(0.3, 0.3), (0.4, 0.8)];
    let case = simulated_case(&truth, &stripes(200), 3);
    let (o0, o1) = (case.observations(0), case.observations(1));
    let (s0, s1) = (fit_lognormal(&o0).unwrap(), fit_lognormal(&o1).unwrap());
    assert!(
        curves_cross(&s0, &s1, (0.05, 1.0)),
        "the premise: separate fits cross"
    );

    let opts = FragilityOptions {
        bootstrap: 200,
        limit_state: limit_states()[1..].to_vec(),
        ..FragilityOptions::default()
    };
    let fits: Vec<CaseFit> = fit_case(&case, &opts);
    let f: Vec<&LognormalFit> = fits.iter().map(|f| f.fit.as_ref().unwrap()).collect();
    eprintln!(
        "separate: θ {:.4} {:.4}, β {:.4} {:.4}; common: θ {:.4} {:.4}, β {:.4}",
        s0.median(),
        s1.median(),
        s0.beta(),
        s1.beta(),
        f[0].median(),
        f[1].median(),
        f[0].beta()
    );
    assert!(fits.iter().all(|f| f.beta_model == BetaModel::Common));
    assert_eq!(f[0].b, f[1].b);
    assert!(f[0].median() < f[1].median());
    assert!(!curves_cross(f[0], f[1], (0.05, 1.0)));
    let (c0, c1) = (
        fits[0].curve.as_ref().unwrap(),
        fits[1].curve.as_ref().unwrap(),
    );
    for (p0, p1) in c0.probability.iter().zip(&c1.probability) {
        assert!(p1 <= p0, "{p1} > {p0}");
    }

    let joint = |a0: f64, a1: f64, b: f64| common::loglik(&o0, a0, b) + common::loglik(&o1, a1, b);
    let best = joint(f[0].a, f[1].a, f[0].b);
    for (d0, d1, db) in [
        (1e-4, 0.0, 0.0),
        (-1e-4, 0.0, 0.0),
        (0.0, 1e-4, 0.0),
        (0.0, -1e-4, 0.0),
        (0.0, 0.0, 1e-3),
        (0.0, 0.0, -1e-3),
    ] {
        assert!(joint(f[0].a + d0, f[1].a + d1, f[0].b + db) < best);
    }
    assert!(best < common::loglik(&o0, s0.a, s0.b) + common::loglik(&o1, s1.a, s1.b));
    // The per-limit-state log-likelihoods (constants included) sum to the
    // joint one: each differs from `loglik` by its own constant only.
    let separate_constants = (s0.loglik - common::loglik(&o0, s0.a, s0.b))
        + (s1.loglik - common::loglik(&o1, s1.a, s1.b));
    assert!((f[0].loglik + f[1].loglik - best - separate_constants).abs() < 1e-6);

    let (b0, b1) = (
        fits[0].bootstrap.as_ref().unwrap(),
        fits[1].bootstrap.as_ref().unwrap(),
    );
    assert_eq!(b0.beta, b1.beta);
    assert_eq!(b0.fitted, b1.fitted);
    assert!(b0.fitted > 190, "{} of 200 replicates fitted", b0.fitted);
    let beta = b0.beta.unwrap();
    assert!(beta.lo < f[0].beta() && f[0].beta() < beta.hi);
}

/// With one limit state, the common-β fit is the ordinary fit (to 1e-9).
#[test]
fn common_beta_fit_of_one_limit_state_is_the_ordinary_fit() {
    let case = simulated_case(&[(0.5, 0.4)], &stripes(50), 5);
    let obs = case.observations(0);
    let one = fit_lognormal(&obs).unwrap();
    let joint = fit_common_beta(&[&obs]).unwrap();
    assert_eq!(joint.len(), 1);
    let j = joint[0];
    for (x, y) in [
        (one.median(), j.median()),
        (one.beta(), j.beta()),
        (one.loglik, j.loglik),
        (one.se_median(), j.se_median()),
        (one.se_beta(), j.se_beta()),
    ] {
        assert!((x / y - 1.0).abs() < 1e-9, "{x} vs {y}");
    }
}

/// `rockfrag run` on a small spec with three limit states (rocking beyond
/// 0.2 θc, sliding beyond 5 cm, overturning): one fragility.csv row per limit
/// state, in the spec's order, all fitted (status `ok`, or
/// `extrapolated-above` for a median above the strongest stripe), with the fitted medians rising
/// with severity and the exceedance counts falling; each count is what
/// outcomes.csv gives (overturned, or the measure above its threshold); the
/// curves file has 101 points per limit state; fragility.xml holds the
/// three limit states in order, with one `params` per limit state in the
/// case's function (what OpenQuake's reader requires), each the fitted θ
/// and β as (mean, stddev) of the lognormal (round trip to 1e-9).
#[test]
fn a_study_with_three_limit_states_has_medians_rising_with_severity() {
    let spec = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/specs/limit-states.toml"
    );
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = common::rockfrag(&["run", spec, "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", common::stderr(&o));

    let mut reader = csv::Reader::from_path(out.join("fragility.csv")).unwrap();
    let header = reader.headers().unwrap().clone();
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
    let names: Vec<&str> = rows.iter().map(|r| &r[col("limit_state")]).collect();
    // (5 mm: with the free motion after the record, every block of this
    // study that slides 5 cm also overturns, so that limit state was the
    // overturning's)
    assert_eq!(names, ["rocks-20pc", "slides-5mm", "overturning"]);
    let mut last = (0.0, usize::MAX);
    for r in &rows {
        let median: f64 = r[col("median")].parse().unwrap();
        // Fitted; a median above the strongest stripe (1.2 g) is flagged.
        let want = if median > 1.2 {
            "extrapolated-above"
        } else {
            "ok"
        };
        assert_eq!(&r[col("status")], want, "{r:?}");
        let exceeded: usize = r[col("n_exceeded")].parse().unwrap();
        eprintln!(
            "{}: θ = {median:.3} g, {exceeded} exceeded",
            &r[col("limit_state")]
        );
        assert!(median > last.0 && exceeded < last.1, "{r:?}");
        last = (median, exceeded);
    }

    // The counts, recomputed from outcomes.csv.
    let mut outcomes = csv::Reader::from_path(out.join("outcomes.csv")).unwrap();
    let oh = outcomes.headers().unwrap().clone();
    let oc = |name: &str| oh.iter().position(|h| h == name).unwrap();
    let (mut rocks, mut slides, mut overturned) = (0, 0, 0);
    for r in outcomes.records().map(Result::unwrap) {
        let o = &r[oc("overturned")] == "true";
        let theta: f64 = r[oc("theta_max_over_theta_c")].parse().unwrap();
        let slip: f64 = r[oc("slip_max")].parse().unwrap();
        rocks += usize::from(o || theta > 0.2);
        slides += usize::from(o || slip > 0.005);
        overturned += usize::from(o);
    }
    let count = |i: usize| rows[i][col("n_exceeded")].parse::<usize>().unwrap();
    assert_eq!([count(0), count(1), count(2)], [rocks, slides, overturned]);

    let curves = std::fs::read_to_string(out.join("fragility_curves.csv")).unwrap();
    for name in names {
        let n = curves
            .lines()
            .filter(|l| l.split(',').nth(7) == Some(name))
            .count();
        assert_eq!(n, 101, "{name}");
    }
    let xml = std::fs::read_to_string(out.join("fragility.xml")).unwrap();
    let doc = roxmltree::Document::parse(&xml).unwrap();
    let ls = doc
        .descendants()
        .find(|n| n.has_tag_name("limitStates"))
        .unwrap();
    assert_eq!(
        ls.text().unwrap().trim(),
        "rocks-20pc slides-5mm overturning"
    );
    let functions: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("fragilityFunction"))
        .collect();
    assert_eq!(functions.len(), 1, "{xml}");
    let params: Vec<_> = functions[0]
        .children()
        .filter(|n| n.has_tag_name("params"))
        .collect();
    assert_eq!(params.len(), 3, "{xml}");
    for (p, row) in params.iter().zip(&rows) {
        assert_eq!(p.attribute("ls"), Some(&row[col("limit_state")]));
        let mean: f64 = p.attribute("mean").unwrap().parse().unwrap();
        let sd: f64 = p.attribute("stddev").unwrap().parse().unwrap();
        let (median, beta) = rockfrag::fragility::moments_to_lognormal(mean, sd);
        let want_m: f64 = row[col("median")].parse().unwrap();
        let want_b: f64 = row[col("beta")].parse().unwrap();
        assert!(
            (median - want_m).abs() < 1e-9 * want_m,
            "{median} vs {want_m}"
        );
        assert!((beta - want_b).abs() < 1e-9 * want_b, "{beta} vs {want_b}");
    }

    // A measure the spec accepts but this file lacks (time in mode is off)
    // is an error naming the column and the limit state.
    let options = FragilityOptions {
        limit_state: vec![LimitState {
            name: "rocks-1s".into(),
            measure: "t_rock".into(),
            exceeds: Some(1.0),
        }],
        ..FragilityOptions::default()
    };
    let err = read_outcomes_for(&out.join("outcomes.csv"), &options)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("no `t_rock` column") && err.contains("rocks-1s"),
        "{err}"
    );
}

/// A lognormal fit with median θ and dispersion β (probit a = −ln θ/β,
/// b = 1/β).
fn lognormal(theta: f64, beta: f64) -> LognormalFit {
    LognormalFit {
        a: -theta.ln() / beta,
        b: 1.0 / beta,
        cov: [[0.0; 2]; 2],
        loglik: 0.0,
        iterations: 0,
    }
}

/// Issue 37: curves that cross inside the stripes' range at probabilities
/// below the 10⁻³ tolerance were let pass, and went to OpenQuake and
/// pelicun, whose damage state P(LS₁) − P(LS₂) is then negative there.
/// θ, β = 0.5 g, 0.2 and 0.8 g, 0.3 meet at u* = (0.3 ln 0.5 − 0.2 ln 0.8)/0.1,
/// 0.195 g, where P ≈ 1.3·10⁻⁶: inside stripes from 0.1 g it counts; below
/// stripes from 0.25 g (extrapolated, P below the tolerance) it does not;
/// and the meeting of the 0.3/0.3 and 0.4/0.8 g (P ≈ 0.28) counts
/// wherever the stripes start.
#[test]
fn a_crossing_within_the_stripes_counts_however_small_the_probabilities() {
    let (mild, severe) = (lognormal(0.5, 0.2), lognormal(0.8, 0.3));
    let u_star: f64 = (0.3 * 0.5f64.ln() - 0.2 * 0.8f64.ln()) / 0.1;
    let p = mild.probability(u_star.exp());
    assert!(
        (u_star.exp() - 0.195).abs() < 1e-3 && p < 1e-5,
        "{} {p}",
        u_star.exp()
    );
    assert!(curves_cross(&mild, &severe, (0.1, 1.0)));
    assert!(!curves_cross(&mild, &severe, (0.25, 1.0)));
    assert!(curves_cross(
        &lognormal(0.3, 0.3),
        &lognormal(0.4, 0.8),
        (0.3, 1.0)
    ));
}

/// Simulated exceedances of two nested limit states whose true curves
/// cross in the lower tail inside the stripes (0.5 g, 0.2 and 0.8 g, 0.3,
/// 3,000 analyses on stripes from 0.05 g): the separate fits cross there,
/// so the case is refitted with one β, and its curves are then in order
/// (no caveat). Limit states whose data are in the reverse order (the
/// "severe" one, θ 0.5 g, exceeded more often than the "mild" one, θ
/// 0.8 g) are flagged `out-of-order` on the severe one: fragility.csv says
/// so, the row keeps its numbers (`fit()`), and fragility.xml leaves the
/// case out with a comment naming both limit states.
#[test]
fn curves_out_of_order_within_the_stripes_are_flagged_and_left_out_of_the_model() {
    let opts = FragilityOptions {
        bootstrap: 0,
        limit_state: limit_states()[..2].to_vec(),
        ..FragilityOptions::default()
    };
    let case = simulated_case(&[(0.5, 0.2), (0.8, 0.3)], &stripes(150), 17);
    let (s0, s1) = (
        fit_lognormal(&case.observations(0)).unwrap(),
        fit_lognormal(&case.observations(1)).unwrap(),
    );
    assert!(
        curves_cross(&s0, &s1, (0.05, 1.0)),
        "the premise: separate fits cross within the stripes"
    );
    let fits = fit_case(&case, &opts);
    assert!(fits.iter().all(|f| f.beta_model == BetaModel::Common));
    assert!(fits.iter().all(|f| f.caveat.is_none()), "{fits:?}");

    // The reverse: "slides-5cm" (listed as the more severe) at θ 0.5 g is
    // exceeded more often than "uplift" at θ 0.8 g.
    let case = simulated_case(&[(0.8, 0.3), (0.5, 0.3)], &stripes(150), 19);
    let fits = fit_case(&case, &opts);
    assert_eq!(fits[0].caveat, None);
    assert_eq!(fits[1].caveat, Some(Caveat::OutOfOrder));
    let rows: Vec<FragilityRow> = fits.iter().map(FragilityRow::from_fit).collect();
    assert_eq!(rows[1].status, FitStatus::Caveat(Caveat::OutOfOrder));
    let (m, _) = rows[1]
        .fit()
        .expect("an out-of-order curve keeps its numbers");
    assert!((m / 0.5 - 1.0).abs() < 0.1, "{m}");
    let note = rockfrag::fragility::caveat_note(&fits, 1).unwrap();
    assert!(
        note.contains("more likely than uplift (listed as milder)"),
        "{note}"
    );
    let xml = nrml_string(&fits);
    assert!(
        xml.contains(
            "left out: its limit states are out of order: slides-5cm is more likely than uplift"
        ) && !xml.contains("<fragilityFunction"),
        "{xml}"
    );
}

/// The fixture `limit-states-out-of-order.toml` through the command line:
/// a slender block on firm friction rocks past half its overturning angle
/// long before it slides 5 cm, yet lists sliding first. fragility.csv marks
/// rocks-half `out-of-order`, the console and summary.md say which milder
/// limit state it is more likely than and what to do, fragility.xml leaves
/// the case out, and both exports refuse a model with nothing left in it,
/// naming the case and why.
#[test]
fn limit_states_out_of_order_are_said_and_not_exported() {
    let spec = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/specs/limit-states-out-of-order.toml"
    );
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = common::rockfrag(&["run", spec, "--out", out.to_str().unwrap()]);
    let err = common::stderr(&o);
    assert!(o.status.success(), "{err}");
    let rows = rockfrag::fragility::read_fragility_csv(&out.join("fragility.csv")).unwrap();
    let severe = rows.iter().find(|r| r.limit_state == "rocks-half").unwrap();
    assert_eq!(severe.status, FitStatus::Caveat(Caveat::OutOfOrder));
    let want = "rocks-half: out of order: more likely than slides-5cm (listed as milder)";
    assert!(err.contains(want), "{err}");
    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(
        summary.contains("**out of order: more likely than slides-5cm (listed as milder)"),
        "{summary}"
    );
    let xml = std::fs::read_to_string(out.join("fragility.xml")).unwrap();
    assert!(
        xml.contains("left out: its limit states are out of order"),
        "{xml}"
    );
    let hazard = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/hazard/hazard_curve-mean-PGA_example.csv"
    );
    for args in [
        vec!["export", "pelicun", out.to_str().unwrap()],
        vec![
            "export",
            "openquake",
            out.to_str().unwrap(),
            "--hazard",
            hazard,
            "--site",
            "0",
        ],
    ] {
        let dest = tmp.path().join(format!("x-{}", args[1]));
        let mut args = args.clone();
        args.extend(["--out", dest.to_str().unwrap()]);
        let o = common::rockfrag(&args);
        let err = common::stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert!(err.contains("out-of-order"), "{err}");
    }
}
