//! Hazard curves: the annual rate at which each intensity is exceeded at a
//! site, read from OpenQuake's hazard-curve CSV or from a plain
//! `iml,annual_rate` table.

use crate::detmath as dm;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result, number};
use crate::im::Im;

/// Where a hazard curve came from.
#[derive(Clone, Debug, PartialEq)]
pub enum HazardSource {
    /// An OpenQuake hazard-curve CSV (`hazard_curve-mean-PGA_*.csv`).
    OpenQuake {
        /// The IMT named in the header comment, e.g. `PGA`.
        imt: String,
        /// The investigation time T (years) of the probabilities.
        investigation_time: f64,
        /// The 0-based site (data row) used.
        site: usize,
        /// Its longitude and latitude (degrees).
        lon: f64,
        /// Latitude (degrees).
        lat: f64,
    },
    /// A plain `iml,annual_rate` CSV, IMLs in the unit of the fit's IM.
    Plain,
}

/// A hazard curve: strictly increasing intensity levels and the annual rate
/// of exceeding each, positive and non-increasing.
#[derive(Clone, Debug, PartialEq)]
pub struct HazardCurve {
    /// The file read.
    pub path: PathBuf,
    /// Its format and, for OpenQuake's, the IMT, investigation time and site.
    pub source: HazardSource,
    /// Intensity levels, strictly increasing, > 0.
    pub iml: Vec<f64>,
    /// Annual rate of exceeding each level (1/yr), > 0, non-increasing.
    pub rate: Vec<f64>,
    /// Levels left out at the low end because their probability of
    /// exceedance was 1 (an infinite rate) or so close to 1 that its digits
    /// fix the rate to worse than [`MIN_RATE_PRECISION`] (OpenQuake's 7
    /// digits: poe above about 1 − 5·10⁻⁴).
    pub dropped_low: usize,
    /// Levels left out at the high end because their rate was 0 (the
    /// hazard beyond them is then taken as the last positive segment's
    /// power law, an upper bound, see [`crate::risk`]).
    pub dropped_high: usize,
    /// The site a plain file names in a `# site: …` comment (as
    /// [`USED_HAZARD`] does), see [`HazardCurve::site`].
    pub site_label: Option<String>,
}

impl HazardCurve {
    /// A curve from levels and rates (already in the unit of the fit's IM),
    /// validated as [`read_hazard`] does; `path` names it in errors.
    ///
    /// ```
    /// use rockfrag::risk::HazardCurve;
    /// let h = HazardCurve::from_rates("k0 a^-k".as_ref(), &[0.1, 1.0], &[0.1, 1e-3]).unwrap();
    /// assert_eq!(h.iml.len(), 2);
    /// ```
    pub fn from_rates(path: &Path, iml: &[f64], rate: &[f64]) -> Result<HazardCurve> {
        let points: Vec<(usize, f64, f64)> = iml
            .iter()
            .zip(rate)
            .enumerate()
            .map(|(i, (&x, &r))| (i + 1, x, r))
            .collect();
        finish(path, HazardSource::Plain, &points, 0)
    }

    /// The curve with its levels in the unit of a fit against `im` (`pga`
    /// in g, `pgv` in m/s): OpenQuake's IMT must be that IM's
    /// ([`Im::from_openquake`]: PGA in g, PGV in cm/s, converted); a plain
    /// file is taken to be in the fit's unit already.
    ///
    /// Errors: [`Error::Conflict`] naming the file, its IMT and the fit's IM
    /// when they differ.
    pub fn in_unit_of(mut self, im: Im) -> Result<HazardCurve> {
        let HazardSource::OpenQuake { imt, .. } = &self.source else {
            self.check_plain_unit(im)?;
            return Ok(self);
        };
        let Some(scale) = im.from_openquake(imt) else {
            return Err(Error::Conflict {
                path: self.path.clone(),
                message: format!(
                    "the hazard curve is for imt='{imt}' but the fragility was fitted \
                     against {im}; give a hazard curve for {} (or refit the fragility \
                     with --im matching the hazard)",
                    im.openquake_hint()
                ),
            });
        };
        self.iml.iter_mut().for_each(|x| *x *= scale);
        Ok(self)
    }
}

