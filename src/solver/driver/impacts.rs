//! Sequential corner impacts and the choice of the mode after them, and the
//! chatter rule's place in them (see the driver's module documentation;
//! the cascade rule is in `cascade.rs`).

use super::{
    Chatter, ChatterImpact, ChatterRetry, FlightState, Grip, RockState, Run, SlideState, State,
};
use crate::solver::impact::{self, ImpactLaw, ImpactResult, Velocity};
use crate::solver::physics as ph;

impl Run<'_> {
    /// Sequential corner impacts starting with corner `side`, then the choice
    /// of the next mode (rest, rock or flight).
    pub(super) fn impacts(&mut self, t: f64, pose: FlightState, side: f64) -> State {
        let bl = self.given.bl;
        let mut vel = Velocity {
            vx: pose.vx,
            vy: pose.vy,
            omega: pose.omega,
        };
        // the pose is fixed during the impacts: one sine and cosine (exactly
        // (0, 1) at θ = 0, where a rock impact happens)
        let (sn, cs) = ph::sin_cos_small(pose.theta);
        let offset = |sd: f64| bl.corner_offset_sc(sd, sn, cs);
        let touching: [bool; 2] =
            [-1.0, 1.0].map(|sd| bl.h + pose.y + offset(sd).1 <= self.rules.h_touch);
        let mut next = Some(side);
        if touching == [true, true] && self.flat_landing(t, &mut vel, offset(-1.0), offset(1.0)) {
            // both corners struck at once and the two-contact impact applied
            next = None;
        }
        let mut count = 0;
        // the end of a bounce series closed by the chatter rule
        let mut series_end = None;
        while let Some(sd) = next {
            let (rx, ry) = offset(sd);
            let hit = |e: f64| self.hit(&vel, rx, ry, e);
            let (mut r, mut demand) = hit(self.given.e);
            let mut e_applied = self.given.e;
            let un_after = impact::point_velocity(&r.after, rx, ry).1;
            if self.given.e > 0.0 && un_after > 0.0 && un_after <= self.rules.v_settle {
                // ring-down: a rebound below the threshold is plastic
                (r, demand) = hit(0.0);
                e_applied = 0.0;
                self.tally.out.settles += 1;
            } else if un_after > 0.0
                && count == 0
                && self.chatter_due(sd, un_after)
                && (pose.theta == 0.0 || !touching[if sd < 0.0 { 1 } else { 0 }])
            {
                // the chatter rule: close the series of bounces on this corner
                // with this impact made plastic, its sums carried into the rock
                // state (`close_series`)
                let (plastic, plastic_demand) = hit(0.0);
                if self.sticks(demand)
                    && self.sticks(plastic_demand)
                    && let imp = (ChatterImpact {
                        t,
                        theta: pose.theta,
                        side: sd,
                        rx,
                        ry,
                        newton: r.after,
                        u1: un_after,
                        plastic: plastic.after,
                    })
                    && let Some(ch) = self.try_chatter(&imp)
                {
                    self.tally.out.mu_impact = self.tally.out.mu_impact.max(demand).max(ch.demand);
                    self.tally.out.mu_impact_eq5 = self
                        .tally
                        .out
                        .mu_impact_eq5
                        .max(impact::eq5_mu(&bl, &vel, rx, ry, self.given.e))
                        .max(ch.demand_eq5);
                    series_end = Some((sd, ch.end));
                    if pose.theta == 0.0 {
                        // a rock impact: for the cascade rule
                        self.rules.closed_series = Some(imp);
                    }
                    (r, demand) = (plastic, plastic_demand);
                    e_applied = 0.0;
                    self.tally.out.settles += 1;
                }
            }
            self.note_impact(t, &vel, &r, demand, rx, ry, e_applied);
            vel = r.after;
            count += 1;
            if count >= 64 {
                // no convergence of sequential impacts: set the block down flat
                self.tally.out.settles += 1;
                return self.land_flat(pose);
            }
            // the contact corner approaching fastest, if any
            next = None;
            let mut worst = -self.rules.v_settle;
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
                impact::point_velocity(&vel, rx, ry).1 <= self.rules.v_settle
            }
        });
        match staying {
            [true, true] => {
                if self.given.fric.finite() && vel.vx.abs() > self.rules.v_settle {
                    // flat on both corners, still moving sideways: slide
                    let sigma = vel.vx.signum();
                    if self.given.fric.mu_k > bl.b / bl.h {
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
                    self.tally.out.settles += 1;
                }
                self.land_flat(pose)
            }
            [true, false] | [false, true] => {
                let pivot = if staying[0] { -1.0 } else { 1.0 };
                let s = -pivot;
                if self.given.fric.finite() {
                    let (rx, ry) = offset(pivot);
                    let ut = impact::point_velocity(&vel, rx, ry).0;
                    if ut.abs() > self.rules.v_settle {
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
                match series_end {
                    Some((sd, end)) if sd == pivot => State::Rock(self.close_series(t, rs, &end)),
                    _ => State::Rock(rs),
                }
            }
            [false, false] => {
                self.tally.out.flights += 1;
                State::Flight(FlightState {
                    vx: vel.vx,
                    vy: vel.vy,
                    omega: vel.omega,
                    ..pose
                })
            }
        }
    }

    /// True if a bounce of corner `side` rebounding at `u` is one the chatter
    /// rule tries to close: the rule applies (e in (0, 1); infinite friction,
    /// or Coulomb friction with Newton's impact law, under which the series
    /// is the same while its impacts stick), the rebound is below
    /// `CLOSE_TOL`·√(gR), and, after a try on this corner failed, it has
    /// halved since.
    #[inline]
    pub(super) fn chatter_due(&self, side: f64, u: f64) -> bool {
        self.given.set.settle_cascades
            && (!self.given.fric.finite() || self.given.set.impact == ImpactLaw::Newton)
            && self.given.e > 0.0
            && self.given.e < 1.0
            && u <= self.rules.v_close
            && self
                .rules
                .chatter_retry
                .is_none_or(|r| r.side != side || u <= r.below)
    }

    /// A try of the chatter rule at the impact `imp` ([`Run::chatter_settles`]),
    /// or the result `bounce` already found for this very impact. After a
    /// failure the next try on this corner waits until the rebound has halved
    /// (the bounds need a shorter series); a success clears that wait. (The
    /// caller builds `imp` only for a try, by value from its impact results:
    /// a reference to them would keep them in memory on every bounce.)
    pub(super) fn try_chatter(&mut self, imp: &ChatterImpact) -> Option<Chatter> {
        let tried = match self.rules.chatter_tried.take() {
            Some(tried) if tried.t == imp.t && tried.side == imp.side => Some(tried.chatter),
            _ => self.chatter_settles(imp),
        };
        self.rules.chatter_retry = if tried.is_some() {
            None
        } else {
            Some(ChatterRetry {
                side: imp.side,
                below: 0.5 * imp.u1,
            })
        };
        tried
    }

    /// True if an impact asking for friction `demand` (|P_t/P_n| of the
    /// sticking impulse) sticks: always under infinite friction, and under
    /// Coulomb friction if demand ≤ μs, with a hair of margin so that the test
    /// holds whatever the rounding of `corner_impact_friction`'s own.
    #[inline]
    pub(super) fn sticks(&self, demand: f64) -> bool {
        !self.given.fric.finite() || demand <= self.given.fric.mu_s * (1.0 - 1e-12)
    }

    /// One impact of the corner at offset (rx, ry) from G with restitution
    /// `e`, by the analysis' impact law and friction: the result and the
    /// friction needed to prevent sliding during it.
    // (always inlined: its result, returned through memory, would be stored
    // field by field and read back in pairs, which stalls store forwarding)
    #[inline(always)]
    pub(super) fn hit(&self, vel: &Velocity, rx: f64, ry: f64, e: f64) -> (ImpactResult, f64) {
        let law = self.given.set.impact;
        let Grip { mu_s, mu_k } = self.given.fric;
        if self.given.fric.finite() {
            impact::corner_impact_friction(&self.given.bl, vel, rx, ry, e, law, mu_s, mu_k)
        } else {
            let r = impact::corner_impact(&self.given.bl, vel, rx, ry, e, law);
            (r, r.friction_demand())
        }
    }

    /// Counts an impact at `t` of the corner at (rx, ry), applied with
    /// restitution `e_applied` to the velocity `vel` with result `r`, and
    /// notes its friction demand, eq. (5)'s, and any energy it gained.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub(super) fn note_impact(
        &mut self,
        t: f64,
        vel: &Velocity,
        r: &ImpactResult,
        demand: f64,
        rx: f64,
        ry: f64,
        e_applied: f64,
    ) {
        let bl = &self.given.bl;
        self.tally.out.impacts += 1;
        self.tally.out.first_impact_time.get_or_insert(t);
        // friction needed to prevent sliding during this impact
        self.tally.out.mu_impact = self.tally.out.mu_impact.max(demand);
        // the same, as the paper's eq. (5) evaluates it
        let eq5 = impact::eq5_mu(bl, vel, rx, ry, e_applied);
        self.tally.out.mu_impact_eq5 = self.tally.out.mu_impact_eq5.max(eq5);
        let t_before = bl.kinetic(vel.vx, vel.vy, vel.omega);
        if r.delta_kinetic > 1e-12 * t_before.max(f64::MIN_POSITIVE) {
            self.tally.out.energy_gains += 1;
        }
    }

    /// A flat landing: both corners touching and both approaching the ground
    /// faster than the ring-down threshold. Applies the simultaneous
    /// two-corner impact ([`impact::two_corner_impact`]) to `vel` and returns
    /// true when it is an impact (both normal impulses ≥ 0) that sticks;
    /// otherwise leaves `vel` alone for the sequential rule (one corner's
    /// impulse would pull, or under Coulomb friction the base would slip).
    /// Rebounds below the threshold are plastic (ring-down rule).
    fn flat_landing(
        &mut self,
        t: f64,
        vel: &mut Velocity,
        left: (f64, f64),
        right: (f64, f64),
    ) -> bool {
        let v_settle = self.rules.v_settle;
        let approaching = |(rx, ry): (f64, f64)| impact::point_velocity(vel, rx, ry).1 < -v_settle;
        if !approaching(left) || !approaching(right) {
            // e.g. a rock impact: the pivot does not approach (Housner's rule)
            return false;
        }
        let bl = self.given.bl;
        let law = self.given.set.impact;
        let mut e = self.given.e;
        // simultaneous Newton restitution at both corners (physics.md, two-contact rule)
        let mut r = impact::two_corner_impact(&bl, vel, left, right, e, law);
        let rebound = |r: &impact::TwoCornerImpact, (rx, ry): (f64, f64)| {
            impact::point_velocity(&r.after, rx, ry).1
        };
        if e > 0.0 && rebound(&r, left).max(rebound(&r, right)) <= v_settle {
            // ring-down: a rebound below the threshold is plastic
            e = 0.0;
            r = impact::two_corner_impact(&bl, vel, left, right, e, law);
            self.tally.out.settles += 1;
        }
        if r.delta_kinetic > 0.0 {
            // Newton's targets gained energy (u_t⁻ ≠ 0 couples into the normals):
            // Poisson's u⁺ = −e u⁻ at all three contact velocities, ΔT = −(1 − e²)T⁻
            r = impact::two_corner_impact(&bl, vel, left, right, e, ImpactLaw::Energetic);
        }
        let demand = r.friction_demand();
        if r.p_left < 0.0 || r.p_right < 0.0 || !self.sticks(demand) {
            if e != self.given.e {
                self.tally.out.settles -= 1;
            }
            return false;
        }
        let out = &mut self.tally.out;
        out.impacts += 2;
        out.first_impact_time.get_or_insert(t);
        out.mu_impact = out.mu_impact.max(demand);
        // eq. (5) of the two-corner sticking impulse is its |P_t/P_n|
        out.mu_impact_eq5 = out.mu_impact_eq5.max(demand);
        let t_before = bl.kinetic(vel.vx, vel.vy, vel.omega);
        if r.delta_kinetic > 1e-12 * t_before.max(f64::MIN_POSITIVE) {
            out.energy_gains += 1;
        }
        *vel = r.after;
        true
    }

    /// Both corners down, no velocity: rest at the current footprint.
    fn land_flat(&mut self, pose: FlightState) -> State {
        self.x_base = pose.x;
        State::Rest
    }
}

type Vec2 = [bool; 2];
