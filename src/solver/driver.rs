//! The event loop: one mode at a time, stopping at every record sample and at
//! every located event, then applying the reset map of the event.
//!
//! The record's acceleration is linear between samples, so each sample
//! interval is a smooth stretch of forcing. Inside it:
//! - **rest** needs no integration: the start of rocking is the exact crossing
//!   of |ẍg| = (g + ÿg)·B/H on the linear forcing;
//! - **rock** (1 DOF) is integrated by a Taylor series of order 8 (or by
//!   Dormand–Prince 5(4), or solved in closed form for the linearised model)
//!   and its events (impact θ = 0, lift-off N = 0, overturning |θ| = π/2) are
//!   located by root finding on the series (the dense output);
//! - **flight** (3 DOF) has a closed form (G follows a cubic in time, θ̇ is
//!   constant) and landings are located on it.
//!
//! Ring-down rule: an impact whose rebound normal velocity is below
//! ε·√(gR) is treated as plastic (e = 0 at that impact), and a block whose
//! corners are both within touching distance and move slower than ε·√(gR)
//! is set to rest (ε = `settle_tol`). Two-contact rule: at an impact every
//! corner within 1e-9·B of the ground is in contact; while any contact corner
//! approaches the ground, the single-corner impact law is applied at the one
//! approaching fastest (sequential impacts), at most 64 times, after which
//! the block is set down flat and still.
//!
//! Cascade rule (`settle_cascades`, e = 0 and infinite friction): after a rock
//! impact, a block rocking on alternate corners with a shrinking speed u
//! (uₙ₊₁ = η·uₙ on landing, η = 1 − 1.5 sin²θc) makes an endless cascade of
//! ever shorter bounces that the ε rule only ends after dozens of impacts.
//! Over a window of the record let lo be the smallest restoring acceleration
//! Aₛ of eq. (1) at θ = 0 on either side, and let x bound how far the
//! acceleration of one bounce strays from its value A* at the bounce's start
//! (the rate of change of Aₛ times the bounce's duration, plus the change of
//! eq. (1) over the bounce's height). Then each bounce lasts at most
//! 2u/(lo − x), lands at most √((lo + x)/(lo − x)) faster than it left, and so
//! the cascade ends within T = 2u₀/((lo − x)(1 − ρ)), ρ = η·√((lo + x)/(lo − x))
//! < 1. If it ends inside the window, never rises above the peak rotation
//! already reached, and N stays positive, the block is set to rest at once:
//! the exact cascade is at rest by then too, and the record cannot lift the
//! block in between, so the motion afterwards, the peak rotation and
//! overturning are those of the cascade followed impact by impact. The
//! cascade's own friction demand is taken at its two ends (a rest-like
//! demand, to O(u²)); its impacts are not counted in `impacts`; it counts one
//! in `settles`.
//!
//! Lift-off rule under infinite friction: when N reaches 0 in rock, the pivot
//! is released into flight only if it would then rise (q < 0, see
//! [`RockContact::q`](super::physics::RockContact::q)); otherwise
//! the pivot is held (a tensile contact, counted in `liftoff_holds`) until
//! N > 0 again or the release becomes consistent.

use super::block::Block;
use super::dopri::{StepCounts, Stepper, Tolerance};
use super::history::{History, HistoryRow};
use super::impact::{self, Velocity};
use super::physics as ph;
use super::roots::brent;
use super::scan::{first_descent, first_descent_after_release};
use super::settings::{Analysis, Friction, Integrator, Model, SolverSettings};
use super::taylor;
use crate::error::{Error, Result};
use crate::motion::Record;
use crate::outcome::{Mode, Outcome};
use std::f64::consts::FRAC_PI_2;

/// Rock about the corner on side −s (s = +1: left corner, θ ≥ 0).
#[derive(Clone, Copy, Debug)]
struct RockState {
    s: f64,
    theta: f64,
    omega: f64,
    /// N reached 0 but releasing the pivot was inconsistent: the pivot is held.
    hold: bool,
    /// Contact quantities at the end of the last step (time, values), reused
    /// as the start of the next one.
    last: Option<(f64, ph::RockContact)>,
}

/// Free flight, relative to the ground.
#[derive(Clone, Copy, Debug)]
struct FlightState {
    x: f64,
    vx: f64,
    y: f64,
    vy: f64,
    theta: f64,
    omega: f64,
}

/// Slide on both corners (θ = 0); `x` is the footprint's offset from its
/// initial place (m), `v` its velocity relative to the ground (m/s).
#[derive(Clone, Copy, Debug)]
struct SlideState {
    x: f64,
    v: f64,
    /// Slip direction σ = sign(v) (kept explicitly: v is 0 at the start).
    sigma: f64,
}

/// Slide-rock: rock about the corner on side −s while it slips; `xp` is the
/// pivot's offset from its rest position (m), `vp` its slip velocity (m/s).
#[derive(Clone, Copy, Debug)]
struct SlideRockState {
    s: f64,
    theta: f64,
    omega: f64,
    xp: f64,
    vp: f64,
    sigma: f64,
}

#[derive(Clone, Copy, Debug)]
enum State {
    Rest,
    Slide(SlideState),
    Rock(RockState),
    SlideRock(SlideRockState),
    Flight(FlightState),
}

impl State {
    fn mode(&self) -> Mode {
        match self {
            State::Rest => Mode::Rest,
            State::Slide(_) => Mode::Slide,
            State::Rock(_) => Mode::Rock,
            State::SlideRock(_) => Mode::SlideRock,
            State::Flight(_) => Mode::Flight,
        }
    }
}

/// Events located inside a sample interval.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Event {
    /// Rest broken: start rocking with θ > 0 (s = +1) or θ < 0 (s = −1).
    StartRock(f64),
    /// θ reached 0 while rocking.
    RockImpact,
    /// N reached 0 and the pivot can be released.
    Uplift,
    /// N reached 0 but the pivot would not rise: hold it.
    HoldStart,
    /// N > 0 again while holding.
    HoldEnd,
    /// While holding, the release became consistent.
    Release,
    /// A corner (side ±1) reached the ground in flight.
    Landing(f64),
    /// |θ| reached π/2.
    Overturn,
    /// Rest broken by friction: start sliding in direction σ.
    StartSlide(f64),
    /// Sliding on both corners stopped (v = 0).
    SlideStop,
    /// Rocking with a stuck pivot: the friction demand reached μs N.
    SlipStart,
    /// Slide-rock: the pivot's slip velocity reached 0.
    SlipStop,
    /// Slide-rock: N reached 0 (consistent lift-off with finite friction).
    SlideRockLiftoff,
    /// Slide-rock has no slipping solution (Painlevé): the pivot sticks.
    Jam,
}

/// Ground acceleration on one sample interval: ẍg = a0 + a1 (t − t0),
/// ÿg = v0 + v1 (t − t0).
#[derive(Clone, Copy, Debug)]
struct Segment {
    t0: f64,
    a0: f64,
    a1: f64,
    v0: f64,
    v1: f64,
}

impl Segment {
    #[inline]
    fn at(&self, t: f64) -> (f64, f64) {
        let tau = t - self.t0;
        (self.a0 + self.a1 * tau, self.v0 + self.v1 * tau)
    }
}

/// Solves one analysis: a block under a record. Returns the per-run outcome;
/// pushes the full history into `history` when one is given.
///
/// ```
/// use rockfrag::motion::Record;
/// use rockfrag::solver::{simulate, Analysis, Block, SolverSettings};
/// let block = Block::new(0.5, 4.0, 9.81).unwrap();
/// // 2 s of constant acceleration at 0.3 g, above the rocking threshold g/4
/// let record = Record::from_acc("pulse", 0.01, vec![0.3 * 9.81; 201]).unwrap();
/// let out = simulate(&Analysis::new(block, 0.0), &record, &SolverSettings::default(), None).unwrap();
/// assert!(out.moved);
/// ```
pub fn simulate(
    analysis: &Analysis,
    record: &Record,
    settings: &SolverSettings,
    history: Option<&mut History>,
) -> Result<Outcome> {
    analysis.validate()?;
    settings.validate()?;
    record.validate_forcing()?;
    if settings.model == Model::Linear && analysis.friction != Friction::Infinite {
        return Err(Error::invalid(
            "model",
            "linear",
            "nonlinear with finite friction (the linearised model is for rock with stuck corners)",
        ));
    }
    if settings.model == Model::Linear && record.acc_v.is_some() {
        return Err(Error::invalid(
            "model",
            "linear",
            "nonlinear when the record has vertical acceleration",
        ));
    }
    let mut run = Run::new(analysis, record, settings, history);
    run.solve()?;
    Ok(run.out)
}

