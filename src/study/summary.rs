//! `summary.md`: a study's tables, computed from `outcomes.csv`.
//!
//! For each friction model, width and aspect ratio, a table of e, intensity,
//! number of runs that overturned, and over the runs that did not, the mean
//! θmax/θc, μ_mot and μ_imp. Two conventions: **strict** (overturned means
//! |θ| reached π/2) and the **paper's** (a run that lifted off from rock
//! also counts as overturned: the seed paper's program stopped there). A
//! [`Reference`] of published results (the paper layer has one for its own
//! study) puts each published value beside ours and tests the counts.
//!
//! The summary is always computed by reading `outcomes.csv` back, so a run,
//! a resumed run and a merge of shards give the same bytes.

use super::plan::{self, Shard};
use crate::case::{Case, Param};
use crate::error::Result;
use crate::io_util::sig3;
use crate::outcomes_csv::{Column, OutcomesFile};
use crate::solver::Friction;
use crate::spec::{Intensity, Motions, Study, Uncertainty, friction_label};
use crate::stats::{Trend, cochran_armitage, fisher_exact, p_text};
use crate::uncertainty::{Distribution, Property, Value};
use std::fmt::Write;
use std::path::Path;

/// Counts over all analyses of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Counts {
    /// Analyses in `outcomes.csv`.
    pub analyses: u64,
    /// Analyses the solver could not finish (status `failed`).
    pub failed: u64,
    /// Runs that reached |θ| = π/2.
    pub overturned: u64,
    /// Runs that lifted off from rock at least once.
    pub uplifted: u64,
    /// Runs overturned or uplifted (the paper's convention).
    pub overturned_or_uplifted: u64,
}

#[derive(Clone, Copy, Debug, Default)]
struct Means {
    n: u64,
    /// Sums of θmax/θc, μ_mot, μ_imp (impulse ratio), μ_imp by eq. (5).
    sums: [f64; 4],
}

impl Means {
    fn add(&mut self, values: [f64; 4]) {
        self.n += 1;
        for (s, v) in self.sums.iter_mut().zip(values) {
            *s += v;
        }
    }

    fn get(&self) -> Option<[f64; 4]> {
        let n = self.n as f64;
        (self.n > 0).then(|| self.sums.map(|s| s / n))
    }
}

#[derive(Clone, Copy, Debug, Default)]
struct Cell {
    ok: u64,
    failed: u64,
    overturned: u64,
    overturned_or_uplifted: u64,
    strict: Means,
    paper: Means,
}

/// Statistics of a run read back from its `outcomes.csv`.
#[derive(Clone, Debug)]
pub struct Tally {
    cells: Vec<Cell>,
    counts: Counts,
    levels: usize,
}

