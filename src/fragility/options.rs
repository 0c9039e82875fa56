//! What a fit is asked for: the intensity measure, the limit states and the
//! fit's settings (the spec's `[fragility]` table).

use std::collections::HashMap;

use serde::{Deserialize, Serialize};

use crate::case::Field;
use crate::error::{Error, Result};
use crate::im::{Im, ImPair};
use crate::outcomes_csv::{Column, MeasureKind};

/// Most limit states a fit accepts (each analysis keeps its exceedances as
/// the bits of a `u64`).
pub const MAX_LIMIT_STATES: usize = 64;

/// One limit state: exceeded by an analysis that overturned, or whose
/// `measure` is above `exceeds` (or, for a yes/no measure, is yes).
///
/// ```toml
/// [[fragility.limit_state]]
/// name = "slides-5cm"
/// measure = "slip_max"
/// exceeds = 0.05
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LimitState {
    /// Name, written to the `limit_state` column (unique within a fit).
    pub name: String,
    /// A numeric or yes/no column of `outcomes.csv` (see [`Column::measure_kind`]).
    pub measure: String,
    /// Threshold: exceeded when the measure is above it. Required for a
    /// numeric measure, left out for a yes/no one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exceeds: Option<f64>,
}

impl LimitState {
    /// The one limit state of a fit that names none: overturning.
    pub fn overturning() -> Self {
        LimitState {
            name: "overturning".into(),
            measure: Column::Overturned.name().into(),
            exceeds: None,
        }
    }

    /// The measure's column, if `measure` names one that can be a measure:
    /// a column of `outcomes.csv`, a body's (`top.overturned`,
    /// `base.theta_max_over_theta_c`), or `any.` a stack-wide one (`any.X`
    /// is the column `X`: overturned, uplifted, moved if any body did; the
    /// largest θmax/θc or slip of the bodies).
    pub fn column(&self) -> Option<(Column, MeasureKind)> {
        let name = match self.measure.strip_prefix("any.") {
            Some(rest)
                if crate::outcomes_csv::BodyField::ALL
                    .iter()
                    .any(|f| f.name() == rest) =>
            {
                rest
            }
            Some(_) => return None,
            None => &self.measure,
        };
        Column::from_name(name).and_then(|c| c.measure_kind().map(|k| (c, k)))
    }

    /// The body whose limit state this is (`top.overturned`: the top),
    /// `None` for a block's or a stack-wide one. Limit states are ordered
    /// in severity within one body's.
    pub fn body(&self) -> Option<crate::outcome::Slot> {
        match self.column() {
            Some((Column::Body(slot, _), _)) => Some(slot),
            _ => None,
        }
    }
}

/// The values of one IM that `outcomes.csv` does not hold, for every
/// motion (level, record) of a study folder: measured on the study's
/// records (`study::measure_records`) and handed to the fit in
/// [`FragilityOptions::measured`].
#[derive(Clone, Debug, PartialEq)]
pub struct RecordIms {
    /// The IM.
    pub im: Im,
    /// The `outcomes.csv` column holding each row's level.
    pub level_column: Column,
    /// The value of each (level's bits, record).
    pub values: HashMap<(u64, usize), f64>,
}

impl RecordIms {
    /// The IM of record `record` at level `level` (as the level column
    /// holds it), if measured.
    pub fn get(&self, level: f64, record: usize) -> Option<f64> {
        self.values.get(&(level.to_bits(), record)).copied()
    }

    /// Motions measured.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether none was.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }
}

/// The most bootstrap replicates a fit draws: 10⁵. Each costs about 200
/// bytes of memory, 30 µs of fitting per 200 analyses and a 78-byte row of
/// `fragility_bootstrap.csv` for every curve, and more buy nothing: the
/// Monte Carlo error of a 90 % band's ends is about 0.6 % of its width at
/// 10⁴ replicates and 0.2 % at 10⁵ (√(q(1−q)/B)/φ(z_q) standard deviations
/// at q = 0.05). `--bootstrap 1000000000` aborted on an allocation.
pub const MAX_BOOTSTRAP: usize = 100_000;

/// The most points of a curve's IM grid (`grid_points`): 10⁴, a point
/// every 0.01 % of the curve's range; each is a row of
/// `fragility_curves.csv` and is evaluated for every bootstrap replicate.
pub const MAX_GRID_POINTS: usize = 10_000;

