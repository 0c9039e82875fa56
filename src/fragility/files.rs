//! The fit's stage files, each one row type with its writer and reader side
//! by side: `fragility.csv` ([`FragilityRow`], one row per case and limit
//! state), `fragility_curves.csv` ([`CurveRow`], the sampled curves with
//! their bands) and `fragility_bootstrap.csv` ([`BootstrapRow`], every
//! bootstrap replicate's θ and β). Every consumer — the risk integral, the
//! figures, the summary, Python — reads them through these types, so a
//! column is added here and nowhere else.
//!
//! Files are written atomically; numbers use the shortest representation
//! that reads back exactly, and a number that does not exist (a case that
//! could not be fitted, a band without a bootstrap) is an empty field, never
//! NaN.

use std::path::{Path, PathBuf};

use super::case::CaseFit;
use super::nrml;
use super::status::{Caveat, FitStatus, UnfitKind};
use crate::case::Case;
use crate::error::{Error, Result};
use crate::im::Im;
use crate::io_util::{number, write_atomic};
use crate::table::{Row, Table};

/// Header of `fragility.csv`, one row per case and limit state (a case's
/// limit states together, in order of severity). `case_id` is the case's id
/// ([`Case::id`]: the NRML function id, the OpenQuake exposure taxonomy and
/// the pelicun component of the exports, and `risk.csv`'s); `limit_state` names the
/// limit state; `n_overturned` counts the analyses that overturned,
/// `n_exceeded` those that exceeded the limit state (what was fitted);
/// `n_stripes` counts the study's intensity levels (stripes) with an
/// analysis, whatever IM the curve is fitted against (a PGV-level or
/// record-pair study's analyses each have their own measured PGA);
/// `beta_model` is `separate` (fitted alone) or `common` (one β shared with
/// the case's other fitted limit states, because the separate curves
/// crossed; empty when not fitted). `median`, `median_lo`, `median_hi`,
/// `se_median`, `boot_sd_median`, `im_min`, `im_max` are in the unit of `im`
/// (`im_unit`); `loglik` includes the binomial coefficients; `status` is `ok`
/// for a fitted curve, `extrapolated-above` or `extrapolated-below` for a
/// fitted curve whose median lies above the strongest stripe (below the
/// weakest), `out-of-order` for one more likely than a milder limit state
/// of its case within the stripes (a [`Caveat`]; the numbers are written
/// all the same), or an [`Unfit`](super::Unfit) keyword when there is no
/// curve; `boot_unfit` counts the replicates
/// that could not be fitted, `boot_unfit_reasons` lists them as `reason=count`
/// separated by spaces.
/// A case column is empty when the parameter was drawn per analysis (the
/// spec's `[uncertainty]`): the case pools the analyses over its draws.
pub const FRAGILITY_HEADER: &str = "case_id,aspect,width,restitution,friction,mu_s,mu_k,limit_state,im,\
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

/// One row of `fragility.csv`: a case and limit state and its fit (see
/// [`FRAGILITY_HEADER`] for each column).
#[derive(Clone, Debug, PartialEq)]
pub struct FragilityRow {
    /// The case (drawn parameters pooled).
    pub case: Case,
    /// The limit state's name.
    pub limit_state: String,
    /// The intensity measure.
    pub im: Im,
    /// Median θ (unit of `im`), `None` when not fitted.
    pub median: Option<f64>,
    /// β, `None` when not fitted.
    pub beta: Option<f64>,
    /// Bootstrap band of θ.
    pub median_band: Option<(f64, f64)>,
    /// Bootstrap band of β.
    pub beta_band: Option<(f64, f64)>,
    /// Records with at least one successful analysis.
    pub n_records: usize,
    /// Stripes with at least one successful analysis.
    pub n_stripes: usize,
    /// Maximised log-likelihood.
    pub loglik: Option<f64>,
    /// Standard error of θ (Fisher information, delta method).
    pub se_median: Option<f64>,
    /// Standard error of β.
    pub se_beta: Option<f64>,
    /// `ok`, a caveat, or why the case has no curve.
    pub status: FitStatus,
    /// Successful analyses.
    pub n_analyses: usize,
    /// Analyses that overturned.
    pub n_overturned: usize,
    /// Failed analyses, skipped.
    pub n_failed: usize,
    /// Smallest and largest intensity among the analyses.
    pub im_range: Option<(f64, f64)>,
    /// Newton iterations of the fit.
    pub iterations: Option<u32>,
    /// Bootstrap replicates drawn.
    pub boot_replicates: Option<usize>,
    /// Bootstrap replicates fitted.
    pub boot_fitted: Option<usize>,
    /// Bootstrap replicates not fitted.
    pub boot_unfit: Option<usize>,
    /// Why, as `reason=count` separated by spaces.
    pub boot_unfit_reasons: String,
    /// Standard deviation of θ over the fitted replicates.
    pub boot_sd_median: Option<f64>,
    /// Standard deviation of β over the fitted replicates.
    pub boot_sd_beta: Option<f64>,
    /// `separate` or `common`; empty when not fitted.
    pub beta_model: String,
    /// Analyses that exceeded the limit state.
    pub n_exceeded: usize,
}

