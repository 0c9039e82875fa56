//! `fragility.xml` against what OpenQuake's NRML 0.5 reader requires
//! (`openquake.risklib.read_nrml.get_fragility_model` and `ffconvert`, with
//! the validators of `openquake.hazardlib.nrml`, engine 3.26): the structure
//! attribute by attribute, and the numbers by round trip to (θ, β).
//!
//! What the reader does, and so what is checked here:
//! - `fragilityModel['id']` (simple id: `[A-Za-z0-9_:-]`, at most 75
//!   characters), `['assetCategory']`, `['lossCategory']` are read by key: a
//!   missing attribute is a `KeyError`;
//! - `~description` (not empty) and `~limitStates` (names of
//!   `[A-Za-z0-9_:-]`), and the functions are `node[2:]`: description and
//!   limitStates must be the first two element children;
//! - each function: `id` without `#`, `'`, `"`; `format` `continuous` or
//!   `discrete`; `imls` is its first child (`ff[1:]` are the curves):
//!   continuous, with `imt`, `minIML`, `maxIML` (non-negative floats) and
//!   optionally `noDamageLimit`, then exactly one `params` per limit state,
//!   `ls` equal to the limit state in order, `mean` and `stddev`
//!   non-negative floats (`shape="logncdf"` selects the lognormal CDF);
//!   discrete, with `imt` and its levels as text (strictly increasing,
//!   positive), then one `poes` per limit state with one probability per
//!   level.
//!
//! And what OpenQuake *does* with `minIML`/`maxIML` (`scientific.py`,
//! `FragilityFunctionContinuous.__call__`): it holds the curve at P(minIML)
//! below minIML and at P(maxIML) above maxIML. So every written curve must
//! be within 1e-6 of 0 at minIML and of 1 at maxIML, or OpenQuake's rates
//! are not rockfrag's (issue 28: +4,353 % with the stripes' range).
//!
//! XML comments are dropped by the reader (checked with OpenQuake on the
//! default study's file), so unfitted cases may be comments. CI does not run
//! OpenQuake; these tests encode its requirements.

use rockfrag::case::Case;
use rockfrag::fragility::{
    CaseData, CaseFit, FragilityOptions, LimitState, NrmlEntry, NrmlFunction, NrmlShape, Trial,
    fit_case, moments_to_lognormal, nrml_model_string, nrml_string,
};
use rockfrag::im::Im;
use rockfrag::solver::Friction;
use statrs::distribution::{ContinuousCDF, Normal};

const NS: &str = "http://openquake.org/xmlns/nrml/0.5";

/// A case with `n` analyses at each PGA 0.1, 0.15, …, 1.05 g of which
/// round(n Φ(ln(x/θ)/β)) overturn: deterministic, not separated for n = 40.
fn case(aspect: f64, theta: f64, beta: f64, n: usize, scale: f64) -> CaseData {
    let normal = Normal::standard();
    let mut c = CaseData {
        key: Case::fixed(aspect, 0.5, 0.0, Friction::Infinite),
        records: Vec::new(),
        trials: Vec::new(),
        failed: 0,
    };
    for i in 0..20 {
        let x = 0.1 + 0.05 * i as f64;
        let k = (n as f64 * normal.cdf((x / theta).ln() / beta)).round() as usize;
        for j in 0..n {
            c.trials.push(Trial {
                record: c.records.len(),
                level: x,
                im: x * scale,
                overturned: j < k,
                exceeded: (j < k) as u64,
            });
            c.records.push(c.records.len().to_string());
        }
    }
    c
}

fn fit(c: &CaseData, im: Im) -> CaseFit {
    fit_case(
        c,
        &FragilityOptions {
            im: Some(im),
            bootstrap: 0,
            ..FragilityOptions::default()
        },
    )
    .remove(0)
}

