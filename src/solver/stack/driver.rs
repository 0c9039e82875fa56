//! The event loop of the stack solver.
//!
//! The record's acceleration is linear between samples; the loop stops at
//! every sample. Inside a sample interval the state's coordinates (q, q̇)
//! are integrated by Dormand–Prince 5(4) with error control (the crate's
//! `dopri`, the same stepper as the single block's), and the events of the
//! state are located on its dense output: every accepted step is scanned at
//! four interior points and a sign change of an event function is refined by
//! Brent's method. A stack at rest (no free coordinate) is not integrated:
//! its contact forces are affine in the ground's acceleration: they are
//! taken once per state at rest as such, and a sample over which every
//! event function stays clear of 0 is passed on them; the others are
//! scanned in the same way over the interval.
//!
//! The cascade rule (`settle_cascades`): in the choice of the state after
//! an impact, a corner on its face moving along the normal slower than
//! `CASCADE_REST` √(gR) rests on it (docs/stack.md, "Rules").
//!
//! Event functions, per interface (each positive while its state holds):
//! - flat: the normal force at each corner (N_L, N_R), μs N − |T| if stuck,
//!   σẊ if slipping;
//! - rock about corner c: −cφ (the other corner strikes at φ = 0), N (−N
//!   while the lift-off rule holds the pivot), μs N − |T| if stuck, σṗ if
//!   slipping, π/2 − |φ| (overturning);
//! - open: the gap of each corner, π/2 − |φ|.
//!
//! An event either strikes a corner (an impact over every touching corner,
//! `impact`), or ends a condition of the state; the next state is then
//! chosen by `select`. A body whose |φ| reaches π/2 has overturned: it and
//! the bodies above it leave the scene (their fall onto the ground or the
//! body below is not followed) and the solver goes on with the bodies
//! below; the base's overturning ends the analysis. A state that `select`
//! cannot continue, an impact it cannot resolve, or a step size that
//! underflows ends the analysis with its reason in
//! [`StackOutcome::failure`]: never a silent answer.

use super::dynamics::{accelerations, forces};
use super::impact::{Resolution, kinetic, resolve, touching, velocities};
use super::kinematics::{Body, Chain, MAX_DOF, Modes, Slip, Touch, corner_rel, initial_modes};
use super::outcome::{BodyOutcome, StackHistory, StackOutcome, StackRow};
use super::rest::RestForces;
use super::scene::MAX_BODIES;
use super::scene::{Scene, Stack};
use super::select::{Exclude, NoState, select, tolerances};
use crate::error::{Error, Result};
use crate::motion::Record;
use crate::solver::dopri::{Stepper, Tolerance, attempt};
use crate::solver::driver::Segment;
use crate::solver::roots::brent;
use crate::solver::settings::{Model, RockImpact, SolverSettings};
use std::f64::consts::FRAC_PI_2;

/// Length of the integrated state: q then q̇, padded.
const NY: usize = 2 * MAX_DOF;
/// Offset of q̇ in the state.
const QD: usize = MAX_DOF;
/// Event slots per interface.
const SLOTS: usize = 4;
/// Event slots.
const NE: usize = SLOTS * MAX_BODIES;
/// How far past the edge of the face below, relative to that face's
/// half-width, a corner of the body above may be and still count as on it.
/// A stack of equal widths has its upper corners on the edges below, and
/// under Coulomb friction slips of 1e-9 to 5e-8 m (rounding in the slip's
/// integration) took them past an edge at 1e-9 and ended the analysis; at
/// 1e-6 the contact's lever arm is off by at most that fraction, and a
/// genuine slip off the support (millimetres) is still refused.
const EDGE_TOLERANCE: f64 = 1e-6;
/// Interior points at which a step is scanned for events.
const SUB: usize = 4;
/// The cascade rule's rest threshold ε_r (`settle_cascades`): after an
/// impact, a corner on its face whose normal speed is below ε_r√(gR) rests
/// on it (docs/stack.md, "Rules": what it changes and by how much).
pub(super) const CASCADE_REST: f64 = 1e-4;

/// What an event slot detects.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Ev {
    /// Unused slot.
    None,
    /// A corner of the body on interface k strikes its face.
    Strike(usize),
    /// The pivot's normal force at interface k reached 0.
    Unload(usize),
    /// A flat contact's corner at interface k unloaded.
    UnloadFlat(usize),
    /// The friction cone was reached at interface k.
    Cone(usize),
    /// The slip in direction σ at interface k stopped.
    SlipStop(usize, f64),
    /// The body on interface k overturned (|φ| = π/2).
    Overturn(usize),
    /// The held pivot at interface k is compressed again.
    HoldEnd(usize),
}

