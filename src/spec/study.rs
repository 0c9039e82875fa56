//! The validated stage: a [`Study`] is everything a run needs, every value
//! in range. It is built only by [`SpecFile::validate`], and written back as
//! canonical spec text by [`Study::to_toml`].

use super::raw::{
    FrictionEntry, GridFile, LevelRange, Levels, MotionFile, OutputFile, RecordEntry, SpecFile,
    SupportFile, UncertaintyFile,
};
use crate::case::{Case, CaseValues, Field, Param};
use crate::error::{Error, Result};
use crate::fragility::FragilityOptions;
use crate::im::Im;
use crate::motion::{Floor, SynthesisSettings};
use crate::solver::{Friction, SolverSettings};
use crate::uncertainty::{
    Distribution, Property, Value, analysis_seed, orientation_uniform, uniforms,
};
use std::path::{Path, PathBuf};

/// The paper's study (Shenton and Jones), the default of `rockfrag run`.
pub const SHENTON_JONES_TOML: &str = include_str!("../../studies/shenton-jones.toml");

/// Name used in messages for the embedded paper study.
pub const SHENTON_JONES_ORIGIN: &str = "shenton-jones.toml (built-in)";

/// A validated study: everything a run needs, every value in range.
#[derive(Clone, Debug, PartialEq)]
pub struct Study {
    /// Study name (letters, digits, `.`, `_`, `-`).
    pub name: String,
    /// Free text.
    pub description: String,
    /// Gravity, m/s².
    pub g: f64,
    /// Where the records come from.
    pub motions: Motions,
    /// What the blocks stand on: the ground ([`Floor::ground`], no modes)
    /// or a floor of a linear building (`[support] floor`). The intensity
    /// levels are the ground's; each record is filtered through the floor
    /// after it is scaled.
    pub floor: Floor,
    /// Intensity levels.
    pub intensity: Intensity,
    /// Base widths 2B, m: the grid's values, or the one [`Param::Drawn`]
    /// when `[uncertainty]` draws the width (one case pools all its draws).
    pub widths: Vec<Param<f64>>,
    /// Aspect ratios H/B (or the one [`Param::Drawn`]).
    pub aspects: Vec<Param<f64>>,
    /// Coefficients of restitution (or the one [`Param::Drawn`]).
    pub restitutions: Vec<Param<f64>>,
    /// Friction models (or the one [`Param::Drawn`]: Coulomb friction with
    /// μs or μk/μs drawn per analysis).
    pub frictions: Vec<Param<Friction>>,
    /// Stacks of two or three blocks (`[[grid.stack]]`), each a case after
    /// the block cases, in the order given.
    pub stacks: Vec<super::stack::StudyStack>,
    /// Block parameters drawn per analysis, if any.
    pub uncertainty: Option<Uncertainty>,
    /// Solver settings.
    pub solver: SolverSettings,
    /// Output options.
    pub output: OutputFile,
    /// Fragility fit on completion, if the spec asks for one.
    pub fragility: Option<FragilityOptions>,
    /// `rockfrag infer`'s settings, if the spec has an `[infer]` table.
    pub infer: Option<super::infer::InferSettings>,
    /// An adaptive run (`grid.pga = { min, max }` with `[fragility]
    /// precision`): its range; [`Study::intensity`] then holds the lattice
    /// of levels it chooses from ([`crate::fragility::lattice`]).
    pub adaptive: Option<Adaptive>,
}

/// What an adaptive study asks for (docs/adaptive.md): levels placed in a
/// range of PGA or PGV, records added, until the band of every limit
/// state's median and β is as narrow as asked, per case.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Adaptive {
    /// The IM of the levels: [`Im::PGA`] (g) or [`Im::PGV`] (m/s).
    pub im: Im,
    /// The range of the levels, in the IM's unit.
    pub range: LevelRange,
    /// The target half-widths.
    pub precision: crate::fragility::Precision,
    /// The most analyses per case.
    pub max_analyses: usize,
}

