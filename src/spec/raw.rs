//! The raw stage: a spec as written, read by serde. Every field has a
//! default and unknown fields are errors; nothing here checks a value's range
//! (that is [`SpecFile::validate`]'s job).

use super::locate::key_at;
use crate::error::{Error, Result};
use crate::fragility::FragilityOptions;
use crate::motion::{Baseline, CloughPenzien, Envelope, Mode, SynthesisSettings};
use crate::solver::{Friction, SolverSettings};
use crate::uncertainty::Value;
use serde::de::{self, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::path::Path;

/// A study spec as written (raw stage): every field optional with a
/// documented default. Turned into a [`Study`](super::Study) by [`SpecFile::validate`].
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
    /// Horizontal components per synthetic record: 1, or 2 for pairs of
    /// independent components of the same model, scaled by their RotD50 and
    /// turned to the direction the blocks face, as recorded pairs are
    /// (default: 1; left out of the canonical spec then).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub components: Option<usize>,
    /// Recorded motions (`.AT2` in g or `.csv` in m/s²), paths relative to
    /// the spec file: each entry one component (`"a.AT2"`) or, for every
    /// entry, a pair of horizontal components (`["a-H1.AT2", "a-H2.AT2"]`;
    /// the block faces `grid.orientation` or a drawn
    /// `uncertainty.orientation`). When given, they replace the synthetic
    /// ensemble and `seed`, `records` and `[motion]` must be left out
    /// (default: none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub record_files: Vec<RecordEntry>,
    /// Stochastic ground-motion model (default: the generator's default
    /// model, see [`crate::motion::SynthesisSettings`]; or a named preset).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub motion: Option<MotionFile>,
    /// What the blocks stand on (default: the ground; see `SupportFile`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub support: Option<SupportFile>,
    /// The grids of the study.
    pub grid: GridFile,
    /// Block parameters drawn per analysis instead of taken from the grid
    /// (default: none; see [`UncertaintyFile`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub uncertainty: Option<UncertaintyFile>,
    /// Numerical settings of the solver (default: `SolverSettings::default()`).
    pub solver: SolverSettings,
    /// What to write.
    pub output: OutputFile,
    /// Fit fragility curves when the run completes (`fragility.csv`,
    /// `fragility_curves.csv`, `fragility.xml`), with these settings; an
    /// empty `[fragility]` table takes every default (default: no fit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fragility: Option<FragilityOptions>,
    /// Settings of `rockfrag infer` (default: its defaults; a study run
    /// ignores them).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub infer: Option<super::infer::InferSettings>,
}

/// The `[grid]` table: every combination of its values is analysed under
/// every record at every intensity level. A block list left out takes its
/// default unless the parameter is drawn under `[uncertainty]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GridFile {
    /// Base widths 2B, m (default: `[0.5]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub width: Option<Vec<f64>>,
    /// Aspect ratios H/B (default: `[2, 4, 6]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub aspect: Option<Vec<f64>>,
    /// Coefficients of restitution e in [0, 1] (default: `[0, 0.3, 0.6, 0.9]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub restitution: Option<Vec<f64>>,
    /// Friction models: `"inf"` or `{ mu_s = …, mu_k = … }` (or `[mu_s, mu_k]`)
    /// with 0 ≤ μk ≤ μs (default: `["inf"]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction: Option<Vec<FrictionEntry>>,
    /// Intensity levels as PGA, g, each record scaled to it
    /// (default: `[0.3, 0.6, 0.9, 1.2]` when `pgv` is not given); or a
    /// range `{ min = 0.05, max = 3.0 }` within which an adaptive run
    /// places its levels (with `[fragility] precision`, docs/adaptive.md).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pga: Option<Levels>,
    /// Intensity levels as PGV, m/s, each record scaled to it instead of to a
    /// PGA (default: not used); or a range `{ min = 0.05, max = 2.0 }` m/s
    /// for an adaptive run, as for `pga`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pgv: Option<Levels>,
    /// Directions φ the blocks face, degrees from the first component of
    /// each record pair towards the second: every pair is run at every
    /// angle, and a case's curve pools them with the pairs (only with
    /// record pairs; default: φ drawn, see `uncertainty.orientation`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub orientation: Option<Vec<f64>>,
    /// Factors each recorded motion is multiplied by, instead of scaling it
    /// to a PGA or PGV: `[1.0]` runs each record as recorded (a cloud
    /// analysis), several factors an incremental dynamic analysis. Only with
    /// `record_files` (default: not used).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scale_factors: Option<Vec<f64>>,
    /// Stacks of two or three blocks, each a case of its own
    /// (`[[grid.stack]]`, see `spec::stack`). With stacks, the block
    /// lists (`width`, `aspect`, `restitution`, `friction`) make cases of
    /// one block only when `width` or `aspect` is given (default: none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub stack: Vec<StackEntry>,
}