impl FragilityRow {
    /// The row of one fitted case and limit state.
    pub fn from_fit(f: &CaseFit) -> FragilityRow {
        let fit = f.fit.as_ref().ok();
        let boot = f.bootstrap.as_ref();
        FragilityRow {
            case: f.key,
            limit_state: f.limit_state.clone(),
            im: f.im,
            median: fit.map(|x| x.median()),
            beta: fit.map(|x| x.beta()),
            median_band: boot.and_then(|b| b.median).map(|i| (i.lo, i.hi)),
            beta_band: boot.and_then(|b| b.beta).map(|i| (i.lo, i.hi)),
            n_records: f.n_records,
            n_stripes: f.n_stripes,
            loglik: fit.map(|x| x.loglik),
            se_median: fit.map(|x| x.se_median()),
            se_beta: fit.map(|x| x.se_beta()),
            status: FitStatus::of(&f.fit, f.caveat),
            n_analyses: f.n_analyses,
            n_overturned: f.n_overturned,
            n_failed: f.n_failed,
            im_range: f.im_range,
            iterations: fit.map(|x| x.iterations),
            boot_replicates: boot.map(|b| b.replicates),
            boot_fitted: boot.map(|b| b.fitted),
            boot_unfit: boot.map(|b| b.unfit_total()),
            boot_unfit_reasons: boot.map_or(String::new(), |b| {
                b.unfit
                    .iter()
                    .map(|(k, n)| format!("{k}={n}"))
                    .collect::<Vec<_>>()
                    .join(" ")
            }),
            boot_sd_median: boot.and_then(|b| b.sd_median),
            boot_sd_beta: boot.and_then(|b| b.sd_beta),
            beta_model: fit.map_or(String::new(), |_| f.beta_model.name().to_string()),
            n_exceeded: f.n_exceeded,
        }
    }

    /// The fitted (θ, β), `None` when the case could not be fitted (a
    /// curve with a [`Caveat`] is fitted: `status` says what to read it
    /// with).
    pub fn fit(&self) -> Option<(f64, f64)> {
        match (self.is_fitted(), self.median, self.beta) {
            (true, Some(m), Some(b)) => Some((m, b)),
            _ => None,
        }
    }

    /// Whether `status` is a fitted curve's: `ok` or a [`Caveat`].
    pub fn is_fitted(&self) -> bool {
        self.status.is_fitted()
    }

    /// The caveat `status` names, if any.
    pub fn caveat(&self) -> Option<Caveat> {
        self.status.caveat()
    }

    /// The row's line, without its newline (columns of [`FRAGILITY_HEADER`]).
    pub fn line(&self) -> String {
        let count = |x: Option<usize>| x.map_or(String::new(), |n| n.to_string());
        let fields = [
            self.case.id(),
            self.case.fields(),
            self.limit_state.clone(),
            crate::io_util::csv_field(self.im.name()),
            opt(self.median),
            opt(self.beta),
            opt(self.median_band.map(|b| b.0)),
            opt(self.median_band.map(|b| b.1)),
            opt(self.beta_band.map(|b| b.0)),
            opt(self.beta_band.map(|b| b.1)),
            self.n_records.to_string(),
            self.n_stripes.to_string(),
            opt(self.loglik),
            opt(self.se_median),
            opt(self.se_beta),
            self.status.to_string(),
            self.im.unit().to_string(),
            self.n_analyses.to_string(),
            self.n_overturned.to_string(),
            self.n_failed.to_string(),
            opt(self.im_range.map(|r| r.0)),
            opt(self.im_range.map(|r| r.1)),
            self.iterations.map_or(String::new(), |n| n.to_string()),
            count(self.boot_replicates),
            count(self.boot_fitted),
            count(self.boot_unfit),
            self.boot_unfit_reasons.clone(),
            opt(self.boot_sd_median),
            opt(self.boot_sd_beta),
            self.beta_model.clone(),
            self.n_exceeded.to_string(),
        ];
        fields.join(",")
    }

