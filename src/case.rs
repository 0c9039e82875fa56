//! A **case**: one block configuration — aspect ratio H/B, base width 2B,
//! coefficient of restitution e and friction model — described once, for the
//! spec, the plan, every stage file, the fit, the figures and Python.
//!
//! A parameter is either fixed for the case or drawn per analysis (a spec's
//! `[uncertainty]`, or pooled on request with `rockfrag fragility --pool`):
//! [`Param::Fixed`] or [`Param::Drawn`]. One analysis has concrete values
//! only, a [`CaseValues`] (plain numbers, drawn values as drawn: no
//! parameter of it can be drawn); the case it belongs to marks the
//! parameters that vary from analysis to analysis as [`Param::Drawn`]
//! ([`CaseValues::pooled`]), and a fragility curve is fitted per such case,
//! over the draws.
//!
//! In a CSV file the case is six columns, `aspect,width,restitution,
//! friction,mu_s,mu_k` ([`CASE_COLUMNS`]): a drawn parameter is an empty
//! field (friction drawn: `coulomb` with `mu_s` and `mu_k` empty), and under
//! infinite friction `mu_s` and `mu_k` are empty. [`Case::fields`] writes
//! them and [`Case::parse`] reads them back, for every file that carries a
//! case.

use std::cmp::Ordering;
use std::hash::{Hash, Hasher};

use crate::io_util::number;
use crate::solver::{Analysis, Block, Friction};

/// A case parameter: fixed for the case, or drawn per analysis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Param<T> {
    /// The same value for every analysis of the case.
    Fixed(T),
    /// A value of its own for every analysis (the case pools over them).
    Drawn,
}

impl<T: Copy> Param<T> {
    /// The fixed value, `None` when drawn.
    pub fn fixed(self) -> Option<T> {
        match self {
            Param::Fixed(x) => Some(x),
            Param::Drawn => None,
        }
    }

    /// Whether the parameter is drawn per analysis.
    pub fn is_drawn(self) -> bool {
        matches!(self, Param::Drawn)
    }
}

/// A fixed parameter equals its value; a drawn one equals no value.
impl<T: PartialEq> PartialEq<T> for Param<T> {
    fn eq(&self, other: &T) -> bool {
        matches!(self, Param::Fixed(x) if x == other)
    }
}

impl Param<f64> {
    /// The value as text (Rust's shortest round-trip form), or `drawn`.
    pub fn text(self) -> String {
        match self {
            Param::Fixed(x) => x.to_string(),
            Param::Drawn => "drawn".to_string(),
        }
    }

    /// The value as a CSV field: the number (the shortest form that reads
    /// back exactly), or empty when drawn.
    pub fn field(self) -> String {
        self.fixed().map_or(String::new(), number)
    }

    /// Total order: fixed values by [`f64::total_cmp`], drawn last.
    pub fn total_cmp(&self, other: &Param<f64>) -> Ordering {
        match (self, other) {
            (Param::Fixed(a), Param::Fixed(b)) => a.total_cmp(b),
            (Param::Fixed(_), Param::Drawn) => Ordering::Less,
            (Param::Drawn, Param::Fixed(_)) => Ordering::Greater,
            (Param::Drawn, Param::Drawn) => Ordering::Equal,
        }
    }
}

/// One of the four parameters of a case, e.g. to pool a case over
/// ([`Case::pooled`]). `Friction` stands for μs and μk together.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Field {
    /// Aspect ratio H/B.
    Aspect,
    /// Base width 2B.
    Width,
    /// Coefficient of restitution e.
    Restitution,
    /// Friction coefficients μs, μk.
    Friction,
}

impl Field {
    /// Every field, in column order.
    pub const ALL: [Field; 4] = [
        Field::Aspect,
        Field::Width,
        Field::Restitution,
        Field::Friction,
    ];

