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
//! corner within 1e-9·B of the ground is in contact. A flat landing, both
//! corners in contact and both approaching faster than ε·√(gR), is one
//! simultaneous impact (`impact::two_corner_impact`: u_n⁺ = −e u_n⁻ at each
//! corner, no slip at the middle of the base; Poisson's u⁺ = −e u⁻ of all
//! three contact velocities where that would add energy), taken when both normal
//! impulses come out ≥ 0 and it sticks; so a symmetric landing rebounds
//! straight up at e·v and never turns. Otherwise (a rock impact, whose pivot
//! does not approach; a pull at one corner; a slipping base under Coulomb
//! friction), while any contact corner approaches the ground, the
//! single-corner impact law is applied at the one approaching fastest
//! (sequential impacts), at most 64 times, after which the block is set
//! down flat and still.
//!
//! Cascade rule (`settle_cascades`; e = 0, and e > 0 below): after a rock
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
//! in `settles`. Its duration counts as time in rock, summed in closed form
//! on the ground frozen at its start: with the restoring acceleration
//! A(ψ) = A_s − c_s ψ on side s, a bounce leaving at u lasts
//! 2u/A_s + (2/3) c_s u³/A_s³ + O(u⁵) and lands at u, and bounce n leaves at
//! ηⁿu₀ on alternate sides, so T = 2u₀(1/A₀ + η/A₁)/(1 − η²) +
//! (2/3) u₀³ (c₀/A₀³ + η³c₁/A₁³)/(1 − η⁶) (within 1e-4 s of every impact
//! followed, on still ground from θc/2; capped at the bound above, inside
//! the window, so the block is at rest for at least that long).
//!
//! Under Coulomb friction (`cascade.rs`) the cascade is the same motion,
//! impulse for impulse, as long as nothing in it slips, since a sticking
//! impact gives the infinite-friction impulse and a stuck pivot the same
//! rock: its rock impacts strike at θ = 0, where the new corner moves
//! straight down, so each asks for eq. (8)'s μ_imp whatever its speed (the
//! rule needs μ_imp < μs); its bounces keep μs N − |F| > 0, bounded below
//! over the window like N (F and N move by at most R w² + 2Rkψm(|ẍg| +
//! |g + ÿg|) each, w the cascade's fastest speed); and the rest it is set to
//! cannot break into sliding within the window, |ẍg| < μs (g + ÿg). With
//! e > 0 (Newton's law) each rock impact of the cascade starts a bounce
//! series on the new corner, and the rule is tried only once the chatter
//! rule (below) has closed the first: the bounds then take in what a series
//! started at an impact of speed v ≤ v_top can do (`Run::series_bounds`, the
//! chatter rule's bounds per power of v): it ends before the block can rock
//! back, it changes rock about the new corner by |Δθ| ≤ c_θ v² and
//! |Δθ̇| ≤ c_ω v², so the next excursion leaves at most η_e = √((η +
//! c_ω v_top)² + 2A_hi c_θ) times as fast, which replaces η in ρ; and under
//! Coulomb friction its impacts stick. The series' friction demands are
//! taken, as the chatter rule takes them, at the window's two ends.
//!
//! Friction demand `mu_motion`: |F|/N at the end of every rock step with
//! N > 0. Steps that end beyond θc are held apart until a step ends within
//! θc again (then they count) or the run ends: a run that overturns leaves
//! out its final fall, where N → 0 and |F|/N grows without bound; a run
//! that does not keeps them all ([`Outcome::mu_motion`]).
//!
//! Chatter rule (`settle_cascades`, e > 0; infinite friction, or Coulomb
//! friction with Newton's law while nothing slips). With
//! e > 0 a rock impact starts a series of bounces on the new corner B: the
//! block flies, B lands, rebounds at e times its landing speed, and so on,
//! dozens of times, while the block rocks about B underneath. Take B's place
//! (x_B, y_B) and θ as coordinates; ρ = G − B, I_B = 4R²/3 (per unit mass).
//! The momentum conjugate to θ, p = Ḃ·ρ⊥ + I_B θ̇ (the angular momentum
//! about B), does not jump at an impulse applied at B, and obeys
//! ṗ = −∂V/∂θ − θ̇ Ḃ·ρ (V: gravity and the ground's inertial force, the
//! same in rock and flight), while θ̇ = (p − Ḃ·ρ⊥)/I_B. In rock Ḃ = 0: so the
//! series is rock about B from the state a plastic impact leaves, except for
//! what Ḃ adds. Let b = B − B₀ (B₀ where the series starts): each flight
//! k leaves at u_k with no tangential velocity (Newton's stick), lasts τ_k
//! and drifts ΔD_k = a_t τ_k²/2 (+ ȧ_t τ_k³/6) along the ground, a_t =
//! −ẍg − ω² r_x being B's tangential acceleration in flight, while B's height
//! traces a parabola with ∫ b_y dt = u_k τ_k²/6; the flight's ω is θ̇ + u r_x/I_B
//! (p is the rock's). Linearised about rock (δθ, δp), the series drives
//! I_B δθ̇ = δp − Ḃ·ρ′ and δṗ = −V_θθ δθ − θ̇ Ḃ·ρ + (Ḃ·ρ′)(Ḃ·ρ)/I_B; to third
//! order in u its effect is the integral of that drive plus one step of
//! rock's linearised motion. Applied at the drift's centroid t* = T − J/D
//! (D = Σ ΔD_k, J = ∫ D dt, T = Σ τ_k), which absorbs the drift's spread in
//! time to first order, with Y = Σ u_k τ_k²/6 the correction to rock about B
//! is
//!
//! ```text
//! I_B Δθ = ρ_y D − 2 θ̇ ρ_y Y
//! Δp     = −θ̇ ρ_x D + (θ̈ ρ_y + θ̇² ρ_x) Y + [Q + V_θθ ρ_x Y]/I_B
//! Q      = Σ [ρ_x ρ_y (u_k² τ_k − a_t² τ_k³)/3 − (ρ_x² − ρ_y²) a_t u_k τ_k²/6]
//! ```
//!
//! with ρ, θ̇, θ̈ those of rock about B at t*, V = (g + ÿg) ρ_y + ẍg ρ_x, and
//! the footprint moved by D. Each flight's own terms were checked against
//! exact flights (their residual falls as u⁴), and the closed series against
//! every bounce followed (its error falls as u⁴: at a rebound of 1e-2·√(gR),
//! 6e-8 rad after one series under ẍg = 0.1 g, where the second-order rule
//! applied at T was off by 1e-6 in θ̇). D, T and the sums are taken flight by
//! flight on the record's linear pieces, with the rock's own θ̇ and turn
//! during the series, until the rest lies in one sample, where they are
//! geometric in closed form to first order in the series' rates
//! (`geometric_sums`). The rule closes a bounce whose rebound u is below
//! 1e-3·√(gR) (`CLOSE_TOL`), making the impact plastic (the energy the
//! series would lose, the whole of B's normal motion), and applies the
//! correction at once, carried back from t* to the closing impact along
//! rock's linearised motion to second order in t* − t0 (`Run::close_series`;
//! what this neglects is of fifth order), so rock runs on with no stop at
//! t*. The rule is tried inside a flight's plain bounces as well as in the
//! event loop; after a try fails on a corner, the next waits until the
//! rebound has halved. The rule applies only where bounds over the
//! coming samples prove the series converges before anything else happens
//! (`Run::chatter_settles`): B's fall stays positive, lo = min(g + ÿg) −
//! ω_max² R > 0, with ω_max bounding every ω of the series (ω_p + θ̈_max·T +
//! k_w u, θ̈_max from eq. (1)); within a flight a strays by at most x, so
//! each flight lands at most √((lo + x)/(lo − x)) faster than it left and
//! the rebounds shrink by ρ = e√((lo + x)/(lo − x)) < 1; the series, at most
//! 2u/((lo − x)(1 − ρ)) long, fits in the window; rock about B stays on its
//! side and below θc over it (a concave bound on ψ and the series' own
//! excursion k_w h, so the old corner stays off the ground); and N of rock
//! about B stays positive. Otherwise every bounce is followed. That includes
//! every series the old corner's landing interrupts: near rest on quiet
//! ground a series lasts 3e sin²θc/(2(1 − e)η) of the time rock about B takes
//! to return to θ = 0 (η = 1 − 1.5 sin²θc, the plastic impact's θ̇ ratio;
//! about 0.9 at H/B 4 and 4 at H/B 2 for e = 0.9), and where it outlasts
//! that, B is still bouncing when the old corner lands, an effect of first
//! order in B's rebound that no closure at the series' end can carry. A closed
//! series counts one impact and one in `settles`; its later impacts' friction
//! demand (all with the same impulse ratio, since they scale with u) is
//! taken from one of them; its flights are not counted in `flights`.
//! Under Coulomb friction the series is that of infinite friction as long
//! as every impact sticks and the rock about B does not slip: the closing
//! impact and its plastic twin must stick, μs N − |F| of rock about B is
//! bounded below over the window as N is, and the later impacts, each
//! meeting the ground after a flight of τ ≤ 2u/(lo − x) from no tangential
//! velocity (Newton's stick), arrive with |u_t/u_n| ≤ ζ = 2|a_t|max/(lo − x)
//! ·√((lo + x)/(lo − x)), so their sticking impulse asks for at most (c ζ +
//! |b|(1 + e))/(a(1 + e) − |b| ζ) < μs (K⁻¹ = [[a, b], [b, c]] at its worst
//! as the corner turns over the series).
//!
//! Rock-impact rule (`rock_impact`): by default a rock impact with e > 0 is
//! resolved by the impact law in full (the block flies and rings down on the
//! new corner). `rock_impact = "rock"` instead keeps the block rocking on the
//! new corner with θ̇2 = δ(e)θ̇1 and no flight (infinite friction only): a
//! reading of the paper's program, not the physics
//! ([`RockImpact`](super::settings::RockImpact)).
//!
//! Lift-off rule under infinite friction: when N reaches 0 in rock, the pivot
//! is released into flight only if it would then rise (q < 0, see
//! [`RockContact::q`](super::physics::RockContact::q)); otherwise
//! the pivot is held (a tensile contact, counted in `liftoff_holds`) until
//! N > 0 again or the release becomes consistent.
//!
//! The driver's own files, one per mode and concern: `rest`, `slide` (slide
//! and slide-rock), `rock`, `flight`; `events` (reset maps), `impacts`
//! (sequential impacts), `cascade` (the cascade rule), `chatter` (the chatter
//! rule);
//! `stepping` (the Dormand–Prince
//! loop shared by rock and slide-rock); `bookkeeping` (peaks, slip, energy
//! audit, history rows).