/// The validated `[uncertainty]` table: what each analysis draws, per
/// block property (`None`: from the grid).
#[derive(Clone, Debug, PartialEq)]
pub struct Uncertainty {
    /// Seed of the draws.
    pub seed: u64,
    /// Base width 2B, m.
    pub width: Option<Value>,
    /// Aspect ratio H/B.
    pub aspect: Option<Value>,
    /// Coefficient of restitution e.
    pub restitution: Option<Value>,
    /// Static friction coefficient μs (with `mu_k_over_mu_s`).
    pub mu_s: Option<Value>,
    /// μk/μs (with `mu_s`).
    pub mu_k_over_mu_s: Option<Value>,
    /// What the study's stacks draw (`[uncertainty.stack.NAME.BODY]`), one
    /// entry per stack that draws, in the order of their names.
    pub stacks: Vec<super::stack_draws::StackDraws>,
}

impl Uncertainty {
    /// The value given for `property`, if any.
    pub fn get(&self, property: Property) -> Option<&Value> {
        match property {
            Property::Width => self.width.as_ref(),
            Property::Aspect => self.aspect.as_ref(),
            Property::Restitution => self.restitution.as_ref(),
            Property::MuS => self.mu_s.as_ref(),
            Property::MuKOverMuS => self.mu_k_over_mu_s.as_ref(),
        }
    }

    /// Whether `property` is drawn (not fixed, not from the grid).
    pub fn is_drawn(&self, property: Property) -> bool {
        self.get(property).is_some_and(Value::is_drawn)
    }

    /// The case fields that vary from analysis to analysis, in column order.
    pub fn drawn(&self) -> Vec<Field> {
        let drawn = |p| self.is_drawn(p);
        [
            (Field::Aspect, drawn(Property::Aspect)),
            (Field::Width, drawn(Property::Width)),
            (Field::Restitution, drawn(Property::Restitution)),
            (
                Field::Friction,
                drawn(Property::MuS) || drawn(Property::MuKOverMuS),
            ),
        ]
        .into_iter()
        .filter_map(|(f, d)| d.then_some(f))
        .collect()
    }

    /// The block of the analysis of case `case` (number `number` in
    /// canonical order) on record `record` at level `level`: each property
    /// given here replaces the case's, drawn from the stream
    /// [`analysis_seed`]`(seed, record, level, number)`; the others keep the
    /// case's fixed values ([`analysis_values`]).
    pub fn draw(&self, case: &Case, record: usize, level: usize, number: usize) -> CaseValues {
        let u = uniforms(analysis_seed(
            self.seed,
            record as u64,
            level as u64,
            number as u64,
        ));
        self.at(case, u)
    }

    /// The block of case `case` with every property given here at
    /// quantile `q` of its distribution (the ends of what a draw can reach,
    /// to check that every draw makes a valid block).
    pub fn at_quantile(&self, case: &Case, q: f64) -> CaseValues {
        self.at(case, [q; Property::ALL.len()])
    }

    /// The block of case `case` with each property given here at its
    /// uniform in `u` (one per property, in the order of
    /// [`Property::ALL`]), the others at the case's fixed values: `case`'s
    /// drawn parameters are the ones given here (validation makes it so
    /// for a study's cases).
    fn at(&self, case: &Case, u: [f64; Property::ALL.len()]) -> CaseValues {
        let value = |p: Property, grid: Param<f64>| match self.get(p) {
            Some(v) => v.at(u[p.index()]),
            None => grid
                .fixed()
                .expect("a parameter not drawn is fixed by the grid"),
        };
        let friction = match (&self.mu_s, &self.mu_k_over_mu_s) {
            (Some(s), Some(r)) => {
                let mu_s = s.at(u[Property::MuS.index()]);
                // μk = μs · (μk/μs): μk ≤ μs by construction.
                Friction::Coulomb {
                    mu_s,
                    mu_k: mu_s * r.at(u[Property::MuKOverMuS.index()]),
                }
            }
            _ => case
                .friction
                .fixed()
                .expect("friction not drawn is fixed by the grid"),
        };
        CaseValues {
            stack: case.stack,
            ..CaseValues::block(
                value(Property::Aspect, case.aspect),
                value(Property::Width, case.width),
                value(Property::Restitution, case.restitution),
                friction,
            )
        }
    }
}

