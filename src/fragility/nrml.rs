//! Export to an OpenQuake fragility model (NRML 0.5).
//!
//! A continuous `logncdf` fragility function in NRML stores the arithmetic
//! **mean and standard deviation of the intensity** at which the limit state
//! is reached, not θ and β (OpenQuake manual, *Fragility models*):
//!
//! ```text
//! mean = θ exp(β²/2),  stddev = mean √(exp(β²) − 1)
//! β = √ln(1 + (stddev/mean)²),  θ = mean / √(1 + (stddev/mean)²)
//! ```
//!
//! One limit state, `overturning`, today ([`nrml_model_string`] writes any
//! number, in order); one function per fitted case, its `id` built from the
//! case (`.` written `p`). OpenQuake knows PGA in g and PGV in
//! cm/s, so PGV curves are scaled by 100 and PGA/(g tan θc) curves are written
//! in PGA, θ_PGA = θ/(H/B) (exact for one case, whose H/B is fixed). Cases
//! that could not be fitted are left out, with an XML comment saying why.
//! The asset category is `buildings` and the loss category `contents`: the
//! blocks are the contents (equipment, artefacts) of the buildings of an
//! OpenQuake exposure. OpenQuake's reader requires both attributes.

use crate::detmath as dm;
use std::path::Path;

use super::case::CaseFit;
use super::options::{IntensityMeasure, is_nrml_name};
use crate::error::{Error, Result};
use crate::io_util::number;
use crate::io_util::write_atomic;
use crate::outcomes_csv::CaseKey;

/// `assetCategory` of the model.
pub const ASSET_CATEGORY: &str = "buildings";
/// `lossCategory` of the model: the blocks are a building's contents.
pub const LOSS_CATEGORY: &str = "contents";

/// (θ, β) → (mean, standard deviation) of the lognormal intensity, with
/// `expm1` so that small β keeps full precision.
pub fn lognormal_to_moments(median: f64, beta: f64) -> (f64, f64) {
    let b2 = beta * beta;
    let mean = median * dm::exp(0.5 * b2);
    (mean, mean * dm::exp_m1(b2).sqrt())
}

/// (mean, standard deviation) → (θ, β): the inverse of [`lognormal_to_moments`].
pub fn moments_to_lognormal(mean: f64, stddev: f64) -> (f64, f64) {
    let cv2 = dm::powi(stddev / mean, 2);
    let b2 = dm::ln_1p(cv2);
    (mean * dm::exp(-0.5 * b2), b2.sqrt())
}

/// The OpenQuake intensity measure type of a fit and the factor converting
/// its intensities to OpenQuake's unit for that type (PGA in g, PGV in cm/s).
pub fn openquake_imt(im: IntensityMeasure, key: &CaseKey) -> (&'static str, f64) {
    match im {
        IntensityMeasure::Pga => ("PGA", 1.0),
        IntensityMeasure::Pgv => ("PGV", 100.0),
        IntensityMeasure::PgaOverTan => ("PGA", 1.0 / key.aspect),
    }
}

/// The limit state rockfrag fits today.
pub const OVERTURNING: &str = "overturning";

/// One fragility function of an NRML model: a case and its lognormal
/// parameters for every limit state of the model, in the model's order.
#[derive(Clone, Debug, PartialEq)]
pub struct NrmlFunction {
    /// Function id (letters, digits, `-` and `_`).
    pub id: String,
    /// OpenQuake intensity measure type (`PGA`, `PGV`).
    pub imt: &'static str,
    /// Smallest and largest intensity of the fitted data, in OpenQuake's unit
    /// for `imt`.
    pub iml_range: (f64, f64),
    /// (mean, standard deviation) of the intensity in OpenQuake's unit, one
    /// pair per limit state, in the order of the model's limit states.
    pub params: Vec<(f64, f64)>,
}

/// What the model holds for one case: a function, or why there is none
/// (written as an XML comment).
#[derive(Clone, Debug, PartialEq)]
pub enum NrmlEntry {
    /// A fitted case.
    Function(NrmlFunction),
    /// A case that could not be fitted: its id and the reason.
    Omitted {
        /// Function id the case would have had.
        id: String,
        /// Why it is left out.
        reason: String,
    },
}

