//! Study specs: the TOML file a user writes once and runs anywhere.
//!
//! This is the only module that knows about TOML. A spec is read in two
//! stages, like ripgrep's `LowArgs` → `HiArgs`: serde reads the text into the
//! raw [`SpecFile`] (every field has a default, unknown fields are errors),
//! then [`SpecFile::validate`] checks every value once and builds the
//! validated [`Study`], which nothing downstream re-checks. Every error names
//! the file, the line, the field path (e.g. `grid.aspect[2]`) and the accepted
//! range.
//!
//! ```toml
//! name = "example"            # default: the file's stem
//! seed = 7                    # ensemble seed (default: 1)
//! records = 25                # synthetic records per intensity level (default: 25)
//! # record_files = ["motions/elcentro.AT2"]   # or recorded motions instead
//!
//! [motion]                    # SynthesisSettings (default: the paper's firm soil)
//! duration = 30.0
//!
//! [grid]
//! width = [0.5]               # base width 2B, m
//! aspect = [2, 4, 6]          # H/B
//! restitution = [0.0, 0.6]    # e
//! friction = ["inf", { mu_s = 0.7, mu_k = 0.6 }]
//! pga = [0.3, 0.6]            # g; or pgv = [0.2, 0.4] in m/s
//!
//! [solver]                    # SolverSettings (default: nonlinear, rtol 1e-8, …)
//! [output]
//! summary = true
//! ```

use crate::error::{Error, Result};
use crate::fragility::FragilityOptions;
use crate::motion::{G_STANDARD, SynthesisSettings};
use crate::solver::{Block, Friction, SolverSettings};
use serde::de::{self, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::path::{Path, PathBuf};

/// The paper's study (Shenton and Jones), the default of `rockfrag run`.
pub const SHENTON_JONES_TOML: &str = include_str!("../studies/shenton-jones.toml");

/// Name used in messages for the embedded paper study.
pub const SHENTON_JONES_ORIGIN: &str = "shenton-jones.toml (built-in)";

/// Largest ensemble size accepted.
const MAX_RECORDS: usize = 10_000_000;
/// Largest PGA accepted, g.
const MAX_PGA_G: f64 = 10.0;
/// Largest PGV accepted, m/s.
const MAX_PGV: f64 = 20.0;

// ───────────────────────────── raw form ─────────────────────────────

/// A study spec as written (raw stage): every field optional with a
/// documented default. Turned into a [`Study`] by [`SpecFile::validate`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SpecFile {
    /// Study name; the default output directory is `results/<name>/`
    /// (default: the spec file's stem). Letters, digits, `.`, `_`, `-`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Free text, copied to the manifest and the summary (default: empty).
    pub description: String,
    /// Gravity, m/s², for the blocks, for intensities in g and for `.AT2`
    /// files (default: 9.81). `motion.g`, if written, must agree.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub g: Option<f64>,
    /// Ensemble seed of the synthetic records (default: 1). Record i is a pure
    /// function of (seed, i).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Synthetic records per intensity level (default: 25).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub records: Option<usize>,
    /// Recorded motions (`.AT2` in g or `.csv` in m/s²), paths relative to
    /// the spec file; when given, they replace the synthetic ensemble and
    /// `seed`, `records` and `[motion]` must be left out (default: none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub record_files: Vec<String>,
    /// Stochastic ground-motion model (default: the paper's section 4).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub motion: Option<SynthesisSettings>,
    /// The grids of the study.
    pub grid: GridFile,
    /// Numerical settings of the solver (default: `SolverSettings::default()`).
    pub solver: SolverSettings,
    /// What to write.
    pub output: OutputFile,
    /// Fit fragility curves when the run completes (`fragility.csv`,
    /// `fragility_curves.csv`, `fragility.xml`), with these settings; an
    /// empty `[fragility]` table takes every default (default: no fit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fragility: Option<FragilityOptions>,
}