/// Settings of the fragility fit. Plain data with documented defaults.
/// Read from and written to a spec's `[fragility]` table (through a
/// private mirror whose `im` is one name or a list of two).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(from = "OptionsFile", into = "OptionsFile")]
pub struct FragilityOptions {
    /// Intensity measure ([`Im`]; default: PGA in g, or a record pair's
    /// RotD50 PGA for a study of pairs, which the spec's validation fills
    /// in when the spec names none). With [`FragilityOptions::surface`],
    /// the surface's IM1 (spec: the first of `im = ["pga", "pgv"]`).
    pub im: Option<Im>,
    /// The second IM of a fragility surface P(LS | IM1, IM2) fitted beside
    /// the curves (spec: the second of `im = ["pga", "pgv"]`; command
    /// line: `--im pga,pgv`); `None` (the default): no surface.
    pub surface: Option<Im>,
    /// The values of an IM `outcomes.csv` does not hold (`sa(T)`, …),
    /// measured on the study's records by `study::measure_records`; not
    /// part of a spec. Holds `im`'s and, for a surface, the second IM's.
    pub measured: Vec<std::sync::Arc<RecordIms>>,
    /// Bootstrap replicates, at most [`MAX_BOOTSTRAP`]; 0 skips the
    /// bootstrap and leaves the bands empty (default: 1000).
    pub bootstrap: usize,
    /// What a replicate resamples (default: whole records, shared across stripes).
    pub unit: BootstrapUnit,
    /// Seed of the bootstrap; replicate r draws from a generator seeded with
    /// `replicate_seed(seed, r)`, a splitmix of the two (default: 1).
    pub seed: u64,
    /// Two-sided confidence level of the intervals and bands, in (0, 1)
    /// (default: 0.9, i.e. the 5th and 95th percentiles).
    pub confidence: f64,
    /// Points of each curve's IM grid, evenly spaced from 0 to the largest
    /// intensity of the case, from 2 to [`MAX_GRID_POINTS`] (default: 101).
    pub grid_points: usize,
    /// Limit states in order of increasing severity, one fit per case and
    /// limit state (spec: `[[fragility.limit_state]]`; default: none, which
    /// means overturning alone, see [`FragilityOptions::limit_states`]).
    pub limit_state: Vec<LimitState>,
    /// Case parameters pooled into one curve: those a study draws per
    /// analysis (its `[uncertainty]`, filled in when the spec is read), or
    /// any a user chooses (`rockfrag fragility --pool`). Not a spec field.
    pub pool: Vec<Field>,
    /// The precision an adaptive run stops at (with `grid.pga = { min, max }`;
    /// [`super::precision::Precision`], docs/adaptive.md). Default: none, a fixed grid.
    pub precision: Option<super::precision::Precision>,
    /// The most analyses an adaptive run spends on one case (default with
    /// `precision`: [`super::precision::DEFAULT_MAX_ANALYSES`]).
    pub max_analyses: Option<usize>,
}

/// `[fragility]` as a spec writes it: [`FragilityOptions`]' spec fields,
/// in their order, with `im` one name or a list of two.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
struct OptionsFile {
    #[serde(skip_serializing_if = "Option::is_none")]
    im: Option<ImField>,
    bootstrap: usize,
    unit: BootstrapUnit,
    seed: u64,
    confidence: f64,
    grid_points: usize,
    #[serde(rename = "limit_state", skip_serializing_if = "Vec::is_empty")]
    limit_state: Vec<LimitState>,
    #[serde(skip_serializing_if = "Option::is_none")]
    precision: Option<super::precision::Precision>,
    #[serde(skip_serializing_if = "Option::is_none")]
    max_analyses: Option<usize>,
}

impl Default for OptionsFile {
    fn default() -> Self {
        FragilityOptions::default().into()
    }
}

impl From<OptionsFile> for FragilityOptions {
    fn from(f: OptionsFile) -> FragilityOptions {
        let (im, surface) = match f.im {
            None => (None, None),
            Some(ImField::One(im)) => (Some(im), None),
            Some(ImField::Pair(pair)) => (Some(pair.first()), Some(pair.second())),
        };
        FragilityOptions {
            im,
            surface,
            bootstrap: f.bootstrap,
            unit: f.unit,
            seed: f.seed,
            confidence: f.confidence,
            grid_points: f.grid_points,
            limit_state: f.limit_state,
            precision: f.precision,
            max_analyses: f.max_analyses,
            ..FragilityOptions::default()
        }
    }
}

impl From<FragilityOptions> for OptionsFile {
    fn from(o: FragilityOptions) -> OptionsFile {
        let im = match (o.im, o.surface) {
            (Some(first), Some(second)) => ImPair::new(first, second).ok().map(ImField::Pair),
            (im, _) => im.map(ImField::One),
        };
        OptionsFile {
            im,
            bootstrap: o.bootstrap,
            unit: o.unit,
            seed: o.seed,
            confidence: o.confidence,
            grid_points: o.grid_points,
            limit_state: o.limit_state,
            precision: o.precision,
            max_analyses: o.max_analyses,
        }
    }
}

