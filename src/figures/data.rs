//! The study results the figures read: `outcomes.csv` (one row per analysis)
//! and, optionally, `fragility_curves.csv` (fitted curves with their band)
//! and `fragility.csv` (each fit's θ and β, so that a figure can draw a
//! fitted curve beyond the intensities `fragility_curves.csv` samples).
//!
//! They are read through their stage files' row types
//! ([`OutcomesFile`], [`read_curves_csv`], [`read_fragility_csv`]) and kept
//! in the compact form
//! the figures plot; failed analyses are skipped, having no outcome. Rows
//! are sorted once after reading, so every figure sees the same order
//! whatever order the study (or a merge of its shards) wrote them in, and
//! the figures are byte-identical.

use std::path::Path;

use crate::case::{Case, Field, Param, cmp_friction};
use crate::error::{Error, Result};
use crate::fragility::{FragilityOptions, read_curves_csv, read_fragility_csv, read_outcomes_for};
use crate::im::Im;
use crate::outcomes_csv::{Column, OutcomesFile};
use crate::solver::Friction;
use crate::spec::Study;
use crate::uncertainty::{Distribution, Property, Value};

/// One analysis as the figures plot it: the case, the intensity and the
/// outcome quantities that are drawn (taken from an
/// [`OutcomeRow`](crate::outcomes_csv::OutcomeRow)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlotRow {
    /// The block and its contact (drawn parameters as drawn, or pooled).
    pub case: Case,
    /// Peak ground acceleration of the stripe (g): the record's, or a
    /// record pair's RotD50 (studies of pairs: the level, whatever
    /// direction the block faces).
    pub pga: f64,
    /// Record index in the ensemble.
    pub record: u64,
    /// |θ| reached π/2.
    pub overturned: bool,
    /// N reached 0 during rock at least once (the paper stopped such runs).
    pub uplifted: bool,
    /// Peak |θ|/θc.
    pub theta_max_over_theta_c: f64,
    /// Peak |F|/N while rocking, μ_mot (0 if the block never rocked).
    pub mu_motion: f64,
    /// Peak |P_t/P_n| over impacts, μ_imp (meaningless if `impacts` is 0).
    pub mu_impact: f64,
    /// Peak of the paper's eq. (5) over impacts; `None` for a file written
    /// before the column existed.
    pub mu_impact_eq5: Option<f64>,
    /// Number of corner impacts.
    pub impacts: u64,
}

/// One point of a fitted fragility curve.
#[derive(Clone, Debug, PartialEq)]
pub struct CurvePoint {
    /// The case.
    pub case: Case,
    /// The limit state (`overturning` for a file without a `limit_state`
    /// column, which predates limit states).
    pub limit_state: String,
    /// Intensity measure, PGA (g).
    pub im: f64,
    /// Fitted probability of overturning.
    pub p: f64,
    /// Lower bound of the 90 % band.
    pub p_lo: f64,
    /// Upper bound of the 90 % band.
    pub p_hi: f64,
}

/// A fitted lognormal fragility curve, P(im) = Φ(ln(im/θ)/β), from
/// `fragility.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct LognormalCurve {
    /// The case.
    pub case: Case,
    /// The limit state.
    pub limit_state: String,
    /// Median θ (g).
    pub median: f64,
    /// Logarithmic standard deviation β.
    pub beta: f64,
    /// The bootstrap band of θ, when the fit has one.
    pub median_band: Option<(f64, f64)>,
    /// Analyses that exceeded the limit state.
    pub n_exceeded: usize,
}

/// The observed fraction of a case's analyses at one stripe that exceeded
/// one limit state (as the fit counts them: [`read_outcomes_for`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ObservedStripe {
    /// The case (drawn parameters pooled).
    pub case: Case,
    /// The limit state.
    pub limit_state: String,
    /// The stripe's PGA (g), as [`PlotRow::pga`].
    pub im: f64,
    /// Analyses that exceeded the limit state.
    pub exceeded: usize,
    /// Analyses at the stripe.
    pub trials: usize,
}

