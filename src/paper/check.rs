//! Reproducing the seed paper: its study (infinite friction, 25 records per
//! cell) run over K ensembles under each candidate reading of its section 4,
//! and scored against its Tables 1–3 (`rockfrag paper`, `paper-check.md`).
//!
//! Section 4 says the records used "frequency increments Δω = 0.05 Hz
//! distributed over the range 0.05 – 25 Hz". The symbol is ω, so the grid
//! may have been in rad/s. The readings compared ([`readings`]):
//!
//! - **as written**: Δf = 0.05 Hz, 0.05–25 Hz;
//! - **rad/s band**: the band 0.05–25 rad/s (0.05–3.98 Hz), Δf = 0.05 Hz;
//! - **rad/s grid**: the whole grid in rad/s, Δω = 0.05 rad/s over
//!   0.05–25 rad/s (Δf ≈ 0.00796 Hz, 0.008–3.98 Hz; Δf is rounded by
//!   3·10⁻⁵ so that 1/(Δf·Δt) is an integer, as the FFT synthesis needs).
//!
//! The PSD's parameters stay in Hz in every reading (eq. 6 is written in f).
//! The rad/s grid is also run with `[solver] rock_impact = "rock"`, the rule
//! that reproduces the paper's fall of overturning with e ([`candidates`]).
//!
//! Every count uses the paper's convention (a run that lifted off from rock
//! counts as overturned: its program stopped there), and every mean is over
//! the runs that did not overturn in that convention. The scores, per reading:
//!
//! - the e = 0 total (paper: 159 of 300) and the totals per e, mean and
//!   standard deviation over the K ensembles;
//! - the cells that differ from the paper's at 5 % (Fisher's exact test,
//!   25 runs against 25, [`crate::stats::fisher_exact`]), averaged over the
//!   ensembles;
//! - the binomial log-likelihood of the paper's 44 counts, Σ ln P(kᵢ | 25,
//!   p̂ᵢ), with a p-value from the ensembles themselves: for each ensemble j,
//!   p̂ is estimated from the other K − 1 (leave-one-out, (k + ½)/(n + 1)),
//!   and the paper's table is ranked among the K simulated tables scored
//!   the same way, p = (1 + #{LLⱼ ≤ LL_paper})/(K + 1). This keeps the
//!   correlation between cells (the same 25 records drive every cell of an
//!   ensemble), which a test assuming independent cells would not;
//! - near-threshold mean θmax/θc (H/B 2 at 0.6 g, H/B 4 and 6 at 0.3 g),
//!   pooled over the ensembles, against the paper's;
//! - the Cochran–Armitage trend of the counts over e, pooled over H/B and
//!   A_g ([`crate::stats::cochran_armitage`]).

use std::fmt::Write;

use super::tables::{self as paper, PaperRow, Reading, readings};
use crate::case::{CaseValues, Param, Scene};
use crate::error::{Error, Result};
use crate::io_util::sig3;
use crate::motion::Record;
use crate::motion::SynthesisSettings;
use crate::outcome::Outcome;
use crate::solver::{Friction, RockImpact};
use crate::spec::{Motions, Study};
use crate::stats::{binomial_log_likelihood, cochran_armitage, fisher_exact, p_text};
use crate::study::{Source, Unit, ensemble, plan};

/// Options of [`check`].
#[derive(Clone, Debug)]
pub struct CheckOptions {
    /// Ensembles per reading (seeds `seed`, `seed` + 1, …).
    pub replicates: usize,
    /// The first ensemble's seed (default: the built-in study's, 1991).
    pub seed: u64,
    /// Worker threads (0: one per core).
    pub threads: usize,
}

impl Default for CheckOptions {
    fn default() -> Self {
        CheckOptions {
            replicates: 12,
            seed: match Study::shenton_jones().motions {
                Motions::Synthetic { seed, .. } => seed,
                Motions::Files(_) | Motions::Pairs { .. } => {
                    unreachable!("the built-in study is synthetic")
                }
            },
            threads: 0,
        }
    }
}