mod bookkeeping;
mod cascade;
mod chatter;
mod events;
mod flight;
mod impacts;
mod rest;
mod rock;
mod slide;
mod stepping;

use super::block::Block;
use super::history::History;
use super::impact::Velocity;
use super::physics as ph;
use super::settings::{Analysis, Friction, Initial, Integrator, Model, SolverSettings};
use crate::error::{Error, Result};
use crate::motion::Record;
use crate::outcome::{Mode, Outcome};

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

/// The ground contact's friction as the driver reads it: static and kinetic
/// coefficients, both infinite under infinite friction (the contact never
/// slips) and finite under Coulomb friction (`Analysis::validate` sees to
/// it), so a rule that needs μs or μk reads it without unwrapping, and one
/// that differs between the two models asks [`Grip::finite`].
#[derive(Clone, Copy, Debug, PartialEq)]
struct Grip {
    /// Static coefficient μs (∞: infinite friction).
    mu_s: f64,
    /// Kinetic coefficient μk (∞: infinite friction).
    mu_k: f64,
}

impl Grip {
    /// The coefficients of an analysis' friction model.
    fn of(friction: Friction) -> Grip {
        match friction {
            Friction::Infinite => Grip {
                mu_s: f64::INFINITY,
                mu_k: f64::INFINITY,
            },
            Friction::Coulomb { mu_s, mu_k } => Grip { mu_s, mu_k },
        }
    }