/// Solves one analysis of a stack under a record: every body's response,
/// bottom first. Pushes the full history into `history` when one is given.
/// The settings' tolerances, impact law, settle threshold and event limit
/// apply; the stack is always integrated by Dormand–Prince 5(4) on the
/// nonlinear equations (`model = "linear"` and `rock_impact = "rock"` are
/// refused). An analysis that leaves the modes the solver models returns
/// `Ok` with [`StackOutcome::failure`] set.
///
/// ```
/// use rockfrag::motion::Record;
/// use rockfrag::solver::SolverSettings;
/// use rockfrag::solver::stack::{Stack, StackBody, simulate_stack};
/// // a statue 0.3 × 1.2 m on a pedestal 0.8 × 1.0 m
/// let stack = Stack::new(vec![StackBody::new(0.8, 1.0), StackBody::new(0.3, 1.2)], 0.0, 9.81);
/// // 1 s of constant acceleration at 0.3 g: above the statue's B/H = 0.25
/// let record = Record::from_acc("pulse", 0.01, vec![0.3 * 9.81; 101]).unwrap();
/// let out = simulate_stack(&stack, &record, &SolverSettings::default(), None).unwrap();
/// assert!(out.failure.is_none());
/// assert!(out.bodies[1].theta_max_over_theta_c > 0.0);
/// ```
pub fn simulate_stack(
    stack: &Stack,
    record: &Record,
    settings: &SolverSettings,
    history: Option<&mut StackHistory>,
) -> Result<StackOutcome> {
    stack.validate()?;
    settings.validate()?;
    record.validate_forcing()?;
    if settings.model == Model::Linear {
        return Err(Error::invalid(
            "model",
            "linear",
            "nonlinear for a stack (the stack solver integrates the full equations)",
        ));
    }
    if settings.rock_impact == RockImpact::Rock {
        return Err(Error::invalid(
            "rock_impact",
            "rock",
            "bounce for a stack (the impact law in full)",
        ));
    }
    let mut sc = Scene::new(stack);
    sc.settle = settings.settle_tol;
    let mut run = Run::new(sc, record, settings, history);
    run.solve();
    Ok(run.finish())
}

/// One analysis in progress.
struct Run<'a> {
    sc: Scene,
    rec: &'a Record,
    set: &'a SolverSettings,
    hist: Option<&'a mut StackHistory>,
    modes: Modes,
    y: [f64; NY],
    t: f64,
    /// Step size carried between intervals.
    h: f64,
    bodies: [BodyOutcome; MAX_BODIES],
    out: StackOutcome,
    /// Rest place of each body's footprint centre along its face.
    x0: [f64; MAX_BODIES],
    /// The contact forces of the last state at rest, affine in the ground's
    /// acceleration ([`Run::rest_interval`]).
    rest: Option<RestForces>,
}

impl<'a> Run<'a> {
    fn new(
        sc: Scene,
        rec: &'a Record,
        set: &'a SolverSettings,
        hist: Option<&'a mut StackHistory>,
    ) -> Self {
        let mut x0 = [0.0; MAX_BODIES];
        x0[..sc.n].copy_from_slice(&sc.offset[..sc.n]);
        Run {
            sc,
            rec,
            set,
            hist,
            modes: initial_modes(&sc),
            y: [0.0; NY],
            t: 0.0,
            h: 0.25 * rec.dt,
            bodies: Default::default(),
            out: StackOutcome::default(),
            x0,
            rest: None,
        }
    }

    fn finish(mut self) -> StackOutcome {
        self.out.bodies = self.bodies[..self.sc.n].to_vec();
        self.out.end_time = self.t;
        self.out
    }

    fn segment(&self, i: usize) -> Segment {
        Segment::of(&self.rec.acc, self.rec.acc_v.as_deref(), self.rec.dt, i)
    }

    fn fail(&mut self, message: String) {
        if self.out.failure.is_none() {
            self.out.failure = Some(format!("at t = {:.6} s: {message}", self.t));
        }
    }

    /// The chain of the current state at `y`.
    fn chain(&self, y: &[f64; NY]) -> Chain {
        let dof = self.modes.dof();
        Chain::new(&self.sc, &self.modes, &y[..dof], &y[QD..QD + dof])
    }

    /// Sets the state from a choice.
    fn set_state(&mut self, modes: Modes, q: &[f64; MAX_DOF], qd: &[f64; MAX_DOF]) {
        self.modes = modes;
        self.y = [0.0; NY];
        let dof = modes.dof();
        self.y[..dof].copy_from_slice(&q[..dof]);
        self.y[QD..QD + dof].copy_from_slice(&qd[..dof]);
        for k in 0..modes.n {
            let m = modes.ifs[k];
            if !(m.touch == Touch::Flat && m.slip == Slip::Stick) {
                self.bodies[k].moved = true;
            }
            if matches!(m.touch, Touch::Corner(_) | Touch::Open) {
                self.bodies[k].uplifted = true;
            }
        }
    }

