//! The columns of `outcomes.csv`: their one definition.
//!
//! [`Column`] names every column the file can have; the lists below give
//! their order. The writer ([`super::OutcomeRow::write_field`]) writes the columns of a
//! [`Columns`] in the order of [`Columns::list`], and every reader finds
//! them by [`Column::name`], so a column is added, renamed or moved here
//! and nowhere else.

use std::borrow::Cow;

use crate::im::Im;
use crate::outcome::{BodySummary, Mode, Outcome, Slot};

/// One column of `outcomes.csv`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Column {
    /// Aspect ratio H/B.
    Aspect,
    /// Base width 2B (m).
    Width,
    /// Coefficient of restitution e.
    Restitution,
    /// Friction model: `inf` or `coulomb`.
    Friction,
    /// Static friction coefficient μs (empty under `inf`).
    MuS,
    /// Kinetic friction coefficient μk (empty under `inf`).
    MuK,
    /// An intensity measure of the record ([`Im::COLUMNS`]), in its unit:
    /// `pga` (g) and `pgv` (m/s), the level or the scaled record's measured
    /// peak; `pga_rotd50`, `pgv_rotd50` of a record pair (studies of pairs:
    /// the level, or the scaled pair's measured RotD50; `pga` is then the
    /// peak of the component the block feels); `pfa`, `pfv` of the floor
    /// the block stands on (studies with `[support] floor`). Named by
    /// [`Im::column`].
    Im(Im),
    /// Record index in the ensemble (0-based).
    Record,
    /// The record file as the spec names it (recorded motions only; a
    /// pair's two files joined by ` + `).
    RecordFile,
    /// The direction the block faces, degrees from the pair's first
    /// component (studies of record pairs).
    Phi,
    /// The factor the record was multiplied by (`scale_factors` studies).
    Scale,
    /// `ok` or `failed`.
    Status,
    /// |θ| reached π/2.
    Overturned,
    /// Time of overturning (s; empty if none).
    OverturnTime,
    /// N reached 0 while rocking at least once.
    Uplifted,
    /// Rest was broken.
    Moved,
    /// Peak |θ|/θc.
    ThetaMaxOverThetaC,
    /// Peak |F|/N while rocking, μ_mot; in an overturned run, before its
    /// final excursion beyond θc, where N → 0 (see [`Outcome::mu_motion`]).
    MuMotion,
    /// Peak |P_t/P_n| over impacts, μ_imp.
    MuImpact,
    /// Peak of the paper's eq. (5) over impacts (see [`Outcome::mu_impact_eq5`]).
    MuImpactEq5,
    /// Corner impacts.
    Impacts,
    /// Free-flight phases.
    Flights,
    /// Rock → flight lift-offs.
    Uplifts,
    /// Lift-offs held because the release was inconsistent.
    LiftoffHolds,
    /// Impacts that gained kinetic energy.
    EnergyGains,
    /// Ring-down settles.
    Settles,
    /// Peak |slip| (m).
    SlipMax,
    /// Slip at the end (m, signed).
    SlipFinal,
    /// Painlevé holds under finite friction.
    StickHolds,
    /// Time at which the analysis ended (s).
    EndTime,
    /// Time of the first impact (s; empty if none).
    FirstImpactTime,
    /// Time in one mode (s); a cascade the cascade rule settles counts as
    /// rock for its closed-form duration (see [`Outcome::time_in_mode`]).
    TimeIn(Mode),
    /// Right-hand-side evaluations.
    RhsCalls,
    /// Accepted Runge–Kutta steps.
    StepsAccepted,
    /// Rejected Runge–Kutta steps.
    StepsRejected,
    /// Events handled.
    Events,
    /// The analysis solved again under its record scaled by 1 + 1e-9 changed
    /// its outcome (see [`crate::solver::sensitivity()`]); empty when either
    /// solve failed.
    Sensitive,
    /// Why the analysis failed (empty if it did not).
    Error,
    /// The stack the analysis is of (studies with `[[grid.stack]]`; empty
    /// for a block's row): its name.
    Stack,
    /// Which body of the stack overturned first (`base`, `middle`, `top`;
    /// empty if none, or for a block).
    FirstOverturned,
    /// One body's response (`top.overturned`, …; empty for a block's row).
    Body(Slot, BodyField),
    /// One body's value in the analysis (`top.width`, …: drawn values as
    /// drawn; studies whose stacks draw under `[uncertainty]`; empty for a
    /// block's row).
    BodyValue(Slot, ValueField),
}

