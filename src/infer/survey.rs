//! The survey: what was seen at a site after the earthquake, one row per
//! kind of object, and how each kind is simulated (its block, which of its
//! properties are drawn, how many draws).
//!
//! ```text
//! # lines starting with '#' are comments
//! name,width,aspect,count,overturned[,restitution][,mu_s][,mu_k][,slid]
//! slab,0.45,5.0,24,7
//! ```
//!
//! `width` is the base width 2B (m), `aspect` H/B, `count` the objects of the
//! kind seen and `overturned` how many of them overturned. The optional
//! columns give a kind's own restitution, friction (`mu_s`, a number or
//! `inf`; `mu_k` ≤ `mu_s`, default: drawn from the spec's μk/μs if it
//! draws one, else μs) and `slid`, the standing objects that slid beyond the
//! spec's sliding limit state. An empty optional field takes the spec's
//! value or distribution. Every fault names the file, the line, the column
//! and the value.

use std::path::{Path, PathBuf};

use crate::case::{Case, CaseValues, Param};
use crate::error::{Error, Result};
use crate::fragility::LimitState;
use crate::outcome::Outcome;
use crate::solver::{Analysis, Friction};
use crate::spec::{InferSettings, Motions, Study, Uncertainty, analysis_values};
use crate::uncertainty::{Property, Value, analysis_seed, uniforms};

/// Columns every survey has.
pub const REQUIRED: [&str; 5] = ["name", "width", "aspect", "count", "overturned"];
/// Columns a survey may have.
pub const OPTIONAL: [&str; 4] = ["restitution", "mu_s", "mu_k", "slid"];

/// Static friction as a survey gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MuS {
    /// `inf`: contacts that never slip.
    Infinite,
    /// A coefficient ≥ 0.
    Coulomb(f64),
}

/// One kind of object seen at the site (one row of the survey).
#[derive(Clone, Debug, PartialEq)]
pub struct Kind {
    /// Its name (unique in the survey).
    pub name: String,
    /// The survey's line it is on (1-based).
    pub line: usize,
    /// Base width 2B, m.
    pub width: f64,
    /// Aspect ratio H/B.
    pub aspect: f64,
    /// Its own coefficient of restitution, if the survey gives one.
    pub restitution: Option<f64>,
    /// Its own static friction, if given.
    pub mu_s: Option<MuS>,
    /// Its own kinetic friction, if given (only with `mu_s`).
    pub mu_k: Option<f64>,
    /// Objects of the kind seen.
    pub count: u64,
    /// How many of them overturned.
    pub overturned: u64,
    /// How many of those standing slid beyond the sliding limit state, if
    /// counted.
    pub slid: Option<u64>,
}

/// A survey file, read and checked.
#[derive(Clone, Debug, PartialEq)]
pub struct Survey {
    /// The file.
    pub path: PathBuf,
    /// Its kinds, in the file's order.
    pub kinds: Vec<Kind>,
}

fn parse_err(path: &Path, line: usize, message: String) -> Error {
    Error::Parse {
        path: path.to_path_buf(),
        line,
        message,
    }
}

impl Survey {
    /// Reads and checks a survey file (see the [module docs](self)).
    ///
    /// Errors: [`Error::Io`]; [`Error::Parse`] naming the file, the line, the
    /// column and the value of anything malformed.
    pub fn read(path: &Path) -> Result<Survey> {
        let text = crate::io_util::read_text(path)?;
        Survey::parse(&text, path)
    }

