//! What one analysis (one block, one record) produces: a small summary struct.

use serde::Serialize;

/// Modes of motion of the block (the paper's five).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mode {
    /// At rest on both corners.
    Rest,
    /// Sliding on both corners (finite friction only).
    Slide,
    /// Rocking about a stuck corner.
    Rock,
    /// Rocking about a slipping corner (finite friction only).
    SlideRock,
    /// No contact.
    Flight,
}

impl Mode {
    /// All modes, in the order of [`Outcome::time_in_mode`].
    pub const ALL: [Mode; 5] = [
        Mode::Rest,
        Mode::Slide,
        Mode::Rock,
        Mode::SlideRock,
        Mode::Flight,
    ];

    /// Lower-case name used in CSV and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Rest => "rest",
            Mode::Slide => "slide",
            Mode::Rock => "rock",
            Mode::SlideRock => "slide-rock",
            Mode::Flight => "flight",
        }
    }

    /// Index into [`Outcome::time_in_mode`].
    pub fn index(self) -> usize {
        self as usize
    }
}

/// Work counters of one analysis (for the speed-against-error report).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Stats {
    /// Right-hand-side evaluations of the rock equation.
    pub rhs_calls: u64,
    /// Accepted Runge–Kutta steps.
    pub steps_accepted: u64,
    /// Rejected Runge–Kutta steps.
    pub steps_rejected: u64,
    /// Events handled (impacts, landings, uplifts, starts, settles, …).
    pub events: u64,
}

/// Summary of one analysis. Angles in rad, times in s, ratios dimensionless.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Outcome {
    /// |θ| reached π/2 (the paper's definition of overturning).
    pub overturned: bool,
    /// Time of overturning, if it happened.
    pub overturn_time: Option<f64>,
    /// The normal force reached 0 while rocking at least once (whether the
    /// block then flew or, under infinite friction, the pivot was held). The
    /// paper's program stopped there and counted the run as overturned.
    pub uplifted: bool,
    /// The block moved at all (rest was broken).
    pub moved: bool,
    /// Peak |θ| over the run divided by θc.
    pub theta_max_over_theta_c: f64,
    /// Peak |F|/N while rocking on a stuck pivot: the friction needed to
    /// sustain the motion, the paper's μ_mot (the demand at impacts, eq. (5)
    /// and at a rock impact eq. (8), is `mu_impact`). Taken at the end of
    /// every rock step (about one per record sample) where N > 0, and at the
    /// two ends of a cascade the cascade rule settles. In a run that
    /// overturned, the final excursion beyond θc is left out: the steps after
    /// the last one that ended with |θ| ≤ θc, the fall during which N → 0 and
    /// |F|/N grows without bound (to 4e13–5e15 in the studies' overturned
    /// runs before this rule). So it is the friction the run needed while the
    /// block could still come back, finite in every run (largest 1.15 over the
    /// 100,000 analyses of `studies/fragility-100k.toml`). A run that did not
    /// overturn keeps every step, its excursions beyond θc included: its value
    /// is the peak over the whole motion, as before.
    pub mu_motion: f64,
    /// Peak |P_t/P_n| over all impacts (friction needed to prevent sliding at impact).
    pub mu_impact: f64,
    /// Peak over all impacts (rock impacts and landings) of the paper's
    /// eq. (5), the friction needed to prevent sliding during an impact as the
    /// paper's program evaluated it: |P_t/P_n| of the Newton sticking impulse,
    /// with the absolute value taken even when P_n ≤ 0 (see
    /// [`eq5_mu`](crate::solver::eq5_mu) for the reconstruction). Equal to the paper's
    /// eq. (8) at a rock impact; unbounded near landings whose sticking normal
    /// impulse vanishes. The largest over the run, as the paper's tables
    /// report it; 0 when there are no impacts, like `mu_impact`.
    pub mu_impact_eq5: f64,
    /// Number of corner impacts (rock impacts and landings, each corner counted).
    pub impacts: u64,
    /// Number of free-flight phases.
    pub flights: u64,
    /// Number of rock → flight lift-offs (N reached 0 with a consistent release).
    pub uplifts: u64,
    /// Number of times N reached 0 but releasing the pivot was inconsistent
    /// (the pivot was kept until N > 0 again or the release became consistent).
    pub liftoff_holds: u64,
    /// Number of times under finite friction that neither sticking nor
    /// slipping was consistent (Painlevé) and the pivot was held.
    pub stick_holds: u64,
    /// Number of impacts that increased kinetic energy (possible under Newton's law).
    pub energy_gains: u64,
    /// Number of ring-down settles (an impact rebound below the settle threshold
    /// treated as plastic, or a flat block with negligible velocity set to rest).
    pub settles: u64,
    /// Time at which the analysis ended: overturning, or rest after the
    /// record's end (the free motion after it, `solver.free_motion_max`),
    /// or the record's end for a body at rest then.
    pub end_time: f64,
    /// Time of the first impact, if any.
    pub first_impact_time: Option<f64>,
    /// Time spent in each mode, in the order of [`Mode::ALL`] (s; they sum
    /// to `end_time`). A cascade of rock impacts that the cascade rule
    /// settles counts as rock for as long as it would have lasted (its
    /// duration in closed form on the ground of its start, within 1e-4 s of
    /// every impact followed on still ground at e = 0) and as rest from then on; the
    /// history shows the block at rest from the settle. A series of bounces
    /// closed by the chatter rule counts as rock from the closing impact.
    pub time_in_mode: [f64; 5],
    /// Peak |slip| of the block relative to the ground (m): the largest offset
    /// of its footprint (or of its slipping pivot) from where it started.
    pub slip_max: f64,
    /// Slip at the end of the analysis (m), signed (positive to the right).
    pub slip_final: f64,
    /// Counts of mode transitions: `transitions[from][to]`, indices as in [`Mode::ALL`].
    pub transitions: [[u64; 5]; 5],
    /// Largest |energy residual| between events, relative to the run's energy
    /// scale, when the energy audit is on.
    pub energy_residual: Option<f64>,
    /// Work counters.
    pub stats: Stats,
    /// Each body's response when the analysis was of a stack (`None` for
    /// one block). The fields above then hold the stack's: overturned,
    /// uplifted, moved if any body did, the first overturning time, the
    /// largest θmax/θc, slip and μ_imp of the bodies, the stack's impacts
    /// and events; the ones the stack solver does not compute (`mu_motion`,
    /// `mu_impact_eq5`, `flights`, `uplifts`, `stick_holds`, `slip_final`,
    /// the time in each mode and the integrator's counters) are left empty
    /// in `outcomes.csv` (`outcomes_csv::STACK_EMPTY`).
    #[serde(skip)]
    pub stack: Option<StackSummary>,
}