struct Run<'a> {
    bl: Block,
    e: f64,
    set: &'a SolverSettings,
    acc: &'a [f64],
    acc_v: Option<&'a [f64]>,
    dt: f64,
    init: super::settings::Initial,
    out: Outcome,
    hist: Option<&'a mut History>,
    /// Step size carried between steps (s).
    h: f64,
    /// Horizontal offset of the block's footprint from its initial place (m).
    x_base: f64,
    /// Accumulated work of the ground (J/kg), energy audit.
    work: f64,
    /// Accumulated energy jumps at events (J/kg), energy audit.
    jumps: f64,
    /// Energy at t = 0 (J/kg).
    e0: f64,
    /// Largest |E − E0 − W − jumps| seen and the energy scale.
    resid: f64,
    escale: f64,
    /// Ring-down velocity threshold ε√(gR) (m/s).
    v_settle: f64,
    /// Contact distance of the two-contact rule (m).
    h_touch: f64,
    /// Coulomb friction (μs, μk), or `None` for infinite friction.
    fric: Option<(f64, f64)>,
    /// The last release of a rock pivot into flight: (time, rock state).
    released: Option<(f64, RockState)>,
    /// |ẍg| below which rest cannot break (the smaller of the rocking and
    /// sliding thresholds, less a margin for rounding); 0 when rest is
    /// decided sample by sample (vertical ground motion, or a history).
    quiet: f64,
}

impl<'a> Run<'a> {
    fn new(
        an: &Analysis,
        rec: &'a Record,
        set: &'a SolverSettings,
        hist: Option<&'a mut History>,
    ) -> Self {
        let bl = an.block;
        let hist_none = hist.is_none();
        Run {
            bl,
            e: an.restitution,
            set,
            acc: &rec.acc,
            acc_v: rec.acc_v.as_deref(),
            dt: rec.dt,
            init: an.initial,
            out: Outcome::default(),
            hist,
            h: rec.dt * 0.25,
            x_base: 0.0,
            work: 0.0,
            jumps: 0.0,
            e0: 0.0,
            resid: 0.0,
            escale: bl.g * bl.r * (1.0 - bl.cos_c),
            v_settle: set.settle_tol * (bl.g * bl.r).sqrt(),
            h_touch: 1e-9 * bl.b,
            fric: match an.friction {
                Friction::Infinite => None,
                Friction::Coulomb { mu_s, mu_k } => Some((mu_s, mu_k)),
            },
            released: None,
            quiet: if rec.acc_v.is_none() && hist_none {
                // rest breaks when |ẍg| > g tanθc (eq. (1) at θ = 0), or slides
                // when |ẍg| > μs g; the margin covers the rounding of the
                // interpolated forcing at a sample's end
                let mu = match an.friction {
                    Friction::Infinite => f64::INFINITY,
                    Friction::Coulomb { mu_s, .. } => mu_s,
                };
                (bl.sin_c * bl.g / bl.cos_c).min(mu * bl.g) * (1.0 - 1e-9)
            } else {
                0.0
            },
        }
    }

    #[inline]
    fn segment(&self, k: usize) -> Segment {
        let t0 = k as f64 * self.dt;
        let (a0, a1) = (self.acc[k], (self.acc[k + 1] - self.acc[k]) / self.dt);
        let (v0, v1) = match self.acc_v {
            Some(v) => (v[k], (v[k + 1] - v[k]) / self.dt),
            None => (0.0, 0.0),
        };
        Segment { t0, a0, a1, v0, v1 }
    }

    fn initial_state(&self) -> State {
        let (th, om) = (self.init.theta, self.init.theta_dot);
        if self.init.y_dot > 0.0 {
            let i = self.init;
            State::Flight(FlightState {
                x: 0.0,
                vx: i.x_dot,
                y: 0.0,
                vy: i.y_dot,
                theta: 0.0,
                omega: om,
            })
        } else if th == 0.0 && om == 0.0 {
            State::Rest
        } else {
            let s = if th != 0.0 { th.signum() } else { om.signum() };
            State::Rock(RockState {
                s,
                theta: th,
                omega: om,
                hold: false,
                last: None,
            })
        }
    }

    fn solve(&mut self) -> Result<()> {
        let n = self.acc.len();
        let mut state = self.initial_state();
        match state {
            State::Rest => {}
            State::Flight(_) => {
                self.out.moved = true;
                self.out.flights += 1;
            }
            State::Rock(_) | State::Slide(_) | State::SlideRock(_) => self.out.moved = true,
        }
        self.e0 = self.energy(&state);
        let mut k = 0usize;
        let mut t = 0.0;
        let seg0 = self.segment(0);
        self.push_row(t, &state, &seg0, false);
        self.note_theta(&state);
        while k + 1 < n {
            if matches!(state, State::Rest) && self.quiet > 0.0 {
                // Fast-forward over samples where the ground is too weak, at both
                // ends, to break rest (the forcing is linear in between).
                let k0 = k;
                if self.acc[k].abs() < self.quiet {
                    while k + 1 < n && self.acc[k + 1].abs() < self.quiet {
                        k += 1;
                    }
                }
                if k > k0 {
                    let t_start = t;
                    t = k as f64 * self.dt;
                    self.out.time_in_mode[Mode::Rest.index()] += t - t_start;
                    continue;
                }
            }
            let seg = self.segment(k);
            let t_end = (k + 1) as f64 * self.dt;
            let t_start = t;
            let mode = state.mode();
            let event = match &mut state {
                State::Rest => match self.fric {
                    // Shenton (1996): from rest a block slides if μs < B/H and rocks if
                    // μs > B/H. At μs = B/H both thresholds coincide, and a block that
                    // starts to tip needs F/N rising above B/H at once (d(F/N)/dẍg = 1/4g
                    // > 0 at θ = 0), so it slips flat: the tie slides.
                    // A block coming to rest (after a landing) while |ẍg| already
                    // exceeds μs (g + ÿg) cannot stay stuck, nor rock on a stuck
                    // corner: it slides.
                    Some((mu_s, _))
                        if mu_s <= self.bl.b / self.bl.h || self.slide_exceeded(&seg, t, mu_s) =>
                    {
                        self.rest_slide(&seg, &mut t, t_end, mu_s)
                    }
                    _ => self.rest(&seg, &mut t, t_end),
                },
                State::Slide(ss) => self.slide(ss, &seg, &mut t, t_end),
                State::SlideRock(sr) => {
                    if self.set.audit_energy {
                        self.slide_rock::<5>(sr, &seg, &mut t, t_end)?
                    } else {
                        self.slide_rock::<4>(sr, &seg, &mut t, t_end)?
                    }
                }
                State::Rock(rs) => match (self.set.model, self.set.integrator) {
                    (Model::Linear, _) => self.rock_linear(rs, &seg, &mut t, t_end),
                    (Model::Nonlinear, Integrator::Taylor) => {
                        self.rock_taylor(rs, &seg, &mut t, t_end)?
                    }
                    (Model::Nonlinear, Integrator::Dopri5) if self.set.audit_energy => {
                        self.rock_nonlinear::<3>(rs, &seg, &mut t, t_end)?
                    }
                    (Model::Nonlinear, Integrator::Dopri5) => {
                        self.rock_nonlinear::<2>(rs, &seg, &mut t, t_end)?
                    }
                },
                State::Flight(fs) => self.flight(fs, &seg, &mut t, t_end),
            };
            self.out.time_in_mode[mode.index()] += t - t_start;
            match event {
                None => {
                    t = t_end;
                    k += 1;
                    if self.hist.is_some() {
                        let seg_end = if k + 1 < n {
                            self.segment(k)
                        } else {
                            Segment { t0: t, ..seg }
                        };
                        self.push_row(t, &state, &seg_end, false);
                    }
                    self.audit(&state);
                    // the footprint moves between events only while slipping
                    if matches!(state, State::Slide(_) | State::SlideRock(_)) {
                        self.note_slip(&state);
                    }
                }
                Some(ev) => {
                    self.out.stats.events += 1;
                    if self.out.stats.events > self.set.max_events {
                        return Err(Error::Solver {
                            time: t,
                            message: format!(
                                "more than {} events (max_events)",
                                self.set.max_events
                            ),
                        });
                    }
                    self.audit(&state);
                    self.push_row(t, &state, &seg, true);
                    let before = if self.set.audit_energy {
                        self.energy(&state)
                    } else {
                        0.0
                    };
                    let from = state.mode();
                    state = self.handle(ev, state, t)?;
                    let to = state.mode();
                    if from != to {
                        self.out.transitions[from.index()][to.index()] += 1;
                    }
                    self.note_slip(&state);
                    if self.set.audit_energy {
                        self.jumps += self.energy(&state) - before;
                    }
                    self.note_theta(&state);
                    self.push_row(t, &state, &seg, true);
                    if self.out.overturned {
                        break;
                    }
                }
            }
        }
        self.out.end_time = t;
        if self.set.audit_energy {
            self.out.energy_residual = Some(self.resid / self.escale);
        }
        Ok(())
    }

    // ---------------------------------------------------------------- rest

    /// Rest: find the first time in [t, t_end] where |ẍg| > (g + ÿg)·B/H
    /// (exact on linear forcing: both sides of the inequality are linear in t).
    fn rest(&mut self, seg: &Segment, t: &mut f64, t_end: f64) -> Option<Event> {
        let (sc, cc, g) = (self.bl.sin_c, self.bl.cos_c, self.bl.g);
        // f = cosθc·s·ẍg − sinθc·(g + ÿg) ∝ s·θ̈ of eq. (1) at θ = 0 (same
        // floating-point operations, so f > 0 ⇔ the block departs)
        let found = first_exceedance(seg, t, t_end, |s, ax, ay| cc * (s * ax) - sc * (g + ay));
        found.map(Event::StartRock)
    }

