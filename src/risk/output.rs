//! `risk.csv` and the `## Risk` section of `summary.md`, both written
//! atomically.

use std::path::Path;

use super::assess::{RiskOptions, RiskRow, standing_rows};
use super::hazard::{HazardCurve, HazardSource};
use crate::case::Case;
use crate::error::{Error, Result};
use crate::fragility::FitStatus;
use crate::im::Im;
use crate::io_util::{number, sig3, write_atomic};
use crate::table::Table;

/// Header of `risk.csv`, one row per row of `fragility.csv` (same
/// `case_id`, case columns and `limit_state`, same order). `median`, `beta` are the fit's
/// (unit of `im`, `im_unit`); `annual_rate` is λ_LS (1/yr) and
/// `annual_rate_lo`, `annual_rate_hi` its bootstrap percentile band (empty
/// without `fragility_bootstrap.csv`); `return_period` = 1/λ_LS (years;
/// `inf` for a rate of 0);
/// `poe` = 1 − exp(−λ_LS·`years`); `peak_im` the intensity (unit of `im`)
/// where the rate's density over ln im peaks; `share_below`, `share_above`
/// the fractions of λ_LS from beyond the hazard curve's lowest and highest
/// levels; `boot_fitted` the replicates behind the band; `status` the fit's
/// (`ok`; a fitted curve's caveat, e.g. `extrapolated-above`, see
/// `fragility.csv`; or why there is no curve and the numbers are empty).
pub const RISK_HEADER: &str = "case_id,aspect,width,restitution,friction,mu_s,mu_k,limit_state,im,\
im_unit,median,beta,annual_rate,annual_rate_lo,annual_rate_hi,return_period,years,poe,peak_im,\
share_below,share_above,boot_fitted,status";

/// One row of `risk.csv` ([`RISK_HEADER`]), as [`write_risk_csv`] writes
/// it and [`read_risk_csv`] reads it back: the one place that knows the
/// file's columns. Numbers are `None` where the file has an empty field.
#[derive(Clone, Debug, PartialEq)]
pub struct RiskCsvRow {
    /// The case (`case_id` and the case columns).
    pub case: Case,
    /// The limit state.
    pub limit_state: String,
    /// The IM of the fit (`im`, `im_unit`).
    pub im: Im,
    /// The fit's median θ and β.
    pub fit: Option<(f64, f64)>,
    /// λ_LS, 1/yr.
    pub annual_rate: Option<f64>,
    /// The bootstrap percentile band of λ_LS.
    pub band: Option<(f64, f64)>,
    /// 1/λ_LS, years (+∞ for a rate of 0, written `inf`).
    pub return_period: Option<f64>,
    /// The exposure time N, years.
    pub years: f64,
    /// 1 − exp(−λ_LS·N).
    pub poe: Option<f64>,
    /// Where the rate's density over ln im peaks (unit of `im`).
    pub peak_im: Option<f64>,
    /// Fractions of λ_LS from beyond the lowest and highest hazard levels.
    pub shares: Option<(f64, f64)>,
    /// Bootstrap replicates behind the band (`None` without a rate).
    pub boot_fitted: Option<usize>,
    /// The fit's status (`ok`, a caveat, or why there is no curve).
    pub status: FitStatus,
}

impl RiskCsvRow {
    /// The row of `r` over an exposure of `years`.
    pub fn of(r: &RiskRow, years: f64) -> RiskCsvRow {
        let c = &r.curve;
        RiskCsvRow {
            case: c.key,
            limit_state: c.limit_state.clone(),
            im: c.im,
            fit: c.fit,
            annual_rate: r.rate(),
            band: r.band.map(|b| (b.lo, b.hi)),
            return_period: r.return_period(),
            years,
            poe: r.poe(years),
            peak_im: r.integral.map(|i| i.peak_im),
            shares: r.shares(),
            boot_fitted: r.integral.map(|_| c.replicates.len()),
            status: c.status,
        }
    }