/// A plain hazard file's levels are taken in the fit's unit (g for PGA,
/// m/s for PGV): one whose lowest level is at or above this, or whose
/// highest is above [`PLAIN_MAX_LEVEL`], is refused as being in another
/// unit (cm/s² or m/s², cm/s): a hazard curve in g starts well below 1 g
/// (OpenQuake's default levels from 0.005 g), one in m/s well below 1 m/s.
pub const PLAIN_MIN_LEVEL: f64 = 2.0;

/// See [`PLAIN_MIN_LEVEL`]: no hazard curve needs levels above 20 g (the
/// largest recorded PGA is about 4.4 g) or 20 m/s.
pub const PLAIN_MAX_LEVEL: f64 = 20.0;

impl HazardCurve {
    /// Refuses a plain file whose levels cannot be in the unit of a fit
    /// against `im` ([`PLAIN_MIN_LEVEL`], [`PLAIN_MAX_LEVEL`]), naming the
    /// levels and the likely unit; PGA/(g tan θc) is not checked.
    fn check_plain_unit(&self, im: Im) -> Result<()> {
        let Some(likely) = im.other_units() else {
            return Ok(());
        };
        let unit = im.unit();
        let (lo, hi) = (self.iml[0], self.iml[self.iml.len() - 1]);
        if lo < PLAIN_MIN_LEVEL && hi <= PLAIN_MAX_LEVEL {
            return Ok(());
        }
        Err(Error::Parse {
            path: self.path.clone(),
            line: 0,
            message: format!(
                "levels from {lo} to {hi}: a plain iml,annual_rate file is taken in the fit's \
                 unit, {unit} ({im}), and a hazard curve in {unit} starts below \
                 {PLAIN_MIN_LEVEL} and ends at most at {PLAIN_MAX_LEVEL} {unit}; these levels \
                 look like {likely}: convert them"
            ),
        })
    }
}

impl HazardCurve {
    /// λ(im): the curve interpolated log–log, its first and last segments'
    /// power laws extended beyond its levels (as the risk integral does).
    ///
    /// ```
    /// use rockfrag::risk::HazardCurve;
    /// let h = HazardCurve::from_rates("".as_ref(), &[0.1, 1.0], &[1e-2, 1e-4]).unwrap();
    /// assert!((h.rate_at(0.316_227_766) / 1e-3 - 1.0).abs() < 1e-8);
    /// assert!((h.rate_at(10.0) / 1e-6 - 1.0).abs() < 1e-12);
    /// ```
    pub fn rate_at(&self, im: f64) -> f64 {
        let n = self.iml.len();
        let i = self.iml.partition_point(|&x| x <= im).clamp(1, n - 1) - 1;
        let (u0, u1) = (dm::ln(self.iml[i]), dm::ln(self.iml[i + 1]));
        let (l0, l1) = (dm::ln(self.rate[i]), dm::ln(self.rate[i + 1]));
        dm::exp(l0 + (l1 - l0) * (dm::ln(im) - u0) / (u1 - u0))
    }
}

impl HazardCurve {
    /// Where the curve is for, as a figure names it: `site K of FILE` for
    /// an OpenQuake curve, else the file's name; for a plain file with a
    /// `# site: …` comment (as [`USED_HAZARD`] has), that site.
    pub fn site(&self) -> String {
        if let Some(site) = &self.site_label {
            return site.clone();
        }
        let name = self
            .path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        match &self.source {
            HazardSource::OpenQuake { site, .. } => format!("site {site} of {name}"),
            HazardSource::Plain => name,
        }
    }
}