/// The `[grid]` table: every combination of its values is analysed under
/// every record at every intensity level.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GridFile {
    /// Base widths 2B, m (default: `[0.5]`).
    pub width: Vec<f64>,
    /// Aspect ratios H/B (default: `[2, 4, 6]`).
    pub aspect: Vec<f64>,
    /// Coefficients of restitution e in [0, 1] (default: `[0, 0.3, 0.6, 0.9]`).
    pub restitution: Vec<f64>,
    /// Friction models: `"inf"` or `{ mu_s = …, mu_k = … }` (or `[mu_s, mu_k]`)
    /// with 0 ≤ μk ≤ μs (default: `["inf"]`).
    pub friction: Vec<FrictionEntry>,
    /// Intensity levels as PGA, g, each record scaled to it
    /// (default: `[0.3, 0.6, 0.9, 1.2]` when `pgv` is not given).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pga: Option<Vec<f64>>,
    /// Intensity levels as PGV, m/s, each record scaled to it instead of to a
    /// PGA (default: not used).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pgv: Option<Vec<f64>>,
}

impl Default for GridFile {
    fn default() -> Self {
        GridFile {
            width: vec![0.5],
            aspect: vec![2.0, 4.0, 6.0],
            restitution: vec![0.0, 0.3, 0.6, 0.9],
            friction: vec![FrictionEntry(Friction::Infinite)],
            pga: None,
            pgv: None,
        }
    }
}

/// The `[output]` table. `outcomes.csv` and `manifest.json` are always
/// written (they carry the results and their provenance, and resuming and
/// merging rely on them).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OutputFile {
    /// Write `summary.md`, the paper-style tables (default: true).
    pub summary: bool,
    /// Add the time spent in each mode to `outcomes.csv`
    /// (`t_rest,t_slide,t_rock,t_slide_rock,t_flight`, default: false).
    pub time_in_mode: bool,
    /// Add the solver's work counters to `outcomes.csv`
    /// (`rhs_calls,steps_accepted,steps_rejected,events`, default: false).
    pub stats: bool,
    /// Draw the study's figures into `figures/` inside the output folder
    /// when the run completes, as `rockfrag figures` does (default: false).
    pub figures: bool,
}

impl Default for OutputFile {
    fn default() -> Self {
        OutputFile {
            summary: true,
            time_in_mode: false,
            stats: false,
            figures: false,
        }
    }
}

/// One entry of `grid.friction`: `"inf"`, `{ mu_s = 0.7, mu_k = 0.6 }` or
/// `[0.7, 0.6]`. Serialised as `"inf"` or the table form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionEntry(pub Friction);

impl Serialize for FrictionEntry {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        match self.0 {
            Friction::Infinite => s.serialize_str("inf"),
            Friction::Coulomb { mu_s, mu_k } => {
                let mut st = s.serialize_struct("Coulomb", 2)?;
                st.serialize_field("mu_s", &mu_s)?;
                st.serialize_field("mu_k", &mu_k)?;
                st.end()
            }
        }
    }
}

const FRICTION_EXPECTED: &str = "\"inf\", { mu_s = …, mu_k = … } or [mu_s, mu_k]";