    /// The row's line, without its newline.
    pub fn line(&self) -> String {
        let opt = |x: Option<f64>| x.filter(|v| v.is_finite()).map_or(String::new(), number);
        let fields = [
            self.case.id(),
            self.case.fields(),
            self.limit_state.clone(),
            crate::io_util::csv_field(self.im.name()),
            self.im.unit().to_string(),
            opt(self.fit.map(|f| f.0)),
            opt(self.fit.map(|f| f.1)),
            opt(self.annual_rate),
            opt(self.band.map(|b| b.0)),
            opt(self.band.map(|b| b.1)),
            // +∞ (a rate of 0) as `inf`: never.
            self.return_period.map_or(String::new(), number),
            number(self.years),
            opt(self.poe),
            opt(self.peak_im),
            opt(self.shares.map(|s| s.0)),
            opt(self.shares.map(|s| s.1)),
            self.boot_fitted.map_or(String::new(), |n| n.to_string()),
            self.status.to_string(),
        ];
        fields.join(",")
    }
}

/// Writes `risk.csv` (header [`RISK_HEADER`]).
pub fn write_risk_csv(path: &Path, rows: &[RiskRow], options: &RiskOptions) -> Result<()> {
    write_atomic(path, |w| {
        writeln!(w, "{RISK_HEADER}")?;
        for r in rows {
            writeln!(w, "{}", RiskCsvRow::of(r, options.years).line())?;
        }
        Ok(())
    })
    .map_err(Error::io(path))
}

/// Reads a `risk.csv` written by [`write_risk_csv`]. Errors name the file,
/// line, column and value: a header that is not [`RISK_HEADER`], a bad
/// number, an unknown IM or a unit that is not the IM's.
pub fn read_risk_csv(path: &Path) -> Result<Vec<RiskCsvRow>> {
    let names: Vec<&str> = RISK_HEADER.split(',').collect();
    let (mut table, c) = Table::open_dyn(path, &names, "reading risk.csv")?;
    let col = |name: &str| {
        c[names
            .iter()
            .position(|n| *n == name)
            .expect("a risk.csv column")]
    };
    let mut rows = Vec::new();
    while let Some(row) = table.next_row()? {
        let opt = |name: &str| -> Result<Option<f64>> {
            let i = col(name);
            if row.field(i).is_empty() {
                Ok(None)
            } else {
                row.number(i).map(Some)
            }
        };
        let both = |a: &str, b: &str| -> Result<Option<(f64, f64)>> { Ok(opt(a)?.zip(opt(b)?)) };
        let im: Im = row
            .field(col("im"))
            .parse()
            .map_err(|e: String| row.error(col("im"), &e))?;
        if row.field(col("im_unit")) != im.unit() {
            return Err(row.error(col("im_unit"), &format!("{im}'s unit, {}", im.unit())));
        }
        let boot = col("boot_fitted");
        rows.push(RiskCsvRow {
            case: row.case()?,
            limit_state: row.text(col("limit_state"))?.to_string(),
            im,
            fit: both("median", "beta")?,
            annual_rate: opt("annual_rate")?,
            band: both("annual_rate_lo", "annual_rate_hi")?,
            return_period: opt("return_period")?,
            years: row.number(col("years"))?,
            poe: opt("poe")?,
            peak_im: opt("peak_im")?,
            shares: both("share_below", "share_above")?,
            boot_fitted: if row.field(boot).is_empty() {
                None
            } else {
                Some(row.integer(boot)? as usize)
            },
            status: row
                .text(col("status"))?
                .parse()
                .map_err(|e: String| row.error(col("status"), &e))?,
        });
    }
    Ok(rows)
}