    /// The field's name on the command line (`rockfrag fragility --pool`).
    pub fn name(self) -> &'static str {
        match self {
            Field::Aspect => "aspect",
            Field::Width => "width",
            Field::Restitution => "restitution",
            Field::Friction => "friction",
        }
    }

    /// The columns that hold the field (`mu_s, mu_k` for friction).
    pub fn columns(self) -> &'static str {
        match self {
            Field::Friction => "mu_s, mu_k",
            f => f.name(),
        }
    }
}

impl std::str::FromStr for Field {
    type Err = String;

    fn from_str(s: &str) -> Result<Field, String> {
        Field::ALL
            .into_iter()
            .find(|f| f.name() == s)
            .ok_or_else(|| format!("'{s}' is not one of width, aspect, restitution, friction"))
    }
}

/// The case columns of every file that carries a case, in order.
pub const CASE_COLUMNS: [&str; 6] = ["aspect", "width", "restitution", "friction", "mu_s", "mu_k"];

/// One block configuration (see the [module docs](self)), or the stack of a
/// study named by [`Case::stack`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Case {
    /// Aspect ratio H/B (> 0).
    pub aspect: Param<f64>,
    /// Base width 2B, m (> 0).
    pub width: Param<f64>,
    /// Coefficient of restitution e, in [0, 1].
    pub restitution: Param<f64>,
    /// Friction model; drawn friction is Coulomb with drawn μs and μk.
    pub friction: Param<Friction>,
    /// The stack this case is (`[[grid.stack]]`, by its name), `None` for
    /// one block on the ground. A stack's other four fields are its top
    /// body's aspect and width and the restitution and friction of the
    /// interface under that body (the six case columns of its rows); the
    /// stack itself is the study's ([`crate::spec::Study::stacks`]).
    pub stack: Option<StackName>,
}

/// The name of a study's stack (`[[grid.stack]] name`): 1 to
/// [`StackName::MAX`] ASCII letters, digits or `_` (what a case id may
/// hold: the case id is `stack_NAME`), held inline so a
/// [`Case`] stays `Copy`.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct StackName {
    len: u8,
    bytes: [u8; StackName::MAX],
}

impl StackName {
    /// The longest name, in bytes.
    pub const MAX: usize = 32;

    /// The name `text`, if it is one (1 to [`StackName::MAX`] ASCII
    /// letters, digits or `_`).
    pub fn new(text: &str) -> Option<StackName> {
        let ok = !text.is_empty()
            && text.len() <= StackName::MAX
            && text.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_');
        if !ok {
            return None;
        }
        let mut bytes = [0u8; StackName::MAX];
        bytes[..text.len()].copy_from_slice(text.as_bytes());
        Some(StackName {
            len: text.len() as u8,
            bytes,
        })
    }

    /// The name as text.
    pub fn as_str(&self) -> &str {
        std::str::from_utf8(&self.bytes[..self.len as usize]).expect("ASCII by construction")
    }

    /// The stack name in a case id (`stack_NAME`), if `id` is
    /// one: how a file that carries a case by its `case_id` names a stack.
    pub fn from_case_id(id: &str) -> Option<StackName> {
        id.strip_prefix("stack_").and_then(StackName::new)
    }
}

impl std::fmt::Debug for StackName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:?}", self.as_str())
    }
}

impl std::fmt::Display for StackName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One analysis's own block: the values of its case's parameters, those
/// drawn under `[uncertainty]` as drawn. Every parameter is a value, so code
/// that holds an analysis (a run's row, a history figure's block, a survey
/// kind's draw) cannot meet a drawn one; the [`Case`] it belongs to is
/// [`CaseValues::pooled`] over the drawn fields. A stack's values are its
/// top body's aspect and width and the interface under it ([`Case::stack`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CaseValues {
    /// Aspect ratio H/B (> 0).
    pub aspect: f64,
    /// Base width 2B, m (> 0).
    pub width: f64,
    /// Coefficient of restitution e, in [0, 1].
    pub restitution: f64,
    /// Friction model.
    pub friction: Friction,
    /// The stack this analysis is of, `None` for one block on the ground.
    pub stack: Option<StackName>,
}

