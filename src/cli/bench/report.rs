//! Speed against error: the work–precision report behind `rockfrag bench`.
//!
//! A reference solution per analysis at very tight tolerance (nonlinear
//! model, Dormand–Prince at rtol 1e-12, atol 1e-14), then for each solver
//! setting (each integrator of the nonlinear model at rtol 1e-3 … 1e-10 with
//! atol = rtol/100, and the linearised model) the errors against it and the
//! cost per analysis:
//!
//! - **θmax**: relative error of θmax/θc over the runs that overturned in
//!   neither solution (an overturned run's θmax is capped at π/2);
//! - **overturning**: the number of runs whose outcome differs;
//! - **μ_mot**: relative error of the peak friction demand while rocking, over
//!   the same runs;
//! - **first impact**: absolute error of the first impact's time (s);
//! - **cost**: median wall time per analysis (one thread, the fastest of
//!   three runs of each analysis) and mean right-hand-side evaluations (for
//!   the Taylor integrator: series).
//!
//! Single runs on strong records are chaotic near overturning (physics.md,
//! "Sensitivity"): the report therefore gives medians and maxima over the
//! ensemble and counts outcome mismatches rather than trusting one run.

use rayon::prelude::*;
use rockfrag::Result;
use rockfrag::fragility::percentile;
use rockfrag::motion::{G_STANDARD, Record, SynthesisSettings, Synthesizer};
use rockfrag::outcome::Outcome;
use rockfrag::solver::{Analysis, Block, Friction, Integrator, Model, SolverSettings, simulate};
use std::time::Instant;

/// What the report covers. Plain data with documented defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkPrecisionOptions {
    /// Records per intensity level (default 25).
    pub records: u64,
    /// Ensemble seed (default 1991).
    pub seed: u64,
    /// PGA levels in g (default 0.6 and 1.2).
    pub pga: Vec<f64>,
    /// Aspect ratios H/B (default 2, 4, 6), base width 0.5 m.
    pub aspect: Vec<f64>,
    /// Coefficients of restitution (default 0 and 0.9).
    pub restitution: Vec<f64>,
    /// Friction models (default infinite, and μs = 0.7, μk = 0.6).
    pub friction: Vec<Friction>,
    /// Integrators of the nonlinear model to compare (default: Taylor and
    /// Dormand–Prince).
    pub integrators: Vec<Integrator>,
    /// Relative tolerances of the nonlinear model to compare (default 1e-3 …
    /// 1e-10); each is run with atol = rtol/100.
    pub rtols: Vec<f64>,
    /// Relative tolerance of the reference solutions, by Dormand–Prince with
    /// atol = rtol/100 (default 1e-12).
    pub reference_rtol: f64,
}

impl Default for WorkPrecisionOptions {
    fn default() -> Self {
        WorkPrecisionOptions {
            records: 25,
            seed: 1991,
            pga: vec![0.6, 1.2],
            aspect: vec![2.0, 4.0, 6.0],
            restitution: vec![0.0, 0.9],
            friction: vec![
                Friction::Infinite,
                Friction::Coulomb {
                    mu_s: 0.7,
                    mu_k: 0.6,
                },
            ],
            integrators: vec![Integrator::Taylor, Integrator::Dopri5],
            rtols: vec![1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10],
            reference_rtol: 1e-12,
        }
    }
}

/// One solver setting's errors and cost.
#[derive(Clone, Debug, PartialEq)]
pub struct SettingReport {
    /// Short label, e.g. `nonlinear rtol=1e-6` or `linear`.
    pub label: String,
    /// The settings measured.
    pub settings: SolverSettings,
    /// The coefficient of restitution this setting was run on alone, or
    /// `None` for every case (a point of its own, e.g. the chatter rule at
    /// e = 0.9, the cases it is for).
    pub restitution_only: Option<f64>,
    /// Analyses compared.
    pub analyses: usize,
    /// Median wall time per analysis (s).
    pub median_time: f64,
    /// Mean right-hand-side evaluations per analysis.
    pub mean_rhs: f64,
    /// Runs whose overturning outcome differs from the reference.
    pub overturn_mismatches: usize,
    /// Median and maximum relative error of θmax/θc.
    pub theta_err: (f64, f64),
    /// 95th percentile of the relative error of θmax/θc (the bulk of the
    /// ensemble, without its few chaotic runs).
    pub theta_err_p95: f64,
    /// Median and maximum relative error of μ_mot.
    pub mu_err: (f64, f64),
    /// Median and maximum absolute error of the first impact time (s).
    pub first_impact_err: (f64, f64),
}