/// `grid.pga` or `grid.pgv` as written: a list of levels, or a range for an
/// adaptive run (in the field's unit: g, or m/s).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "a list of levels [0.1, 0.2, …] or a range { min = …, max = … }"
)]
pub enum Levels {
    /// The levels (g, or m/s).
    List(Vec<f64>),
    /// The range an adaptive run places its levels in (g, or m/s).
    Range(LevelRange),
}

/// A range of intensity levels (g for PGA, m/s for PGV):
/// `{ min = 0.05, max = 3.0 }`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LevelRange {
    /// Lowest level.
    pub min: f64,
    /// Highest level.
    pub max: f64,
}

/// The `[support]` table: what the blocks stand on. Without it, or with
/// an empty `floor`, the ground. With `floor`, a floor of a **linear**
/// building described by its modes at that floor, one entry per mode (one
/// is the common case); every record is filtered through them
/// ([`crate::motion::floor_record`]) before the blocks feel it, and
/// `outcomes.csv` gains the floor's peaks `pfa`, `pfv`.
///
/// ```toml
/// [support]
/// floor = [{ period = 0.8, damping = 0.05, participation = 1.3 }]
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SupportFile {
    /// The building's modes at the floor: period T (s, > 0), damping ratio
    /// ζ (0 ≤ ζ < 1) and participation Γφ (the modal participation factor
    /// times the mode shape at the floor; default 1).
    pub floor: Vec<Mode>,
}

/// Default grid lists, for the lists a spec leaves out.
impl GridFile {
    /// Default base widths 2B, m.
    pub const WIDTH: [f64; 1] = [0.5];
    /// Default aspect ratios H/B.
    pub const ASPECT: [f64; 3] = [2.0, 4.0, 6.0];
    /// Default coefficients of restitution.
    pub const RESTITUTION: [f64; 4] = [0.0, 0.3, 0.6, 0.9];
}

/// The `[uncertainty]` table: block parameters drawn per analysis, each
/// replacing the grid list of the same name (`mu_s` and `mu_k_over_mu_s`
/// replace `grid.friction`, μk = μs · (μk/μs) ≤ μs by construction).
///
/// ```toml
/// [uncertainty]
/// restitution = { dist = "uniform", min = 0.0, max = 0.9 }
/// mu_s = { dist = "lognormal", median = 0.6, beta = 0.15 }
/// mu_k_over_mu_s = { dist = "uniform", min = 0.7, max = 1.0 }
/// width = { dist = "normal", mean = 0.5, sd = 0.02, min = 0.4, max = 0.6 }
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct UncertaintyFile {
    /// Seed of the draws (default: the study's `seed`, or 1 with
    /// `record_files`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Base width 2B, m: a distribution.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub width: Option<Value>,
    /// Aspect ratio H/B: a distribution.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub aspect: Option<Value>,
    /// Coefficient of restitution e: a distribution within [0, 1].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub restitution: Option<Value>,
    /// Static friction μs: a distribution or a number (needs `mu_k_over_mu_s`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mu_s: Option<Value>,
    /// μk/μs within [0, 1]: a distribution or a number (needs `mu_s`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mu_k_over_mu_s: Option<Value>,
    /// Direction φ the blocks face, degrees from the first component of
    /// each record pair: a distribution, drawn once per record (the same at
    /// every level and for every case), or a number (only with record
    /// pairs; default with pairs and no `grid.orientation`: uniform on
    /// [0°, 180°), since an object's orientation is rarely known). Drawn
    /// with `seed`, as the block's parameters are.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub orientation: Option<Value>,
    /// The drawn properties of the bodies of the study's stacks, by the
    /// stack's name and the body's (`base`, `middle`, `top`):
    /// `[uncertainty.stack.statue_on_pedestal.top]` (see [`StackDrawEntry`]).
    #[serde(skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub stack:
        std::collections::BTreeMap<String, std::collections::BTreeMap<String, StackDrawEntry>>,
}