/// A spec's `im`: one name (`"pga"`), or a list of two for a surface
/// (`["pga", "pgv"]`).
#[derive(Clone, Copy, Debug, PartialEq)]
enum ImField {
    One(Im),
    Pair(ImPair),
}

impl Serialize for ImField {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            ImField::One(im) => im.serialize(s),
            ImField::Pair(p) => [p.first(), p.second()].serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for ImField {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<ImField, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Given {
            One(String),
            List(Vec<String>),
        }
        let given = Given::deserialize(d).map_err(|_| {
            serde::de::Error::custom(
                "expected an intensity measure (\"pga\") or a list of two for a fragility \
                 surface ([\"pga\", \"pgv\"])",
            )
        })?;
        match given {
            Given::One(name) => Im::try_from(name)
                .map(ImField::One)
                .map_err(serde::de::Error::custom),
            Given::List(names) => {
                let quoted: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
                ImPair::from_names(&names).map(ImField::Pair).map_err(|e| {
                    serde::de::Error::custom(format!("[{}]: expected {e}", quoted.join(", ")))
                })
            }
        }
    }
}

impl Default for FragilityOptions {
    fn default() -> Self {
        FragilityOptions {
            im: None,
            surface: None,
            measured: Vec::new(),
            bootstrap: 1000,
            unit: BootstrapUnit::Records,
            seed: 1,
            confidence: 0.9,
            grid_points: 101,
            limit_state: Vec::new(),
            pool: Vec::new(),
            precision: None,
            max_analyses: None,
        }
    }
}

impl FragilityOptions {
    /// The intensity measure fitted against: the one given, else PGA.
    pub fn im(&self) -> Im {
        self.im.unwrap_or_default()
    }

    /// The two IMs of the fragility surface asked for, if any.
    pub fn surface_pair(&self) -> Option<ImPair> {
        ImPair::new(self.im(), self.surface?).ok()
    }

    /// The measured values of `im` among [`FragilityOptions::measured`].
    pub fn measured_of(&self, im: Im) -> Option<&RecordIms> {
        self.measured.iter().map(|m| &**m).find(|m| m.im == im)
    }

    /// The limit states fitted: those given, or overturning alone.
    pub fn limit_states(&self) -> Vec<LimitState> {
        if self.limit_state.is_empty() {
            vec![LimitState::overturning()]
        } else {
            self.limit_state.clone()
        }
    }