impl CaseValues {
    /// One block on the ground with these values.
    pub fn block(aspect: f64, width: f64, restitution: f64, friction: Friction) -> CaseValues {
        CaseValues {
            aspect,
            width,
            restitution,
            friction,
            stack: None,
        }
    }

    /// The case this analysis belongs to when `fields` are drawn (or
    /// pooled): those fields marked [`Param::Drawn`], the others fixed at
    /// these values. Infinite friction stays infinite: only Coulomb
    /// coefficients are drawn.
    pub fn pooled(&self, fields: &[Field]) -> Case {
        Case::from(*self).pooled(fields)
    }

    /// The block these values make, at rest under gravity `g` (m/s²) on the
    /// ground: fails if they make no valid block. (A stack's scene is its
    /// study's: [`crate::spec::Study::stacks`].)
    pub fn analysis(&self, g: f64) -> crate::error::Result<Analysis> {
        let mut analysis = Analysis::new(Block::new(self.width, self.aspect, g)?, self.restitution);
        analysis.friction = self.friction;
        Ok(analysis)
    }

    /// Reads the six case columns of one analysis (in [`CASE_COLUMNS`]
    /// order, trimmed), as [`Case::parse`] does, but every field must hold
    /// a value (an analysis's row has no drawn parameter).
    ///
    /// Errors: the index (into the six) of the first bad field and what
    /// was expected there.
    pub fn parse(fields: [&str; 6]) -> Result<CaseValues, (usize, &'static str)> {
        let [aspect, width, restitution, friction, mu_s, mu_k] = fields;
        Ok(CaseValues::block(
            parse_number(0, aspect, POSITIVE)?,
            parse_number(1, width, POSITIVE)?,
            parse_number(2, restitution, FINITE)?,
            parse_friction(friction, mu_s, mu_k)?.ok_or((4, MU))?,
        ))
    }
}

/// A case of fixed values: the analysis's values, every parameter
/// [`Param::Fixed`].
impl From<CaseValues> for Case {
    fn from(v: CaseValues) -> Case {
        Case {
            aspect: Param::Fixed(v.aspect),
            width: Param::Fixed(v.width),
            restitution: Param::Fixed(v.restitution),
            friction: Param::Fixed(v.friction),
            stack: v.stack,
        }
    }
}

impl std::fmt::Display for CaseValues {
    /// As the case of fixed values prints ([`Case`]'s `Display`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        Case::from(*self).fmt(f)
    }
}

/// What [`parse_number`] accepts for H/B and 2B, and what it says otherwise.
const POSITIVE: (fn(f64) -> bool, &str) = (|x| x.is_finite() && x > 0.0, "a finite number > 0");
/// What [`parse_number`] accepts for e, and what it says otherwise.
const FINITE: (fn(f64) -> bool, &str) = (f64::is_finite, "a finite number");
/// What a μ column holds under Coulomb friction.
const MU: &str = "a number or inf under friction coulomb";