    /// Reads a row of a `fragility.csv` whose columns are at `c` (in the
    /// order of [`FragilityRow::COLUMNS`]; `None` for an optional column the
    /// file lacks).
    fn read(row: &Row<'_>, c: &[Option<usize>]) -> Result<FragilityRow> {
        let text = |i: usize| c[i].map_or("", |j| row.field(j));
        let opt = |i: usize| -> Result<Option<f64>> {
            match c[i] {
                Some(j) if !row.field(j).is_empty() => row.number(j).map(Some),
                _ => Ok(None),
            }
        };
        let count = |i: usize| -> Result<Option<usize>> {
            match c[i] {
                Some(j) if !row.field(j).is_empty() => row.integer(j).map(|n| Some(n as usize)),
                _ => Ok(None),
            }
        };
        let required = |i: usize| c[i].expect("a required column");
        let pair = |a: Option<f64>, b: Option<f64>| a.zip(b);
        let im = text(1)
            .parse::<Im>()
            .map_err(|e| row.error(required(1), &e))?;
        let out = FragilityRow {
            case: row.case()?,
            limit_state: row.text(required(0))?.to_string(),
            im,
            median: opt(2)?,
            beta: opt(3)?,
            median_band: pair(opt(4)?, opt(5)?),
            beta_band: pair(opt(6)?, opt(7)?),
            n_records: count(8)?.unwrap_or(0),
            n_stripes: count(9)?.unwrap_or(0),
            loglik: opt(10)?,
            se_median: opt(11)?,
            status: row
                .text(required(12))?
                .parse()
                .map_err(|e: String| row.error(required(12), &e))?,
            se_beta: opt(13)?,
            n_analyses: count(14)?.unwrap_or(0),
            n_overturned: count(15)?.unwrap_or(0),
            n_failed: count(16)?.unwrap_or(0),
            im_range: pair(opt(17)?, opt(18)?),
            iterations: count(19)?.map(|n| n as u32),
            boot_replicates: count(20)?,
            boot_fitted: count(21)?,
            boot_unfit: count(22)?,
            boot_unfit_reasons: text(23).to_string(),
            boot_sd_median: opt(24)?,
            boot_sd_beta: opt(25)?,
            beta_model: text(26).to_string(),
            n_exceeded: count(27)?.unwrap_or(0),
        };
        if out.is_fitted() {
            // A fitted row has its curve: positive θ and β.
            for i in [2, 3] {
                row.positive(required(i))?;
            }
        }
        Ok(out)
    }

    /// The columns of a row besides the case, in the order
    /// [`FragilityRow::read`] indexes them; the first [`REQUIRED`] of them
    /// (by index: limit state, IM, median, β, status) must be in a file,
    /// the others are read when present.
    const COLUMNS: [&'static str; 28] = [
        "limit_state",
        "im",
        "median",
        "beta",
        "median_lo",
        "median_hi",
        "beta_lo",
        "beta_hi",
        "n_records",
        "n_stripes",
        "loglik",
        "se_median",
        "status",
        "se_beta",
        "n_analyses",
        "n_overturned",
        "n_failed",
        "im_min",
        "im_max",
        "iterations",
        "boot_replicates",
        "boot_fitted",
        "boot_unfit",
        "boot_unfit_reasons",
        "boot_sd_median",
        "boot_sd_beta",
        "beta_model",
        "n_exceeded",
    ];
}

/// The indices (into [`FragilityRow::COLUMNS`]) of the columns a
/// `fragility.csv` must have: what the fitted curve is.
const REQUIRED: [usize; 5] = [0, 1, 2, 3, 12];

/// Reads `fragility.csv` (its columns found by header name; a file with
/// only the case, `limit_state`, `im`, `median`, `beta` and `status`
/// columns reads too, the others left empty).
///
/// Errors: [`Error::Io`]; [`Error::Parse`] naming the file, line, column and
/// value of anything unreadable or missing.
pub fn read_fragility_csv(path: &Path) -> Result<Vec<FragilityRow>> {
    let required: Vec<&str> = REQUIRED.iter().map(|&i| FragilityRow::COLUMNS[i]).collect();
    let (mut table, _) = Table::open_dyn(path, &required, "reading fragility.csv")?;
    let c: Vec<Option<usize>> = FragilityRow::COLUMNS
        .iter()
        .map(|n| table.column(n))
        .collect();
    let mut rows = Vec::new();
    while let Some(row) = table.next_row()? {
        rows.push(FragilityRow::read(&row, &c)?);
    }
    Ok(rows)
}