/// The entry of one case for the single limit state [`OVERTURNING`]:
/// θ and β converted to OpenQuake's unit and to (mean, stddev); `None` for a
/// case without analyses (nothing to say about it).
pub fn overturning_entry(f: &CaseFit) -> Option<NrmlEntry> {
    let id = function_id(&f.key);
    match (&f.fit, f.im_range) {
        (Ok(fit), Some((lo, hi))) => {
            let (imt, factor) = openquake_imt(f.im, &f.key);
            Some(NrmlEntry::Function(NrmlFunction {
                id,
                imt,
                iml_range: (lo * factor, hi * factor),
                params: vec![lognormal_to_moments(fit.median() * factor, fit.beta())],
            }))
        }
        (Err(reason), _) => Some(NrmlEntry::Omitted {
            id,
            reason: format!("{}: {reason}", reason.status()),
        }),
        (Ok(_), None) => None,
    }
}

/// The fragility model as NRML 0.5 text: every limit state of `fits`, in
/// the order they first appear (the spec's order of increasing severity),
/// and one function per case fitted for all of them. A case with a limit
/// state that could not be fitted stays out, with a comment saying which
/// and why (OpenQuake needs every limit state of a function).
pub fn nrml_string(fits: &[CaseFit]) -> String {
    let mut limit_states: Vec<&str> = Vec::new();
    for f in fits {
        if !limit_states.contains(&f.limit_state.as_str()) {
            limit_states.push(&f.limit_state);
        }
    }
    if limit_states.is_empty() {
        limit_states.push(OVERTURNING);
    }
    // The fits of one case, in the order of their first appearance.
    let mut cases: Vec<Vec<&CaseFit>> = Vec::new();
    for f in fits {
        match cases.iter_mut().find(|c| c[0].key == f.key) {
            Some(c) => c.push(f),
            None => cases.push(vec![f]),
        }
    }
    let entries: Vec<NrmlEntry> = cases
        .iter()
        .filter_map(|case| case_entry(case, &limit_states))
        .collect();
    nrml_model_string(&limit_states, &entries)
}

/// The entry of one case: its fits, one per limit state of `limit_states`.
fn case_entry(case: &[&CaseFit], limit_states: &[&str]) -> Option<NrmlEntry> {
    let first = case[0];
    let id = function_id(&first.key);
    let (imt, factor) = openquake_imt(first.im, &first.key);
    if factor.is_nan() {
        return Some(NrmlEntry::Omitted {
            id,
            reason: "H/B is drawn per analysis, so PGA/(g tan θc) has no single PGA \
                     equivalent; fit against PGA for OpenQuake"
                .to_string(),
        });
    }
    let mut params = Vec::with_capacity(limit_states.len());
    let mut unfitted = Vec::new();
    for ls in limit_states {
        match case.iter().find(|f| f.limit_state == *ls) {
            Some(f) => match &f.fit {
                Ok(fit) => params.push(lognormal_to_moments(fit.median() * factor, fit.beta())),
                Err(reason) => unfitted.push(format!("{ls}: {}: {reason}", reason.status())),
            },
            None => unfitted.push(format!("{ls}: no fit")),
        }
    }
    if !unfitted.is_empty() {
        if case.len() == 1 && limit_states.len() == 1 {
            // One limit state: the reason alone, as before.
            let reason = unfitted.remove(0);
            let reason = reason
                .split_once(": ")
                .map_or(reason.clone(), |(_, r)| r.to_string());
            return Some(NrmlEntry::Omitted { id, reason });
        }
        return Some(NrmlEntry::Omitted {
            id,
            reason: unfitted.join("; "),
        });
    }
    let (lo, hi) = first.im_range?;
    Some(NrmlEntry::Function(NrmlFunction {
        id,
        imt,
        iml_range: (lo * factor, hi * factor),
        params,
    }))
}