/// The values of one analysis of case `case` (number `number` in its
/// canonical order) on record `record` at level `level`: the parameters of
/// `uncertainty` drawn ([`Uncertainty::draw`]), or the case's own values
/// when nothing is drawn. The one place where a case that may be drawn
/// becomes an analysis's [`CaseValues`]: `case`'s drawn parameters are the
/// ones `uncertainty` draws (validation makes it so for a study's cases,
/// and [`crate::infer`] for a surveyed kind's).
pub fn analysis_values(
    uncertainty: Option<&Uncertainty>,
    case: &Case,
    record: usize,
    level: usize,
    number: usize,
) -> CaseValues {
    match uncertainty {
        Some(u) => u.draw(case, record, level, number),
        None => case
            .values()
            .expect("a case with nothing drawn has every parameter fixed"),
    }
}

/// The ground motions of a study.
#[derive(Clone, Debug, PartialEq)]
pub enum Motions {
    /// A synthetic ensemble: record i is `Synthesizer::generate(seed, i, …)`.
    Synthetic {
        /// Generator settings (its `g` equals the study's).
        settings: SynthesisSettings,
        /// Ensemble seed.
        seed: u64,
        /// Records per intensity level (for pairs: pairs, times the angles
        /// of a grid of orientations, see [`Orientation::per_pair`]).
        records: usize,
        /// `None`: one horizontal component per record. Some: two
        /// independent components per record (`components = 2`), H1 the
        /// ensemble's record and H2 the same index of a second ensemble
        /// ([`crate::motion::second_component_seed`]), scaled as a pair by
        /// its RotD50 and turned to the direction the blocks face.
        pairs: Option<Orientation>,
    },
    /// Recorded motions, each scaled to every intensity level.
    Files(Vec<RecordFile>),
    /// Recorded motions as pairs of horizontal components (H1, H2), each
    /// pair scaled to every intensity level by its RotD50 (PGA or PGV
    /// levels) or by the factor; the blocks feel the component along the
    /// direction they face, cos φ·H1 + sin φ·H2.
    Pairs {
        /// The pairs, H1 then H2.
        pairs: Vec<[RecordFile; 2]>,
        /// The directions the blocks face.
        orientation: Orientation,
    },
}

impl Motions {
    /// The directions the blocks face, for motions in pairs (recorded or
    /// synthetic); `None` for single components.
    pub fn orientation(&self) -> Option<&Orientation> {
        match self {
            Motions::Synthetic { pairs, .. } => pairs.as_ref(),
            Motions::Files(_) => None,
            Motions::Pairs { orientation, .. } => Some(orientation),
        }
    }

    /// Every record file, in the spec's order (a pair's H1 then H2); none
    /// for a synthetic ensemble.
    pub fn files(&self) -> Vec<&RecordFile> {
        match self {
            Motions::Synthetic { .. } => Vec::new(),
            Motions::Files(files) => files.iter().collect(),
            Motions::Pairs { pairs, .. } => pairs.iter().flatten().collect(),
        }
    }

    /// As [`Motions::files`], to change their paths.
    pub fn files_mut(&mut self) -> Vec<&mut RecordFile> {
        match self {
            Motions::Synthetic { .. } => Vec::new(),
            Motions::Files(files) => files.iter_mut().collect(),
            Motions::Pairs { pairs, .. } => pairs.iter_mut().flatten().collect(),
        }
    }
}