/// One row of `fragility_curves.csv`: a point of a fitted curve.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveRow {
    /// The row of the case and limit state in `fragility.csv`.
    pub index: usize,
    /// The case.
    pub case: Case,
    /// The limit state.
    pub limit_state: String,
    /// The intensity measure.
    pub im: Im,
    /// The intensity (unit of `im`).
    pub im_value: f64,
    /// Fitted probability of exceeding the limit state.
    pub p: f64,
    /// Pointwise bootstrap band, `None` without a bootstrap.
    pub band: Option<(f64, f64)>,
}

impl CurveRow {
    /// The row's line, without its newline (columns of [`CURVES_HEADER`]).
    pub fn line(&self) -> String {
        let (lo, hi) = (opt(self.band.map(|b| b.0)), opt(self.band.map(|b| b.1)));
        format!(
            "{},{},{},{},{},{},{lo},{hi}",
            self.index,
            self.case.fields(),
            self.limit_state,
            crate::io_util::csv_field(self.im.name()),
            number(self.im_value),
            number(self.p)
        )
    }
}

/// The rows of `fit` (row `index` of `fragility.csv`): its curve with its
/// band, none for a case that was not fitted.
pub(crate) fn curve_rows(index: usize, fit: &CaseFit) -> Vec<CurveRow> {
    let Some(curve) = &fit.curve else {
        return Vec::new();
    };
    let band = fit
        .bootstrap
        .as_ref()
        .filter(|b| b.curve_lo.len() == curve.im.len());
    curve
        .im
        .iter()
        .zip(&curve.probability)
        .enumerate()
        .map(|(i, (&x, &p))| CurveRow {
            index,
            case: fit.key,
            limit_state: fit.limit_state.clone(),
            im: fit.im,
            im_value: x,
            p,
            band: band.map(|b| (b.curve_lo[i], b.curve_hi[i])),
        })
        .collect()
}

/// Reads `fragility_curves.csv` (a file without a `limit_state` column,
/// which predates limit states, reads as `overturning`).
pub fn read_curves_csv(path: &Path) -> Result<Vec<CurveRow>> {
    let (mut table, [index, im, im_value, p, lo, hi]) = Table::open(
        path,
        ["case", "im", "im_value", "p", "p_lo", "p_hi"],
        "reading fragility_curves.csv",
    )?;
    let limit_state = table.column("limit_state");
    let mut rows = Vec::new();
    while let Some(row) = table.next_row()? {
        let band = if row.field(lo).is_empty() || row.field(hi).is_empty() {
            None
        } else {
            Some((row.number(lo)?, row.number(hi)?))
        };
        rows.push(CurveRow {
            index: row.integer(index)? as usize,
            case: row.case()?,
            limit_state: limit_state
                .map_or("overturning", |i| row.field(i))
                .to_string(),
            im: row.field(im).parse::<Im>().map_err(|e| row.error(im, &e))?,
            im_value: row.number(im_value)?,
            p: row.number(p)?,
            band,
        });
    }
    let stacks = stacks_beside(path)?;
    for r in &mut rows {
        r.case.stack = stacks.get(r.index).copied().flatten();
    }
    Ok(rows)
}

/// The stack of each row of the `fragility.csv` beside `path` (`None` for
/// a block's; empty without the file): the curves' and replicates' files
/// name a case by its six columns and its row there (`case`), so a stack,
/// whose six columns are its top block's, is known by that row's `case_id`.
fn stacks_beside(path: &Path) -> Result<Vec<Option<crate::case::StackName>>> {
    let fragility = path.with_file_name("fragility.csv");
    if !fragility.is_file() {
        return Ok(Vec::new());
    }
    Ok(read_fragility_csv(&fragility)?
        .into_iter()
        .map(|f| f.case.stack)
        .collect())
}

/// One row of `fragility_bootstrap.csv`: one bootstrap replicate of a case
/// and limit state.
#[derive(Clone, Debug, PartialEq)]
pub struct BootstrapRow {
    /// The row of the case and limit state in `fragility.csv`.
    pub index: usize,
    /// The case.
    pub case: Case,
    /// The limit state.
    pub limit_state: String,
    /// The intensity measure.
    pub im: Im,
    /// The replicate (0-based).
    pub replicate: usize,
    /// The replicate's (θ, β), or why it could not be fitted.
    pub fit: std::result::Result<(f64, f64), UnfitKind>,
}