/// Case column `i`'s number, if it is one that `ok` accepts.
fn parse_number(
    i: usize,
    text: &str,
    (ok, expected): (fn(f64) -> bool, &'static str),
) -> Result<f64, (usize, &'static str)> {
    text.parse::<f64>()
        .ok()
        .filter(|&x| ok(x))
        .ok_or((i, expected))
}

/// The friction of the `friction`, `mu_s` and `mu_k` columns; `None` for
/// Coulomb friction with both μ empty (drawn, where a case allows it).
fn parse_friction(
    friction: &str,
    mu_s: &str,
    mu_k: &str,
) -> Result<Option<Friction>, (usize, &'static str)> {
    match friction {
        "inf" => {
            for (i, f) in [(4, mu_s), (5, mu_k)] {
                if !f.is_empty() {
                    return Err((i, "empty under friction inf"));
                }
            }
            Ok(Some(Friction::Infinite))
        }
        "coulomb" => match (mu_s.is_empty(), mu_k.is_empty()) {
            (true, true) => Ok(None),
            (true, _) => Err((4, MU)),
            (_, true) => Err((5, MU)),
            _ => {
                let mu = |i: usize, t: &str| {
                    t.parse::<f64>().ok().filter(|x| !x.is_nan()).ok_or((i, MU))
                };
                Ok(Some(Friction::Coulomb {
                    mu_s: mu(4, mu_s)?,
                    mu_k: mu(5, mu_k)?,
                }))
            }
        },
        _ => Err((3, "inf or coulomb")),
    }
}

/// One body of a stack's analysis as simulated (drawn values as drawn):
/// its own values and those of the interface under it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyValues {
    /// Width 2B, m.
    pub width: f64,
    /// Height 2H, m.
    pub height: f64,
    /// Mass, relative to the other bodies'.
    pub mass: f64,
    /// Offset of its centre from the centre of the body below, m.
    pub offset: f64,
    /// Restitution of the interface under it.
    pub restitution: f64,
    /// Friction of the interface under it.
    pub friction: Friction,
}

/// A stack's bodies by slot ([`crate::outcome::Slot::index`]; `None` for a
/// middle a stack of two has not).
pub type StackValues = [Option<BodyValues>; 3];

impl BodyValues {
    /// The bodies of `stack`, by slot.
    pub fn of(stack: &crate::solver::stack::Stack) -> StackValues {
        let n = stack.bodies.len();
        let mut out = [None; 3];
        for (i, (b, f)) in stack.bodies.iter().zip(&stack.interfaces).enumerate() {
            out[crate::outcome::Slot::of(i, n).index()] = Some(BodyValues {
                width: b.width,
                height: b.height,
                mass: b.mass,
                offset: b.offset,
                restitution: f.restitution,
                friction: f.friction,
            });
        }
        out
    }
}

/// What one analysis simulates, made from its [`Case`] (drawn values
/// drawn): one block on the ground, solved by the single block's solver,
/// or a stack, solved by the stack solver.
#[derive(Clone, Debug)]
pub enum Scene {
    /// One block.
    Block(crate::solver::Analysis),
    /// A stack of two or three blocks.
    Stack(crate::solver::stack::Stack),
}

impl Scene {
    /// The block, `None` for a stack.
    pub fn block(&self) -> Option<&crate::solver::Analysis> {
        match self {
            Scene::Block(a) => Some(a),
            Scene::Stack(_) => None,
        }
    }

    /// The block, for a caller whose studies are of blocks only (the
    /// paper's); a stack is refused.
    pub fn into_block(self) -> crate::error::Result<crate::solver::Analysis> {
        match self {
            Scene::Block(a) => Ok(a),
            Scene::Stack(_) => Err(crate::error::Error::invalid(
                "scene",
                "a stack",
                "one block (this command takes no stacks)",
            )),
        }
    }
}

// A case's numbers are never NaN (parsing and validation refuse it), so
// equality is an equivalence.
impl Eq for Case {}

impl Hash for Case {
    /// Hashes the bit patterns (−0.0 as 0.0, which compare equal).
    fn hash<H: Hasher>(&self, state: &mut H) {
        let bits = |p: Param<f64>| p.fixed().map(|x| (x + 0.0).to_bits());
        bits(self.aspect).hash(state);
        bits(self.width).hash(state);
        bits(self.restitution).hash(state);
        match self.friction {
            Param::Fixed(Friction::Infinite) => 0u8.hash(state),
            Param::Fixed(Friction::Coulomb { mu_s, mu_k }) => {
                1u8.hash(state);
                (mu_s + 0.0).to_bits().hash(state);
                (mu_k + 0.0).to_bits().hash(state);
            }
            Param::Drawn => 2u8.hash(state),
        }
        self.stack.hash(state);
    }
}

