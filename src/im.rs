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
//! Besides the peaks, the measures that govern rocking: the 5 %-damped
//! pseudo-spectral acceleration `sa(T)` at period T s, its geometric mean
//! over a log-spaced band of periods `sa-avg(T1,T2)`, and the ratio
//! `pgv/pga` (s; Purvance, Anooshehpoor and Brune's second axis). Each is
//! taken on the ground (`sa(1.0)`), on the floor (`sa(1.0)-floor`) or as a
//! record pair's RotD50 (`sa(1.0)-rotd50`). Their spectra come from the
//! exact recurrence of a linear oscillator under an acceleration linear
//! between samples ([`Oscillator`], the floor filter's).
//!
//! Names are case-insensitive and parsed once, like OpenQuake's
//! `imt.from_string`: `"PGA"`, `"pga"` and `" pga "` are one IM; every
//! file and message writes its canonical name ([`Im::name`]).
//!
//! Units are those the spec and the files use: accelerations in g (the
//! study's `g` converts), velocities in m/s.

use std::fmt;
use std::hash::{Hash, Hasher};

use crate::detmath as dm;
use crate::motion::{MeasuredPair, Oscillator, OscillatorState, Record, rotd_series};

/// Damping ratio of the oscillators of `sa(T)` and `sa-avg`: 5 % of
/// critical, that of the spectra ground-motion models and hazard give.
pub const SA_DAMPING: f64 = 0.05;

/// Shortest and longest period `sa(T)` takes, s: OpenQuake's models span
/// about 0.01–10 s.
pub const SA_PERIODS: (f64, f64) = (0.01, 10.0);

