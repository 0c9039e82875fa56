//! Several intensity measures compared on one study (`rockfrag fragility
//! DIR --im A --im B …`): every case and limit state fitted against each,
//! ranked by β (efficiency: the smaller β, the fewer records a median of
//! given precision needs, and the less the hazard's spread widens the
//! risk), with a sufficiency check: the slope of the fit's residuals
//! against a record feature that carries no magnitude, ln(PGV/PGA) of the
//! ground record each analysis felt (the motion's period content, what
//! rocking depends on beyond its amplitude). An IM whose residuals trend
//! with it leaves that content out of the curve.

use std::path::Path;

use super::measure::measure_records;
use crate::detmath as dm;
use crate::error::Result;
use crate::fragility::{FitStatus, FragilityOptions, FragilityRow, fit_cases, read_outcomes_for};
use crate::im::Im;
use crate::io_util::sig3;

/// The heading of the section [`compare_ims`] writes.
pub const IMS_HEADING: &str = "## Intensity measures";

/// One IM's fit of one case and limit state, as [`compare_ims`] ranks it.
#[derive(Clone, Debug, PartialEq)]
pub struct ImFit {
    /// The case, as `fragility.csv`'s `case_id`.
    pub case_id: String,
    /// The case in words.
    pub case: String,
    /// The limit state.
    pub limit_state: String,
    /// The IM.
    pub im: Im,
    /// Median θ and β, `None` when not fitted.
    pub fit: Option<(f64, f64)>,
    /// β's bootstrap band.
    pub beta_band: Option<(f64, f64)>,
    /// Slope of the Pearson residuals against ln(PGV/PGA) and its standard
    /// error (ordinary least squares over the analyses).
    pub slope: Option<(f64, f64)>,
    /// `fragility.csv`'s status.
    pub status: FitStatus,
}

/// Fits the study folder `dir` against each of `ims` (with `options`
/// otherwise) and returns every fit, case by case and limit state by
/// limit state in the fit's order, IMs ranked by β (unfitted last).
pub fn compare_ims(dir: &Path, options: &FragilityOptions, ims: &[Im]) -> Result<Vec<ImFit>> {
    let path = dir.join("outcomes.csv");
    let feature = measure_records(dir, Im::PGV_OVER_PGA)?;
    let mut all: Vec<Vec<ImFit>> = Vec::new();
    for &im in ims {
        let measured = if im.stored() || !im.of_record() {
            Vec::new()
        } else {
            vec![std::sync::Arc::new(measure_records(dir, im)?)]
        };
        let opts = FragilityOptions {
            im: Some(im),
            surface: None,
            measured,
            ..options.clone()
        };
        let outcomes = read_outcomes_for(&path, &opts)?;
        let fits = fit_cases(&outcomes, &opts)?;
        let mut rows = Vec::with_capacity(fits.len());
        for f in &fits {
            let row = FragilityRow::from_fit(f);
            let k = outcomes
                .limit_states
                .iter()
                .position(|l| l.name == f.limit_state)
                .expect("a fit's limit state is the outcomes'");
            let case = outcomes
                .cases
                .iter()
                .find(|c| c.key == f.key)
                .expect("a fit's case is the outcomes'");
            let slope = row.fit().and_then(|(theta, beta)| {
                // Pearson residual of each analysis, against its record's ln(PGV/PGA)
                let points: Vec<(f64, f64)> = case
                    .trials
                    .iter()
                    .filter_map(|t| {
                        let record: usize = case.records[t.record].parse().ok()?;
                        let x = dm::ln(feature.get(t.level, record)?);
                        let p = dm::norm_cdf(dm::ln(t.im / theta) / beta).clamp(1e-9, 1.0 - 1e-9);
                        let y = f64::from(u8::from(t.exceeded >> k & 1 == 1));
                        Some((x, (y - p) / (p * (1.0 - p)).sqrt()))
                    })
                    .collect();
                ols_slope(&points)
            });
            rows.push(ImFit {
                case_id: f.key.id(),
                case: f.key.to_string(),
                limit_state: f.limit_state.clone(),
                im,
                fit: row.fit(),
                beta_band: row.beta_band,
                slope,
                status: row.status,
            });
        }
        all.push(rows);
    }
    // regroup: for each case and limit state, its fit against every IM
    let n = all.first().map_or(0, Vec::len);
    let mut out = Vec::with_capacity(n * ims.len());
    for i in 0..n {
        let mut group: Vec<ImFit> = all.iter().map(|rows| rows[i].clone()).collect();
        group.sort_by(|a, b| {
            let beta = |f: &ImFit| f.fit.map_or(f64::INFINITY, |x| x.1);
            beta(a).total_cmp(&beta(b))
        });
        out.extend(group);
    }
    Ok(out)
}