impl Case {
    /// A case of one block with every parameter fixed.
    pub fn fixed(aspect: f64, width: f64, restitution: f64, friction: Friction) -> Case {
        CaseValues::block(aspect, width, restitution, friction).into()
    }

    /// The values of a case none of whose parameters is drawn, `None` if
    /// one is.
    pub fn values(&self) -> Option<CaseValues> {
        Some(CaseValues {
            aspect: self.aspect.fixed()?,
            width: self.width.fixed()?,
            restitution: self.restitution.fixed()?,
            friction: self.friction.fixed()?,
            stack: self.stack,
        })
    }

    /// Whether `field` is drawn.
    pub fn is_drawn(&self, field: Field) -> bool {
        match field {
            Field::Aspect => self.aspect.is_drawn(),
            Field::Width => self.width.is_drawn(),
            Field::Restitution => self.restitution.is_drawn(),
            Field::Friction => self.friction.is_drawn(),
        }
    }

    /// The drawn fields, in column order.
    pub fn drawn(&self) -> Vec<Field> {
        Field::ALL
            .into_iter()
            .filter(|&f| self.is_drawn(f))
            .collect()
    }

    /// This case with `fields` drawn (or pooled) too: those fields marked
    /// [`Param::Drawn`]. Infinite friction stays infinite: only Coulomb
    /// coefficients are drawn. A stack's case is its stack, whose six
    /// columns are its top body's values as `[[grid.stack]]` gives them,
    /// drawn or not (its draws are `outcomes.csv`'s `SLOT.width`, … columns):
    /// it is left as it is.
    pub fn pooled(mut self, fields: &[Field]) -> Case {
        if self.stack.is_some() {
            return self;
        }
        for f in fields {
            match f {
                Field::Aspect => self.aspect = Param::Drawn,
                Field::Width => self.width = Param::Drawn,
                Field::Restitution => self.restitution = Param::Drawn,
                Field::Friction => {
                    if matches!(self.friction, Param::Fixed(Friction::Coulomb { .. })) {
                        self.friction = Param::Drawn;
                    }
                }
            }
        }
        self
    }