    fn solve(&mut self) {
        let n_samples = self.rec.acc.len();
        if n_samples < 2 {
            return;
        }
        // the initial state: tilted bodies on their corners, the rest flat
        let mut q = [0.0; MAX_DOF];
        for k in 0..self.sc.n {
            if self.modes.ifs[k].touch != Touch::Flat {
                q[self.modes.start(k)] = self.sc.tilt[k];
            }
        }
        let ch = Chain::new(&self.sc, &self.modes, &q, &[0.0; MAX_DOF]);
        let seg = self.segment(0);
        let (ax, ay) = seg.at(0.0);
        match select(&self.sc, &ch.body, self.sc.n, ax, ay, Exclude::None) {
            Ok(c) => self.set_state(c.modes, &c.q, &c.qd),
            Err(e) => {
                self.fail(format!("the initial state is not consistent: {e:?}"));
                return;
            }
        }
        self.push_row(true);
        let mut repeats = 0;
        // the record's samples, then still ground up to the free-motion cap
        let n_all = n_samples + self.set.free_samples(self.rec.dt);
        for i in 0..n_all - 1 {
            if i + 1 >= n_samples && self.settled() {
                // past the record the ground is still: rest is final, and
                // so is a rigid slide on frictionless ground
                return;
            }
            let seg = self.segment(i);
            let t_end = (i + 1) as f64 * self.rec.dt;
            while self.t < t_end {
                if self.out.failure.is_some() || self.bodies[0].overturned {
                    return;
                }
                let found = if self.modes.dof() == 0 {
                    self.rest_interval(&seg, t_end)
                } else {
                    self.integrate(&seg, t_end)
                };
                let Some((te, ev)) = found else {
                    break;
                };
                // events repeating at one instant make no progress: after 8,
                // the striking body's release is taken as inconsistent (its
                // corner is kept, by the lift-off rule); after 64 the
                // analysis fails
                if te == self.t && self.out.events > 0 {
                    repeats += 1;
                } else {
                    repeats = 0;
                }
                self.t = te;
                self.out.events += 1;
                if repeats > 64 {
                    self.fail(format!(
                        "events accumulate at one instant (the last: {ev:?}); the contact \
                         states cannot continue consistently"
                    ));
                    return;
                }
                if repeats > 8
                    && let Ev::Strike(k) = ev
                    && self.modes.ifs[k].touch == Touch::Open
                {
                    self.transition(&seg, Exclude::Open(k));
                    self.note(&self.y.clone());
                    self.push_row(true);
                    continue;
                }
                if self.out.events > self.set.max_events {
                    let states: Vec<String> = (0..self.modes.n)
                        .map(|k| format!("{:?}", self.modes.ifs[k]))
                        .collect();
                    self.fail(format!(
                        "more than {} events (max_events); the last: {ev:?} in state [{}]",
                        self.set.max_events,
                        states.join(", ")
                    ));
                    return;
                }
                self.handle(ev, &seg);
                self.note(&self.y.clone());
                self.push_row(true);
            }
            if self.out.failure.is_some() || self.bodies[0].overturned {
                return;
            }
            self.t = t_end;
            self.push_row(false);
        }
        if n_all > n_samples && !self.settled() {
            self.fail(format!(
                "still moving {} s after the record's end (free_motion_max): no decided state",
                self.set.free_motion_max
            ));
        }
    }

    /// Past the record (still ground), whether the state is final: every
    /// interface flat and stuck (rest), or the ground interface sliding flat
    /// with μk = 0 and every other stuck: the stack then translates rigidly
    /// at constant speed, with no horizontal force on any body and the
    /// bodies' weights where they were, so nothing can stop, tip or shift
    /// it (the single block's rule; the slip grows without bound and is
    /// reported at the record's end). A slide at an upper interface is not
    /// final: it moves the weight of the bodies above along the one below.
    fn settled(&self) -> bool {
        (0..self.modes.n).all(|k| {
            let m = self.modes.ifs[k];
            let frictionless = k == 0 && matches!(self.sc.fric[0], Some((_, mu_k)) if mu_k == 0.0);
            m.touch == Touch::Flat && (m.slip == Slip::Stick || frictionless)
        })
    }