/// Periods of `sa-avg(T1,T2)`: log-spaced from T1 to T2, both included.
pub const SA_AVG_POINTS: usize = 10;

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
    /// 5 %-damped pseudo-spectral acceleration ω²·max|u| at a period, g.
    Sa {
        /// The oscillator's period T, s.
        period: f64,
    },
    /// Geometric mean of [`Measure::Sa`] over [`SA_AVG_POINTS`] periods
    /// log-spaced from `from` to `to`, g.
    SaAvg {
        /// Shortest period, s.
        from: f64,
        /// Longest period, s.
        to: f64,
    },
    /// PGV/PGA, s: the motion's characteristic period over 2π, the second
    /// axis of Purvance et al.'s fragility surfaces.
    PgvOverPga,
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
    /// PGV/PGA of the ground, s ([`Measure::PgvOverPga`]).
    pub const PGV_OVER_PGA: Im = Im::new(Measure::PgvOverPga, At::Ground);
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

    /// `sa(T)` of the ground, T in s: `None` outside [`SA_PERIODS`].
    pub fn sa(period: f64) -> Option<Im> {
        in_sa_range(period).then_some(Im::new(Measure::Sa { period }, At::Ground))
    }

    /// `sa-avg(T1,T2)` of the ground: `None` unless both are in
    /// [`SA_PERIODS`] and T1 < T2.
    pub fn sa_avg(from: f64, to: f64) -> Option<Im> {
        (in_sa_range(from) && in_sa_range(to) && from < to)
            .then_some(Im::new(Measure::SaAvg { from, to }, At::Ground))
    }

    /// Whether it is measured on the records: every IM but PGA/(g tan θc),
    /// which is the block's as much as the motion's.
    pub fn of_record(self) -> bool {
        self.measure != Measure::PgaOverTan
    }

    /// Whether `outcomes.csv` holds it ([`Im::COLUMNS`]); the others are
    /// measured on the records again when a fit asks for them.
    pub fn stored(self) -> bool {
        Im::COLUMNS.contains(&self)
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
            (Measure::Pga, _) => "pga".into(),
            (Measure::Pgv, _) => "pgv".into(),
            (Measure::PgaOverTan, _) => "pga-over-tan".into(),
            (Measure::Sa { period }, _) => format!("sa({})", period_text(period)),
            (Measure::SaAvg { from, to }, _) => {
                format!("sa-avg({},{})", period_text(from), period_text(to))
            }
            (Measure::PgvOverPga, _) => "pgv/pga".to_string(),
        };
        match self.at {
            At::RotD50 => format!("{base}-rotd50"),
            At::Floor => format!("{base}-floor"),
            At::Ground => base,
        }
    }

    /// Every form a name can take, for help texts and messages.
    pub fn forms() -> String {
        let plain: Vec<String> = Im::PLAIN.iter().map(|im| im.name()).collect();
        format!(
            "{}, sa(T), sa-avg(T1,T2), pgv/pga (T in s, {}–{}; each also -floor or -rotd50)",
            plain.join(", "),
            SA_PERIODS.0,
            SA_PERIODS.1
        )
    }

    /// Its `outcomes.csv` column: the name with `-` written `_`
    /// (`pga_rotd50`); `None` for PGA/(g tan θc), computed from the `pga`
    /// column and the block.
    pub fn column(self) -> Option<String> {
        self.stored().then(|| self.name().replace('-', "_"))
    }

    /// The IM whose column is `name` ([`Im::column`]).
    pub fn from_column(name: &str) -> Option<Im> {
        let im: Im = name.replace('_', "-").parse().ok()?;
        (im.column().as_deref() == Some(name)).then_some(im)
    }

    /// Its unit: `g`, `m/s`, or `1` when dimensionless.
    pub fn unit(self) -> &'static str {
        match self.measure {
            Measure::Pga | Measure::Sa { .. } | Measure::SaAvg { .. } => "g",
            Measure::Pgv => "m/s",
            Measure::PgvOverPga => "s",
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
            (Measure::Pga, At::Floor) => "PFA".to_string(),
            (Measure::Pgv, At::Floor) => "PFV".to_string(),
            (Measure::Pga, _) => "PGA".to_string(),
            (Measure::Pgv, _) => "PGV".to_string(),
            (Measure::PgaOverTan, _) => "PGA/(g tan θc)".to_string(),
            (Measure::PgvOverPga, At::Floor) => "PFV/PFA".to_string(),
            (Measure::PgvOverPga, _) => "PGV/PGA".to_string(),
            (Measure::Sa { period }, _) => format!("Sa({} s)", period_text(period)),
            (Measure::SaAvg { from, to }, _) => {
                format!("Sa_avg({}–{} s)", period_text(from), period_text(to))
            }
        };
        match (self.at, self.measure) {
            (At::RotD50, _) => format!("RotD50 {base}"),
            (At::Floor, Measure::Sa { .. } | Measure::SaAvg { .. }) => format!("floor {base}"),
            _ => base,
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
            (Measure::Pga | Measure::Pgv, At::Floor) => format!(
                "the floor's peak {} {} in {}",
                if self.measure == Measure::Pga {
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
            (_, At::Floor) => format!(
                "the floor's {} (5 % damped) in {}",
                self.short(),
                self.unit()
            ),
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
        let text: String = s
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect::<String>()
            .to_ascii_lowercase();
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
            ("pgv/pga", at) => Im::of(Measure::PgvOverPga, at),
            (b, at) => spectral(b).and_then(|m| Im::of(m, at)),
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

/// The two IMs of a fragility surface P(LS | IM1, IM2): distinct, in the
/// order given (`IM1` is the one the one-IM curves are fitted against).
/// Written `pga,pgv` on the command line (commas inside a name's
/// parentheses, as in `sa-avg(0.5,2.0)`, do not split it) and
/// `["pga", "pgv"]` in a spec.
///
/// ```
/// use rockfrag::im::{Im, ImPair};
/// let pair = ImPair::parse("PGA, sa-avg(0.5,2)").unwrap().unwrap();
/// assert_eq!((pair.first(), pair.second().name()), (Im::PGA, "sa-avg(0.5,2.0)".to_string()));
/// assert_eq!(pair.to_string(), "pga,sa-avg(0.5,2.0)");
/// assert!(ImPair::parse("sa-avg(0.5,2)").is_none()); // one IM, not a pair
/// assert!(ImPair::parse("pga,pga").unwrap().is_err());
/// assert!(ImPair::parse("pga,pgv,pfa").unwrap().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ImPair {
    first: Im,
    second: Im,
}

impl ImPair {
    /// The pair, if the two differ. Errors: what was expected.
    pub fn new(first: Im, second: Im) -> Result<ImPair, String> {
        if first == second {
            return Err(format!(
                "two different intensity measures, not {first} twice"
            ));
        }
        Ok(ImPair { first, second })
    }

    /// The first IM (the surface's IM1; the one-IM curves' IM).
    pub fn first(self) -> Im {
        self.first
    }

    /// The second IM (IM2).
    pub fn second(self) -> Im {
        self.second
    }

    /// Reads `IM1,IM2`: `None` when `text` has no comma outside
    /// parentheses (it names one IM, or nothing); else the pair, or why
    /// not (not two parts, a part that is no IM, the same IM twice).
    pub fn parse(text: &str) -> Option<Result<ImPair, String>> {
        let parts = split_top_level(text);
        if parts.len() < 2 {
            return None;
        }
        Some(ImPair::from_names(&parts))
    }

    /// The pair named by `names` (exactly two IMs). Errors: what was
    /// expected, naming the values.
    pub fn from_names<S: AsRef<str>>(names: &[S]) -> Result<ImPair, String> {
        let shown: Vec<&str> = names.iter().map(AsRef::as_ref).collect();
        if names.len() != 2 {
            return Err(format!(
                "one intensity measure, or exactly two (IM1,IM2: a fragility surface, or \
                 `infer`'s joint posterior), not {} ({})",
                names.len(),
                shown.join(", ")
            ));
        }
        let im = |s: &str| {
            s.parse::<Im>()
                .map_err(|e| format!("two intensity measures, and `{}` is not {e}", s.trim()))
        };
        ImPair::new(im(shown[0])?, im(shown[1])?)
    }
}

impl fmt::Display for ImPair {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{}", self.first, self.second)
    }
}

/// `text` split at the commas outside parentheses.
fn split_top_level(text: &str) -> Vec<&str> {
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0i32, 0);
    for (i, c) in text.char_indices() {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&text[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&text[start..]);
    parts
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
            (_, At::Floor)
            | (Measure::PgaOverTan | Measure::SaAvg { .. } | Measure::PgvOverPga, _) => {
                return None;
            }
            (Measure::Pga, _) => ("PGA".to_string(), 1.0),
            // OpenQuake's PGV is in cm/s
            (Measure::Pgv, _) => ("PGV".to_string(), 100.0),
            // OpenQuake's SA(T) is 5 % damped, in g
            (Measure::Sa { period }, _) => (format!("SA({})", period_text(period)), 1.0),
        };
        Some(OpenQuakeImt { imt, factor })
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
        Some(match (self.at, self.measure) {
            (At::Floor, _) => format!(
                "fitted against {} (the floor's peak), an intensity OpenQuake's hazard does \
                 not compute; fit against pga (the ground's) for OpenQuake",
                self.name()
            ),
            (_, Measure::PgaOverTan) => "H/B is drawn per analysis, so PGA/(g tan θc) has no \
                                        single PGA equivalent; fit against PGA for OpenQuake"
                .into(),
            _ => format!(
                "fitted against {}, which OpenQuake has no IMT for; fit against pga, pgv or \
                 sa(T) for OpenQuake",
                self.name()
            ),
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
    /// P-58's names, pelicun 3.10's vocabulary); `None` when pelicun has
    /// none. Sa(T) of the ground is `Peak Spectral Acceleration|T` (pelicun
    /// reads it as the EDP `SA_T`, e.g. `SA_1.00` with the period written
    /// to two decimals when that is exact, as pelicun's own examples do).
    pub fn pelicun(self) -> Option<(String, &'static str)> {
        let named = |name: &str, unit| Some((name.to_string(), unit));
        match (self.measure, self.at) {
            (Measure::Pga, At::Ground | At::RotD50) => named("Peak Ground Acceleration", "g"),
            (Measure::Pgv, At::Ground | At::RotD50) => named("Peak Ground Velocity", "mps"),
            // pelicun's floor demands, at the floor the block stands on
            (Measure::Pga, At::Floor) => named("Peak Floor Acceleration", "g"),
            (Measure::Pgv, At::Floor) => named("Peak Floor Velocity", "mps"),
            (Measure::Sa { period }, At::Ground | At::RotD50) => {
                let two = format!("{period:.2}");
                let exact = two.parse::<f64>() == Ok(period);
                let t = if exact { two } else { format!("{period}") };
                Some((format!("Peak Spectral Acceleration|{t}"), "g"))
            }
            (Measure::Sa { .. }, At::Floor) => None,
            (Measure::PgaOverTan | Measure::SaAvg { .. } | Measure::PgvOverPga, _) => None,
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
                    // the ratio of the pair's RotD50 peaks (k cancels)
                    Measure::PgvOverPga => Some(pair.pgv / pair.pga),
                    Measure::Sa { period } => Some(k * sa_rotd50(pair, period)? / felt.g),
                    Measure::SaAvg { from, to } => {
                        geometric_mean(from, to, |t| sa_rotd50(pair, t)).map(|v| k * v / felt.g)
                    }
                };
            }
        };
        match self.measure {
            Measure::Pga => Some(record.pga() / felt.g),
            Measure::Pgv => Some(record.pgv()),
            Measure::PgaOverTan => None,
            Measure::PgvOverPga => Some(record.pgv() / record.pga()),
            Measure::Sa { period } => Some(spectral_acceleration(record, period)? / felt.g),
            Measure::SaAvg { from, to } => {
                geometric_mean(from, to, |t| spectral_acceleration(record, t)).map(|v| v / felt.g)
            }
        }
    }
}