    /// The `friction` column's value: `inf` or `coulomb`.
    pub fn friction_name(&self) -> &'static str {
        match self.friction {
            Param::Fixed(Friction::Infinite) => "inf",
            _ => "coulomb",
        }
    }

    /// Static friction coefficient μs: `None` under infinite friction.
    pub fn mu_s(&self) -> Option<Param<f64>> {
        match self.friction {
            Param::Fixed(Friction::Infinite) => None,
            Param::Fixed(Friction::Coulomb { mu_s, .. }) => Some(Param::Fixed(mu_s)),
            Param::Drawn => Some(Param::Drawn),
        }
    }

    /// Kinetic friction coefficient μk: `None` under infinite friction.
    pub fn mu_k(&self) -> Option<Param<f64>> {
        match self.friction {
            Param::Fixed(Friction::Infinite) => None,
            Param::Fixed(Friction::Coulomb { mu_k, .. }) => Some(Param::Fixed(mu_k)),
            Param::Drawn => Some(Param::Drawn),
        }
    }

    /// Total order: aspect, width, restitution, then friction (infinite
    /// first, then Coulomb by (μs, μk), drawn last).
    pub fn total_cmp(&self, other: &Case) -> Ordering {
        self.aspect
            .total_cmp(&other.aspect)
            .then(self.width.total_cmp(&other.width))
            .then(self.restitution.total_cmp(&other.restitution))
            .then(cmp_friction(&self.friction, &other.friction))
            .then_with(|| {
                let name = |c: &Case| c.stack.map(|s| s.as_str().to_string());
                name(self).cmp(&name(other))
            })
    }

    /// The case's id, the same in every output that names a case (the
    /// `case_id` columns, OpenQuake's fragility function and exposure
    /// taxonomy, pelicun's component): letters, digits and `_` only, e.g.
    /// `a4_w0p5_e0_inf`, `a4_w0p5_e0p3_mus0p7_muk0p6` or
    /// `a5_wdrawn_edrawn_mudrawn`. Numbers are written in their shortest
    /// form with `.` as `p` (and an exponent's `-` as `m`).
    pub fn id(&self) -> String {
        if let Some(stack) = self.stack {
            return format!("stack_{stack}");
        }
        let num = |x: Param<f64>| -> String {
            x.text()
                .chars()
                .map(|c| match c {
                    '.' => 'p',
                    '-' => 'm',
                    '+' => 'P',
                    c if c.is_ascii_alphanumeric() => c,
                    _ => '_',
                })
                .collect()
        };
        let friction = match self.friction {
            Param::Fixed(Friction::Infinite) => "inf".to_string(),
            Param::Fixed(Friction::Coulomb { mu_s, mu_k }) => format!(
                "mus{}_muk{}",
                num(Param::Fixed(mu_s)),
                num(Param::Fixed(mu_k))
            ),
            Param::Drawn => "mudrawn".to_string(),
        };
        format!(
            "a{}_w{}_e{}_{friction}",
            num(self.aspect),
            num(self.width),
            num(self.restitution)
        )
    }

    /// The six case columns, comma-separated, as every file writes them.
    pub fn fields(&self) -> String {
        let opt = |p: Option<Param<f64>>| p.map_or(String::new(), Param::field);
        format!(
            "{},{},{},{},{},{}",
            self.aspect.field(),
            self.width.field(),
            self.restitution.field(),
            self.friction_name(),
            opt(self.mu_s()),
            opt(self.mu_k())
        )
    }

    /// Reads the six case columns (in [`CASE_COLUMNS`] order, trimmed) of
    /// a fitted case: H/B and 2B finite and > 0, e finite, `friction` `inf`
    /// (μ columns empty) or `coulomb` (μs, μk numbers, `inf` allowed, or
    /// both empty for drawn friction); an empty H/B, 2B or e is a drawn
    /// parameter. An analysis's row is read by [`CaseValues::parse`].
    ///
    /// Errors: the index (into the six) of the first bad field and what
    /// was expected there.
    pub fn parse(fields: [&str; 6]) -> Result<Case, (usize, &'static str)> {
        let [aspect, width, restitution, friction, mu_s, mu_k] = fields;
        let number = |i: usize, text: &str, rule| {
            if text.is_empty() {
                return Ok(Param::Drawn);
            }
            parse_number(i, text, rule).map(Param::Fixed)
        };
        Ok(Case {
            aspect: number(0, aspect, POSITIVE)?,
            width: number(1, width, POSITIVE)?,
            restitution: number(2, restitution, FINITE)?,
            friction: parse_friction(friction, mu_s, mu_k)?.map_or(Param::Drawn, Param::Fixed),
            stack: None,
        })
    }
}

impl std::fmt::Display for Case {
    /// `H/B=4 2B=0.5 e=0 inf`, or `… coulomb μs=0.7 μk=0.6`; a drawn
    /// parameter reads `drawn` (`e=drawn`, `coulomb μs=drawn μk=drawn`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if let Some(stack) = self.stack {
            return write!(f, "stack {stack}");
        }
        write!(
            f,
            "H/B={} 2B={} e={} {}",
            self.aspect.text(),
            self.width.text(),
            self.restitution.text(),
            self.friction_name()
        )?;
        if let (Some(s), Some(k)) = (self.mu_s(), self.mu_k()) {
            write!(f, " μs={} μk={}", s.text(), k.text())?;
        }
        Ok(())
    }
}