/// Relative difference below which two intensities are one stripe: the
/// measured IMs of records scaled to one level differ in their last bits.
pub const STRIPE_TOL: f64 = 1e-9;

/// Whether `a` and `b` are the same stripe ([`STRIPE_TOL`]).
pub fn same_stripe(a: f64, b: f64) -> bool {
    (a - b).abs() <= STRIPE_TOL * a.abs().max(b.abs())
}

/// The stripes of `values`: sorted, those within [`STRIPE_TOL`] of the
/// previous one merged into it (each stripe is its smallest value).
pub fn stripes(values: impl IntoIterator<Item = f64>) -> Vec<f64> {
    let mut v = distinct_numbers(values);
    v.dedup_by(|b, a| same_stripe(*a, *b));
    v
}

/// A friction model for legends: `μ = ∞` or `μₛ = 0.7, μₖ = 0.6` (`μₛ, μₖ
/// drawn` when drawn per analysis).
pub fn friction_label(f: &Param<Friction>) -> String {
    match *f {
        Param::Fixed(Friction::Infinite) => "μ = ∞".to_string(),
        Param::Drawn => "μₛ, μₖ drawn".to_string(),
        Param::Fixed(Friction::Coulomb { mu_s, mu_k }) => format!(
            "μₛ = {}, μₖ = {}",
            super::style::tick_label(mu_s),
            super::style::tick_label(mu_k)
        ),
    }
}

/// A distribution in a legend: `U(0.2, 0.6)`, `N(0.5, 0.02)`,
/// `LN(0.5, 0.15)` (median, β), with ` on [a, b]` when truncated.
pub fn distribution_label(d: &Distribution) -> String {
    let t = super::style::tick_label;
    let bounds = |min: Option<f64>, max: Option<f64>| match (min, max) {
        (None, None) => String::new(),
        (a, b) => format!(
            " on [{}, {}]",
            a.map_or("−∞".to_string(), t),
            b.map_or("∞".to_string(), t)
        ),
    };
    match *d {
        Distribution::Uniform { min, max } => format!("U({}, {})", t(min), t(max)),
        Distribution::Normal { mean, sd, min, max } => {
            format!("N({}, {}){}", t(mean), t(sd), bounds(min, max))
        }
        Distribution::Lognormal {
            median,
            beta,
            min,
            max,
        } => format!("LN({}, {}){}", t(median), t(beta), bounds(min, max)),
    }
}

/// What a study draws for `field`, for a legend: `e ~ U(0.2, 0.6)`,
/// `2B ~ N(0.5, 0.02) m`, `μₛ ~ LN(0.5, 0.15), μₖ/μₛ ~ U(0.75, 0.95)`;
/// `None` when `study` is unknown or does not draw the field.
pub fn drawn_label(study: Option<&Study>, field: Field) -> Option<String> {
    let u = study?.uncertainty.as_ref()?;
    let value = |v: &Value| match v {
        Value::Fixed(x) => format!("= {}", super::style::tick_label(*x)),
        Value::Drawn(d) => format!("~ {}", distribution_label(d)),
    };
    let one = |name: &str, p: Property, unit: &str| {
        u.get(p)
            .filter(|v| v.is_drawn())
            .map(|v| format!("{name} {}{unit}", value(v)))
    };
    match field {
        Field::Aspect => one("H/B", Property::Aspect, ""),
        Field::Width => one("2B", Property::Width, " m"),
        Field::Restitution => one("e", Property::Restitution, ""),
        Field::Friction => {
            let parts: Vec<String> = [(Property::MuS, "μₛ"), (Property::MuKOverMuS, "μₖ/μₛ")]
                .iter()
                .filter_map(|&(p, name)| u.get(p).map(|v| format!("{name} {}", value(v))))
                .collect();
            (u.is_drawn(Property::MuS) || u.is_drawn(Property::MuKOverMuS))
                .then(|| parts.join(", "))
        }
    }
}