/// The shortest text that reads back as `period` (`1.0`, `0.3`): how a
/// period is written in a name and in OpenQuake's IMT.
fn period_text(period: f64) -> String {
    format!("{period:?}")
}

/// Whether `period` is a period `sa(T)` takes ([`SA_PERIODS`]).
fn in_sa_range(period: f64) -> bool {
    (SA_PERIODS.0..=SA_PERIODS.1).contains(&period)
}

/// The spectral measure a base name (without `-floor`, `-rotd50`) names:
/// `sa(T)`, `sa-avg(T1,T2)`.
fn spectral(base: &str) -> Option<Measure> {
    let number = |t: &str| t.parse::<f64>().ok().filter(|p| p.is_finite());
    if let Some(args) = base
        .strip_prefix("sa-avg(")
        .and_then(|r| r.strip_suffix(')'))
    {
        let (a, b) = args.split_once(',')?;
        return Im::sa_avg(number(a)?, number(b)?).map(Im::measure);
    }
    let arg = base.strip_prefix("sa(")?.strip_suffix(')')?;
    Im::sa(number(arg)?).map(Im::measure)
}

/// The relative displacement u of the 5 %-damped oscillator of period
/// `period` under `acc` (m/s², linear between samples `dt` apart, at rest
/// at the start), at every sample: the floor filter's exact recurrence.
fn oscillator_response(acc: &[f64], dt: f64, period: f64) -> Option<(Oscillator, Vec<f64>)> {
    let osc = Oscillator::new(period, SA_DAMPING, dt).ok()?;
    let mut u = Vec::with_capacity(acc.len());
    let mut state = OscillatorState::default();
    u.push(state.disp);
    for w in acc.windows(2) {
        // Nigam and Jennings (1969): [u, u̇]ₖ₊₁ = A[u, u̇]ₖ + b₀ẍg[k] + b₁ẍg[k+1]
        state = osc.step(state, w[0], w[1]);
        u.push(state.disp);
    }
    Some((osc, u))
}