/// One line naming the hazard curve: file, format, IMT, investigation time,
/// site.
pub fn describe_hazard(h: &HazardCurve) -> String {
    let name = h.path.file_name().map_or_else(
        || h.path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let levels = format!(
        "{} levels, {} to {}",
        h.iml.len(),
        sig3(h.iml[0]),
        sig3(h.iml[h.iml.len() - 1])
    );
    match &h.source {
        HazardSource::OpenQuake {
            imt,
            investigation_time,
            site,
            lon,
            lat,
        } => format!(
            "`{name}` (OpenQuake, imt='{imt}', investigation_time={investigation_time} yr, \
             site {site} at lon {lon}, lat {lat}; {levels})"
        ),
        HazardSource::Plain => format!("`{name}` (iml,annual_rate; {levels})"),
    }
}

/// A probability for the console and summary: 4 decimals from 0.01 up
/// (a survival near 1 keeps its digits), 3 significant digits below.
fn probability(p: f64) -> String {
    if p >= 0.01 {
        format!("{p:.4}")
    } else {
        sig3(p)
    }
}

/// P(still standing after `years` years) of one row of
/// [`standing_rows`], as printed: exp(−λN) with its bootstrap band, the
/// limit state named unless it is `overturning`, or why there is none.
pub fn survival_cell(row: &RiskRow, years: f64) -> String {
    let Some(p) = row.survival(years) else {
        return format!("not fitted ({})", row.curve.status);
    };
    let band = row.survival_band(years).map_or(String::new(), |b| {
        format!(" [{}, {}]", probability(b.lo), probability(b.hi))
    });
    match row.curve.limit_state.as_str() {
        "overturning" => format!("{}{band}", probability(p)),
        ls => format!("{}{band} (not exceeding {ls})", probability(p)),
    }
}

/// The `## Risk` section of `summary.md`: the hazard used and a table of the
/// rates, return periods and probabilities over `options.years`.
pub fn summary_section(rows: &[RiskRow], hazard: &HazardCurve, options: &RiskOptions) -> String {
    let unit = rows
        .first()
        .map_or(String::new(), |r| r.curve.im.unit_suffix());
    let pct = (options.confidence * 100.0).round();
    let years = number(options.years);
    let mut s = format!(
        "## Risk\n\nAnnual rate of each limit state over the hazard curve {}, from \
         `rockfrag risk` (`risk.csv`, `figures/risk.svg`): λ = ∫ P(LS | im) |dλ/dim| dim, the \
         hazard interpolated log–log. [{pct} %]: bootstrap band of the fit carried through. \
         Peak IM: the intensity that contributes most (the rate's density over ln IM).\n\n\
         | case | limit state | annual rate [{pct} %] | return period (yr) | P in {years} yr | \
         peak IM{unit} |\n|---|---|---|---|---|---|\n",
        describe_hazard(hazard)
    );
    let mut worst: (f64, f64) = (0.0, 0.0);
    for r in rows {
        let c = &r.curve;
        let Some(rate) = r.rate() else {
            s.push_str(&format!(
                "| {} | {} | not fitted ({}) | | | |\n",
                c.key, c.limit_state, c.status
            ));
            continue;
        };
        let band = r.band.map_or(String::new(), |b| {
            format!(" [{}, {}]", sig3(b.lo), sig3(b.hi))
        });
        let (below, above) = r.shares().unwrap_or_default();
        worst = (worst.0.max(below), worst.1.max(above));
        s.push_str(&format!(
            "| {} | {} | {}{band} | {} | {} | {} |\n",
            c.key,
            c.limit_state,
            sig3(rate),
            r.return_period_text().unwrap_or_default(),
            sig3(r.poe(options.years).unwrap_or(f64::NAN)),
            r.peak_text(),
        ));
    }
    s.push_str(&format!(
        "\nLargest shares of a rate from beyond the hazard curve's ends (power-law \
         extrapolation): {:.2} % below its lowest level, {:.2} % above its highest.\n",
        100.0 * worst.0,
        100.0 * worst.1
    ));
    s.push_str(&format!(
        "\nP(still standing after {years} years) = exp(−λN), λ the rate of overturning: \
         for an object that has stood that long (a precariously balanced rock), how likely \
         the hazard curve makes it; a small value argues against the hazard curve.\n\n\
         | case | P(still standing after {years} years) [{pct} %] |\n|---|---|\n"
    ));
    for r in standing_rows(rows) {
        s.push_str(&format!(
            "| {} | {} |\n",
            r.curve.key,
            survival_cell(r, options.years)
        ));
    }
    s
}
