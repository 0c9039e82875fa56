//! Intensity measures (IMs): one type, [`Im`], for every stage.
//!
//! An IM is a measure of a motion ([`Measure`]: its peak acceleration or
//! velocity, or PGA/(g tan θc) of a block) taken somewhere ([`At`]: on the
//! ground the block would feel, on the floor it stands on, or over every
//! direction of a record pair, RotD50). Everything that depends on which IM
//! it is lives here and nowhere else:
//!
//! | what | where |
//! |---|---|
//! | the spec's and the command line's name (`pga`, `pfv`, `pga-rotd50`), parsed once | [`Im::name`], [`str::parse`] |
//! | its unit, and the factor from the unit to OpenQuake's | [`Im::unit`], [`Im::openquake`] |
//! | its `outcomes.csv` column | [`Im::column`], [`Im::from_column`] |
//! | OpenQuake's IMT (`PGA`, `PGV`) and a hazard curve's conversion | [`Im::openquake`], [`Im::from_openquake`] |
//! | pelicun's demand type | [`Im::pelicun`] |
//! | labels: axes, tables, sentences | [`Im::axis_label`], [`Im::short`], [`Im::description`] |
//! | how it is measured on the motion a block felt | [`Im::on`] |
//!
//! Names are case-insensitive and parsed once, like OpenQuake's
//! `imt.from_string`: `"PGA"`, `"pga"` and `" pga "` are one IM; every
//! file and message writes its canonical name ([`Im::name`]).
//!
//! Units are those the spec and the files use: accelerations in g (the
//! study's `g` converts), velocities in m/s.

use std::fmt;
use std::hash::{Hash, Hasher};

use crate::motion::{MeasuredPair, Record};

/// What is measured on a motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Measure {
    /// Peak acceleration, g.
    Pga,
    /// Peak velocity, m/s.
    Pgv,
    /// PGA/(g tan θc) = PGA·(H/B), dimensionless: 1 is the uplift threshold
    /// of a block on a rigid base under infinite friction. Of the block as
    /// much as of the motion: measured per analysis, from its PGA and H/B.
    PgaOverTan,
}

/// Where a measure is taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum At {
    /// The ground motion the block would feel on the ground (of a record
    /// pair: the component along the direction the block faces).
    Ground,
    /// The floor the block stands on (a study with `[support] floor`):
    /// the floor's absolute motion, what the block feels.
    Floor,
    /// The median over directions of the peak of a record pair's rotated
    /// component (Boore 2010), independent of how the block faces: what
    /// ground-motion models and OpenQuake's hazard give (studies of record
    /// pairs).
    RotD50,
}

/// An intensity measure: a [`Measure`] taken [`At`] some place.
///
/// ```
/// use rockfrag::im::Im;
/// let im: Im = "PGA-RotD50".parse().unwrap();
/// assert_eq!(im, Im::PGA_ROTD50);
/// assert_eq!(im.name(), "pga-rotd50");
/// assert_eq!(im.column().as_deref(), Some("pga_rotd50"));
/// assert_eq!(Im::PGV.openquake().map(|o| (o.imt, o.factor)), Some(("PGV".to_string(), 100.0)));
/// assert!("pga-floor-rotd50".parse::<Im>().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Im {
    measure: Measure,
    at: At,
}

// Every period an `Im` holds is finite (checked when it is made), so
// equality is an equivalence and hashing the bits agrees with it.
impl Eq for Im {}

impl Hash for Im {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.name().hash(state);
    }
}

impl Default for Im {
    /// Peak ground acceleration.
    fn default() -> Im {
        Im::PGA
    }
}

impl Im {
    /// Peak ground acceleration, g (the default).
    pub const PGA: Im = Im::new(Measure::Pga, At::Ground);
    /// Peak ground velocity, m/s.
    pub const PGV: Im = Im::new(Measure::Pgv, At::Ground);
    /// PGA/(g tan θc) = PGA·(H/B), dimensionless ([`Measure::PgaOverTan`]).
    pub const PGA_OVER_TAN: Im = Im::new(Measure::PgaOverTan, At::Ground);
    /// Peak floor acceleration, g: the peak absolute acceleration of the
    /// floor the block stands on. A risk calculation needs the hazard in
    /// PFA at that floor (a plain `iml,annual_rate` file).
    pub const PFA: Im = Im::new(Measure::Pga, At::Floor);
    /// Peak floor velocity, m/s, as [`Im::PFA`].
    pub const PFV: Im = Im::new(Measure::Pgv, At::Floor);
    /// RotD50 PGA of a record pair, g: the default measure of a study of
    /// pairs' fit.
    pub const PGA_ROTD50: Im = Im::new(Measure::Pga, At::RotD50);
    /// RotD50 PGV of a record pair, m/s.
    pub const PGV_ROTD50: Im = Im::new(Measure::Pgv, At::RotD50);