/// The 5 %-damped pseudo-spectral acceleration of `record` at `period`,
/// m/s²: Sa = ω²·max|u| over the samples.
///
/// ```
/// use rockfrag::im::spectral_acceleration;
/// use rockfrag::motion::Record;
/// // a stiff oscillator follows the ground: Sa(T → 0) = PGA
/// let r = Record::from_acc("r", 0.01, vec![0.0, 1.0, -2.0, 0.5, 0.0]).unwrap();
/// let sa = spectral_acceleration(&r, 0.01).unwrap();
/// assert!(sa > 0.0 && sa.is_finite());
/// ```
pub fn spectral_acceleration(record: &Record, period: f64) -> Option<f64> {
    let (osc, u) = oscillator_response(&record.acc, record.dt, period)?;
    // pseudo-spectral acceleration: PSa = ω² max|u|
    Some(osc.omega_sq * u.iter().fold(0.0_f64, |m, x| m.max(x.abs())))
}

/// The RotD50 of the 5 %-damped pseudo-spectral acceleration of an
/// unscaled record pair at `period`, m/s²: the median over directions of
/// ω²·max|u(θ)|, u(θ) = u₁ cos θ + u₂ sin θ (Boore 2010).
fn sa_rotd50(pair: &MeasuredPair, period: f64) -> Option<f64> {
    let (osc, u1) = oscillator_response(&pair.pair.h1.acc, pair.pair.h1.dt, period)?;
    let (_, u2) = oscillator_response(&pair.pair.h2.acc, pair.pair.h2.dt, period)?;
    // the oscillator is linear: the response to the rotated component is
    // the rotated response
    Some(osc.omega_sq * rotd_series(&u1, &u2, 50.0).ok()?)
}