/// A fragility model of any number of limit states as NRML 0.5 text, in the
/// layout OpenQuake's reader (`openquake.risklib.read_nrml`) requires:
/// `fragilityModel` with `id`, `assetCategory` and `lossCategory`; its first
/// two children `description` and `limitStates` (names separated by spaces,
/// in order of increasing damage), then one `fragilityFunction` per fitted
/// case, whose first child is `imls` and then one `params` per limit state
/// in the order of `limit_states`. OpenQuake refuses a function with fewer
/// `params` than limit states, so a case must be fitted for every limit
/// state to be written; an [`NrmlEntry::Omitted`] becomes an XML comment.
///
/// Panics if a function's `params` do not match `limit_states` in number,
/// or a limit-state name or function id is not a word of ASCII letters,
/// digits, `_` and `-`.
pub fn nrml_model_string(limit_states: &[&str], entries: &[NrmlEntry]) -> String {
    for ls in limit_states {
        assert!(is_nrml_name(ls), "limit state {ls:?} is not an NRML name");
    }
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    s.push_str("<nrml xmlns=\"http://openquake.org/xmlns/nrml/0.5\">\n");
    // OpenQuake's model id: at most 75 characters of [A-Za-z0-9_:-]
    let model_id = match limit_states {
        [one] => format!("rockfrag-{one}"),
        _ => "rockfrag-limit-states".to_string(),
    };
    s.push_str(&format!(
        "<fragilityModel id=\"{model_id}\" assetCategory=\"{ASSET_CATEGORY}\" \
         lossCategory=\"{LOSS_CATEGORY}\">\n"
    ));
    s.push_str(&format!(
        "  <description>Free-standing rigid blocks ({}): lognormal fragility \
         fitted by maximum likelihood over stripes (rockfrag {})</description>\n",
        limit_states.join(", "),
        env!("CARGO_PKG_VERSION")
    ));
    s.push_str(&format!(
        "  <limitStates>{}</limitStates>\n",
        limit_states.join(" ")
    ));
    for e in entries {
        let f = match e {
            NrmlEntry::Function(f) => f,
            NrmlEntry::Omitted { id, reason } => {
                let why = reason.replace("--", "- -");
                s.push_str(&format!("  <!-- {id} not fitted ({why}) -->\n"));
                continue;
            }
        };
        assert!(
            is_nrml_name(&f.id),
            "function id {:?} is not an NRML id",
            f.id
        );
        assert_eq!(
            f.params.len(),
            limit_states.len(),
            "function {}: one (mean, stddev) per limit state",
            f.id
        );
        s.push_str(&format!(
            "  <fragilityFunction id=\"{}\" format=\"continuous\" shape=\"logncdf\">\n",
            f.id
        ));
        s.push_str(&format!(
            "    <imls imt=\"{}\" minIML=\"{}\" maxIML=\"{}\"/>\n",
            f.imt,
            number(f.iml_range.0),
            number(f.iml_range.1)
        ));
        for (ls, &(mean, stddev)) in limit_states.iter().zip(&f.params) {
            s.push_str(&format!(
                "    <params ls=\"{ls}\" mean=\"{}\" stddev=\"{}\"/>\n",
                number(mean),
                number(stddev)
            ));
        }
        s.push_str("  </fragilityFunction>\n");
    }
    s.push_str("</fragilityModel>\n</nrml>\n");
    s
}

/// Writes [`nrml_string`] to `path`, atomically.
pub fn write_nrml(path: &Path, fits: &[CaseFit]) -> Result<()> {
    let text = nrml_string(fits);
    write_atomic(path, |w| w.write_all(text.as_bytes())).map_err(Error::io(path))
}

/// A fragility-function id from the case: letters, digits, `-` and `_` only
/// (NRML's rule), e.g. `block-a4-w0p5-e0-inf` or
/// `block-a4-w0p5-e0p2-coulomb-ms0p6-mk0p5`.
fn function_id(k: &CaseKey) -> String {
    let num = |x: f64| {
        // A drawn parameter (NaN in a pooled case) reads `drawn`.
        let text = if x.is_nan() {
            "drawn".to_string()
        } else {
            x.to_string()
        };
        text.chars()
            .map(|c| match c {
                '.' => 'p',
                '-' => 'm',
                '+' => 'P',
                c if c.is_ascii_alphanumeric() => c,
                _ => '_',
            })
            .collect::<String>()
    };
    let mut id = format!(
        "block-a{}-w{}-e{}-{}",
        num(k.aspect),
        num(k.width),
        num(k.restitution),
        k.friction_name()
    );
    if let Some(mu) = k.mu_s() {
        id.push_str(&format!("-ms{}", num(mu)));
    }
    if let Some(mu) = k.mu_k() {
        id.push_str(&format!("-mk{}", num(mu)));
    }
    id
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::Friction;

    /// Ids keep to NRML's alphabet.
    #[test]
    fn function_ids_use_only_allowed_characters() {
        let key = CaseKey {
            aspect: 4.0,
            width: 0.5,
            restitution: 0.25,
            friction: Friction::Coulomb {
                mu_s: 0.6,
                mu_k: f64::INFINITY,
            },
        };
        let id = function_id(&key);
        assert_eq!(id, "block-a4-w0p5-e0p25-coulomb-ms0p6-mkinf");
        assert!(is_nrml_name(&id));
    }
}
