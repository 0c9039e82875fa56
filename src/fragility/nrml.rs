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
//! One limit state, `overturning`; one function per fitted case, its `id`
//! built from the case (`.` written `p`). OpenQuake knows PGA in g and PGV in
//! cm/s, so PGV curves are scaled by 100 and PGA/(g tan θc) curves are written
//! in PGA, θ_PGA = θ/(H/B) (exact for one case, whose H/B is fixed). Cases
//! that could not be fitted are left out, with an XML comment saying why.
//! The loss category is `contents` (free-standing objects).

use std::path::Path;

use super::case::CaseFit;
use super::options::IntensityMeasure;
use crate::error::{Error, Result};
use crate::io_util::number;
use crate::io_util::write_atomic;
use crate::outcomes_csv::CaseKey;

/// (θ, β) → (mean, standard deviation) of the lognormal intensity, with
/// `expm1` so that small β keeps full precision.
pub fn lognormal_to_moments(median: f64, beta: f64) -> (f64, f64) {
    let b2 = beta * beta;
    let mean = median * (0.5 * b2).exp();
    (mean, mean * b2.exp_m1().sqrt())
}

/// (mean, standard deviation) → (θ, β): the inverse of [`lognormal_to_moments`].
pub fn moments_to_lognormal(mean: f64, stddev: f64) -> (f64, f64) {
    let cv2 = (stddev / mean).powi(2);
    let b2 = cv2.ln_1p();
    (mean * (-0.5 * b2).exp(), b2.sqrt())
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

/// The fragility model as NRML 0.5 text.
pub fn nrml_string(fits: &[CaseFit]) -> String {
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    s.push_str("<nrml xmlns=\"http://openquake.org/xmlns/nrml/0.5\">\n");
    s.push_str("<fragilityModel id=\"rockfrag-overturning\" lossCategory=\"contents\">\n");
    s.push_str(&format!(
        "  <description>Overturning of free-standing rigid blocks: lognormal fragility \
         fitted by maximum likelihood over stripes (rockfrag {})</description>\n",
        env!("CARGO_PKG_VERSION")
    ));
    s.push_str("  <limitStates>overturning</limitStates>\n");
    for f in fits {
        let id = function_id(&f.key);
        let (fit, (lo, hi)) = match (&f.fit, f.im_range) {
            (Ok(fit), Some(range)) => (fit, range),
            (Err(reason), _) => {
                let why = format!("{}: {reason}", reason.status()).replace("--", "- -");
                s.push_str(&format!("  <!-- {id} not fitted ({why}) -->\n"));
                continue;
            }
            (Ok(_), None) => continue,
        };
        let (imt, factor) = openquake_imt(f.im, &f.key);
        let (mean, stddev) = lognormal_to_moments(fit.median() * factor, fit.beta());
        s.push_str(&format!(
            "  <fragilityFunction id=\"{id}\" format=\"continuous\" shape=\"logncdf\">\n"
        ));
        s.push_str(&format!(
            "    <imls imt=\"{imt}\" minIML=\"{}\" maxIML=\"{}\"/>\n",
            number(lo * factor),
            number(hi * factor)
        ));
        s.push_str(&format!(
            "    <params ls=\"overturning\" mean=\"{}\" stddev=\"{}\"/>\n",
            number(mean),
            number(stddev)
        ));
        s.push_str("  </fragilityFunction>\n");
    }
    s.push_str("</fragilityModel>\n</nrml>\n");
    s
}

/// Writes [`nrml_string`] to `path`, atomically.
pub fn write_nrml(path: &Path, fits: &[CaseFit]) -> Result<()> {
    let text = nrml_string(fits);
    write_atomic(path, |w| w.write_all(text.as_bytes())).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// A fragility-function id from the case: letters, digits, `-` and `_` only
/// (NRML's rule), e.g. `block-a4-w0p5-e0-inf` or
/// `block-a4-w0p5-e0p2-coulomb-ms0p6-mk0p5`.
fn function_id(k: &CaseKey) -> String {
    let num = |x: f64| {
        x.to_string()
            .chars()
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
        assert!(
            id.chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        );
    }
}