    /// Checks the ranges documented on each field, and that the limit states
    /// have distinct names, known measures, a threshold exactly when the
    /// measure is numeric, thresholds that rise along a measure, and
    /// overturning (if named) last: an overturned analysis exceeds every
    /// limit state, so none can be more severe.
    pub fn validate(&self) -> Result<()> {
        if let Some(second) = self.surface
            && second == self.im()
        {
            return Err(Error::invalid(
                "fragility.im",
                format!("[\"{second}\", \"{second}\"]"),
                "two different intensity measures for a fragility surface",
            ));
        }
        if !(self.confidence > 0.0 && self.confidence < 1.0) {
            return Err(Error::invalid(
                "fragility.confidence",
                self.confidence,
                "a number in (0, 1)",
            ));
        }
        if !(2..=MAX_GRID_POINTS).contains(&self.grid_points) {
            return Err(Error::invalid(
                "fragility.grid_points",
                self.grid_points,
                &format!("an integer from 2 to {MAX_GRID_POINTS}"),
            ));
        }
        if self.bootstrap > MAX_BOOTSTRAP {
            return Err(Error::invalid(
                "fragility.bootstrap",
                self.bootstrap,
                &bootstrap_limit(),
            ));
        }
        if self.limit_state.len() > MAX_LIMIT_STATES {
            return Err(Error::invalid(
                "fragility.limit_state",
                self.limit_state.len(),
                &format!("at most {MAX_LIMIT_STATES} limit states"),
            ));
        }
        for (i, ls) in self.limit_state.iter().enumerate() {
            let field = |f: &str| format!("fragility.limit_state[{i}].{f}");
            let earlier = &self.limit_state[..i];
            // The name is written into fragility.xml.
            if !is_nrml_name(&ls.name) {
                return Err(Error::invalid(
                    &field("name"),
                    format!("{:?}", ls.name),
                    "a name of ASCII letters, digits, '_' and '-' (OpenQuake's limit-state names)",
                ));
            }
            if earlier.iter().any(|e| e.name == ls.name) {
                return Err(Error::invalid(
                    &field("name"),
                    format!("{:?}", ls.name),
                    "a limit-state name not already used",
                ));
            }
            let Some((column, kind)) = ls.column() else {
                if let Some((body, what)) = ls.measure.split_once('.') {
                    let slots = crate::outcome::Slot::ALL.map(|s| s.name()).join(", ");
                    let fields = crate::outcomes_csv::BodyField::ALL
                        .map(|f| f.name())
                        .join(", ");
                    let known = body == "any" || crate::outcome::Slot::from_name(body).is_some();
                    return Err(Error::invalid(
                        &field("measure"),
                        format!("{:?}", ls.measure),
                        &if known {
                            format!(
                                "a body's measure: BODY.FIELD with FIELD one of {fields} (not {what:?})"
                            )
                        } else {
                            format!(
                                "a body's measure BODY.FIELD with BODY one of {slots} or any \
                                 (bodies are named by their place, bottom first): no body \
                                 {body:?}"
                            )
                        },
                    ));
                }
                return Err(Error::invalid(
                    &field("measure"),
                    format!("{:?}", ls.measure),
                    &format!(
                        "a numeric or yes/no column of outcomes.csv: {}",
                        Column::measures()
                            .map(Column::name)
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ));
            };
            match (kind, ls.exceeds) {
                (MeasureKind::Flag, Some(x)) => {
                    return Err(Error::invalid(
                        &field("exceeds"),
                        x,
                        &format!("no threshold: `{}` is a yes/no column", ls.measure),
                    ));
                }
                (MeasureKind::Number, None) => {
                    return Err(Error::invalid(
                        &field("measure"),
                        format!("{:?}", ls.measure),
                        "an `exceeds` threshold beside a numeric measure",
                    ));
                }
                (MeasureKind::Number, Some(x)) if !x.is_finite() => {
                    return Err(Error::invalid(&field("exceeds"), x, "a finite number"));
                }
                _ => {}
            }
            if let Some(prev) = earlier.iter().rev().find(|e| e.measure == ls.measure) {
                let expected = match prev.exceeds {
                    Some(t) => format!(
                        "a threshold above {t}, that of the less severe limit state {:?} \
                         on the same measure (limit states go in order of increasing severity)",
                        prev.name
                    ),
                    None => format!(
                        "a measure other than that of limit state {:?}, which it would repeat",
                        prev.name
                    ),
                };
                let exceeds = ls.exceeds.zip(prev.exceeds);
                if exceeds.is_none_or(|(x, t)| x <= t) {
                    return match ls.exceeds {
                        Some(x) => Err(Error::invalid(&field("exceeds"), x, &expected)),
                        None => Err(Error::invalid(
                            &field("measure"),
                            format!("{:?}", ls.measure),
                            &expected,
                        )),
                    };
                }
            }
            if column == Column::Overturned && i + 1 < self.limit_state.len() {
                return Err(Error::invalid(
                    &field("measure"),
                    format!("{:?}", ls.measure),
                    "overturning only in the last limit state: an overturned analysis \
                     exceeds every limit state, so none can be more severe",
                ));
            }
        }
        Ok(())
    }
}

/// Whether `w` is a name OpenQuake's NRML reader takes for a limit state or
/// a fragility function: a non-empty word of ASCII letters, digits, `_`
/// and `-`.
pub fn is_nrml_name(w: &str) -> bool {
    !w.is_empty()
        && w.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

crate::io_util::named!(BootstrapUnit, "resample" {
    Records => "records",
    Analyses => "analyses",
});

/// What a bootstrap replicate resamples.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum BootstrapUnit {
    /// Whole records (default): as many records as the case has are drawn
    /// with replacement, and a drawn record brings its analyses at *every*
    /// stripe. Right for a study that scales the same records to each stripe,
    /// where one record's outcomes at different stripes are correlated.
    #[default]
    Records,
    /// Analyses, independently within each stripe (each stripe keeps its
    /// size). Right only when analyses are independent trials, e.g. a
    /// different record for every analysis.
    Analyses,
}

/// What [`MAX_BOOTSTRAP`] allows and why, for the messages of the spec
/// field and of `--bootstrap`.
pub fn bootstrap_limit() -> String {
    format!(
        "a number of replicates from 0 to {MAX_BOOTSTRAP}: each costs about 200 bytes of \
         memory and a row of fragility_bootstrap.csv per curve, and more do not sharpen the \
         90 % bands (their ends' Monte Carlo error is 0.6 % of their width at 10000 replicates, \
         0.2 % at 100000)"
    )
}