/// The paper's grid: H/B, e and A_g, in its tables' order.
const ASPECTS: [f64; 3] = [2.0, 4.0, 6.0];
pub(crate) const RESTITUTIONS: [f64; 4] = [0.0, 0.3, 0.6, 0.9];
const PGAS: [f64; 4] = [0.3, 0.6, 0.9, 1.2];
/// Number of (H/B, e, A_g) cells.
const CELLS: usize = 48;

fn cell_index(ai: usize, ei: usize, li: usize) -> usize {
    (ai * RESTITUTIONS.len() + ei) * PGAS.len() + li
}

/// The index into [`RESTITUTIONS`] of cell `ci` (see [`cell_index`]).
pub(crate) fn cell_restitution(ci: usize) -> usize {
    (ci / PGAS.len()) % RESTITUTIONS.len()
}

/// One (H/B, e, A_g) cell of one ensemble, in the paper's convention.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cell {
    /// Runs (25).
    pub runs: u32,
    /// Runs that overturned or lifted off from rock.
    pub overturned: u32,
    /// Sum of θmax/θc over the other runs.
    pub theta_sum: f64,
}

/// The outcome of one reading: `ensembles[j][cell]`.
#[derive(Clone, Debug)]
pub struct ReadingResult {
    /// The reading.
    pub reading: Reading,
    /// The rock-impact rule the ensembles were solved with.
    pub rock_impact: RockImpact,
    /// The seeds of the ensembles, in order.
    pub seeds: Vec<u64>,
    /// Cells of each ensemble, indexed H/B-major, then e, then A_g.
    pub ensembles: Vec<[Cell; CELLS]>,
}

/// Runs the paper's study, infinite friction only, for every reading and
/// `options.replicates` ensembles; `progress` is called after each ensemble.
pub fn check(options: &CheckOptions, mut progress: impl FnMut(&str)) -> Result<Vec<ReadingResult>> {
    if options.replicates < 2 {
        return Err(Error::invalid(
            "replicates",
            options.replicates,
            "at least 2 (the p-values compare ensembles with each other)",
        ));
    }
    let (pool, _) = crate::threads::pool(options.threads)?;
    let mut out = Vec::new();
    for (reading, rock_impact) in candidates() {
        let mut result = ReadingResult {
            reading: reading.clone(),
            rock_impact,
            seeds: Vec::new(),
            ensembles: Vec::new(),
        };
        for r in 0..options.replicates {
            let seed = options.seed + r as u64;
            let mut study = paper_study(&reading.settings, seed);
            study.solver.rock_impact = rock_impact;
            let cells = pool.install(|| run_ensemble(&study))?;
            result.seeds.push(seed);
            result.ensembles.push(cells);
            progress(&format!(
                "{}: ensemble {}/{} (seed {seed})",
                reading.name,
                r + 1,
                options.replicates
            ));
        }
        out.push(result);
    }
    Ok(out)
}

/// What [`check`] runs: every reading with the physics (`rock_impact =
/// "bounce"`), and the rad/s grid once more with the rule that reproduces
/// the paper's fall of overturning with e (`rock_impact = "rock"`, not
/// physics: see [`RockImpact::Rock`]).
pub fn candidates() -> Vec<(Reading, RockImpact)> {
    let mut v: Vec<(Reading, RockImpact)> = readings()
        .into_iter()
        .map(|r| (r, RockImpact::Bounce))
        .collect();
    let grid = v[2].0.clone();
    v.push((
        Reading {
            name: "rad/s grid, rock rule",
            meaning: "the rad/s grid, solved with [solver] rock_impact = \"rock\"",
            ..grid
        },
        RockImpact::Rock,
    ));
    v
}

/// The built-in study with `settings` and `seed`, infinite friction only.
fn paper_study(settings: &SynthesisSettings, seed: u64) -> Study {
    let mut study = Study::shenton_jones();
    study.motions = Motions::Synthetic {
        settings: settings.clone(),
        seed,
        records: paper::RECORDS,
        pairs: None,
    };
    study.frictions = vec![Param::Fixed(Friction::Infinite)];
    study.aspects = ASPECTS.map(Param::Fixed).to_vec();
    study.restitutions = RESTITUTIONS.map(Param::Fixed).to_vec();
    study.widths = vec![Param::Fixed(paper::WIDTH)];
    study.intensity = crate::spec::Intensity::Pga(PGAS.to_vec());
    study
}