    /// True under Coulomb friction: contacts can slip.
    #[inline]
    fn finite(&self) -> bool {
        self.mu_s.is_finite()
    }
}

/// A bounce whose rebound is below `CLOSE_TOL`·√(gR) may close its series.
/// The closure's error is fourth order in the rebound (measured over 100
/// records × H/B 2, 4, 6 at 0.6 g and e = 0.9: the median |Δθmax/θc|
/// against every bounce followed is 3e-11 at 1e-3, as between the two
/// integrators, and 4e-9 at 3e-3).
const CLOSE_TOL: f64 = 1e-3;

/// An impact at which the chatter rule is tried: a bounce of one corner whose
/// Newton rebound is slow enough to close its series (`Run::chatter_due`),
/// with what the impact leaves under Newton's law and made plastic.
#[derive(Clone, Copy, Debug)]
struct ChatterImpact {
    /// Time of the impact (s).
    t: f64,
    /// The block's rotation θ at it (rad; 0 at a rock impact).
    theta: f64,
    /// The corner's side (±1).
    side: f64,
    /// The corner's offset (r_x, r_y) from G (m).
    rx: f64,
    ry: f64,
    /// The block's velocity after the impact under Newton's law.
    newton: Velocity,
    /// The corner's rebound (normal velocity) after it (m/s).
    u1: f64,
    /// The block's velocity after the same impact made plastic (rock about
    /// the corner).
    plastic: Velocity,
}