impl Tally {
    /// Reads `outcomes.csv` of `study` (shard `shard`) through
    /// [`OutcomesFile`], checking that its header is the study's, that
    /// every row is the analysis expected at its place (case, level,
    /// record), and the count.
    pub fn read(path: &Path, study: &Study, shard: Shard) -> Result<Tally> {
        let cols = plan::columns(study);
        let mut table = OutcomesFile::open(
            path,
            &[
                cols.level(),
                Column::Record,
                Column::Status,
                Column::Overturned,
                Column::Uplifted,
                Column::ThetaMaxOverThetaC,
                Column::MuMotion,
                Column::MuImpact,
                Column::MuImpactEq5,
            ],
            "the study's summary",
        )?;
        let names = cols.names();
        if table.header().iter().ne(names.iter().copied()) {
            return Err(table.header_error(format!(
                "header is not the study's: expected {}",
                names.join(",")
            )));
        }

        let cases = plan::cases(study);
        let drawn = study.drawn();
        let total = plan::unit_count(study);
        let levels = study.intensity.levels();
        let mut tally = Tally {
            cells: vec![Cell::default(); cases.len() * levels.len()],
            counts: Counts::default(),
            levels: levels.len(),
        };
        let mut units = shard.units(total);
        let mut unit = None;
        let mut rows = 0usize;
        while let Some((line, row)) = table.next_row()? {
            let at = |message: String| table.error_at(line, message);
            let ci = rows % cases.len();
            if ci == 0 {
                unit = units.next().map(|u| plan::unit(study, u));
            }
            let Some(u) = unit else {
                return Err(at("more rows than the study has analyses".into()));
            };
            let case = &cases[ci];
            let key = row.case.pooled(&drawn);
            if key != *case {
                return Err(at(format!(
                    "case {key} where the study's order puts {case}"
                )));
            }
            let level = row.level(&cols);
            if level != Some(levels[u.level]) {
                return Err(at(format!(
                    "{} = {} where the study's order puts {}",
                    cols.level(),
                    level.map_or(String::new(), |x| x.to_string()),
                    levels[u.level]
                )));
            }
            if row.record != u.record {
                return Err(at(format!(
                    "record = {} where the study's order puts {}",
                    row.record, u.record
                )));
            }
            let cell = &mut tally.cells[ci * tally.levels + u.level];
            tally.counts.analyses += 1;
            match &row.result {
                Ok(o) => {
                    let (ot, up) = (o.overturned, o.uplifted);
                    let values = [
                        o.theta_max_over_theta_c,
                        o.mu_motion,
                        o.mu_impact,
                        o.mu_impact_eq5,
                    ];
                    cell.ok += 1;
                    tally.counts.overturned += ot as u64;
                    tally.counts.uplifted += up as u64;
                    tally.counts.overturned_or_uplifted += (ot || up) as u64;
                    if ot {
                        cell.overturned += 1;
                    } else {
                        cell.strict.add(values);
                    }
                    if ot || up {
                        cell.overturned_or_uplifted += 1;
                    } else {
                        cell.paper.add(values);
                    }
                }
                Err(_) => {
                    cell.failed += 1;
                    tally.counts.failed += 1;
                }
            }
            rows += 1;
        }
        let expected = shard.unit_count(total) * cases.len();
        if rows != expected {
            return Err(table.error_at(
                rows + 1,
                format!("{rows} analyses where the study (shard {shard}) has {expected}"),
            ));
        }
        Ok(tally)
    }

    /// Counts over every analysis read.
    pub fn counts(&self) -> Counts {
        self.counts
    }