/// The directions φ (degrees from H1 towards H2) the blocks of a study of
/// record pairs face.
///
/// With a grid, ensemble member `record` is pair `record / n` at angle
/// `angles[record % n]` (n angles): every pair at every angle, a stratified
/// sample of the orientation. Drawn, member `record` is pair `record` at an
/// angle drawn per record ([`crate::uncertainty::orientation_uniform`]).
/// Either way the blocks under a member face the same way at every level
/// and in every case, and a case's curve
/// pools over the orientations as over the records: the azimuth of a
/// record's H1 is arbitrary from record to record, so an angle to it means
/// something only as a sample of the object's unknown orientation.
#[derive(Clone, Debug, PartialEq)]
pub enum Orientation {
    /// Every pair at each of these angles, degrees (`grid.orientation`, or a
    /// fixed `uncertainty.orientation`).
    Grid(Vec<f64>),
    /// One angle per unit drawn from `dist` with `seed`
    /// (`uncertainty.orientation`; by default uniform on [0°, 180°)).
    Drawn {
        /// The distribution of φ, degrees.
        dist: Distribution,
        /// Seed of the draws (`uncertainty.seed`).
        seed: u64,
    },
}

impl Orientation {
    /// The default: φ uniform on [0°, 180°) (a(φ + 180°) = −a(φ), so the
    /// half turn covers every direction of rocking).
    pub fn unknown(seed: u64) -> Orientation {
        Orientation::Drawn {
            dist: Distribution::Uniform {
                min: 0.0,
                max: 180.0,
            },
            seed,
        }
    }

    /// Ensemble members per pair: the grid's angles, or 1 when drawn.
    pub fn per_pair(&self) -> usize {
        match self {
            Orientation::Grid(angles) => angles.len(),
            Orientation::Drawn { .. } => 1,
        }
    }

    /// The pair of ensemble member `record`.
    pub fn pair_of(&self, record: usize) -> usize {
        record / self.per_pair()
    }

    /// The pair and the angle φ (degrees) of ensemble member `record`.
    pub fn member(&self, record: usize) -> (usize, f64) {
        let angle = match self {
            Orientation::Grid(angles) => angles[record % angles.len()],
            Orientation::Drawn { dist, seed } => {
                dist.quantile(orientation_uniform(*seed, record as u64))
            }
        };
        (self.pair_of(record), angle)
    }
}

/// A recorded-motion file of a study.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordFile {
    /// The path as written in the spec (relative to the spec file).
    pub given: String,
    /// The path to open.
    pub path: PathBuf,
}

/// Intensity levels of a study.
#[derive(Clone, Debug, PartialEq)]
pub enum Intensity {
    /// Peak ground accelerations, g.
    Pga(Vec<f64>),
    /// Peak ground velocities, m/s.
    Pgv(Vec<f64>),
    /// Factors the recorded motions are multiplied by (each analysis's IM is
    /// then its record's own measured PGA or PGV).
    Scale(Vec<f64>),
}

impl Intensity {
    /// The levels, in the spec's order.
    pub fn levels(&self) -> &[f64] {
        match self {
            Intensity::Pga(v) | Intensity::Pgv(v) | Intensity::Scale(v) => v,
        }
    }
}

/// The largest spec file read: 16 MiB (a spec is a few kB; a grid of
/// 10⁵ values is 1 MB).
pub const MAX_SPEC_BYTES: u64 = 16 << 20;

impl Study {
    /// Reads and validates a spec file; record files are relative to its
    /// folder. A file of more than [`MAX_SPEC_BYTES`] (a link to
    /// `/dev/zero`) is refused before it is read.
    pub fn load(path: &Path) -> Result<Study> {
        let text = crate::io_util::read_text_limited(path, MAX_SPEC_BYTES, "a study spec")
            .map_err(Error::io(path))?;
        Study::from_toml(&text, path)
    }

    /// The paper's study, embedded in the binary.
    pub fn shenton_jones() -> Study {
        Study::from_toml(SHENTON_JONES_TOML, Path::new(SHENTON_JONES_ORIGIN))
            .expect("the embedded paper study is valid")
    }

    /// Parses and validates spec text. `origin` is the spec's path: it names
    /// the file in errors, gives the default name and the folder that record
    /// files are relative to. Record files must exist.
    pub fn from_toml(text: &str, origin: &Path) -> Result<Study> {
        SpecFile::parse(text, origin)?.validate(text, origin, true)
    }