/// `[uncertainty.stack.NAME.BODY]`: what one body of a stack draws per
/// analysis, each replacing its value in `[[grid.stack]]`; `restitution`,
/// `mu_s` and `mu_k_over_mu_s` are those of the interface the body stands
/// on, as a single block's are of its contact with the ground.
///
/// ```toml
/// [uncertainty.stack.statue_on_pedestal.top]
/// width = { dist = "normal", mean = 0.3, sd = 0.01, min = 0.27, max = 0.33 }
/// restitution = { dist = "uniform", min = 0.0, max = 0.3 }
/// mu_s = { dist = "lognormal", median = 0.6, beta = 0.15 }
/// mu_k_over_mu_s = 0.85
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StackDrawEntry {
    /// Width 2B, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub width: Option<Value>,
    /// Height 2H, m (or `aspect`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub height: Option<Value>,
    /// Aspect ratio H/B (or `height`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub aspect: Option<Value>,
    /// Relative mass (where the stack gives masses).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mass: Option<Value>,
    /// Relative density (where the stack gives no masses).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub density: Option<Value>,
    /// Offset from the centre of the body below, m (not the base's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub offset: Option<Value>,
    /// Restitution of the interface under the body.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub restitution: Option<Value>,
    /// μs of the interface under the body (with `mu_k_over_mu_s`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mu_s: Option<Value>,
    /// μk/μs of the interface under the body (with `mu_s`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mu_k_over_mu_s: Option<Value>,
}

impl StackDrawEntry {
    /// The values given, in the order of
    /// [`crate::uncertainty::StackProperty::ALL`].
    pub fn values(&self) -> [Option<Value>; 9] {
        [
            self.width,
            self.height,
            self.aspect,
            self.mass,
            self.density,
            self.offset,
            self.restitution,
            self.mu_s,
            self.mu_k_over_mu_s,
        ]
    }

