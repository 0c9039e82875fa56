//! Free flight in closed form, and the location of landings and overturning.

use super::{Event, FlightState, Run, Segment, earliest};
use crate::solver::physics as ph;
use crate::solver::scan::{first_descent, first_descent_after_release};
use std::f64::consts::FRAC_PI_2;

impl Run<'_> {
    /// Free flight over [t, t_end] in closed form; locates landings of either
    /// corner and overturning.
    pub(super) fn flight(
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
}