struct Case {
    analysis: Analysis,
    record: usize,
}

/// Runs the report: reference solutions, then every setting (the nonlinear
/// model at each rtol, and the linearised model on the infinite-friction
/// cases, which is all it models).
pub fn work_precision(opts: &WorkPrecisionOptions) -> Result<Vec<SettingReport>> {
    let settings = SynthesisSettings::default();
    let synth = Synthesizer::new(&settings)?;
    let records: Vec<Record> = opts
        .pga
        .iter()
        .flat_map(|&pga| (0..opts.records).map(move |i| (pga, i)))
        .collect::<Vec<_>>()
        .par_iter()
        .map(|&(pga, i)| synth.clone().generate(opts.seed, i, pga * G_STANDARD))
        .collect::<Result<_>>()?;
    let mut cases = Vec::new();
    for &aspect in &opts.aspect {
        let block = Block::new(0.5, aspect, G_STANDARD)?;
        for &e in &opts.restitution {
            for &friction in &opts.friction {
                for record in 0..records.len() {
                    let mut analysis = Analysis::new(block, e);
                    analysis.friction = friction;
                    cases.push(Case { analysis, record });
                }
            }
        }
    }
    let reference_settings = SolverSettings {
        integrator: Integrator::Dopri5,
        rtol: opts.reference_rtol,
        atol: opts.reference_rtol * 1e-2,
        // every impact followed: the cascade rule's own error is measured too
        settle_cascades: false,
        ..SolverSettings::default()
    };
    let reference: Vec<Outcome> = cases
        .par_iter()
        .map(|c| simulate(&c.analysis, &records[c.record], &reference_settings, None))
        .collect::<Result<_>>()?;
    let mut reports = Vec::new();
    let mut all: Vec<(String, SolverSettings, Option<f64>)> = Vec::new();
    for &integrator in &opts.integrators {
        for &rtol in &opts.rtols {
            all.push((
                format!("{} rtol={rtol:e}", integrator.name()),
                SolverSettings {
                    integrator,
                    rtol,
                    atol: rtol * 1e-2,
                    ..SolverSettings::default()
                },
                None,
            ));
        }
    }
    let off = SolverSettings {
        settle_cascades: false,
        ..SolverSettings::default()
    };
    all.push(("taylor rtol=1e-8, cascade rules off".to_string(), off, None));
    if opts.restitution.contains(&0.9) {
        // the chatter rule's own point: the bouncy cases, with and without it
        let label = "taylor rtol=1e-8, e=0.9 only";
        all.push((label.to_string(), SolverSettings::default(), Some(0.9)));
        all.push((format!("{label}, cascade rules off"), off, Some(0.9)));
    }
    all.push((
        "linear".to_string(),
        SolverSettings {
            model: Model::Linear,
            ..SolverSettings::default()
        },
        None,
    ));
    for (label, set, only) in all {
        let mut rows = Vec::new();
        for (c, r) in cases.iter().zip(&reference) {
            if set.model == Model::Linear && c.analysis.friction != Friction::Infinite {
                continue;
            }
            if only.is_some_and(|e| c.analysis.restitution != e) {
                continue;
            }
            // timed one at a time, on one thread, for a fair cost per
            // analysis; the fastest of three runs, so that a busy machine
            // adds less noise
            let mut best = f64::INFINITY;
            let mut out = None;
            for _ in 0..3 {
                let start = Instant::now();
                let o = simulate(&c.analysis, &records[c.record], &set, None)?;
                best = best.min(start.elapsed().as_secs_f64());
                out = Some(o);
            }
            if let Some(o) = out {
                rows.push((best, o, r));
            }
        }
        reports.push(summarise(label, set, only, &rows));
    }
    Ok(reports)
}

