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
//! Every limit state of the fit, in order of severity, and one function per
//! case, its `id` the case's id ([`Case::id`]). OpenQuake knows PGA in g and
//! PGV in cm/s, so PGV curves are scaled by 100 and PGA/(g tan θc) curves
//! are written in PGA, θ_PGA = θ/(H/B) (exact for one case, whose H/B is
//! fixed). The asset category is `buildings` and the loss category
//! `contents`: the blocks are the contents (equipment, artefacts) of the
//! buildings of an OpenQuake exposure. OpenQuake's reader requires both.
//!
//! ## What `minIML`, `maxIML` and `noDamageLimit` mean to OpenQuake
//!
//! They are not a record of the fitted range: OpenQuake computes with them
//! (`openquake/risklib/scientific.py`, 3.26). A continuous function is
//! **held** at P(minIML) below minIML and at P(maxIML) above maxIML
//! (`FragilityFunctionContinuous.__call__` clamps the intensities before
//! the lognormal CDF), and is 0 where the clamped intensity is at or below
//! noDamageLimit. Written as the range of the fitted stripes (as rockfrag
//! did), a curve at 2–10 % at the lowest stripe was applied to every
//! hazard level below it, where the annual rates are largest: OpenQuake's
//! rates came out up to 44 times rockfrag's. So the model's range is where
//! every function is ≈ 0 and ≈ 1: minIML = min θ·e^(−6β), maxIML =
//! max θ·e^(+6β) over every fitted limit state of every case (P = Φ(∓6) <
//! 10⁻⁹ there), one range for the whole model; noDamageLimit = minIML, so
//! below it P is exactly 0. A discrete function (below) is held at its last
//! poe above its last level and interpolated linearly from 0 at its
//! noDamageLimit to its first level, so its levels span the same range.
//!
//! ## A case with a limit state that could not be fitted
//!
//! OpenQuake needs every limit state of the model in every function. A case
//! fitted for some limit states but not all is written as a **discrete**
//! function, so that its fitted curves are kept: levels log-spaced over the
//! model's range (and the case's stripes), each fitted limit state its
//! curve at the levels, and each unfitted one its observed exceedance
//! fractions at the stripes (interpolated between them in ln IM, rising
//! linearly in ln IM from 0 at the lowest level to the lowest stripe, held
//! beyond the highest), each limit state no more likely than the milder
//! one before it. An XML comment before the function says which limit
//! state is observed, not fitted, and why. A case with no fitted limit
//! state is left out, with a comment saying why; so is a case whose limit
//! states are out of order (a more severe one more likely than a milder
//! one within the stripes, [`Caveat::OutOfOrder`]), for which OpenQuake
//! would compute a negative damage-state probability.

use crate::detmath as dm;
use std::path::Path;

use super::case::{CaseFit, first_inversion};
use super::options::is_nrml_name;
use super::status::Caveat;
use crate::error::{Error, Result};
use crate::im::OpenQuakeImt;
use crate::io_util::number;
use crate::io_util::write_atomic;

/// `assetCategory` of the model.
pub(crate) const ASSET_CATEGORY: &str = "buildings";
/// `lossCategory` of the model: the blocks are a building's contents.
pub(crate) const LOSS_CATEGORY: &str = "contents";

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

/// The limit state of a fit that names none.
pub(crate) const OVERTURNING: &str = "overturning";

/// How far (in β) beyond its median a fitted curve is taken as 0 or 1: the
/// model's minIML and maxIML are θ·e^(∓Kβ), where P = Φ(∓6) < 10⁻⁹.
pub const IML_SIGMAS: f64 = 6.0;

/// Levels per decade of a discrete function.
const DISCRETE_LEVELS_PER_DECADE: f64 = 40.0;

/// The shape of one fragility function, its limit states in the model's
/// order.
#[derive(Clone, Debug, PartialEq)]
pub enum NrmlShape {
    /// Lognormal: (mean, standard deviation) of the intensity in
    /// OpenQuake's unit, one pair per limit state.
    Continuous(Vec<(f64, f64)>),
    /// Probabilities of exceedance at `imls` (OpenQuake's unit), one list
    /// per limit state.
    Discrete {
        /// The intensity levels, increasing.
        imls: Vec<f64>,
        /// One list of probabilities per limit state, one per level.
        poes: Vec<Vec<f64>>,
        /// Which limit states are observed fractions, not fitted curves,
        /// and why (written as a comment).
        note: String,
    },
}