impl BootstrapRow {
    /// The row's line, without its newline (columns of [`BOOTSTRAP_HEADER`]).
    pub fn line(&self) -> String {
        format!("{},{}", self.curve(), self.replicate_fields())
    }

    /// The row's first four fields: its curve (index, case, limit state,
    /// IM), the same for every replicate of a fit.
    fn curve(&self) -> String {
        format!(
            "{},{},{},{}",
            self.index,
            self.case.fields(),
            self.limit_state,
            crate::io_util::csv_field(self.im.name()),
        )
    }

    /// The row's other fields: the replicate and its fit.
    fn replicate_fields(&self) -> String {
        let (median, beta, status) = match &self.fit {
            Ok((m, b)) => (number(*m), number(*b), "ok"),
            Err(reason) => (String::new(), String::new(), reason.keyword()),
        };
        format!("{},{median},{beta},{status}", self.replicate)
    }
}

/// The bootstrap rows of `fit` (row `index` of `fragility.csv`); none for a
/// case that was not fitted or a fit without a bootstrap.
pub(crate) fn bootstrap_rows(index: usize, fit: &CaseFit) -> Vec<BootstrapRow> {
    let Some(boot) = fit.bootstrap.as_ref().filter(|_| fit.fit.is_ok()) else {
        return Vec::new();
    };
    boot.replicate_fits
        .iter()
        .enumerate()
        .map(|(r, f)| BootstrapRow {
            index,
            case: fit.key,
            limit_state: fit.limit_state.clone(),
            im: fit.im,
            replicate: r,
            fit: f.map_err(|reason| reason.kind()),
        })
        .collect()
}

/// Reads `fragility_bootstrap.csv`.
pub fn read_bootstrap_csv(path: &Path) -> Result<Vec<BootstrapRow>> {
    let (mut table, [index, ls, im, replicate, median, beta, status]) = Table::open(
        path,
        [
            "case",
            "limit_state",
            "im",
            "replicate",
            "median",
            "beta",
            "status",
        ],
        "reading fragility_bootstrap.csv",
    )?;
    let mut rows = Vec::new();
    while let Some(row) = table.next_row()? {
        let fit = if row.text(status)? == "ok" {
            Ok((row.positive(median)?, row.positive(beta)?))
        } else {
            Err(row
                .field(status)
                .parse::<UnfitKind>()
                .map_err(|e| row.error(status, &format!("ok or {e}")))?)
        };
        rows.push(BootstrapRow {
            index: row.integer(index)? as usize,
            case: row.case()?,
            limit_state: row.text(ls)?.to_string(),
            im: row.field(im).parse::<Im>().map_err(|e| row.error(im, &e))?,
            replicate: row.integer(replicate)? as usize,
            fit,
        });
    }
    let stacks = stacks_beside(path)?;
    for r in &mut rows {
        r.case.stack = stacks.get(r.index).copied().flatten();
    }
    Ok(rows)
}

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
/// and `fragility.xml` into `dir`, as one set (`fragility_set.json`, see
/// [`check_set`](super::check_set)). The NRML file holds every limit state,
/// in order (see [`nrml::nrml_string`]).
pub fn write_outputs(dir: &Path, fits: &[CaseFit]) -> Result<OutputPaths> {
    write_outputs_with(dir, fits, None)
}