    /// The `summary.md` text; with a `reference`, its published values
    /// beside ours and the counts tested against them.
    pub fn markdown(
        &self,
        study: &Study,
        shard: Shard,
        reference: Option<&dyn Reference>,
    ) -> String {
        let mut s = String::new();
        let c = self.counts;
        let _ = writeln!(s, "# Study `{}`\n", study.name);
        if !study.description.is_empty() {
            let _ = writeln!(s, "{}\n", study.description);
        }
        if shard != Shard::WHOLE {
            let _ = writeln!(
                s,
                "**Shard {shard} only**: merge the shards (`rockfrag merge`) for the study's tables.\n"
            );
        }
        let motions = match &study.motions {
            Motions::Synthetic { seed, records, .. } => {
                format!("{records} synthetic records per level (seed {seed})")
            }
            Motions::Files(f) => format!("{} recorded motions per level", f.len()),
        };
        let _ = writeln!(
            s,
            "{} analyses: {} overturned, {} uplifted, {} overturned or uplifted, {} failed. {motions}.\n",
            c.analyses, c.overturned, c.uplifted, c.overturned_or_uplifted, c.failed
        );
        if let Some(u) = &study.uncertainty {
            let _ = writeln!(s, "{}\n", uncertainty_text(u));
        }
        let _ = writeln!(
            s,
            "Conventions. *Strict*: a run overturned when |θ| reached π/2. *Paper*: a run that \
             lifted off from rock (N = 0) also counts as overturned, as in the paper, whose \
             program stopped there. Means are over the runs that did not overturn in the \
             table's convention (a run that never left rest counts with θmax/θc = μ = 0); \
             failed analyses are left out.\n"
        );
        if let Some(r) = reference {
            let _ = writeln!(s, "{}\n", r.intro());
        }
        let _ = writeln!(
            s,
            "Friction at impacts: μ_imp is the largest |P_t/P_n| of a run's impacts (the \
             friction that keeps the striking corner from slipping); μ_imp eq. (5) is the \
             paper's eq. (5), repaired (see `solver::eq5_mu`), largest over the run. The two \
             differ only where the sticking impulse would pull (P_n ≤ 0). The paper's μ_imp \
             stands beside ours of eq. (5): its e = 0 rows are eq. (8) and agree; its values of \
             3–9,550 at e > 0 are not reproduced by eq. (5) evaluated on our impacts.\n"
        );
        s.push_str(&self.statistics(study, reference));
        let (level_name, level_unit) = match study.intensity {
            Intensity::Pga(_) => ("A_g", "g"),
            Intensity::Pgv(_) => ("PGV", "m/s"),
            Intensity::Scale(_) => ("scale", "×"),
        };
        let any_failed = c.failed > 0;
        let cases = plan::cases(study);
        for &friction in &study.frictions {
            let _ = writeln!(s, "## Friction: {}\n", friction_label(friction));
            for &width in &study.widths {
                for &aspect in &study.aspects {
                    let _ = writeln!(s, "### H/B = {}, 2B = {} m\n", aspect.text(), width.text());
                    for strict in [true, false] {
                        let _ = writeln!(
                            s,
                            "{}\n",
                            if strict {
                                "Strict convention (overturned):"
                            } else {
                                "Paper's convention (overturned or uplifted):"
                            }
                        );
                        let mut head = format!("| e | {level_name} ({level_unit}) | runs |");
                        if any_failed {
                            head.push_str(" failed |");
                        }
                        let names = ["# OT", "θmax/θc", "μ_mot", "μ_imp", "μ_imp eq. (5)"];
                        for n in names {
                            let _ = write!(head, " {n} |");
                        }
                        // The published values are in the paper's own
                        // convention, under the friction model they are for.
                        let compared = reference.filter(|r| r.friction() == friction);
                        // Fisher's test of the count against the published one.
                        let fisher = compared.is_some() && !strict;
                        if fisher {
                            head.push_str(" p (Fisher) |");
                        }
                        let _ = writeln!(s, "{head}");
                        let cols = 3 + any_failed as usize + names.len() + fisher as usize;
                        let _ = writeln!(s, "|{}", "---|".repeat(cols));
                        for &e in &study.restitutions {
                            let case = Case {
                                aspect,
                                width,
                                restitution: e,
                                friction,
                            };
                            let ci = cases
                                .iter()
                                .position(|c| *c == case)
                                .expect("every case exists");
                            for (li, &level) in study.intensity.levels().iter().enumerate() {
                                let cell = &self.cells[ci * self.levels + li];
                                let (ot, means) = if strict {
                                    (cell.overturned, cell.strict.get())
                                } else {
                                    (cell.overturned_or_uplifted, cell.paper.get())
                                };
                                // Beside each value of every table: the
                                // reference published one set.
                                let published = reference.map(|r| r.cell(&case, level));
                                let mut line = format!("| {} | {level} | {} |", e.text(), cell.ok);
                                if any_failed {
                                    let _ = write!(line, " {} |", cell.failed);
                                }
                                let ours_ot = ot.to_string();
                                let theirs_ot = published.map(|p| {
                                    p.map_or("n/a".to_string(), |r| r.overturned.to_string())
                                });
                                let _ = write!(line, " {} |", beside(&ours_ot, theirs_ot));
                                for k in 0..4 {
                                    let ours = means.map_or("-".to_string(), |m| sig3(m[k]));
                                    let theirs = published.map(|p| match p {
                                        None => "n/a".to_string(),
                                        Some(r) => r.means[k].map_or("-".to_string(), sig3),
                                    });
                                    // A column the reference has no values for
                                    // shows ours alone.
                                    let theirs =
                                        theirs.filter(|_| reference.is_some_and(|r| r.has_mean(k)));
                                    let _ = write!(line, " {} |", beside(&ours, theirs));
                                }
                                if fisher {
                                    let p = published
                                        .flatten()
                                        .map(|r| fisher_exact(ot, cell.ok, r.overturned, r.runs));
                                    let _ = write!(line, " {} |", p.map_or("n/a".into(), p_mark));
                                }
                                let _ = writeln!(s, "{line}");
                            }
                        }
                        s.push('\n');
                    }
                }
            }
        }
        s
    }
}

/// Published results a study is compared with, cell by cell, in the
/// paper's convention (overturned or uplifted): counts out of a number of
/// runs per cell and means over the runs that did not overturn. The paper
/// layer has one for the seed paper's Tables 1–3.
pub trait Reference {
    /// The paragraph that introduces the published values.
    fn intro(&self) -> String;
    /// The friction model the published values are for.
    fn friction(&self) -> Param<Friction>;
    /// Runs per published cell.
    fn runs(&self) -> u64;
    /// The published cell of `case` at intensity `level`, `None` when
    /// there is none (then `n/a`, and no runs overturned in the group
    /// totals: a cell left out of a table had none).
    fn cell(&self, case: &Case, level: f64) -> Option<ReferenceCell>;
    /// Whether the reference has values of mean `k` (θmax/θc, μ_mot,
    /// μ_imp, μ_imp eq. (5)).
    fn has_mean(&self, k: usize) -> bool;
}

