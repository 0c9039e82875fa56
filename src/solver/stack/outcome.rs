//! What one analysis of a stack gives: per body (bottom first) its peak
//! rotation, overturning and slip; for the stack which body overturned
//! first, the impacts and, if the analysis could not be trusted to its
//! end, why.

use crate::error::Result;
use crate::outcome::{BodySummary, Mode, Outcome, Slot, StackSummary};
use serde::Serialize;
use std::path::Path;

/// The response of one body of a stack.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct BodyOutcome {
    /// Peak |φ|/θc: the body's rotation relative to the face it stands on
    /// (the ground for the base), over its own critical angle θc = atan(B/H).
    pub theta_max_over_theta_c: f64,
    /// Peak |θ| of the body's absolute rotation (rad).
    pub theta_abs_max: f64,
    /// The body overturned: |φ| reached π/2, or the body under it overturned
    /// (it falls with it).
    pub overturned: bool,
    /// When it overturned (s).
    pub overturn_time: Option<f64>,
    /// Peak |slip| (m) of the body's footprint along the face below (at the
    /// pivot while rocking), from its place at the start.
    pub slip_max: f64,
    /// Peak friction demand |P_t|/ΣP_n of the sticking impulse at impacts on
    /// the interface under the body (the single block's `mu_impact`).
    pub mu_impact: f64,
    /// The interface under the body opened at least once (a corner lifted).
    pub uplifted: bool,
    /// The body moved relative to the face below.
    pub moved: bool,
    /// Time (s) the interface under the body spent in each state, in the
    /// order of [`Mode::ALL`] (rest, slide, rock, slide-rock, flight).
    pub time_in_mode: [f64; 5],
}

/// The outcome of one analysis of a stack.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct StackOutcome {
    /// Each body's response, bottom first.
    pub bodies: Vec<BodyOutcome>,
    /// Which body overturned first (0-based, bottom first).
    pub first_overturned: Option<usize>,
    /// Why the analysis stopped before its end (every body at rest or the
    /// base overturned, the free motion after the record included), if it
    /// could not continue in the modes this solver models or was still
    /// moving `solver.free_motion_max` after the record: its numbers then
    /// cover only up to `end_time` and must not be read as the run's response.
    pub failure: Option<String>,
    /// Time at which the analysis ended (s).
    pub end_time: f64,
    /// Number of corner impacts (each corner struck counted).
    pub impacts: u64,
    /// Time of the first impact, if any.
    pub first_impact_time: Option<f64>,
    /// Impacts whose sticking impulse left a friction cone, resolved by
    /// Stronge's law on the one slipping contact or by the plastic impulse
    /// with Coulomb friction scaled by 1 + e.
    pub slipping_impacts: u64,
    /// Impacts that increased the kinetic energy (possible under Newton's law).
    pub energy_gains: u64,
    /// Rebounds below the settle threshold made plastic.
    pub settles: u64,
    /// Lift-offs under infinite friction held because releasing the corner
    /// was inconsistent (the body's corner kept until N > 0 again).
    pub liftoff_holds: u64,
    /// Events handled (mode changes, impacts).
    pub events: u64,
}

impl StackOutcome {
    /// The outcome as a study's row holds it ([`Outcome::stack`]): each
    /// body by its [`Slot`], and the stack as a whole in the single block's
    /// fields (overturned, uplifted, moved if any body did; the first
    /// overturning; the largest θmax/θc, slip and μ_imp of the bodies; the
    /// impacts, settles, holds, energy gains and events). The fields the
    /// stack solver does not compute stay at their defaults (and are left
    /// empty in `outcomes.csv`).
    pub fn summary(&self) -> Outcome {
        let n = self.bodies.len();
        let mut stack = StackSummary {
            first_overturned: self.first_overturned.map(|i| Slot::of(i, n)),
            bodies: [None; 3],
        };
        let mut o = Outcome {
            end_time: self.end_time,
            impacts: self.impacts,
            first_impact_time: self.first_impact_time,
            energy_gains: self.energy_gains,
            settles: self.settles,
            liftoff_holds: self.liftoff_holds,
            ..Outcome::default()
        };
        o.stats.events = self.events;
        for (i, b) in self.bodies.iter().enumerate() {
            stack.bodies[Slot::of(i, n).index()] = Some(BodySummary {
                theta_max_over_theta_c: b.theta_max_over_theta_c,
                overturned: b.overturned,
                overturn_time: b.overturn_time,
                slip_max: b.slip_max,
                uplifted: b.uplifted,
                moved: b.moved,
            });
            o.overturned |= b.overturned;
            o.uplifted |= b.uplifted;
            o.moved |= b.moved;
            o.theta_max_over_theta_c = o.theta_max_over_theta_c.max(b.theta_max_over_theta_c);
            o.slip_max = o.slip_max.max(b.slip_max);
            o.mu_impact = o.mu_impact.max(b.mu_impact);
            o.overturn_time = match (o.overturn_time, b.overturn_time) {
                (Some(a), Some(t)) => Some(a.min(t)),
                (a, t) => a.or(t),
            };
        }
        o.stack = Some(stack);
        o
    }

