//! Sequential corner impacts and the choice of the mode after them; the
//! cascade rule and the chatter rule's place (see the driver's module
//! documentation).

use super::{Chatter, FlightState, RockState, Run, SlideState, State};
use crate::outcome::Mode;
use crate::solver::impact::{self, ImpactResult, Velocity};
use crate::solver::physics as ph;

impl Run<'_> {
    /// Sequential corner impacts starting with corner `side`, then the choice
    /// of the next mode (rest, rock or flight).
    pub(super) fn impacts(&mut self, t: f64, pose: FlightState, side: f64) -> State {
        let bl = self.bl;
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
            [-1.0, 1.0].map(|sd| bl.h + pose.y + offset(sd).1 <= self.h_touch);
        let mut next = Some(side);
        let mut count = 0;
        // the end of a bounce series closed by the chatter rule
        let mut series_end = None;
        while let Some(sd) = next {
            let (rx, ry) = offset(sd);
            let hit = |e: f64| self.hit(&vel, rx, ry, e);
            let (mut r, mut demand) = hit(self.e);
            let mut e_applied = self.e;
            let un_after = impact::point_velocity(&r.after, rx, ry).1;
            if self.e > 0.0 && un_after > 0.0 && un_after <= self.v_settle {
                // ring-down: a rebound below the threshold is plastic
                (r, demand) = hit(0.0);
                e_applied = 0.0;
                self.out.settles += 1;
            } else if un_after > 0.0
                && count == 0
                && self.chatter_due(sd, un_after)
                && (pose.theta == 0.0 || !touching[if sd < 0.0 { 1 } else { 0 }])
            {
                // the chatter rule: close the series of bounces on this corner
                // with this impact made plastic, its sums carried into the rock
                // state (`close_series`)
                let (plastic, plastic_demand) = hit(0.0);
                if let Some(ch) =
                    self.try_chatter(t, pose.theta, sd, rx, ry, r.after, un_after, plastic.after)
                {
                    self.out.mu_impact = self.out.mu_impact.max(demand).max(ch.demand);
                    self.out.mu_impact_eq5 = self
                        .out
                        .mu_impact_eq5
                        .max(impact::eq5_mu(&bl, &vel, rx, ry, self.e))
                        .max(ch.demand_eq5);
                    series_end = Some((sd, ch.end));
                    (r, demand) = (plastic, plastic_demand);
                    e_applied = 0.0;
                    self.out.settles += 1;
                }
            }
            self.note_impact(t, &vel, &r, demand, rx, ry, e_applied);
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
                match series_end {
                    Some((sd, end)) if sd == pivot => State::Rock(self.close_series(t, rs, &end)),
                    _ => State::Rock(rs),
                }
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

    /// True if a bounce of corner `side` rebounding at `u` is one the chatter
    /// rule tries to close: the rule applies (e in (0, 1), infinite friction),
    /// the rebound is below `CLOSE_TOL`·√(gR), and, after a try on this corner
    /// failed, it has halved since.
    #[inline]
    pub(super) fn chatter_due(&self, side: f64, u: f64) -> bool {
        self.set.settle_cascades
            && self.fric.is_none()
            && self.e > 0.0
            && self.e < 1.0
            && u <= self.v_close
            && (self.chatter_retry.0 != side || u <= self.chatter_retry.1)
    }

    /// A try of the chatter rule at an impact of corner `side` (the arguments
    /// of [`Run::chatter_settles`]), or the result `bounce` already found for
    /// this very impact. After a failure the next try on this corner waits
    /// until the rebound has halved (the bounds need a shorter series); a
    /// success clears that wait. (The velocities come by value: a reference
    /// would keep the caller's impact result in memory on every bounce, not
    /// only on a try.)
    #[allow(clippy::too_many_arguments)]
    pub(super) fn try_chatter(
        &mut self,
        t: f64,
        theta: f64,
        side: f64,
        rx: f64,
        ry: f64,
        newton: Velocity,
        u1: f64,
        plastic: Velocity,
    ) -> Option<Chatter> {
        let tried = match self.chatter_tried.take() {
            Some((tt, ts, ch)) if tt == t && ts == side => Some(ch),
            _ => self.chatter_settles(t, theta, side, rx, ry, newton, u1, plastic),
        };
        self.chatter_retry = if tried.is_some() {
            (0.0, f64::INFINITY)
        } else {
            (side, 0.5 * u1)
        };
        tried
    }

    /// One impact of the corner at offset (rx, ry) from G with restitution
    /// `e`, by the analysis' impact law and friction: the result and the
    /// friction needed to prevent sliding during it.
    // (always inlined: its result, returned through memory, would be stored
    // field by field and read back in pairs, which stalls store forwarding)
    #[inline(always)]
    pub(super) fn hit(&self, vel: &Velocity, rx: f64, ry: f64, e: f64) -> (ImpactResult, f64) {
        let law = self.set.impact;
        match self.fric {
            None => {
                let r = impact::corner_impact(&self.bl, vel, rx, ry, e, law);
                (r, r.friction_demand())
            }
            Some((mu_s, mu_k)) => {
                impact::corner_impact_friction(&self.bl, vel, rx, ry, e, law, mu_s, mu_k)
            }
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
        let bl = &self.bl;
        self.out.impacts += 1;
        self.out.first_impact_time.get_or_insert(t);
        // friction needed to prevent sliding during this impact
        self.out.mu_impact = self.out.mu_impact.max(demand);
        // the same, as the paper's eq. (5) evaluates it
        let eq5 = impact::eq5_mu(bl, vel, rx, ry, e_applied);
        self.out.mu_impact_eq5 = self.out.mu_impact_eq5.max(eq5);
        let t_before = bl.kinetic(vel.vx, vel.vy, vel.omega);
        if r.delta_kinetic > 1e-12 * t_before.max(f64::MIN_POSITIVE) {
            self.out.energy_gains += 1;
        }
    }

    /// The cascade rule (module documentation): true if the rock impacts that
    /// follow a rock impact at `t`, leaving the block in `rs` (θ = 0), provably
    /// die out before the ground can lift the block. Then the cascade's
    /// friction demand is noted and the caller sets the block to rest.
    pub(super) fn cascade_settles(&mut self, t: f64, rs: &RockState) -> bool {
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
            // The cascade's duration, counted as rock rather than rest. On
            // the ground frozen at the cascade's start, side s restores at
            // A(ψ) = k[(g + ÿg) sin(θc − ψ) − s ẍg cos(θc − ψ)] = A_s − c_s ψ
            // + O(ψ²), so a bounce leaving at u lands at u after
            // (2/λ) atanh(uλ/A_s) = 2u/A_s + (2/3) c_s u³/A_s³ + O(u⁵),
            // λ² = c_s; the bounces alternate sides, bounce n leaving at
            // uₙ = ηⁿu0, so the sum is geometric (module documentation). It
            // ends within the window, where rest cannot break (capped at the
            // bound `t_cascade`, which it is below: A_s ≥ lo_min, η ≤ ρ).
            let (ax, gy) = (at_start.0, bl.g + at_start.1);
            let a_s = |s: f64| kk * (gy * bl.sin_c - s * ax * bl.cos_c);
            let c_s = |s: f64| kk * (gy * bl.cos_c + s * ax * bl.sin_c);
            let (a0, a1) = (a_s(rs.s), a_s(-rs.s));
            let (e2, e3) = (eta * eta, eta * eta * eta);
            let t_rock = (2.0 * u0 * (1.0 / a0 + eta / a1) / (1.0 - e2)
                + 2.0 / 3.0 * u0 * u0 * u0 / (1.0 - e3 * e3)
                    * (c_s(rs.s) / (a0 * a0 * a0) + e3 * c_s(-rs.s) / (a1 * a1 * a1)))
                .min(t_cascade);
            self.out.time_in_mode[Mode::Rock.index()] += t_rock;
            self.out.time_in_mode[Mode::Rest.index()] -= t_rock;
            return true;
        }
        false
    }

    /// Both corners down, no velocity: rest at the current footprint.
    fn land_flat(&mut self, pose: FlightState) -> State {
        self.x_base = pose.x;
        State::Rest
    }
}

type Vec2 = [bool; 2];