    /// Rest with μs ≤ B/H: find the first time in [t, t_end] where
    /// |ẍg| > μs (g + ÿg) (Shenton 1996), exact on the linear forcing. The
    /// block then slides opposite to the ground's acceleration.
    fn rest_slide(&mut self, seg: &Segment, t: &mut f64, t_end: f64, mu_s: f64) -> Option<Event> {
        let g = self.bl.g;
        let found = first_exceedance(seg, t, t_end, |s, ax, ay| s * ax - mu_s * (g + ay));
        found.map(|s| Event::StartSlide(-s))
    }

    /// True if |ẍg(t)| > μs (g + ÿg(t)): friction cannot hold the block at rest.
    fn slide_exceeded(&self, seg: &Segment, t: f64, mu_s: f64) -> bool {
        let (ax, ay) = seg.at(t);
        ax.abs() > mu_s * (self.bl.g + ay)
    }

    /// Slide on both corners over [t, t_end], in closed form: the relative
    /// acceleration −ẍg − μk σ (g + ÿg) is linear in time.
    fn slide(
        &mut self,
        ss: &mut SlideState,
        seg: &Segment,
        t: &mut f64,
        t_end: f64,
    ) -> Option<Event> {
        let (_, mu_k) = self.fric.expect("slide needs finite friction");
        let t0 = *t;
        let (a0, b0) = seg.at(t0);
        let sg = ss.sigma;
        // ẍ = A + Bτ
        let acc0 = -a0 - mu_k * sg * (self.bl.g + b0);
        let acc1 = -seg.a1 - mu_k * sg * seg.v1;
        let st = *ss;
        let vel = move |tau: f64| st.v + acc0 * tau + 0.5 * acc1 * tau * tau;
        let span = t_end - t0;
        let xtol = 1e-15 * t_end.abs().max(1.0);
        let fd = |tau: f64| (sg * vel(tau), sg * (acc0 + acc1 * tau));
        let found = if st.v == 0.0 {
            first_descent_after_release(fd, 0.0, span, 1, xtol)
        } else {
            first_descent(fd, 0.0, span, 1, xtol)
        };
        let tau_end = found.unwrap_or(span);
        if self.set.audit_energy {
            // ground and friction work: ∫ v·ẍ dτ (cubic integrand: 3-point Gauss is exact)
            self.work += gauss3(tau_end, |tau| vel(tau) * (acc0 + acc1 * tau));
        }
        ss.x =
            st.x + st.v * tau_end + 0.5 * acc0 * tau_end * tau_end + acc1 * tau_end.powi(3) / 6.0;
        ss.v = if found.is_some() { 0.0 } else { vel(tau_end) };
        *t = t0 + tau_end;
        if found.is_some() {
            Some(Event::SlideStop)
        } else {
            *t = t_end;
            None
        }
    }

    /// Slide-rock over [t, t_end] by DOPRI5 on (θ, θ̇, xp, ẋp); N = 5 also
    /// integrates the work of the ground and of friction for the audit.
    fn slide_rock<const N: usize>(
        &mut self,
        sr: &mut SlideRockState,
        seg: &Segment,
        t: &mut f64,
        t_end: f64,
    ) -> Result<Option<Event>> {
        let (_, mu_k) = self.fric.expect("slide-rock needs finite friction");
        let bl = self.bl;
        let (s, sg) = (sr.s, sr.sigma);
        let seg = *seg;
        let mut rhs = |tt: f64, y: &[f64; N]| -> [f64; N] {
            let (ax, ay) = seg.at(tt);
            let a = ph::slide_rock_accel(&bl, s, sg, mu_k, y[0], y[1], ax, ay);
            let mut out = [0.0; N];
            out[0] = y[1];
            out[1] = a.alpha;
            out[2] = y[3];
            out[3] = a.xp_acc;
            if let Some(w) = out.get_mut(4) {
                let k = ph::rock_kinematics(&bl, s, y[0], y[1]);
                *w = ph::ground_power(ax, ay, y[3] + k[1], k[3]) + a.f * y[3];
            }
            out
        };
        let (tc, p, r) = (bl.theta_c, bl.p, bl.r);
        let tol = self.tolerance::<N>(&[tc, p * tc, r * tc, p * r * tc]);
        let mut y = [0.0; N];
        y[..4].copy_from_slice(&[sr.theta, sr.omega, sr.xp, sr.vp]);
        let mut st = Stepper::new(&mut rhs, *t, y, t_end, self.h, tol, self.dt);
        let mut released = sr.vp == 0.0;
        let mut found = None;
        loop {
            let step = match st.step(&mut rhs) {
                Ok(Some(step)) => step,
                Ok(None) => break,
                Err(time) => {
                    return Err(Error::Solver {
                        time,
                        message: format!("step size {} s too small in slide-rock", st.h),
                    });
                }
            };
            let (ta, t1) = (st.t, step.t0 + step.h);
            let xtol = 1e-15 * t1.abs().max(1.0);
            let comp = |i: usize, tt: f64| step.component_at(i, tt);
            let mut best: Option<(f64, Event)> = None;
            let psi = |tt: f64| (s * comp(0, tt), s * comp(1, tt));
            earliest(
                &mut best,
                first_descent(psi, ta, t1, 1, xtol),
                Event::RockImpact,
            );
            let over = |tt: f64| (FRAC_PI_2 - s * comp(0, tt), -s * comp(1, tt));
            earliest(
                &mut best,
                first_descent(over, ta, t1, 1, xtol),
                Event::Overturn,
            );
            let acc_at = |tt: f64| {
                let (ax, ay) = seg.at(tt);
                ph::slide_rock_accel(&bl, s, sg, mu_k, comp(0, tt), comp(1, tt), ax, ay)
            };
            // slip velocity σ ẋp reaching 0
            let slip = |tt: f64| (sg * comp(3, tt), sg * acc_at(tt).xp_acc);
            let slip_stop = if released {
                first_descent_after_release(slip, ta, t1, 1, xtol)
            } else {
                first_descent(slip, ta, t1, 1, xtol)
            };
            earliest(&mut best, slip_stop, Event::SlipStop);
            let (a0, a1) = (acc_at(ta), acc_at(t1));
            if a0.den <= 0.0 {
                earliest(&mut best, Some(ta), Event::Jam);
            } else if a1.den <= 0.0 {
                earliest(
                    &mut best,
                    Some(brent(|tt| acc_at(tt).den, ta, t1, a0.den, a1.den, xtol)),
                    Event::Jam,
                );
            }
            if a0.n < 0.0 {
                earliest(&mut best, Some(ta), Event::SlideRockLiftoff);
            } else if a1.n < 0.0 {
                earliest(
                    &mut best,
                    Some(brent(|tt| acc_at(tt).n, ta, t1, a0.n, a1.n, xtol)),
                    Event::SlideRockLiftoff,
                );
            }
            let t_stop = best.map_or(t1, |(te, _)| te);
            let ratio = (comp(0, t_stop).abs().max(comp(0, ta).abs()) / bl.theta_c)
                .min(FRAC_PI_2 / bl.theta_c);
            self.out.theta_max_over_theta_c = self.out.theta_max_over_theta_c.max(ratio);
            if let Some((te, ev)) = best {
                found = Some((te, ev, step.at(te)));
                break;
            }
            st.accept(&step);
            released = false;
        }
        self.h = st.h;
        self.count(&st.counts);
        let (t_stop, event, ye) = match found {
            Some((te, ev, ye)) => (te, Some(ev), ye),
            None => (t_end, None, st.y),
        };
        if N == 5 {
            self.work += ye[4];
        }
        sr.theta = ye[0];
        sr.omega = ye[1];
        sr.xp = ye[2];
        sr.vp = if event == Some(Event::SlipStop) {
            0.0
        } else {
            ye[3]
        };
        *t = t_stop;
        Ok(event)
    }

    // ---------------------------------------------------------------- rock

    /// Nonlinear rock over [t, t_end] by DOPRI5; N = 3 also integrates the
    /// ground work for the energy audit.
    fn rock_nonlinear<const N: usize>(
        &mut self,
        rs: &mut RockState,
        seg: &Segment,
        t: &mut f64,
        t_end: f64,
    ) -> Result<Option<Event>> {
        let bl = self.bl;
        let s = rs.s;
        let seg = *seg;
        let mut rhs = |tt: f64, y: &[f64; N]| -> [f64; N] {
            let (ax, ay) = seg.at(tt);
            let mut out = [0.0; N];
            out[0] = y[1];
            out[1] = ph::rock_accel(&bl, s, y[0], ax, ay);
            if let Some(w) = out.get_mut(2) {
                let k = ph::rock_kinematics(&bl, s, y[0], y[1]);
                *w = ph::ground_power(ax, ay, k[1], k[3]);
            }
            out
        };
        let tol = self.tolerance::<N>(&[bl.theta_c, bl.p * bl.theta_c]);
        let mut y = [0.0; N];
        y[0] = rs.theta;
        y[1] = rs.omega;
        let mut st = Stepper::new(&mut rhs, *t, y, t_end, self.h, tol, self.dt);
        let mut found = None;
        loop {
            let step = match st.step(&mut rhs) {
                Ok(Some(step)) => step,
                Ok(None) => break,
                Err(time) => {
                    return Err(Error::Solver {
                        time,
                        message: format!("step size {} s too small in rock", st.h),
                    });
                }
            };
            let path = |tt: f64| (step.component_at(0, tt), step.component_at(1, tt));
            let trig = |tt: f64| (bl.theta_c - s * step.component_at(0, tt)).sin_cos();
            let unknown = (f64::NEG_INFINITY, f64::INFINITY);
            if let Some((te, ev)) =
                self.rock_events(rs, &path, &trig, unknown, &seg, st.t, step.t0 + step.h, 1)
            {
                found = Some((te, ev, step.at(te)));
                break;
            }
            st.accept(&step);
        }
        self.h = st.h;
        self.count(&st.counts);
        let (t_stop, event, ye) = match found {
            Some((te, ev, ye)) => (te, Some(ev), ye),
            None => (t_end, None, st.y),
        };
        if N == 3 {
            self.work += ye[N - 1];
        }
        rs.theta = ye[0];
        rs.omega = ye[1];
        *t = t_stop;
        Ok(event)
    }