/// One function as OpenQuake reads it.
#[derive(Debug)]
struct Read {
    id: String,
    imt: String,
    /// (minIML, maxIML) of a continuous function, (first, last level) of a
    /// discrete one.
    iml: (f64, f64),
    /// noDamageLimit, if written.
    no_damage: Option<f64>,
    /// Continuous: (mean, stddev) per limit state.
    params: Vec<(f64, f64)>,
    /// Discrete: the levels and the poes per limit state.
    levels: Vec<f64>,
    poes: Vec<Vec<f64>>,
}

/// Element children only (the reader ignores comments and whitespace).
fn elements<'a, 'i>(n: roxmltree::Node<'a, 'i>) -> Vec<roxmltree::Node<'a, 'i>> {
    n.children().filter(|c| c.is_element()).collect()
}

fn attr<'a>(n: roxmltree::Node<'a, '_>, name: &str) -> &'a str {
    n.attribute(name).unwrap_or_else(|| {
        panic!(
            "<{}> has no {name}: OpenQuake's reader raises KeyError",
            n.tag_name().name()
        )
    })
}

/// A non-negative float, as `valid.positivefloat` accepts.
fn positive_float(n: roxmltree::Node, name: &str) -> f64 {
    let x: f64 = attr(n, name).parse().expect("a float");
    assert!(x >= 0.0 && x.is_finite(), "{name} = {x}");
    x
}

fn is_simple_id(s: &str) -> bool {
    !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == ':')
}

/// Checks `text` against every requirement of OpenQuake's reader listed in
/// the module docs, with the limit states `expected`; returns the functions.
fn read_as_openquake(text: &str, expected: &[&str]) -> Vec<Read> {
    let doc = roxmltree::Document::parse(text).expect("well-formed XML");
    let root = doc.root_element();
    assert!(root.has_tag_name((NS, "nrml")), "root is nrml 0.5");
    let models = elements(root);
    assert_eq!(models.len(), 1);
    let model = models[0];
    assert!(model.has_tag_name((NS, "fragilityModel")));
    let id = attr(model, "id");
    assert!(is_simple_id(id) && id.len() <= 75, "model id {id}");
    assert_eq!(attr(model, "assetCategory"), "buildings");
    assert_eq!(attr(model, "lossCategory"), "contents");
    let children = elements(model);
    assert!(children.len() >= 2);
    assert!(children[0].has_tag_name((NS, "description")));
    assert!(children[0].text().is_some_and(|t| !t.trim().is_empty()));
    assert!(children[1].has_tag_name((NS, "limitStates")));
    let ls: Vec<&str> = children[1].text().unwrap().split_whitespace().collect();
    assert_eq!(ls, expected);
    assert!(ls.iter().all(|l| is_simple_id(l)));
    let mut out = Vec::new();
    for f in &children[2..] {
        assert!(f.has_tag_name((NS, "fragilityFunction")));
        let id = attr(*f, "id");
        assert!(!id.contains(['#', '\'', '"']), "function id {id}");
        let parts = elements(*f);
        assert_eq!(parts.len(), 1 + ls.len(), "{id}: imls + one curve per ls");
        let imls = parts[0];
        assert!(imls.has_tag_name((NS, "imls")), "{id}: imls first");
        let no_damage = imls
            .attribute("noDamageLimit")
            .map(|_| positive_float(imls, "noDamageLimit"));
        let mut read = Read {
            id: id.to_string(),
            imt: attr(imls, "imt").to_string(),
            iml: (0.0, 0.0),
            no_damage,
            params: Vec::new(),
            levels: Vec::new(),
            poes: Vec::new(),
        };
        match attr(*f, "format") {
            "continuous" => {
                assert_eq!(attr(*f, "shape"), "logncdf");
                read.iml = (
                    positive_float(imls, "minIML"),
                    positive_float(imls, "maxIML"),
                );
                assert!(read.iml.0 < read.iml.1, "{id}: {:?}", read.iml);
                for (p, l) in parts[1..].iter().zip(&ls) {
                    assert!(p.has_tag_name((NS, "params")));
                    assert_eq!(attr(*p, "ls"), *l, "{id}: params in limit-state order");
                    read.params
                        .push((positive_float(*p, "mean"), positive_float(*p, "stddev")));
                }
            }
            "discrete" => {
                let floats = |n: roxmltree::Node| -> Vec<f64> {
                    n.text()
                        .unwrap_or("")
                        .split_whitespace()
                        .map(|t| t.parse().expect("a float"))
                        .collect()
                };
                read.levels = floats(imls);
                assert!(read.levels[0] > 0.0);
                assert!(
                    read.levels.windows(2).all(|w| w[0] < w[1]),
                    "{id}: increasing levels"
                );
                read.iml = (read.levels[0], *read.levels.last().unwrap());
                for (p, l) in parts[1..].iter().zip(&ls) {
                    assert!(p.has_tag_name((NS, "poes")));
                    assert_eq!(attr(*p, "ls"), *l, "{id}: poes in limit-state order");
                    let poes = floats(*p);
                    assert_eq!(poes.len(), read.levels.len(), "{id}: a poe per level");
                    assert!(poes.iter().all(|q| (0.0..=1.0).contains(q)));
                    read.poes.push(poes);
                }
            }
            other => panic!("{id}: format {other}"),
        }
        out.push(read);
    }
    out
}