/// One fragility function of an NRML model: a case and its curves for
/// every limit state of the model.
#[derive(Clone, Debug, PartialEq)]
pub struct NrmlFunction {
    /// Function id: the case's id ([`Case::id`]).
    pub id: String,
    /// OpenQuake intensity measure type (`PGA`, `PGV`).
    pub imt: String,
    /// The curves.
    pub shape: NrmlShape,
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

/// The fragility model as NRML 0.5 text: every limit state of `fits`, in
/// the order they first appear (the spec's order of increasing severity),
/// and one function per case (see the docs of `src/fragility/nrml.rs` for a case with
/// a limit state that could not be fitted).
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
    let range = model_range(fits);
    let entries: Vec<NrmlEntry> = cases
        .iter()
        .filter_map(|case| case_entry(case, &limit_states, range))
        .collect();
    nrml_model_string(&limit_states, &entries, range)
}

/// The model's (minIML, maxIML) in OpenQuake's unit: θ·e^(∓6β) over every
/// fitted limit state of every case ([`IML_SIGMAS`]); the range of the
/// analyses' intensities when nothing was fitted.
pub fn model_range(fits: &[CaseFit]) -> (f64, f64) {
    let mut range = (f64::INFINITY, 0.0_f64);
    for f in fits {
        let (Ok(fit), Some(oq)) = (&f.fit, f.im.openquake_for(f.key.aspect.fixed())) else {
            continue;
        };
        let factor = oq.factor;
        let (theta, beta) = (fit.median() * factor, fit.beta());
        range.0 = range.0.min(theta * dm::exp(-IML_SIGMAS * beta));
        range.1 = range.1.max(theta * dm::exp(IML_SIGMAS * beta));
    }
    if range.0.is_finite() {
        return range;
    }
    for f in fits {
        if let (Some((lo, hi)), Some(oq)) = (f.im_range, f.im.openquake_for(f.key.aspect.fixed())) {
            range.0 = range.0.min(lo * oq.factor);
            range.1 = range.1.max(hi * oq.factor);
        }
    }
    if range.0.is_finite() {
        range
    } else {
        (1e-3, 1.0)
    }
}

/// The entry of one case: its fits, one per limit state of `limit_states`.
fn case_entry(case: &[&CaseFit], limit_states: &[&str], range: (f64, f64)) -> Option<NrmlEntry> {
    let first = case[0];
    let id = first.key.id();
    let aspect = first.key.aspect.fixed();
    let Some(OpenQuakeImt { imt, factor }) = first.im.openquake_for(aspect) else {
        let reason = first
            .im
            .no_openquake_reason(aspect)
            .expect("an IM without an IMT has a reason");
        return Some(NrmlEntry::Omitted { id, reason });
    };
    first.im_range?;
    if let Some(reason) = out_of_order_reason(case) {
        return Some(NrmlEntry::Omitted { id, reason });
    }
    let fits: Vec<Option<&CaseFit>> = limit_states
        .iter()
        .map(|ls| case.iter().copied().find(|f| f.limit_state == *ls))
        .collect();
    let unfitted: Vec<String> = limit_states
        .iter()
        .zip(&fits)
        .filter_map(|(ls, f)| match f.map(|f| &f.fit) {
            Some(Ok(_)) => None,
            Some(Err(reason)) => Some(format!("{ls}: {}: {reason}", reason.status())),
            None => Some(format!("{ls}: no fit")),
        })
        .collect();
    if unfitted.is_empty() {
        let params = fits
            .iter()
            .map(|f| {
                let fit = f
                    .expect("every limit state fitted")
                    .fit
                    .as_ref()
                    .expect("fitted");
                lognormal_to_moments(fit.median() * factor, fit.beta())
            })
            .collect();
        return Some(NrmlEntry::Function(NrmlFunction {
            id,
            imt,
            shape: NrmlShape::Continuous(params),
        }));
    }
    if unfitted.len() == limit_states.len() || fits.iter().any(Option::is_none) {
        let reason = if case.len() == 1 && limit_states.len() == 1 {
            // One limit state: the reason alone.
            unfitted[0]
                .split_once(": ")
                .map_or(unfitted[0].clone(), |(_, r)| r.to_string())
        } else {
            unfitted.join("; ")
        };
        return Some(NrmlEntry::Omitted { id, reason });
    }
    // Some fitted, some not: a discrete function keeps the fitted curves.
    let (mut lo, mut hi) = range;
    for f in fits.iter().flatten() {
        if let Some((a, b)) = f.im_range {
            lo = lo.min(a * factor);
            hi = hi.max(b * factor);
        }
    }
    let n = (dm::log10(hi / lo) * DISCRETE_LEVELS_PER_DECADE)
        .ceil()
        .max(1.0) as usize;
    let imls: Vec<f64> = (0..=n)
        .map(|i| lo * dm::powf(hi / lo, i as f64 / n as f64))
        .collect();
    let mut poes: Vec<Vec<f64>> = fits
        .iter()
        .map(|f| {
            let f = f.expect("checked above");
            match &f.fit {
                Ok(fit) => imls.iter().map(|&x| fit.probability(x / factor)).collect(),
                Err(_) => observed(&f.observations, &imls, factor),
            }
        })
        .collect();
    // A more severe limit state is never more likely than the milder one.
    for k in 1..poes.len() {
        let (milder, severe) = poes.split_at_mut(k);
        for (p, &q) in severe[0].iter_mut().zip(&milder[k - 1]) {
            *p = p.min(q);
        }
    }
    Some(NrmlEntry::Function(NrmlFunction {
        id,
        imt,
        shape: NrmlShape::Discrete {
            imls,
            poes,
            note: format!(
                "observed fractions, not fitted curves, for {}",
                unfitted.join("; ")
            ),
        },
    }))
}