    /// The IMs `outcomes.csv` can hold a column of, in the file's order.
    pub const COLUMNS: [Im; 6] = [
        Im::PGA,
        Im::PGV,
        Im::PGA_ROTD50,
        Im::PGV_ROTD50,
        Im::PFA,
        Im::PFV,
    ];

    /// Every IM without a parameter, in the order the help lists them.
    pub const PLAIN: [Im; 7] = [
        Im::PGA,
        Im::PGV,
        Im::PGA_OVER_TAN,
        Im::PFA,
        Im::PFV,
        Im::PGA_ROTD50,
        Im::PGV_ROTD50,
    ];

    const fn new(measure: Measure, at: At) -> Im {
        Im { measure, at }
    }

    /// `measure` taken `at`, if that is an IM (PGA/(g tan θc) is the
    /// ground's only).
    pub fn of(measure: Measure, at: At) -> Option<Im> {
        match (measure, at) {
            (Measure::PgaOverTan, At::Floor | At::RotD50) => None,
            _ => Some(Im::new(measure, at)),
        }
    }

    /// What is measured.
    pub fn measure(self) -> Measure {
        self.measure
    }

    /// Where.
    pub fn at(self) -> At {
        self.at
    }

    /// Whether the IM is the floor's rather than the ground's.
    pub fn is_floor(self) -> bool {
        self.at == At::Floor
    }

    /// Whether the IM is a record pair's RotD50.
    pub fn is_rotd50(self) -> bool {
        self.at == At::RotD50
    }

    /// The same measure taken `at` (`None` where it is not an IM).
    pub fn taken(self, at: At) -> Option<Im> {
        Im::of(self.measure, at)
    }

    /// The canonical name: `pga`, `pgv`, `pga-over-tan`, `pfa`, `pfv`,
    /// `pga-rotd50`, `pgv-rotd50`. What the spec, the command line,
    /// Python and every file write.
    pub fn name(self) -> String {
        let base = match (self.measure, self.at) {
            (Measure::Pga, At::Floor) => return "pfa".into(),
            (Measure::Pgv, At::Floor) => return "pfv".into(),
            (Measure::Pga, _) => "pga",
            (Measure::Pgv, _) => "pgv",
            (Measure::PgaOverTan, _) => "pga-over-tan",
        };
        match self.at {
            At::RotD50 => format!("{base}-rotd50"),
            At::Floor => format!("{base}-floor"),
            At::Ground => base.into(),
        }
    }

    /// Every form a name can take, for help texts and messages.
    pub fn forms() -> String {
        let plain: Vec<String> = Im::PLAIN.iter().map(|im| im.name()).collect();
        plain.join(", ")
    }

    /// Its `outcomes.csv` column: the name with `-` written `_`
    /// (`pga_rotd50`); `None` for PGA/(g tan θc), computed from the `pga`
    /// column and the block.
    pub fn column(self) -> Option<String> {
        match self.measure {
            Measure::PgaOverTan => None,
            _ => Some(self.name().replace('-', "_")),
        }
    }

    /// The IM whose column is `name` ([`Im::column`]).
    pub fn from_column(name: &str) -> Option<Im> {
        let im: Im = name.replace('_', "-").parse().ok()?;
        (im.column().as_deref() == Some(name)).then_some(im)
    }