/// The file `rockfrag risk` writes beside `risk.csv`: the hazard curve it
/// integrated over, as a plain `iml,annual_rate` table (levels in the fit's
/// unit, exactly the levels used: those left out at the ends are not in
/// it). `rockfrag figures` redraws the risk figure from it and the study's
/// fit, and it is itself a hazard file `rockfrag risk --hazard` reads.
pub const USED_HAZARD: &str = "risk_hazard.csv";

/// The comment line of [`USED_HAZARD`] naming the site.
const SITE_COMMENT: &str = "# site: ";

/// Writes `hazard` to `path` as [`USED_HAZARD`] is written: comment lines
/// saying what it is and naming its site ([`HazardCurve::site`]), then
/// `iml,annual_rate` with every number as the shortest text that reads back
/// exactly, so that [`read_hazard`] gives the same curve bit for bit, at the
/// same site.
pub fn write_used_hazard(path: &Path, hazard: &HazardCurve) -> Result<()> {
    let name = hazard
        .path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    crate::io_util::write_atomic(path, |w| {
        writeln!(
            w,
            "# the hazard curve rockfrag risk integrated over, from {name}: annual rate of \
             exceeding each level, levels in the fit's unit"
        )?;
        writeln!(w, "{SITE_COMMENT}{}", hazard.site())?;
        writeln!(w, "iml,annual_rate")?;
        for (x, r) in hazard.iml.iter().zip(&hazard.rate) {
            writeln!(
                w,
                "{},{}",
                crate::io_util::number(*x),
                crate::io_util::number(*r)
            )?;
        }
        Ok(())
    })
    .map_err(Error::io(path))
}

/// Reads a hazard curve: OpenQuake's hazard-curve CSV (a first comment line
/// with `investigation_time=…` and `imt='…'`, a header
/// `lon,lat,depth,poe-<iml>,…`, a row per site; `site` picks the 0-based
/// row, default the first) or a plain CSV with columns `iml` and
/// `annual_rate` (lines starting with `#` are comments; one starting
/// `# site: ` names the curve's site, see [`HazardCurve::site`]). Probabilities of
/// exceedance in the investigation time T become annual rates
/// λ = −ln(1 − poe)/T (Poisson occurrence, as OpenQuake assumes).
///
/// Levels at the low end whose poe is 1 (an infinite rate) or too close to 1
/// for its digits to fix the rate to 0.1 % ([`MIN_RATE_PRECISION`]), and
/// levels with a zero rate at the high end, are left out and counted. The levels must increase
/// and the rates must not.
///
/// Errors: [`Error::Io`]; [`Error::Parse`] naming the file, the line, the
/// column and the value for anything malformed, and the number of sites
/// when `site` is beyond them.
pub fn read_hazard(path: &Path, site: Option<usize>) -> Result<HazardCurve> {
    // 64 MiB: an OpenQuake hazard-curve CSV of 10⁵ sites is some 30 MB
    let text = crate::io_util::read_text_limited(path, 64 << 20, "a hazard curve file")
        .map_err(Error::io(path))?;
    let lines: Vec<String> = text.lines().map(str::to_string).collect();
    let first = lines.iter().position(|l| !l.trim().is_empty());
    let is_openquake = first.is_some_and(|i| {
        let l = lines[i].trim_start();
        l.starts_with('#') && l.contains("imt=")
    });
    if is_openquake {
        read_openquake(path, &lines, site.unwrap_or(0))
    } else {
        if let Some(k) = site.filter(|&k| k > 0) {
            return Err(parse(
                path,
                0,
                format!(
                    "--site {k} needs an OpenQuake file; a plain iml,annual_rate file holds one site"
                ),
            ));
        }
        read_plain(path, &lines)
    }
}

fn parse(path: &Path, line: usize, message: String) -> Error {
    Error::Parse {
        path: path.to_path_buf(),
        line,
        message,
    }
}

