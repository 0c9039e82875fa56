//! One analysis of a study solved again on its own (`rockfrag simulate
//! --study`): its case, intensity level and record give the block (drawn
//! values drawn from the same stream), the motion the block feels (the
//! record made and scaled as the run made it, a pair turned to its
//! direction, a floor's filter) and the study's solver settings, and the
//! row is made by the run's own code ([`analyse`], which the run calls): the same bytes
//! as its line of `outcomes.csv`. [`simulate_command`] is the one text of
//! the command, for the figures and the docs.

use super::ensemble::solve;
use super::plan::{self, Unit};
use super::source::{Source, UnitMotion};
use crate::case::{Case, CaseValues, Scene};
use crate::error::{Error, Result, number};
use crate::im::ImValues;
use crate::outcome::Outcome;
use crate::outcomes_csv::{Columns, RecordInfo};
use crate::solver::{Friction, History, Sensitivity, sensitivity};
use crate::spec::Study;
use std::path::Path;

/// One analysis of a study, solved again.
#[derive(Clone, Debug)]
pub struct Reanalysis {
    /// The study's case (drawn parameters still drawn) and its number in
    /// canonical order.
    pub case: (Case, usize),
    /// The work unit: level and record.
    pub unit: Unit,
    /// The motion the block felt (`Err`: why it could not be made, as the
    /// run wrote it).
    pub motion: std::result::Result<UnitMotion, String>,
    /// What was solved: the block's own parameters, the outcome.
    pub analysed: Analysed,
    /// `outcomes.csv`'s header for this study, with its newline.
    pub header: String,
    /// The analysis's row, with its newline: the run's bytes.
    pub row: String,
}

/// The work unit of `study` at intensity `level` (in the study's unit: g
/// for PGA levels, m/s for PGV, the factor for scale factors; one of its
/// levels, to the bit as written in the spec) and record `record` (0-based,
/// `outcomes.csv`'s `record`). Errors list what the study has.
pub fn locate(study: &Study, level: f64, record: usize) -> Result<Unit> {
    let levels = study.intensity.levels();
    let Some(li) = levels.iter().position(|&l| l == level) else {
        let have: Vec<String> = levels.iter().map(|&l| number(l)).collect();
        return Err(Error::invalid(
            "level",
            level,
            &format!("one of the study's levels ({})", have.join(", ")),
        ));
    };
    let records = study.records();
    if record >= records {
        return Err(Error::invalid(
            "record",
            record,
            &format!(
                "a record of the study, 0 to {} ({records} records per level)",
                records.saturating_sub(1)
            ),
        ));
    }
    Ok(plan::unit(study, li * records + record))
}

/// Solves again the analysis of `study` at case `case_id` (the `case_id`
/// of `fragility.csv`, e.g. `a4_w0p2_edrawn_mudrawn`), `level` and
/// `record` ([`locate`]). With `history`, the analysis is solved a second
/// time for its time history: a solve that records one decides rest
/// sample by sample, which can move the last bit of `time_in_mode`, so the
/// row and the outcome are the first solve's, the run's.
pub fn reanalyse(
    study: &Study,
    case_id: &str,
    level: f64,
    record: usize,
    history: Option<&mut History>,
) -> Result<Reanalysis> {
    let cases = plan::cases(study);
    let Some(ci) = cases.iter().position(|c| c.id() == case_id) else {
        let ids: Vec<String> = cases.iter().map(Case::id).collect();
        return Err(Error::invalid(
            "case",
            case_id,
            &format!("the id of one of the study's cases ({})", ids.join(", ")),
        ));
    };
    let unit = locate(study, level, record)?;
    let motion = Source::new(study)?
        .motion(study, level, record)
        .map_err(|e| e.to_string());
    let cols = plan::columns(study);
    let file = study.record_file(record);
    let (analysed, row) = analyse(
        study,
        &cols,
        (&cases[ci], ci),
        &unit,
        &motion,
        file.as_deref(),
    );
    if let (Some(h), Some(Scene::Block(analysis)), Ok(m)) = (history, &analysed.analysis, &motion) {
        // the row's solve succeeded or failed alone; this one only records
        let _ = crate::solver::simulate(analysis, &m.felt, &study.solver, Some(h));
    }
    Ok(Reanalysis {
        case: (cases[ci], ci),
        unit,
        motion,
        analysed,
        header: cols.header(),
        row,
    })
}

/// The study's case whose analysis `own` is (its drawn parameters match
/// any value), and its number: for naming an analysis read back from
/// `outcomes.csv` by its case.
pub fn case_of(study: &Study, own: &CaseValues) -> Option<(Case, usize)> {
    plan::cases(study)
        .into_iter()
        .enumerate()
        .find(|(_, c)| own.pooled(&c.drawn()) == *c)
        .map(|(i, c)| (c, i))
}