    /// A stack at rest over [t, t_end]: the first event, if any (then the
    /// time is left at it), else the time moves to t_end.
    fn rest_interval(&mut self, seg: &Segment, t_end: f64) -> Option<(f64, Ev)> {
        let y = self.y;
        let t0 = self.t;
        // the forces at rest are affine in (ẍg, ÿg): every event function
        // clearly positive at both ends from them is positive over the
        // sample, as the exact scan below would find (bit for bit the same
        // answer, at a fraction of its cost: no chain, no forces)
        let rf = match self.rest {
            Some(r) if r.modes == self.modes => r,
            _ => {
                let r = RestForces::new(&self.sc, &self.modes, &self.chain(&self.y));
                self.rest = Some(r);
                r
            }
        };
        let ((ax0, ay0), (ax1, ay1)) = (seg.at(t0), seg.at(t_end));
        if rf.clear(&self.sc, ax0, ay0) && rf.clear(&self.sc, ax1, ay1) {
            self.time_in_modes(t_end - t0);
            self.t = t_end;
            return None;
        }
        // at rest every event function is affine in (ẍg, ÿg), so linear in
        // t over the sample (the cone's μs N − |T| concave): positive at
        // both ends, positive between them; the ends suffice
        let found = self.scan(seg, t0, t_end, 1, |_| y, |i, _| y[i]);
        let t1 = found.map_or(t_end, |f| f.0);
        self.time_in_modes(t1 - t0);
        if found.is_none() {
            self.t = t_end;
        }
        found
    }

    /// Integrates the current state over [t, t_end]; stops at the first event.
    fn integrate(&mut self, seg: &Segment, t_end: f64) -> Option<(f64, Ev)> {
        let sc = self.sc;
        let modes = self.modes;
        let seg_c = *seg;
        let dof = modes.dof();
        let mut failed = false;
        let mut f = move |t: f64, y: &[f64; NY]| -> [f64; NY] {
            let ch = Chain::new(&sc, &modes, &y[..dof], &y[QD..QD + dof]);
            let (ax, ay) = seg_c.at(t);
            let mut qdd = [0.0; MAX_DOF];
            let mut out = [0.0; NY];
            if !accelerations(&sc, &modes, &ch, ax, ay, &mut qdd) {
                return [f64::NAN; NY];
            }
            out[..dof].copy_from_slice(&y[QD..QD + dof]);
            out[QD..QD + dof].copy_from_slice(&qdd[..dof]);
            out
        };
        let tol = self.tolerance();
        let mut st = Stepper::new(&mut f, self.t, self.y, t_end, self.h, tol, self.rec.dt);
        loop {
            match st.step(&mut f) {
                Ok(Some(step)) => {
                    let (t0, t1) = (step.t0, step.t0 + step.h);
                    let found = self.scan(
                        seg,
                        t0,
                        t1,
                        SUB,
                        |t| step.at(t),
                        |i, t| step.component_at(i, t),
                    );
                    self.peaks_in_step(
                        &|t| step.at(t),
                        &|i, t| step.component_at(i, t),
                        t0,
                        found.map_or(t1, |f| f.0),
                    );
                    if let Some((te, ev)) = found {
                        self.time_in_modes(te - t0);
                        // the state at the event by a step of its own from
                        // t0 (fifth order, where the dense output is fourth)
                        self.y = if te > t0 {
                            let f0 = f(t0, &st.y);
                            attempt(&mut f, t0, &st.y, &f0, te - t0, &tol).y1
                        } else {
                            st.y
                        };
                        self.h = st.h;
                        return Some((te, ev));
                    }
                    st.accept(&step);
                    self.time_in_modes(t1 - t0);
                    self.t = t1;
                    self.y = step.y1;
                    if self.out.failure.is_some() {
                        return None;
                    }
                    if self.hist.is_some() {
                        self.push_row(false);
                    }
                }
                Ok(None) => break,
                Err(t) => {
                    self.t = t;
                    failed = true;
                    break;
                }
            }
        }
        self.h = st.h;
        if failed {
            self.fail(
                "the step size underflowed (a state the equations cannot continue)".to_string(),
            );
            return None;
        }
        self.t = t_end;
        self.y = st.y;
        None
    }

    /// Error tolerances of the current state's coordinates: angles against
    /// atol·θc, lengths against atol·θc·R, rates against those times p,
    /// scaled so that the stepper's RMS over its padded state is the RMS
    /// over the coordinates in use.
    fn tolerance(&self) -> Tolerance<NY> {
        let dof = self.modes.dof();
        let f = (2.0 * dof as f64 / NY as f64).sqrt();
        let mut atol = [1.0; NY];
        let mut j = 0;
        for k in 0..self.modes.n {
            let m = self.modes.ifs[k];
            let ang = self.set.atol * self.sc.theta_c[k];
            let len = ang * self.sc.r[k];
            let kinds: &[f64] = match (m.touch, m.slip) {
                (Touch::Flat, Slip::Stick) => &[],
                (Touch::Flat, Slip::Slip(_)) => &[len],
                (Touch::Corner(_), Slip::Stick) => &[ang],
                (Touch::Corner(_), Slip::Slip(_)) => &[ang, len],
                (Touch::Open, _) => &[len, len, ang],
            };
            for &a in kinds {
                atol[j] = a * f;
                atol[QD + j] = a * self.sc.p[k] * f;
                j += 1;
            }
        }
        Tolerance {
            rtol: self.set.rtol * f,
            atol,
        }
    }