    /// Its unit: `g`, `m/s`, or `1` when dimensionless.
    pub fn unit(self) -> &'static str {
        match self.measure {
            Measure::Pga => "g",
            Measure::Pgv => "m/s",
            Measure::PgaOverTan => "1",
        }
    }

    /// ` (g)`, ` (m/s)`; empty when dimensionless: a unit after a name.
    pub fn unit_suffix(self) -> String {
        match self.unit() {
            "1" => String::new(),
            u => format!(" ({u})"),
        }
    }

    /// Its short name in headings and legends: `PGA`, `RotD50 PGV`, `PFA`,
    /// `PGA/(g tan θc)`.
    pub fn short(self) -> String {
        let base = match (self.measure, self.at) {
            (Measure::Pga, At::Floor) => "PFA",
            (Measure::Pgv, At::Floor) => "PFV",
            (Measure::Pga, _) => "PGA",
            (Measure::Pgv, _) => "PGV",
            (Measure::PgaOverTan, _) => "PGA/(g tan θc)",
        };
        match self.at {
            At::RotD50 => format!("RotD50 {base}"),
            _ => base.into(),
        }
    }

    /// The label of an axis of this IM: `PGA (g)`, `RotD50 PGV (m/s)`.
    pub fn axis_label(self) -> String {
        format!("{}{}", self.short(), self.unit_suffix())
    }

    /// What it is, in a sentence of the summary: `the PGA in g`, `the
    /// floor's peak velocity PFV in m/s`.
    pub fn description(self) -> String {
        match (self.measure, self.at) {
            (Measure::PgaOverTan, _) => "PGA/(g tan θc), dimensionless".into(),
            (m, At::Floor) => format!(
                "the floor's peak {} {} in {}",
                if m == Measure::Pga {
                    "acceleration"
                } else {
                    "velocity"
                },
                self.short(),
                self.unit()
            ),
            (_, At::RotD50) => {
                format!("the {} of the record pair in {}", self.short(), self.unit())
            }
            (_, At::Ground) => format!("the {} in {}", self.short(), self.unit()),
        }
    }
}

impl fmt::Display for Im {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}

impl std::str::FromStr for Im {
    type Err = String;

    /// Parses a name ([`Im::name`]), ignoring case and surrounding
    /// blanks. Errors: what was expected.
    fn from_str(s: &str) -> Result<Im, String> {
        let text = s.trim().to_ascii_lowercase();
        let (base, at) = if let Some(b) = text.strip_suffix("-rotd50") {
            (b, At::RotD50)
        } else if let Some(b) = text.strip_suffix("-floor") {
            (b, At::Floor)
        } else {
            (text.as_str(), At::Ground)
        };
        let found = match (base, at) {
            ("pfa", At::Ground) => Some(Im::PFA),
            ("pfv", At::Ground) => Some(Im::PFV),
            // the floor's peaks are written pfa, pfv
            ("pga" | "pgv", At::Floor) => None,
            ("pga", at) => Im::of(Measure::Pga, at),
            ("pgv", at) => Im::of(Measure::Pgv, at),
            ("pga-over-tan", at) => Im::of(Measure::PgaOverTan, at),
            _ => None,
        };
        found.ok_or_else(|| format!("an intensity measure: {} (case ignored)", Im::forms()))
    }
}

impl crate::error::Shown for Im {
    fn shown(&self) -> String {
        self.name()
    }
}

impl From<Im> for String {
    fn from(im: Im) -> String {
        im.name()
    }
}

impl TryFrom<String> for Im {
    type Error = String;

    /// Serde's message for an unknown name.
    fn try_from(s: String) -> Result<Im, String> {
        s.parse()
            .map_err(|e| format!("unknown intensity measure `{s}`: expected {e}"))
    }
}

impl serde::Serialize for Im {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.name())
    }
}

impl<'de> serde::Deserialize<'de> for Im {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Im, D::Error> {
        let s = String::deserialize(d)?;
        Im::try_from(s).map_err(serde::de::Error::custom)
    }
}

/// An OpenQuake intensity measure type and how an intensity in rockfrag's
/// unit becomes one in OpenQuake's.
#[derive(Clone, Debug, PartialEq)]
pub struct OpenQuakeImt {
    /// The IMT as OpenQuake writes it: `PGA`, `PGV`.
    pub imt: String,
    /// OpenQuake's intensity = rockfrag's × this (PGV: m/s to cm/s, 100).
    pub factor: f64,
}

impl Im {
    /// OpenQuake's IMT of this IM and the factor to its unit (PGA in g,
    /// PGV in cm/s); `None` when OpenQuake has none: the floor's peaks
    /// (OpenQuake's hazard is the ground's) and PGA/(g tan θc) (a block's
    /// own; see [`Im::openquake_for`]). OpenQuake's PGA and PGV are what
    /// its ground-motion models give, for most of them the RotD50 of the
    /// two components: a pair's RotD50 maps to them, and so does a single
    /// component's peak.
    pub fn openquake(self) -> Option<OpenQuakeImt> {
        let (imt, factor) = match (self.measure, self.at) {
            (_, At::Floor) | (Measure::PgaOverTan, _) => return None,
            (Measure::Pga, _) => ("PGA", 1.0),
            // OpenQuake's PGV is in cm/s
            (Measure::Pgv, _) => ("PGV", 100.0),
        };
        Some(OpenQuakeImt {
            imt: imt.into(),
            factor,
        })
    }