/// The geometric mean of `f` over [`SA_AVG_POINTS`] periods log-spaced
/// from `from` to `to`.
fn geometric_mean(from: f64, to: f64, f: impl Fn(f64) -> Option<f64>) -> Option<f64> {
    let n = SA_AVG_POINTS;
    let (l0, l1) = (dm::ln(from), dm::ln(to));
    let mut sum = 0.0;
    for i in 0..n {
        let t = if i + 1 == n {
            to
        } else {
            dm::exp(l0 + (l1 - l0) * i as f64 / (n - 1) as f64)
        };
        // Sa_avg = (Π Sa(Tᵢ))^(1/n), summed in logs
        sum += dm::ln(f(t)?);
    }
    Some(dm::exp(sum / n as f64))
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

    /// The measures with periods: names round-trip in any case and
    /// spacing, to the shortest period text; OpenQuake's IMT is SA(T) in g
    /// for the ground's and a pair's Sa only; none is stored in
    /// outcomes.csv.
    #[test]
    fn spectral_names_round_trip() {
        for (given, name, imt) in [
            ("SA(1)", "sa(1.0)", Some("SA(1.0)")),
            (" sa( 0.30 ) ", "sa(0.3)", Some("SA(0.3)")),
            ("sa(2.0)-rotd50", "sa(2.0)-rotd50", Some("SA(2.0)")),
            ("sa(0.5)-FLOOR", "sa(0.5)-floor", None),
            ("sa-avg(0.2, 3)", "sa-avg(0.2,3.0)", None),
            ("PGV/PGA", "pgv/pga", None),
            ("pgv/pga-floor", "pgv/pga-floor", None),
        ] {
            let im: Im = given.parse().unwrap();
            assert_eq!(im.name(), name);
            assert_eq!(name.parse::<Im>(), Ok(im));
            assert_eq!(im.openquake().map(|o| o.imt).as_deref(), imt, "{given}");
            assert_eq!(im.column(), None);
            assert!(im.of_record() && !im.stored());
        }
        for bad in [
            "sa()",
            "sa(0)",
            "sa(11)",
            "sa(nan)",
            "sa-avg(1,0.5)",
            "sa-avg(1)",
            "sa(1)-x",
        ] {
            assert!(bad.parse::<Im>().is_err(), "{bad}");
        }
    }
}