/// The probability of a continuous function's limit state `k` at `x`
/// (OpenQuake's lognormal of mean and stddev).
fn p_at(r: &Read, k: usize, x: f64) -> f64 {
    let (theta, beta) = moments_to_lognormal(r.params[k].0, r.params[k].1);
    Normal::standard().cdf((x / theta).ln() / beta)
}

/// The file of one fitted and one unfitted case has every attribute
/// OpenQuake's reader requires (the missing `assetCategory` made it refuse
/// the file with `KeyError: node fragilityModel: 'assetCategory'`); the
/// unfitted case is a comment with its reason; the fitted case's mean and
/// stddev convert back to its θ and β to 1e-12 relative (two rounding
/// steps of `exp`, `ln_1p` and `sqrt`), and its IML range is θ·e^(∓6β)
/// with noDamageLimit = minIML.
#[test]
fn overturning_model_has_what_openquake_reads() {
    let fitted = fit(&case(4.0, 0.5, 0.4, 40, 1.0), Im::PGA);
    let mut none = case(6.0, 0.5, 0.4, 5, 1.0);
    none.trials.iter_mut().for_each(|a| {
        a.overturned = false;
        a.exceeded = 0;
    });
    let unfitted = fit(&none, Im::PGA);
    assert!(unfitted.fit.is_err());
    let text = nrml_string(&[fitted.clone(), unfitted]);
    let read = read_as_openquake(&text, &["overturning"]);
    assert_eq!(read.len(), 1);
    let r = &read[0];
    assert_eq!(r.id, "a4_w0p5_e0_inf");
    assert_eq!(r.imt, "PGA");
    let f = fitted.fit.as_ref().unwrap();
    let (lo, hi) = (
        f.median() * (-6.0 * f.beta()).exp(),
        f.median() * (6.0 * f.beta()).exp(),
    );
    assert!((r.iml.0 / lo - 1.0).abs() < 1e-12 && (r.iml.1 / hi - 1.0).abs() < 1e-12);
    assert_eq!(r.no_damage, Some(r.iml.0));
    let (theta, beta) = moments_to_lognormal(r.params[0].0, r.params[0].1);
    assert!((theta / f.median() - 1.0).abs() < 1e-12, "θ {theta}");
    assert!((beta / f.beta() - 1.0).abs() < 1e-12, "β {beta}");
    assert!(
        text.contains("<!-- a6_w0p5_e0_inf not fitted (none-overturned"),
        "{text}"
    );
}