/// One body's values in a stack study whose stacks draw
/// (`[uncertainty.stack]`), each named `SLOT.FIELD` (`top.width`,
/// `base.mu_s`): the body's own and those of the interface under it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ValueField {
    /// Width 2B (m).
    Width,
    /// Height 2H (m).
    Height,
    /// Mass, relative to the others'.
    Mass,
    /// Offset of its centre from the centre of the body below (m).
    Offset,
    /// Restitution of the interface under it.
    Restitution,
    /// μs of the interface under it (empty under infinite friction).
    MuS,
    /// μk of the interface under it (empty under infinite friction).
    MuK,
}

impl ValueField {
    /// Every field, in column order.
    pub const ALL: [ValueField; 7] = [
        ValueField::Width,
        ValueField::Height,
        ValueField::Mass,
        ValueField::Offset,
        ValueField::Restitution,
        ValueField::MuS,
        ValueField::MuK,
    ];

    /// The field's name.
    pub fn name(self) -> &'static str {
        match self {
            ValueField::Width => "width",
            ValueField::Height => "height",
            ValueField::Mass => "mass",
            ValueField::Offset => "offset",
            ValueField::Restitution => "restitution",
            ValueField::MuS => "mu_s",
            ValueField::MuK => "mu_k",
        }
    }

    /// The field of `b` (`None`: μ under infinite friction).
    pub fn of(self, b: &crate::case::BodyValues) -> Option<f64> {
        use crate::solver::Friction;
        match (self, b.friction) {
            (ValueField::Width, _) => Some(b.width),
            (ValueField::Height, _) => Some(b.height),
            (ValueField::Mass, _) => Some(b.mass),
            (ValueField::Offset, _) => Some(b.offset),
            (ValueField::Restitution, _) => Some(b.restitution),
            (ValueField::MuS, Friction::Coulomb { mu_s, .. }) => Some(mu_s),
            (ValueField::MuK, Friction::Coulomb { mu_k, .. }) => Some(mu_k),
            (_, Friction::Infinite) => None,
        }
    }
}

/// One body's columns in a stack study's `outcomes.csv`, each named
/// `SLOT.FIELD` (`base.overturned`, `top.theta_max_over_theta_c`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyField {
    /// Peak |φ|/θc of the body on the face below, over its own θc.
    ThetaMaxOverThetaC,
    /// The body overturned (or the body under it did, and it fell with it).
    Overturned,
    /// When it overturned (s; empty if it did not).
    OverturnTime,
    /// Peak |slip| on the face below (m).
    SlipMax,
    /// The interface under it opened at least once.
    Uplifted,
    /// It moved relative to the face below.
    Moved,
}

impl BodyField {
    /// Every field, in column order.
    pub const ALL: [BodyField; 6] = [
        BodyField::ThetaMaxOverThetaC,
        BodyField::Overturned,
        BodyField::OverturnTime,
        BodyField::SlipMax,
        BodyField::Uplifted,
        BodyField::Moved,
    ];

