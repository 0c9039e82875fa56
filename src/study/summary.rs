//! `summary.md`: what a study found, in the order a user reads it.
//!
//! 1. the study: what was run, how many analyses, what they drew;
//! 2. **Fragility**: per case and limit state, the fitted median with its
//!    90 % band, β, how many analyses exceeded it, and the fit's notes in
//!    plain words (a curve that could not be fitted says why and what to
//!    try); written once the fit is done, and replaced by `rockfrag
//!    fragility` when it refits;
//! 3. **Counts per stripe**: per case and intensity level, the runs, how
//!    many failed, overturned, lifted off and left rest, and the mean
//!    θmax/θc of the runs that stood;
//! 4. **Sensitivity**, only when the study asked for it (`[output]
//!    sensitivity`): per case and intensity level, the share of analyses
//!    that a perturbation of the record by 1e-9 changes, and where they sit
//!    on the fragility curve;
//! 5. **Provenance**: the spec, its hash and the program's version (the
//!    times and machine are in `manifest.json`).
//!
//! A layer above may add sections (the paper's study gets its Tables 1–3)
//! and `rockfrag risk` adds `## Risk`. The counts are always computed by
//! reading `outcomes.csv` back, so a run, a resumed run and a merge of
//! shards give the same bytes.

use super::manifest::Manifest;
use super::plan::{self, Shard};
use super::tally::{Cell, Tally};
use crate::case::Case;
use crate::fragility::{
    Caveat, FragilityRow, caveat_words, first_inversion, unfit_advice, unfit_words,
};
use crate::im::Im;
use crate::io_util::sig3;
use crate::spec::{Intensity, Motions, Orientation, Study, Uncertainty};
use crate::uncertainty::{Distribution, Property, Value};
use std::fmt::Write;

impl Tally {
    /// The cell of case number `case` at level index `level`.
    pub(crate) fn cell(&self, case: usize, level: usize) -> &Cell {
        &self.cells[case * self.levels + level]
    }

    /// The generic `summary.md` (see the docs of `src/study/summary.rs`): the fitted
    /// curves `fits` (`fragility.csv`'s rows) when there are any, then the
    /// counts per stripe and the provenance from `manifest`.
    pub fn markdown(
        &self,
        study: &Study,
        shard: Shard,
        fits: Option<&[FragilityRow]>,
        manifest: Option<&Manifest>,
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
                "**Shard {shard} only**: merge the shards (`rockfrag merge`) for the study's \
                 fragility and tables.\n"
            );
        }
        let motions = match &study.motions {
            Motions::Synthetic {
                seed,
                records,
                pairs: None,
                ..
            } => format!("{records} synthetic records per level (seed {seed})"),
            Motions::Synthetic { seed, records, .. } => {
                format!("{records} synthetic pairs of independent components (seed {seed})")
            }
            Motions::Files(f) => format!("{} recorded motions per level", f.len()),
            Motions::Pairs { pairs, .. } => format!("{} record pairs", pairs.len()),
        };
        let motions = match study.motions.orientation() {
            None => motions,
            Some(Orientation::Grid(angles)) => {
                format!("{motions} at {} orientations per level", angles.len())
            }
            Some(Orientation::Drawn { .. }) => {
                format!("{motions} per level, each at a drawn orientation")
            }
        };
        let cases = plan::cases(study);
        let plural = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
        let _ = writeln!(
            s,
            "{} analyses ({} × {} × {motions}): {} overturned, {} lifted off a rocking pivot \
             (N = 0; bounces into flight after impacts are not counted, and under finite \
             friction the pivot slips before N reaches 0), {} failed.\n",
            c.analyses,
            plural(cases.len(), "case"),
            plural(study.intensity.levels().len(), "intensity level"),
            c.overturned,
            c.uplifted,
            c.failed
        );
        if let Some(u) = &study.uncertainty {
            let _ = writeln!(s, "{}\n", uncertainty_text(u));
        }
        if !study.floor.is_ground() {
            let _ = writeln!(s, "{}\n", floor_text(&study.floor));
        }
        if let Some(orientation) = study.motions.orientation() {
            let _ = writeln!(s, "{}\n", orientation_text(orientation, &study.intensity));
        }
        if let Some(fits) = fits.filter(|f| !f.is_empty()) {
            s.push_str(&fragility_section(fits));
            s.push('\n');
        }
        s.push_str(&self.stripes_section(study));
        s.push('\n');
        if study.output.sensitivity {
            s.push_str(&self.sensitivity_section(study));
            s.push('\n');
        }
        s.push_str(&provenance_section(study, manifest));
        s
    }

    /// `## Counts per stripe`: per case and level, runs, failed, overturned,
    /// lifted off, moved, and the mean θmax/θc of the runs that stood.
    fn stripes_section(&self, study: &Study) -> String {
        let (level_name, unit) = level_heading(study);
        let any_failed = self.counts.failed > 0;
        let mut s = format!(
            "{COUNTS_HEADING}\n\nPer case and intensity level: the runs, how many \
             overturned (|θ| reached π/2), lifted off a rocking pivot (N reached 0 on it: \
             the seed paper's stop; a bounce into flight after an impact is not one, and under \
             finite friction the pivot slips before N reaches 0, so the count is rarely above \
             0 there), left rest, and the mean peak rotation θmax/θc of the runs that \
             stood.\n\n\
             | case | {level_name}{unit} | runs |{} overturned | lifted off | moved | mean θmax/θc (standing) |\n\
             |---|---|---|{}---|---|---|---|\n",
            if any_failed { " failed |" } else { "" },
            if any_failed { "---|" } else { "" },
        );
        for (ci, case) in plan::cases(study).iter().enumerate() {
            for (li, level) in study.intensity.levels().iter().enumerate() {
                let cell = self.cell(ci, li);
                let theta = cell.strict.get().map_or("-".to_string(), |m| {
                    // A few slid runs leave round-off rotations (1e-40): not a number to read.
                    if m[0] > 0.0 && m[0] < 1e-6 {
                        "< 1e-6".to_string()
                    } else {
                        sig3(m[0])
                    }
                });
                let _ = writeln!(
                    s,
                    "| `{}` | {level} | {} |{} {} | {} | {} | {theta} |",
                    case.id(),
                    cell.ok,
                    if any_failed {
                        format!(" {} |", cell.failed)
                    } else {
                        String::new()
                    },
                    cell.overturned,
                    cell.uplifted,
                    cell.moved,
                );
            }
        }
        s
    }
}