/// Total order on friction models: infinite first, then Coulomb by (μs,
/// μk), drawn last.
pub fn cmp_friction(a: &Param<Friction>, b: &Param<Friction>) -> Ordering {
    let key = |f: &Param<Friction>| match *f {
        Param::Fixed(Friction::Infinite) => (0, 0.0, 0.0),
        Param::Fixed(Friction::Coulomb { mu_s, mu_k }) => (1, mu_s, mu_k),
        Param::Drawn => (2, 0.0, 0.0),
    };
    let (ka, kb) = (key(a), key(b));
    ka.0.cmp(&kb.0)
        .then(ka.1.total_cmp(&kb.1))
        .then(ka.2.total_cmp(&kb.2))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn coulomb(mu_s: f64, mu_k: f64) -> Friction {
        Friction::Coulomb { mu_s, mu_k }
    }

    /// Writing and reading the case columns gives the case back, drawn
    /// parameters as empty fields.
    #[test]
    fn fields_round_trip() {
        let concrete = Case::fixed(4.0, 0.5, 0.3, coulomb(0.7, f64::INFINITY));
        assert_eq!(concrete.fields(), "4,0.5,0.3,coulomb,0.7,inf");
        let pooled = concrete.pooled(&[Field::Restitution, Field::Friction]);
        assert_eq!(pooled.fields(), "4,0.5,,coulomb,,");
        assert_eq!(
            pooled.to_string(),
            "H/B=4 2B=0.5 e=drawn coulomb μs=drawn μk=drawn"
        );
        for case in [concrete, pooled] {
            let text = case.fields();
            let f: Vec<&str> = text.split(',').collect();
            let back = Case::parse([f[0], f[1], f[2], f[3], f[4], f[5]]).unwrap();
            assert_eq!(back, case);
        }
        // An analysis's row must be concrete.
        assert_eq!(
            CaseValues::parse(["4", "0.5", "", "inf", "", ""]),
            Err((2, "a finite number"))
        );
        assert_eq!(
            CaseValues::parse(["4", "0.5", "0.3", "coulomb", "", ""]),
            Err((4, MU))
        );
        assert_eq!(
            CaseValues::parse(["4", "0.5", "0.3", "coulomb", "0.7", "inf"]),
            Ok(CaseValues::block(
                4.0,
                0.5,
                0.3,
                coulomb(0.7, f64::INFINITY)
            ))
        );
        // Infinite friction is never drawn.
        let inf = Case::fixed(4.0, 0.5, 0.0, Friction::Infinite);
        assert_eq!(inf.pooled(&[Field::Friction]), inf);
    }

    /// Case ids keep to letters, digits and `_` (what NRML and pelicun
    /// accept) and tell cases apart.
    #[test]
    fn ids() {
        let a = Case::fixed(4.0, 0.5, 0.0, Friction::Infinite);
        assert_eq!(a.id(), "a4_w0p5_e0_inf");
        let b = Case::fixed(4.0, 0.5, 0.3, coulomb(0.7, f64::INFINITY));
        assert_eq!(b.id(), "a4_w0p5_e0p3_mus0p7_mukinf");
        let c = b.pooled(&[Field::Width, Field::Restitution, Field::Friction]);
        assert_eq!(c.id(), "a4_wdrawn_edrawn_mudrawn");
        let tiny = Case::fixed(4.0, 0.5, 1e-5, Friction::Infinite);
        for id in [a.id(), b.id(), c.id(), tiny.id()] {
            assert!(
                id.chars().all(|ch| ch.is_ascii_alphanumeric() || ch == '_'),
                "{id}"
            );
        }
    }

    /// Drawn sorts after every fixed value; −0 and 0 are one case.
    #[test]
    fn order_and_hash() {
        let a = Case::fixed(4.0, 0.5, 0.0, Friction::Infinite);
        let b = a.pooled(&[Field::Aspect]);
        assert_eq!(a.total_cmp(&b), Ordering::Less);
        let minus = Case::fixed(4.0, 0.5, -0.0, Friction::Infinite);
        let mut set = std::collections::HashSet::new();
        set.insert(a);
        assert!(set.contains(&minus));
        assert!(!set.contains(&b));
    }
}