    /// Nonlinear rock over [t, t_end] by Taylor series ([`taylor`]): one
    /// series per step, usually one step per sample; events are located on
    /// the series. With the energy audit, the ground's work is a series too.
    fn rock_taylor(
        &mut self,
        rs: &mut RockState,
        seg: &Segment,
        t: &mut f64,
        t_end: f64,
    ) -> Result<Option<Event>> {
        let bl = self.bl;
        let s = rs.s;
        let seg = *seg;
        let k = 0.75 / bl.r; // eq. (1): I_O = 4mR²/3
        let (atol_th, atol_om) = (
            self.set.atol * bl.theta_c,
            self.set.atol * bl.p * bl.theta_c,
        );
        let h_min = 1e-14 * t_end.abs().max(1.0);
        while *t < t_end {
            let t0 = *t;
            let (ax0, ay0) = seg.at(t0);
            let forcing = taylor::LinearForcing {
                a0: ax0,
                a1: seg.a1,
                v0: bl.g + ay0,
                v1: seg.v1,
            };
            let (psi0, dpsi0) = (s * rs.theta, s * rs.omega);
            let (sin0, cos0) = bl.phi_sin_cos(psi0);
            let series = taylor::RockSeries::new(sin0, cos0, k, s, psi0, dpsi0, &forcing);
            self.out.stats.rhs_calls += 1;
            let tol_psi = atol_th + self.set.rtol * psi0.abs();
            let tol_dpsi = atol_om + self.set.rtol * dpsi0.abs();
            let h = series.step(t_end - t0, tol_psi, tol_dpsi);
            if h.is_nan() || h <= h_min {
                return Err(Error::Solver {
                    time: t0,
                    message: format!("Taylor step {h} s too small in rock"),
                });
            }
            self.out.stats.steps_accepted += 1;
            let t1 = if h == t_end - t0 { t_end } else { t0 + h };
            // the ends are asked for several times by the event checks: once each
            let start = (psi0, dpsi0, series.sin[0], series.cos[0]);
            let end = series.full_at(t1 - t0);
            let cached = |tt: f64| {
                if tt == t0 {
                    Some(start)
                } else if tt == t1 {
                    Some(end)
                } else {
                    None
                }
            };
            let full = |tt: f64| cached(tt).unwrap_or_else(|| series.full_at(tt - t0));
            let path = |tt: f64| {
                let (p, d) = cached(tt).map_or_else(|| series.at(tt - t0), |c| (c.0, c.1));
                (s * p, s * d)
            };
            let trig = |tt: f64| {
                let (_, _, sn, cs) = full(tt);
                (sn, cs)
            };
            let range = series.psi_bounds(t1 - t0, tol_psi);
            let found = self.rock_events(rs, &path, &trig, range, &seg, t0, t1, 1);
            let t_stop = found.map_or(t1, |(te, _)| te);
            if self.set.audit_energy {
                let w = series.work(bl.r, s, &forcing, bl.g);
                self.work += taylor::eval(&w, t_stop - t0);
            }
            (rs.theta, rs.omega) = path(t_stop);
            *t = t_stop;
            if let Some((_, ev)) = found {
                return Ok(Some(ev));
            }
        }
        Ok(None)
    }

    /// Linearised rock over [t, t_end], in closed form:
    /// θ(τ) = A cosh λτ + B sinh λτ − (c0 + c1τ)/λ².
    fn rock_linear(
        &mut self,
        rs: &mut RockState,
        seg: &Segment,
        t: &mut f64,
        t_end: f64,
    ) -> Option<Event> {
        let (ax0, _) = seg.at(*t);
        let (l2, c0, c1) = ph::linear_coeffs(&self.bl, rs.s, ax0, seg.a1);
        let lam = l2.sqrt();
        let (th0, om0) = (rs.theta, rs.omega);
        let t0 = *t;
        // θ(τ) = θ0 cosh λτ + (ω0/λ) sinh λτ + (c0/λ²)(cosh λτ − 1) + (c1/λ³)(sinh λτ − λτ),
        // written so that τ = 0 returns (θ0, ω0) exactly and small τ loses no digits
        let path = |tt: f64| {
            let tau = tt - t0;
            let x = lam * tau;
            // one expm1 gives sinh, cosh and cosh − 1 without cancellation
            let em = x.exp_m1();
            let sh = 0.5 * (em + em / (1.0 + em));
            let chm1 = 0.5 * em * em / (1.0 + em); // cosh x − 1
            let ch = 1.0 + chm1;
            let shmx = if x.abs() < 0.5 {
                sinh_minus_x(x)
            } else {
                sh - x
            };
            let th = th0 * ch + om0 / lam * sh + c0 / l2 * chm1 + c1 / (l2 * lam) * shmx;
            let om = th0 * lam * sh + om0 * ch + c0 / lam * sh + c1 / l2 * chm1;
            (th, om)
        };
        let n = 1 + (2.0 * lam * (t_end - t0)) as usize;
        self.out.stats.steps_accepted += 1;
        let (s, theta_c) = (rs.s, self.bl.theta_c);
        let trig = |tt: f64| (theta_c - s * path(tt).0).sin_cos();
        let unknown = (f64::NEG_INFINITY, f64::INFINITY);
        if let Some((te, ev)) = self.rock_events(rs, &path, &trig, unknown, seg, t0, t_end, n) {
            let (th, om) = path(te);
            rs.theta = th;
            rs.omega = om;
            *t = te;
            return Some(ev);
        }
        let (th, om) = path(t_end);
        rs.theta = th;
        rs.omega = om;
        *t = t_end;
        None
    }