    /// As [`Im::openquake`], for a block of H/B `aspect` (`None`: drawn
    /// per analysis): PGA/(g tan θc) is OpenQuake's PGA divided by H/B,
    /// for a block whose H/B is fixed.
    pub fn openquake_for(self, aspect: Option<f64>) -> Option<OpenQuakeImt> {
        match self.measure {
            Measure::PgaOverTan if self.at == At::Ground => aspect.map(|a| OpenQuakeImt {
                imt: "PGA".into(),
                factor: 1.0 / a,
            }),
            _ => self.openquake(),
        }
    }

    /// Why a curve against this IM has no OpenQuake function, for the
    /// comment `fragility.xml` writes in its place (`aspect` as in
    /// [`Im::openquake_for`]); `None` when it has one.
    pub fn no_openquake_reason(self, aspect: Option<f64>) -> Option<String> {
        if self.openquake_for(aspect).is_some() {
            return None;
        }
        Some(match self.at {
            At::Floor => format!(
                "fitted against {} (the floor's peak), an intensity OpenQuake's hazard does \
                 not compute; fit against pga (the ground's) for OpenQuake",
                self.name()
            ),
            _ => "H/B is drawn per analysis, so PGA/(g tan θc) has no single PGA \
                  equivalent; fit against PGA for OpenQuake"
                .into(),
        })
    }

    /// The factor that brings the levels of an OpenQuake hazard curve of
    /// IMT `imt` to this IM's unit, when the curve is of this IM (PGV in
    /// cm/s becomes m/s: 0.01); `None` when it is not.
    pub fn from_openquake(self, imt: &str) -> Option<f64> {
        let o = self.openquake()?;
        (o.imt == imt).then(|| 1.0 / o.factor)
    }

    /// The hazard curve a fit against this IM needs, in words (for the
    /// message refusing one of another IMT).
    pub fn openquake_hint(self) -> String {
        match (self.at, self.openquake()) {
            (At::Floor, _) => "the floor's peak: OpenQuake computes ground hazard only, so give a \
                               plain iml,annual_rate file of the floor's peak (e.g. a floor \
                               spectrum hazard), or refit against pga"
                .into(),
            (_, Some(o)) if o.factor == 1.0 => format!("{} ({})", o.imt, self.unit()),
            (_, Some(o)) if o.imt == "PGV" => "PGV (cm/s)".into(),
            (_, Some(o)) => o.imt,
            (_, None) => "the fit's IM (no OpenQuake IMT matches it; use a plain \
                          iml,annual_rate file)"
                .into(),
        }
    }

    /// What a plain `iml,annual_rate` file in another unit than this IM's
    /// likely holds, for the message refusing it: `None` when its levels
    /// are not checked (a dimensionless IM).
    pub fn other_units(self) -> Option<&'static str> {
        match self.unit() {
            "g" => Some("cm/s² (gal; divide by 981 for g) or m/s² (divide by 9.81)"),
            "m/s" => Some("cm/s (divide by 100 for m/s)"),
            _ => None,
        }
    }

    /// pelicun's demand type and unit for curves against this IM (FEMA
    /// P-58's names); `None` when pelicun has none.
    pub fn pelicun(self) -> Option<(&'static str, &'static str)> {
        match (self.measure, self.at) {
            (Measure::Pga, At::Ground | At::RotD50) => Some(("Peak Ground Acceleration", "g")),
            (Measure::Pgv, At::Ground | At::RotD50) => Some(("Peak Ground Velocity", "mps")),
            // pelicun's floor demands, at the floor the block stands on
            (Measure::Pga, At::Floor) => Some(("Peak Floor Acceleration", "g")),
            (Measure::Pgv, At::Floor) => Some(("Peak Floor Velocity", "mps")),
            (Measure::PgaOverTan, _) => None,
        }
    }
}