/// How the reason of a case left out for [`Caveat::OutOfOrder`] begins.
const OUT_OF_ORDER: &str = "its limit states are out of order";

/// Why a case whose limit states are out of order ([`Caveat::OutOfOrder`])
/// is left out: OpenQuake's damage state k is P(LSₖ) − P(LSₖ₊₁), negative
/// where a more severe curve lies above a milder one.
fn out_of_order_reason(case: &[&CaseFit]) -> Option<String> {
    let i = case
        .iter()
        .position(|f| f.caveat == Some(Caveat::OutOfOrder))?;
    let pair = |f: &CaseFit| f.fit.as_ref().ok().map(|x| (x.median(), x.beta()));
    let inversion = first_inversion(
        pair(case[i])?,
        case[..i]
            .iter()
            .filter_map(|g| pair(g).map(|p| (g.limit_state.as_str(), p))),
        case[i].im_range?,
    );
    Some(match inversion {
        Some((milder, x, d)) => format!(
            "{OUT_OF_ORDER}: {} is more likely than {milder} (listed as milder) at {} by {}, \
             where OpenQuake would give a damage state a negative probability",
            case[i].limit_state,
            number(x),
            crate::io_util::sig3(d)
        ),
        None => format!(
            "{OUT_OF_ORDER}: {} is more likely than a milder one",
            case[i].limit_state
        ),
    })
}

/// Observed exceedance fractions at `levels` (OpenQuake's unit, the data's
/// intensities times `factor`): interpolated in ln IM between the stripes,
/// from 0 at the lowest level up to the lowest stripe, held beyond the
/// highest stripe.
fn observed(obs: &[super::fit::Observation], levels: &[f64], factor: f64) -> Vec<f64> {
    let mut points: Vec<(f64, f64)> = obs
        .iter()
        .filter(|o| o.trials > 0)
        .map(|o| (dm::ln(o.im * factor), o.overturned as f64 / o.trials as f64))
        .collect();
    if let Some(&first) = levels.first() {
        points.insert(
            0,
            (dm::ln(first).min(points.first().map_or(0.0, |p| p.0)), 0.0),
        );
    }
    levels
        .iter()
        .map(|&x| {
            let l = dm::ln(x);
            match points.iter().position(|p| p.0 >= l) {
                None => points.last().map_or(0.0, |p| p.1),
                Some(0) => points[0].1,
                Some(i) => {
                    let (a, b) = (points[i - 1], points[i]);
                    if b.0 == a.0 {
                        b.1
                    } else {
                        a.1 + (b.1 - a.1) * (l - a.0) / (b.0 - a.0)
                    }
                }
            }
        })
        .collect()
}