    /// Parses survey text; `path` names it in errors.
    pub fn parse(text: &str, path: &Path) -> Result<Survey> {
        let text = crate::io_util::strip_bom(text);
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let Some((header_line, header)) = lines.next() else {
            return Err(parse_err(
                path,
                0,
                format!(
                    "no header: expected a first line `{}` (optional columns: {})",
                    REQUIRED.join(","),
                    OPTIONAL.join(", ")
                ),
            ));
        };
        let columns: Vec<String> = header.split(',').map(|c| c.trim().to_string()).collect();
        for (i, c) in columns.iter().enumerate() {
            if !REQUIRED.contains(&c.as_str()) && !OPTIONAL.contains(&c.as_str()) {
                return Err(parse_err(
                    path,
                    header_line,
                    format!(
                        "column {} is \"{c}\", which is not a survey column: expected {} and \
                         optionally {}",
                        i + 1,
                        REQUIRED.join(", "),
                        OPTIONAL.join(", ")
                    ),
                ));
            }
            if columns[..i].contains(c) {
                return Err(parse_err(
                    path,
                    header_line,
                    format!("column {} repeats \"{c}\"", i + 1),
                ));
            }
        }
        if let Some(missing) = REQUIRED.iter().find(|r| !columns.iter().any(|c| c == *r)) {
            return Err(parse_err(
                path,
                header_line,
                format!(
                    "no column \"{missing}\": a survey needs {}",
                    REQUIRED.join(", ")
                ),
            ));
        }
        let index = |name: &str| columns.iter().position(|c| c == name);
        let mut kinds: Vec<Kind> = Vec::new();
        for (line, text) in lines {
            let fields: Vec<&str> = text.split(',').map(str::trim).collect();
            if fields.len() != columns.len() {
                return Err(parse_err(
                    path,
                    line,
                    format!(
                        "{} fields, but the header has {} columns ({})",
                        fields.len(),
                        columns.len(),
                        columns.join(",")
                    ),
                ));
            }
            let field = |name: &str| index(name).map(|i| (i, fields[i]));
            let bad = |name: &str, expected: &str| {
                let (i, value) = field(name).expect("a column of the header");
                parse_err(
                    path,
                    line,
                    format!(
                        "column {} ({name}) = \"{value}\": expected {expected}",
                        i + 1
                    ),
                )
            };
            let number = |name: &str, ok: fn(f64) -> bool, expected: &str| -> Result<f64> {
                let (_, v) = field(name).expect("a required column");
                v.parse::<f64>()
                    .ok()
                    .filter(|&x| ok(x))
                    .ok_or_else(|| bad(name, expected))
            };
            let optional =
                |name: &str, ok: fn(f64) -> bool, expected: &str| -> Result<Option<f64>> {
                    match field(name) {
                        None | Some((_, "")) => Ok(None),
                        Some(_) => number(name, ok, expected).map(Some),
                    }
                };
            let whole = |name: &str, expected: &str| -> Result<Option<u64>> {
                match field(name) {
                    None | Some((_, "")) => Ok(None),
                    Some((_, v)) => v.parse::<u64>().map(Some).map_err(|_| bad(name, expected)),
                }
            };
            let name = fields[index("name").expect("required")].to_string();
            if name.is_empty() || name.contains('"') {
                return Err(bad("name", "a name for the kind of object (no quotes)"));
            }
            if let Some(first) = kinds.iter().find(|k| k.name == name) {
                return Err(bad(
                    "name",
                    &format!("a name not already used (line {} has it)", first.line),
                ));
            }
            let positive = |x: f64| x.is_finite() && x > 0.0;
            let width = number("width", positive, "a base width 2B in m, > 0")?;
            let aspect = number("aspect", positive, "an aspect ratio H/B > 0")?;
            let count = whole("count", "a whole number of objects ≥ 1")?
                .filter(|&n| n >= 1)
                .ok_or_else(|| bad("count", "a whole number of objects ≥ 1"))?;
            let overturned = whole(
                "overturned",
                &format!("a whole number of objects from 0 to the count, {count}"),
            )?
            .filter(|&k| k <= count)
            .ok_or_else(|| {
                bad(
                    "overturned",
                    &format!("a whole number of objects from 0 to the count, {count}"),
                )
            })?;
            let standing = count - overturned;
            let slid_expected = format!(
                "empty, or a whole number of standing objects that slid, from 0 to {standing} \
                 (the count {count} less the {overturned} overturned)"
            );
            let slid = match whole("slid", &slid_expected)? {
                Some(s) if s > standing => return Err(bad("slid", &slid_expected)),
                s => s,
            };
            let restitution = optional(
                "restitution",
                |x| (0.0..=1.0).contains(&x),
                "empty (the spec's), or a coefficient of restitution in [0, 1]",
            )?;
            let mu_s = match field("mu_s") {
                None | Some((_, "")) => None,
                Some((_, "inf")) => Some(MuS::Infinite),
                Some(_) => Some(MuS::Coulomb(number(
                    "mu_s",
                    |x| x.is_finite() && x >= 0.0,
                    "empty (the spec's friction), inf, or a static friction coefficient ≥ 0",
                )?)),
            };
            let mu_k = match (mu_s, field("mu_k")) {
                (_, None | Some((_, ""))) => None,
                (None, Some(_)) => {
                    return Err(bad(
                        "mu_k",
                        "empty when mu_s is empty (give the kind's mu_s too)",
                    ));
                }
                (Some(MuS::Infinite), Some(_)) => {
                    return Err(bad("mu_k", "empty when mu_s is inf"));
                }
                (Some(MuS::Coulomb(s)), Some((_, v))) => Some(
                    v.parse::<f64>()
                        .ok()
                        .filter(|&x| x.is_finite() && (0.0..=s).contains(&x))
                        .ok_or_else(|| {
                            bad(
                                "mu_k",
                                &format!("a kinetic friction coefficient from 0 to mu_s = {s}"),
                            )
                        })?,
                ),
            };
            kinds.push(Kind {
                name,
                line,
                width,
                aspect,
                restitution,
                mu_s,
                mu_k,
                count,
                overturned,
                slid,
            });
        }
        if kinds.is_empty() {
            return Err(parse_err(
                path,
                header_line,
                "no kinds of object: expected a row per kind below the header".into(),
            ));
        }
        Ok(Survey {
            path: path.to_path_buf(),
            kinds,
        })
    }

