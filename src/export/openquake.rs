//! `rockfrag export openquake`: a runnable OpenQuake `classical_damage` job
//! whose annual rates are `rockfrag risk`'s.
//!
//! The job folder holds `job.ini`, `exposure.xml` (one asset per fragility
//! function, its taxonomy the function's id, at the hazard site),
//! `fragility.xml` (the study's, whose `minIML`/`maxIML` are where every
//! curve is 0 and 1, see [`crate::fragility::nrml_string`]), a one-site
//! `hazard.csv` in OpenQuake's layout, `expected.csv` (rockfrag's rates, to
//! compare with) and a `README.md` on running it and reading it back.
//!
//! **Why the hazard is resampled.** OpenQuake's `classical_damage`
//! (`risklib/scientific.py`) gives hazard level i the rate
//! (λᵢ₋₁ − λᵢ₊₁)/2 and the fragility at the level, and counts nothing
//! beyond the first and last levels. On a hazard of log-slope k with levels
//! h apart in ln IM that is biased by cosh(kh/2) − 1 ≈ (kh)²/8, always
//! high: +5 to +12 % on a typical 25-level curve. Below 1 % needs
//! h ≤ 0.283/k, i.e. at least 8.14·k levels per decade. The job's hazard is
//! the same curve (rockfrag's log–log interpolant of the file, its end
//! segments' power laws beyond it), sampled on log-uniform levels from the
//! model's minIML up to where λ has fallen to 10⁻⁵ of λ(maxIML), at
//! 1.25 × 8.14 × k_eff levels per decade (at least 20), k_eff the
//! hazard's log-slope averaged (root mean square) with the weight of each
//! curve's integrand P·(−dλ/d ln IM), the largest over the curves.
//!
//! **Why the investigation time is chosen.** OpenQuake reads the
//! probabilities as 32-bit floats and takes 1 − poe in 32 bits, so λT is
//! known only to about 6·10⁻⁸ absolute, and λT above about 17 reads as
//! poe = 1. T is a power of ten that puts the rate at every curve's median
//! at λT ≥ 10⁻³, lowered (not below 1 year) while a level where a curve
//! exceeds 10⁻⁶ would have λT > 15. OpenQuake takes the investigation time
//! from the CSV's header; `job.ini` says the same.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::detmath as dm;
use crate::error::{Error, Result};
use crate::fragility::{Caveat, FitStatus, FragilityRow, IML_SIGMAS, read_fragility_csv};
use crate::im::Im;
use crate::io_util::{number, sig3, write_atomic};
use crate::risk::{HazardCurve, HazardSource, read_hazard, risk_integral};

/// Levels per decade OpenQuake's quadrature needs per unit of hazard
/// log-slope for a bias below 1 %: kh ≤ 2 acosh(1.01) = 0.283.
pub const LEVELS_PER_DECADE_PER_SLOPE: f64 = 8.14;
/// Safety factor on that density.
const DENSITY_MARGIN: f64 = 1.25;
/// The fewest levels per decade written.
const MIN_LEVELS_PER_DECADE: f64 = 20.0;
/// The levels go up to where λ has fallen to this fraction of λ(maxIML).
const TOP_RATE_FRACTION: f64 = 1e-5;

/// What [`export_openquake`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct OpenQuakeJob {
    /// The job folder.
    pub dir: PathBuf,
    /// Fragility functions (= assets) of the model.
    pub functions: usize,
    /// Cases of `fragility.csv` not in the model, with why.
    pub omitted: Vec<String>,
    /// Hazard levels written.
    pub levels: usize,
    /// Their density, levels per decade.
    pub levels_per_decade: f64,
    /// The hazard's effective log-slope k_eff that set it.
    pub slope: f64,
    /// The investigation time of `hazard.csv` (years).
    pub investigation_time: f64,
    /// rockfrag's annual rate of each fitted case and limit state: (case
    /// id, limit state, rate), as `expected.csv` holds them.
    pub expected: Vec<(String, String, f64)>,
}

