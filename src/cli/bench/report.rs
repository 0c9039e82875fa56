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
//!   the Taylor integrator: series);
//! - **fragility**: each case's lognormal fragility fitted to the setting's
//!   outcomes against the fit to the reference's, in units of the reference
//!   fit's 90 % bootstrap band and absolute (`fragility.rs`): what a user's
//!   curve would move by.
//!
//! Single runs on strong records are chaotic near overturning: the report
//! therefore gives medians and maxima over the ensemble, counts outcome
//! mismatches rather than trusting one run, and says which mismatches are
//! runs a hair decides: every reference solution is solved again under the
//! record scaled by 1 + 1e-9 ([`rockfrag::solver::sensitivity`]), and a
//! mismatch on a run the reference itself finds sensitive is chaos, not
//! solver error. The fraction of sensitive runs is given per stripe.

use super::fragility::{CaseGroup, FragilityError, ReferenceFit, fragility_error, reference_fits};
use rayon::prelude::*;
use rockfrag::Result;
use rockfrag::case::Case as CaseKey;
use rockfrag::fragility::percentile;
use rockfrag::motion::{G_STANDARD, Record, SynthesisSettings, Synthesizer};
use rockfrag::outcome::Outcome;
use rockfrag::solver::{
    Analysis, Block, Friction, Integrator, Model, Sensitivity, SolverSettings, sensitivity,
    simulate,
};
use std::time::Instant;

/// What the report covers. Plain data with documented defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkPrecisionOptions {
    /// Records per intensity level (default 25).
    pub records: u64,
    /// Ensemble seed (default 1991).
    pub seed: u64,
    /// PGA levels in g, the stripes of the fragility fits (default 0.2, 0.4
    /// … 1.2).
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
    /// Bootstrap replicates of the reference's fits (default 1000).
    pub bootstrap: usize,
}