/// Every analysis of `study` (a study of blocks), solved through the
/// ensemble primitive ([`ensemble`]): `each` of its (unit, case number, own
/// values, outcome), in canonical order (unit-major, then case), so that
/// what is summed from them does not depend on the threads. The paper's
/// check and its `e_trend` figure run their ensembles here.
///
/// Errors: a record that cannot be made, a case that is a stack or makes
/// no valid block, or an analysis the solver does not finish.
pub(crate) fn solve_study<T, F>(study: &Study, each: F) -> Result<Vec<T>>
where
    T: Send,
    F: Fn(&Unit, usize, &CaseValues, &Outcome) -> T + Sync + Send,
{
    let cases = plan::cases(study);
    let mut source = Source::new(study)?;
    let units: Vec<Unit> = (0..plan::unit_count(study))
        .map(|u| plan::unit(study, u))
        .collect();
    // each member filtered once, then scaled to every level
    source.prepare(study, &(0..units.len()).collect::<Vec<_>>());
    let levels = study.intensity.levels();
    let mut out = Vec::with_capacity(units.len() * cases.len());
    // a chunk of units at a time: its records, then its analyses (the
    // records of a whole study need not be held at once)
    for units in units.chunks(UNITS_AT_ONCE) {
        let records = ensemble::motions(&source, units, |src, unit| {
            src.record(&study.intensity, levels[unit.level], unit.record, study.g)
        });
        let records = records.into_iter().collect::<Result<Vec<Record>>>()?;
        let jobs: Vec<(usize, usize)> = (0..units.len())
            .flat_map(|u| (0..cases.len()).map(move |c| (u, c)))
            .collect();
        let solved = ensemble::analyses(&jobs, |&(u, number)| -> Result<T> {
            let unit = &units[u];
            let (own, scene) = plan::analysis(study, &cases[number], number, unit);
            let scene = Scene::Block(scene?.into_block()?);
            let o = ensemble::solve(&scene, &records[u], &study.solver, None).map_err(|why| {
                Error::invalid(
                    "analysis",
                    format!(
                        "{own} on record {} at {} g: {why}",
                        unit.record, levels[unit.level]
                    ),
                    "one the solver finishes",
                )
            })?;
            Ok(each(unit, number, &own, &o))
        });
        for t in solved {
            out.push(t?);
        }
    }
    Ok(out)
}

/// Units whose records [`solve_study`] holds at once.
const UNITS_AT_ONCE: usize = 16;

fn run_ensemble(study: &Study) -> Result<[Cell; CELLS]> {
    let rows = solve_study(study, |unit, number, _, o| {
        // Cases are aspect-major, then e (one width, one friction).
        let (ai, ei) = (number / RESTITUTIONS.len(), number % RESTITUTIONS.len());
        (
            cell_index(ai, ei, unit.level),
            o.overturned || o.uplifted,
            o.theta_max_over_theta_c,
        )
    })?;
    let mut cells = [Cell::default(); CELLS];
    // Summed in unit order, so the result does not depend on the threads.
    for (ci, ot, theta) in rows {
        let c = &mut cells[ci];
        c.runs += 1;
        if ot {
            c.overturned += 1;
        } else {
            c.theta_sum += theta;
        }
    }
    Ok(cells)
}

/// The paper's row of a cell, if it published one.
fn published(ci: usize) -> Option<&'static PaperRow> {
    let (ai, rest) = (ci / 16, ci % 16);
    paper::lookup(ASPECTS[ai], RESTITUTIONS[rest / 4], PGAS[rest % 4])
}

fn mean_sd(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0).max(1.0);
    (m, var.sqrt())
}