/// Units OpenQuake knows: a PGA/(g tan θc) fit of H/B = 4 is written in PGA
/// (θ/4 g, range /4) and a PGV fit in cm/s (×100); β is unchanged. Both
/// to 1e-9 relative (the fits are of scaled data, converged to ~1e-10).
#[test]
fn other_intensity_measures_are_written_in_openquake_units() {
    let base = fit(&case(4.0, 0.5, 0.4, 40, 1.0), Im::PGA);
    let base = base.fit.unwrap();
    for (im, scale, imt, factor) in [
        (Im::PGA_OVER_TAN, 4.0, "PGA", 1.0),
        (Im::PGV, 1.0, "PGV", 100.0),
    ] {
        let f = fit(&case(4.0, 0.5, 0.4, 40, scale), im);
        let read = read_as_openquake(&nrml_string(&[f]), &["overturning"]);
        assert_eq!(read[0].imt, imt);
        let (lo, hi) = read[0].iml;
        let (m, b) = (base.median() * factor, base.beta());
        assert!(
            (lo / (m * (-6.0 * b).exp()) - 1.0).abs() < 1e-9,
            "{imt} {lo}"
        );
        assert!(
            (hi / (m * (6.0 * b).exp()) - 1.0).abs() < 1e-9,
            "{imt} {hi}"
        );
        let (theta, beta) = moments_to_lognormal(read[0].params[0].0, read[0].params[0].1);
        assert!(
            (theta / (base.median() * factor) - 1.0).abs() < 1e-9,
            "{imt} θ {theta}"
        );
        assert!((beta / base.beta() - 1.0).abs() < 1e-9, "{imt} β {beta}");
    }
}

/// Several limit states: `limitStates` lists them in the given order and
/// every function has one `params` per limit state, in that order, with the
/// numbers given (written in shortest round-trip form, so equal exactly).
#[test]
fn several_limit_states_are_written_in_order() {
    let f = |id: &str, params: Vec<(f64, f64)>| {
        NrmlEntry::Function(NrmlFunction {
            id: id.to_string(),
            imt: "PGA".into(),
            shape: NrmlShape::Continuous(params),
        })
    };
    let entries = [
        f("block-a", vec![(0.3, 0.1), (0.6, 0.2), (0.9, 0.25)]),
        NrmlEntry::Omitted {
            id: "block-b".to_string(),
            reason: "separated: uplift -- no beta".to_string(),
        },
        f("block-c", vec![(0.2, 0.05), (0.5, 0.1), (0.8, 0.3)]),
    ];
    let states = ["uplift", "sliding", "overturning"];
    let text = nrml_model_string(&states, &entries, (0.1, 1.2));
    let read = read_as_openquake(&text, &states);
    assert_eq!(read.len(), 2);
    assert_eq!(read[0].id, "block-a");
    assert_eq!(read[0].params, vec![(0.3, 0.1), (0.6, 0.2), (0.9, 0.25)]);
    assert_eq!(read[1].id, "block-c");
    assert_eq!(read[1].params, vec![(0.2, 0.05), (0.5, 0.1), (0.8, 0.3)]);
    // "--" cannot appear inside an XML comment
    assert!(text.contains("<!-- block-b not fitted (separated: uplift - - no beta) -->"));
}

/// A function with fewer params than limit states would be refused by
/// OpenQuake ("expected 2 limit states, found 1"): the writer refuses it.
#[test]
#[should_panic(expected = "one (mean, stddev) per limit state")]
fn a_function_missing_a_limit_state_is_refused() {
    let entry = NrmlEntry::Function(NrmlFunction {
        id: "block-a".to_string(),
        imt: "PGA".into(),
        shape: NrmlShape::Continuous(vec![(0.3, 0.1)]),
    });
    nrml_model_string(&["uplift", "overturning"], &[entry], (0.1, 1.2));
}