/// A try of the chatter rule that succeeded inside a flight ([`Run::bounce`]),
/// kept for the event loop's impact at the same instant.
#[derive(Clone, Copy, Debug)]
struct ChatterTry {
    /// Time of the impact (s).
    t: f64,
    /// The corner's side (±1).
    side: f64,
    /// What the rule found.
    chatter: Chatter,
}

/// What a closed series leaves to apply: rock about the corner from the
/// plastic impact, corrected by the series' sums at the drift's centroid
/// (carried back to the impact by [`Run::close_series`]).
#[derive(Clone, Copy, Debug)]
struct SeriesEnd {
    /// The centroid of the drift t* (s).
    t: f64,
    /// The series' sums.
    sums: SeriesSums,
}

/// What a closed series leaves to the solver besides the plastic impact.
#[derive(Clone, Copy, Debug)]
struct Chatter {
    /// Friction demand |P_t/P_n| of the series' later impacts.
    demand: f64,
    /// The same, as the paper's eq. (5) evaluates it.
    demand_eq5: f64,
    /// The series' sums and the drift's centroid, for [`Run::close_series`].
    end: SeriesEnd,
}

/// Sums over the flights k of a bounce series (module documentation): each
/// flight leaves at uₖ, lasts τₖ and drifts ΔDₖ, under the corner's
/// tangential acceleration a_t.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct SeriesSums {
    /// Duration Σ τₖ (s).
    duration: f64,
    /// Drift D = Σ ΔDₖ (m).
    d: f64,
    /// ∫ D(t) dt over the series (m s): D (T − t*) for the centroid t*.
    j: f64,
    /// Σ uₖ τₖ² (m s).
    u_tau2: f64,
    /// Σ uₖ² τₖ (m² s⁻¹).
    u2_tau: f64,
    /// Σ a_t² τₖ³ (m² s⁻¹).
    at2_tau3: f64,
    /// Σ a_t uₖ τₖ² (m² s⁻¹).
    at_u_tau2: f64,
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
/// ÿg = v0 + v1 (t − t0). Shared by the single block's driver and the
/// stack's.
#[derive(Clone, Copy, Debug)]
pub(in crate::solver) struct Segment {
    t0: f64,
    a0: f64,
    a1: f64,
    v0: f64,
    v1: f64,
}