impl Default for WorkPrecisionOptions {
    fn default() -> Self {
        WorkPrecisionOptions {
            records: 25,
            seed: 1991,
            pga: vec![0.2, 0.4, 0.6, 0.8, 1.0, 1.2],
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
            bootstrap: 1000,
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
    /// Of those, runs the reference finds sensitive (decided by a hair).
    pub sensitive_mismatches: usize,
    /// The mismatches on runs the reference does not find sensitive, as
    /// indices into the ensemble.
    pub plain_mismatches: Vec<usize>,
    /// The error of the fitted fragility curves.
    pub fragility: FragilityError,
    /// The same with the reference's outcome on every run the reference
    /// finds sensitive: the error the solver makes, without the runs a hair
    /// decides (which any perturbation flips).
    pub fragility_robust: FragilityError,
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

/// One analysis of the ensemble.
#[derive(Clone, Debug)]
pub struct Case {
    /// The block and its contacts.
    pub analysis: Analysis,
    /// The record, as an index into the ensemble's records.
    pub record: usize,
    /// The stripe, as an index into [`WorkPrecisionOptions::pga`].
    pub stripe: usize,
    /// The record's index within its stripe (the same record shape at every
    /// stripe).
    pub index: usize,
    /// The case (block configuration), as an index into [`Report::groups`].
    pub group: usize,
}

/// What the reference found, besides each setting's errors.
#[derive(Clone, Debug)]
pub struct Report {
    /// The ensemble's analyses.
    pub cases: Vec<Case>,
    /// The cases (block configurations) and their analyses.
    pub groups: Vec<CaseGroup>,
    /// The reference's outcomes.
    pub reference: Vec<Outcome>,
    /// The reference's sensitivity, per analysis.
    pub sensitivity: Vec<Sensitivity>,
    /// The reference's fit of each case, with its band.
    pub fits: Vec<ReferenceFit>,
    /// The fragility error of the reference itself under the record scaled
    /// by 1 + 1e-9: what the runs a hair decides move the curves by, the
    /// floor of every setting's error.
    pub floor: FragilityError,
    /// Each setting's errors and cost.
    pub settings: Vec<SettingReport>,
}

/// Runs the report: reference solutions and their sensitivity, then every
/// setting (the nonlinear model at each rtol, and the linearised model on
/// the infinite-friction cases, which is all it models).
pub fn work_precision(opts: &WorkPrecisionOptions) -> Result<Report> {
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
    let n_rec = opts.records as usize;
    let mut cases = Vec::new();
    let mut groups = Vec::new();
    for &aspect in &opts.aspect {
        let block = Block::new(0.5, aspect, G_STANDARD)?;
        for &e in &opts.restitution {
            for &friction in &opts.friction {
                let mut group = CaseGroup {
                    key: CaseKey::fixed(aspect, 0.5, e, friction),
                    label: case_label(aspect, e, friction),
                    analyses: Vec::new(),
                };
                for record in 0..records.len() {
                    let mut analysis = Analysis::new(block, e);
                    analysis.friction = friction;
                    let (stripe, index) = (record / n_rec, record % n_rec);
                    group.analyses.push((cases.len(), index, opts.pga[stripe]));
                    cases.push(Case {
                        analysis,
                        record,
                        stripe,
                        index,
                        group: groups.len(),
                    });
                }
                groups.push(group);
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
    let (reference, sens): (Vec<Outcome>, Vec<Sensitivity>) = cases
        .par_iter()
        .map(|c| {
            let rec = &records[c.record];
            let o = simulate(&c.analysis, rec, &reference_settings, None)?;
            let s = sensitivity(&c.analysis, rec, &reference_settings, &o)?;
            Ok((o, s))
        })
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .unzip();
    let all_reference: Vec<Option<Outcome>> = reference.iter().cloned().map(Some).collect();
    let fits = reference_fits(&groups, &all_reference, n_rec, opts.bootstrap);
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
    // Timed one analysis at a time, on one thread, for a fair cost per
    // analysis: each analysis by every setting in turn (from a different
    // one each time), three rounds, the fastest kept, so that a busy machine
    // adds less noise and what it adds falls on every setting alike.
    let runs = |c: &Case, set: &SolverSettings, only: Option<f64>| {
        !(set.model == Model::Linear && c.analysis.friction != Friction::Infinite
            || only.is_some_and(|e| c.analysis.restitution != e))
    };
    let mut rows: Vec<Vec<(usize, f64, Outcome)>> = vec![Vec::new(); all.len()];
    let mut outcomes: Vec<Vec<Option<Outcome>>> = vec![vec![None; cases.len()]; all.len()];
    for (i, c) in cases.iter().enumerate() {
        let mut best = vec![f64::INFINITY; all.len()];
        for round in 0..3 {
            // each round starts at another setting, so that none is always
            // the first after another's code and data
            for j in 0..all.len() {
                let k = (i + round * 7 + j) % all.len();
                let (_, set, only) = &all[k];
                if !runs(c, set, *only) {
                    continue;
                }
                let start = Instant::now();
                let o = simulate(&c.analysis, &records[c.record], set, None)?;
                best[k] = best[k].min(start.elapsed().as_secs_f64());
                outcomes[k][i] = Some(o);
            }
        }
        for k in 0..all.len() {
            if let Some(o) = &outcomes[k][i] {
                rows[k].push((i, best[k], o.clone()));
            }
        }
    }
    for (((label, set, only), rows), mut outcomes) in all.into_iter().zip(rows).zip(outcomes) {
        let mut report = summarise(label, set, only, &rows, &reference, &sens);
        report.fragility = fragility_error(&groups, &outcomes, n_rec, &fits);
        for (i, o) in outcomes.iter_mut().enumerate() {
            if sens[i].sensitive && o.is_some() {
                *o = Some(reference[i].clone());
            }
        }
        report.fragility_robust = fragility_error(&groups, &outcomes, n_rec, &fits);
        reports.push(report);
    }
    // the floor: the reference itself under the record scaled by 1 + 1e-9
    let perturbed: Vec<Option<Outcome>> = sens
        .iter()
        .map(|s| {
            Some(Outcome {
                overturned: s.overturned,
                ..Outcome::default()
            })
        })
        .collect();
    let floor = fragility_error(&groups, &perturbed, n_rec, &fits);
    Ok(Report {
        cases,
        groups,
        reference,
        sensitivity: sens,
        fits,
        floor,
        settings: reports,
    })
}

/// `H/B 4, e 0.9, μ 0.7/0.6` (or `μ ∞`).
fn case_label(aspect: f64, e: f64, friction: Friction) -> String {
    let mu = match friction {
        Friction::Infinite => "μ ∞".to_string(),
        Friction::Coulomb { mu_s, mu_k } => format!("μ {mu_s}/{mu_k}"),
    };
    format!("H/B {aspect}, e {e}, {mu}")
}

fn summarise(
    label: String,
    settings: SolverSettings,
    restitution_only: Option<f64>,
    rows: &[(usize, f64, Outcome)],
    reference: &[Outcome],
    sens: &[Sensitivity],
) -> SettingReport {
    let mut times: Vec<f64> = rows.iter().map(|r| r.1).collect();
    let rel = |a: f64, b: f64| {
        if b != 0.0 {
            ((a - b) / b).abs()
        } else {
            (a - b).abs()
        }
    };
    let (mut th, mut mu, mut fi) = (Vec::new(), Vec::new(), Vec::new());
    let (mut mismatches, mut sensitive, mut plain) = (0, 0, Vec::new());
    for (i, _, o) in rows {
        let r = &reference[*i];
        if o.overturned != r.overturned {
            mismatches += 1;
            if sens[*i].sensitive {
                sensitive += 1;
            } else {
                plain.push(*i);
            }
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
        rows.iter().map(|r| r.2.stats.rhs_calls as f64).sum::<f64>() / rows.len().max(1) as f64;
    SettingReport {
        label,
        settings,
        restitution_only,
        analyses: rows.len(),
        median_time: median(&mut times),
        mean_rhs: rhs,
        overturn_mismatches: mismatches,
        sensitive_mismatches: sensitive,
        plain_mismatches: plain,
        fragility: FragilityError::default(),
        fragility_robust: FragilityError::default(),
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

/// A setting's fragility error must stay below this many 90 % bands.
pub const ADEQUATE_BANDS: f64 = 0.1;

/// The cheapest setting that covers every case (the nonlinear model over
/// all restitutions) whose fragility error stays below [`ADEQUATE_BANDS`] of
/// the reference fits' 90 % bands, if any; with `robust`, the error without
/// the runs the reference finds sensitive
/// ([`SettingReport::fragility_robust`]).
pub fn cheapest_adequate(reports: &[SettingReport], robust: bool) -> Option<&SettingReport> {
    reports
        .iter()
        .filter(|r| {
            let f = if robust {
                &r.fragility_robust
            } else {
                &r.fragility
            };
            r.settings.model == Model::Nonlinear
                && r.restitution_only.is_none()
                && f.bands() < ADEQUATE_BANDS
        })
        .min_by(|a, b| a.median_time.total_cmp(&b.median_time))
}

/// The default setting's report (the nonlinear model by Taylor series at
/// rtol 1e-8, cascade rules on, over every case).
fn default_setting(reports: &[SettingReport]) -> Option<&SettingReport> {
    let d = SolverSettings::default();
    reports.iter().find(|r| {
        r.restitution_only.is_none()
            && r.settings.model == d.model
            && r.settings.integrator == d.integrator
            && r.settings.rtol == d.rtol
            && r.settings.settle_cascades == d.settle_cascades
    })
}

/// An error in bands for the tables: 0 when exact, ∞ when unfitted.
fn bands(x: f64) -> String {
    if x == 0.0 {
        "0".to_string()
    } else if x.is_infinite() {
        "unfit".to_string()
    } else {
        format!("{x:.3}")
    }
}

/// The report as markdown: the analysis-by-analysis table, the sensitive
/// runs per stripe, and the fragility-level table with the cheapest
/// adequate setting.
pub fn markdown(opts: &WorkPrecisionOptions, report: &Report) -> String {
    let reports = &report.settings;
    let mut s = String::new();
    s.push_str(
        "# Speed against error

",
    );
    s.push_str(&format!(
        "Reference: nonlinear model, Dormand–Prince at rtol {:e} (atol rtol/100), every impact followed (cascade rules off). Settings: each integrator at rtol 1e-3 … 1e-10 with atol = rtol/100 and the cascade rules on (the default), the default without the cascade rules, and the linearised model. Ensemble: {} records (seed {}) at each PGA of {:?} g; H/B {:?}, 2B = 0.5 m; e {:?}; \
         infinite friction and μs = 0.7, μk = 0.6 (the linearised model: infinite friction only); {} analyses. \
         Times are medians per analysis on one thread (the fastest of three runs each).\n\n",
        opts.reference_rtol,
        opts.records,
        opts.seed,
        opts.pga,
        opts.aspect,
        opts.restitution,
        report.cases.len()
    ));
    s.push_str("## Analysis by analysis\n\n");
    s.push_str(
        "Errors over runs that overturned in neither solution. A mismatch is a run whose overturning differs from the reference's; \
         in brackets, how many of them the reference itself finds sensitive: solved again under the record scaled by 1 + 1e-9, \
         its overturning flips, θmax/θc moves by more than 1e-3 or the time of overturning by more than 0.01 s \
         (`rockfrag::solver::sensitivity`; `rockfrag simulate --sensitivity`).\n\n",
    );
    s.push_str("| setting | analyses | median time (µs) | mean RHS calls (Taylor: series) | overturn mismatches (sensitive) | θmax err median | θmax err p95 | θmax err max | μ_mot err median | first impact err median (s) |\n");
    s.push_str("|---|---|---|---|---|---|---|---|---|---|\n");
    for r in reports {
        s.push_str(&format!(
            "| {} | {} | {:.0} | {:.0} | {} ({}) | {:.1e} | {:.1e} | {:.1e} | {:.1e} | {:.1e} |\n",
            r.label,
            r.analyses,
            r.median_time * 1e6,
            r.mean_rhs,
            r.overturn_mismatches,
            r.sensitive_mismatches,
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
        None => s.push_str(
            "\nNo setting has both zero overturning mismatches and θmax error < 1e-6: \
             many mismatches are runs a hair decides (below), which no tolerance removes, \
             so the choice is made on the fitted curves (last section).\n",
        ),
    }
    // the mismatches over the nonlinear settings, and those that are not
    // sensitive (the linearised model's are its own equation's error too)
    let nonlinear = || {
        reports
            .iter()
            .filter(|r| r.settings.model == Model::Nonlinear)
    };
    let total: usize = nonlinear().map(|r| r.overturn_mismatches).sum();
    let sensitive: usize = nonlinear().map(|r| r.sensitive_mismatches).sum();
    let mut plain: Vec<(usize, Vec<&str>)> = Vec::new();
    for r in nonlinear() {
        for &i in &r.plain_mismatches {
            match plain.iter_mut().find(|p| p.0 == i) {
                Some(p) => p.1.push(&r.label),
                None => plain.push((i, vec![&r.label])),
            }
        }
    }
    plain.sort_by_key(|p| p.0);
    s.push_str(&format!(
        "\nOver the nonlinear model's settings, {total} overturning mismatches, {sensitive} of them on runs the reference finds sensitive",
    ));
    if plain.is_empty() {
        s.push_str(": every mismatch is a run decided by a hair, not a solver error.\n");
    } else {
        s.push_str(&format!(
            "; {} on {} run(s) it does not:\n\n",
            total - sensitive,
            plain.len()
        ));
        for (i, labels) in &plain {
            let c = &report.cases[*i];
            let r = &report.reference[*i];
            s.push_str(&format!(
                "- {}, {} g, record {}: the reference {} (θmax/θc {:.3}); mismatched by {}.\n",
                report.groups[c.group].label,
                opts.pga[c.stripe],
                c.index,
                match r.overturn_time {
                    Some(t) => format!("overturns at {t:.2} s"),
                    None => "does not overturn".to_string(),
                },
                r.theta_max_over_theta_c,
                labels.join("; ")
            ));
        }
        s.push_str(
            "\nEach is a run a larger perturbation of the record flips (a hair the 1e-9 does not probe), \
             or the setting's own error: solved under the record scaled by 1 ± 1e-9 … 1e-6, a setting that errs \
             there errs under every scaling (the docs of `rockfrag::solver::sensitivity` say which, on this ensemble).\n",
        );
    }
    for r in reports.iter().filter(|r| r.settings.model == Model::Linear) {
        s.push_str(&format!(
            "\nThe linearised model mismatches {} runs, {} of them sensitive: the others are its own equation's error \
             (eq. (1) linearised in θ), not the solver's.\n",
            r.overturn_mismatches, r.sensitive_mismatches
        ));
    }
    s.push_str(&stripes(opts, report));
    s.push_str(&fragility_tables(report));
    s
}

/// The sensitive runs per stripe, and where the stripe sits on the
/// reference's curves.
fn stripes(opts: &WorkPrecisionOptions, report: &Report) -> String {
    let mut s = String::new();
    s.push_str("\n## Runs a hair decides, per stripe\n\n");
    s.push_str(
        "Reference solutions that are sensitive (as above), per PGA level, and the reference's fitted probability of overturning there \
         (mean over the cases, each case's lognormal fit): the sensitive runs sit where the curves rise and above, among blocks that rock hard, bounce or balance past θc.\n\n",
    );
    s.push_str("| PGA (g) | analyses | overturned | sensitive | share | of them overturned | e = 0 / e = 0.9 | mean fitted P(overturn) |\n");
    s.push_str("|---|---|---|---|---|---|---|---|\n");
    let (mut n_all, mut s_all) = (0, 0);
    for (k, &pga) in opts.pga.iter().enumerate() {
        let idx: Vec<usize> = (0..report.cases.len())
            .filter(|&i| report.cases[i].stripe == k)
            .collect();
        let sens: Vec<usize> = idx
            .iter()
            .copied()
            .filter(|&i| report.sensitivity[i].sensitive)
            .collect();
        let over = idx
            .iter()
            .filter(|&&i| report.reference[i].overturned)
            .count();
        let sens_over = sens
            .iter()
            .filter(|&&i| report.reference[i].overturned)
            .count();
        let by_e = |e: f64| {
            sens.iter()
                .filter(|&&i| report.cases[i].analysis.restitution == e)
                .count()
        };
        let fitted: Vec<f64> = report
            .fits
            .iter()
            .filter_map(|f| f.fit.as_ref().ok().map(|f| f.probability(pga)))
            .collect();
        let p = fitted.iter().sum::<f64>() / fitted.len().max(1) as f64;
        s.push_str(&format!(
            "| {pga} | {} | {over} | {} | {:.1} % | {sens_over} | {} / {} | {p:.2} |\n",
            idx.len(),
            sens.len(),
            100.0 * sens.len() as f64 / idx.len().max(1) as f64,
            by_e(0.0),
            by_e(0.9),
        ));
        n_all += idx.len();
        s_all += sens.len();
    }
    s.push_str(&format!(
        "| all | {n_all} | {} | {s_all} | {:.1} % | | | |\n",
        report.reference.iter().filter(|o| o.overturned).count(),
        100.0 * s_all as f64 / n_all.max(1) as f64
    ));
    s
}

/// The reference's fits, each setting's fragility error, and the cheapest
/// adequate setting.
fn fragility_tables(report: &Report) -> String {
    let reports = &report.settings;
    let mut s = String::new();
    s.push_str("\n## The fragility curves\n\n");
    s.push_str(
        "Each case's lognormal fragility (probit maximum likelihood over the stripes, PGA in g) fitted to the reference's outcomes, \
         with its 90 % band from 1000 bootstrap replicates over records (`rockfrag::fragility`):\n\n",
    );
    s.push_str("| case | median θ (g) | 90 % band | β | 90 % band | unfitted replicates |\n");
    s.push_str("|---|---|---|---|---|---|\n");
    for (g, f) in report.groups.iter().zip(&report.fits) {
        match (&f.fit, f.bands) {
            (Ok(fit), Some((bt, bb))) => s.push_str(&format!(
                "| {} | {:.3} | {:.3}–{:.3} | {:.3} | {:.3}–{:.3} | {} |\n",
                g.label,
                fit.median(),
                bt.lo,
                bt.hi,
                fit.beta(),
                bb.lo,
                bb.hi,
                f.unfit_replicates
            )),
            (Ok(fit), None) => s.push_str(&format!(
                "| {} | {:.3} | – | {:.3} | – | {} |\n",
                g.label,
                fit.median(),
                fit.beta(),
                f.unfit_replicates
            )),
            (Err(u), _) => s.push_str(&format!("| {} | {} | | | | |\n", g.label, u.status())),
        }
    }
    s.push_str(&format!(
        "\nEach setting's fits against those: the largest change over the cases of the median and of β, in units of the reference's 90 % band \
         (its width, 5th to 95th percentile) and absolute; the fragility error is the larger of the two in bands. \
         A setting is adequate when it stays below {ADEQUATE_BANDS} of the band: it moves no curve by more than a tenth of what {} records leave uncertain. \
         A setting with every outcome of the reference fits the same curves (error 0). \
         The first row is the reference itself under the record scaled by 1 + 1e-9: its sensitive runs flip, and the curves move by that much \
         whatever the solver. The column *without sensitive runs* gives each setting's error with the reference's outcome on every run the reference \
         finds sensitive: the solver's own error, without the runs a hair decides.\n\n",
        report.groups.first().map_or(0, |g| g.analyses.iter().map(|a| a.1).max().map_or(0, |m| m + 1))
    ));
    s.push_str("| setting | median time (µs) | cases | fragility err (bands) | without sensitive runs (bands) | θ err max (bands) | β err max (bands) | θ err max (g) | β err max | largest in |\n");
    s.push_str("|---|---|---|---|---|---|---|---|---|---|\n");
    let row = |label: &str, time: String, f: &FragilityError, robust: String| {
        format!(
            "| {} | {} | {} | {} | {} | {} | {} | {:.1e} | {:.1e} | {} |\n",
            label,
            time,
            f.compared,
            bands(f.bands()),
            robust,
            bands(f.theta_bands),
            bands(f.beta_bands),
            f.theta_abs,
            f.beta_abs,
            if f.bands() > 0.0 {
                f.worst_case.as_str()
            } else {
                "–"
            }
        )
    };
    s.push_str(&row(
        "reference, record × (1 + 1e-9)",
        "–".to_string(),
        &report.floor,
        "0".to_string(),
    ));
    for r in reports {
        s.push_str(&row(
            &r.label,
            format!("{:.0}", r.median_time * 1e6),
            &r.fragility,
            bands(r.fragility_robust.bands()),
        ));
    }
    let default = default_setting(reports);
    let floor = report.floor.bands();
    match cheapest_adequate(reports, false) {
        Some(r) => s.push_str(&format!(
            "\nCheapest setting over every case whose fragility error stays below {ADEQUATE_BANDS} of the 90 % band: **{}** ({:.0} µs per analysis, error {}).\n",
            r.label,
            r.median_time * 1e6,
            bands(r.fragility.bands())
        )),
        None => s.push_str(&format!(
            "\nNo setting over every case keeps its fragility error below {ADEQUATE_BANDS} of the 90 % band, and none can: \
             the reference itself, under the record scaled by 1 + 1e-9, moves the curves by {} of the band. \
             That error is the runs a hair decides, which flip under any perturbation, a solver's error included; \
             it is part of the statistical uncertainty of a curve from {} records, not an error a tolerance can remove.\n",
            bands(floor),
            report.groups.first().map_or(0, |g| g.analyses.iter().map(|a| a.1).max().map_or(0, |m| m + 1))
        )),
    }
    if let Some(r) = cheapest_adequate(reports, true) {
        s.push_str(&format!(
            "\nWithout the runs a hair decides, the cheapest setting over every case whose fragility error stays below {ADEQUATE_BANDS} of the band is **{}** ({:.0} µs per analysis, error {}).",
            r.label,
            r.median_time * 1e6,
            bands(r.fragility_robust.bands())
        ));
        if let Some(d) = default {
            if std::ptr::eq(d, r) {
                s.push_str(" It is the default.\n");
            } else if d.fragility_robust.bands() < ADEQUATE_BANDS {
                s.push_str(&format!(
                    " The default ({}) is adequate too (error {}) but not the cheapest: {:.0} µs, {:+.0} % (differences of a few per cent are timing noise on a shared machine)",
                    d.label,
                    bands(d.fragility_robust.bands()),
                    d.median_time * 1e6,
                    100.0 * (d.median_time / r.median_time - 1.0)
                ));
                if d.settings.integrator == r.settings.integrator {
                    s.push_str(&format!(
                        ", {:.0} against {:.0} {} per analysis",
                        d.mean_rhs,
                        r.mean_rhs,
                        match d.settings.integrator {
                            Integrator::Taylor => "series",
                            Integrator::Dopri5 => "RHS calls",
                        }
                    ));
                }
                s.push_str(".\n");
            } else {
                s.push_str(&format!(
                    " The default ({}) is not adequate: its error is {}.\n",
                    d.label,
                    bands(d.fragility_robust.bands())
                ));
            }
        }
    } else {
        s.push_str(&format!(
            "\nEven without the runs a hair decides, no setting over every case keeps its fragility error below {ADEQUATE_BANDS} of the band.\n"
        ));
    }
    s
}