impl Tally {
    /// `## Sensitivity`: per case and level, the analyses whose outcome the
    /// record scaled by 1 + 1e-9 changed (`sensitive` in `outcomes.csv`),
    /// their share per level over every case, and where they sit on the
    /// curve: at levels where none of the case's runs overturned, some, or
    /// all (the counts the curve is fitted to, so the placement does not
    /// depend on the fit).
    fn sensitivity_section(&self, study: &Study) -> String {
        let (level_name, unit) = level_heading(study);
        let share = |k: u64, n: u64| {
            if n == 0 {
                "-".to_string()
            } else {
                format!("{:.1} %", 100.0 * k as f64 / n as f64)
            }
        };
        let cases = plan::cases(study);
        let levels = study.intensity.levels();
        let (mut known, mut sensitive, mut unknown) = (0, 0, 0);
        // sensitive runs at levels where none, some or all of the case's runs overturned
        let mut place = [0u64; 3];
        let mut per_level = vec![(0u64, 0u64); levels.len()];
        let mut table = String::new();
        for (ci, case) in cases.iter().enumerate() {
            for (li, level) in levels.iter().enumerate() {
                let cell = self.cell(ci, li);
                known += cell.sensitivity_known;
                sensitive += cell.sensitive;
                unknown += cell.ok - cell.sensitivity_known;
                per_level[li].0 += cell.sensitivity_known;
                per_level[li].1 += cell.sensitive;
                let at = match cell.overturned {
                    0 => 0,
                    k if k == cell.ok => 2,
                    _ => 1,
                };
                place[at] += cell.sensitive;
                let _ = writeln!(
                    table,
                    "| `{}` | {level} | {} | {} | {} | {} |",
                    case.id(),
                    cell.ok,
                    cell.overturned,
                    cell.sensitive,
                    share(cell.sensitive, cell.sensitivity_known)
                );
            }
        }
        let mut s = format!(
            "{SENSITIVITY_HEADING}\n\nEach analysis was solved a second time under its record \
             scaled by 1 + 1e-9, a change far below any physical uncertainty of a record and of \
             the size of the default solver's own error. An analysis is *sensitive* when its \
             outcome changed: overturning flipped, θmax/θc moved by more than {} or the time of \
             overturning by more than {} s (`sensitive` in `outcomes.csv`). Such a run is \
             decided by a hair, near the overturning threshold: another solver setting, or \
             another solver, can flip it without either being wrong, so a sensitive run that \
             differs between two solvers is chaos, not a solver error. The share is a lower \
             bound on such runs (a larger perturbation flags more). The second solve doubles \
             the solver's work.\n\n",
            crate::solver::sensitivity::THETA_TOL,
            crate::solver::sensitivity::TIME_TOL,
        );
        let _ = write!(
            s,
            "{sensitive} of {known} analyses sensitive ({})",
            share(sensitive, known)
        );
        if unknown > 0 {
            let _ = write!(
                s,
                "; {unknown} whose second solve failed are left out (`sensitive` empty)"
            );
        }
        let by_level: Vec<String> = levels
            .iter()
            .zip(&per_level)
            .map(|(level, &(n, k))| match study.intensity {
                Intensity::Pga(_) => format!("{level} g: {}", share(k, n)),
                Intensity::Pgv(_) => format!("{level} m/s: {}", share(k, n)),
                Intensity::Scale(_) => format!("×{level}: {}", share(k, n)),
            })
            .collect();
        let _ = writeln!(
            s,
            ". Per {level_name} level, over every case: {}.\n",
            by_level.join("; ")
        );
        if sensitive > 0 {
            let _ = writeln!(
                s,
                "Where they sit on the fragility curve: {} at levels where none of the case's \
                 runs overturned (below the curve's rise), {} where some did (on the rise, \
                 where the curve is fitted from) and {} where all did (above it).\n",
                place[0], place[1], place[2]
            );
        }
        let _ = write!(
            s,
            "| case | {level_name}{unit} | runs | overturned | sensitive | share |\n\
             |---|---|---|---|---|---|\n{table}"
        );
        s
    }
}