    /// Whether any kind counts the objects that slid.
    pub fn counts_slides(&self) -> bool {
        self.kinds.iter().any(|k| k.slid.is_some())
    }
}

/// How one kind is simulated: its block (width and aspect from the survey;
/// restitution and friction the survey's, else the spec's value or
/// distribution), what each analysis draws, and how many draws.
#[derive(Clone, Debug, PartialEq)]
pub struct KindModel {
    /// The kind's case: drawn parameters are [`Param::Drawn`].
    pub case: Case,
    /// What each analysis of the kind draws from the spec's distributions
    /// (`None`: none). Its seed is the inference's.
    pub uncertainty: Option<Uncertainty>,
    /// Draws per record and level (`[infer] draws`).
    pub draws: usize,
    /// `[infer] seating`: each draw's base width is the nominal times a
    /// factor uniform in [1 − seating, 1], its height unchanged (0: off).
    pub seating: f64,
    /// Seed of the seating factors.
    pub seating_seed: u64,
}

impl KindModel {
    /// Analyses actually solved per record and level (1 when nothing is
    /// drawn).
    pub fn solved(&self) -> usize {
        if self.is_drawn() { self.draws } else { 1 }
    }

    /// Whether anything varies from draw to draw.
    pub fn is_drawn(&self) -> bool {
        self.uncertainty.is_some() || self.seating > 0.0
    }

    /// The block of draw `draw` of kind number `kind` on record `record` at
    /// level `level` (the spec's level index): every parameter fixed, drawn
    /// from the stream keyed by (seed, record, level, kind · 2³² + draw).
    pub fn draw(&self, kind: usize, record: usize, level: usize, draw: usize) -> CaseValues {
        let number = (kind << 32) | draw;
        let case = analysis_values(self.uncertainty.as_ref(), &self.case, record, level, number);
        if self.seating == 0.0 {
            return case;
        }
        let u = uniforms(analysis_seed(
            self.seating_seed,
            record as u64,
            level as u64,
            number as u64,
        ))[0];
        seated(case, 1.0 - self.seating * u)
    }
}

/// `case` seated on a fraction `f` of its base: the base width times `f`,
/// the height unchanged.
fn seated(case: CaseValues, f: f64) -> CaseValues {
    CaseValues {
        width: case.width * f,
        aspect: case.aspect / f,
        ..case
    }
}

/// The seed of the inference's draws: `[infer] seed`, else the
/// `[uncertainty]` seed, else the study's ensemble seed, else 1.
pub fn draws_seed(study: &Study, settings: &InferSettings) -> u64 {
    let fallback = match (&study.uncertainty, &study.motions) {
        (Some(u), _) => u.seed,
        (None, Motions::Synthetic { seed, .. }) => *seed,
        (None, Motions::Files(_) | Motions::Pairs { .. }) => 1,
    };
    settings.seed.unwrap_or(fallback)
}