/// Writes an OpenQuake `classical_damage` job folder `out` for the fitted
/// study folder `dir` (its `fragility.csv` and `fragility.xml`) over the
/// hazard curve `hazard` (OpenQuake's CSV, site `site`, or a plain
/// `iml,annual_rate` file in the fit's unit); see the [module docs](self).
///
/// Errors: a fit against PGA/(g tan θc) (OpenQuake has no such IMT: fit
/// against PGA); no fitted curve; a `fragility.xml` that is not the one the
/// fit in `fragility.csv` writes (refit); a hazard curve for another IM;
/// unreadable files.
pub fn export_openquake(
    dir: &Path,
    hazard: &Path,
    site: Option<usize>,
    out: &Path,
) -> Result<OpenQuakeJob> {
    let rows = {
        if !dir.join("fragility.csv").exists() {
            // An unfinished run or another folder: say so, not "No such file".
            crate::study::require_finished(dir)?;
        }
        crate::fragility::check_set(dir)?;
        read_fragility_csv(&dir.join("fragility.csv"))?
    };
    let im = rows.first().map_or(Im::PGA, |r| r.im);
    let Some(oq) = im.openquake() else {
        return Err(Error::invalid(
            "fragility.im",
            im,
            "an IM OpenQuake's hazard has: pga, pgv or sa(T) of the ground (or their RotD50) \
             (refit with --im pga or --im \"sa(1.0)\"; a floor's curve against the ground's \
             PGA is what OpenQuake integrates)",
        ));
    };
    let factor = oq.factor;
    let fitted: Vec<&FragilityRow> = rows.iter().filter(|r| r.fit().is_some()).collect();
    if fitted.is_empty() {
        return Err(Error::Parse {
            path: dir.join("fragility.csv"),
            line: 0,
            message: "no fitted curve to export".to_string(),
        });
    }
    let xml_path = dir.join("fragility.xml");
    let xml = std::fs::read_to_string(&xml_path).map_err(Error::io(&xml_path))?;
    let ids = function_ids(&xml);
    check_model(&xml, &xml_path, &rows, factor)?;
    let mut omitted: Vec<String> = Vec::new();
    let mut seen: Vec<String> = Vec::new();
    for r in &rows {
        let id = r.case.id();
        if !ids.contains(&id) && !seen.contains(&id) {
            // Why: out of order, else the case's first status other than `ok`.
            let mine = || rows.iter().filter(|o| o.case == r.case);
            let status = mine()
                .find(|o| o.caveat() == Some(Caveat::OutOfOrder))
                .or_else(|| mine().find(|o| o.status != FitStatus::Ok))
                .map_or(r.status, |o| o.status);
            omitted.push(format!("{id} ({status})"));
            seen.push(id);
        }
    }
    if ids.is_empty() {
        return Err(Error::Conflict {
            path: xml_path.clone(),
            message: format!(
                "has no fragility function to export: every case is left out ({}; the XML \
                 comments say why)",
                omitted.join(", ")
            ),
        });
    }

    let curve = read_hazard(hazard, site)?.in_unit_of(im)?;
    let curves: Vec<(f64, f64)> = fitted.iter().filter_map(|r| r.fit()).collect();
    let (lo, hi) = curves
        .iter()
        .fold((f64::INFINITY, 0.0_f64), |(a, b), &(m, s)| {
            (
                a.min(m * dm::exp(-IML_SIGMAS * s)),
                b.max(m * dm::exp(IML_SIGMAS * s)),
            )
        });
    let top = top_level(&curve, hi);
    let slope = curves
        .iter()
        .map(|&(m, b)| effective_slope(&curve, m, b, lo, top))
        .fold(0.0_f64, f64::max);
    let per_decade = (DENSITY_MARGIN * LEVELS_PER_DECADE_PER_SLOPE * slope)
        .max(MIN_LEVELS_PER_DECADE)
        .ceil();
    let n = (dm::log10(top / lo) * per_decade).ceil().max(1.0) as usize;
    let levels: Vec<f64> = (0..=n)
        .map(|i| lo * dm::powf(top / lo, i as f64 / n as f64))
        .collect();
    let t = investigation_time(&curve, &curves, &levels);

    crate::io_util::create_folder(out)?;
    let (lon, lat, depth) = match curve.source {
        HazardSource::OpenQuake { lon, lat, .. } => (lon, lat, 0.0),
        HazardSource::Plain => (0.0, 0.0, 0.0),
    };
    let imt = oq.imt;
    let source_name = hazard.file_name().map_or_else(
        || hazard.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );

    // hazard.csv: one site, OpenQuake's layout.
    let mut csv = format!(
        "# generated_by='rockfrag {} export openquake: {source_name}{} resampled log-log, {} \
         levels per decade', kind='mean', investigation_time={t:?}, imt='{imt}'\n",
        env!("CARGO_PKG_VERSION"),
        site.map_or(String::new(), |s| format!(" site {s}")),
        per_decade
    );
    csv.push_str("lon,lat,depth");
    for &x in &levels {
        let _ = write!(csv, ",poe-{}", number(x * factor));
    }
    let _ = write!(csv, "\n{lon:.5},{lat:.5},{depth:.5}");
    for &x in &levels {
        // poe = 1 − exp(−λT), OpenQuake's Poisson reading of a rate.
        let _ = write!(csv, ",{:.6E}", -dm::exp_m1(-curve.rate_at(x) * t));
    }
    csv.push('\n');
    write_text(&out.join("hazard.csv"), &csv)?;

    // exposure.xml: one block per function, at the site.
    let mut exposure = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <nrml xmlns=\"http://openquake.org/xmlns/nrml/0.5\">\n\
         <exposureModel id=\"rockfrag\" category=\"buildings\" taxonomySource=\"rockfrag case ids\">\n\
         \x20 <description>One free-standing block per rockfrag case (number 1: the outputs are \
         probabilities)</description>\n\
         \x20 <conversions>\n    <costTypes/>\n  </conversions>\n  <assets>\n",
    );
    for (i, id) in ids.iter().enumerate() {
        let _ = writeln!(
            exposure,
            "    <asset id=\"a{}\" number=\"1\" taxonomy=\"{id}\">\n      \
             <location lon=\"{lon:.5}\" lat=\"{lat:.5}\"/>\n      <costs/>\n    </asset>",
            i + 1
        );
    }
    exposure.push_str("  </assets>\n</exposureModel>\n</nrml>\n");
    write_text(&out.join("exposure.xml"), &exposure)?;
    write_text(&out.join("fragility.xml"), &xml)?;

    let job = format!(
        "[general]\n\
         description = rockfrag {}: classical_damage over {source_name}{}\n\
         calculation_mode = classical_damage\n\n\
         [exposure]\nexposure_file = exposure.xml\n\n\
         [hazard]\n\
         # one site; OpenQuake takes the investigation time of the poes from its header\n\
         hazard_curves_csv = hazard.csv\n\n\
         [fragility]\ncontents_fragility_file = fragility.xml\n\n\
         [calculation]\ninvestigation_time = {t:?}\nrisk_investigation_time = 1.0\n",
        dir.display(),
        site.map_or(String::new(), |s| format!(", site {s}"))
    );
    write_text(&out.join("job.ini"), &job)?;

    // rockfrag's rates over the file's own curve, to compare with.
    let mut expected = Vec::new();
    let mut text = String::from("case_id,limit_state,annual_rate\n");
    for r in &fitted {
        let id = r.case.id();
        if !ids.contains(&id) {
            continue;
        }
        let (m, b) = r.fit().expect("fitted");
        let rate = risk_integral(&curve, m, b).rate;
        let _ = writeln!(text, "{id},{},{}", r.limit_state, number(rate));
        expected.push((id, r.limit_state.clone(), rate));
    }
    write_text(&out.join("expected.csv"), &text)?;
    let job = OpenQuakeJob {
        dir: out.to_path_buf(),
        functions: ids.len(),
        omitted,
        levels: levels.len(),
        levels_per_decade: per_decade,
        slope,
        investigation_time: t,
        expected,
    };
    write_text(&out.join("README.md"), &readme(&job, &source_name, &imt))?;
    Ok(job)
}