    /// The event functions of the current state at (t, y) and their kinds.
    fn values(&self, seg: &Segment, t: f64, y: &[f64; NY]) -> [(f64, Ev); NE] {
        let sc = &self.sc;
        let n = self.modes.n;
        let ch = self.chain(y);
        let (ax, ay) = seg.at(t);
        let f = forces(sc, &self.modes, &ch, ax, ay);
        let mut v = [(1.0, Ev::None); NE];
        for k in 0..n {
            let m = self.modes.ifs[k];
            let w = sc.g * sc.carried(k, n);
            let con = f.contact[k];
            let cone = match sc.fric[k] {
                Some((mu_s, _)) => (mu_s * con.n - con.t.abs()) / w,
                None => 1.0,
            };
            let rel = ch.rel[k];
            let (sp, cp) = ch.rtrig[k];
            let vs = (sc.g * sc.r[k]).sqrt();
            let s = &mut v[SLOTS * k..SLOTS * (k + 1)];
            let over = ((FRAC_PI_2 - rel.phi.abs()) / sc.theta_c[k], Ev::Overturn(k));
            match (m.touch, m.slip) {
                (Touch::Flat, slip) => {
                    s[0] = (con.nl / w, Ev::UnloadFlat(k));
                    s[1] = (con.nr / w, Ev::UnloadFlat(k));
                    s[2] = match slip {
                        Slip::Stick => (cone, Ev::Cone(k)),
                        Slip::Slip(sg) => (sg * rel.xd / vs, Ev::SlipStop(k, sg)),
                    };
                }
                (Touch::Corner(c), slip) => {
                    s[0] = (-c * rel.phi / sc.theta_c[k], Ev::Strike(k));
                    s[1] = if m.hold {
                        (-con.n / w, Ev::HoldEnd(k))
                    } else {
                        (con.n / w, Ev::Unload(k))
                    };
                    s[2] = match slip {
                        Slip::Stick if m.hold => (1.0, Ev::None),
                        Slip::Stick => (cone, Ev::Cone(k)),
                        Slip::Slip(sg) => {
                            let d = corner_rel(&rel, sp, cp, sc.b[k], sc.h[k], c);
                            (sg * d[2] / vs, Ev::SlipStop(k, sg))
                        }
                    };
                    s[3] = over;
                }
                (Touch::Open, _) => {
                    // max(gap, normal velocity): the gap's sign while the
                    // corner is above its face; a corner left below it
                    // (within the contact tolerance, by a step's error)
                    // but rising strikes where it stops rising, not at once
                    for (i, side) in [-1.0, 1.0].into_iter().enumerate() {
                        let d = corner_rel(&rel, sp, cp, sc.b[k], sc.h[k], side);
                        s[i] = ((d[1] / sc.h[k]).max(d[3] / vs), Ev::Strike(k));
                    }
                    s[3] = over;
                }
            }
        }
        v
    }

    /// Event slot `i` when it is a function of one coordinate alone (a
    /// rocking body's other corner striking, −cφ/θc, or a body overturning,
    /// (π/2 − |φ|)/θc): that coordinate's index in the state and the
    /// function, which give [`Run::values`]'s value bit for bit from one
    /// component of the dense output instead of the whole chain and its
    /// forces (the event search's refinement, most of its cost).
    fn kinematic_slot(&self, i: usize) -> Option<(usize, impl Fn(f64) -> f64)> {
        let (k, s) = (i / SLOTS, i % SLOTS);
        let theta_c = self.sc.theta_c[k];
        let j0 = self.modes.start(k);
        let (j, strike) = match (self.modes.ifs[k].touch, s) {
            (Touch::Corner(c), 0) => (j0, Some(c)),
            (Touch::Corner(_), 3) => (j0, None),
            (Touch::Open, 3) => (j0 + 2, None),
            _ => return None,
        };
        Some((j, move |phi: f64| match strike {
            Some(c) => -c * phi / theta_c,
            None => (FRAC_PI_2 - phi.abs()) / theta_c,
        }))
    }