    /// Locates the earliest rock event on (ta, tb] along `path(t) = (θ, θ̇)`,
    /// and updates the peak rotation and friction demand. Contact forces are
    /// those of eq. (1) at the path's state; the value at `ta` is reused from
    /// the previous step's end when available.
    #[allow(clippy::too_many_arguments)]
    fn rock_events(
        &mut self,
        rs: &mut RockState,
        path: &impl Fn(f64) -> (f64, f64),
        trig: &impl Fn(f64) -> (f64, f64),
        psi_range: (f64, f64),
        seg: &Segment,
        ta: f64,
        tb: f64,
        n: usize,
    ) -> Option<(f64, Event)> {
        let s = rs.s;
        let bl = self.bl;
        let xtol = 1e-15 * tb.abs().max(1.0);
        let contact = |tt: f64| {
            let (_, om) = path(tt);
            let (sp, cp) = trig(tt);
            let (ax, ay) = seg.at(tt);
            ph::rock_contact_sc(&bl, s, sp, cp, om, ax, ay)
        };
        let mut best: Option<(f64, Event)> = None;
        // Impact: ψ = sθ reaches 0 (grazing dips included).
        let psi = |tt: f64| {
            let (th, om) = path(tt);
            (s * th, s * om)
        };
        // `psi_range` bounds ψ over the step (infinite when unknown): the
        // searches are skipped when it proves there is nothing to find.
        if psi_range.0 <= 0.0 {
            earliest(
                &mut best,
                first_descent(psi, ta, tb, n, xtol),
                Event::RockImpact,
            );
        }
        // Overturning: π/2 − ψ reaches 0.
        let over = |tt: f64| {
            let (th, om) = path(tt);
            (FRAC_PI_2 - s * th, -s * om)
        };
        if psi_range.1 >= FRAC_PI_2 {
            earliest(
                &mut best,
                first_descent(over, ta, tb, n, xtol),
                Event::Overturn,
            );
        }
        // Normal force and release condition, checked at the ends of each piece.
        // Release needs q < 0 (the freed pivot accelerates upwards). Within
        // rounding of q = 0 the third-order motion decides and the freed
        // corner can be driven straight back into the ground, so release
        // asks for q below −1e-9 g; otherwise the pivot is held.
        let q_tol = 1e-9 * bl.g;
        // the release indicator: < 0 when release is consistent
        let release_q = |c: &ph::RockContact| c.q + q_tol;
        let normal = |tt: f64| contact(tt).n;
        let release = |tt: f64| release_q(&contact(tt));
        let c_a = match rs.last {
            Some((t_last, c)) if t_last == ta => c,
            _ => contact(ta),
        };
        let (mut n0, mut q0) = (c_a.n, release_q(&c_a));
        let mut c_end: Option<ph::RockContact> = None;
        if let Some((mu_s, mu_k)) = self.fric {
            // Stuck pivot under Coulomb friction: slip starts when |F| reaches
            // μs N (this comes before N = 0, since |F| ≤ μs N fails first). If
            // neither sticking nor slipping is consistent (Painlevé), the pivot
            // is held until the friction demand is met again, slipping becomes
            // consistent, or the pivot can be released into flight.
            let margin = |c: &ph::RockContact| mu_s * c.n - c.f.abs();
            let mut m0 = margin(&c_a);
            if !rs.hold && m0 < 0.0 {
                return Some((ta, Event::SlipStart));
            }
            let width = (tb - ta) / n as f64;
            let mut t0 = ta;
            for i in 1..=n {
                let t1 = if i == n { tb } else { ta + width * i as f64 };
                let c1 = contact(t1);
                if i == n {
                    c_end = Some(c1);
                }
                let m1 = margin(&c1);
                if !rs.hold && m1 < 0.0 {
                    let te = brent(|tt| margin(&contact(tt)), t0, t1, m0, m1, xtol);
                    earliest(&mut best, Some(te), Event::SlipStart);
                    break;
                }
                if rs.hold {
                    if m0 < 0.0 && m1 >= 0.0 {
                        let te = brent(|tt| margin(&contact(tt)), t0, t1, m0, m1, xtol);
                        earliest(&mut best, Some(te), Event::HoldEnd);
                    }
                    let q1 = release_q(&c1);
                    if q0 >= 0.0 && q1 < 0.0 && c1.n < 0.0 {
                        earliest(
                            &mut best,
                            Some(brent(release, t0, t1, q0, q1, xtol)),
                            Event::Release,
                        );
                    }
                    if best.is_none() && i == n {
                        let (th, om) = path(t1);
                        let (ax, ay) = seg.at(t1);
                        let slips = [1.0, -1.0].into_iter().any(|sg| {
                            let a = ph::slide_rock_accel(&bl, s, sg, mu_k, th, om, ax, ay);
                            a.den > 0.0 && sg * a.xp_acc > 0.0
                        });
                        if slips {
                            earliest(&mut best, Some(t1), Event::SlipStart);
                        }
                    }
                    if best.is_some() {
                        break;
                    }
                }
                t0 = t1;
                m0 = m1;
                q0 = release_q(&c1);
            }
        } else if !rs.hold && n0 < 0.0 {
            // Entered rock with the pivot already in tension (after an impact
            // or from initial conditions): decide at once.
            let ev = if q0 < 0.0 {
                Event::Uplift
            } else {
                Event::HoldStart
            };
            return Some((ta, ev));
        }
        let width = (tb - ta) / n as f64;
        let mut t0 = ta;
        for i in 1..=n {
            if self.fric.is_some() {
                break;
            }
            let t1 = if i == n { tb } else { ta + width * i as f64 };
            let c1 = contact(t1);
            if i == n {
                c_end = Some(c1);
            }
            let (n1, q1) = (c1.n, release_q(&c1));
            if !rs.hold && n0 >= 0.0 && n1 < 0.0 {
                let te = brent(normal, t0, t1, n0, n1, xtol);
                let ev = if release(te) < 0.0 {
                    Event::Uplift
                } else {
                    Event::HoldStart
                };
                earliest(&mut best, Some(te), ev);
                break;
            }
            if rs.hold {
                if n0 <= 0.0 && n1 > 0.0 {
                    earliest(
                        &mut best,
                        Some(brent(normal, t0, t1, n0, n1, xtol)),
                        Event::HoldEnd,
                    );
                }
                if q0 >= 0.0 && q1 < 0.0 {
                    earliest(
                        &mut best,
                        Some(brent(release, t0, t1, q0, q1, xtol)),
                        Event::Release,
                    );
                }
                if best.is_some() {
                    break;
                }
            }
            t0 = t1;
            n0 = n1;
            q0 = q1;
        }
        // Peak rotation: turning points (θ̇ = 0) inside, and the end point.
        let t_stop = best.map_or(tb, |(te, _)| te);
        let c_b = match (best, c_end) {
            (None, Some(c)) => c,
            _ => contact(t_stop),
        };
        rs.last = Some((t_stop, c_b));
        let (th_a, om_a) = path(ta);
        let (th_b, om_b) = path(t_stop);
        let mut peak = th_a.abs().max(th_b.abs());
        // a turning point can only raise θmax if ψ's bound exceeds it
        let may_raise = psi_range.1 > self.out.theta_max_over_theta_c * bl.theta_c;
        if om_a * om_b < 0.0 && (may_raise || self.hist.is_some()) {
            let tm = brent(|tt| path(tt).1, ta, t_stop, om_a, om_b, xtol);
            let (th_m, om_m) = path(tm);
            peak = peak.max(th_m.abs());
            if self.hist.is_some() {
                // turning points are part of the history: they are the amplitudes
                let st = State::Rock(RockState {
                    theta: th_m,
                    omega: om_m,
                    ..*rs
                });
                self.push_row(tm, &st, seg, true);
            }
        }
        let ratio = peak / bl.theta_c;
        if ratio > self.out.theta_max_over_theta_c {
            self.out.theta_max_over_theta_c = ratio.min(FRAC_PI_2 / bl.theta_c);
        }
        // Friction demand |F|/N at the end of the step (N > 0 only).
        if c_b.n > 0.0 {
            self.out.mu_motion = self.out.mu_motion.max(c_b.f.abs() / c_b.n);
        }
        best
    }

    // ---------------------------------------------------------------- flight

    /// Free flight over [t, t_end] in closed form; locates landings of either
    /// corner and overturning.
    fn flight(
        &mut self,
        fs: &mut FlightState,
        seg: &Segment,
        t: &mut f64,
        t_end: f64,
    ) -> Option<Event> {
        let bl = self.bl;
        let t0 = *t;
        let (a0, b0) = seg.at(t0);
        let (a1, b1) = (seg.a1, seg.v1);
        let gy0 = bl.g + b0;
        let f = *fs;
        // relative motion: ẍ = −ẍg, ÿ = −g − ÿg, θ̈ = 0
        let pos = move |tau: f64| -> FlightState {
            FlightState {
                x: f.x + f.vx * tau - a0 * tau * tau / 2.0 - a1 * tau * tau * tau / 6.0,
                vx: f.vx - a0 * tau - a1 * tau * tau / 2.0,
                y: f.y + f.vy * tau - gy0 * tau * tau / 2.0 - b1 * tau * tau * tau / 6.0,
                vy: f.vy - gy0 * tau - b1 * tau * tau / 2.0,
                theta: f.theta + f.omega * tau,
                omega: f.omega,
            }
        };
        let span = t_end - t0;
        let n = 1 + (f.omega.abs() * span / 0.2) as usize;
        let xtol = 1e-15 * t_end.abs().max(1.0);
        let mut best: Option<(f64, Event)> = None;
        // θ(τ) = θ0 + ωτ: sin and cos by angle addition, the small rotation
        // by its series (most flights of a ring-down rotate little)
        let (s0, c0) = f.theta.sin_cos();
        for side in [-1.0, 1.0] {
            let height = |tau: f64| {
                let p = pos(tau);
                let (sx, cx) = ph::sin_cos_small(f.omega * tau);
                let (st, ct) = (s0 * cx + c0 * sx, c0 * cx - s0 * sx);
                let (rx, ry) = bl.corner_offset_sc(side, st, ct);
                (bl.h + p.y + ry, p.vy + p.omega * rx)
            };
            // a corner leaving the ground at the start of this piece of flight
            // (just released by an impact or a lift-off) is departing
            let (h0, u0) = height(0.0);
            let found = if h0 <= self.h_touch && u0 >= -self.v_settle {
                first_descent_after_release(height, 0.0, span, n, xtol)
            } else {
                first_descent(height, 0.0, span, n, xtol)
            };
            earliest(&mut best, found, Event::Landing(side));
        }
        if f.omega != 0.0 {
            let te = (FRAC_PI_2.copysign(f.omega) - f.theta) / f.omega;
            if (0.0..=span).contains(&te) {
                earliest(&mut best, Some(te), Event::Overturn);
            }
        }
        let tau_end = best.map_or(span, |(te, _)| te);
        if self.set.audit_energy {
            // ∫ (−ẍg ẋ − ÿg ẏ) dτ, exact by 3-point Gauss–Legendre (integrand is cubic)
            let (half, mid) = (0.5 * tau_end, 0.5 * tau_end);
            let nodes = [
                (-0.6f64.sqrt(), 5.0 / 9.0),
                (0.0, 8.0 / 9.0),
                (0.6f64.sqrt(), 5.0 / 9.0),
            ];
            for (xi, w) in nodes {
                let tau = mid + half * xi;
                let p = pos(tau);
                self.work += w * half * ph::ground_power(a0 + a1 * tau, b0 + b1 * tau, p.vx, p.vy);
            }
        }
        *fs = pos(tau_end);
        *t = t0 + tau_end;
        let ratio = fs.theta.abs() / bl.theta_c;
        self.out.theta_max_over_theta_c = self
            .out
            .theta_max_over_theta_c
            .max(ratio.min(FRAC_PI_2 / bl.theta_c));
        match best {
            Some((_, ev)) => Some(ev),
            None => {
                *t = t_end;
                None
            }
        }
    }