/// A case parameter for titles and legends: its tick label, or `drawn`.
pub fn param_label(p: Param<f64>) -> String {
    match p {
        Param::Fixed(x) => super::style::tick_label(x),
        Param::Drawn => "drawn".to_string(),
    }
}

/// What the figures read from a study folder.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StudyData {
    /// Successful analyses, sorted by case, PGA and record.
    pub outcomes: Vec<PlotRow>,
    /// Fitted fragility curves, sorted by case and IM; `None` when the folder
    /// has no `fragility_curves.csv`.
    pub curves: Option<Vec<CurvePoint>>,
    /// The fitted curves' θ and β (against PGA), from `fragility.csv`;
    /// empty when the folder has none.
    pub lognormal: Vec<LognormalCurve>,
    /// The PGA of the stripes ([`PlotRow::pga`]): the record's, or a
    /// record pair's RotD50 ([`read_outcomes`]).
    pub im: Im,
    /// The IM the folder's fit is against (`fragility.csv`; `curves` and
    /// `lognormal` are its curves), `None` without a fit.
    pub fit_im: Option<Im>,
    /// The study, when known (from the folder's manifest): its limit
    /// states' definitions and the distributions of what it draws.
    pub study: Option<Study>,
    /// The observed fractions of every limit state of the study's
    /// `[fragility]` at every stripe of every case (empty without a study
    /// or when `outcomes.csv` cannot be read for them).
    pub observed: Vec<ObservedStripe>,
}

impl StudyData {
    /// The label of the PGA axis: `PGA (g)`, or `RotD50 PGA (g)` for a
    /// study of record pairs.
    pub fn pga_label(&self) -> String {
        self.im.axis_label()
    }

    /// The IM of the fitted curves ([`StudyData::fit_im`]), else of the
    /// stripes.
    pub fn curve_im(&self) -> Im {
        self.fit_im.unwrap_or(self.im)
    }

    /// Whether the fitted curves are against the stripes' PGA (what the
    /// figures drawn over stripes, the history's and the comparison's,
    /// need).
    pub fn fit_on_stripes(&self) -> bool {
        self.curve_im() == self.im
    }
}

impl StudyData {
    /// Reads `dir/outcomes.csv` and, if present, `dir/fragility_curves.csv`.
    pub fn load(dir: &Path) -> Result<StudyData> {
        StudyData::load_pooled(dir, &[])
    }

    /// As [`StudyData::load`], with each analysis in the case that pools
    /// the fields `pooled` (those the study draws per analysis).
    pub fn load_pooled(dir: &Path, pooled: &[Field]) -> Result<StudyData> {
        let (outcomes, im) = read_pooled(&dir.join("outcomes.csv"), pooled)?;
        let mut data = StudyData::fits(dir, im)?;
        data.outcomes = outcomes;
        Ok(data)
    }

    /// The folder's fit (`fragility.csv`, `fragility_curves.csv`, checked
    /// as one set) for stripes at `im`, without rows.
    fn fits(dir: &Path, im: Im) -> Result<StudyData> {
        crate::fragility::check_set(dir)?;
        let curves_path = dir.join("fragility_curves.csv");
        let fits_path = dir.join("fragility.csv");
        // one fit writes one IM: its first row's
        let fit_im = if fits_path.exists() {
            read_fragility_csv(&fits_path)?.first().map(|r| r.im)
        } else if curves_path.exists() {
            read_curves_csv(&curves_path)?.first().map(|r| r.im)
        } else {
            None
        };
        let curve_im = fit_im.unwrap_or(im);
        let curves = if curves_path.exists() {
            Some(read_fragility_curves(&curves_path, curve_im)?)
        } else {
            None
        };
        let lognormal = if fits_path.exists() {
            read_lognormal(&fits_path, curve_im)?
        } else {
            Vec::new()
        };
        Ok(StudyData {
            outcomes: Vec::new(),
            curves,
            lognormal,
            im,
            fit_im,
            study: None,
            observed: Vec::new(),
        })
    }