/// A domain tag mixed into the draws' seed, so that an inference's draws are
/// not the study run's draws of the same seed.
const DRAWS_TAG: u64 = 0x1AF3_6E0B_5E12_7D01;

/// A domain tag for the seating factors' streams.
const SEATING_TAG: u64 = 0x5EA7_1A60_0F0B_0001;

/// How each kind of `survey` is simulated under `study` (`spec` names the
/// spec file in errors).
///
/// Errors: [`Error::Spec`] when the spec draws a width or an aspect ratio
/// (the survey gives each kind's); [`Error::Parse`] on the survey's line
/// when a kind's restitution or friction is neither given nor single in the
/// spec, or makes no valid block.
pub fn models(
    survey: &Survey,
    study: &Study,
    settings: &InferSettings,
    spec: &Path,
) -> Result<Vec<KindModel>> {
    if let Some(stack) = study.stacks.first() {
        // a surveyed kind is one block: a stack of the spec would be left
        // out of the inference without a word
        return Err(Error::Spec {
            path: spec.to_path_buf(),
            line: 0,
            field: "grid.stack".into(),
            value: format!("stack {}", stack.name),
            expected: format!(
                "no [[grid.stack]] for rockfrag infer: a surveyed kind is one block on the \
                 ground (width, aspect in {}); kinds that are stacks (a tombstone's die on its \
                 base, with which body fell) are not supported yet",
                survey.path.display()
            ),
        });
    }
    if let Some(u) = &study.uncertainty {
        for p in [Property::Width, Property::Aspect] {
            if u.get(p).is_some() {
                return Err(Error::Spec {
                    path: spec.to_path_buf(),
                    line: 0,
                    field: format!("uncertainty.{}", p.name()),
                    value: "(a distribution)".into(),
                    expected: format!(
                        "no distribution for rockfrag infer: the survey gives each kind's {} \
                         ({})",
                        p.name(),
                        survey.path.display()
                    ),
                });
            }
        }
    }
    let seed = draws_seed(study, settings) ^ DRAWS_TAG;
    survey
        .kinds
        .iter()
        .map(|k| model(k, survey, study, settings, seed))
        .collect()
}