    /// The field's name, as a block's column of the same meaning.
    pub fn name(self) -> &'static str {
        match self {
            BodyField::ThetaMaxOverThetaC => "theta_max_over_theta_c",
            BodyField::Overturned => "overturned",
            BodyField::OverturnTime => "overturn_time",
            BodyField::SlipMax => "slip_max",
            BodyField::Uplifted => "uplifted",
            BodyField::Moved => "moved",
        }
    }

    /// The field of `b` as a measure: a flag 1 or 0, an absent time `None`.
    fn measure(self, b: &BodySummary) -> Option<f64> {
        let flag = |x: bool| Some(if x { 1.0 } else { 0.0 });
        match self {
            BodyField::ThetaMaxOverThetaC => Some(b.theta_max_over_theta_c),
            BodyField::Overturned => flag(b.overturned),
            BodyField::OverturnTime => b.overturn_time,
            BodyField::SlipMax => Some(b.slip_max),
            BodyField::Uplifted => flag(b.uplifted),
            BodyField::Moved => flag(b.moved),
        }
    }
}

/// The outcome columns a stack's row leaves empty: the stack solver does
/// not compute them (see [`Outcome::stack`]).
pub const STACK_EMPTY: [Column; 14] = [
    Column::MuMotion,
    Column::MuImpactEq5,
    Column::Flights,
    Column::Uplifts,
    Column::StickHolds,
    Column::SlipFinal,
    Column::TimeIn(Mode::Rest),
    Column::TimeIn(Mode::Slide),
    Column::TimeIn(Mode::Rock),
    Column::TimeIn(Mode::SlideRock),
    Column::TimeIn(Mode::Flight),
    Column::RhsCalls,
    Column::StepsAccepted,
    Column::StepsRejected,
];

/// The case columns: one block configuration ([`crate::case::Case`]).
pub const CASE: [Column; 6] = [
    Column::Aspect,
    Column::Width,
    Column::Restitution,
    Column::Friction,
    Column::MuS,
    Column::MuK,
];

/// The pair's orientation-independent peaks, after the felt component's
/// (studies of record pairs).
pub const ROTD50: [Column; 2] = [Column::Im(Im::PGA_ROTD50), Column::Im(Im::PGV_ROTD50)];

/// The floor's peaks, after the ground's (studies on a floor).
pub const FLOOR: [Column; 2] = [Column::Im(Im::PFA), Column::Im(Im::PFV)];

/// The ground's peaks, which every file has.
pub const GROUND: [Column; 2] = [Column::Im(Im::PGA), Column::Im(Im::PGV)];

/// The outcome columns every file has, after `status`.
pub const OUTCOME: [Column; 19] = [
    Column::Overturned,
    Column::OverturnTime,
    Column::Uplifted,
    Column::Moved,
    Column::ThetaMaxOverThetaC,
    Column::MuMotion,
    Column::MuImpact,
    Column::MuImpactEq5,
    Column::Impacts,
    Column::Flights,
    Column::Uplifts,
    Column::LiftoffHolds,
    Column::EnergyGains,
    Column::Settles,
    Column::SlipMax,
    Column::SlipFinal,
    Column::StickHolds,
    Column::EndTime,
    Column::FirstImpactTime,
];

/// The time-in-mode columns (`[output] time_in_mode`), in the order of [`Mode::ALL`].
pub const TIME_IN_MODE: [Column; 5] = [
    Column::TimeIn(Mode::Rest),
    Column::TimeIn(Mode::Slide),
    Column::TimeIn(Mode::Rock),
    Column::TimeIn(Mode::SlideRock),
    Column::TimeIn(Mode::Flight),
];

/// The solver's work counters (`[output] stats`).
pub const STATS: [Column; 4] = [
    Column::RhsCalls,
    Column::StepsAccepted,
    Column::StepsRejected,
    Column::Events,
];

/// The sensitivity column (`[output] sensitivity`).
pub const SENSITIVITY: [Column; 1] = [Column::Sensitive];

/// What a column holds, when it can serve as a limit state's measure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeasureKind {
    /// A yes/no flag (`true`/`false`).
    Flag,
    /// A number (an empty field, e.g. a time that did not occur, is absent).
    Number,
}

impl Column {
    /// The column named `name`, among every column a file can have.
    pub fn from_name(name: &str) -> Option<Column> {
        Columns::ALL.list().into_iter().find(|c| c.name() == name)
    }

