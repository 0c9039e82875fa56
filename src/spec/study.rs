//! The validated stage: a [`Study`] is everything a run needs, every value
//! in range. It is built only by [`SpecFile::validate`], and written back as
//! canonical spec text by [`Study::to_toml`].

use super::raw::{FrictionEntry, GridFile, OutputFile, SpecFile, UncertaintyFile};
use crate::error::{Error, Result};
use crate::fragility::FragilityOptions;
use crate::motion::SynthesisSettings;
use crate::outcomes_csv::{Pooled, same, same_friction};
use crate::solver::{Friction, SolverSettings};
use crate::uncertainty::{Param, Value, analysis_seed, uniforms};
use std::path::{Path, PathBuf};

/// The paper's study (Shenton and Jones), the default of `rockfrag run`.
pub const SHENTON_JONES_TOML: &str = include_str!("../../studies/shenton-jones.toml");

/// Name used in messages for the embedded paper study.
pub const SHENTON_JONES_ORIGIN: &str = "shenton-jones.toml (built-in)";

/// A validated study: everything a run needs, every value in range.
/// Studies compare NaN placeholders (drawn parameters) equal.
#[derive(Clone, Debug)]
pub struct Study {
    /// Study name (letters, digits, `.`, `_`, `-`).
    pub name: String,
    /// Free text.
    pub description: String,
    /// Gravity, m/s².
    pub g: f64,
    /// Where the records come from.
    pub motions: Motions,
    /// Intensity levels.
    pub intensity: Intensity,
    /// Base widths 2B, m. A parameter drawn under `[uncertainty]` has the
    /// one placeholder value NaN in its list (and friction the one model
    /// Coulomb with NaN coefficients): one case pools all its draws.
    pub widths: Vec<f64>,
    /// Aspect ratios H/B.
    pub aspects: Vec<f64>,
    /// Coefficients of restitution.
    pub restitutions: Vec<f64>,
    /// Friction models.
    pub frictions: Vec<Friction>,
    /// Block parameters drawn per analysis, if any.
    pub uncertainty: Option<Uncertainty>,
    /// Solver settings.
    pub solver: SolverSettings,
    /// Output options.
    pub output: OutputFile,
    /// Fragility fit on completion, if the spec asks for one.
    pub fragility: Option<FragilityOptions>,
}

impl PartialEq for Study {
    fn eq(&self, other: &Study) -> bool {
        let lists =
            |a: &[f64], b: &[f64]| a.len() == b.len() && a.iter().zip(b).all(|(x, y)| same(*x, *y));
        self.name == other.name
            && self.description == other.description
            && self.g == other.g
            && self.motions == other.motions
            && self.intensity == other.intensity
            && lists(&self.widths, &other.widths)
            && lists(&self.aspects, &other.aspects)
            && lists(&self.restitutions, &other.restitutions)
            && self.frictions.len() == other.frictions.len()
            && self
                .frictions
                .iter()
                .zip(&other.frictions)
                .all(|(a, b)| same_friction(a, b))
            && self.uncertainty == other.uncertainty
            && self.solver == other.solver
            && self.output == other.output
            && self.fragility == other.fragility
    }
}

/// The validated `[uncertainty]` table: what each analysis draws.
#[derive(Clone, Debug, PartialEq)]
pub struct Uncertainty {
    /// Seed of the draws.
    pub seed: u64,
    /// The value of each parameter of [`Param::ALL`], in its order (`None`:
    /// from the grid).
    pub values: [Option<Value>; 5],
}

/// The block parameters of one analysis, after its draws.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Draw {
    /// Base width 2B, m.
    pub width: f64,
    /// Aspect ratio H/B.
    pub aspect: f64,
    /// Coefficient of restitution e.
    pub restitution: f64,
    /// Friction model.
    pub friction: Friction,
}

impl Uncertainty {
    /// The value given for `param`, if any.
    pub fn get(&self, param: Param) -> Option<&Value> {
        let i = Param::ALL.iter().position(|&p| p == param).expect("listed");
        self.values[i].as_ref()
    }

    /// Whether `param` is drawn (not fixed, not from the grid).
    pub fn is_drawn(&self, param: Param) -> bool {
        self.get(param).is_some_and(Value::is_drawn)
    }

    /// The case parameters that vary from analysis to analysis.
    pub fn pooled(&self) -> Pooled {
        Pooled {
            width: self.is_drawn(Param::Width),
            aspect: self.is_drawn(Param::Aspect),
            restitution: self.is_drawn(Param::Restitution),
            friction: self.is_drawn(Param::MuS) || self.is_drawn(Param::MuKOverMuS),
        }
    }