/// The scores of one reading (see the module docs of `paper::check`).
#[derive(Clone, Debug)]
pub struct Scores {
    /// Overturn totals per e, one entry per ensemble: `totals[e][j]`.
    pub totals: [Vec<f64>; 4],
    /// Mean number of the 44 published cells differing at 5 %.
    pub cells_differing: f64,
    /// Mean number of the 11 populated e = 0 cells differing at 5 %.
    pub e0_cells_differing: f64,
    /// For each ensemble, the e = 0 cells differing at 5 %.
    pub e0_cells_differing_each: Vec<usize>,
    /// Mean log-likelihood of the paper's counts (leave-one-out rates).
    pub ll_paper: f64,
    /// Mean log-likelihood of the simulated tables (leave-one-out rates).
    pub ll_simulated: f64,
    /// Rank p-value of the paper's table among the simulated ones.
    pub p_value: f64,
    /// The same, over the 11 e = 0 cells only.
    pub p_value_e0: f64,
    /// Mean log-likelihood of the paper's e = 0 counts.
    pub ll_paper_e0: f64,
    /// Mean log-likelihood of a simulated table's e = 0 counts.
    pub ll_simulated_e0: f64,
    /// Near-threshold mean θmax/θc: (H/B, A_g, e, ours, paper's).
    pub near_threshold: Vec<(f64, f64, f64, f64, f64)>,
    /// Cochran–Armitage Z over e, pooled over the ensembles.
    pub trend_z: f64,
    /// Its two-sided p-value.
    pub trend_p: f64,
}

/// Scores a reading's ensembles against the paper.
pub fn score(result: &ReadingResult) -> Scores {
    let k = result.ensembles.len();
    let totals: [Vec<f64>; 4] = std::array::from_fn(|ei| {
        result
            .ensembles
            .iter()
            .map(|cells| {
                (0..3)
                    .flat_map(|ai| (0..4).map(move |li| cell_index(ai, ei, li)))
                    .map(|ci| cells[ci].overturned as f64)
                    .sum()
            })
            .collect()
    });
    let published_cells: Vec<(usize, &PaperRow)> = (0..CELLS)
        .filter_map(|ci| published(ci).map(|p| (ci, p)))
        .collect();
    let differing = |cells: &[Cell; CELLS], e0: bool| -> usize {
        published_cells
            .iter()
            .filter(|(_, p)| !e0 || p.restitution == 0.0)
            .filter(|(ci, p)| {
                let c = cells[*ci];
                fisher_exact(
                    c.overturned as u64,
                    c.runs as u64,
                    p.overturned as u64,
                    paper::RECORDS as u64,
                ) < 0.05
            })
            .count()
    };
    let e0_each: Vec<usize> = result
        .ensembles
        .iter()
        .map(|c| differing(c, true))
        .collect();
    let all_each: Vec<usize> = result
        .ensembles
        .iter()
        .map(|c| differing(c, false))
        .collect();

    // Leave-one-out log-likelihoods, over all published cells and over e = 0.
    let loo = |only_e0: bool| -> (f64, f64, f64) {
        let (mut ll_paper, mut ll_sim, mut below) = (0.0, 0.0, 0usize);
        for j in 0..k {
            let rate = |ci: usize| {
                let (mut kk, mut n) = (0.0, 0.0);
                for (i, cells) in result.ensembles.iter().enumerate() {
                    if i != j {
                        kk += cells[ci].overturned as f64;
                        n += cells[ci].runs as f64;
                    }
                }
                (kk + 0.5) / (n + 1.0)
            };
            let (mut lp, mut ls) = (0.0, 0.0);
            for &(ci, p) in published_cells
                .iter()
                .filter(|(_, p)| !only_e0 || p.restitution == 0.0)
            {
                let q = rate(ci);
                lp += binomial_log_likelihood(p.overturned as u64, paper::RECORDS as u64, q);
                let c = result.ensembles[j][ci];
                ls += binomial_log_likelihood(c.overturned as u64, c.runs as u64, q);
            }
            ll_paper += lp / k as f64;
            ll_sim += ls / k as f64;
            below += (ls <= lp) as usize;
        }
        (ll_paper, ll_sim, (1 + below) as f64 / (k + 1) as f64)
    };
    let (ll_paper, ll_simulated, p_value) = loo(false);
    let (ll_paper_e0, ll_simulated_e0, p_value_e0) = loo(true);

    let mut near_threshold = Vec::new();
    for (ai, li) in [(0, 1), (1, 0), (2, 0)] {
        for (ei, &e) in RESTITUTIONS.iter().enumerate() {
            let ci = cell_index(ai, ei, li);
            let (mut sum, mut n) = (0.0, 0.0);
            for cells in &result.ensembles {
                sum += cells[ci].theta_sum;
                n += (cells[ci].runs - cells[ci].overturned) as f64;
            }
            let theirs = published(ci)
                .and_then(|p| p.theta_max_over_theta_c)
                .unwrap_or(f64::NAN);
            near_threshold.push((ASPECTS[ai], PGAS[li], e, sum / n, theirs));
        }
    }
    let pooled: Vec<u64> = totals
        .iter()
        .map(|t| t.iter().sum::<f64>() as u64)
        .collect();
    let trials = [(300 * k) as u64; 4];
    let trend = cochran_armitage(&pooled, &trials, &RESTITUTIONS);
    Scores {
        cells_differing: all_each.iter().sum::<usize>() as f64 / k as f64,
        e0_cells_differing: e0_each.iter().sum::<usize>() as f64 / k as f64,
        e0_cells_differing_each: e0_each,
        totals,
        ll_paper,
        ll_simulated,
        p_value,
        ll_paper_e0,
        ll_simulated_e0,
        p_value_e0,
        near_threshold,
        trend_z: trend.map_or(f64::NAN, |t| t.z),
        trend_p: trend.map_or(f64::NAN, |t| t.p),
    }
}