fn model(
    kind: &Kind,
    survey: &Survey,
    study: &Study,
    settings: &InferSettings,
    seed: u64,
) -> Result<KindModel> {
    let err = |message: String| parse_err(&survey.path, kind.line, message);
    let spec_u = study.uncertainty.as_ref();
    let mut drawn = Uncertainty {
        seed,
        width: None,
        aspect: None,
        restitution: None,
        mu_s: None,
        mu_k_over_mu_s: None,
        stacks: Vec::new(),
    };
    let restitution = match kind.restitution {
        Some(e) => Param::Fixed(e),
        None => match spec_u.and_then(|u| u.restitution) {
            Some(v) => {
                drawn.restitution = Some(v);
                Param::Drawn
            }
            None => match study.restitutions.as_slice() {
                [Param::Fixed(e)] => Param::Fixed(*e),
                values => {
                    return Err(err(format!(
                        "kind \"{}\" has no restitution, and the spec gives {} values of \
                         grid.restitution ({}): give the kind a restitution column, or the spec \
                         one grid.restitution value or an [uncertainty] restitution",
                        kind.name,
                        values.len(),
                        values
                            .iter()
                            .map(|p| p.text())
                            .collect::<Vec<_>>()
                            .join(", ")
                    )));
                }
            },
        },
    };
    let spec_friction = spec_u.and_then(|u| u.mu_s.zip(u.mu_k_over_mu_s));
    let friction = match (kind.mu_s, kind.mu_k) {
        (Some(MuS::Infinite), _) => Param::Fixed(Friction::Infinite),
        (Some(MuS::Coulomb(mu_s)), Some(mu_k)) => Param::Fixed(Friction::Coulomb { mu_s, mu_k }),
        (Some(MuS::Coulomb(mu_s)), None) => match spec_friction {
            Some((_, ratio)) if ratio.is_drawn() => {
                drawn.mu_s = Some(Value::Fixed(mu_s));
                drawn.mu_k_over_mu_s = Some(ratio);
                Param::Drawn
            }
            Some((_, ratio)) => Param::Fixed(Friction::Coulomb {
                mu_s,
                mu_k: mu_s * ratio.at(0.0),
            }),
            None => Param::Fixed(Friction::Coulomb { mu_s, mu_k: mu_s }),
        },
        (None, _) => match spec_friction {
            Some((mu_s, ratio)) => {
                drawn.mu_s = Some(mu_s);
                drawn.mu_k_over_mu_s = Some(ratio);
                if mu_s.is_drawn() || ratio.is_drawn() {
                    Param::Drawn
                } else {
                    let s = mu_s.at(0.0);
                    Param::Fixed(Friction::Coulomb {
                        mu_s: s,
                        mu_k: s * ratio.at(0.0),
                    })
                }
            }
            None => match study.frictions.as_slice() {
                [Param::Fixed(f)] => Param::Fixed(*f),
                values => {
                    return Err(err(format!(
                        "kind \"{}\" has no mu_s, and the spec gives {} friction models in \
                         grid.friction: give the kind mu_s (and mu_k), or the spec one \
                         grid.friction entry or an [uncertainty] mu_s with mu_k_over_mu_s",
                        kind.name,
                        values.len()
                    )));
                }
            },
        },
    };
    if !friction.is_drawn() {
        drawn.mu_s = None;
        drawn.mu_k_over_mu_s = None;
    }
    let case = Case {
        aspect: Param::Fixed(kind.aspect),
        width: Param::Fixed(kind.width),
        restitution,
        friction,
        stack: None,
    };
    let uncertainty = (restitution.is_drawn() || friction.is_drawn()).then_some(drawn);
    let model = KindModel {
        case,
        uncertainty,
        draws: settings.draws,
        seating: settings.seating,
        seating_seed: seed ^ SEATING_TAG,
    };
    // Every draw must make a valid block: check the fixed values, and the
    // drawn ones at the ends of the range a draw can reach (the uniforms
    // are in [0, U_MAX]: an unbounded lognormal's quantile at 1 is +∞,
    // which no draw gives).
    for u in [0.0, 0.5, crate::uncertainty::U_MAX] {
        let c = match &model.uncertainty {
            None => analysis_values(None, &model.case, 0, 0, 0),
            Some(d) => d.at_quantile(&model.case, u),
        };
        let c = seated(c, 1.0 - settings.seating);
        analysis(&c, study.g).map_err(|e| {
            err(format!(
                "kind \"{}\" makes no block rockfrag can simulate: {e}",
                kind.name
            ))
        })?;
    }
    Ok(model)
}

/// The analysis (at rest) of a kind's block, validated.
pub fn analysis(case: &CaseValues, g: f64) -> Result<Analysis> {
    let analysis = case.analysis(g)?;
    analysis.validate()?;
    Ok(analysis)
}

/// What a survey's `slid` column counts: standing objects whose measure
/// (`slip_max` or `slip_final`, m) went above `exceeds`.
#[derive(Clone, Debug, PartialEq)]
pub struct SlideRule {
    /// The limit state's name.
    pub name: String,
    /// Its measure: `slip_max` (true) or `slip_final` (false).
    pub slip_max: bool,
    /// Threshold, m.
    pub exceeds: f64,
}

impl SlideRule {
    /// Whether an outcome (of a block still standing) slid beyond the limit.
    pub fn slid(&self, o: &Outcome) -> bool {
        let m = if self.slip_max {
            o.slip_max
        } else {
            o.slip_final
        };
        m > self.exceeds
    }
}