    /// The outcome as JSON: `{"bodies": [ … ], …}`, bottom first, each body
    /// with the keys of a single block's outcome where they mean the same
    /// (`theta_max_over_theta_c`, `overturned`, `slip_max`, …) and its time
    /// in each mode by name.
    pub fn to_json(&self) -> serde_json::Value {
        let mut v = serde_json::to_value(self).expect("outcome serialises");
        for (b, j) in self
            .bodies
            .iter()
            .zip(v["bodies"].as_array_mut().expect("bodies"))
        {
            let modes: serde_json::Map<String, serde_json::Value> = Mode::ALL
                .iter()
                .map(|m| {
                    (
                        m.name().to_string(),
                        serde_json::json!(b.time_in_mode[m.index()]),
                    )
                })
                .collect();
            j["time_in_mode"] = serde_json::Value::Object(modes);
        }
        v
    }
}

/// One instant of a stack's history: every body's state.
#[derive(Clone, Debug, PartialEq)]
pub struct StackRow {
    /// Time (s).
    pub t: f64,
    /// The row marks an event rather than a step's end.
    pub event: bool,
    /// The state of the interface under each body, bottom first.
    pub mode: Vec<Mode>,
    /// Absolute rotation θ of each body (rad).
    pub theta: Vec<f64>,
    /// Rotation φ relative to the face below (rad).
    pub phi: Vec<f64>,
    /// φ̇ (rad/s).
    pub phi_dot: Vec<f64>,
    /// Centre of mass, horizontal (m, relative to the moving ground).
    pub x: Vec<f64>,
    /// Centre of mass, vertical (m).
    pub y: Vec<f64>,
    /// Slip along the face below (m) from the body's place at the start:
    /// its footprint's centre while flat, its pivot corner while rocking
    /// (the quantity of [`BodyOutcome::slip_max`]); NaN in flight (no
    /// contact) and once the body has overturned.
    pub slip: Vec<f64>,
    /// Mechanical energy of the stack relative to the ground's frame:
    /// kinetic plus gravity's potential (J per unit of the stack's relative
    /// mass); conserved between impacts when the ground is still.
    pub energy: f64,
}

/// A stack's time history.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StackHistory {
    /// The rows, in time order.
    pub rows: Vec<StackRow>,
}

impl StackHistory {
    /// Writes CSV `t,event,mode_1,theta_1,phi_1,phi_dot_1,x_1,y_1,slip_1,…,energy`
    /// (bodies numbered from 1, bottom first) to a temporary file beside
    /// `path`, then renames it into place.
    pub fn write_csv(&self, path: &Path) -> Result<()> {
        let n = self.rows.first().map_or(0, |r| r.theta.len());
        crate::io_util::write_atomic(path, |w| {
            write!(w, "t,event")?;
            for i in 1..=n {
                write!(
                    w,
                    ",mode_{i},theta_{i},phi_{i},phi_dot_{i},x_{i},y_{i},slip_{i}"
                )?;
            }
            writeln!(w, ",energy")?;
            for r in &self.rows {
                write!(w, "{},{}", r.t, u8::from(r.event))?;
                for i in 0..n {
                    write!(
                        w,
                        ",{},{},{},{},{},{},{}",
                        r.mode[i].name(),
                        r.theta[i],
                        r.phi[i],
                        r.phi_dot[i],
                        r.x[i],
                        r.y[i],
                        r.slip[i]
                    )?;
                }
                writeln!(w, ",{}", r.energy)?;
            }
            Ok(())
        })
        .map_err(crate::error::Error::io(path))
    }
}