    // ---------------------------------------------------------------- events

    /// Applies the reset map of an event and returns the new state.
    fn handle(&mut self, ev: Event, state: State, t: f64) -> Result<State> {
        Ok(match (ev, state) {
            (Event::Overturn, st) => {
                self.out.overturned = true;
                self.out.overturn_time = Some(t);
                st
            }
            (Event::StartRock(s), _) => {
                self.out.moved = true;
                self.h = self.h.min(0.25 * self.dt);
                State::Rock(RockState {
                    s,
                    theta: 0.0,
                    omega: 0.0,
                    hold: false,
                    last: None,
                })
            }
            (Event::HoldStart, State::Rock(mut rs)) => {
                // N reached 0: the paper's program stopped here and counted the
                // run as overturned, whether or not flight was consistent
                self.out.uplifted = true;
                self.out.liftoff_holds += 1;
                rs.hold = true;
                State::Rock(rs)
            }
            (Event::HoldEnd, State::Rock(mut rs)) => {
                rs.hold = false;
                State::Rock(rs)
            }
            (Event::Uplift | Event::Release, State::Rock(rs)) => {
                self.out.uplifted = true;
                self.out.uplifts += 1;
                self.out.flights += 1;
                self.released = Some((t, rs));
                State::Flight(self.rock_to_flight(&rs))
            }
            (Event::Landing(side), State::Flight(_))
                if self
                    .released
                    .is_some_and(|(tr, rs)| tr == t && side == -rs.s) =>
            {
                // The freed pivot is driven back into the ground at the
                // instant of release (q ≈ 0 and the rotation pushes it down):
                // no flight is possible, so the pivot is held instead.
                let Some((_, rs)) = self.released.take() else {
                    unreachable!("the guard checked `released`")
                };
                self.out.uplifts -= 1;
                self.out.flights -= 1;
                self.out.liftoff_holds += 1;
                State::Rock(RockState {
                    hold: true,
                    last: None,
                    ..rs
                })
            }
            (Event::RockImpact, State::Rock(rs)) => {
                // the impact happens at θ = 0 (the path's θ there is zero to
                // within the root's tolerance)
                let fs = self.rock_to_flight(&RockState { theta: 0.0, ..rs });
                match self.impacts(t, fs, rs.s) {
                    State::Rock(after) if self.cascade_settles(t, &after) => {
                        self.out.settles += 1;
                        State::Rest
                    }
                    st => st,
                }
            }
            (Event::Landing(side), State::Flight(fs)) => self.impacts(t, fs, side),
            (Event::StartSlide(sigma), State::Rest) => {
                self.out.moved = true;
                State::Slide(SlideState {
                    x: self.x_base,
                    v: 0.0,
                    sigma,
                })
            }
            (Event::SlideStop, State::Slide(ss)) => self.after_slide_stop(ss, t),
            (Event::SlipStart, State::Rock(rs)) => {
                match self.start_slide_rock(rs.s, rs.theta, rs.omega, self.x_base, 0.0, t) {
                    State::Rock(mut held) => {
                        // neither sticking nor slipping is consistent: hold the pivot
                        self.out.stick_holds += 1;
                        held.hold = true;
                        State::Rock(held)
                    }
                    st => st,
                }
            }
            (Event::SlipStop, State::SlideRock(sr)) => self.after_slip_stop(sr, t),
            (Event::Jam, State::SlideRock(sr)) => {
                // Painlevé: no slipping solution; the pivot sticks, held if the
                // friction demand exceeds μs N
                self.x_base = sr.xp;
                self.out.stick_holds += 1;
                let (ax, ay) = self.ground_at(t);
                let c = ph::rock_contact(&self.bl, sr.s, sr.theta, sr.omega, ax, ay);
                let hold = c.f.abs() > self.fric.map_or(f64::INFINITY, |f| f.0) * c.n;
                State::Rock(RockState {
                    s: sr.s,
                    theta: sr.theta,
                    omega: sr.omega,
                    hold,
                    last: None,
                })
            }
            (Event::SlideRockLiftoff, State::SlideRock(sr)) => {
                self.out.uplifted = true;
                self.out.uplifts += 1;
                self.out.flights += 1;
                State::Flight(self.slide_rock_to_flight(&sr))
            }
            (Event::RockImpact, State::SlideRock(sr)) => {
                let mut fs = self.slide_rock_to_flight(&sr);
                fs.theta = 0.0;
                self.impacts(t, fs, sr.s)
            }
            (ev, st) => {
                return Err(Error::Solver {
                    time: t,
                    message: format!("event {ev:?} cannot happen in mode {}", st.mode().name()),
                });
            }
        })
    }

    /// Enters slide-rock about the corner on side −s with the pivot at `xp`
    /// slipping at `vp`. At vp = 0 the slip direction σ is the one whose
    /// kinetic friction lets the pivot accelerate that way (σ ẍp > 0); if
    /// neither direction is consistent the pivot sticks (rock).
    fn start_slide_rock(
        &mut self,
        s: f64,
        theta: f64,
        omega: f64,
        xp: f64,
        vp: f64,
        t: f64,
    ) -> State {
        let (_, mu_k) = self.fric.expect("finite friction");
        let (ax, ay) = self.ground_at(t);
        let accel = |sg: f64| ph::slide_rock_accel(&self.bl, s, sg, mu_k, theta, omega, ax, ay);
        let sigma = if vp != 0.0 {
            // Slipping with no slipping solution (Painlevé, den ≤ 0): the slip is
            // stopped by a tangential impulse (dynamic jamming) and the pivot sticks.
            Some(vp.signum()).filter(|&sg| accel(sg).den > 0.0)
        } else {
            [1.0, -1.0].into_iter().find(|&sg| {
                let a = accel(sg);
                a.den > 0.0 && sg * a.xp_acc > 0.0
            })
        };
        if vp != 0.0 && sigma.is_none() {
            self.out.stick_holds += 1;
        }
        match sigma {
            Some(sigma) => State::SlideRock(SlideRockState {
                s,
                theta,
                omega,
                xp,
                vp,
                sigma,
            }),
            None => {
                self.x_base = xp;
                State::Rock(RockState {
                    s,
                    theta,
                    omega,
                    hold: false,
                    last: None,
                })
            }
        }
    }

    /// Slide-rock's slip stopped: stick (rock) if the sticking friction demand
    /// is within μs N, otherwise slip on in the consistent direction.
    fn after_slip_stop(&mut self, sr: SlideRockState, t: f64) -> State {
        let (mu_s, _) = self.fric.expect("finite friction");
        let (ax, ay) = self.ground_at(t);
        let c = ph::rock_contact(&self.bl, sr.s, sr.theta, sr.omega, ax, ay);
        if c.f.abs() <= mu_s * c.n {
            self.x_base = sr.xp;
            State::Rock(RockState {
                s: sr.s,
                theta: sr.theta,
                omega: sr.omega,
                hold: false,
                last: None,
            })
        } else {
            self.start_slide_rock(sr.s, sr.theta, sr.omega, sr.xp, 0.0, t)
        }
    }

    /// Sliding on both corners stopped: rest if |ẍg| ≤ μs (g + ÿg), otherwise
    /// slide on, opposite to the ground's acceleration.
    fn after_slide_stop(&mut self, ss: SlideState, t: f64) -> State {
        let (mu_s, _) = self.fric.expect("finite friction");
        let (ax, ay) = self.ground_at(t);
        self.x_base = ss.x;
        if ax.abs() <= mu_s * (self.bl.g + ay) {
            State::Rest
        } else {
            State::Slide(SlideState {
                x: ss.x,
                v: 0.0,
                sigma: -ax.signum(),
            })
        }
    }

    /// Ground acceleration (ẍg, ÿg) at time t.
    fn ground_at(&self, t: f64) -> (f64, f64) {
        let k = ((t / self.dt) as usize).min(self.acc.len() - 2);
        self.segment(k).at(t)
    }

    /// Slide-rock state → flight representation.
    fn slide_rock_to_flight(&self, sr: &SlideRockState) -> FlightState {
        let [x, vx, y, vy] = ph::rock_kinematics(&self.bl, sr.s, sr.theta, sr.omega);
        FlightState {
            x: sr.xp + x,
            vx: sr.vp + vx,
            y,
            vy,
            theta: sr.theta,
            omega: sr.omega,
        }
    }

    /// Error tolerances: `atol` times the given scale for each state component
    /// (θc for angles, p·θc for rates, …), and the energy scale for the
    /// audit's work component that follows them when N is one larger.
    fn tolerance<const N: usize>(&self, scales: &[f64]) -> Tolerance<N> {
        let atol =
            std::array::from_fn(|i| self.set.atol * scales.get(i).copied().unwrap_or(self.escale));
        Tolerance {
            rtol: self.set.rtol,
            atol,
        }
    }

    /// Adds a stepper's counters to the run's statistics.
    fn count(&mut self, c: &StepCounts) {
        self.out.stats.rhs_calls += c.rhs_calls;
        self.out.stats.steps_accepted += c.accepted;
        self.out.stats.steps_rejected += c.rejected;
    }