/// A body of a stack by its place, bottom first: the names of its columns
/// in `outcomes.csv` (`base.overturned`, `top.theta_max_over_theta_c`) and
/// of its limit states. A stack of two has a base and a top; of three, a
/// middle between them. One block on the ground is its own base and top.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Slot {
    /// The lowest body, on the ground.
    Base,
    /// The body between base and top (stacks of three).
    Middle,
    /// The highest body.
    Top,
}

impl Slot {
    /// Every slot, bottom first.
    pub const ALL: [Slot; 3] = [Slot::Base, Slot::Middle, Slot::Top];

    /// The slot's name: `base`, `middle` or `top`.
    pub fn name(self) -> &'static str {
        match self {
            Slot::Base => "base",
            Slot::Middle => "middle",
            Slot::Top => "top",
        }
    }

    /// The slot named `name`.
    pub fn from_name(name: &str) -> Option<Slot> {
        Slot::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The slot of body `i` (bottom first, from 0) of a stack of `n`
    /// bodies (2 or 3).
    pub fn of(i: usize, n: usize) -> Slot {
        match (i, n) {
            (0, _) => Slot::Base,
            (i, n) if i + 1 == n => Slot::Top,
            _ => Slot::Middle,
        }
    }

    /// Index into [`StackSummary::bodies`].
    pub fn index(self) -> usize {
        self as usize
    }
}

/// One body's response in a study's row (a stack's
/// [`crate::solver::stack::BodyOutcome`], the columns `outcomes.csv` keeps).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodySummary {
    /// Peak |φ|/θc of the body on the face below, over its own θc.
    pub theta_max_over_theta_c: f64,
    /// The body overturned (or the body under it did).
    pub overturned: bool,
    /// When it overturned (s).
    pub overturn_time: Option<f64>,
    /// Peak |slip| on the face below (m).
    pub slip_max: f64,
    /// The interface under it opened at least once.
    pub uplifted: bool,
    /// It moved relative to the face below.
    pub moved: bool,
}

/// The bodies of a stack's analysis, by [`Slot`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StackSummary {
    /// Which body overturned first.
    pub first_overturned: Option<Slot>,
    /// Each slot's body (`None`: the stack has no middle).
    pub bodies: [Option<BodySummary>; 3],
}

impl Outcome {
    /// The response of the body at `slot`: a stack's body, or for one block
    /// the block itself as its base and top (`None` for a middle it has
    /// not).
    pub fn body(&self, slot: Slot) -> Option<BodySummary> {
        match &self.stack {
            Some(s) => s.bodies[slot.index()],
            None if slot == Slot::Middle => None,
            None => Some(BodySummary {
                theta_max_over_theta_c: self.theta_max_over_theta_c,
                overturned: self.overturned,
                overturn_time: self.overturn_time,
                slip_max: self.slip_max,
                uplifted: self.uplifted,
                moved: self.moved,
            }),
        }
    }

    /// The outcome as one JSON object (what `rockfrag simulate --json`
    /// prints, and the Python `simulate` returns): the fields by name, with
    /// `time_in_mode` keyed by mode name ([`Mode::name`]).
    pub fn to_json(&self) -> serde_json::Value {
        let mut v = serde_json::to_value(self).expect("outcome serialises");
        let modes: serde_json::Map<String, serde_json::Value> = Mode::ALL
            .iter()
            .map(|m| {
                (
                    m.name().to_string(),
                    serde_json::json!(self.time_in_mode[m.index()]),
                )
            })
            .collect();
        v["time_in_mode"] = serde_json::Value::Object(modes);
        v
    }
}