    /// The parameters of the analysis of case `case` (index in canonical
    /// order) on record `record` at level `level`, whose grid values are
    /// `grid`: each parameter given here replaces the grid's, drawn from the
    /// stream [`analysis_seed`]`(seed, record, level, case)`.
    pub fn draw(&self, grid: Draw, record: usize, level: usize, case: usize) -> Draw {
        let u = uniforms(analysis_seed(
            self.seed,
            record as u64,
            level as u64,
            case as u64,
        ));
        let value = |i: usize, grid: f64| self.values[i].as_ref().map_or(grid, |v| v.at(u[i]));
        let friction = match (&self.values[3], &self.values[4]) {
            (Some(s), Some(r)) => {
                let mu_s = s.at(u[3]);
                // μk = μs · (μk/μs): μk ≤ μs by construction.
                Friction::Coulomb {
                    mu_s,
                    mu_k: mu_s * r.at(u[4]),
                }
            }
            _ => grid.friction,
        };
        Draw {
            width: value(0, grid.width),
            aspect: value(1, grid.aspect),
            restitution: value(2, grid.restitution),
            friction,
        }
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
        /// Records per intensity level.
        records: usize,
    },
    /// Recorded motions, each scaled to every intensity level.
    Files(Vec<RecordFile>),
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

impl Study {
    /// Reads and validates a spec file; record files are relative to its folder.
    pub fn load(path: &Path) -> Result<Study> {
        let text = std::fs::read_to_string(path).map_err(Error::io(path))?;
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
        let (seed, records, record_files, motion) = match &self.motions {
            Motions::Synthetic {
                settings,
                seed,
                records,
            } => (
                Some(*seed),
                Some(*records),
                Vec::new(),
                Some(settings.clone()),
            ),
            Motions::Files(files) => (
                None,
                None,
                files.iter().map(|f| f.given.clone()).collect(),
                None,
            ),
        };
        let drawn = |p: Param| {
            self.uncertainty
                .as_ref()
                .is_some_and(|u| u.get(p).is_some())
        };
        let grid_list = |p: Param, v: &Vec<f64>| (!drawn(p)).then(|| v.clone());
        let (pga, pgv, scale_factors) = match &self.intensity {
            Intensity::Pga(v) => (Some(v.clone()), None, None),
            Intensity::Pgv(v) => (None, Some(v.clone()), None),
            Intensity::Scale(v) => (None, None, Some(v.clone())),
        };
        SpecFile {
            name: Some(self.name.clone()),
            description: self.description.clone(),
            g: Some(self.g),
            seed,
            records,
            record_files,
            motion,
            grid: GridFile {
                width: grid_list(Param::Width, &self.widths),
                aspect: grid_list(Param::Aspect, &self.aspects),
                restitution: grid_list(Param::Restitution, &self.restitutions),
                friction: (!drawn(Param::MuS))
                    .then(|| self.frictions.iter().map(|&f| FrictionEntry(f)).collect()),
                pga,
                pgv,
                scale_factors,
            },
            uncertainty: self.uncertainty.as_ref().map(|u| UncertaintyFile {
                seed: Some(u.seed),
                width: u.values[0],
                aspect: u.values[1],
                restitution: u.values[2],
                mu_s: u.values[3],
                mu_k_over_mu_s: u.values[4],
            }),
            solver: self.solver,
            output: self.output,
            fragility: self.fragility.clone(),
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

    /// The case parameters drawn per analysis (none without `[uncertainty]`).
    pub fn pooled(&self) -> Pooled {
        self.uncertainty
            .as_ref()
            .map_or(Pooled::default(), Uncertainty::pooled)
    }

    /// Number of records per intensity level.
    pub fn records(&self) -> usize {
        match &self.motions {
            Motions::Synthetic { records, .. } => *records,
            Motions::Files(files) => files.len(),
        }
    }
}

/// FNV-1a, 64 bits: a small stable hash for provenance (not for security).
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// A friction model as text: `inf` or `coulomb(μs, μk)`; `coulomb(drawn)`
/// when its coefficients are drawn per analysis (NaN, see [`Study::frictions`]).
pub fn friction_label(f: Friction) -> String {
    match f {
        Friction::Infinite => "inf".to_string(),
        Friction::Coulomb { mu_s, .. } if mu_s.is_nan() => "coulomb(drawn)".to_string(),
        Friction::Coulomb { mu_s, mu_k } => format!("coulomb(mu_s = {mu_s}, mu_k = {mu_k})"),
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