/// The motion one analysis felt, as [`Im::on`] reads it.
#[derive(Clone, Copy, Debug)]
pub struct Felt<'a> {
    /// The ground record (of a record pair: the component the block
    /// faces), scaled to the level.
    pub ground: &'a Record,
    /// The floor's absolute motion under it (`None` on the ground).
    pub floor: Option<&'a Record>,
    /// The record pair and the factor it was scaled by (`None` without
    /// pairs).
    pub pair: Option<(&'a MeasuredPair, f64)>,
    /// Gravity, m/s².
    pub g: f64,
}

impl Im {
    /// This IM of the motion `felt`; `None` where it is not defined (the
    /// floor's on the ground, a RotD50 without a pair, PGA/(g tan θc),
    /// which is the block's as much as the motion's).
    pub fn on(self, felt: &Felt) -> Option<f64> {
        let record = match self.at {
            At::Ground => felt.ground,
            At::Floor => felt.floor?,
            At::RotD50 => {
                let (pair, k) = felt.pair?;
                return match self.measure {
                    // the scaled pair's RotD50: every rotated peak scales by k
                    Measure::Pga => Some(k * pair.pga / felt.g),
                    Measure::Pgv => Some(k * pair.pgv),
                    Measure::PgaOverTan => None,
                };
            }
        };
        match self.measure {
            Measure::Pga => Some(record.pga() / felt.g),
            Measure::Pgv => Some(record.pgv()),
            Measure::PgaOverTan => None,
        }
    }
}

/// The IMs measured on one motion: at most one value per IM.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImValues(Vec<(Im, f64)>);

impl ImValues {
    /// No values.
    pub fn new() -> ImValues {
        ImValues(Vec::new())
    }

    /// The value of `im`, if measured.
    pub fn get(&self, im: Im) -> Option<f64> {
        self.0.iter().find(|(i, _)| *i == im).map(|&(_, v)| v)
    }

    /// Sets the value of `im` (replacing one already there).
    pub fn set(&mut self, im: Im, value: f64) {
        match self.0.iter_mut().find(|(i, _)| *i == im) {
            Some(slot) => slot.1 = value,
            None => self.0.push((im, value)),
        }
    }

    /// Every value, in the order they were set.
    pub fn iter(&self) -> impl Iterator<Item = (Im, f64)> + '_ {
        self.0.iter().copied()
    }

    /// `ims` of `felt` ([`Im::on`]), those defined.
    pub fn of(ims: &[Im], felt: &Felt) -> ImValues {
        ImValues(
            ims.iter()
                .filter_map(|&im| im.on(felt).map(|v| (im, v)))
                .collect(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every plain IM's name parses back to it, in any case and with
    /// blanks; its column (if any) maps back to it; names and columns are
    /// distinct.
    #[test]
    fn names_and_columns_round_trip() {
        let mut names = Vec::new();
        for im in Im::PLAIN {
            let name = im.name();
            assert_eq!(name.parse::<Im>(), Ok(im), "{name}");
            assert_eq!(format!(" {} ", name.to_uppercase()).parse::<Im>(), Ok(im));
            if let Some(c) = im.column() {
                assert_eq!(Im::from_column(&c), Some(im), "{c}");
                assert!(!c.contains('-'), "{c}");
            }
            names.push(name);
        }
        names.sort();
        names.dedup();
        assert_eq!(names.len(), Im::PLAIN.len());
        for bad in [
            "",
            "pg",
            "pfa-rotd50",
            "pga-over-tan-floor",
            "pga-floor",
            "sa",
        ] {
            assert!(bad.parse::<Im>().is_err(), "{bad}");
        }
        assert_eq!(Im::from_column("pga-rotd50"), None);
    }

    /// The conversions to OpenQuake's units and back are exact inverses
    /// where an IMT exists (PGV in cm/s: 100 and 0.01).
    #[test]
    fn openquake_factors_invert() {
        assert_eq!(Im::PGV.from_openquake("PGV"), Some(0.01));
        assert_eq!(Im::PGA_ROTD50.from_openquake("PGA"), Some(1.0));
        assert_eq!(Im::PGA.from_openquake("PGV"), None);
        assert_eq!(Im::PFA.openquake(), None);
        assert_eq!(
            Im::PGA_OVER_TAN.openquake_for(Some(4.0)).map(|o| o.factor),
            Some(0.25)
        );
        assert!(Im::PGA_OVER_TAN.no_openquake_reason(None).is_some());
    }
}