/// Issue 28: every function of a model of several cases (medians 0.25 to
/// 0.9 g, β 0.15 to 0.6) is within 1e-6 of 0 at the model's minIML and of 1
/// at its maxIML, so that OpenQuake, which holds a curve at those values
/// beyond them, computes rockfrag's curve everywhere it matters; and
/// noDamageLimit is minIML (P exactly 0 at and below it).
#[test]
fn every_function_is_0_at_min_iml_and_1_at_max_iml() {
    let fits: Vec<CaseFit> = [
        (2.0, 0.3, 0.15),
        (4.0, 0.6, 0.4),
        (6.0, 0.25, 0.6),
        (5.0, 0.9, 0.25),
    ]
    .iter()
    .map(|&(aspect, theta, beta)| fit(&case(aspect, theta, beta, 400, 1.0), Im::PGA))
    .collect();
    assert!(fits.iter().all(|f| f.fit.is_ok()));
    let read = read_as_openquake(&nrml_string(&fits), &["overturning"]);
    assert_eq!(read.len(), 4);
    for r in &read {
        let (lo, hi) = r.iml;
        assert_eq!(r.no_damage, Some(lo));
        let (p_lo, p_hi) = (p_at(r, 0, lo), p_at(r, 0, hi));
        assert!(p_lo < 1e-6, "{}: P(minIML) = {p_lo}", r.id);
        assert!(p_hi > 1.0 - 1e-6, "{}: P(maxIML) = {p_hi}", r.id);
    }
    // One range for the model: the same on every function.
    assert!(read.windows(2).all(|w| w[0].iml == w[1].iml));
}

/// A case fitted for some limit states but not all keeps its fitted curves
/// (issue 29): it is a discrete function whose fitted limit states are
/// their curves at its levels (to 1e-12) and whose unfitted one is its
/// observed fractions, never above the milder limit state; its levels span
/// the model's range, so its fitted curves are 0 at the first level and 1 at
/// the last within 1e-6; a comment says which limit state is observed. A
/// case with no limit state fitted is left out with a comment.
#[test]
fn a_case_missing_a_fit_keeps_its_fitted_limit_states() {
    let options = FragilityOptions {
        bootstrap: 0,
        limit_state: vec![
            LimitState {
                name: "rocks".into(),
                measure: "theta_max_over_theta_c".into(),
                exceeds: Some(0.5),
            },
            LimitState::overturning(),
        ],
        ..FragilityOptions::default()
    };
    // Limit state 0 exceeded as by Φ(ln(x/0.4)/0.3); overturning never.
    let mut data = case(5.0, 0.4, 0.3, 40, 1.0);
    for t in &mut data.trials {
        t.exceeded = u64::from(t.overturned);
        t.overturned = false;
    }
    let fits = fit_case(&data, &options);
    assert!(fits[0].fit.is_ok() && fits[1].fit.is_err());
    let text = nrml_string(&fits);
    let read = read_as_openquake(&text, &["rocks", "overturning"]);
    assert_eq!(read.len(), 1);
    let r = &read[0];
    assert!(!r.levels.is_empty(), "a discrete function");
    let f = fits[0].fit.as_ref().unwrap();
    for (x, p) in r.levels.iter().zip(&r.poes[0]) {
        assert!((p - f.probability(*x)).abs() < 1e-12, "{x}: {p}");
    }
    assert!(r.poes[0][0] < 1e-6 && *r.poes[0].last().unwrap() > 1.0 - 1e-6);
    assert!(
        r.poes[1].iter().all(|&p| p == 0.0),
        "never overturned: observed 0"
    );
    assert!(r.poes[1].iter().zip(&r.poes[0]).all(|(s, m)| s <= m));
    assert!(
        text.contains("observed fractions, not fitted curves, for overturning"),
        "{text}"
    );
    // Nothing fitted: left out.
    let mut none = data.clone();
    none.trials.iter_mut().for_each(|t| t.exceeded = 0);
    let fits = fit_case(&none, &options);
    let text = nrml_string(&fits);
    assert!(read_as_openquake(&text, &["rocks", "overturning"]).is_empty());
    assert!(
        text.contains("<!-- a5_w0p5_e0_inf not fitted (rocks: none-overturned"),
        "{text}"
    );
}