/// The heading of the sensitivity section (`[output] sensitivity`).
pub const SENSITIVITY_HEADING: &str = "## Sensitivity";

/// The heading of the fitted curves' section ([`fragility_section`]).
pub const FRAGILITY_HEADING: &str = "## Fragility";

/// The heading of the counts per case and intensity level.
pub const COUNTS_HEADING: &str = "## Counts per stripe";

/// A case in a table: its id and its parameters.
fn case_label(case: &Case) -> String {
    format!("`{}` {case}", case.id())
}

/// `## Fragility`: the fitted curves of `fits` (`fragility.csv`'s rows, in
/// its order): per case and limit state, the median with its 90 % band, β,
/// the counts and the fit's notes in plain words; then the curves that
/// could not be fitted, why, and what to try. `rockfrag fragility` replaces
/// this section when it refits.
pub fn fragility_section(fits: &[FragilityRow]) -> String {
    let Some(first) = fits.first() else {
        return format!("{FRAGILITY_HEADING}\n\nNo curves: `fragility.csv` has no rows.\n");
    };
    let im = first.im;
    let unit = im.unit_suffix();
    let replicates = fits.iter().filter_map(|f| f.boot_replicates).max();
    let im_text = im.description();
    let mut s = format!(
        "{FRAGILITY_HEADING}\n\nLognormal curves P(limit state | IM) = Φ(ln(IM/θ)/β), IM {im_text}, \
         fitted by maximum likelihood over the stripes (`fragility.csv`; \
         `fragility_curves.csv`, `fragility.xml` for OpenQuake). {}\n\n\
         | case | limit state | median θ{unit} [90 %] | β [90 %] | exceeded / analyses | \
         stripes | notes |\n|---|---|---|---|---|---|---|\n",
        match replicates {
            Some(n) => format!(
                "The 90 % bands come from {n} bootstrap replicates over records (a \
                 replicate draws the study's records with replacement, each with its \
                 analyses at every stripe)."
            ),
            None => "No bootstrap: no bands.".to_string(),
        }
    );
    let band = |b: Option<(f64, f64)>| {
        b.map_or(String::new(), |(lo, hi)| {
            format!(" [{}, {}]", sig3(lo), sig3(hi))
        })
    };
    let mut unfitted = Vec::new();
    let mut explain = Vec::new();
    for (i, f) in fits.iter().enumerate() {
        let (median, beta, notes) = match (f.fit(), f.status.unfit()) {
            (Some((m, b)), _) => (
                format!("{}{}", sig3(m), band(f.median_band)),
                format!("{}{}", sig3(b), band(f.beta_band)),
                fit_notes(fits, i, &mut explain),
            ),
            (None, why) => {
                unfitted.push(f);
                (
                    "-".to_string(),
                    "-".to_string(),
                    // A fitted row always has its numbers (the reader checks).
                    format!(
                        "not fitted: {}",
                        why.map_or_else(|| f.status.to_string(), unfit_words)
                    ),
                )
            }
        };
        let _ = writeln!(
            s,
            "| {} | {} | {median} | {beta} | {} / {} | {} | {notes} |",
            case_label(&f.case),
            f.limit_state,
            f.n_exceeded,
            f.n_analyses,
            f.n_stripes
        );
    }
    if !explain.is_empty() {
        s.push('\n');
        for e in &explain {
            let _ = writeln!(s, "{e}");
        }
    }
    if !unfitted.is_empty() {
        let _ = writeln!(
            s,
            "\n{} of {} curves could not be fitted; what to try:\n",
            unfitted.len(),
            fits.len()
        );
        for f in unfitted {
            let _ = writeln!(
                s,
                "- `{}` {}: {}",
                f.case.id(),
                f.limit_state,
                f.status
                    .unfit()
                    .map_or_else(|| f.status.to_string(), |why| unfit_advice(why, f.im_range))
            );
        }
    }
    s
}