    /// As [`Study::from_toml`], without checking that record files exist
    /// (for reading back the spec recorded in a manifest).
    pub fn from_toml_unchecked(text: &str, origin: &Path) -> Result<Study> {
        SpecFile::parse(text, origin)?.validate(text, origin, false)
    }

    /// The raw form of this study with every default written out.
    pub fn to_spec_file(&self) -> SpecFile {
        let components =
            matches!(self.motions, Motions::Synthetic { pairs: Some(_), .. }).then_some(2);
        let (seed, records, record_files, motion) = match &self.motions {
            Motions::Synthetic {
                settings,
                seed,
                records,
                ..
            } => (
                Some(*seed),
                Some(*records),
                Vec::new(),
                Some(MotionFile::from_settings(settings)),
            ),
            Motions::Files(files) => (
                None,
                None,
                files
                    .iter()
                    .map(|f| RecordEntry::One(f.given.clone()))
                    .collect(),
                None,
            ),
            Motions::Pairs { pairs, .. } => (
                None,
                None,
                pairs
                    .iter()
                    .map(|[h1, h2]| RecordEntry::Pair([h1.given.clone(), h2.given.clone()]))
                    .collect(),
                None,
            ),
        };
        let orientation = self.motions.orientation();
        let (grid_orientation, drawn_orientation, orientation_seed) = match orientation {
            Some(Orientation::Grid(angles)) => (Some(angles.clone()), None, None),
            Some(Orientation::Drawn { dist, seed }) => {
                (None, Some(Value::Drawn(*dist)), Some(*seed))
            }
            None => (None, None, None),
        };
        let drawn = |p: Property| {
            self.uncertainty
                .as_ref()
                .is_some_and(|u| u.get(p).is_some())
        };
        // a study of stacks alone writes no block lists
        let blocks = !self.aspects.is_empty();
        let grid_list = |p: Property, v: &[Param<f64>]| {
            (blocks && !drawn(p)).then(|| v.iter().filter_map(|x| x.fixed()).collect())
        };
        let (pga, pgv, scale_factors) = match &self.intensity {
            _ if self.adaptive.is_some_and(|a| a.im == Im::PGV) => {
                (None, self.adaptive.map(|a| Levels::Range(a.range)), None)
            }
            _ if self.adaptive.is_some() => {
                (self.adaptive.map(|a| Levels::Range(a.range)), None, None)
            }
            Intensity::Pga(v) => (Some(Levels::List(v.clone())), None, None),
            Intensity::Pgv(v) => (None, Some(Levels::List(v.clone())), None),
            Intensity::Scale(v) => (None, None, Some(v.clone())),
        };
        SpecFile {
            name: Some(self.name.clone()),
            description: self.description.clone(),
            g: Some(self.g),
            seed,
            records,
            components,
            record_files,
            motion,
            // the ground writes no [support]: a study without one keeps its hash
            support: (!self.floor.modes.is_empty()).then(|| SupportFile {
                floor: self.floor.modes.clone(),
            }),
            grid: GridFile {
                width: grid_list(Property::Width, &self.widths),
                aspect: grid_list(Property::Aspect, &self.aspects),
                restitution: grid_list(Property::Restitution, &self.restitutions),
                friction: (blocks && !drawn(Property::MuS)).then(|| {
                    self.frictions
                        .iter()
                        .filter_map(|f| f.fixed().map(FrictionEntry))
                        .collect()
                }),
                pga,
                pgv,
                scale_factors,
                orientation: grid_orientation,
                stack: self
                    .stacks
                    .iter()
                    .map(|s| s.to_entry(self.stack_draws(s.name).is_some()))
                    .collect(),
            },
            uncertainty: match (&self.uncertainty, drawn_orientation) {
                (Some(u), orientation) => Some(UncertaintyFile {
                    seed: Some(u.seed),
                    width: u.width,
                    aspect: u.aspect,
                    restitution: u.restitution,
                    mu_s: u.mu_s,
                    mu_k_over_mu_s: u.mu_k_over_mu_s,
                    orientation,
                    stack: super::stack_draws::to_table(&u.stacks),
                }),
                (None, Some(orientation)) => Some(UncertaintyFile {
                    seed: orientation_seed,
                    orientation: Some(orientation),
                    ..UncertaintyFile::default()
                }),
                (None, None) => None,
            },
            solver: self.solver,
            output: self.output,
            fragility: self.fragility.clone(),
            infer: self.infer.clone(),
        }
    }