/// The text after `key=` in an OpenQuake header comment, up to the next
/// comma or quote (for a number) or the matching quote (for a string).
fn metadata<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    let mut rest = line;
    loop {
        let i = rest.find(key)?;
        let before = rest[..i].chars().next_back();
        rest = &rest[i + key.len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let Some(value) = rest.strip_prefix('=') else {
            continue;
        };
        let value = value.trim_start();
        return Some(match value.chars().next() {
            Some(q @ ('\'' | '"')) => {
                let inner = &value[1..];
                &inner[..inner.find(q).unwrap_or(inner.len())]
            }
            _ => {
                let end = value
                    .find(|c: char| c == ',' || c == '"' || c == '\'' || c.is_whitespace())
                    .unwrap_or(value.len());
                &value[..end]
            }
        });
    }
}

fn read_openquake(path: &Path, lines: &[String], site: usize) -> Result<HazardCurve> {
    let mut numbered = lines
        .iter()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty());
    let (meta_line, meta) = numbered.next().expect("checked by the caller");
    let imt = metadata(meta, "imt")
        .ok_or_else(|| parse(path, meta_line, "no imt='…' in the header comment".into()))?
        .to_string();
    let t_text = metadata(meta, "investigation_time").ok_or_else(|| {
        parse(
            path,
            meta_line,
            "no investigation_time=… in the header comment".into(),
        )
    })?;
    let t: f64 = t_text
        .parse()
        .ok()
        .filter(|t: &f64| t.is_finite() && *t > 0.0)
        .ok_or_else(|| {
            parse(
                path,
                meta_line,
                format!("investigation_time = {t_text:?}: expected a number of years > 0"),
            )
        })?;
    let (header_line, header) = numbered.next().ok_or_else(|| {
        parse(
            path,
            meta_line + 1,
            "no header line after the comment".into(),
        )
    })?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let lon = names.iter().position(|n| *n == "lon");
    let lat = names.iter().position(|n| *n == "lat");
    let mut poe_columns = Vec::new();
    for (c, name) in names.iter().enumerate() {
        if let Some(level) = name.strip_prefix("poe-") {
            let x: f64 = level
                .parse()
                .ok()
                .filter(|x: &f64| x.is_finite() && *x > 0.0)
                .ok_or_else(|| {
                    parse(
                        path,
                        header_line,
                        format!("column {name:?}: expected poe-<intensity level > 0>"),
                    )
                })?;
            poe_columns.push((c, name, x));
        }
    }
    if poe_columns.len() < 2 {
        return Err(parse(
            path,
            header_line,
            format!(
                "{} poe-<iml> columns in the header: expected at least 2",
                poe_columns.len()
            ),
        ));
    }
    let mut rows = numbered.filter(|(_, l)| !l.starts_with('#'));
    let mut n_sites = 0;
    let (line, row) = loop {
        match rows.next() {
            Some((line, row)) if n_sites == site => break (line, row),
            Some(_) => n_sites += 1,
            None => {
                return Err(parse(
                    path,
                    0,
                    format!("--site {site}: the file has {n_sites} site row(s), numbered from 0"),
                ));
            }
        }
    };
    let fields: Vec<&str> = row.split(',').map(str::trim).collect();
    if fields.len() != names.len() {
        return Err(parse(
            path,
            line,
            format!(
                "{} fields: expected {} as in the header",
                fields.len(),
                names.len()
            ),
        ));
    }
    let coordinate = |c: Option<usize>| -> Result<f64> {
        c.map_or(Ok(f64::NAN), |c| {
            fields[c].parse().map_err(|_| {
                parse(
                    path,
                    line,
                    format!("column {}: {:?} is not a number", names[c], fields[c]),
                )
            })
        })
    };
    let (lon, lat) = (coordinate(lon)?, coordinate(lat)?);
    let mut points = Vec::with_capacity(poe_columns.len());
    let mut precision = Vec::with_capacity(poe_columns.len());
    for &(c, name, x) in &poe_columns {
        let poe: f64 = fields[c]
            .parse()
            .ok()
            .filter(|p: &f64| (0.0..=1.0).contains(p))
            .ok_or_else(|| {
                parse(
                    path,
                    line,
                    format!(
                        "column {name}: {:?} is not a probability of exceedance in [0, 1]",
                        fields[c]
                    ),
                )
            })?;
        let rate = -dm::ln_1p(-poe) / t;
        precision.push(rate_precision(fields[c], poe, rate * t));
        points.push((line, x, rate));
    }
    // poe = 1 at the low end (an infinite rate), or so close to 1 that the
    // file's digits fix the rate to worse than MIN_RATE_PRECISION: left out.
    let dropped_low = precision
        .iter()
        .take_while(|&&p| p > MIN_RATE_PRECISION || p.is_nan())
        .count();
    let source = HazardSource::OpenQuake {
        imt,
        investigation_time: t,
        site,
        lon,
        lat,
    };
    finish(path, source, &points[dropped_low..], dropped_low)
}

