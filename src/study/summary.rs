//! `summary.md`: the paper's tables for a study, computed from `outcomes.csv`.
//!
//! For each friction model, width and aspect ratio, a table in the layout of
//! the paper's Tables 1–3: e, intensity, number of runs that overturned, and
//! over the runs that did not, the mean θmax/θc, μ_mot and μ_imp. Two
//! conventions: **strict** (overturned means |θ| reached π/2) and the
//! **paper's** (a run that lifted off from rock also counts as overturned:
//! the paper's program stopped there). When the study is the paper's
//! (synthetic firm-soil records at the default settings, 25 per level,
//! 2B = 0.5 m, PGA levels), each value has the published one beside it.
//!
//! The summary is always computed by reading `outcomes.csv` back, so a run,
//! a resumed run and a merge of shards give the same bytes.

use super::paper;
use super::plan::{self, Case, Shard};
use crate::detmath as dm;
use crate::error::Result;
use crate::motion::G_STANDARD;
use crate::outcomes_csv::param_text;
use crate::outcomes_csv::{Column, OutcomesReader};
use crate::solver::Friction;
use crate::spec::{Intensity, Motions, Study, Uncertainty, friction_label};
use crate::stats::{Trend, cochran_armitage, fisher_exact, p_text};
use crate::uncertainty::{Distribution, Param, Value};
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
    /// [`OutcomesReader`], checking that its header is the study's, that
    /// every row is the analysis expected at its place (case, level,
    /// record), and the count.
    pub fn read(path: &Path, study: &Study, shard: Shard) -> Result<Tally> {
        let cols = plan::columns(study);
        let (
            mut table,
            [
                c_level,
                c_record,
                c_status,
                c_ot,
                c_up,
                c_theta,
                c_mot,
                c_imp,
                c_eq5,
            ],
        ) = OutcomesReader::open(
            path,
            [
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
        let pooled = study.pooled();
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
        while let Some(row) = table.next_row()? {
            let ci = rows % cases.len();
            if ci == 0 {
                unit = units.next().map(|u| plan::unit(study, u));
            }
            let Some(u) = unit else {
                return Err(row.line_error("more rows than the study has analyses".into()));
            };
            let case = &cases[ci];
            let key = row.case()?.pooled(pooled);
            if key != case.key() {
                return Err(row.line_error(format!(
                    "case {key} where the study's order puts {}",
                    case.key()
                )));
            }
            for (i, want) in [(c_level, levels[u.level]), (c_record, u.record as f64)] {
                if row.number(i)? != want {
                    return Err(row.line_error(format!(
                        "{} = {} where the study's order puts {want}",
                        names[i],
                        row.field(i)
                    )));
                }
            }
            let cell = &mut tally.cells[ci * tally.levels + u.level];
            tally.counts.analyses += 1;
            match row.field(c_status) {
                "ok" => {
                    let (ot, up) = (row.boolean(c_ot)?, row.boolean(c_up)?);
                    let theta = row.number(c_theta)?;
                    let (mot, imp) = (row.number(c_mot)?, row.number(c_imp)?);
                    let values = [theta, mot, imp, row.number(c_eq5)?];
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
                "failed" => {
                    cell.failed += 1;
                    tally.counts.failed += 1;
                }
                _ => return Err(row.error(c_status, "ok or failed")),
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

    /// The `summary.md` text.
    pub fn markdown(&self, study: &Study, shard: Shard) -> String {
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
        let paper = is_papers(study);
        if paper {
            let _ = writeln!(
                s,
                "This is the paper's study: each cell shows ours / the paper's (Shenton and Jones, \
                 Tables 1–3, infinite friction, paper convention); `n/a`: no published value; \
                 `-`: every run overturned.\n"
            );
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
        s.push_str(&self.statistics(study, paper));
        let (level_name, level_unit) = match study.intensity {
            Intensity::Pga(_) => ("A_g", "g"),
            Intensity::Pgv(_) => ("PGV", "m/s"),
            Intensity::Scale(_) => ("scale", "×"),
        };
        let any_failed = c.failed > 0;
        let cases = plan::cases(study);
        for (fi, &friction) in study.frictions.iter().enumerate() {
            let _ = writeln!(s, "## Friction: {}\n", friction_label(friction));
            for (wi, &width) in study.widths.iter().enumerate() {
                for (ai, &aspect) in study.aspects.iter().enumerate() {
                    let _ = writeln!(
                        s,
                        "### H/B = {}, 2B = {} m\n",
                        param_text(aspect),
                        param_text(width)
                    );
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
                        // Fisher's test of the count against the paper's,
                        // in the paper's own convention only.
                        let fisher = paper && !strict && friction == Friction::Infinite;
                        if fisher {
                            head.push_str(" p (Fisher) |");
                        }
                        let _ = writeln!(s, "{head}");
                        let cols = 3 + any_failed as usize + names.len() + fisher as usize;
                        let _ = writeln!(s, "|{}", "---|".repeat(cols));
                        for (ei, &e) in study.restitutions.iter().enumerate() {
                            let ci = cases
                                .iter()
                                .position(|c: &Case| c.index == [ai, wi, ei, fi])
                                .expect("every case exists");
                            for (li, &level) in study.intensity.levels().iter().enumerate() {
                                let cell = &self.cells[ci * self.levels + li];
                                let (ot, means) = if strict {
                                    (cell.overturned, cell.strict.get())
                                } else {
                                    (cell.overturned_or_uplifted, cell.paper.get())
                                };
                                let published = paper.then(|| paper::lookup(aspect, e, level));
                                let mut line =
                                    format!("| {} | {level} | {} |", param_text(e), cell.ok);
                                if any_failed {
                                    let _ = write!(line, " {} |", cell.failed);
                                }
                                let ours_ot = ot.to_string();
                                let paper_ot = published.map(|p| {
                                    p.map_or("n/a".to_string(), |r| r.overturned.to_string())
                                });
                                let _ = write!(line, " {} |", beside(&ours_ot, paper_ot));
                                for k in 0..4 {
                                    let ours = means.map_or("-".to_string(), |m| sig3(m[k]));
                                    // The paper's μ_imp is its eq. (5): it stands
                                    // beside ours of eq. (5), not the impulse ratio.
                                    let theirs = published.filter(|_| k != 2).map(|p| match p {
                                        None => "n/a".to_string(),
                                        Some(r) => [
                                            r.theta_max_over_theta_c,
                                            r.mu_motion,
                                            None,
                                            r.mu_impact,
                                        ][k]
                                            .map_or("-".to_string(), sig3),
                                    });
                                    let _ = write!(line, " {} |", beside(&ours, theirs));
                                }
                                if fisher {
                                    let p = published.flatten().map(|r| {
                                        fisher_exact(ot, cell.ok, r.overturned as u64, RECORDS)
                                    });
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

/// Runs per cell in the paper.
const RECORDS: u64 = paper::RECORDS as u64;

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
    /// Counts in the paper's convention over every level of (aspect index,
    /// e index, friction index): (overturned or uplifted, runs).
    fn pooled(
        &self,
        study: &Study,
        cases: &[Case],
        keep: impl Fn(usize, usize, usize) -> bool,
    ) -> (u64, u64) {
        let (mut k, mut n) = (0, 0);
        for (ci, case) in cases.iter().enumerate() {
            let [ai, _, ei, fi] = case.index;
            if !keep(ai, ei, fi) {
                continue;
            }
            for li in 0..study.intensity.levels().len() {
                let cell = &self.cells[ci * self.levels + li];
                k += cell.overturned_or_uplifted;
                n += cell.ok;
            }
        }
        (k, n)
    }

    /// The `## Statistics` section: totals per e and per H/B, the trend
    /// over e (Cochran–Armitage), and for the paper's study the same for
    /// the paper's counts and how many cells differ from them at 5 %.
    fn statistics(&self, study: &Study, paper: bool) -> String {
        let mut s = String::new();
        let cases = plan::cases(study);
        let _ = writeln!(
            s,
            "## Statistics (paper's convention: overturned or uplifted)\n"
        );
        for (fi, &friction) in study.frictions.iter().enumerate() {
            let compare = paper && friction == Friction::Infinite;
            let _ = writeln!(s, "### Friction: {}\n", friction_label(friction));
            let published = |keep: &dyn Fn(&paper::PaperRow) -> bool| -> u64 {
                paper::TABLES
                    .iter()
                    .filter(|r| study.aspects.contains(&r.aspect))
                    .filter(|r| study.restitutions.contains(&r.restitution))
                    .filter(|r| study.intensity.levels().contains(&r.pga))
                    .filter(|r| keep(r))
                    .map(|r| r.overturned as u64)
                    .sum()
            };
            let _ = writeln!(
                s,
                "| group | overturned / runs |{}",
                if compare { " paper's |" } else { "" }
            );
            let _ = writeln!(s, "|---|---|{}", if compare { "---|" } else { "" });
            let mut per_e = Vec::new();
            for (ei, &e) in study.restitutions.iter().enumerate() {
                let (k, n) = self.pooled(study, &cases, |_, e2, f2| e2 == ei && f2 == fi);
                per_e.push((k, n, published(&|r| r.restitution == e)));
                let theirs = per_e.last().expect("pushed").2;
                let _ = writeln!(
                    s,
                    "| e = {} | {k} / {n} |{}",
                    param_text(e),
                    if compare {
                        format!(" {theirs} / {} |", 300 * study.aspects.len() / 3)
                    } else {
                        String::new()
                    }
                );
            }
            for (ai, &aspect) in study.aspects.iter().enumerate() {
                let (k, n) = self.pooled(study, &cases, |a2, _, f2| a2 == ai && f2 == fi);
                let theirs = published(&|r| r.aspect == aspect);
                let runs =
                    (study.restitutions.len() * study.intensity.levels().len()) as u64 * RECORDS;
                let _ = writeln!(
                    s,
                    "| H/B = {} | {k} / {n} |{}",
                    param_text(aspect),
                    if compare {
                        format!(" {theirs} / {runs} |")
                    } else {
                        String::new()
                    }
                );
            }
            s.push('\n');
            let scores = &study.restitutions;
            let ours = cochran_armitage(
                &per_e.iter().map(|p| p.0).collect::<Vec<_>>(),
                &per_e.iter().map(|p| p.1).collect::<Vec<_>>(),
                scores,
            );
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
            if compare {
                // The paper's runs per e: 25 per published cell; H/B = 2 at
                // 0.3 g had no rocking, so its 25 runs count with none overturned.
                let n_paper =
                    (study.aspects.len() * study.intensity.levels().len()) as u64 * RECORDS;
                let theirs = cochran_armitage(
                    &per_e.iter().map(|p| p.2).collect::<Vec<_>>(),
                    &vec![n_paper; per_e.len()],
                    scores,
                );
                let _ = writeln!(s, "The paper's: {}.", trend(theirs));
                let (mut differ, mut tested) = (0, 0);
                for (ci, case) in cases.iter().enumerate() {
                    if case.index[3] != fi {
                        continue;
                    }
                    for (li, &level) in study.intensity.levels().iter().enumerate() {
                        if let Some(r) = paper::lookup(case.aspect, case.restitution, level) {
                            let cell = &self.cells[ci * self.levels + li];
                            tested += 1;
                            let p = fisher_exact(
                                cell.overturned_or_uplifted,
                                cell.ok,
                                r.overturned as u64,
                                RECORDS,
                            );
                            differ += (p < 0.05) as usize;
                        }
                    }
                }
                let _ = writeln!(
                    s,
                    "\n{differ} of the {tested} published cells differ from the paper's count at \
                     5 % (Fisher's exact test, ours against the paper's 25 runs, two-sided; \
                     marked \\* in the tables below); about {:.1} would by chance alone.",
                    0.05 * tested as f64
                );
            }
            s.push('\n');
        }
        s
    }
}

fn beside(ours: &str, paper: Option<String>) -> String {
    match paper {
        Some(p) => format!("{ours} / {p}"),
        None => ours.to_string(),
    }
}

/// Whether `study` is the paper's set-up, cell for cell comparable with
/// Tables 1–3 (its grids may be a subset of the paper's; its records follow
/// one of the readings of section 4, [`crate::reproduce::readings`]).
pub fn is_papers(study: &Study) -> bool {
    let synthetic_default = match &study.motions {
        Motions::Synthetic {
            settings, records, ..
        } => {
            paper::readings().iter().any(|r| r.settings == *settings) && *records == paper::RECORDS
        }
        Motions::Files(_) => false,
    };
    synthetic_default
        && study.g == G_STANDARD
        && matches!(study.intensity, Intensity::Pga(_))
        && study.widths == [paper::WIDTH]
        && study.frictions.contains(&Friction::Infinite)
        && study.aspects.iter().all(|a| [2.0, 4.0, 6.0].contains(a))
}

/// Three significant figures, as in the paper's tables; below 10⁻⁴ in
/// scientific notation (`3.42e-41`, a graze), not forty zeros.
pub fn sig3(x: f64) -> String {
    if !x.is_finite() {
        return x.to_string();
    }
    if x == 0.0 {
        return "0".to_string();
    }
    if x.abs() < 1e-4 {
        return format!("{x:.2e}");
    }
    let mag = dm::log10(x.abs()).floor() as i32;
    let decimals = (2 - mag).max(0) as usize;
    format!("{x:.decimals$}")
}

/// One sentence on what each analysis draws: "Drawn per analysis (seed 7):
/// e ~ uniform(0, 0.9); …; the tables pool the draws (`drawn`)."
fn uncertainty_text(u: &Uncertainty) -> String {
    let parts: Vec<String> = Param::ALL
        .iter()
        .filter_map(|&p| u.get(p).map(|v| (p, v)))
        .map(|(p, v)| {
            let name = match p {
                Param::Width => "2B (m)",
                Param::Aspect => "H/B",
                Param::Restitution => "e",
                Param::MuS => "μs",
                Param::MuKOverMuS => "μk/μs",
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Three significant figures; a graze's 3.4e-41 in scientific notation.
    #[test]
    fn sig3_keeps_three_figures_and_small_numbers_short() {
        assert_eq!(sig3(0.148_3), "0.148");
        assert_eq!(sig3(12.345), "12.3");
        assert_eq!(sig3(0.000_123_4), "0.000123");
        assert_eq!(sig3(3.42e-41), "3.42e-41");
        assert_eq!(sig3(0.0), "0");
    }

    #[test]
    fn three_significant_figures() {
        assert_eq!(sig3(0.0155), "0.0155");
        assert_eq!(sig3(0.5244), "0.524");
        assert_eq!(sig3(5480.2), "5480");
        assert_eq!(sig3(14.93), "14.9");
        assert_eq!(sig3(0.0), "0");
    }
}
