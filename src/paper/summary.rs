//! The paper's tables in `summary.md`: the study's results in the layout of
//! Shenton and Jones's Tables 1–3, the published values beside ours, and the
//! statistics that compare them (Fisher's exact test per cell, the
//! Cochran–Armitage trend over e).

use std::fmt::Write;

use super::tables;
use crate::case::{Case, Param};
use crate::im::Im;
use crate::io_util::sig3;
use crate::solver::Friction;
use crate::spec::{Intensity, Study, friction_label};
use crate::stats::{Trend, cochran_armitage, fisher_exact, p_text};
use crate::study::Tally;

/// The paper's section of `summary.md`: for each friction model, width and
/// aspect ratio, a table in the layout of the paper's Tables 1–3 (e,
/// intensity, runs that overturned, and over the runs that did not, the mean
/// θmax/θc, μ_mot and μ_imp) in two conventions, **strict** (overturned
/// means |θ| reached π/2) and the **paper's** (a run that lifted off from
/// rock also counts: its program stopped there), with the published value
/// beside ours in every cell and Fisher's test of each count; and the
/// statistics: totals per e and H/B, the trend over e (Cochran–Armitage),
/// the paper's beside ours.
pub(crate) fn tables_section(tally: &Tally, study: &Study) -> String {
    let mut s = String::from("## The paper's Tables 1–3\n\n");
    let c = tally.counts();
    let _ = writeln!(
        s,
        "Conventions. *Strict*: a run overturned when |θ| reached π/2. *Paper*: a run that \
         lifted off from rock (N = 0) also counts as overturned, as in the paper, whose \
         program stopped there. Means are over the runs that did not overturn in the \
         table's convention (a run that never left rest counts with θmax/θc = μ = 0); \
         failed analyses are left out.\n"
    );
    let _ = writeln!(s, "{}\n", PaperTables.intro());
    let _ = writeln!(
        s,
        "Friction at impacts: μ_imp is the largest |P_t/P_n| of a run's impacts (the \
         friction that keeps the striking corner from slipping); μ_imp eq. (5) is the \
         paper's eq. (5), repaired (see `solver::eq5_mu`), largest over the run. The two \
         differ only where the sticking impulse would pull (P_n ≤ 0). The paper's μ_imp \
         stands beside ours of eq. (5): its e = 0 rows are eq. (8) and agree; its values of \
         3–9,550 at e > 0 are not reproduced by eq. (5) evaluated on our impacts.\n"
    );
    s.push_str(&statistics(tally, study));
    let (level_name, level_unit) = match study.intensity {
        Intensity::Pga(_) => ("A_g".to_string(), "g"),
        Intensity::Pgv(_) => (Im::PGV.short(), Im::PGV.unit()),
        Intensity::Scale(_) => ("scale".to_string(), "×"),
    };
    let any_failed = c.failed > 0;
    let cases = crate::study::plan::cases(study);
    for &friction in &study.frictions {
        let _ = writeln!(s, "### Friction: {}\n", friction_label(friction));
        for &width in &study.widths {
            for &aspect in &study.aspects {
                let _ = writeln!(s, "#### H/B = {}, 2B = {} m\n", aspect.text(), width.text());
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
                    let compared = (PaperTables.friction() == friction).then_some(&PaperTables);
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
                            stack: None,
                        };
                        let ci = cases
                            .iter()
                            .position(|c| *c == case)
                            .expect("every case exists");
                        for (li, &level) in study.intensity.levels().iter().enumerate() {
                            let cell = &tally.cells[ci * tally.levels + li];
                            let (ot, means) = if strict {
                                (cell.overturned, cell.strict.get())
                            } else {
                                (cell.overturned_or_uplifted, cell.paper.get())
                            };
                            // Beside each value of every table: the
                            // reference published one set.
                            let published = Some(PaperTables.cell(&case, level));
                            let mut line = format!("| {} | {level} | {} |", e.text(), cell.ok);
                            if any_failed {
                                let _ = write!(line, " {} |", cell.failed);
                            }
                            let ours_ot = ot.to_string();
                            let theirs_ot = published
                                .map(|p| p.map_or("n/a".to_string(), |r| r.overturned.to_string()));
                            let _ = write!(line, " {} |", beside(&ours_ot, theirs_ot));
                            for k in 0..4 {
                                let ours = means.map_or("-".to_string(), |m| sig3(m[k]));
                                let theirs = published.map(|p| match p {
                                    None => "n/a".to_string(),
                                    Some(r) => r.means[k].map_or("-".to_string(), sig3),
                                });
                                // A column the reference has no values for
                                // shows ours alone.
                                let theirs = theirs.filter(|_| PaperTables.has_mean(k));
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

/// A p-value (see [`p_text`]), in bold with `*` below 0.05.
fn p_mark(p: f64) -> String {
    let text = p_text(p);
    if p < 0.05 {
        format!("**{text}\\***")
    } else {
        text
    }
}

/// Counts in the paper's convention over every level of the cases `keep`
/// accepts: (overturned or uplifted, runs).
fn pooled(tally: &Tally, cases: &[Case], keep: impl Fn(&Case) -> bool) -> (u64, u64) {
    let (mut k, mut n) = (0, 0);
    for (ci, case) in cases.iter().enumerate() {
        if !keep(case) {
            continue;
        }
        for li in 0..tally.levels {
            let cell = &tally.cells[ci * tally.levels + li];
            k += cell.overturned_or_uplifted;
            n += cell.ok;
        }
    }
    (k, n)
}

/// The statistics: totals per e and per H/B, the trend over e
/// (Cochran–Armitage), the same for the paper's counts and how many cells
/// differ from them at 5 %.
fn statistics(tally: &Tally, study: &Study) -> String {
    let mut s = String::new();
    let cases = crate::study::plan::cases(study);
    let levels = study.intensity.levels();
    let _ = writeln!(
        s,
        "### Statistics (paper's convention: overturned or uplifted)\n"
    );
    for &friction in &study.frictions {
        let compare = (PaperTables.friction() == friction).then_some(&PaperTables);
        let _ = writeln!(s, "#### Friction: {}\n", friction_label(friction));
        // The reference's count over the study's cells `keep` accepts.
        let published = |r: &PaperTables, keep: &dyn Fn(&Case) -> bool| -> u64 {
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
            let (k, n) = pooled(tally, &cases, |c| keep(c) && c.friction == friction);
            let theirs = compare.map_or(0, |r| published(r, &keep));
            per_e.push((k, n, theirs));
            let runs = |r: &PaperTables| {
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
            let (k, n) = pooled(tally, &cases, |c| keep(c) && c.friction == friction);
            let runs = |r: &PaperTables| {
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
                "A_g".to_string()
            } else {
                Im::PGV.short()
            },
            trend(ours)
        );
        if let Some(r) = compare {
            // The reference's runs per e: every cell of the study's grid
            // counts its runs (a cell it left out had none overturned).
            let n_ref = (study.aspects.len() * study.widths.len() * levels.len()) as u64 * r.runs();
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
                        let cell = &tally.cells[ci * tally.levels + li];
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

fn beside(ours: &str, theirs: Option<String>) -> String {
    match theirs {
        Some(p) => format!("{ours} / {p}"),
        None => ours.to_string(),
    }
}

/// The paper's Tables 1–3 as cells: counts of 25 runs per cell in the
/// paper's convention, and the means of θmax/θc, μ_mot and (beside ours of
/// eq. (5)) μ_imp.
pub(crate) struct PaperTables;

/// One published cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PaperCell {
    /// Runs that overturned (or lifted off).
    pub overturned: u64,
    /// Runs in the cell.
    pub runs: u64,
    /// Means over the runs that did not overturn: θmax/θc, μ_mot, μ_imp,
    /// μ_imp eq. (5) (`None`: not published, or every run overturned).
    pub means: [Option<f64>; 4],
}

impl PaperTables {
    /// The paragraph that introduces the published values.
    fn intro(&self) -> String {
        "This is the paper's study: each cell shows ours / the paper's (Shenton and Jones, \
         Tables 1–3, infinite friction, paper convention); `n/a`: no published value; \
         `-`: every run overturned."
            .to_string()
    }

    /// The friction model the published values are for.
    fn friction(&self) -> Param<Friction> {
        Param::Fixed(Friction::Infinite)
    }

    /// Runs per published cell.
    fn runs(&self) -> u64 {
        tables::RECORDS as u64
    }

    /// The published cell of `case` at `level` (g), if any.
    fn cell(&self, case: &Case, level: f64) -> Option<PaperCell> {
        let (aspect, e) = (case.aspect.fixed()?, case.restitution.fixed()?);
        tables::lookup(aspect, e, level).map(|r| PaperCell {
            overturned: u64::from(r.overturned),
            runs: tables::RECORDS as u64,
            // The paper's μ_imp is its eq. (5): it stands beside ours of
            // eq. (5), not beside the impulse ratio.
            means: [r.theta_max_over_theta_c, r.mu_motion, None, r.mu_impact],
        })
    }

    /// Whether the tables have values of mean `k` (θmax/θc, μ_mot, μ_imp,
    /// μ_imp eq. (5)).
    fn has_mean(&self, k: usize) -> bool {
        k != 2
    }
}