/// Relative precision below which a rate read from a poe near 1 is used:
/// with OpenQuake's 7 significant digits, poe up to about 1 − 5·10⁻⁴
/// (λT ≈ 7.6).
pub const MIN_RATE_PRECISION: f64 = 1e-3;

/// The relative precision of λ = −ln(1 − poe)/T given the digits of the
/// poe as written (`text`): half a unit in its last digit, δpoe, gives
/// δλ/λ = δpoe / ((1 − poe)·λT). Infinite for poe = 1.
fn rate_precision(text: &str, poe: f64, lambda_t: f64) -> f64 {
    let mantissa = text.split(['e', 'E']).next().unwrap_or(text);
    let digits = mantissa
        .chars()
        .filter(char::is_ascii_digit)
        .skip_while(|&c| c == '0')
        .count()
        .max(1);
    let half_ulp = 0.5 * poe * dm::powi(10.0, 1 - digits as i32);
    if lambda_t > 0.0 {
        half_ulp / ((1.0 - poe) * lambda_t)
    } else {
        0.0
    }
}

fn read_plain(path: &Path, lines: &[String]) -> Result<HazardCurve> {
    let mut numbered = lines
        .iter()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (header_line, header) = numbered.next().ok_or_else(|| {
        parse(
            path,
            1,
            "empty file: expected a header iml,annual_rate".into(),
        )
    })?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let column = |name: &str| {
        names.iter().position(|n| *n == name).ok_or_else(|| {
            parse(
                path,
                header_line,
                format!(
                    "no column {name:?} in the header {header:?}: expected an OpenQuake \
                     hazard-curve CSV or a plain CSV with columns iml,annual_rate"
                ),
            )
        })
    };
    let (ci, cr) = (column("iml")?, column("annual_rate")?);
    let site = lines
        .iter()
        .find_map(|l| l.trim().strip_prefix(SITE_COMMENT))
        .map(|s| s.trim().to_string());
    let mut points = Vec::new();
    for (line, row) in numbered {
        let fields: Vec<&str> = row.split(',').map(str::trim).collect();
        let get = |c: usize, what: &str, ok: fn(f64) -> bool| -> Result<f64> {
            let text = fields.get(c).copied().unwrap_or("");
            text.parse().ok().filter(|&x| ok(x)).ok_or_else(|| {
                parse(
                    path,
                    line,
                    format!("column {}: {text:?}: expected {what}", names[c]),
                )
            })
        };
        let x = get(ci, "an intensity level > 0", |x| x.is_finite() && x > 0.0)?;
        let r = get(cr, "an annual rate ≥ 0", |r| r.is_finite() && r >= 0.0)?;
        points.push((line, x, r));
    }
    let mut hazard = finish(path, HazardSource::Plain, &points, 0)?;
    hazard.site_label = site;
    Ok(hazard)
}

