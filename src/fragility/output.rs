//! The CSV outputs: one row per case and limit state (`fragility.csv`) and the sampled curves
//! with their bands (`fragility_curves.csv`). Both are written atomically;
//! numbers use the shortest representation that reads back exactly, and a
//! number that does not exist (a case that could not be fitted, a band without
//! a bootstrap) is an empty field, never NaN.

use std::path::{Path, PathBuf};

use super::case::CaseFit;
use super::nrml;
use crate::error::{Error, Result};
use crate::io_util::number;
use crate::io_util::write_atomic;
use crate::outcomes_csv::CaseKey;

/// Header of `fragility.csv`, one row per case and limit state (a case's
/// limit states together, in order of severity). `limit_state` names the
/// limit state; `n_overturned` counts the analyses that overturned,
/// `n_exceeded` those that exceeded the limit state (what was fitted);
/// `beta_model` is `separate` (fitted alone) or `common` (one β shared with
/// the case's other fitted limit states, because the separate curves
/// crossed; empty when not fitted). `median`, `median_lo`, `median_hi`,
/// `se_median`, `boot_sd_median`, `im_min`, `im_max` are in the unit of `im`
/// (`im_unit`); `loglik` includes the binomial coefficients; `status` is `ok`
/// or an [`Unfit`](super::Unfit) keyword; `boot_unfit` counts the replicates
/// that could not be fitted, `boot_unfit_reasons` lists them as `reason=count`
/// separated by spaces.
/// A case column is empty when the parameter was drawn per analysis (the
/// spec's `[uncertainty]`): the case pools the analyses over its draws.
pub const FRAGILITY_HEADER: &str = "aspect,width,restitution,friction,mu_s,mu_k,limit_state,im,\
median,beta,median_lo,median_hi,beta_lo,beta_hi,n_records,n_stripes,loglik,se_median,se_beta,\
status,im_unit,n_analyses,n_overturned,n_failed,im_min,im_max,iterations,boot_replicates,\
boot_fitted,boot_unfit,boot_unfit_reasons,boot_sd_median,boot_sd_beta,beta_model,n_exceeded";

/// Header of `fragility_curves.csv`: `case` is the 0-based row of the case
/// and limit state in `fragility.csv`; `im_value` is the intensity (unit of
/// `im`); `p` the fitted probability of exceeding the limit state; `p_lo`, `p_hi` the pointwise bootstrap band
/// (empty without a bootstrap). Only fitted cases have rows.
pub const CURVES_HEADER: &str =
    "case,aspect,width,restitution,friction,mu_s,mu_k,limit_state,im,im_value,p,p_lo,p_hi";

/// Header of `fragility_bootstrap.csv`, one row per bootstrap replicate of
/// each fitted case and limit state: `case` is the 0-based row in
/// `fragility.csv`; `replicate` the 0-based replicate (seeded from the fit's
/// seed and this number alone); `median` and `beta` the replicate's fit (unit
/// of `im`), empty when it could not be fitted, `status` then naming why.
/// Header only when the fit ran without a bootstrap.
pub const BOOTSTRAP_HEADER: &str =
    "case,aspect,width,restitution,friction,mu_s,mu_k,limit_state,im,replicate,median,beta,status";

/// The files [`write_outputs`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputPaths {
    /// One row per case.
    pub fragility: PathBuf,
    /// The sampled curves.
    pub curves: PathBuf,
    /// The OpenQuake fragility model.
    pub nrml: PathBuf,
    /// Every bootstrap replicate's (θ, β).
    pub bootstrap: PathBuf,
}

/// Writes `fragility.csv`, `fragility_curves.csv`, `fragility_bootstrap.csv`
/// and `fragility.xml` into `dir`. The NRML file holds every limit state, in
/// order (see [`nrml::nrml_string`]).
pub fn write_outputs(dir: &Path, fits: &[CaseFit]) -> Result<OutputPaths> {
    let paths = OutputPaths {
        fragility: dir.join("fragility.csv"),
        curves: dir.join("fragility_curves.csv"),
        nrml: dir.join("fragility.xml"),
        bootstrap: dir.join("fragility_bootstrap.csv"),
    };
    write_fragility_csv(&paths.fragility, fits)?;
    write_curves_csv(&paths.curves, fits)?;
    write_bootstrap_csv(&paths.bootstrap, fits)?;
    nrml::write_nrml(&paths.nrml, fits)?;
    Ok(paths)
}