impl Segment {
    /// The interval from sample `k` to `k + 1` of a record's acceleration
    /// `acc` (and vertical acceleration `acc_v`, zero without one),
    /// sampled every `dt`: linear between samples. Past the record's last
    /// sample the ground is still (the free motion after the record).
    #[inline]
    pub(in crate::solver) fn of(acc: &[f64], acc_v: Option<&[f64]>, dt: f64, k: usize) -> Segment {
        let t0 = k as f64 * dt;
        if k + 1 >= acc.len() {
            return Segment {
                t0,
                a0: 0.0,
                a1: 0.0,
                v0: 0.0,
                v1: 0.0,
            };
        }
        let (a0, a1) = (acc[k], (acc[k + 1] - acc[k]) / dt);
        let (v0, v1) = match acc_v {
            Some(v) => (v[k], (v[k + 1] - v[k]) / dt),
            None => (0.0, 0.0),
        };
        Segment { t0, a0, a1, v0, v1 }
    }

    #[inline]
    pub(in crate::solver) fn at(&self, t: f64) -> (f64, f64) {
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
    Ok(run.tally.out)
}

/// One analysis being solved: what it is given, what it accumulates, the
/// rules' thresholds and memory, and the two quantities carried from step to
/// step besides the mode's own state ([`State`]).
struct Run<'a> {
    given: Given<'a>,
    tally: Tally<'a>,
    rules: Rules,
    /// Step size carried between steps (s).
    h: f64,
    /// Horizontal offset of the block's footprint from its initial place (m).
    x_base: f64,
}

/// What a run is given: the block and its contact, the settings and the
/// record. Read-only while it runs.
struct Given<'a> {
    bl: Block,
    /// Coefficient of restitution e.
    e: f64,
    /// The ground contact's friction coefficients.
    fric: Grip,
    set: &'a SolverSettings,
    /// The record's horizontal acceleration ẍg (m/s²), sampled every `dt` (s),
    /// and its vertical acceleration ÿg, if it has one.
    acc: &'a [f64],
    acc_v: Option<&'a [f64]>,
    dt: f64,
    /// Samples of the record followed by those of still ground up to the
    /// free-motion cap ([`SolverSettings::free_motion_max`]), set once.
    samples: usize,
    /// Initial conditions.
    init: Initial,
}

/// What a run accumulates: the outcome, the history (when asked for), the
/// energy audit and the peak friction demand not yet counted.
struct Tally<'a> {
    out: Outcome,
    hist: Option<&'a mut History>,
    audit: Audit,
    /// The peak friction demand |F|/N of the rock steps that ended beyond θc
    /// since the last one that ended within θc (0 if none). It joins
    /// `mu_motion` when the block comes back within θc or the run ends
    /// without overturning; an overturned run drops it, so that its
    /// `mu_motion` leaves out the final fall, where N → 0 and F/N grows
    /// without bound (to 1e13–1e16).
    mu_beyond: f64,
}

/// The energy audit (`audit_energy`), per unit mass: E − E0 should equal
/// the ground's work plus the jumps at events.
struct Audit {
    /// Energy at t = 0 (J/kg).
    e0: f64,
    /// Accumulated work of the ground (and of friction) (J/kg).
    work: f64,
    /// Accumulated energy jumps at events (J/kg).
    jumps: f64,
    /// Largest |E − E0 − W − jumps| seen (J/kg).
    resid: f64,
    /// The energy scale the residual is reported against (J/kg); also the
    /// tolerance scale of the integrated work.
    escale: f64,
}