    /// As [`StudyData::load_pooled`] for `study` (the folder's, when known,
    /// pooling what it draws), with the observed fraction of each of its
    /// limit states at each stripe ([`StudyData::observed`]). A limit state
    /// whose count differs from the fit's (`fragility.csv` refitted with
    /// other definitions) gets none.
    ///
    /// The fractions are counted from the file's trials before its rows are
    /// read: held together, the two would double the memory the figures
    /// take (25 MB at 100,000 analyses, against 15 MB for the rows alone).
    pub fn load_study(dir: &Path, study: Option<&Study>, pooled: &[Field]) -> Result<StudyData> {
        let path = dir.join("outcomes.csv");
        let mut data = StudyData::fits(dir, stripes_im(&path)?)?;
        data.study = study.cloned();
        data.observed = data.observed(dir, study, pooled);
        let (outcomes, _) = read_pooled(&path, pooled)?;
        data.outcomes = outcomes;
        Ok(data)
    }

    /// The observed fractions of [`StudyData::load_study`], for the fit
    /// and IM already in `self`.
    fn observed(&self, dir: &Path, study: Option<&Study>, pooled: &[Field]) -> Vec<ObservedStripe> {
        let mut observed = Vec::new();
        // Without a study, only a fit against another IM than the stripes'
        // needs the fractions counted here (overturning's); else the
        // figure counts them from the rows.
        if study.is_none() && self.fit_on_stripes() {
            return observed;
        }
        let im = self.curve_im();
        let measured = match study {
            Some(s) if !im.stored() && im.of_record() => {
                crate::study::measure_study_records(s, dir, im)
                    .ok()
                    .map(std::sync::Arc::new)
            }
            _ => None,
        };
        let measured: Vec<_> = measured.into_iter().collect();
        let options = FragilityOptions {
            im: Some(im),
            measured,
            limit_state: study
                .and_then(|s| s.fragility.as_ref())
                .map_or_else(Vec::new, |f| f.limit_state.clone()),
            pool: pooled.to_vec(),
            ..FragilityOptions::default()
        };
        // A spec whose limit states the file cannot count draws without them.
        let Ok(outcomes) = read_outcomes_for(&dir.join("outcomes.csv"), &options) else {
            return observed;
        };
        let on_stripes = self.fit_on_stripes();
        for case in &outcomes.cases {
            // each trial's stripe: by its IM when the fit is against the
            // stripes' own; else by its level, drawn at the stripe's IM
            // (the level's, or the geometric mean of the analyses' own)
            let key = |t: &crate::fragility::Trial| if on_stripes { t.im } else { t.level };
            let levels = stripes(case.trials.iter().map(key));
            let mut at_im: Vec<(f64, f64, usize)> = vec![(0.0, 0.0, 0); levels.len()];
            let stripe_of = |x: f64| {
                levels
                    .partition_point(|&l| l < x && !same_stripe(l, x))
                    .min(levels.len() - 1)
            };
            for t in &case.trials {
                let a = &mut at_im[stripe_of(key(t))];
                a.0 = if a.2 == 0 || a.0 == t.im {
                    t.im
                } else {
                    f64::NAN
                };
                a.1 += crate::detmath::ln(t.im);
                a.2 += 1;
            }
            let positions: Vec<f64> = at_im
                .iter()
                .zip(&levels)
                .map(|(&(same, sum_ln, n), &level)| {
                    if on_stripes {
                        level
                    } else if same.is_nan() {
                        crate::detmath::exp(sum_ln / n as f64)
                    } else {
                        same
                    }
                })
                .collect();
            for (k, ls) in outcomes.limit_states.iter().enumerate() {
                let mut counts: Vec<(usize, usize)> = vec![(0, 0); levels.len()];
                for t in &case.trials {
                    let i = stripe_of(key(t));
                    counts[i].0 += usize::from(t.exceeds(k));
                    counts[i].1 += 1;
                }
                // the fit's count, if it has one, must be this one
                let total: usize = counts.iter().map(|c| c.0).sum();
                let fitted = self
                    .lognormal
                    .iter()
                    .find(|l| l.case == case.key && l.limit_state == ls.name);
                if fitted.is_some_and(|l| l.n_exceeded != total) {
                    continue;
                }
                observed.extend(
                    positions
                        .iter()
                        .zip(counts)
                        .map(|(&im, (exceeded, trials))| ObservedStripe {
                            case: case.key,
                            limit_state: ls.name.clone(),
                            im,
                            exceeded,
                            trials,
                        }),
                );
            }
        }
        observed
    }
}