    /// The column of intensity measure `im` (`None` for one computed from
    /// others, PGA/(g tan θc)).
    pub fn of_im(im: Im) -> Option<Column> {
        im.column().map(|_| Column::Im(im))
    }

    /// Whether the column can be a limit state's measure, and as what: the
    /// outcome columns ([`OUTCOME`], [`TIME_IN_MODE`], [`STATS`]) are.
    pub fn measure_kind(self) -> Option<MeasureKind> {
        match self {
            Column::Overturned | Column::Uplifted | Column::Moved => Some(MeasureKind::Flag),
            Column::Body(_, BodyField::Overturned | BodyField::Uplifted | BodyField::Moved) => {
                Some(MeasureKind::Flag)
            }
            Column::Body(..) => Some(MeasureKind::Number),
            c if OUTCOME.contains(&c) || TIME_IN_MODE.contains(&c) || STATS.contains(&c) => {
                Some(MeasureKind::Number)
            }
            _ => None,
        }
    }

    /// Every column that can be a measure, in file order.
    pub fn measures() -> impl Iterator<Item = Column> {
        OUTCOME
            .into_iter()
            .chain(TIME_IN_MODE)
            .chain(STATS)
            .filter(|c| c.measure_kind().is_some())
    }

    /// The column's name in the header.
    pub fn name(self) -> Cow<'static, str> {
        if let Column::Im(im) = self {
            return Cow::Owned(im.column().unwrap_or_else(|| im.name()));
        }
        if let Column::Body(slot, field) = self {
            return Cow::Owned(format!("{}.{}", slot.name(), field.name()));
        }
        if let Column::BodyValue(slot, field) = self {
            return Cow::Owned(format!("{}.{}", slot.name(), field.name()));
        }
        Cow::Borrowed(self.static_name())
    }

    /// The name of a column other than an IM's.
    const fn static_name(self) -> &'static str {
        match self {
            Column::Im(_) | Column::Body(..) | Column::BodyValue(..) => "",
            Column::Stack => "stack",
            Column::FirstOverturned => "first_overturned",
            Column::Aspect => "aspect",
            Column::Width => "width",
            Column::Restitution => "restitution",
            Column::Friction => "friction",
            Column::MuS => "mu_s",
            Column::MuK => "mu_k",
            Column::Record => "record",
            Column::RecordFile => "record_file",
            Column::Phi => "phi",
            Column::Scale => "scale",
            Column::Status => "status",
            Column::Overturned => "overturned",
            Column::OverturnTime => "overturn_time",
            Column::Uplifted => "uplifted",
            Column::Moved => "moved",
            Column::ThetaMaxOverThetaC => "theta_max_over_theta_c",
            Column::MuMotion => "mu_motion",
            Column::MuImpact => "mu_impact",
            Column::MuImpactEq5 => "mu_impact_eq5",
            Column::Impacts => "impacts",
            Column::Flights => "flights",
            Column::Uplifts => "uplifts",
            Column::LiftoffHolds => "liftoff_holds",
            Column::EnergyGains => "energy_gains",
            Column::Settles => "settles",
            Column::SlipMax => "slip_max",
            Column::SlipFinal => "slip_final",
            Column::StickHolds => "stick_holds",
            Column::EndTime => "end_time",
            Column::FirstImpactTime => "first_impact_time",
            Column::TimeIn(Mode::Rest) => "t_rest",
            Column::TimeIn(Mode::Slide) => "t_slide",
            Column::TimeIn(Mode::Rock) => "t_rock",
            Column::TimeIn(Mode::SlideRock) => "t_slide_rock",
            Column::TimeIn(Mode::Flight) => "t_flight",
            Column::RhsCalls => "rhs_calls",
            Column::StepsAccepted => "steps_accepted",
            Column::StepsRejected => "steps_rejected",
            Column::Events => "events",
            Column::Sensitive => "sensitive",
            Column::Error => "error",
        }
    }

    /// Writes this outcome column's value of `o` to `out` (nothing for a
    /// column that is not an outcome column, or an absent time). Floats use
    /// Rust's shortest round-trip form.
    pub fn write_value(self, o: &Outcome, out: &mut String) {
        use std::fmt::Write;
        fn opt(out: &mut String, x: Option<f64>) {
            if let Some(v) = x {
                let _ = write!(out, "{v}");
            }
        }
        if o.stack.is_some() && STACK_EMPTY.contains(&self) {
            return;
        }
        let s = &o.stats;
        let _ = match self {
            Column::FirstOverturned => {
                if let Some(slot) = o.stack.and_then(|s| s.first_overturned) {
                    out.push_str(slot.name());
                }
                Ok(())
            }
            Column::Body(slot, field) => {
                if let Some(b) = o.stack.and_then(|s| s.bodies[slot.index()]) {
                    match field {
                        BodyField::Overturned => write!(out, "{}", b.overturned),
                        BodyField::Uplifted => write!(out, "{}", b.uplifted),
                        BodyField::Moved => write!(out, "{}", b.moved),
                        f => {
                            opt(out, f.measure(&b));
                            Ok(())
                        }
                    }
                } else {
                    Ok(())
                }
            }
            Column::Overturned => write!(out, "{}", o.overturned),
            Column::OverturnTime => {
                opt(out, o.overturn_time);
                Ok(())
            }
            Column::Uplifted => write!(out, "{}", o.uplifted),
            Column::Moved => write!(out, "{}", o.moved),
            Column::ThetaMaxOverThetaC => write!(out, "{}", o.theta_max_over_theta_c),
            Column::MuMotion => write!(out, "{}", o.mu_motion),
            Column::MuImpact => write!(out, "{}", o.mu_impact),
            Column::MuImpactEq5 => write!(out, "{}", o.mu_impact_eq5),
            Column::Impacts => write!(out, "{}", o.impacts),
            Column::Flights => write!(out, "{}", o.flights),
            Column::Uplifts => write!(out, "{}", o.uplifts),
            Column::LiftoffHolds => write!(out, "{}", o.liftoff_holds),
            Column::EnergyGains => write!(out, "{}", o.energy_gains),
            Column::Settles => write!(out, "{}", o.settles),
            Column::SlipMax => write!(out, "{}", o.slip_max),
            Column::SlipFinal => write!(out, "{}", o.slip_final),
            Column::StickHolds => write!(out, "{}", o.stick_holds),
            Column::EndTime => write!(out, "{}", o.end_time),
            Column::FirstImpactTime => {
                opt(out, o.first_impact_time);
                Ok(())
            }
            Column::TimeIn(mode) => write!(out, "{}", o.time_in_mode[mode.index()]),
            Column::RhsCalls => write!(out, "{}", s.rhs_calls),
            Column::StepsAccepted => write!(out, "{}", s.steps_accepted),
            Column::StepsRejected => write!(out, "{}", s.steps_rejected),
            Column::Events => write!(out, "{}", s.events),
            _ => Ok(()),
        };
    }
}

