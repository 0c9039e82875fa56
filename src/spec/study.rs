//! The validated stage: a [`Study`] is everything a run needs, every value
//! in range. It is built only by [`SpecFile::validate`], and written back as
//! canonical spec text by [`Study::to_toml`].

use super::raw::{FrictionEntry, GridFile, OutputFile, SpecFile};
use crate::error::{Error, Result};
use crate::fragility::FragilityOptions;
use crate::motion::SynthesisSettings;
use crate::solver::{Friction, SolverSettings};
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
    /// Intensity levels.
    pub intensity: Intensity,
    /// Base widths 2B, m.
    pub widths: Vec<f64>,
    /// Aspect ratios H/B.
    pub aspects: Vec<f64>,
    /// Coefficients of restitution.
    pub restitutions: Vec<f64>,
    /// Friction models.
    pub frictions: Vec<Friction>,
    /// Solver settings.
    pub solver: SolverSettings,
    /// Output options.
    pub output: OutputFile,
    /// Fragility fit on completion, if the spec asks for one.
    pub fragility: Option<FragilityOptions>,
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
                width: self.widths.clone(),
                aspect: self.aspects.clone(),
                restitution: self.restitutions.clone(),
                friction: self.frictions.iter().map(|&f| FrictionEntry(f)).collect(),
                pga,
                pgv,
                scale_factors,
            },
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

/// A friction model as text: `inf` or `coulomb(μs, μk)`.
pub fn friction_label(f: Friction) -> String {
    match f {
        Friction::Infinite => "inf".to_string(),
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