/// Sorts the rows by case, PGA and record, stably: by sorting their
/// indices and then moving each row once along the permutation's cycles. (A
/// stable sort of the rows themselves takes scratch of 8 MB at 100,000 rows,
/// on top of the rows' own 14 MB.)
fn sort(rows: &mut [PlotRow]) {
    let cmp = |a: &PlotRow, b: &PlotRow| {
        a.case
            .total_cmp(&b.case)
            .then(a.pga.total_cmp(&b.pga))
            .then(a.record.cmp(&b.record))
    };
    let Ok(n) = u32::try_from(rows.len()) else {
        return rows.sort_by(cmp);
    };
    let mut order: Vec<u32> = (0..n).collect();
    order.sort_by(|&i, &j| cmp(&rows[i as usize], &rows[j as usize]));
    // row k takes old row order[k]: follow each cycle once, marking it done
    const DONE: u32 = u32::MAX;
    for i in 0..rows.len() {
        let mut k = i;
        while order[k] != DONE {
            let from = order[k] as usize;
            order[k] = DONE;
            if from == i {
                break;
            }
            rows.swap(k, from);
            k = from;
        }
    }
}

/// Reads `outcomes.csv` through [`OutcomesFile`]; skips failed rows;
/// returns the rows sorted by case, PGA and record, and the PGA the
/// stripes are at: a record pair's RotD50 when the file has `pga_rotd50`
/// (a study of pairs), else the record's PGA.
///
/// Errors: [`Error::Io`] if the file cannot be read,
/// [`Error::Parse`] naming the line for a missing
/// column, or the line, column and value for an unreadable value.
pub fn read_outcomes(path: &Path) -> Result<(Vec<PlotRow>, Im)> {
    let mut table = open_outcomes(path)?;
    // optional: files written before the column existed lack it
    let has_eq5 = table.has(Column::MuImpactEq5);
    let im = stripes_of(&table);
    let column = Column::Im(im);
    // sized once, by the file's lines: grown by doubling, 100,000 rows
    // would hold 19 MB and copy 9 MB into it on the last growth
    let mut rows = Vec::with_capacity(line_count(path)?.saturating_sub(1));
    while let Some((line, row)) = table.next_row()? {
        let Ok(o) = &row.result else { continue };
        let pga = row.intensity(column).ok_or_else(|| Error::Parse {
            path: path.to_path_buf(),
            line,
            message: format!("column `{column}` = \"\": expected a number"),
        })?;
        rows.push(PlotRow {
            case: row.case.into(),
            pga,
            record: row.record as u64,
            overturned: o.overturned,
            uplifted: o.uplifted,
            theta_max_over_theta_c: o.theta_max_over_theta_c,
            mu_motion: o.mu_motion,
            mu_impact: o.mu_impact,
            mu_impact_eq5: has_eq5.then_some(o.mu_impact_eq5),
            impacts: o.impacts,
        });
    }
    sort(&mut rows);
    Ok((rows, im))
}