/// The rules' thresholds, fixed at the start, and their memory: what one
/// rule leaves for another, or for itself, at a later instant.
struct Rules {
    /// Ring-down velocity threshold ε√(gR) (m/s).
    v_settle: f64,
    /// Rebound below which the chatter rule may close a bounce series (m/s).
    v_close: f64,
    /// Contact distance of the two-contact rule (m).
    h_touch: f64,
    /// |ẍg| below which rest cannot break (the smaller of the rocking and
    /// sliding thresholds, less a margin for rounding); `None` when rest is
    /// decided sample by sample (vertical ground motion, or a history).
    quiet: Option<f64>,
    /// After a failed try of the chatter rule, when it may try again.
    chatter_retry: Option<ChatterRetry>,
    /// A try of the chatter rule that succeeded inside a flight
    /// ([`Run::bounce`]), for the event loop's impact at the same instant.
    chatter_tried: Option<ChatterTry>,
    /// The impact at which the chatter rule last closed a bounce series
    /// started by a rock impact, for the cascade rule at the same instant.
    closed_series: Option<ChatterImpact>,
    /// The last release of a rock pivot into flight.
    released: Option<Released>,
    /// The time rest was last left, if it was.
    left_rest: Option<f64>,
    /// A time at which rest was left and re-entered: the mode it broke into
    /// found no motion (a threshold met within rounding), so rest does not
    /// break again at that instant (it would loop there).
    stuck_at: Option<f64>,
}

/// After a failed try of the chatter rule on a corner: the next try there
/// waits until the rebound is below `below`.
#[derive(Clone, Copy, Debug)]
struct ChatterRetry {
    /// The corner's side (±1).
    side: f64,
    /// Half the rebound of the failed try (m/s).
    below: f64,
}

/// A release of a rock pivot into flight, for the landing at the same
/// instant that would undo it.
#[derive(Clone, Copy, Debug)]
struct Released {
    /// Time of the release (s).
    t: f64,
    /// The rock state released.
    rock: RockState,
}

impl<'a> Run<'a> {
    fn new(
        an: &Analysis,
        rec: &'a Record,
        set: &'a SolverSettings,
        hist: Option<&'a mut History>,
    ) -> Self {
        let bl = an.block;
        let fric = Grip::of(an.friction);
        let quiet = (rec.acc_v.is_none() && hist.is_none()).then(|| {
            // rest breaks when |ẍg| > g tanθc (eq. (1) at θ = 0), or slides
            // when |ẍg| > μs g; the margin covers the rounding of the
            // interpolated forcing at a sample's end
            (bl.sin_c * bl.g / bl.cos_c).min(fric.mu_s * bl.g) * (1.0 - 1e-9)
        });
        Run {
            given: Given {
                bl,
                e: an.restitution,
                fric,
                set,
                acc: &rec.acc,
                acc_v: rec.acc_v.as_deref(),
                dt: rec.dt,
                samples: rec.acc.len() + set.free_samples(rec.dt),
                init: an.initial,
            },
            tally: Tally {
                out: Outcome::default(),
                hist,
                audit: Audit {
                    e0: 0.0,
                    work: 0.0,
                    jumps: 0.0,
                    resid: 0.0,
                    escale: bl.g * bl.r * (1.0 - bl.cos_c),
                },
                mu_beyond: 0.0,
            },
            rules: Rules {
                v_settle: set.settle_tol * (bl.g * bl.r).sqrt(),
                v_close: CLOSE_TOL * (bl.g * bl.r).sqrt(),
                h_touch: 1e-9 * bl.b,
                // (a threshold of 0, μs = 0, breaks rest at every sample)
                quiet: quiet.filter(|&q| q > 0.0),
                chatter_retry: None,
                chatter_tried: None,
                closed_series: None,
                released: None,
                left_rest: None,
                stuck_at: None,
            },
            h: rec.dt * 0.25,
            x_base: 0.0,
        }
    }