/// The ids of the `fragilityFunction`s of an NRML text, in order.
fn function_ids(xml: &str) -> Vec<String> {
    let tag = "<fragilityFunction id=\"";
    xml.match_indices(tag)
        .filter_map(|(i, _)| {
            let rest = &xml[i + tag.len()..];
            rest.find('"').map(|j| rest[..j].to_string())
        })
        .collect()
}

/// Checks that `xml` is the model the fit of `rows` writes today: its
/// continuous functions' `minIML` is the model's θ·e^(−6β).
fn check_model(xml: &str, path: &Path, rows: &[FragilityRow], factor: f64) -> Result<()> {
    let lo = rows
        .iter()
        .filter_map(FragilityRow::fit)
        .map(|(m, b)| m * factor * dm::exp(-IML_SIGMAS * b))
        .fold(f64::INFINITY, f64::min);
    let attr = "minIML=\"";
    let written = xml.find(attr).map(|i| {
        let rest = &xml[i + attr.len()..];
        rest[..rest.find('"').unwrap_or(0)]
            .parse::<f64>()
            .unwrap_or(f64::NAN)
    });
    match written {
        // Only discrete functions: nothing to compare.
        None if !xml.contains("format=\"continuous\"") => Ok(()),
        Some(x) if (x / lo - 1.0).abs() < 1e-9 => Ok(()),
        _ => Err(Error::Conflict {
            path: path.to_path_buf(),
            message: format!(
                "is not the model of this folder's fragility.csv (minIML should be {} for \
                 OpenQuake to compute its curves, see rockfrag's fragility docs): rerun \
                 `rockfrag fragility` on the folder",
                number(lo)
            ),
        }),
    }
}