/// Writes `fragility.csv` (header [`FRAGILITY_HEADER`]).
pub fn write_fragility_csv(path: &Path, fits: &[CaseFit]) -> Result<()> {
    write_atomic(path, |w| {
        writeln!(w, "{FRAGILITY_HEADER}")?;
        for f in fits {
            let fit = f.fit.as_ref().ok();
            let boot = f.bootstrap.as_ref();
            let reasons = boot.map(|b| {
                b.unfit
                    .iter()
                    .map(|(k, n)| format!("{k}={n}"))
                    .collect::<Vec<_>>()
                    .join(" ")
            });
            let status = match &f.fit {
                Ok(_) => "ok",
                Err(reason) => reason.status(),
            };
            let fields = [
                key_fields(&f.key),
                f.limit_state.clone(),
                f.im.name().to_string(),
                opt(fit.map(|x| x.median())),
                opt(fit.map(|x| x.beta())),
                opt(boot.and_then(|b| b.median).map(|i| i.lo)),
                opt(boot.and_then(|b| b.median).map(|i| i.hi)),
                opt(boot.and_then(|b| b.beta).map(|i| i.lo)),
                opt(boot.and_then(|b| b.beta).map(|i| i.hi)),
                f.n_records.to_string(),
                f.n_stripes.to_string(),
                opt(fit.map(|x| x.loglik)),
                opt(fit.map(|x| x.se_median())),
                opt(fit.map(|x| x.se_beta())),
                status.to_string(),
                f.im.unit().to_string(),
                f.n_analyses.to_string(),
                f.n_overturned.to_string(),
                f.n_failed.to_string(),
                opt(f.im_range.map(|r| r.0)),
                opt(f.im_range.map(|r| r.1)),
                fit.map_or(String::new(), |x| x.iterations.to_string()),
                boot.map_or(String::new(), |b| b.replicates.to_string()),
                boot.map_or(String::new(), |b| b.fitted.to_string()),
                boot.map_or(String::new(), |b| b.unfit_total().to_string()),
                reasons.unwrap_or_default(),
                opt(boot.and_then(|b| b.sd_median)),
                opt(boot.and_then(|b| b.sd_beta)),
                fit.map_or(String::new(), |_| f.beta_model.name().to_string()),
                f.n_exceeded.to_string(),
            ];
            writeln!(w, "{}", fields.join(","))?;
        }
        Ok(())
    })
    .map_err(Error::io(path))
}

/// Writes `fragility_curves.csv` (header [`CURVES_HEADER`]).
pub fn write_curves_csv(path: &Path, fits: &[CaseFit]) -> Result<()> {
    write_atomic(path, |w| {
        writeln!(w, "{CURVES_HEADER}")?;
        for (case, f) in fits.iter().enumerate() {
            let Some(curve) = &f.curve else { continue };
            let key = key_fields(&f.key);
            let band = f
                .bootstrap
                .as_ref()
                .filter(|b| b.curve_lo.len() == curve.im.len());
            for (i, (&x, &p)) in curve.im.iter().zip(&curve.probability).enumerate() {
                let lo = opt(band.map(|b| b.curve_lo[i]));
                let hi = opt(band.map(|b| b.curve_hi[i]));
                let (x, p) = (number(x), number(p));
                let (ls, im) = (&f.limit_state, f.im.name());
                writeln!(w, "{case},{key},{ls},{im},{x},{p},{lo},{hi}")?;
            }
        }
        Ok(())
    })
    .map_err(Error::io(path))
}

/// Writes `fragility_bootstrap.csv` (header [`BOOTSTRAP_HEADER`]).
pub fn write_bootstrap_csv(path: &Path, fits: &[CaseFit]) -> Result<()> {
    write_atomic(path, |w| {
        writeln!(w, "{BOOTSTRAP_HEADER}")?;
        for (case, f) in fits.iter().enumerate() {
            let Some(boot) = f.bootstrap.as_ref().filter(|_| f.fit.is_ok()) else {
                continue;
            };
            let key = key_fields(&f.key);
            let (ls, im) = (&f.limit_state, f.im.name());
            for (r, fit) in boot.replicate_fits.iter().enumerate() {
                let (median, beta, status) = match fit {
                    Ok((m, b)) => (number(*m), number(*b), "ok"),
                    Err(reason) => (String::new(), String::new(), reason.status()),
                };
                writeln!(w, "{case},{key},{ls},{im},{r},{median},{beta},{status}")?;
            }
        }
        Ok(())
    })
    .map_err(Error::io(path))
}

/// The six case columns, comma-separated (absent μ, or a parameter drawn
/// per analysis and pooled, as an empty field).
pub(crate) fn key_fields(k: &CaseKey) -> String {
    format!(
        "{},{},{},{},{},{}",
        opt(Some(k.aspect)),
        opt(Some(k.width)),
        opt(Some(k.restitution)),
        k.friction_name(),
        opt(k.mu_s()),
        opt(k.mu_k())
    )
}

/// A number, or an empty field when absent or NaN (infinite μ reads `inf`).
fn opt(x: Option<f64>) -> String {
    x.filter(|v| !v.is_nan()).map_or(String::new(), number)
}