/// What a column's values are, for a reader that types them (Python's
/// `read_outcomes`: booleans, whole numbers, floats or text).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ValueKind {
    /// `true` or `false`.
    Flag,
    /// A whole number ≥ 0.
    Count,
    /// A number; empty when absent (a time that did not occur, a failed
    /// analysis's outcome).
    Number,
    /// Text.
    Text,
}

impl Column {
    /// The kind of the column's values.
    pub fn value_kind(self) -> ValueKind {
        match self {
            Column::Overturned | Column::Uplifted | Column::Moved | Column::Sensitive => {
                ValueKind::Flag
            }
            Column::Body(_, BodyField::Overturned | BodyField::Uplifted | BodyField::Moved) => {
                ValueKind::Flag
            }
            Column::Record
            | Column::Impacts
            | Column::Flights
            | Column::Uplifts
            | Column::LiftoffHolds
            | Column::EnergyGains
            | Column::Settles
            | Column::StickHolds
            | Column::RhsCalls
            | Column::StepsAccepted
            | Column::StepsRejected
            | Column::Events => ValueKind::Count,
            Column::Friction
            | Column::RecordFile
            | Column::Status
            | Column::Error
            | Column::Stack
            | Column::FirstOverturned => ValueKind::Text,
            _ => ValueKind::Number,
        }
    }