/// The largest annual rate of exceedance a hazard curve may give: 1000 a
/// year, nearly three a day (a curve's lowest levels, a few thousandths of
/// g, are exceeded a few times a year at the most active sites). Rates of
/// 10²⁰⁰ made the figure's axes loop for minutes.
pub const MAX_ANNUAL_RATE: f64 = 1e3;

/// Validates (line, level, rate) points and drops the zero rates at the top.
fn finish(
    path: &Path,
    source: HazardSource,
    points: &[(usize, f64, f64)],
    dropped_low: usize,
) -> Result<HazardCurve> {
    for w in points.windows(2) {
        let ((_, x0, r0), (line, x1, r1)) = (w[0], w[1]);
        if x1 <= x0 || x1.is_nan() {
            return Err(parse(
                path,
                line,
                format!(
                    "intensity level {} after {}: the levels must increase",
                    number(x1),
                    number(x0)
                ),
            ));
        }
        if r1 > r0 {
            return Err(parse(
                path,
                line,
                format!(
                    "rate of exceeding {} ({r1:e}/yr) is above that of {} ({r0:e}/yr): \
                     a hazard curve cannot rise",
                    number(x1),
                    number(x0)
                ),
            ));
        }
    }
    if let Some(&(line, x, r)) = points.iter().find(|p| !p.2.is_finite()) {
        return Err(parse(
            path,
            line,
            format!(
                "intensity level {}: rate {}: expected a finite rate (poe < 1)",
                number(x),
                number(r)
            ),
        ));
    }
    if let Some(&(line, x, r)) = points.iter().find(|p| p.2 > MAX_ANNUAL_RATE) {
        return Err(parse(
            path,
            line,
            format!(
                "intensity level {x}: rate {r:e}/yr: expected an annual rate ≤ {MAX_ANNUAL_RATE} \
                 (more than {} exceedances a day is no site's hazard: a rate per second or per \
                 day, or an investigation time in seconds?)",
                crate::io_util::sig3(MAX_ANNUAL_RATE / 365.25)
            ),
        ));
    }
    let positive = points.iter().take_while(|p| p.2 > 0.0).count();
    if positive < 2 {
        return Err(parse(
            path,
            points.first().map_or(0, |p| p.0),
            format!(
                "{positive} intensity level(s) with a finite rate > 0: expected at least 2 \
                 to interpolate"
            ),
        ));
    }
    let kept = &points[..positive];
    Ok(HazardCurve {
        path: path.to_path_buf(),
        source,
        iml: kept.iter().map(|p| p.1).collect(),
        rate: kept.iter().map(|p| p.2).collect(),
        dropped_low,
        dropped_high: points.len() - positive,
        site_label: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both header-comment layouts OpenQuake has written: the engine 3.x
    /// `#,,,"…, investigation_time=50.0, imt='PGA'"` and the older
    /// `# …, investigation_time=1.0, imt="PGA", checksum=…`.
    #[test]
    fn metadata_reads_both_header_styles() {
        let new = "#,,,,\"generated_by='OpenQuake engine 3.16.0', start_date='2023-01-01', \
                   checksum=1, kind='mean', investigation_time=50.0, imt='PGA'\"";
        assert_eq!(metadata(new, "imt"), Some("PGA"));
        assert_eq!(metadata(new, "investigation_time"), Some("50.0"));
        let old = "# source_model_tree_path=('b11',), gsim_tree_path=('b1',), \
                   investigation_time=1.0, imt=\"SA(0.1)\", checksum=141718627";
        assert_eq!(metadata(old, "imt"), Some("SA(0.1)"));
        assert_eq!(metadata(old, "investigation_time"), Some("1.0"));
        assert_eq!(metadata(old, "kind"), None);
    }
}