    /// The canonical spec text: this study as TOML with every default written
    /// out. Parsing it (from the same folder) gives this study back.
    pub fn to_toml(&self) -> String {
        toml::to_string(&self.to_spec_file()).expect("a study serialises to TOML")
    }

    /// Stable 64-bit hash of the study: FNV-1a of [`Study::to_toml`].
    pub fn hash(&self) -> u64 {
        fnv1a64(self.to_toml().as_bytes())
    }

    /// Stable 64-bit hash of what decides the analyses: [`Study::hash`] of
    /// the study without its name, description, `[fragility]`,
    /// `output.summary` and `output.figures`, which only change what is made
    /// from `outcomes.csv`. A run resumes, and a finished run is reused,
    /// when this hash matches.
    pub fn analyses_hash(&self) -> u64 {
        let defaults = OutputFile::default();
        let analyses = Study {
            name: String::new(),
            description: String::new(),
            // an adaptive run's fit decides which analyses it runs
            fragility: self.adaptive.and(self.fragility.clone()),
            output: OutputFile {
                summary: defaults.summary,
                figures: defaults.figures,
                ..self.output
            },
            ..self.clone()
        };
        analyses.hash()
    }

    /// What stack `name` draws per analysis, if it draws anything.
    pub fn stack_draws(
        &self,
        name: crate::case::StackName,
    ) -> Option<&super::stack_draws::StackDraws> {
        self.uncertainty
            .as_ref()?
            .stacks
            .iter()
            .find(|d| d.stack == name)
    }

    /// The case fields drawn per analysis (none without `[uncertainty]`).
    pub fn drawn(&self) -> Vec<Field> {
        self.uncertainty
            .as_ref()
            .map_or_else(Vec::new, Uncertainty::drawn)
    }

    /// Number of records per intensity level.
    pub fn records(&self) -> usize {
        match &self.motions {
            Motions::Synthetic {
                records,
                pairs: Some(orientation),
                ..
            } => records * orientation.per_pair(),
            Motions::Synthetic { records, .. } => *records,
            Motions::Files(files) => files.len(),
            Motions::Pairs { pairs, orientation } => pairs.len() * orientation.per_pair(),
        }
    }

    /// What `record_file` says of ensemble member `record` (recorded motions
    /// only): the file as the spec names it, or a pair's two files joined by
    /// ` + `.
    pub fn record_file(&self, record: usize) -> Option<String> {
        match &self.motions {
            Motions::Synthetic { .. } => None,
            Motions::Files(files) => Some(files[record].given.clone()),
            Motions::Pairs { pairs, orientation } => {
                let [h1, h2] = &pairs[orientation.pair_of(record)];
                Some(format!("{} + {}", h1.given, h2.given))
            }
        }
    }
}

pub use crate::io_util::fnv1a64;

/// A friction model as text: `inf` or `coulomb(μs, μk)`; `coulomb(drawn)`
/// when its coefficients are drawn per analysis.
pub fn friction_label(f: Param<Friction>) -> String {
    match f {
        Param::Fixed(Friction::Infinite) => "inf".to_string(),
        Param::Drawn => "coulomb(drawn)".to_string(),
        Param::Fixed(Friction::Coulomb { mu_s, mu_k }) => {
            format!("coulomb(mu_s = {mu_s}, mu_k = {mu_k})")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_reference_values() {
        assert_eq!(fnv1a64(b""), 0xcbf29ce484222325);
        assert_eq!(fnv1a64(b"a"), 0xaf63dc4c8601ec8c);
    }
}