/// `outcomes.csv` at `path` opened for [`read_outcomes`] (its header read
/// and checked).
fn open_outcomes(path: &Path) -> Result<OutcomesFile> {
    OutcomesFile::open(
        path,
        &[
            Column::Im(Im::PGA),
            Column::Record,
            Column::Overturned,
            Column::Uplifted,
            Column::ThetaMaxOverThetaC,
            Column::MuMotion,
            Column::MuImpact,
            Column::Impacts,
        ],
        "the figures",
    )
}

/// The PGA the stripes of an outcomes file are at: a record pair's RotD50
/// when it has `pga_rotd50`, else the record's PGA.
fn stripes_of(table: &OutcomesFile) -> Im {
    if table.has(Column::Im(Im::PGA_ROTD50)) {
        Im::PGA_ROTD50
    } else {
        Im::PGA
    }
}

/// [`stripes_of`] the outcomes file at `path`, from its header alone.
fn stripes_im(path: &Path) -> Result<Im> {
    open_outcomes(path).map(|table| stripes_of(&table))
}

/// [`read_outcomes`], each row in the case that pools the fields `pooled`
/// (sorted again when any are).
fn read_pooled(path: &Path, pooled: &[Field]) -> Result<(Vec<PlotRow>, Im)> {
    let (mut outcomes, im) = read_outcomes(path)?;
    if !pooled.is_empty() {
        for row in &mut outcomes {
            row.case = row.case.pooled(pooled);
        }
        sort(&mut outcomes);
    }
    Ok((outcomes, im))
}

/// The number of lines of the file at `path` (its newlines, and a last
/// line without one).
fn line_count(path: &Path) -> Result<usize> {
    use std::io::Read;
    let mut file = std::fs::File::open(path).map_err(Error::io(path))?;
    let mut buf = vec![0u8; 1 << 16];
    let (mut lines, mut last) = (0, b'\n');
    loop {
        let n = match file.read(&mut buf) {
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            read => read.map_err(Error::io(path))?,
        };
        if n == 0 {
            break;
        }
        lines += buf[..n].iter().filter(|&&b| b == b'\n').count();
        last = buf[n - 1];
    }
    Ok(lines + usize::from(last != b'\n'))
}

/// Reads `fragility_curves.csv` ([`read_curves_csv`]): the fitted
/// probability and its 90 % band on an IM grid. Only curves fitted against
/// `im` are kept, the PGA the figure draws the stripes at
/// ([`read_outcomes`]); an empty
/// band (no bootstrap) reads as the curve itself. Returns the points sorted
/// by case, limit state (in the file's order: a case's limit states in
/// order of severity) and IM.
pub fn read_fragility_curves(path: &Path, im: Im) -> Result<Vec<CurvePoint>> {
    let mut points: Vec<CurvePoint> = read_curves_csv(path)?
        .into_iter()
        .filter(|r| r.im == im)
        .map(|r| CurvePoint {
            case: r.case,
            limit_state: r.limit_state,
            im: r.im_value,
            p: r.p,
            p_lo: r.band.map_or(r.p, |b| b.0),
            p_hi: r.band.map_or(r.p, |b| b.1),
        })
        .collect();
    // Limit states keep the file's order (a case's, in order of severity).
    let mut order: Vec<String> = Vec::new();
    for p in &points {
        if !order.contains(&p.limit_state) {
            order.push(p.limit_state.clone());
        }
    }
    let rank = |ls: &str| order.iter().position(|o| o == ls);
    points.sort_by(|a, b| {
        a.case
            .total_cmp(&b.case)
            .then_with(|| rank(&a.limit_state).cmp(&rank(&b.limit_state)))
            .then(a.im.total_cmp(&b.im))
    });
    Ok(points)
}