fn summarise(
    label: String,
    settings: SolverSettings,
    restitution_only: Option<f64>,
    rows: &[(f64, Outcome, &Outcome)],
) -> SettingReport {
    let mut times: Vec<f64> = rows.iter().map(|r| r.0).collect();
    let rel = |a: f64, b: f64| {
        if b != 0.0 {
            ((a - b) / b).abs()
        } else {
            (a - b).abs()
        }
    };
    let (mut th, mut mu, mut fi) = (Vec::new(), Vec::new(), Vec::new());
    let mut mismatches = 0;
    for (_, o, r) in rows {
        if o.overturned != r.overturned {
            mismatches += 1;
            continue;
        }
        if !o.overturned && r.theta_max_over_theta_c > 0.0 {
            th.push(rel(o.theta_max_over_theta_c, r.theta_max_over_theta_c));
            mu.push(rel(o.mu_motion, r.mu_motion));
        }
        if let (Some(a), Some(b)) = (o.first_impact_time, r.first_impact_time) {
            fi.push((a - b).abs());
        }
    }
    let rhs: f64 =
        rows.iter().map(|r| r.1.stats.rhs_calls as f64).sum::<f64>() / rows.len().max(1) as f64;
    SettingReport {
        label,
        settings,
        restitution_only,
        analyses: rows.len(),
        median_time: median(&mut times),
        mean_rhs: rhs,
        overturn_mismatches: mismatches,
        theta_err: (median(&mut th), max(&th)),
        // `median` above left `th` sorted
        theta_err_p95: if th.is_empty() {
            0.0
        } else {
            percentile(&th, 0.95)
        },
        mu_err: (median(&mut mu), max(&mu)),
        first_impact_err: (median(&mut fi), max(&fi)),
    }
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn max(v: &[f64]) -> f64 {
    v.iter().copied().fold(0.0, f64::max)
}

/// The cheapest nonlinear setting whose overturning outcomes all match the
/// reference and whose worst θmax error is below 1e-6 (the rule for the
/// default tolerance), if any.
pub fn cheapest_acceptable(reports: &[SettingReport]) -> Option<&SettingReport> {
    reports
        .iter()
        .filter(|r| {
            r.settings.model == Model::Nonlinear
                && r.restitution_only.is_none()
                && r.overturn_mismatches == 0
                && r.theta_err.1 < 1e-6
        })
        .min_by(|a, b| a.median_time.total_cmp(&b.median_time))
}

/// The report as a markdown table.
pub fn markdown(opts: &WorkPrecisionOptions, reports: &[SettingReport]) -> String {
    let mut s = String::new();
    s.push_str("# Speed against error\n\n");
    s.push_str(&format!(
        "Reference: nonlinear model, Dormand–Prince at rtol {:e} (atol rtol/100), every impact followed (cascade rule off). Settings: each integrator at rtol 1e-3 … 1e-10 with atol = rtol/100 and the cascade rule on (the default), the default without the cascade rule, and the linearised model. Ensemble: {} records (seed {}) at PGA {:?} g; H/B {:?}, 2B = 0.5 m; e {:?}; \
         infinite friction and μs = 0.7, μk = 0.6 (the linearised model: infinite friction only). \
         Errors over runs that overturned in neither solution; times are medians per analysis on one thread.\n\n",
        opts.reference_rtol, opts.records, opts.seed, opts.pga, opts.aspect, opts.restitution
    ));
    s.push_str("| setting | analyses | median time (µs) | mean RHS calls (Taylor: series) | overturn mismatches | θmax err median | θmax err p95 | θmax err max | μ_mot err median | first impact err median (s) |\n");
    s.push_str("|---|---|---|---|---|---|---|---|---|---|\n");
    for r in reports {
        s.push_str(&format!(
            "| {} | {} | {:.0} | {:.0} | {} | {:.1e} | {:.1e} | {:.1e} | {:.1e} | {:.1e} |\n",
            r.label,
            r.analyses,
            r.median_time * 1e6,
            r.mean_rhs,
            r.overturn_mismatches,
            r.theta_err.0,
            r.theta_err_p95,
            r.theta_err.1,
            r.mu_err.0,
            r.first_impact_err.0
        ));
    }
    match cheapest_acceptable(reports) {
        Some(r) => s.push_str(&format!(
            "\nCheapest setting with no overturning mismatch and θmax error < 1e-6: **{}**.\n",
            r.label
        )),
        None => {
            s.push_str("\nNo setting has both zero overturning mismatches and θmax error < 1e-6.\n")
        }
    }
    s
}