/// The caveat of row `i` of `rows` in words ([`caveat_words`]), naming
/// the milder limit state of its case it is more likely than.
fn caveat_text(rows: &[FragilityRow], i: usize) -> Option<String> {
    let f = &rows[i];
    let caveat = f.caveat()?;
    let inversion = match (caveat, f.fit(), f.im_range) {
        (Caveat::OutOfOrder, Some(severe), Some(range)) => first_inversion(
            severe,
            rows[..i]
                .iter()
                .filter(|g| g.case == f.case)
                .filter_map(|g| g.fit().map(|p| (g.limit_state.as_str(), p))),
            range,
        ),
        _ => None,
    };
    Some(caveat_words(caveat, f.im_range, inversion, f.im.unit()))
}

/// The notes of fitted curve `rows[i]`, short; what they mean is added to
/// `explain` once.
fn fit_notes(rows: &[FragilityRow], i: usize, explain: &mut Vec<String>) -> String {
    let f = &rows[i];
    let mut add = |text: &str| {
        if !explain.iter().any(|e| e == text) {
            explain.push(text.to_string());
        }
    };
    let mut notes = Vec::new();
    if let Some(text) = caveat_text(rows, i) {
        notes.push(format!("**{text}**"));
    }
    if f.beta_model == "common" {
        notes.push("common β".to_string());
        add(
            "*common β*: the case's limit states were fitted with one β, because their \
             separate curves crossed (a more severe limit state cannot be more likely).",
        );
    }
    if let (Some(unfit), Some(n)) = (f.boot_unfit.filter(|&u| u > 0), f.boot_replicates) {
        // More than a tenth left out: the band is not one to quote.
        if unfit * 10 > n {
            notes.push(format!(
                "**{unfit} of {n} replicates unfitted: band too narrow**"
            ));
        } else {
            notes.push(format!("{unfit} of {n} replicates unfitted"));
        }
        add(
            "*replicates unfitted*: bootstrap replicates whose resampled records left no \
             finite fit (most often separated: none exceeded below some stripe and all above \
             it, which a steep curve invites); the band comes from the others, so it is \
             narrow on the steep side: a little where few were left out, too narrow to quote \
             where more than a tenth were. More records per stripe, or stripes closer \
             together near the median, make them fewer.",
        );
    }
    if f.n_failed > 0 {
        notes.push(format!("{} failed analyses left out", f.n_failed));
    }
    notes.join("; ")
}

/// `## Provenance`: where the study came from, with its hash.
fn provenance_section(study: &Study, manifest: Option<&Manifest>) -> String {
    let mut s = String::from("## Provenance\n\n");
    if let Some(m) = manifest {
        let _ = writeln!(
            s,
            "- spec `{}` (study `{}`), hash `{}`{}",
            m.spec_file,
            m.study,
            m.spec_hash,
            m.records_hash
                .as_ref()
                .map_or(String::new(), |h| format!(", record files `{h}`"))
        );
        let _ = writeln!(s, "- rockfrag {}", m.rockfrag_version);
    } else {
        let _ = writeln!(
            s,
            "- study `{}`, hash `{}`",
            study.name,
            super::manifest::hash_text(study.hash())
        );
    }
    let sv = &study.solver;
    let _ = writeln!(
        s,
        "- solver: {} model, {} integrator, rtol {:e}, {} impacts{}",
        sv.model,
        sv.integrator,
        sv.rtol,
        sv.impact,
        if sv.rock_impact == crate::solver::RockImpact::Rock {
            ", rock impacts kept rocking (`rock_impact = \"rock\"`, not physics)"
        } else {
            ""
        }
    );
    let _ = writeln!(
        s,
        "- `outcomes.csv`: one row per analysis; `manifest.json`: the spec as parsed, with \
         every default written out, the times and the machine"
    );
    s
}