/// The sliding limit state a survey's `slid` column refers to: `[infer]
/// slide_limit_state`, or the spec's one limit state on `slip_max` or
/// `slip_final`. `None` when the survey counts no slides.
///
/// Errors: [`Error::Parse`] on the survey's header when it counts slides and
/// the spec has no such limit state (or several, none chosen).
pub fn slide_rule(
    survey: &Survey,
    study: &Study,
    settings: &InferSettings,
    spec: &Path,
) -> Result<Option<SlideRule>> {
    if !survey.counts_slides() {
        return Ok(None);
    }
    let states: Vec<LimitState> = study
        .fragility
        .as_ref()
        .map(|f| f.limit_state.clone())
        .unwrap_or_default();
    let sliding: Vec<&LimitState> = states
        .iter()
        .filter(|l| matches!(l.measure.as_str(), "slip_max" | "slip_final"))
        .collect();
    let chosen = match &settings.slide_limit_state {
        Some(name) => states.iter().find(|l| &l.name == name),
        None if sliding.len() == 1 => Some(sliding[0]),
        None => None,
    };
    let line = survey
        .kinds
        .iter()
        .find(|k| k.slid.is_some())
        .map_or(0, |k| k.line);
    match chosen {
        Some(ls) if matches!(ls.measure.as_str(), "slip_max" | "slip_final") => {
            Ok(Some(SlideRule {
                name: ls.name.clone(),
                slip_max: ls.measure == "slip_max",
                exceeds: ls.exceeds.unwrap_or(0.0),
            }))
        }
        _ => Err(parse_err(
            &survey.path,
            line,
            format!(
                "column slid counts objects that slid, but the spec {} {}: add a \
                 [[fragility.limit_state]] with measure = \"slip_max\" (or \"slip_final\") and \
                 `exceeds` in m{}",
                spec.display(),
                match (&settings.slide_limit_state, sliding.len()) {
                    (Some(n), _) => format!("has no sliding limit state named \"{n}\""),
                    (None, 0) => "has no sliding limit state".to_string(),
                    (None, n) => format!(
                        "has {n} ({}), and [infer] slide_limit_state names none",
                        sliding
                            .iter()
                            .map(|l| l.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                },
                if sliding.len() > 1 {
                    ", or name one with [infer] slide_limit_state"
                } else {
                    ""
                }
            ),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Survey> {
        Survey::parse(text, Path::new("survey.csv"))
    }

    #[test]
    fn reads_required_and_optional_columns() {
        let s = parse(
            "# a comment\nname,width,aspect,count,overturned,restitution,mu_s,mu_k,slid\n\
             a,0.4,5,20,3,,,,\nb,0.5,4,10,0,0.2,0.6,0.5,2\nc,0.3,6,5,5,,inf,,0\n",
        )
        .unwrap();
        assert_eq!(s.kinds.len(), 3);
        assert_eq!(s.kinds[0].line, 3);
        assert_eq!(s.kinds[1].mu_k, Some(0.5));
        assert_eq!(s.kinds[2].mu_s, Some(MuS::Infinite));
        assert!(s.counts_slides());
    }

    #[test]
    fn faults_name_line_column_and_value() {
        let cases = [
            (
                "name,width,aspect,count,overturned\na,0.4,5,10,12\n",
                ":2:",
                "overturned",
            ),
            (
                "name,width,aspect,count,overturned,colour\n",
                ":1:",
                "colour",
            ),
            ("name,width,aspect,count\n", ":1:", "overturned"),
            (
                "name,width,aspect,count,overturned\na,-1,5,10,1\n",
                ":2:",
                "column 2 (width)",
            ),
            (
                "name,width,aspect,count,overturned\na,0.4,5,1.5,1\n",
                ":2:",
                "\"1.5\"",
            ),
            (
                "name,width,aspect,count,overturned\na,0.4,5,10\n",
                ":2:",
                "4 fields",
            ),
            (
                "name,width,aspect,count,overturned\na,0.4,5,10,1\na,0.4,5,10,1\n",
                ":3:",
                "line 2",
            ),
            (
                "name,width,aspect,count,overturned,mu_s,mu_k\na,0.4,5,10,1,0.5,0.6\n",
                ":2:",
                "mu_k",
            ),
            (
                "name,width,aspect,count,overturned,slid\na,0.4,5,10,8,3\n",
                ":2:",
                "slid",
            ),
            ("# only a comment\n", ":0:", "no header"),
        ];
        for (text, line, what) in cases {
            let e = parse(text).unwrap_err().to_string();
            assert!(
                e.contains("survey.csv") && e.contains(line) && e.contains(what),
                "{e}"
            );
        }
    }
}