    /// Sets this outcome column's field of `o` from its text (the inverse
    /// of [`Column::write_value`]); a column that is not an outcome column
    /// is ignored. Errors: what was expected.
    pub fn read_value(self, o: &mut Outcome, text: &str) -> Result<(), &'static str> {
        fn flag(t: &str) -> Result<bool, &'static str> {
            match t {
                "true" | "1" => Ok(true),
                "false" | "0" => Ok(false),
                _ => Err("true or false"),
            }
        }
        fn count(t: &str) -> Result<u64, &'static str> {
            t.parse().map_err(|_| "a whole number ≥ 0")
        }
        fn num(t: &str) -> Result<f64, &'static str> {
            t.parse().map_err(|_| "a number")
        }
        fn opt(t: &str) -> Result<Option<f64>, &'static str> {
            if t.is_empty() {
                Ok(None)
            } else {
                num(t).map(Some)
            }
        }
        if o.stack.is_some() && text.is_empty() {
            // a stack's row leaves empty what the stack solver does not compute
            return Ok(());
        }
        if let Column::Body(slot, field) = self {
            if text.is_empty() {
                return Ok(());
            }
            let stack = o.stack.get_or_insert_with(Default::default);
            let b = stack.bodies[slot.index()].get_or_insert_with(Default::default);
            match field {
                BodyField::ThetaMaxOverThetaC => b.theta_max_over_theta_c = num(text)?,
                BodyField::Overturned => b.overturned = flag(text)?,
                BodyField::OverturnTime => b.overturn_time = opt(text)?,
                BodyField::SlipMax => b.slip_max = num(text)?,
                BodyField::Uplifted => b.uplifted = flag(text)?,
                BodyField::Moved => b.moved = flag(text)?,
            }
            return Ok(());
        }
        if self == Column::FirstOverturned {
            if !text.is_empty() {
                let slot = Slot::from_name(text).ok_or("base, middle, top or empty")?;
                o.stack
                    .get_or_insert_with(Default::default)
                    .first_overturned = Some(slot);
            }
            return Ok(());
        }
        let s = &mut o.stats;
        match self {
            Column::Overturned => o.overturned = flag(text)?,
            Column::OverturnTime => o.overturn_time = opt(text)?,
            Column::Uplifted => o.uplifted = flag(text)?,
            Column::Moved => o.moved = flag(text)?,
            Column::ThetaMaxOverThetaC => o.theta_max_over_theta_c = num(text)?,
            Column::MuMotion => o.mu_motion = num(text)?,
            Column::MuImpact => o.mu_impact = num(text)?,
            Column::MuImpactEq5 => o.mu_impact_eq5 = num(text)?,
            Column::Impacts => o.impacts = count(text)?,
            Column::Flights => o.flights = count(text)?,
            Column::Uplifts => o.uplifts = count(text)?,
            Column::LiftoffHolds => o.liftoff_holds = count(text)?,
            Column::EnergyGains => o.energy_gains = count(text)?,
            Column::Settles => o.settles = count(text)?,
            Column::SlipMax => o.slip_max = num(text)?,
            Column::SlipFinal => o.slip_final = num(text)?,
            Column::StickHolds => o.stick_holds = count(text)?,
            Column::EndTime => o.end_time = num(text)?,
            Column::FirstImpactTime => o.first_impact_time = opt(text)?,
            Column::TimeIn(mode) => o.time_in_mode[mode.index()] = num(text)?,
            Column::RhsCalls => s.rhs_calls = count(text)?,
            Column::StepsAccepted => s.steps_accepted = count(text)?,
            Column::StepsRejected => s.steps_rejected = count(text)?,
            Column::Events => s.events = count(text)?,
            _ => {}
        }
        Ok(())
    }

    /// This outcome column's value of `o` as a number, for a limit state's
    /// measure: a flag is 1 or 0, a count or number itself, an absent time
    /// `None`; `None` for a column that is not an outcome column.
    pub fn measure(self, o: &Outcome) -> Option<f64> {
        if let Column::Body(slot, field) = self {
            return o.body(slot).and_then(|b| field.measure(&b));
        }
        let s = &o.stats;
        let flag = |b: bool| Some(if b { 1.0 } else { 0.0 });
        match self {
            Column::Overturned => flag(o.overturned),
            Column::OverturnTime => o.overturn_time,
            Column::Uplifted => flag(o.uplifted),
            Column::Moved => flag(o.moved),
            Column::ThetaMaxOverThetaC => Some(o.theta_max_over_theta_c),
            Column::MuMotion => Some(o.mu_motion),
            Column::MuImpact => Some(o.mu_impact),
            Column::MuImpactEq5 => Some(o.mu_impact_eq5),
            Column::Impacts => Some(o.impacts as f64),
            Column::Flights => Some(o.flights as f64),
            Column::Uplifts => Some(o.uplifts as f64),
            Column::LiftoffHolds => Some(o.liftoff_holds as f64),
            Column::EnergyGains => Some(o.energy_gains as f64),
            Column::Settles => Some(o.settles as f64),
            Column::SlipMax => Some(o.slip_max),
            Column::SlipFinal => Some(o.slip_final),
            Column::StickHolds => Some(o.stick_holds as f64),
            Column::EndTime => Some(o.end_time),
            Column::FirstImpactTime => o.first_impact_time,
            Column::TimeIn(mode) => Some(o.time_in_mode[mode.index()]),
            Column::RhsCalls => Some(s.rhs_calls as f64),
            Column::StepsAccepted => Some(s.steps_accepted as f64),
            Column::StepsRejected => Some(s.steps_rejected as f64),
            Column::Events => Some(s.events as f64),
            _ => None,
        }
    }
}