/// Reads the fitted θ and β of `fragility.csv` ([`read_fragility_csv`]):
/// the cases and limit states fitted against `im` (see
/// [`read_fragility_curves`]), in the file's order.
pub fn read_lognormal(path: &Path, im: Im) -> Result<Vec<LognormalCurve>> {
    Ok(read_fragility_csv(path)?
        .into_iter()
        .filter(|r| r.im == im)
        .filter_map(|r| match (r.median, r.beta) {
            (Some(median), Some(beta)) if median > 0.0 && beta > 0.0 => Some(LognormalCurve {
                case: r.case,
                limit_state: r.limit_state,
                median,
                beta,
                median_band: r.median_band,
                n_exceeded: r.n_exceeded,
            }),
            _ => None,
        })
        .collect())
}

/// The distinct values of `values`, sorted (drawn last, once).
pub fn distinct(values: impl IntoIterator<Item = Param<f64>>) -> Vec<Param<f64>> {
    let mut v = runs(values, |a, b| a.total_cmp(b).is_eq());
    v.sort_by(Param::total_cmp);
    v.dedup();
    v
}

/// `values` less each value equal (`same` and `==`) to the one before it,
/// for the sort and dedup above: a study's rows come sorted by case, so
/// 100,000 analyses give a few dozen values, not 100,000 copies (the
/// figures' peak memory). The dedup after the sort gives the same list
/// either way: a dropped value equals the one it followed, which stays
/// next to it through a stable sort.
pub(crate) fn runs<T: PartialEq>(
    values: impl IntoIterator<Item = T>,
    same: impl Fn(&T, &T) -> bool,
) -> Vec<T> {
    let mut v: Vec<T> = Vec::new();
    for x in values {
        if v.last().is_none_or(|last| !(same(last, &x) && *last == x)) {
            v.push(x);
        }
    }
    v
}

/// The distinct fixed values of `values`, sorted (drawn ones left out).
pub fn distinct_fixed(values: impl IntoIterator<Item = Param<f64>>) -> Vec<f64> {
    distinct(values)
        .into_iter()
        .filter_map(Param::fixed)
        .collect()
}

/// The distinct numbers of `values`, sorted.
pub fn distinct_numbers(values: impl IntoIterator<Item = f64>) -> Vec<f64> {
    let mut v = runs(values, |a, b| a.total_cmp(b).is_eq());
    v.sort_by(f64::total_cmp);
    v.dedup();
    v
}

/// The distinct friction models of `values`, infinite first, drawn last.
pub fn distinct_friction(
    values: impl IntoIterator<Item = Param<Friction>>,
) -> Vec<Param<Friction>> {
    let mut v = runs(values, |a, b| cmp_friction(a, b).is_eq());
    v.sort_by(cmp_friction);
    v.dedup();
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_by_header_name_skips_failed_rows_and_sorts() {
        // Columns in any order, unknown columns ignored, failed rows skipped,
        // rows sorted whatever order they came in.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("outcomes.csv");
        std::fs::write(
            &path,
            "extra,record,pga,aspect,width,restitution,friction,mu_s,mu_k,status,overturned,\
             uplifted,theta_max_over_theta_c,mu_motion,mu_impact,impacts,error\n\
             x,1,0.6,4,0.5,0,coulomb,0.7,0.6,ok,true,false,2.5,0.3,0.2,4,\n\
             x,0,0.6,4,0.5,0,inf,,,failed,,,,,,,boom\n\
             x,0,0.6,4,0.5,0,inf,,,ok,false,true,0.5,0.3,0.185,12,\n",
        )
        .unwrap();
        let (rows, im) = read_outcomes(&path).unwrap();
        assert_eq!(im, Im::PGA, "no pga_rotd50 column");
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].case.friction, Param::Fixed(Friction::Infinite));
        assert!(rows[0].uplifted && !rows[0].overturned);
        assert_eq!(
            rows[1].case.friction,
            Param::Fixed(Friction::Coulomb {
                mu_s: 0.7,
                mu_k: 0.6
            })
        );
        assert_eq!(rows[1].impacts, 4);
        // a file from before the eq. (5) column reads, without it
        assert!(rows.iter().all(|r| r.mu_impact_eq5.is_none()));
    }
}
