//! Bookkeeping between and at events: the peak rotation, the slip, the
//! energy audit and the rows of the history.

use super::{Run, Segment, State};
use crate::outcome::Mode;
use crate::solver::history::HistoryRow;
use crate::solver::physics as ph;
use std::f64::consts::FRAC_PI_2;

impl Run<'_> {
    pub(super) fn note_theta(&mut self, state: &State) {
        let th = match state {
            State::Rest | State::Slide(_) => 0.0,
            State::Rock(r) => r.theta,
            State::SlideRock(r) => r.theta,
            State::Flight(f) => f.theta,
        };
        self.note_angle(th);
    }

    /// Raises the peak θmax/θc to |θ|/θc (capped at the overturning angle).
    #[inline]
    pub(super) fn note_angle(&mut self, th: f64) {
        // the division only where θ may raise the peak (a bound with margin
        // for the rounding of the ratio)
        if th.abs() >= self.tally.out.theta_max_over_theta_c * self.given.bl.theta_c * (1.0 - 1e-12)
        {
            let ratio = (th.abs() / self.given.bl.theta_c).min(FRAC_PI_2 / self.given.bl.theta_c);
            self.tally.out.theta_max_over_theta_c =
                self.tally.out.theta_max_over_theta_c.max(ratio);
        }
    }

    /// Tracks the block's slip: the offset of its footprint (or of the
    /// slipping pivot) from its initial place.
    pub(super) fn note_slip(&mut self, state: &State) {
        let x = match state {
            State::Rest | State::Rock(_) => self.x_base,
            State::Slide(ss) => ss.x,
            State::SlideRock(sr) => sr.xp,
            State::Flight(_) => return,
        };
        self.tally.out.slip_max = self.tally.out.slip_max.max(x.abs());
        self.tally.out.slip_final = x;
    }

    /// Mechanical energy per unit mass in the ground frame.
    pub(super) fn energy(&self, state: &State) -> f64 {
        match state {
            State::Rest => 0.0,
            State::Slide(ss) => 0.5 * ss.v * ss.v,
            State::Rock(r) => {
                let [_, vx, y, vy] = ph::rock_kinematics(&self.given.bl, r.s, r.theta, r.omega);
                ph::energy(&self.given.bl, vx, vy, r.omega, y)
            }
            State::SlideRock(r) => {
                let [_, vx, y, vy] = ph::rock_kinematics(&self.given.bl, r.s, r.theta, r.omega);
                ph::energy(&self.given.bl, r.vp + vx, vy, r.omega, y)
            }
            State::Flight(f) => ph::energy(&self.given.bl, f.vx, f.vy, f.omega, f.y),
        }
    }

    pub(super) fn audit(&mut self, state: &State) {
        if self.given.set.audit_energy {
            let e = self.energy(state);
            let r = e - self.tally.audit.e0 - self.tally.audit.work - self.tally.audit.jumps;
            self.tally.audit.resid = self.tally.audit.resid.max(r.abs());
            self.tally.audit.escale = self
                .tally
                .audit
                .escale
                .max(e.abs())
                .max(self.tally.audit.work.abs());
        }
    }

    pub(super) fn push_row(&mut self, t: f64, state: &State, seg: &Segment, event: bool) {
        let Some(hist) = self.tally.hist.as_deref_mut() else {
            return;
        };
        let bl = &self.given.bl;
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
                f: -self.given.fric.mu_k * ss.sigma * (bl.g + ay),
                event,
            },
            State::SlideRock(r) => {
                let [x, vx, y, vy] = ph::rock_kinematics(bl, r.s, r.theta, r.omega);
                let mu_k = self.given.fric.mu_k;
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