/// The level above `hi` where λ has fallen to [`TOP_RATE_FRACTION`] of
/// λ(hi) (at most 40 e-folds of IM past the curve's last level).
fn top_level(curve: &HazardCurve, hi: f64) -> f64 {
    let target = TOP_RATE_FRACTION * curve.rate_at(hi);
    let cap = curve.iml[curve.iml.len() - 1] * dm::exp(40.0);
    let mut x = hi;
    while curve.rate_at(x) > target && x < cap {
        x *= 1.05;
    }
    x.min(cap).max(hi)
}

/// The hazard's log-slope k = −d ln λ/d ln IM, root-mean-square averaged
/// over [lo, top] with the weight of the integrand P(LS | IM)·(−dλ/d ln IM)
/// of the curve (θ, β).
fn effective_slope(curve: &HazardCurve, theta: f64, beta: f64, lo: f64, top: f64) -> f64 {
    let n = 4000;
    let (a, b) = (dm::ln(lo), dm::ln(top));
    let h = (b - a) / n as f64;
    let (mut sw, mut swk2) = (0.0_f64, 0.0_f64);
    for i in 0..n {
        let (u0, u1) = (a + i as f64 * h, a + (i + 1) as f64 * h);
        let (l0, l1) = (curve.rate_at(dm::exp(u0)), curve.rate_at(dm::exp(u1)));
        // the slope of the piece, and the rate it sheds
        let k = -(dm::ln(l1) - dm::ln(l0)) / h;
        let shed = (l0 - l1).max(0.0);
        let p = dm::norm_cdf((0.5 * (u0 + u1) - dm::ln(theta)) / beta);
        sw += p * shed;
        swk2 += p * shed * k * k;
    }
    if sw > 0.0 { (swk2 / sw).sqrt() } else { 0.0 }
}