    /// The first event over [t0, t1], scanned at `sub` equal intervals,
    /// with the state at time t given by `at` (one component by `comp`).
    #[allow(clippy::too_many_arguments)]
    fn scan(
        &self,
        seg: &Segment,
        t0: f64,
        t1: f64,
        sub: usize,
        at: impl Fn(f64) -> [f64; NY],
        comp: impl Fn(usize, f64) -> f64,
    ) -> Option<(f64, Ev)> {
        let mut pv = self.values(seg, t0, &at(t0));
        let mut pt = t0;
        let xtol = 1e-13 * t1.max(1.0);
        for j in 1..=sub {
            let tj = if j == sub {
                t1
            } else {
                t0 + (t1 - t0) * j as f64 / sub as f64
            };
            let v = self.values(seg, tj, &at(tj));
            let mut best: Option<(f64, Ev)> = None;
            for i in 0..NE {
                let (a, kind) = pv[i];
                let b = v[i].0;
                if kind == Ev::None {
                    continue;
                }
                let kin = self.kinematic_slot(i);
                let g = |t: f64| match &kin {
                    Some((j, f)) => f(comp(*j, t)),
                    None => self.values(seg, t, &at(t))[i].0,
                };
                let te = if a > 0.0 && b <= 0.0 {
                    Some(brent(g, pt, tj, a, b, xtol))
                } else if j == 1 && a <= 0.0 && b <= 0.0 {
                    // at or below 0 at the start (where the previous event
                    // left it): an excursion above 0 first is a crossing
                    // after it; otherwise a value getting worse is an event
                    // at once, one recovering is not
                    let mut up = None;
                    for frac in [
                        1e-9, 1e-6, 1e-3, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875,
                    ] {
                        let tl = t0 + (tj - t0) * frac;
                        let gl = g(tl);
                        if gl > 0.0 {
                            up = Some((tl, gl));
                        } else if up.is_some() {
                            break;
                        }
                    }
                    match up {
                        Some((tl, gl)) => Some(brent(g, tl, tj, gl, b, xtol)),
                        None if b < a => Some(t0),
                        None => None,
                    }
                } else {
                    None
                };
                if let Some(te) = te
                    && best.is_none_or(|(tb, _)| te < tb)
                {
                    best = Some((te, kind));
                }
            }
            if best.is_some() {
                return best;
            }
            pv = v;
            pt = tj;
        }
        None
    }

    /// Peaks of |φ| within a step: at the scan points and where φ̇ changes
    /// sign (Brent on the dense output), up to `t_stop`.
    fn peaks_in_step(
        &mut self,
        at: &dyn Fn(f64) -> [f64; NY],
        comp: &dyn Fn(usize, f64) -> f64,
        t0: f64,
        t_stop: f64,
    ) {
        let modes = self.modes;
        let mut j0 = 0;
        // where a body's peak was raised inside the step, if it was
        let mut peak_at = [None; MAX_BODIES];
        for k in 0..modes.n {
            let m = modes.ifs[k];
            let idx = match m.touch {
                Touch::Corner(_) => Some(j0),
                Touch::Open => Some(j0 + 2),
                Touch::Flat => None,
            };
            j0 += m.dof();
            let Some(i) = idx else {
                continue;
            };
            let mut pt = t0;
            let mut pw = comp(QD + i, t0);
            for j in 1..=SUB {
                let tj = t0 + (t_stop - t0) * j as f64 / SUB as f64;
                let w = comp(QD + i, tj);
                let (phi, tp) = if pw * w < 0.0 {
                    let tr = brent(|t| comp(QD + i, t), pt, tj, pw, w, 1e-14 * tj.max(1.0));
                    let (at_r, at_j) = (comp(i, tr).abs(), comp(i, tj).abs());
                    if at_r >= at_j { (at_r, tr) } else { (at_j, tj) }
                } else {
                    (comp(i, tj).abs(), tj)
                };
                let b = &mut self.bodies[k];
                let ratio = phi / self.sc.theta_c[k];
                if ratio > b.theta_max_over_theta_c && tp < t_stop {
                    peak_at[k] = Some(tp);
                }
                b.theta_max_over_theta_c = b.theta_max_over_theta_c.max(ratio);
                pt = tj;
                pw = w;
            }
        }
        // with a history, a row at each peak inside the step, so that the
        // history's peak |φ| is the outcome's
        if self.hist.is_some() {
            let mut times: Vec<f64> = peak_at[..modes.n].iter().flatten().copied().collect();
            times.sort_by(f64::total_cmp);
            times.dedup();
            for t in times {
                self.push_row_at(t, &at(t), false);
            }
        }
        let y = at(t_stop);
        self.note(&y);
    }

    /// The slip of body k along the face below, from its place at the
    /// start: its footprint's centre while flat, its pivot while rocking;
    /// `None` in flight (no contact).
    fn slip(&self, ch: &Chain, k: usize) -> Option<f64> {
        let rel = ch.rel[k];
        match self.modes.ifs[k].touch {
            Touch::Flat => Some(rel.x - self.x0[k]),
            Touch::Corner(c) => {
                let (sp, cp) = ch.rtrig[k];
                Some(
                    corner_rel(&rel, sp, cp, self.sc.b[k], self.sc.h[k], c)[0]
                        - (self.x0[k] + c * self.sc.b[k]),
                )
            }
            Touch::Open => None,
        }
    }