/// A fragility model of any number of limit states as NRML 0.5 text, in the
/// layout OpenQuake's reader (`openquake.risklib.read_nrml`) requires:
/// `fragilityModel` with `id`, `assetCategory` and `lossCategory`; its first
/// two children `description` and `limitStates` (names separated by spaces,
/// in order of increasing damage), then one `fragilityFunction` per entry,
/// whose first child is `imls` and then one `params` (continuous) or `poes`
/// (discrete) per limit state in the order of `limit_states`. A continuous
/// function's `imls` carry the model's range `range` as `minIML`, `maxIML`
/// and `noDamageLimit` = minIML (see the docs of `src/fragility/nrml.rs`); a discrete
/// one's its levels, with `noDamageLimit` its first. An
/// [`NrmlEntry::Omitted`] becomes an XML comment.
///
/// Panics if a function's curves do not match `limit_states` in number,
/// or a limit-state name or function id is not a word of ASCII letters,
/// digits, `_` and `-`.
pub fn nrml_model_string(
    limit_states: &[&str],
    entries: &[NrmlEntry],
    range: (f64, f64),
) -> String {
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
         fitted by maximum likelihood over stripes (rockfrag {}); minIML and maxIML \
         are where every curve is 0 and 1 (median times exp(-+6 beta)), not the \
         fitted range</description>\n",
        limit_states.join(", "),
        env!("CARGO_PKG_VERSION")
    ));
    s.push_str(&format!(
        "  <limitStates>{}</limitStates>\n",
        limit_states.join(" ")
    ));
    let list = |v: &[f64]| v.iter().map(|&x| number(x)).collect::<Vec<_>>().join(" ");
    for e in entries {
        let f = match e {
            NrmlEntry::Function(f) => f,
            NrmlEntry::Omitted { id, reason } => {
                let why = reason.replace("--", "- -");
                if why.starts_with(OUT_OF_ORDER) {
                    // Fitted, but not a model OpenQuake can use.
                    s.push_str(&format!("  <!-- {id} left out: {why} -->\n"));
                } else {
                    s.push_str(&format!("  <!-- {id} not fitted ({why}) -->\n"));
                }
                continue;
            }
        };
        assert!(
            is_nrml_name(&f.id),
            "function id {:?} is not an NRML id",
            f.id
        );
        match &f.shape {
            NrmlShape::Continuous(params) => {
                assert_eq!(
                    params.len(),
                    limit_states.len(),
                    "function {}: one (mean, stddev) per limit state",
                    f.id
                );
                s.push_str(&format!(
                    "  <fragilityFunction id=\"{}\" format=\"continuous\" shape=\"logncdf\">\n",
                    f.id
                ));
                s.push_str(&format!(
                    "    <imls imt=\"{}\" minIML=\"{}\" maxIML=\"{}\" noDamageLimit=\"{}\"/>\n",
                    f.imt,
                    number(range.0),
                    number(range.1),
                    number(range.0)
                ));
                for (ls, &(mean, stddev)) in limit_states.iter().zip(params) {
                    s.push_str(&format!(
                        "    <params ls=\"{ls}\" mean=\"{}\" stddev=\"{}\"/>\n",
                        number(mean),
                        number(stddev)
                    ));
                }
            }
            NrmlShape::Discrete { imls, poes, note } => {
                assert_eq!(
                    poes.len(),
                    limit_states.len(),
                    "function {}: one list of poes per limit state",
                    f.id
                );
                s.push_str(&format!(
                    "  <!-- {}: {} -->\n",
                    f.id,
                    note.replace("--", "- -")
                ));
                s.push_str(&format!(
                    "  <fragilityFunction id=\"{}\" format=\"discrete\">\n",
                    f.id
                ));
                s.push_str(&format!(
                    "    <imls imt=\"{}\" noDamageLimit=\"{}\">{}</imls>\n",
                    f.imt,
                    number(imls[0]),
                    list(imls)
                ));
                for (ls, p) in limit_states.iter().zip(poes) {
                    s.push_str(&format!("    <poes ls=\"{ls}\">{}</poes>\n", list(p)));
                }
            }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::Case;
    use crate::solver::Friction;

    /// Ids keep to NRML's alphabet.
    #[test]
    fn function_ids_use_only_allowed_characters() {
        let key = Case::fixed(
            4.0,
            0.5,
            0.25,
            Friction::Coulomb {
                mu_s: 0.6,
                mu_k: f64::INFINITY,
            },
        );
        let id = key.id();
        assert_eq!(id, "a4_w0p5_e0p25_mus0p6_mukinf");
        assert!(is_nrml_name(&id));
    }
}