/// The investigation time of `hazard.csv` (see the [module docs](self)).
fn investigation_time(curve: &HazardCurve, curves: &[(f64, f64)], levels: &[f64]) -> f64 {
    let smallest = curves
        .iter()
        .map(|&(m, _)| curve.rate_at(m))
        .fold(f64::INFINITY, f64::min);
    let mut j = dm::log10(1e-3 / smallest).ceil().max(0.0) as i32;
    let too_big = |t: f64| {
        levels.iter().any(|&x| {
            curves
                .iter()
                .any(|&(m, b)| dm::norm_cdf(dm::ln(x / m) / b) > 1e-6)
                && curve.rate_at(x) * t > 15.0
        })
    };
    while j > 0 && too_big(dm::powi(10.0, j)) {
        j -= 1;
    }
    dm::powi(10.0, j)
}

fn write_text(path: &Path, text: &str) -> Result<()> {
    write_atomic(path, |w| w.write_all(text.as_bytes())).map_err(Error::io(path))
}

/// The job folder's README: how to run it and read it back.
fn readme(job: &OpenQuakeJob, source: &str, imt: &str) -> String {
    let mut s = format!(
        "# OpenQuake `classical_damage` job written by `rockfrag export openquake`\n\n\
         Run it with the OpenQuake engine (3.26):\n\n\
         ```sh\n\
         oq engine --run job.ini -e csv -p export_dir=out\n\
         ```\n\n\
         `out/damages-rlz-000_<calc>.csv` then has one row per asset (one per rockfrag case, \
         its `taxonomy` the case id) and a column `contents-<state>` per damage state: the \
         probability of being *in* that state over `risk_investigation_time` T_r = 1 year. \
         The probability of reaching limit state k is the sum of the states at or above it, \
         p_k = Σ_(j≥k) contents-<state j> (not 1 − no_damage: the file's 32-bit floats lose \
         small probabilities), and its annual rate λ_k = −ln(1 − p_k)/T_r, the inverse of \
         OpenQuake's 1 − exp(−λ·T_r). `expected.csv` holds rockfrag's rates (`rockfrag risk` \
         over {source}) to compare with: they agree within about 1 %.\n\n\
         ## What is in the folder\n\n\
         - `fragility.xml`: the study's model; its `minIML`/`maxIML` are where every curve is 0 \
         and 1, because OpenQuake holds a curve at P(minIML) below minIML and at P(maxIML) \
         above maxIML.\n\
         - `exposure.xml`: one asset (`number` 1) per fragility function, at the hazard site.\n\
         - `hazard.csv`: the same hazard curve as {source} (rockfrag's log–log interpolation \
         of it, its end segments' power laws beyond its levels), resampled on {} log-uniform \
         {imt} levels, {} per decade, with investigation time {} years. OpenQuake's own \
         quadrature gives each level the rate (λ_(i−1) − λ_(i+1))/2 and the fragility at the \
         level: on the file's own levels it is several percent high (second order in the \
         spacing, (k·h)²/8 for a hazard of log-slope k and level spacing h in ln IM). The \
         levels here are dense for the hazard's slope where the rates come from (k_eff = {}), \
         so that the bias stays below 1 %. Only the levels differ; the curve is the same.\n\
         - `job.ini`: `contents_fragility_file` (rockfrag's model has `lossCategory` \
         contents), `investigation_time` (OpenQuake takes the CSV header's), \
         `risk_investigation_time = 1`.\n",
        job.levels,
        job.levels_per_decade,
        job.investigation_time,
        sig3(job.slope)
    );
    if !job.omitted.is_empty() {
        let _ = write!(
            s,
            "\nCases of `fragility.csv` not in the model (no limit state fitted): {}.\n",
            job.omitted.join(", ")
        );
    }
    s
}