    /// Peaks of |φ|, |θ| and slip at the state y.
    fn note(&mut self, y: &[f64; NY]) {
        let ch = self.chain(y);
        for k in 0..self.modes.n {
            let rel = ch.rel[k];
            let slip = self.slip(&ch, k).unwrap_or(0.0);
            let b = &mut self.bodies[k];
            b.theta_max_over_theta_c = b
                .theta_max_over_theta_c
                .max(rel.phi.abs() / self.sc.theta_c[k]);
            b.theta_abs_max = b.theta_abs_max.max(ch.body[k].th.abs());
            let m = self.modes.ifs[k];
            b.slip_max = b.slip_max.max(slip.abs());
            // a corner on the face below must stay on it: running off its
            // edge (a body slipping off its support) is not modelled
            if k > 0 && m.touch != Touch::Open {
                let (sp, cp) = ch.rtrig[k];
                let (bk, hk) = (self.sc.b[k], self.sc.h[k]);
                let edge = self.sc.b[k - 1] * (1.0 + EDGE_TOLERANCE);
                let off = [-1.0, 1.0].into_iter().any(|side| {
                    let touching = match m.touch {
                        Touch::Corner(c) => c == side,
                        _ => true,
                    };
                    touching && corner_rel(&rel, sp, cp, bk, hk, side)[0].abs() > edge
                });
                if off {
                    // a footprint as wide as the face below leaves no margin:
                    // any slip puts a corner past the edge
                    let margin = self.sc.b[k - 1] - (self.sc.offset[k].abs() + bk);
                    let why = if margin <= EDGE_TOLERANCE * self.sc.b[k - 1] {
                        " (its footprint reaches the edges of that face, so a slip or a \
                         landing after flight of any size takes a corner past them; a \
                         narrower upper body is modelled)"
                    } else {
                        ""
                    };
                    self.fail(format!(
                        "body {} reached the edge of the body below (slip {:.3e} m, margin \
                         {:.3e} m){why}: a body running off its support is not modelled",
                        k + 1,
                        slip.abs(),
                        margin.max(0.0)
                    ));
                }
            }
        }
    }

    fn time_in_modes(&mut self, dt: f64) {
        for k in 0..self.modes.n {
            let i = self.modes.ifs[k].mode().index();
            self.bodies[k].time_in_mode[i] += dt;
        }
    }

    /// Applies an event at the current time and state.
    fn handle(&mut self, ev: Ev, seg: &Segment) {
        match ev {
            Ev::None => {}
            Ev::Overturn(k) => {
                // the state at the overturning, before the fallen bodies
                // leave the scene (a history's rows then have them as NaN)
                if k > 0 {
                    self.push_row(true);
                }
                self.overturn(k);
                // the bodies below lose the forces of those that left: their
                // state is chosen again (a pedestal at rest under 1 g whose
                // statue fell must slide or rock at once; its flat state,
                // kept, failed at the next event's exclusion)
                if k > 0 {
                    self.transition(seg, Exclude::None);
                }
            }
            Ev::HoldEnd(k) => self.modes.ifs[k].hold = false,
            Ev::Strike(k) => {
                // a rock impact happens at φ = 0 exactly (both corners down)
                if let Touch::Corner(_) = self.modes.ifs[k].touch {
                    self.y[self.modes.start(k)] = 0.0;
                }
                self.impact(seg)
            }
            Ev::Unload(k) => self.transition(seg, Exclude::Corner(k)),
            Ev::UnloadFlat(k) => self.transition(seg, Exclude::Flat(k)),
            Ev::Cone(k) => self.transition(seg, Exclude::Stick(k)),
            Ev::SlipStop(k, s) => self.transition(seg, Exclude::Slip(k, s)),
        }
    }

    /// Body k overturned: it and the bodies above leave the scene.
    fn overturn(&mut self, k: usize) {
        let n = self.modes.n;
        for b in &mut self.bodies[k..n] {
            if !b.overturned {
                b.overturned = true;
                b.overturn_time = Some(self.t);
            }
        }
        if self.out.first_overturned.is_none() {
            self.out.first_overturned = Some(k);
        }
        if k == 0 {
            return;
        }
        let keep = self.modes.start(k);
        for j in keep..MAX_DOF {
            self.y[j] = 0.0;
            self.y[QD + j] = 0.0;
        }
        self.modes.n = k;
    }