/// The block of a [`simulate_command`]: a case of the study, or a block of
/// one's own under the study's motion.
#[derive(Clone, Copy, Debug)]
pub enum CommandBlock<'a> {
    /// The study's case with this id.
    Case(&'a str),
    /// A block given by its flags.
    Block {
        /// Base width 2B, m.
        width: f64,
        /// Aspect ratio H/B.
        aspect: f64,
        /// Restitution e.
        restitution: f64,
        /// Friction.
        friction: Friction,
    },
}

/// The command that solves one analysis again: `rockfrag simulate --study
/// STUDY --case ID --level L --record R` (or the block's flags instead of
/// `--case`), `study` a spec file or a finished study folder. The one text
/// of it: the history figure names its analysis so.
///
/// ```
/// use rockfrag::study::{CommandBlock, simulate_command};
/// let c = simulate_command("results/vase".as_ref(), 0.5, 21, CommandBlock::Case("a4_w0p2_edrawn_mudrawn"));
/// assert_eq!(c, "rockfrag simulate --study results/vase --case a4_w0p2_edrawn_mudrawn --level 0.5 --record 21");
/// ```
pub fn simulate_command(study: &Path, level: f64, record: usize, block: CommandBlock) -> String {
    let block = match block {
        CommandBlock::Case(id) => format!("--case {}", quoted(id)),
        CommandBlock::Block {
            width,
            aspect,
            restitution,
            friction,
        } => {
            let friction = match friction {
                Friction::Infinite => String::new(),
                Friction::Coulomb { mu_s, mu_k } => {
                    format!(" --mu-s {} --mu-k {}", number(mu_s), number(mu_k))
                }
            };
            format!(
                "--width {} --aspect {} --restitution {}{friction}",
                number(width),
                number(aspect),
                number(restitution)
            )
        }
    };
    format!(
        "rockfrag simulate --study {} {block} --level {} --record {record}",
        quoted(&study.display().to_string()),
        number(level)
    )
}

/// `text` as one shell word: as is when it is plain, else in single quotes.
fn quoted(text: &str) -> String {
    let plain = !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "/._-+=:,@%".contains(c));
    if plain {
        text.to_string()
    } else {
        format!("'{}'", text.replace('\'', r"'\''"))
    }
}

/// One analysis of `study`: `case` (number `case.1` in canonical order) on
/// `unit`, under the unit's motion (or the error that kept it from being
/// made), from record file `file`: its own block (drawn values drawn) and
/// its `outcomes.csv` row, with its newline. The run and [`reanalyse`]
/// make every row here, so a row solved again is the run's.
pub(super) fn analyse(
    study: &Study,
    cols: &Columns,
    case: (&Case, usize),
    unit: &Unit,
    motion: &std::result::Result<UnitMotion, String>,
    file: Option<&str>,
) -> (Analysed, String) {
    let made = motion.as_ref().ok();
    let none = ImValues::new();
    let info = RecordInfo {
        index: unit.record,
        level: study.intensity.levels()[unit.level],
        measured: made.map_or(&none, |m| &m.measured),
        phi: made.and_then(UnitMotion::phi),
        file,
    };
    let (own, analysis) = plan::analysis(study, case.0, case.1, unit);
    let (result, sensitive) = match (&analysis, motion) {
        (Ok(analysis), Ok(m)) => {
            let result = solve(analysis, &m.felt, &study.solver, None);
            // the same analysis under the motion it feels scaled by 1 + 1e-9
            let sensitive = match &result {
                Ok(base) if cols.sensitivity => solve(
                    analysis,
                    &sensitivity::perturbed(&m.felt),
                    &study.solver,
                    None,
                )
                .ok()
                .map(|o| Sensitivity::compare(base, &o).sensitive),
                _ => None,
            };
            (result, sensitive)
        }
        (Ok(_), Err(e)) => (Err(format!("record: {e}")), None),
        (Err(e), _) => (Err(format!("{}: {e}", scene_word(case.0))), None),
    };
    let mut row = cols.row(own, &info, result.clone());
    row.sensitive = sensitive;
    if let (true, Ok(Scene::Stack(stack))) = (cols.stack_values, &analysis) {
        row.bodies = Some(crate::case::BodyValues::of(stack));
    }
    let mut text = String::with_capacity(256);
    cols.write_row(&mut text, &row);
    let analysed = Analysed {
        own,
        analysis: analysis.ok(),
        result,
        sensitive,
    };
    (analysed, text)
}

/// What [`analyse`] solved.
#[derive(Clone, Debug)]
pub struct Analysed {
    /// The scene's own values (drawn values as drawn).
    pub own: CaseValues,
    /// What was simulated (`None` when the drawn values make no valid
    /// block).
    pub analysis: Option<Scene>,
    /// Its outcome, or why there is none (`outcomes.csv`'s `error`).
    pub result: std::result::Result<Outcome, String>,
    /// Whether it is sensitive (with `output.sensitivity`).
    pub sensitive: Option<bool>,
}

/// `block` or `stack`, for a message about the scene of `case`.
fn scene_word(case: &Case) -> &'static str {
    if case.stack.is_some() {
        "stack"
    } else {
        "block"
    }
}