impl<'de> Deserialize<'de> for FrictionEntry {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = FrictionEntry;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(FRICTION_EXPECTED)
            }
            fn visit_str<E: de::Error>(self, v: &str) -> std::result::Result<Self::Value, E> {
                match v {
                    "inf" | "infinite" => Ok(FrictionEntry(Friction::Infinite)),
                    _ => Err(E::custom(format!(
                        "unknown friction model \"{v}\", expected {FRICTION_EXPECTED}"
                    ))),
                }
            }
            fn visit_seq<A: SeqAccess<'de>>(
                self,
                mut a: A,
            ) -> std::result::Result<Self::Value, A::Error> {
                let short = || de::Error::custom("expected two numbers [mu_s, mu_k]");
                let mu_s: f64 = a.next_element()?.ok_or_else(short)?;
                let mu_k: f64 = a.next_element()?.ok_or_else(short)?;
                if a.next_element::<f64>()?.is_some() {
                    return Err(short());
                }
                Ok(FrictionEntry(Friction::Coulomb { mu_s, mu_k }))
            }
            fn visit_map<A: MapAccess<'de>>(
                self,
                mut a: A,
            ) -> std::result::Result<Self::Value, A::Error> {
                let (mut mu_s, mut mu_k) = (None, None);
                while let Some(key) = a.next_key::<String>()? {
                    match key.as_str() {
                        "mu_s" => mu_s = Some(a.next_value::<f64>()?),
                        "mu_k" => mu_k = Some(a.next_value::<f64>()?),
                        _ => return Err(de::Error::unknown_field(&key, &["mu_s", "mu_k"])),
                    }
                }
                match (mu_s, mu_k) {
                    (Some(mu_s), Some(mu_k)) => Ok(FrictionEntry(Friction::Coulomb { mu_s, mu_k })),
                    (None, _) => Err(de::Error::missing_field("mu_s")),
                    (_, None) => Err(de::Error::missing_field("mu_k")),
                }
            }
        }
        d.deserialize_any(V)
    }
}

// ─────────────────────────── validated form ───────────────────────────

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
}

impl Intensity {
    /// The levels, in the spec's order.
    pub fn levels(&self) -> &[f64] {
        match self {
            Intensity::Pga(v) | Intensity::Pgv(v) => v,
        }
    }
}

impl Study {
    /// Reads and validates a spec file; record files are relative to its folder.
    pub fn load(path: &Path) -> Result<Study> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
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
        let (pga, pgv) = match &self.intensity {
            Intensity::Pga(v) => (Some(v.clone()), None),
            Intensity::Pgv(v) => (None, Some(v.clone())),
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
            },
            solver: self.solver,
            output: self.output,
            fragility: self.fragility,
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

impl SpecFile {
    /// Reads spec text into the raw form; a syntax or type error names the
    /// file, the line and the table/key where it happened.
    pub fn parse(text: &str, origin: &Path) -> Result<SpecFile> {
        toml::from_str(text).map_err(|e| {
            let (line, key) = match e.span() {
                Some(span) => key_at(text, span.start),
                None => (0, String::new()),
            };
            let message = e.message().trim().replace('\n', "; ");
            Error::Parse {
                path: origin.to_path_buf(),
                line,
                message: if key.is_empty() {
                    message
                } else {
                    format!("{key}: {message}")
                },
            }
        })
    }