    /// A state condition ended: choose the next state.
    fn transition(&mut self, seg: &Segment, exclude: Exclude) {
        let ch = self.chain(&self.y);
        let (ax, ay) = seg.at(self.t);
        match select(&self.sc, &ch.body, self.modes.n, ax, ay, exclude) {
            Ok(c) => {
                if c.held.is_some() {
                    self.out.liftoff_holds += 1;
                }
                self.set_state(c.modes, &c.q, &c.qd);
            }
            Err(NoState::Approaching(_)) => self.impact(seg),
            Err(NoState::Inconsistent(m)) => self.fail(m),
        }
    }

    /// An impact over every touching corner, repeated while a corner still
    /// approaches its face after it (at most 16 times).
    fn impact(&mut self, seg: &Segment) {
        let sc = self.sc;
        let n = self.modes.n;
        let mut bodies = self.chain(&self.y).body;
        let (ax, ay) = seg.at(self.t);
        let mut touch = [0.0; MAX_BODIES];
        let mut v_settle = [0.0; MAX_BODIES];
        for k in 0..n {
            touch[k] = 10.0 * tolerances(&sc, k).0;
            v_settle[k] = self.set.settle_tol * (sc.g * sc.r[k]).sqrt();
        }
        for _ in 0..16 {
            let (cs, nc) = touching(&sc, &bodies, n, &touch);
            let Some(imp) = resolve(&sc, self.set.impact, &bodies, n, &cs[..nc], &v_settle) else {
                self.fail(format!(
                    "no impulse satisfies the impact law over the {nc} touching corners"
                ));
                return;
            };
            for i in 0..nc {
                if imp.pn[i] > 0.0 && imp.un[i] < -tolerances(&sc, cs[i].k).1 {
                    self.out.impacts += 1;
                    self.out.first_impact_time.get_or_insert(self.t);
                }
            }
            for k in 0..n {
                let b = &mut self.bodies[k];
                b.mu_impact = b.mu_impact.max(imp.demand[k]);
            }
            if imp.how != Resolution::Stick {
                self.out.slipping_impacts += 1;
            }
            if imp.dk > 1e-12 * imp.k_before.max(f64::MIN_POSITIVE) {
                self.out.energy_gains += 1;
            }
            self.out.settles += imp.settled[..n].iter().filter(|&&s| s).count() as u64;
            for (k, b) in bodies.iter_mut().enumerate().take(n) {
                b.v = [imp.v[3 * k], imp.v[3 * k + 1]];
                b.w = imp.v[3 * k + 2];
            }
            // the cascade rule: a corner left moving along its normal
            // slower than CASCADE_REST √(gR) rests on its face
            let mut sc_r = sc;
            if self.set.settle_cascades {
                sc_r.rest_after_impact = CASCADE_REST;
            }
            match select(&sc_r, &bodies, n, ax, ay, Exclude::None) {
                Ok(c) => {
                    self.set_state(c.modes, &c.q, &c.qd);
                    return;
                }
                Err(NoState::Approaching(_)) => continue,
                Err(NoState::Inconsistent(m)) => {
                    self.fail(format!("after an impact, {m}"));
                    return;
                }
            }
        }
        self.fail("16 impacts at one instant left a corner approaching its face".to_string());
    }

    /// A history row at the current time and state.
    fn push_row(&mut self, event: bool) {
        if self.hist.is_some() {
            self.push_row_at(self.t, &self.y.clone(), event);
        }
    }

    /// A history row at time t and state y (of the current modes).
    fn push_row_at(&mut self, t: f64, y: &[f64; NY], event: bool) {
        if self.hist.is_none() {
            return;
        }
        let sc = self.sc;
        let n = sc.n;
        let ch = self.chain(y);
        let nb = self.modes.n;
        let nan = f64::NAN;
        let mut row = StackRow {
            t,
            event,
            mode: Vec::with_capacity(n),
            theta: vec![nan; n],
            phi: vec![nan; n],
            phi_dot: vec![nan; n],
            x: vec![nan; n],
            y: vec![nan; n],
            slip: vec![nan; n],
            energy: 0.0,
        };
        for k in 0..n {
            row.mode.push(if k < nb {
                self.modes.ifs[k].mode()
            } else {
                crate::outcome::Mode::Flight
            });
        }
        let v = velocities(&ch.body, nb);
        let mut e = kinetic(&sc, &v, nb);
        for k in 0..nb {
            let b: &Body = &ch.body[k];
            row.theta[k] = b.th;
            row.phi[k] = ch.rel[k].phi;
            row.phi_dot[k] = ch.rel[k].phid;
            row.x[k] = b.c[0];
            row.y[k] = b.c[1];
            row.slip[k] = self.slip(&ch, k).unwrap_or(nan);
            e += sc.m[k] * sc.g * b.c[1]; // potential energy m g y
        }
        row.energy = e;
        if let Some(h) = self.hist.as_deref_mut() {
            h.rows.push(row);
        }
    }
}
