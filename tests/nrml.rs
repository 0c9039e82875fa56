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
//! - each function: `id` without `#`, `'`, `"`; `format` `continuous`;
//!   `imls` is its first child (`ff[1:]` are the params), with `imt`,
//!   `minIML`, `maxIML` (non-negative floats); then exactly one `params` per
//!   limit state, `ls` equal to the limit state in order, `mean` and `stddev`
//!   non-negative floats. `shape="logncdf"` selects the lognormal CDF.
//!
//! XML comments are dropped by the reader (checked with OpenQuake on the
//! default study's file), so unfitted cases may be comments. CI does not run
//! OpenQuake; these tests encode its requirements.

use rockfrag::case::Case;
use rockfrag::fragility::{
    CaseData, CaseFit, FragilityOptions, IntensityMeasure, NrmlEntry, NrmlFunction, Trial,
    fit_case, moments_to_lognormal, nrml_model_string, nrml_string,
};
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
                pga: x,
                im: x * scale,
                overturned: j < k,
                exceeded: (j < k) as u64,
            });
            c.records.push(c.records.len().to_string());
        }
    }
    c
}

fn fit(c: &CaseData, im: IntensityMeasure) -> CaseFit {
    fit_case(
        c,
        &FragilityOptions {
            im,
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
    iml: (f64, f64),
    params: Vec<(f64, f64)>,
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
        assert_eq!(attr(*f, "format"), "continuous");
        assert_eq!(attr(*f, "shape"), "logncdf");
        let parts = elements(*f);
        assert_eq!(parts.len(), 1 + ls.len(), "{id}: imls + one params per ls");
        let imls = parts[0];
        assert!(imls.has_tag_name((NS, "imls")), "{id}: imls first");
        let iml = (
            positive_float(imls, "minIML"),
            positive_float(imls, "maxIML"),
        );
        assert!(iml.0 < iml.1, "{id}: {iml:?}");
        let mut params = Vec::new();
        for (p, l) in parts[1..].iter().zip(&ls) {
            assert!(p.has_tag_name((NS, "params")));
            assert_eq!(attr(*p, "ls"), *l, "{id}: params in limit-state order");
            params.push((positive_float(*p, "mean"), positive_float(*p, "stddev")));
        }
        out.push(Read {
            id: id.to_string(),
            imt: attr(imls, "imt").to_string(),
            iml,
            params,
        });
    }
    out
}

/// The file of one fitted and one unfitted case has every attribute
/// OpenQuake's reader requires (the missing `assetCategory` made it refuse
/// the file with `KeyError: node fragilityModel: 'assetCategory'`); the
/// unfitted case is a comment with its reason; the fitted case's mean and
/// stddev convert back to its θ and β to 1e-12 relative (two rounding
/// steps of `exp`, `ln_1p` and `sqrt`), and its IML range is the data's.
#[test]
fn overturning_model_has_what_openquake_reads() {
    let fitted = fit(&case(4.0, 0.5, 0.4, 40, 1.0), IntensityMeasure::Pga);
    let mut none = case(6.0, 0.5, 0.4, 5, 1.0);
    none.trials.iter_mut().for_each(|a| {
        a.overturned = false;
        a.exceeded = 0;
    });
    let unfitted = fit(&none, IntensityMeasure::Pga);
    assert!(unfitted.fit.is_err());
    let text = nrml_string(&[fitted.clone(), unfitted]);
    let read = read_as_openquake(&text, &["overturning"]);
    assert_eq!(read.len(), 1);
    let r = &read[0];
    assert_eq!(r.id, "block-a4-w0p5-e0-inf");
    assert_eq!(r.imt, "PGA");
    assert_eq!(r.iml, fitted.im_range.unwrap());
    let f = fitted.fit.as_ref().unwrap();
    let (theta, beta) = moments_to_lognormal(r.params[0].0, r.params[0].1);
    assert!((theta / f.median() - 1.0).abs() < 1e-12, "θ {theta}");
    assert!((beta / f.beta() - 1.0).abs() < 1e-12, "β {beta}");
    assert!(
        text.contains("<!-- block-a6-w0p5-e0-inf not fitted (none-overturned"),
        "{text}"
    );
}

/// Units OpenQuake knows: a PGA/(g tan θc) fit of H/B = 4 is written in PGA
/// (θ/4 g, range /4) and a PGV fit in cm/s (×100); β is unchanged. Both
/// to 1e-9 relative (the fits are of scaled data, converged to ~1e-10).
#[test]
fn other_intensity_measures_are_written_in_openquake_units() {
    let base = fit(&case(4.0, 0.5, 0.4, 40, 1.0), IntensityMeasure::Pga);
    let base = base.fit.unwrap();
    for (im, scale, imt, factor) in [
        (IntensityMeasure::PgaOverTan, 4.0, "PGA", 1.0),
        (IntensityMeasure::Pgv, 1.0, "PGV", 100.0),
    ] {
        let f = fit(&case(4.0, 0.5, 0.4, 40, scale), im);
        let read = read_as_openquake(&nrml_string(&[f]), &["overturning"]);
        assert_eq!(read[0].imt, imt);
        let (lo, hi) = read[0].iml;
        assert!((lo / (0.1 * factor) - 1.0).abs() < 1e-12, "{imt} {lo}");
        assert!((hi / (1.05 * factor) - 1.0).abs() < 1e-12, "{imt} {hi}");
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
            imt: "PGA",
            iml_range: (0.1, 1.2),
            params,
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
    let text = nrml_model_string(&states, &entries);
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
        imt: "PGA",
        iml_range: (0.1, 1.2),
        params: vec![(0.3, 0.1)],
    });
    nrml_model_string(&["uplift", "overturning"], &[entry]);
}