/// One published cell of a [`Reference`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferenceCell {
    /// Runs that overturned (or lifted off).
    pub overturned: u64,
    /// Runs in the cell.
    pub runs: u64,
    /// Means over the runs that did not overturn: θmax/θc, μ_mot, μ_imp,
    /// μ_imp eq. (5) (`None`: not published, or every run overturned).
    pub means: [Option<f64>; 4],
}

/// A p-value (see [`p_text`]), in bold with `*` below 0.05.
fn p_mark(p: f64) -> String {
    let text = p_text(p);
    if p < 0.05 {
        format!("**{text}\\***")
    } else {
        text
    }
}

impl Tally {
    /// Counts in the paper's convention over every level of the cases
    /// `keep` accepts: (overturned or uplifted, runs).
    fn pooled(&self, cases: &[Case], keep: impl Fn(&Case) -> bool) -> (u64, u64) {
        let (mut k, mut n) = (0, 0);
        for (ci, case) in cases.iter().enumerate() {
            if !keep(case) {
                continue;
            }
            for li in 0..self.levels {
                let cell = &self.cells[ci * self.levels + li];
                k += cell.overturned_or_uplifted;
                n += cell.ok;
            }
        }
        (k, n)
    }

    /// The `## Statistics` section: totals per e and per H/B, the trend
    /// over e (Cochran–Armitage), and with a reference the same for its
    /// counts and how many cells differ from them at 5 %.
    fn statistics(&self, study: &Study, reference: Option<&dyn Reference>) -> String {
        let mut s = String::new();
        let cases = plan::cases(study);
        let levels = study.intensity.levels();
        let _ = writeln!(
            s,
            "## Statistics (paper's convention: overturned or uplifted)\n"
        );
        for &friction in &study.frictions {
            let compare = reference.filter(|r| r.friction() == friction);
            let _ = writeln!(s, "### Friction: {}\n", friction_label(friction));
            // The reference's count over the study's cells `keep` accepts.
            let published = |r: &dyn Reference, keep: &dyn Fn(&Case) -> bool| -> u64 {
                cases
                    .iter()
                    .filter(|c| c.friction == friction && keep(c))
                    .flat_map(|c| levels.iter().filter_map(|&l| r.cell(c, l)))
                    .map(|cell| cell.overturned)
                    .sum()
            };
            let _ = writeln!(
                s,
                "| group | overturned / runs |{}",
                if compare.is_some() { " paper's |" } else { "" }
            );
            let _ = writeln!(
                s,
                "|---|---|{}",
                if compare.is_some() { "---|" } else { "" }
            );
            let mut per_e = Vec::new();
            for &e in &study.restitutions {
                let keep = |c: &Case| c.restitution == e;
                let (k, n) = self.pooled(&cases, |c| keep(c) && c.friction == friction);
                let theirs = compare.map_or(0, |r| published(r, &keep));
                per_e.push((k, n, theirs));
                let runs = |r: &dyn Reference| {
                    (study.aspects.len() * study.widths.len() * levels.len()) as u64 * r.runs()
                };
                let _ = writeln!(
                    s,
                    "| e = {} | {k} / {n} |{}",
                    e.text(),
                    compare.map_or(String::new(), |r| format!(" {theirs} / {} |", runs(r)))
                );
            }
            for &aspect in &study.aspects {
                let keep = |c: &Case| c.aspect == aspect;
                let (k, n) = self.pooled(&cases, |c| keep(c) && c.friction == friction);
                let runs = |r: &dyn Reference| {
                    (study.restitutions.len() * study.widths.len() * levels.len()) as u64 * r.runs()
                };
                let _ = writeln!(
                    s,
                    "| H/B = {} | {k} / {n} |{}",
                    aspect.text(),
                    compare.map_or(String::new(), |r| format!(
                        " {} / {} |",
                        published(r, &keep),
                        runs(r)
                    ))
                );
            }
            s.push('\n');
            // No trend over a drawn e.
            let scores: Option<Vec<f64>> = study.restitutions.iter().map(|e| e.fixed()).collect();
            let ours = scores.as_ref().and_then(|scores| {
                cochran_armitage(
                    &per_e.iter().map(|p| p.0).collect::<Vec<_>>(),
                    &per_e.iter().map(|p| p.1).collect::<Vec<_>>(),
                    scores,
                )
            });
            let trend = |t: Option<Trend>| match t {
                Some(t) => format!(
                    "Z = {:.2}, two-sided p = {}, slope {:+.3} per unit e",
                    t.z,
                    p_mark(t.p),
                    t.slope
                ),
                None => "undefined (one e, or no variation)".to_string(),
            };
            let _ = writeln!(
                s,
                "Trend of overturning over e (Cochran–Armitage, counts pooled over H/B and {}): \
                 ours {}.",
                if matches!(study.intensity, Intensity::Pga(_)) {
                    "A_g"
                } else {
                    "PGV"
                },
                trend(ours)
            );
            if let Some(r) = compare {
                // The reference's runs per e: every cell of the study's grid
                // counts its runs (a cell it left out had none overturned).
                let n_ref =
                    (study.aspects.len() * study.widths.len() * levels.len()) as u64 * r.runs();
                let theirs = scores.as_ref().and_then(|scores| {
                    cochran_armitage(
                        &per_e.iter().map(|p| p.2).collect::<Vec<_>>(),
                        &vec![n_ref; per_e.len()],
                        scores,
                    )
                });
                let _ = writeln!(s, "The paper's: {}.", trend(theirs));
                let (mut differ, mut tested) = (0, 0);
                for (ci, case) in cases.iter().enumerate() {
                    if case.friction != friction {
                        continue;
                    }
                    for (li, &level) in levels.iter().enumerate() {
                        if let Some(published) = r.cell(case, level) {
                            let cell = &self.cells[ci * self.levels + li];
                            tested += 1;
                            let p = fisher_exact(
                                cell.overturned_or_uplifted,
                                cell.ok,
                                published.overturned,
                                published.runs,
                            );
                            differ += (p < 0.05) as usize;
                        }
                    }
                }
                let _ = writeln!(
                    s,
                    "\n{differ} of the {tested} published cells differ from the paper's count at \
                     5 % (Fisher's exact test, ours against the paper's {} runs, two-sided; \
                     marked \\* in the tables below); about {:.1} would by chance alone.",
                    r.runs(),
                    0.05 * tested as f64
                );
            }
            s.push('\n');
        }
        s
    }
}