    /// Rock state → rigid-body pose and velocity in the flight representation.
    fn rock_to_flight(&self, rs: &RockState) -> FlightState {
        let [x, vx, y, vy] = ph::rock_kinematics(&self.bl, rs.s, rs.theta, rs.omega);
        FlightState {
            x: self.x_base + x,
            vx,
            y,
            vy,
            theta: rs.theta,
            omega: rs.omega,
        }
    }

    /// Sequential corner impacts starting with corner `side`, then the choice
    /// of the next mode (rest, rock or flight).
    fn impacts(&mut self, t: f64, pose: FlightState, side: f64) -> State {
        let bl = self.bl;
        let mut vel = Velocity {
            vx: pose.vx,
            vy: pose.vy,
            omega: pose.omega,
        };
        // the pose is fixed during the impacts: one sine and cosine (none at θ = 0,
        // where a rock impact happens)
        let (sn, cs) = if pose.theta == 0.0 {
            (0.0, 1.0)
        } else {
            pose.theta.sin_cos()
        };
        let offset = |sd: f64| bl.corner_offset_sc(sd, sn, cs);
        let touching: [bool; 2] =
            [-1.0, 1.0].map(|sd| bl.h + pose.y + offset(sd).1 <= self.h_touch);
        let mut next = Some(side);
        let mut count = 0;
        while let Some(sd) = next {
            let (rx, ry) = offset(sd);
            let law = self.set.impact;
            let hit = |e: f64| match self.fric {
                None => {
                    let r = impact::corner_impact(&bl, &vel, rx, ry, e, law);
                    let demand = if r.p_n > 0.0 {
                        (r.p_t / r.p_n).abs()
                    } else {
                        0.0
                    };
                    (r, demand)
                }
                Some((mu_s, mu_k)) => {
                    impact::corner_impact_friction(&bl, &vel, rx, ry, e, law, mu_s, mu_k)
                }
            };
            let (mut r, mut demand) = hit(self.e);
            let un_after = impact::point_velocity(&r.after, rx, ry).1;
            if self.e > 0.0 && un_after > 0.0 && un_after <= self.v_settle {
                // ring-down: a rebound below the threshold is plastic
                (r, demand) = hit(0.0);
                self.out.settles += 1;
            }
            self.out.impacts += 1;
            self.out.first_impact_time.get_or_insert(t);
            // friction needed to prevent sliding during this impact
            self.out.mu_impact = self.out.mu_impact.max(demand);
            let t_before = bl.kinetic(vel.vx, vel.vy, vel.omega);
            if r.delta_kinetic > 1e-12 * t_before.max(f64::MIN_POSITIVE) {
                self.out.energy_gains += 1;
            }
            vel = r.after;
            count += 1;
            if count >= 64 {
                // no convergence of sequential impacts: set the block down flat
                self.out.settles += 1;
                return self.land_flat(pose);
            }
            // the contact corner approaching fastest, if any
            next = None;
            let mut worst = -self.v_settle;
            for (i, sd) in [-1.0, 1.0].into_iter().enumerate() {
                if touching[i] {
                    let (rx, ry) = offset(sd);
                    let un = impact::point_velocity(&vel, rx, ry).1;
                    if un < worst {
                        worst = un;
                        next = Some(sd);
                    }
                }
            }
        }
        // Which contact corners stay on the ground?
        let staying: Vec2 = [-1.0, 1.0].map(|sd| {
            let i = if sd < 0.0 { 0 } else { 1 };
            touching[i] && {
                let (rx, ry) = offset(sd);
                impact::point_velocity(&vel, rx, ry).1 <= self.v_settle
            }
        });
        match staying {
            [true, true] => {
                if let Some((_, mu_k)) = self.fric
                    && vel.vx.abs() > self.v_settle
                {
                    // flat on both corners, still moving sideways: slide
                    let sigma = vel.vx.signum();
                    if mu_k > bl.b / bl.h {
                        // kinetic friction tips the block: N on the trailing corner < 0
                        return self.start_slide_rock(-sigma, pose.theta, 0.0, pose.x, vel.vx, t);
                    }
                    return State::Slide(SlideState {
                        x: pose.x,
                        v: vel.vx,
                        sigma,
                    });
                }
                if vel.vx != 0.0 || vel.vy != 0.0 || vel.omega != 0.0 {
                    self.out.settles += 1;
                }
                self.land_flat(pose)
            }
            [true, false] | [false, true] => {
                let pivot = if staying[0] { -1.0 } else { 1.0 };
                let s = -pivot;
                if self.fric.is_some() {
                    let (rx, ry) = offset(pivot);
                    let ut = impact::point_velocity(&vel, rx, ry).0;
                    if ut.abs() > self.v_settle {
                        let [x, ..] = ph::rock_kinematics(&bl, s, pose.theta, vel.omega);
                        return self.start_slide_rock(s, pose.theta, vel.omega, pose.x - x, ut, t);
                    }
                }
                let rs = RockState {
                    s,
                    theta: pose.theta,
                    omega: vel.omega,
                    hold: false,
                    last: None,
                };
                let [x, ..] = ph::rock_kinematics(&bl, s, pose.theta, vel.omega);
                self.x_base = pose.x - x;
                State::Rock(rs)
            }
            [false, false] => {
                self.out.flights += 1;
                State::Flight(FlightState {
                    vx: vel.vx,
                    vy: vel.vy,
                    omega: vel.omega,
                    ..pose
                })
            }
        }
    }

    /// The cascade rule (module documentation): true if the rock impacts that
    /// follow a rock impact at `t`, leaving the block in `rs` (θ = 0), provably
    /// die out before the ground can lift the block. Then the cascade's
    /// friction demand is noted and the caller sets the block to rest.
    fn cascade_settles(&mut self, t: f64, rs: &RockState) -> bool {
        /// Longest window, in record samples, over which the bounds are sought.
        const MAX_SAMPLES: usize = 64;
        let bl = self.bl;
        // Housner's ratio of angular velocities at a rock impact with e = 0
        let eta = impact::rock_impact_ratio(&bl, 0.0);
        let n = self.acc.len();
        if !self.set.settle_cascades
            || self.fric.is_some()
            || self.e != 0.0
            || rs.theta != 0.0
            || !(eta > 0.0 && eta < 1.0)
            || n < 2
        {
            return false;
        }
        let u0 = rs.omega.abs();
        let kk = 0.75 / bl.r; // eq. (1): I_O = 4mR²/3
        // Over the window: the smallest A_s (either side), the largest |ẍg| and
        // |g + ÿg|, the smallest N − (g + ÿg)/2 at θ = 0, θ̇ = 0 (all affine in
        // the forcing, which is linear between samples, so extremes are at the
        // window's ends and at samples), and the largest |dA_s/dt|.
        let (mut lo_min, mut ax_max, mut gy_max, mut n_margin, mut rate) =
            (f64::INFINITY, 0.0_f64, 0.0_f64, f64::INFINITY, 0.0_f64);
        let mut include = |ax: f64, ay: f64| {
            for s in [-1.0, 1.0] {
                let c = ph::rock_contact_sc(&bl, s, bl.sin_c, bl.cos_c, 0.0, ax, ay);
                // eq. (1) at θ = 0 on side s: ψ̈ = sθ̈ = −A_s
                lo_min = lo_min.min(-s * c.alpha);
                n_margin = n_margin.min(c.n - 0.5 * (bl.g + ay));
            }
            ax_max = ax_max.max(ax.abs());
            gy_max = gy_max.max((bl.g + ay).abs());
            (lo_min, ax_max, gy_max, n_margin)
        };
        let k0 = ((t / self.dt) as usize).min(n - 2);
        let at_start = self.segment(k0).at(t);
        include(at_start.0, at_start.1);
        for k in k0..(k0 + MAX_SAMPLES).min(n - 1) {
            let seg = self.segment(k);
            let tw = (k + 1) as f64 * self.dt;
            let (ax, ay) = seg.at(tw);
            let (lo_min, ax_max, gy_max, n_margin) = include(ax, ay);
            rate = rate.max(kk * (seg.v1.abs() * bl.sin_c + seg.a1.abs() * bl.cos_c));
            if lo_min <= 0.0 || n_margin <= 0.0 {
                // the ground can lift the block within the window, or the
                // pivot's normal force comes near 0 (bounds on N below)
                return false;
            }
            // A bounce leaving at u ≤ u0 on side s lasts τ, during which its
            // restoring acceleration stays within A* ± x of the value A* ≥ lo_min
            // at its start: x = rate·τ + δ, with δ = k ψm (|ẍg| + |g + ÿg|) the
            // change of eq. (1) over the bounce's height ψ ≤ ψm (|Δsin|,
            // |Δcos| ≤ ψm). First, while x ≤ lo_min/2: τ ≤ 2u/(A* − x) ≤
            // 4u0/lo_min and ψ ≤ u²/(2(A* − x)) ≤ u0²/lo_min, which bounds x by x0.
            let psi_m0 = u0 * u0 / lo_min;
            let x0 = rate * 4.0 * u0 / lo_min + kk * psi_m0 * (ax_max + gy_max);
            if x0 > 0.5 * lo_min {
                return false;
            }
            // Then, with x ≤ x0: τ ≤ 2u0/(lo_min − x0), ψ ≤ u0²/(2(lo_min − x0)).
            let psi_m = 0.5 * u0 * u0 / (lo_min - x0);
            let x = rate * 2.0 * u0 / (lo_min - x0) + kk * psi_m * (ax_max + gy_max);
            // it lands at most √((A* + x)/(A* − x)) ≤ √((lo_min + x)/(lo_min − x))
            // faster than it left, and the impact multiplies the speed by η
            let rho = eta * ((lo_min + x) / (lo_min - x)).sqrt();
            if rho >= 1.0 {
                // a longer window only widens the bounds
                return false;
            }
            // Σ τₙ ≤ Σ 2uₙ/(lo_min − x) with uₙ ≤ ρⁿ u0
            let t_cascade = 2.0 * u0 / ((lo_min - x) * (1.0 - rho));
            if t + t_cascade > tw {
                continue;
            }
            if psi_m > self.out.theta_max_over_theta_c * bl.theta_c {
                // the cascade might set the peak rotation: follow it
                return false;
            }
            // The pivot stays in compression: N (eq. (1)'s reactions) exceeds
            // (g + ÿg)/2 over the window at θ = 0, θ̇ = 0 by n_margin, and a
            // bounce changes it by at most R u0² (the centripetal term) plus
            // R (ψm |θ̈| + sinθc |Δθ̈|) ≤ 2 R k ψm (|ẍg| + |g + ÿg|).
            if n_margin <= bl.r * (u0 * u0 + 2.0 * kk * psi_m * (ax_max + gy_max)) {
                return false;
            }
            // The cascade's friction demand: the contact forces at θ = 0,
            // θ̇ = 0 on either side at its two ends.
            let k1 = (((t + t_cascade) / self.dt) as usize).clamp(k0, k);
            let ends = [at_start, self.segment(k1).at(t + t_cascade)];
            let mut demand = 0.0_f64;
            for (ax, ay) in ends {
                for s in [-1.0, 1.0] {
                    let c = ph::rock_contact_sc(&bl, s, bl.sin_c, bl.cos_c, 0.0, ax, ay);
                    demand = demand.max(c.f.abs() / c.n);
                }
            }
            self.out.mu_motion = self.out.mu_motion.max(demand);
            return true;
        }
        false
    }