    #[inline]
    fn segment(&self, k: usize) -> Segment {
        Segment::of(self.given.acc, self.given.acc_v, self.given.dt, k)
    }

    /// Past the record (still ground), whether `state` is final: rest, or a
    /// flat slide with μk = 0, which nothing can stop or tip (the slip then
    /// grows without bound; it is reported at the record's end).
    fn settled(&self, state: &State) -> bool {
        match state {
            State::Rest => true,
            State::Slide(_) => self.given.fric.finite() && self.given.fric.mu_k == 0.0,
            _ => false,
        }
    }

    /// Samples of the record and of still ground after it ([`Given::samples`]).
    #[inline]
    fn samples(&self) -> usize {
        self.given.samples
    }

    fn initial_state(&self) -> State {
        let (th, om) = (self.given.init.theta, self.given.init.theta_dot);
        if self.given.init.y_dot > 0.0 {
            let i = self.given.init;
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
        let n_rec = self.given.acc.len();
        let n = self.samples();
        let mut state = self.initial_state();
        match state {
            State::Rest => {}
            State::Flight(_) => {
                self.tally.out.moved = true;
                self.tally.out.flights += 1;
            }
            State::Rock(_) | State::Slide(_) | State::SlideRock(_) => self.tally.out.moved = true,
        }
        self.tally.audit.e0 = self.energy(&state);
        let mut k = 0usize;
        let mut t = 0.0;
        let seg0 = self.segment(0);
        self.push_row(t, &state, &seg0, false);
        self.note_theta(&state);
        while k + 1 < n {
            if k + 1 >= n_rec && self.settled(&state) {
                break;
            }
            if matches!(state, State::Rest)
                && let Some(quiet) = self.rules.quiet
            {
                // Fast-forward over samples where the ground is too weak, at both
                // ends, to break rest (the forcing is linear in between).
                let k0 = k;
                if self.given.acc[k].abs() < quiet {
                    while k + 1 < n_rec && self.given.acc[k + 1].abs() < quiet {
                        k += 1;
                    }
                }
                if k > k0 {
                    let t_start = t;
                    t = k as f64 * self.given.dt;
                    self.tally.out.time_in_mode[Mode::Rest.index()] += t - t_start;
                    continue;
                }
            }
            let mut seg = self.segment(k);
            let mut t_end = (k + 1) as f64 * self.given.dt;
            let mut t_start = t;
            let mode = state.mode();
            let event = match &mut state {
                State::Rest => {
                    // Shenton (1996): from rest a block slides if μs < B/H and rocks if
                    // μs > B/H. At μs = B/H both thresholds coincide, and a block that
                    // starts to tip needs F/N rising above B/H at once (d(F/N)/dẍg = 1/4g
                    // > 0 at θ = 0), so it slips flat: the tie slides.
                    // A block coming to rest (after a landing) while |ẍg| already
                    // exceeds μs (g + ÿg) cannot stay stuck, nor rock on a stuck
                    // corner: it slides.
                    let mu_s = self.given.fric.mu_s;
                    if self.given.fric.finite()
                        && (mu_s <= self.given.bl.b / self.given.bl.h
                            || self.slide_exceeded(&seg, t, mu_s))
                    {
                        self.rest_slide(&seg, &mut t, t_end, mu_s)
                    } else {
                        self.rest(&seg, &mut t, t_end)
                    }
                }
                State::Slide(ss) => self.slide(ss, &seg, &mut t, t_end),
                State::SlideRock(sr) => {
                    if self.given.set.audit_energy {
                        self.slide_rock::<5>(sr, &seg, &mut t, t_end)?
                    } else {
                        self.slide_rock::<4>(sr, &seg, &mut t, t_end)?
                    }
                }
                State::Rock(rs) => match (self.given.set.model, self.given.set.integrator) {
                    (Model::Linear, _) => self.rock_linear(rs, &seg, &mut t, t_end),
                    (Model::Nonlinear, Integrator::Taylor) => {
                        // The samples of rock that end without an event are
                        // taken one after another here: after such a sample,
                        // with no history and no energy audit, the loop below
                        // only counts its time and moves on to the next.
                        let quick = self.tally.hist.is_none() && !self.given.set.audit_energy;
                        loop {
                            let ev = self.rock_taylor(rs, &seg, &mut t, t_end)?;
                            if ev.is_some() || !quick || k + 2 >= n {
                                break ev;
                            }
                            self.tally.out.time_in_mode[mode.index()] += t - t_start;
                            t = t_end;
                            k += 1;
                            seg = self.segment(k);
                            t_end = (k + 1) as f64 * self.given.dt;
                            t_start = t;
                        }
                    }
                    (Model::Nonlinear, Integrator::Dopri5) if self.given.set.audit_energy => {
                        self.rock_nonlinear::<3>(rs, &seg, &mut t, t_end)?
                    }
                    (Model::Nonlinear, Integrator::Dopri5) => {
                        self.rock_nonlinear::<2>(rs, &seg, &mut t, t_end)?
                    }
                },
                State::Flight(fs) => self.flight(fs, &seg, &mut t, t_end),
            };
            self.tally.out.time_in_mode[mode.index()] += t - t_start;
            match event {
                None => {
                    t = t_end;
                    k += 1;
                    if self.tally.hist.is_some() {
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
                    self.tally.out.stats.events += 1;
                    if self.tally.out.stats.events > self.given.set.max_events {
                        return Err(Error::Solver {
                            time: t,
                            message: format!(
                                "more than {} events (max_events)",
                                self.given.set.max_events
                            ),
                        });
                    }
                    self.audit(&state);
                    self.push_row(t, &state, &seg, true);
                    let before = if self.given.set.audit_energy {
                        self.energy(&state)
                    } else {
                        0.0
                    };
                    let from = state.mode();
                    state = self.handle(ev, state, t)?;
                    let to = state.mode();
                    if from != to {
                        self.tally.out.transitions[from.index()][to.index()] += 1;
                        if from == Mode::Rest {
                            self.rules.left_rest = Some(t);
                        } else if to == Mode::Rest && self.rules.left_rest == Some(t) {
                            self.rules.stuck_at = Some(t);
                        }
                    }
                    self.note_slip(&state);
                    if self.given.set.audit_energy {
                        self.tally.audit.jumps += self.energy(&state) - before;
                    }
                    self.note_theta(&state);
                    self.push_row(t, &state, &seg, true);
                    if self.tally.out.overturned {
                        break;
                    }
                }
            }
        }
        if self.tally.out.end_time > t {
            // a cascade settled at rest ends after the loop's last instant
            self.tally.out.time_in_mode[Mode::Rest.index()] += self.tally.out.end_time - t;
            t = self.tally.out.end_time;
            if self.tally.hist.is_some() {
                let seg = self.segment(k);
                self.push_row(t, &state, &seg, false);
            }
        }
        self.tally.out.end_time = t;
        if n > n_rec && !self.tally.out.overturned && !self.settled(&state) {
            return Err(Error::Solver {
                time: t,
                message: format!(
                    "still in {} motion {} s after the record's end (free_motion_max): \
                     no decided state",
                    state.mode().name(),
                    self.given.set.free_motion_max
                ),
            });
        }
        if !self.tally.out.overturned {
            // the last excursion beyond θc came back (or the record ended)
            self.tally.out.mu_motion = self.tally.out.mu_motion.max(self.tally.mu_beyond);
        }
        if self.given.set.audit_energy {
            self.tally.out.energy_residual = Some(self.tally.audit.resid / self.tally.audit.escale);
        }
        Ok(())
    }
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