/// `name ~ distribution(…)` or `name = x`, for the summary.
fn value_text(name: &str, v: &Value) -> String {
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
}

/// One sentence on what each analysis draws: "Drawn per analysis (seed 7):
/// e ~ uniform(0, 0.9); …; the tables pool the draws (`drawn`)."
fn uncertainty_text(u: &Uncertainty) -> String {
    let mut parts: Vec<String> = Property::ALL
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
            value_text(name, v)
        })
        .collect();
    // a stack's: `stack statue top: 2B (m) ~ normal(…), …`
    for d in &u.stacks {
        let n = d.bodies.len();
        for (i, values) in d.bodies.iter().enumerate() {
            let given: Vec<String> = crate::uncertainty::StackProperty::ALL
                .iter()
                .zip(values)
                .filter_map(|(p, v)| v.as_ref().map(|v| value_text(p.name(), v)))
                .collect();
            if !given.is_empty() {
                parts.push(format!(
                    "stack {} {}: {}",
                    d.stack,
                    crate::outcome::Slot::of(i, n).name(),
                    given.join(", ")
                ));
            }
        }
    }
    format!(
        "Drawn per analysis (`[uncertainty]`, seed {}): {}. Each case pools its analyses over \
         the draws (`drawn` in the tables); outcomes.csv holds each analysis's own values.",
        u.seed,
        parts.join("; ")
    )
}

/// The floor sentence of a study on a floor: its modes, and that the
/// levels stay the ground's.
/// The sentence on the directions of a study of record pairs, and what
/// its intensities are.
fn orientation_text(orientation: &Orientation, intensity: &Intensity) -> String {
    let faces = match orientation {
        Orientation::Grid(angles) => format!(
            "each pair is run with the blocks facing φ = {}° from its first component",
            angles
                .iter()
                .map(|a| a.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
        Orientation::Drawn {
            dist: Distribution::Uniform { min, max },
            ..
        } => format!(
            "under each record the blocks face a direction φ drawn uniformly on \
             [{min}°, {max}°) from its first component"
        ),
        Orientation::Drawn { .. } => {
            "under each record the blocks face a direction φ drawn from its first component"
                .to_string()
        }
    };
    let levels = match intensity {
        Intensity::Pga(_) => "the levels are the pair's RotD50 PGA",
        Intensity::Pgv(_) => "the levels are the pair's RotD50 PGV",
        Intensity::Scale(_) => "the levels multiply both components",
    };
    format!(
        "Record pairs: {faces} and feel cos φ·H1 + sin φ·H2; {levels}, and `pga`, `pgv` in \
         `outcomes.csv` are the peaks of the component the block feels (`pga_rotd50`, \
         `pgv_rotd50` and `phi` beside them)."
    )
}

fn floor_text(floor: &crate::motion::Floor) -> String {
    let modes: Vec<String> = floor
        .modes
        .iter()
        .map(|m| {
            format!(
                "T = {} s, ζ = {} %, Γφ = {}",
                m.period,
                m.damping * 100.0,
                m.participation
            )
        })
        .collect();
    format!(
        "The blocks stand on a floor of a linear building ({}: {}): each record is \
         filtered through it, the levels are the ground's, and `outcomes.csv` gives the \
         floor's peaks in `pfa` (g) and `pfv` (m/s).",
        if modes.len() == 1 {
            "one mode"
        } else {
            "modes"
        },
        modes.join("; ")
    )
}

/// The name and unit of a study's levels in a table heading: `PGA`, `PGV`
/// (a record pair's RotD50 for studies of pairs) or `scale`.
fn level_heading(study: &Study) -> (String, String) {
    let pairs = study.motions.orientation().is_some();
    let im = match (&study.intensity, pairs) {
        (Intensity::Pga(_), true) => Im::PGA_ROTD50,
        (Intensity::Pga(_), false) => Im::PGA,
        (Intensity::Pgv(_), true) => Im::PGV_ROTD50,
        (Intensity::Pgv(_), false) => Im::PGV,
        (Intensity::Scale(_), _) => return ("scale".into(), String::new()),
    };
    (im.short(), im.unit_suffix())
}