    /// Checks every value and builds the [`Study`]. `text` is the spec's text
    /// (to locate fields in errors), `origin` its path; record files are
    /// checked for existence when `check_files` is set.
    pub fn validate(self, text: &str, origin: &Path, check_files: bool) -> Result<Study> {
        let bad = |field: &str, value: &dyn std::fmt::Display, expected: &str| Error::Spec {
            path: origin.to_path_buf(),
            line: locate(text, field),
            field: field.to_string(),
            value: value.to_string(),
            expected: expected.to_string(),
        };
        // Re-label an error of an embedded settings struct with its table.
        let nested = |table: &str, err: Error| match err {
            Error::InvalidParameter {
                field,
                value,
                expected,
            } => {
                let field = format!("{table}.{field}");
                bad(&field, &value, &expected)
            }
            other => other,
        };

        let name = match self.name {
            Some(n) => n,
            None => origin
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default()
                .split_whitespace()
                .next()
                .unwrap_or_default()
                .to_string(),
        };
        if name.is_empty()
            || name.starts_with('.')
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-'))
        {
            return Err(bad(
                "name",
                &format!("\"{name}\""),
                "a non-empty name of letters, digits, '.', '_' or '-' (not starting with '.')",
            ));
        }

        let g = self.g.unwrap_or(G_STANDARD);
        if !(g.is_finite() && g > 0.0) {
            return Err(bad("g", &g, "a positive gravity in m/s²"));
        }

        let motions = if self.record_files.is_empty() {
            let mut settings = self.motion.unwrap_or_else(|| SynthesisSettings {
                g,
                ..SynthesisSettings::default()
            });
            if settings.g != g {
                return Err(bad(
                    "motion.g",
                    &settings.g,
                    &format!("the study's gravity g = {g} (set the top-level `g` instead)"),
                ));
            }
            settings.g = g;
            settings
                .validate()
                .map_err(|e| nested("motion", psd_path(e)))?;
            let records = self.records.unwrap_or(25);
            if !(1..=MAX_RECORDS).contains(&records) {
                return Err(bad(
                    "records",
                    &records,
                    &format!("a number of records in 1..={MAX_RECORDS}"),
                ));
            }
            Motions::Synthetic {
                settings,
                seed: self.seed.unwrap_or(1),
                records,
            }
        } else {
            for (field, given) in [
                ("seed", self.seed.map(|s| s.to_string())),
                ("records", self.records.map(|r| r.to_string())),
                (
                    "motion",
                    self.motion.as_ref().map(|_| "[motion]".to_string()),
                ),
            ] {
                if let Some(value) = given {
                    return Err(bad(
                        field,
                        &value,
                        "to be left out when record_files is given (recorded motions replace \
                         the synthetic ensemble)",
                    ));
                }
            }
            let base = origin.parent().unwrap_or(Path::new(""));
            let mut files = Vec::with_capacity(self.record_files.len());
            for (i, given) in self.record_files.iter().enumerate() {
                let field = format!("record_files[{i}]");
                let path = base.join(given);
                let ext = path
                    .extension()
                    .map(|e| e.to_string_lossy().to_ascii_lowercase());
                if !matches!(ext.as_deref(), Some("at2" | "csv")) {
                    return Err(bad(&field, &format!("\"{given}\""), "a .AT2 or .csv file"));
                }
                if given.contains(['\n', '\r']) {
                    return Err(bad(
                        &field,
                        &format!("{given:?}"),
                        "a path without line breaks",
                    ));
                }
                if check_files && !path.is_file() {
                    return Err(bad(
                        &field,
                        &format!("\"{given}\""),
                        &format!(
                            "an existing record file, relative to the spec file (not found: {})",
                            path.display()
                        ),
                    ));
                }
                if files.iter().any(|f: &RecordFile| f.given == *given) {
                    return Err(bad(&field, &format!("\"{given}\""), "no file listed twice"));
                }
                files.push(RecordFile {
                    given: given.clone(),
                    path,
                });
            }
            Motions::Files(files)
        };

        let grid = self.grid;
        let check_list = |name: &str,
                          values: &[f64],
                          ok: &dyn Fn(f64) -> bool,
                          expected: &str|
         -> Result<Vec<f64>> {
            let field = format!("grid.{name}");
            if values.is_empty() {
                return Err(bad(&field, &"[]", "at least one value"));
            }
            for (i, &v) in values.iter().enumerate() {
                let f = format!("grid.{name}[{i}]");
                if !(v.is_finite() && ok(v)) {
                    return Err(bad(&f, &v, expected));
                }
                if values[..i].contains(&v) {
                    return Err(bad(&f, &v, "a value not already in the list"));
                }
            }
            Ok(values.to_vec())
        };
        let widths = check_list(
            "width",
            &grid.width,
            &|v| v > 0.0,
            "a positive base width 2B in m",
        )?;
        let aspects = check_list(
            "aspect",
            &grid.aspect,
            &|v| v > 0.0,
            "a positive aspect ratio H/B",
        )?;
        let restitutions = check_list(
            "restitution",
            &grid.restitution,
            &|v| (0.0..=1.0).contains(&v),
            "a coefficient of restitution in [0, 1]",
        )?;
        for &w in &widths {
            for &a in &aspects {
                Block::new(w, a, g).map_err(|e| nested("grid", e))?;
            }
        }
        let intensity = match (grid.pga, grid.pgv) {
            (Some(_), Some(_)) => {
                return Err(bad(
                    "grid.pgv",
                    &"(given)",
                    "to be left out when grid.pga is given (one intensity measure per study)",
                ));
            }
            (None, Some(pgv)) => Intensity::Pgv(check_list(
                "pgv",
                &pgv,
                &|v| v > 0.0 && v <= MAX_PGV,
                &format!("a peak ground velocity in (0, {MAX_PGV}] m/s"),
            )?),
            (pga, None) => Intensity::Pga(check_list(
                "pga",
                &pga.unwrap_or_else(|| vec![0.3, 0.6, 0.9, 1.2]),
                &|v| v > 0.0 && v <= MAX_PGA_G,
                &format!("a peak ground acceleration in (0, {MAX_PGA_G}] g"),
            )?),
        };

        if grid.friction.is_empty() {
            return Err(bad("grid.friction", &"[]", "at least one friction model"));
        }
        let mut frictions = Vec::with_capacity(grid.friction.len());
        for (i, &FrictionEntry(f)) in grid.friction.iter().enumerate() {
            if let Friction::Coulomb { mu_s, mu_k } = f {
                if !(mu_s.is_finite() && mu_s >= 0.0) {
                    return Err(bad(
                        &format!("grid.friction[{i}].mu_s"),
                        &mu_s,
                        "a static friction coefficient μs ≥ 0",
                    ));
                }
                if !(mu_k.is_finite() && mu_k >= 0.0 && mu_k <= mu_s) {
                    return Err(bad(
                        &format!("grid.friction[{i}].mu_k"),
                        &mu_k,
                        &format!("a kinetic friction coefficient μk in [0, μs = {mu_s}]"),
                    ));
                }
            }
            if frictions.contains(&f) {
                return Err(bad(
                    &format!("grid.friction[{i}]"),
                    &friction_label(f),
                    "a friction model not already in the list",
                ));
            }
            frictions.push(f);
        }

        self.solver.validate().map_err(|e| nested("solver", e))?;
        if let Some(options) = &self.fragility {
            // its fields already carry the `fragility.` prefix
            options.validate().map_err(|e| nested_as_is(e, &bad))?;
        }

        Ok(Study {
            name,
            description: self.description,
            g,
            motions,
            intensity,
            widths,
            aspects,
            restitutions,
            frictions,
            solver: self.solver,
            output: self.output,
            fragility: self.fragility,
        })
    }
}

/// An [`Error::InvalidParameter`] whose field is already a full spec path,
/// re-labelled with the spec's file and line by `bad`.
fn nested_as_is(err: Error, bad: &dyn Fn(&str, &dyn std::fmt::Display, &str) -> Error) -> Error {
    match err {
        Error::InvalidParameter {
            field,
            value,
            expected,
        } => bad(&field, &value, &expected),
        other => other,
    }
}

/// A friction model as text: `inf` or `coulomb(μs, μk)`.
pub fn friction_label(f: Friction) -> String {
    match f {
        Friction::Infinite => "inf".to_string(),
        Friction::Coulomb { mu_s, mu_k } => format!("coulomb(mu_s = {mu_s}, mu_k = {mu_k})"),
    }
}

/// The spectrum's own validation names its fields bare (`xi_g`); put them
/// under `psd`.
fn psd_path(err: Error) -> Error {
    match err {
        Error::InvalidParameter {
            field,
            value,
            expected,
        } if ["s0", "xi_g", "f_g", "xi_2", "f_2"].contains(&field.as_str()) => {
            Error::InvalidParameter {
                field: format!("psd.{field}"),
                value,
                expected,
            }
        }
        other => other,
    }
}

/// Line (1-based) of the table header `[a.b]` in `text`, or `None`.
fn header_line(lines: &[&str], table: &str) -> Option<usize> {
    lines.iter().position(|l| {
        let t = l.trim();
        t.strip_prefix('[')
            .and_then(|t| t.split(']').next())
            .map(|h| h.trim().trim_start_matches('[').trim() == table)
            .unwrap_or(false)
    })
}

/// Whether `line` assigns `key` (`key = …` or `key.sub = …`).
fn assigns(line: &str, key: &str) -> bool {
    line.trim_start()
        .strip_prefix(key)
        .map(|rest| {
            let rest = rest.trim_start();
            rest.starts_with('=') || rest.starts_with('.')
        })
        .unwrap_or(false)
}

/// Best-effort line of a field path such as `grid.friction[1].mu_k` in the
/// spec text: the line assigning the deepest key found under its table
/// header, else the header itself; 0 if not written.
fn locate(text: &str, field: &str) -> usize {
    let lines: Vec<&str> = text.lines().collect();
    let parts: Vec<&str> = field
        .split('.')
        .map(|p| p.split('[').next().unwrap_or(p))
        .collect();
    for split in (0..parts.len()).rev() {
        let table = parts[..split].join(".");
        let (start, header) = if table.is_empty() {
            (0, None)
        } else {
            match header_line(&lines, &table) {
                Some(h) => (h + 1, Some(h)),
                None => continue,
            }
        };
        let end = lines[start..]
            .iter()
            .position(|l| l.trim_start().starts_with('['))
            .map_or(lines.len(), |p| start + p);
        let key = parts[split];
        if let Some(p) = lines[start..end].iter().position(|l| assigns(l, key)) {
            return start + p + 1;
        }
        if let Some(h) = header {
            return h + 1;
        }
    }
    0
}

/// The line (1-based) of byte `offset` and the dotted key path written there
/// (its table header plus the key on that line), for TOML errors.
fn key_at(text: &str, offset: usize) -> (usize, String) {
    let offset = offset.min(text.len());
    let before = &text[..offset];
    let line_no = before.matches('\n').count() + 1;
    let mut table = String::new();
    for l in before.lines() {
        let t = l.trim();
        if let Some(h) = t.strip_prefix('[') {
            table = h
                .trim_start_matches('[')
                .split(']')
                .next()
                .unwrap_or("")
                .trim()
                .to_string();
        }
    }
    let line = text.lines().nth(line_no - 1).unwrap_or("");
    let key = line
        .split_once('=')
        .map(|(k, _)| k.trim())
        .filter(|k| !k.is_empty() && !k.starts_with('['))
        .unwrap_or("");
    let path = match (table.is_empty(), key.is_empty()) {
        (true, _) => key.to_string(),
        (false, true) => table,
        (false, false) => format!("{table}.{key}"),
    };
    (line_no, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locate_finds_keys_under_their_table() {
        let text = "name = \"x\"\n[grid]\nwidth = [1]\naspect = [2, -1]\n[solver]\nrtol = 2\n";
        assert_eq!(locate(text, "name"), 1);
        assert_eq!(locate(text, "grid.aspect[1]"), 4);
        assert_eq!(locate(text, "solver.rtol"), 6);
        assert_eq!(locate(text, "solver.atol"), 5);
        assert_eq!(locate(text, "records"), 0);
    }

    #[test]
    fn key_at_names_table_and_key() {
        let text = "[grid]\naspct = [2]\n";
        let off = text.find("aspct").unwrap();
        assert_eq!(key_at(text, off), (2, "grid.aspct".to_string()));
    }

    #[test]
    fn fnv1a_reference_values() {
        assert_eq!(fnv1a64(b""), 0xcbf29ce484222325);
        assert_eq!(fnv1a64(b"a"), 0xaf63dc4c8601ec8c);
    }
}