/// As [`write_outputs`], and `fragility_surface.csv` from `surfaces` when
/// given, as part of the set. A fit without a surface removes the
/// `fragility_surface.csv` of the fit it replaces (listed in that fit's
/// set, so written by rockfrag): it is not this fit's.
pub fn write_outputs_with(
    dir: &Path,
    fits: &[CaseFit],
    surfaces: Option<&[super::surface_files::SurfaceRow]>,
) -> Result<OutputPaths> {
    use super::surface_files::SURFACE_FILE;
    let stale = surfaces.is_none() && super::set::listed(dir).iter().any(|f| f == SURFACE_FILE);
    let paths = OutputPaths {
        fragility: dir.join("fragility.csv"),
        curves: dir.join("fragility_curves.csv"),
        nrml: dir.join("fragility.xml"),
        bootstrap: dir.join("fragility_bootstrap.csv"),
    };
    // one set: readers refuse the folder's fit from `begin` to `complete`
    super::set::begin(dir)?;
    write_fragility_csv(&paths.fragility, fits)?;
    write_curves_csv(&paths.curves, fits)?;
    write_bootstrap_csv(&paths.bootstrap, fits)?;
    nrml::write_nrml(&paths.nrml, fits)?;
    let surface = dir.join(SURFACE_FILE);
    match surfaces {
        Some(rows) => super::surface_files::write_surface_csv(&surface, rows)?,
        None if stale && surface.is_file() => {
            std::fs::remove_file(&surface).map_err(Error::io(&surface))?
        }
        None => {}
    }
    let extra: &[&str] = if surfaces.is_some() {
        &[SURFACE_FILE]
    } else {
        &[]
    };
    super::set::complete(dir, extra)?;
    Ok(paths)
}

/// Writes `fragility.csv` (header [`FRAGILITY_HEADER`]).
pub(crate) fn write_fragility_csv(path: &Path, fits: &[CaseFit]) -> Result<()> {
    write_atomic(path, |w| {
        writeln!(w, "{FRAGILITY_HEADER}")?;
        for f in fits {
            writeln!(w, "{}", FragilityRow::from_fit(f).line())?;
        }
        Ok(())
    })
    .map_err(Error::io(path))
}

/// Writes `fragility_curves.csv` (header [`CURVES_HEADER`]).
pub(crate) fn write_curves_csv(path: &Path, fits: &[CaseFit]) -> Result<()> {
    write_atomic(path, |w| {
        writeln!(w, "{CURVES_HEADER}")?;
        for (i, f) in fits.iter().enumerate() {
            for row in curve_rows(i, f) {
                writeln!(w, "{}", row.line())?;
            }
        }
        Ok(())
    })
    .map_err(Error::io(path))
}

/// Writes `fragility_bootstrap.csv` (header [`BOOTSTRAP_HEADER`]).
pub(crate) fn write_bootstrap_csv(path: &Path, fits: &[CaseFit]) -> Result<()> {
    write_atomic(path, |w| {
        writeln!(w, "{BOOTSTRAP_HEADER}")?;
        for (i, f) in fits.iter().enumerate() {
            let rows = bootstrap_rows(i, f);
            // the curve's fields formatted once, not once a replicate
            let Some(curve) = rows.first().map(BootstrapRow::curve) else {
                continue;
            };
            for row in &rows {
                writeln!(w, "{curve},{}", row.replicate_fields())?;
            }
        }
        Ok(())
    })
    .map_err(Error::io(path))
}

/// A number, or an empty field when absent or NaN (infinity reads `inf`).
fn opt(x: Option<f64>) -> String {
    x.filter(|v| !v.is_nan()).map_or(String::new(), number)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fragility::{CaseData, Trial};
    use crate::fragility::{FragilityOptions, fit_case};
    use crate::solver::Friction;

    /// Every stage file reads back as the rows written.
    #[test]
    fn stage_files_round_trip() {
        // A case with overturning rising over four stripes of 10 records.
        let trials: Vec<Trial> = (0..4)
            .flat_map(|s| {
                (0..10).map(move |r| Trial {
                    record: r,
                    level: 0.3 * (s + 1) as f64,
                    im: 0.3 * (s + 1) as f64,
                    overturned: r < 2 + 2 * s,
                    exceeded: u64::from(r < 2 + 2 * s),
                })
            })
            .collect();
        let case = CaseData {
            key: Case::fixed(4.0, 0.5, 0.0, Friction::Infinite),
            records: (0..10).map(|r| r.to_string()).collect(),
            trials,
            failed: 0,
        };
        let options = FragilityOptions {
            bootstrap: 20,
            ..FragilityOptions::default()
        };
        let fits = fit_case(&case, &options);
        assert!(fits[0].fit.is_ok());
        let dir = tempfile::tempdir().unwrap();
        let paths = write_outputs(dir.path(), &fits).unwrap();
        let rows = read_fragility_csv(&paths.fragility).unwrap();
        assert_eq!(rows, vec![FragilityRow::from_fit(&fits[0])]);
        assert_eq!(
            read_curves_csv(&paths.curves).unwrap(),
            curve_rows(0, &fits[0])
        );
        assert_eq!(
            read_bootstrap_csv(&paths.bootstrap).unwrap(),
            bootstrap_rows(0, &fits[0])
        );
    }
}