/// The least-squares slope of y on x and its standard error; `None` with
/// fewer than 3 points or no spread in x.
fn ols_slope(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = points.len() as f64;
    if points.len() < 3 {
        return None;
    }
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let sxx: f64 = points.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = points.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    // b = Sxy/Sxx, SE(b) = √(s²/Sxx), s² = Σ(y − ȳ − b(x − x̄))²/(n − 2)
    let b = sxy / sxx;
    let rss: f64 = points
        .iter()
        .map(|(x, y)| {
            let e = y - my - b * (x - mx);
            e * e
        })
        .sum();
    Some((b, (rss / (n - 2.0) / sxx).sqrt()))
}

/// The `## Intensity measures` section of `summary.md` for `fits` (from
/// [`compare_ims`]).
pub fn ims_section(fits: &[ImFit]) -> String {
    let mut s = format!(
        "{IMS_HEADING}\n\nEvery case and limit state fitted against each IM asked for \
         (`rockfrag fragility DIR --im A --im B …`; `fragility.csv` holds the first), ranked \
         by β: the smaller, the more efficient (fewer records for a median of given \
         precision, and a narrower risk for a given hazard). Sufficiency: the slope of the \
         fit's Pearson residuals against ln(PGV/PGA) of the ground record each analysis felt \
         (a feature of the motion's period content that carries no magnitude), ± its \
         standard error; a slope beyond 2 standard errors means the curve depends on the \
         record's period content as well as on the IM. Medians in each IM's unit.\n\n\
         | case | limit state | rank | IM | median θ | β [90 %] | residual slope vs ln(PGV/PGA) | note |\n\
         |---|---|---|---|---|---|---|---|\n"
    );
    let mut rank = 0;
    let mut last = None;
    for f in fits {
        let key = (&f.case_id, &f.limit_state);
        if last != Some(key) {
            rank = 0;
            last = Some(key);
        }
        rank += 1;
        let (median, beta) = match f.fit {
            Some((m, b)) => {
                let band = f.beta_band.map_or(String::new(), |(lo, hi)| {
                    format!(" [{}, {}]", sig3(lo), sig3(hi))
                });
                let unit = match f.im.unit() {
                    "1" => String::new(),
                    u => format!(" {u}"),
                };
                (format!("{}{unit}", sig3(m)), format!("{}{band}", sig3(b)))
            }
            None => ("—".into(), "—".into()),
        };
        let (slope, note) = match (f.fit, f.slope) {
            (None, _) => (String::new(), format!("not fitted ({})", f.status)),
            (Some(_), None) => (String::new(), "too few analyses for the slope".into()),
            (Some(_), Some((b, se))) => (
                format!("{} ± {}", sig3(b), sig3(se)),
                if b.abs() > 2.0 * se {
                    "residuals trend with PGV/PGA: not sufficient".into()
                } else {
                    "no trend with PGV/PGA".into()
                },
            ),
        };
        let rank_text = if f.fit.is_some() {
            rank.to_string()
        } else {
            "—".into()
        };
        s.push_str(&format!(
            "| {} | {} | {rank_text} | {} | {median} | {beta} | {slope} | {note} |\n",
            f.case,
            f.limit_state,
            f.im.short()
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight line: its slope, with no error; four points: the slope
    /// and standard error √(s²/Sxx) worked by hand; no spread in x: none.
    #[test]
    fn least_squares_slope_and_error() {
        let line: Vec<(f64, f64)> = (0..10).map(|i| (i as f64, 2.0 * i as f64 - 1.0)).collect();
        let (b, se) = ols_slope(&line).unwrap();
        assert!((b - 2.0).abs() < 1e-12 && se < 1e-12, "{b} {se}");
        let pts = [(0.0, 1.0), (1.0, 1.0), (2.0, 5.0), (3.0, 5.0)];
        // x̄ = 1.5, ȳ = 3, Sxx = 5, Sxy = 8 → b = 1.6; residuals 0.4,
        // −1.2, 1.2, −0.4: RSS = 3.2, s² = 1.6, SE = √(1.6/5)
        let (b, se) = ols_slope(&pts).unwrap();
        assert!((b - 1.6).abs() < 1e-12 && (se - (0.32f64).sqrt()).abs() < 1e-12);
        assert_eq!(ols_slope(&[(1.0, 1.0), (1.0, 2.0), (1.0, 3.0)]), None);
    }
}