fn beside(ours: &str, theirs: Option<String>) -> String {
    match theirs {
        Some(p) => format!("{ours} / {p}"),
        None => ours.to_string(),
    }
}

/// One sentence on what each analysis draws: "Drawn per analysis (seed 7):
/// e ~ uniform(0, 0.9); …; the tables pool the draws (`drawn`)."
fn uncertainty_text(u: &Uncertainty) -> String {
    let parts: Vec<String> = Property::ALL
        .iter()
        .filter_map(|&p| u.get(p).map(|v| (p, v)))
        .map(|(p, v)| {
            let name = match p {
                Property::Width => "2B (m)",
                Property::Aspect => "H/B",
                Property::Restitution => "e",
                Property::MuS => "μs",
                Property::MuKOverMuS => "μk/μs",
            };
            let bounds = |min: Option<f64>, max: Option<f64>| match (min, max) {
                (None, None) => String::new(),
                (lo, hi) => format!(
                    " truncated to [{}, {}]",
                    lo.map_or("−∞".into(), |x| x.to_string()),
                    hi.map_or("∞".into(), |x| x.to_string())
                ),
            };
            match v {
                Value::Fixed(x) => format!("{name} = {x}"),
                Value::Drawn(Distribution::Uniform { min, max }) => {
                    format!("{name} ~ uniform({min}, {max})")
                }
                Value::Drawn(Distribution::Normal { mean, sd, min, max }) => {
                    format!(
                        "{name} ~ normal(mean {mean}, sd {sd}){}",
                        bounds(*min, *max)
                    )
                }
                Value::Drawn(Distribution::Lognormal {
                    median,
                    beta,
                    min,
                    max,
                }) => format!(
                    "{name} ~ lognormal(median {median}, β {beta}){}",
                    bounds(*min, *max)
                ),
            }
        })
        .collect();
    format!(
        "Drawn per analysis (`[uncertainty]`, seed {}): {}. Each case pools its analyses over \
         the draws (`drawn` in the tables); outcomes.csv holds each analysis's own values.",
        u.seed,
        parts.join("; ")
    )
}