    /// The entry that gives `values` (in the order of [`StackDrawEntry::values`]).
    pub fn from_values(values: [Option<Value>; 9]) -> StackDrawEntry {
        let [
            width,
            height,
            aspect,
            mass,
            density,
            offset,
            restitution,
            mu_s,
            mu_k_over_mu_s,
        ] = values;
        StackDrawEntry {
            width,
            height,
            aspect,
            mass,
            density,
            offset,
            restitution,
            mu_s,
            mu_k_over_mu_s,
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
    /// Solve every analysis a second time under its record scaled by
    /// 1 + 1e-9 and add `sensitive` to `outcomes.csv`: whether the outcome
    /// changed (overturning flipped, θmax/θc moved by more than 1e-3 or the
    /// overturning time by more than 0.01 s; [`crate::solver::sensitivity()`]),
    /// with the share of sensitive analyses per case and stripe in
    /// `summary.md`. Doubles the run time (default: false). Left out of the
    /// canonical spec when false, so that a study without it keeps its hash.
    #[serde(skip_serializing_if = "is_false")]
    pub sensitivity: bool,
}

/// Whether a switch is off (it is then left out of the canonical spec).
fn is_false(b: &bool) -> bool {
    !*b
}

impl Default for OutputFile {
    fn default() -> Self {
        OutputFile {
            summary: true,
            time_in_mode: false,
            stats: false,
            figures: false,
            sensitivity: false,
        }
    }
}

/// One entry of `record_files`: a file (one horizontal component), or the
/// two horizontal components of one record, `["a-H1.AT2", "a-H2.AT2"]`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "a file name \"a.AT2\" or a pair of component files [\"a-H1.AT2\", \"a-H2.AT2\"]"
)]
pub enum RecordEntry {
    /// One component.
    One(String),
    /// Two horizontal components, H1 then H2.
    Pair([String; 2]),
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
}
/// `[motion]` as written: a named preset (`preset = "shenton-jones"`) and
/// any field of [`SynthesisSettings`] to override it (or the default model
/// without a preset); a field left out takes the preset's (or default)
/// value, `g` the study's.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MotionFile {
    /// A named model ([`crate::motion::PRESETS`]) whose settings the other
    /// fields override (default: none, the default model).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub preset: Option<String>,
    /// Target power spectral density.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub psd: Option<CloughPenzien>,
    /// Frequency step Δf, Hz.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub df: Option<f64>,
    /// Lowest component frequency, Hz.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub f_min: Option<f64>,
    /// Highest component frequency, Hz.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub f_max: Option<f64>,
    /// Sample interval Δt, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// Record duration, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub duration: Option<f64>,
    /// Time envelope.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub envelope: Option<Envelope>,
    /// High-pass filter and integration.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub baseline: Option<Baseline>,
    /// Gravity, m/s² (must be the study's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub g: Option<f64>,
}

impl MotionFile {
    /// Every field of `s` written out, no preset: the canonical form.
    pub fn from_settings(s: &SynthesisSettings) -> MotionFile {
        MotionFile {
            preset: None,
            psd: Some(s.psd.clone()),
            df: s.df,
            f_min: Some(s.f_min),
            f_max: Some(s.f_max),
            dt: Some(s.dt),
            duration: Some(s.duration),
            envelope: Some(s.envelope.clone()),
            baseline: Some(s.baseline.clone()),
            g: Some(s.g),
        }
    }

    /// The settings: `base` (a preset's, or the default) with the fields
    /// given here.
    pub fn resolve(&self, base: SynthesisSettings) -> SynthesisSettings {
        SynthesisSettings {
            psd: self.psd.clone().unwrap_or(base.psd),
            df: self.df.or(base.df),
            f_min: self.f_min.unwrap_or(base.f_min),
            f_max: self.f_max.unwrap_or(base.f_max),
            dt: self.dt.unwrap_or(base.dt),
            duration: self.duration.unwrap_or(base.duration),
            envelope: self.envelope.clone().unwrap_or(base.envelope),
            baseline: self.baseline.clone().unwrap_or(base.baseline),
            g: self.g.unwrap_or(base.g),
        }
    }
}

/// One `[[grid.stack]]` table as written.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StackEntry {
    /// The stack's name in `outcomes.csv`'s `stack` column and its case id
    /// `stack_NAME` (default: `stack1`, `stack2`, … in the order given).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The blocks, bottom first (2 or 3).
    pub blocks: Vec<StackBlockEntry>,
    /// The interface under each block, bottom first (the ground's first).
    pub interfaces: Vec<StackInterfaceEntry>,
}

/// One block of a `[[grid.stack]]` as written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StackBlockEntry {
    /// Width 2B, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub width: Option<f64>,
    /// Height 2H, m (or `aspect`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// Aspect ratio H/B (or `height`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub aspect: Option<f64>,
    /// Mass relative to the other blocks' (or `density`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
    /// Density relative to the other blocks' (default 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
    /// Offset of the centre from the centre of the block below, m
    /// (default 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub offset: Option<f64>,
}

/// The interface under a block, as written.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StackInterfaceEntry {
    /// Coefficient of restitution e in [0, 1].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    /// `"inf"` (the default without `mu_s`, `mu_k`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction: Option<String>,
    /// Static friction coefficient μs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mu_s: Option<f64>,
    /// Kinetic friction coefficient μk ≤ μs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mu_k: Option<f64>,
}