/// The paper's overturn totals per e (paper convention): 159, 160, 138, 127.
pub fn paper_totals() -> [u32; 4] {
    std::array::from_fn(|ei| {
        paper::TABLES
            .iter()
            .filter(|r| r.restitution == RESTITUTIONS[ei])
            .map(|r| r.overturned)
            .sum()
    })
}

/// `paper-check.md`: every reading's scores, with the command that made it.
pub fn markdown(results: &[ReadingResult], options: &CheckOptions) -> String {
    let mut s = String::new();
    let k = options.replicates;
    let last = options.seed + k as u64 - 1;
    let _ = writeln!(s, "# Reproducing Shenton and Jones, Tables 1–3\n");
    let _ = writeln!(
        s,
        "Made by `rockfrag paper --replicates {k} --seed {}`: the paper's study (2B = 0.5 m; \
         H/B 2, 4, 6; e 0–0.9; A_g 0.3–1.2 g; infinite friction; 25 records per cell) run on \
         {k} ensembles (seeds {}–{last}) under each reading of section 4, and under the rad/s \
         grid once more with `[solver] rock_impact = \"rock\"` (not physics: a rule that keeps \
         the block rocking after a rock impact with e > 0). Counts in the paper's \
         convention (a lift-off from rock counts as overturned); see `src/reproduce.rs` for \
         the statistics.\n",
        options.seed, options.seed
    );
    let theirs = paper_totals();
    let paper_trend = cochran_armitage(&theirs.map(u64::from), &[300; 4], &RESTITUTIONS)
        .expect("the paper's counts vary");
    let scores: Vec<Scores> = results.iter().map(score).collect();

    let _ = writeln!(s, "## Overturn totals per e (of 300 per ensemble)\n");
    let _ = writeln!(
        s,
        "| reading | e = 0 | e = 0.3 | e = 0.6 | e = 0.9 | trend over e: Z (p) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    let _ = writeln!(
        s,
        "| **paper** | {} | {} | {} | {} | {:.2} ({}) |",
        theirs[0],
        theirs[1],
        theirs[2],
        theirs[3],
        paper_trend.z,
        p_text(paper_trend.p)
    );
    for (r, sc) in results.iter().zip(&scores) {
        let mut line = format!("| {} ({}) |", r.reading.name, r.reading.meaning);
        for t in &sc.totals {
            let (m, sd) = mean_sd(t);
            let _ = write!(line, " {m:.1} ± {sd:.1} |");
        }
        let _ = write!(line, " {:.2} ({}) |", sc.trend_z, p_text(sc.trend_p));
        let _ = writeln!(s, "{line}");
    }
    let _ = writeln!(s, "\ne = 0 totals of each ensemble, in seed order:\n");
    for (r, sc) in results.iter().zip(&scores) {
        let each: Vec<String> = sc.totals[0].iter().map(|t| t.to_string()).collect();
        let (m, sd) = mean_sd(&sc.totals[0]);
        let _ = writeln!(
            s,
            "- {}: {} (the paper's 159 is {:+.1} sd from the mean)",
            r.reading.name,
            each.join(", "),
            (f64::from(theirs[0]) - m) / sd
        );
    }
    let _ = writeln!(
        s,
        "\nMean ± standard deviation over the {k} ensembles. The trend is the Cochran–Armitage \
         test on the counts pooled over H/B and A_g (and, for ours, over the ensembles: \
         {}·300 runs per e); Z < 0 means fewer overturns at higher e.\n",
        k
    );

    let _ = writeln!(s, "## Cell by cell\n");
    let _ = writeln!(
        s,
        "| reading | e = 0 cells differing at 5 % (of 11) | all cells differing (of 44) | \
         log-likelihood of the paper's counts: e = 0 / all | of a simulated table: e = 0 / all \
         | p-value: e = 0 / all |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    for (r, sc) in results.iter().zip(&scores) {
        let each: Vec<String> = sc
            .e0_cells_differing_each
            .iter()
            .map(|n| n.to_string())
            .collect();
        let _ = writeln!(
            s,
            "| {} | {:.1} (per ensemble: {}) | {:.1} | {:.1} / {:.1} | {:.1} / {:.1} | {:.2} / {:.2} |",
            r.reading.name,
            sc.e0_cells_differing,
            each.join(", "),
            sc.cells_differing,
            sc.ll_paper_e0,
            sc.ll_paper,
            sc.ll_simulated_e0,
            sc.ll_simulated,
            sc.p_value_e0,
            sc.p_value
        );
    }
    let _ = writeln!(
        s,
        "\nA cell differs when Fisher's exact test of our 25 runs against the paper's 25 gives \
         p < 0.05 (about 2 of 44 would by chance alone). The log-likelihood is Σ ln P(kᵢ | 25, \
         p̂ᵢ) over the 11 published e = 0 cells, or all 44, p̂ from the other ensembles; the p-value ranks the \
         paper's table among the {k} simulated ones scored the same way, (1 + #{{simulated ≤ \
         paper}})/({}): small means the paper's counts are unlike any ensemble of that reading.\n",
        k + 1
    );

    let _ = writeln!(
        s,
        "## Near the threshold: mean θmax/θc of the runs that did not overturn\n"
    );
    let mut head = "| H/B | A_g (g) | e | paper |".to_string();
    for r in results {
        let _ = write!(head, " {} | ratio |", r.reading.name);
    }
    let _ = writeln!(s, "{head}");
    let _ = writeln!(s, "|{}", "---|".repeat(4 + 2 * results.len()));
    for i in 0..scores[0].near_threshold.len() {
        let (a, pga, e, _, theirs) = scores[0].near_threshold[i];
        let mut line = format!("| {a} | {pga} | {e} | {} |", sig3(theirs));
        for sc in &scores {
            let ours = sc.near_threshold[i].3;
            let _ = write!(line, " {} | {:.2} |", sig3(ours), ours / theirs);
        }
        let _ = writeln!(s, "{line}");
    }
    let _ = writeln!(
        s,
        "\nPooled over the {k} ensembles; ratio = ours / the paper's.\n"
    );
    s
}

/// Writes `text` to `path` atomically (temporary file, then rename).
pub fn write_report(path: &std::path::Path, text: &str) -> Result<()> {
    crate::io_util::write_atomic(path, |w| w.write_all(text.as_bytes())).map_err(Error::io(path))
}