impl std::fmt::Display for Column {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.name())
    }
}

/// Which optional columns an `outcomes.csv` has (the study decides: see
/// `study::columns`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Columns {
    /// The levels are PGV (else PGA).
    pub pgv: bool,
    /// Recorded motions (`record_file` column).
    pub files: bool,
    /// Record pairs (`pga_rotd50`, `pgv_rotd50` after `pgv`, `phi` after
    /// `record_file`; the level is then the RotD50).
    pub pairs: bool,
    /// Records multiplied by scale factors (`scale` column; `pga` and `pgv`
    /// are then both the scaled record's measured peaks).
    pub scale: bool,
    /// Time in each mode.
    pub time_in_mode: bool,
    /// Solver work counters.
    pub stats: bool,
    /// The blocks stand on a floor (`pfa`, `pfv` columns after `pgv`).
    pub floor: bool,
    /// Whether each analysis is sensitive (`sensitive` column).
    pub sensitivity: bool,
    /// The study has stacks (`[[grid.stack]]`): the `stack` column first,
    /// and after the outcome columns `first_overturned` and each body's
    /// columns (`base.…`, `top.…`).
    pub stack: bool,
    /// A stack of three: the `middle.…` columns too.
    pub middle: bool,
    /// The study's stacks draw properties (`[uncertainty.stack]`): each
    /// body's values (`base.width`, …, `top.mu_k`) after the case columns.
    pub stack_values: bool,
}

impl Columns {
    /// Every optional column: the layout that lists every column a file can
    /// have.
    pub const ALL: Columns = Columns {
        pgv: true,
        files: true,
        pairs: true,
        scale: true,
        time_in_mode: true,
        stats: true,
        floor: true,
        sensitivity: true,
        stack: true,
        middle: true,
        stack_values: true,
    };