    /// Both corners down, no velocity: rest at the current footprint.
    fn land_flat(&mut self, pose: FlightState) -> State {
        self.x_base = pose.x;
        State::Rest
    }

    // ---------------------------------------------------------------- bookkeeping

    fn note_theta(&mut self, state: &State) {
        let th = match state {
            State::Rest | State::Slide(_) => 0.0,
            State::Rock(r) => r.theta,
            State::SlideRock(r) => r.theta,
            State::Flight(f) => f.theta,
        };
        let ratio = (th.abs() / self.bl.theta_c).min(FRAC_PI_2 / self.bl.theta_c);
        self.out.theta_max_over_theta_c = self.out.theta_max_over_theta_c.max(ratio);
    }

    /// Tracks the block's slip: the offset of its footprint (or of the
    /// slipping pivot) from its initial place.
    fn note_slip(&mut self, state: &State) {
        let x = match state {
            State::Rest | State::Rock(_) => self.x_base,
            State::Slide(ss) => ss.x,
            State::SlideRock(sr) => sr.xp,
            State::Flight(_) => return,
        };
        self.out.slip_max = self.out.slip_max.max(x.abs());
        self.out.slip_final = x;
    }

    /// Mechanical energy per unit mass in the ground frame.
    fn energy(&self, state: &State) -> f64 {
        match state {
            State::Rest => 0.0,
            State::Slide(ss) => 0.5 * ss.v * ss.v,
            State::Rock(r) => {
                let [_, vx, y, vy] = ph::rock_kinematics(&self.bl, r.s, r.theta, r.omega);
                ph::energy(&self.bl, vx, vy, r.omega, y)
            }
            State::SlideRock(r) => {
                let [_, vx, y, vy] = ph::rock_kinematics(&self.bl, r.s, r.theta, r.omega);
                ph::energy(&self.bl, r.vp + vx, vy, r.omega, y)
            }
            State::Flight(f) => ph::energy(&self.bl, f.vx, f.vy, f.omega, f.y),
        }
    }

    fn audit(&mut self, state: &State) {
        if self.set.audit_energy {
            let e = self.energy(state);
            let r = e - self.e0 - self.work - self.jumps;
            self.resid = self.resid.max(r.abs());
            self.escale = self.escale.max(e.abs()).max(self.work.abs());
        }
    }

    fn push_row(&mut self, t: f64, state: &State, seg: &Segment, event: bool) {
        let Some(hist) = self.hist.as_deref_mut() else {
            return;
        };
        let bl = &self.bl;
        let (ax, ay) = seg.at(t);
        let row = match state {
            State::Rest => HistoryRow {
                t,
                mode: Mode::Rest,
                theta: 0.0,
                theta_dot: 0.0,
                x: self.x_base,
                x_dot: 0.0,
                y: 0.0,
                y_dot: 0.0,
                n: bl.g + ay,
                f: ax,
                event,
            },
            State::Rock(r) => {
                let [x, vx, y, vy] = ph::rock_kinematics(bl, r.s, r.theta, r.omega);
                let ph::RockContact { f, n, .. } =
                    ph::rock_contact(bl, r.s, r.theta, r.omega, ax, ay);
                HistoryRow {
                    t,
                    mode: Mode::Rock,
                    theta: r.theta,
                    theta_dot: r.omega,
                    x: self.x_base + x,
                    x_dot: vx,
                    y,
                    y_dot: vy,
                    n,
                    f,
                    event,
                }
            }
            State::Slide(ss) => HistoryRow {
                t,
                mode: Mode::Slide,
                theta: 0.0,
                theta_dot: 0.0,
                x: ss.x,
                x_dot: ss.v,
                y: 0.0,
                y_dot: 0.0,
                n: bl.g + ay,
                f: -self.fric.map_or(0.0, |f| f.1) * ss.sigma * (bl.g + ay),
                event,
            },
            State::SlideRock(r) => {
                let [x, vx, y, vy] = ph::rock_kinematics(bl, r.s, r.theta, r.omega);
                let mu_k = self.fric.map_or(0.0, |f| f.1);
                let a = ph::slide_rock_accel(bl, r.s, r.sigma, mu_k, r.theta, r.omega, ax, ay);
                HistoryRow {
                    t,
                    mode: Mode::SlideRock,
                    theta: r.theta,
                    theta_dot: r.omega,
                    x: r.xp + x,
                    x_dot: r.vp + vx,
                    y,
                    y_dot: vy,
                    n: a.n,
                    f: a.f,
                    event,
                }
            }
            State::Flight(f) => HistoryRow {
                t,
                mode: Mode::Flight,
                theta: f.theta,
                theta_dot: f.omega,
                x: f.x,
                x_dot: f.vx,
                y: f.y,
                y_dot: f.vy,
                n: 0.0,
                f: 0.0,
                event,
            },
        };
        hist.rows.push(row);
    }
}

type Vec2 = [bool; 2];

/// sinh x − x for |x| < 0.5 by its series (error < 1e-15 relative).
#[inline]
fn sinh_minus_x(x: f64) -> f64 {
    let x2 = x * x;
    x * x2 / 6.0
        * (1.0
            + x2 / 20.0
                * (1.0 + x2 / 42.0 * (1.0 + x2 / 72.0 * (1.0 + x2 / 110.0 * (1.0 + x2 / 156.0)))))
}

/// The first time in [t, t_end] at which f(s, ẍg, ÿg) > 0 for s = +1 or −1,
/// where f is linear in the (linear) forcing, so the crossing is exact.
/// Moves `t` to that time (or to t_end) and returns the side s.
fn first_exceedance(
    seg: &Segment,
    t: &mut f64,
    t_end: f64,
    f: impl Fn(f64, f64, f64) -> f64,
) -> Option<f64> {
    let (ax0, ay0) = seg.at(*t);
    let (ax1, ay1) = seg.at(t_end);
    let mut best: Option<(f64, f64)> = None;
    for s in [1.0, -1.0] {
        let (f0, f1) = (f(s, ax0, ay0), f(s, ax1, ay1));
        let tc = if f0 > 0.0 {
            Some(*t)
        } else if f1 > 0.0 {
            Some(*t + (t_end - *t) * (f0 / (f0 - f1)))
        } else {
            None
        };
        if let Some(tc) = tc
            && best.is_none_or(|(tb, _)| tc < tb)
        {
            best = Some((tc, s));
        }
    }
    *t = best.map_or(t_end, |(tc, _)| tc);
    best.map(|(_, s)| s)
}

/// ∫₀^T f(τ) dτ by 3-point Gauss–Legendre (exact for polynomials of degree ≤ 5).
#[inline]
fn gauss3(span: f64, f: impl Fn(f64) -> f64) -> f64 {
    let half = 0.5 * span;
    let x = 0.6f64.sqrt();
    half * (5.0 / 9.0 * f(half * (1.0 - x)) + 8.0 / 9.0 * f(half) + 5.0 / 9.0 * f(half * (1.0 + x)))
}

/// Keeps the earliest of the located events.
#[inline]
fn earliest(best: &mut Option<(f64, Event)>, te: Option<f64>, ev: Event) {
    if let Some(te) = te
        && best.is_none_or(|(tb, _)| te < tb)
    {
        *best = Some((te, ev));
    }
}
