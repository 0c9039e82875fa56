//! The reset map of each event, and the changes of mode it leads to.

use super::{Event, FlightState, Released, RockState, Run, SlideRockState, SlideState, State};
use crate::error::{Error, Result};
use crate::solver::impact;
use crate::solver::physics as ph;
use crate::solver::settings::RockImpact;

impl Run<'_> {
    /// Applies the reset map of an event and returns the new state.
    pub(super) fn handle(&mut self, ev: Event, state: State, t: f64) -> Result<State> {
        Ok(match (ev, state) {
            (Event::Overturn, st) => {
                self.tally.out.overturned = true;
                self.tally.out.overturn_time = Some(t);
                st
            }
            (Event::StartRock(s), _) => {
                self.tally.out.moved = true;
                self.h = self.h.min(0.25 * self.given.dt);
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
                self.tally.out.uplifted = true;
                self.tally.out.liftoff_holds += 1;
                rs.hold = true;
                State::Rock(rs)
            }
            (Event::HoldEnd, State::Rock(mut rs)) => {
                rs.hold = false;
                State::Rock(rs)
            }
            (Event::Uplift | Event::Release, State::Rock(rs)) => {
                self.tally.out.uplifted = true;
                self.tally.out.uplifts += 1;
                self.tally.out.flights += 1;
                self.rules.released = Some(Released { t, rock: rs });
                State::Flight(self.rock_to_flight(&rs))
            }
            (Event::Landing(side), State::Flight(_))
                if self
                    .rules
                    .released
                    .is_some_and(|r| r.t == t && side == -r.rock.s) =>
            {
                // The freed pivot is driven back into the ground at the
                // instant of release (q ≈ 0 and the rotation pushes it down):
                // no flight is possible, so the pivot is held instead.
                let Some(Released { rock: rs, .. }) = self.rules.released.take() else {
                    unreachable!("the guard checked `released`")
                };
                self.tally.out.uplifts -= 1;
                self.tally.out.flights -= 1;
                self.tally.out.liftoff_holds += 1;
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
                if self.given.e > 0.0
                    && !self.given.fric.finite()
                    && self.given.set.rock_impact == RockImpact::Rock
                {
                    return Ok(self.rock_impact_no_flight(t, fs, &rs));
                }
                let after = self.impacts(t, fs, rs.s);
                // the series the chatter rule closed at this impact (e > 0), if any
                let series = self.rules.closed_series.take().filter(|c| c.t == t);
                match after {
                    State::Rock(after) if self.cascade_settles(t, &after, series.as_ref()) => {
                        self.tally.out.settles += 1;
                        State::Rest
                    }
                    st => st,
                }
            }
            (Event::Landing(side), State::Flight(fs)) => self.impacts(t, fs, side),
            (Event::StartSlide(sigma), State::Rest) => {
                self.tally.out.moved = true;
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
                        self.tally.out.stick_holds += 1;
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
                self.tally.out.stick_holds += 1;
                let (ax, ay) = self.ground_at(t);
                let c = ph::rock_contact(&self.given.bl, sr.s, sr.theta, sr.omega, ax, ay);
                let hold = c.f.abs() > self.given.fric.mu_s * c.n;
                State::Rock(RockState {
                    s: sr.s,
                    theta: sr.theta,
                    omega: sr.omega,
                    hold,
                    last: None,
                })
            }
            (Event::SlideRockLiftoff, State::SlideRock(sr)) => {
                self.tally.out.uplifted = true;
                self.tally.out.uplifts += 1;
                self.tally.out.flights += 1;
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
    pub(super) fn start_slide_rock(
        &mut self,
        s: f64,
        theta: f64,
        omega: f64,
        xp: f64,
        vp: f64,
        t: f64,
    ) -> State {
        let mu_k = self.given.fric.mu_k;
        let (ax, ay) = self.ground_at(t);
        let accel =
            |sg: f64| ph::slide_rock_accel(&self.given.bl, s, sg, mu_k, theta, omega, ax, ay);
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
            self.tally.out.stick_holds += 1;
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
        let mu_s = self.given.fric.mu_s;
        let (ax, ay) = self.ground_at(t);
        let c = ph::rock_contact(&self.given.bl, sr.s, sr.theta, sr.omega, ax, ay);
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
        let mu_s = self.given.fric.mu_s;
        let (ax, ay) = self.ground_at(t);
        self.x_base = ss.x;
        if ax.abs() <= mu_s * (self.given.bl.g + ay) {
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
    pub(super) fn ground_at(&self, t: f64) -> (f64, f64) {
        let k = ((t / self.given.dt) as usize).min(self.samples() - 2);
        self.segment(k).at(t)
    }

    /// Rock state → rigid-body pose and velocity in the flight representation.
    fn rock_to_flight(&self, rs: &RockState) -> FlightState {
        let [x, vx, y, vy] = ph::rock_kinematics(&self.given.bl, rs.s, rs.theta, rs.omega);
        FlightState {
            x: self.x_base + x,
            vx,
            y,
            vy,
            theta: rs.theta,
            omega: rs.omega,
        }
    }

    /// The rock impact of [`RockImpact::Rock`] (e > 0, infinite friction):
    /// rocking goes on about the new corner with θ̇2 = δ(e)·θ̇1, or the block
    /// is set to rest if the new corner's speed is below the settle speed.
    fn rock_impact_no_flight(&mut self, t: f64, pose: FlightState, rs: &RockState) -> State {
        // physics.md, impact from rocking: ω2 = δ ω1, δ = 1 − 1.5 (1+e) sin²θc
        let delta = impact::rock_impact_ratio(&self.given.bl, self.given.e);
        self.tally.out.impacts += 1;
        self.tally.out.first_impact_time.get_or_insert(t);
        // paper eq. (8): the rock impact's friction demand, independent of e
        self.tally.out.mu_impact = self
            .tally
            .out
            .mu_impact
            .max(impact::rock_impact_mu(&self.given.bl));
        let omega = delta * rs.omega;
        if omega.abs() * 2.0 * self.given.bl.b <= self.rules.v_settle {
            // the same ring-down threshold as a plastic impact's
            self.tally.out.settles += 1;
            self.x_base = pose.x;
            return State::Rest;
        }
        let after = RockState {
            s: -rs.s,
            theta: 0.0,
            omega,
            hold: false,
            last: None,
        };
        let [x, ..] = ph::rock_kinematics(&self.given.bl, after.s, 0.0, omega);
        self.x_base = pose.x - x;
        State::Rock(after)
    }

    /// Slide-rock state → flight representation.
    fn slide_rock_to_flight(&self, sr: &SlideRockState) -> FlightState {
        let [x, vx, y, vy] = ph::rock_kinematics(&self.given.bl, sr.s, sr.theta, sr.omega);
        FlightState {
            x: sr.xp + x,
            vx: sr.vp + vx,
            y,
            vy,
            theta: sr.theta,
            omega: sr.omega,
        }
    }
}