    /// The outcome columns of a successful row, in order: [`OUTCOME`], then
    /// [`TIME_IN_MODE`] and [`STATS`] when present.
    pub fn outcome(&self) -> Vec<Column> {
        let mut v = OUTCOME.to_vec();
        if self.time_in_mode {
            v.extend(TIME_IN_MODE);
        }
        if self.stats {
            v.extend(STATS);
        }
        if self.stack {
            v.push(Column::FirstOverturned);
            for slot in Slot::ALL {
                if slot != Slot::Middle || self.middle {
                    v.extend(BodyField::ALL.map(|f| Column::Body(slot, f)));
                }
            }
        }
        v
    }

    /// Every column, in order: the case, the ground's peaks (and the
    /// floor's), `record` (and `record_file`, `scale`), `status`, the outcome
    /// columns, `sensitive` when present, `error`.
    pub fn list(&self) -> Vec<Column> {
        let mut v: Vec<Column> = Vec::new();
        if self.stack {
            v.push(Column::Stack);
        }
        v.extend(CASE);
        if self.stack_values {
            for slot in Slot::ALL {
                if slot != Slot::Middle || self.middle {
                    v.extend(ValueField::ALL.map(|f| Column::BodyValue(slot, f)));
                }
            }
        }
        v.extend(GROUND);
        if self.pairs {
            v.extend(ROTD50);
        }
        if self.floor {
            v.extend(FLOOR);
        }
        v.push(Column::Record);
        if self.files {
            v.push(Column::RecordFile);
        }
        if self.pairs {
            v.push(Column::Phi);
        }
        if self.scale {
            v.push(Column::Scale);
        }
        v.push(Column::Status);
        v.extend(self.outcome());
        if self.sensitivity {
            v.extend(SENSITIVITY);
        }
        v.push(Column::Error);
        v
    }

    /// Column names, in order.
    pub fn names(&self) -> Vec<Cow<'static, str>> {
        self.list().into_iter().map(Column::name).collect()
    }

    /// The header line, with its newline.
    pub fn header(&self) -> String {
        let mut s = self.names().join(",");
        s.push('\n');
        s
    }

    /// The level's column: `scale` for scale-factor studies, `pgv` for PGV
    /// studies, else `pga` (`pgv_rotd50`, `pga_rotd50` for record pairs).
    pub fn level(&self) -> Column {
        match (self.scale, self.pgv, self.pairs) {
            (true, _, _) => Column::Scale,
            (false, true, false) => Column::Im(Im::PGV),
            (false, true, true) => Column::Im(Im::PGV_ROTD50),
            (false, false, false) => Column::Im(Im::PGA),
            (false, false, true) => Column::Im(Im::PGA_ROTD50),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_distinct_and_the_header_is_the_documented_one() {
        let all = Columns {
            pgv: false,
            files: true,
            pairs: true,
            scale: true,
            time_in_mode: true,
            stats: true,
            floor: true,
            sensitivity: true,
            stack: false,
            middle: false,
            stack_values: false,
        };
        let names = all.names();
        let mut sorted = names.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(
            sorted.len(),
            names.len(),
            "duplicate column name in {names:?}"
        );
        // The layout documented in the module docs of `outcomes_csv`.
        assert_eq!(
            all.header(),
            "aspect,width,restitution,friction,mu_s,mu_k,pga,pgv,pga_rotd50,pgv_rotd50,pfa,pfv,\
             record,record_file,phi,scale,\
             status,overturned,overturn_time,uplifted,moved,theta_max_over_theta_c,\
             mu_motion,mu_impact,mu_impact_eq5,impacts,flights,uplifts,liftoff_holds,\
             energy_gains,settles,slip_max,slip_final,stick_holds,end_time,first_impact_time,\
             t_rest,t_slide,t_rock,t_slide_rock,t_flight,\
             rhs_calls,steps_accepted,steps_rejected,events,sensitive,error\n"
        );
    }
}
