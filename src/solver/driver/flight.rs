//! Free flight in closed form, and the location of landings and overturning.

use super::{ChatterImpact, ChatterTry, Event, FlightState, Run, Segment, earliest};
use crate::solver::impact::{Velocity, point_velocity};
use crate::solver::physics as ph;
use crate::solver::scan::first_descent_bounded;
use std::f64::consts::FRAC_PI_2;

impl Run<'_> {
    /// Free flight over [t, t_end]: returns the first event (a landing or
    /// overturning) that ends it, having resolved on the way the plain
    /// bounces of a lone corner ([`Run::bounce`]), which need none of the
    /// event loop's decisions.
    pub(super) fn flight(
        &mut self,
        state: &mut FlightState,
        seg: &Segment,
        t: &mut f64,
        t_end: f64,
    ) -> Option<Event> {
        // a local copy, kept in registers over the bounces (the caller's lives in memory)
        let mut fs = *state;
        // sin θ and cos θ at the piece's start, when a bounce has just taken them
        let mut trig = None;
        let event = loop {
            let event = self.flight_piece(&mut fs, seg, t, t_end, trig);
            match event {
                Some(Event::Landing(side)) if *t < t_end => match self.bounce(&mut fs, side, *t) {
                    Some(sc) => trig = Some(sc),
                    None => break event,
                },
                _ => break event,
            }
        };
        *state = fs;
        event
    }

    /// A bounce of corner `side` landing at `t` that leaves the block in
    /// flight with nothing for the event loop to decide: the other corner is
    /// off the ground, the rebound is faster than the ring-down rule looks at
    /// and the chatter rule, if due, does not close the series. Then the
    /// impact is applied to `fs` and counted as the event loop would (the same
    /// arithmetic: results do not depend on the shortcut), and sin θ and cos θ
    /// of the pose are returned. Not taken with a history or the energy
    /// audit, which record every event.
    fn bounce(&mut self, fs: &mut FlightState, side: f64, t: f64) -> Option<(f64, f64)> {
        if self.tally.hist.is_some()
            || self.given.set.audit_energy
            || self.tally.out.stats.events >= self.given.set.max_events
            || self.rules.released.is_some_and(|r| r.t == t)
        {
            return None;
        }
        let bl = self.given.bl;
        // as `impacts` takes the pose
        let (sn, cs) = ph::sin_cos_small(fs.theta);
        let (_, oy) = bl.corner_offset_sc(-side, sn, cs);
        if bl.h + fs.y + oy <= self.rules.h_touch {
            return None;
        }
        let (rx, ry) = bl.corner_offset_sc(side, sn, cs);
        let vel = Velocity {
            vx: fs.vx,
            vy: fs.vy,
            omega: fs.omega,
        };
        let (r, demand) = self.hit(&vel, rx, ry, self.given.e);
        let un_after = point_velocity(&r.after, rx, ry).1;
        if un_after <= self.rules.v_settle {
            return None;
        }
        if self.chatter_due(side, un_after) {
            // try the chatter rule here; only a success needs the event loop
            // (whose `impacts` takes this result), a failure bounces on as
            // `impacts` would
            let (plastic, plastic_demand) = self.hit(&vel, rx, ry, 0.0);
            if self.sticks(demand)
                && self.sticks(plastic_demand)
                && let Some(chatter) = self.try_chatter(&ChatterImpact {
                    t,
                    theta: fs.theta,
                    side,
                    rx,
                    ry,
                    newton: r.after,
                    u1: un_after,
                    plastic: plastic.after,
                })
            {
                self.rules.chatter_tried = Some(ChatterTry { t, side, chatter });
                return None;
            }
        }
        self.tally.out.stats.events += 1;
        self.note_impact(t, &vel, &r, demand, rx, ry, self.given.e);
        self.tally.out.flights += 1;
        fs.vx = r.after.vx;
        fs.vy = r.after.vy;
        fs.omega = r.after.omega;
        Some((sn, cs))
    }

    /// Free flight over [t, t_end] in closed form; locates landings of either
    /// corner and overturning. `trig`: sin θ and cos θ at the start, if known.
    fn flight_piece(
        &mut self,
        fs: &mut FlightState,
        seg: &Segment,
        t: &mut f64,
        t_end: f64,
        trig: Option<(f64, f64)>,
    ) -> Option<Event> {
        let bl = &self.given.bl;
        let t0 = *t;
        let (a0, b0) = seg.at(t0);
        let (a1, b1) = (seg.a1, seg.v1);
        let gy0 = bl.g + b0;
        let f = *fs;
        // relative motion: ẍ = −ẍg, ÿ = −g − ÿg, θ̈ = 0
        let vertical = move |tau: f64| {
            (
                f.y + f.vy * tau - gy0 * tau * tau / 2.0 - b1 * tau * tau * tau * (1.0 / 6.0),
                f.vy - gy0 * tau - b1 * tau * tau / 2.0,
            )
        };
        let pos = move |tau: f64| -> FlightState {
            let (y, vy) = vertical(tau);
            FlightState {
                x: f.x + f.vx * tau - a0 * tau * tau / 2.0 - a1 * tau * tau * tau * (1.0 / 6.0),
                vx: f.vx - a0 * tau - a1 * tau * tau / 2.0,
                y,
                vy,
                theta: f.theta + f.omega * tau,
                omega: f.omega,
            }
        };
        let span = t_end - t0;
        let xtol = 1e-15 * t_end.abs().max(1.0);
        let mut best: Option<(f64, Event)> = None;
        // θ(τ) = θ0 + ωτ: sin and cos by angle addition, the small rotation
        // by its series (most flights of a ring-down rotate little)
        let (s0, c0) = trig.unwrap_or_else(|| ph::sin_cos_small(f.theta));
        // each corner's offset from G at the start, turned by ωτ in flight
        let r_left = bl.corner_offset_sc(-1.0, s0, c0);
        let r_right = bl.corner_offset_sc(1.0, s0, c0);
        let height = |side: f64, tau: f64| {
            let (y, vy) = vertical(tau);
            let (sx, cx) = ph::sin_cos_small(f.omega * tau);
            let (r0x, r0y) = if side > 0.0 { r_right } else { r_left };
            let (rx, ry) = (r0x * cx - r0y * sx, r0x * sx + r0y * cx);
            (bl.h + y + ry, vy + f.omega * rx)
        };
        match self.lone_landing(
            &f,
            (s0, c0),
            (gy0, gy0 + (b1 * span).min(0.0), b1),
            span,
            xtol,
            height,
        ) {
            Some((side, found)) => earliest(&mut best, found, Event::Landing(side)),
            None => {
                let n = 1 + (f.omega.abs() * span / 0.2) as usize;
                // Here h″ may change sign inside a piece (ω²R ≥ g + ÿg), and a
                // corner can touch down and lift again between two points of
                // it: each piece is searched with a bound on |h″|. h = H + y +
                // r_y with y″ = −(g + ÿg(τ)) and r_y″ = −ω² r_y, |r_y| ≤ R: the
                // free-flight closed form above differentiated twice, with
                // g + ÿg linear in τ (extreme at the piece's ends)
                let gy_abs = gy0.abs().max((gy0 + b1 * span).abs());
                let m2 = (gy_abs + f.omega * f.omega * bl.r) * (1.0 + 1e-12);
                // a dip shallower than the height at which a corner counts as
                // touching is not sought
                let floor = self.rules.h_touch;
                let width = span / n as f64;
                for side in [-1.0, 1.0] {
                    // a corner leaving the ground at the start of this piece of
                    // flight (just released by an impact or a lift-off) is departing
                    let (h0, u0) = height(side, 0.0);
                    let fd = |tau| height(side, tau);
                    let released = h0 <= self.rules.h_touch && u0 >= -self.rules.v_settle;
                    let mut found = None;
                    for i in 0..n {
                        let a = width * i as f64;
                        let b = if i + 1 == n {
                            span
                        } else {
                            width * (i + 1) as f64
                        };
                        found =
                            first_descent_bounded(fd, a, b, m2, floor, xtol, released && i == 0);
                        if found.is_some() {
                            break;
                        }
                    }
                    earliest(&mut best, found, Event::Landing(side));
                }
            }
        }
        // overturning, |θ| = π/2 (the division only when it may fall in the piece)
        let to_go = FRAC_PI_2.copysign(f.omega) - f.theta;
        if f.omega != 0.0 && to_go.abs() <= f.omega.abs() * span * (1.0 + 1e-12) {
            let te = to_go / f.omega;
            if (0.0..=span).contains(&te) {
                earliest(&mut best, Some(te), Event::Overturn);
            }
        }
        let tau_end = best.map_or(span, |(te, _)| te);
        if self.given.set.audit_energy {
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
                self.tally.audit.work +=
                    w * half * ph::ground_power(a0 + a1 * tau, b0 + b1 * tau, p.vx, p.vy);
            }
        }
        *fs = pos(tau_end);
        *t = t0 + tau_end;
        self.note_angle(fs.theta);
        match best {
            Some((_, ev)) => Some(ev),
            None => {
                *t = t_end;
                None
            }
        }
    }

    /// The landing of a flight's lower corner when it alone can land: while
    /// θ keeps its sign the upper corner stays 2B|sin θ| above the lower one,
    /// and the lower corner's height h is concave (h″ = −(g + ÿg) − ω² r_y ≤
    /// −`gy_min` + ω²R < 0), so it has at most one descent through zero after
    /// a departure ([`descent`]). If θ crosses 0 first, with both corners
    /// above the ground, the other corner is the lower one from there to the
    /// piece's end, and the same holds for it. Returns the landing corner's
    /// side and its landing in (0, `span`], if any; `None` where those
    /// conditions do not hold (the caller then searches both corners). Most
    /// flights of a bounce series meet them: this is their fast path.
    ///
    /// `height(side, τ)` gives the corner's height and its rate, (s0, c0) are
    /// sin θ and cos θ at the start, `gy0` is g + ÿg at the piece's start,
    /// `gy_min` its least value over the piece and `b1` its rate.
    fn lone_landing(
        &self,
        f: &FlightState,
        (s0, c0): (f64, f64),
        (gy0, gy_min, b1): (f64, f64, f64),
        span: f64,
        xtol: f64,
        height: impl Fn(f64, f64) -> (f64, f64),
    ) -> Option<(f64, Option<f64>)> {
        let bl = &self.given.bl;
        let w2r = f.omega * f.omega * bl.r;
        if gy_min <= w2r {
            return None;
        }
        // θ's sign over the piece, and the lower corner
        let sigma = if f.theta != 0.0 {
            f.theta.signum()
        } else if f.omega != 0.0 {
            f.omega.signum()
        } else {
            return None;
        };
        let low = -sigma;
        // the search ends where θ would cross 0 (the corners change places)
        let limit = if sigma * f.omega < 0.0 {
            (-f.theta / f.omega).min(span)
        } else {
            span
        };
        // the lower corner at τ = 0: height and rate
        let (rx0, ry0) = bl.corner_offset_sc(low, s0, c0);
        let (h0, d0) = (bl.h + f.y + ry0, f.vy + f.omega * rx0);
        if h0 <= self.rules.h_touch && d0 <= 0.0 {
            // touching and not departing: the general search decides
            return None;
        }
        let c2 = gy0 + (b1 * span).max(0.0) + w2r;
        let curv = -gy0 - f.omega * f.omega * ry0;
        match descent(|tau| height(low, tau), (0.0, h0, d0), curv, limit, c2, xtol)? {
            Some(found) => return Some((low, Some(found))),
            None if limit >= span => return Some((low, None)),
            None => {}
        }
        // θ crosses 0 at `limit` with both corners above the ground (the
        // lower one is above it there, so is the other, level with it); after
        // it the other corner is the lower one, to the piece's end
        let up = -low;
        let (hl, dl) = height(up, limit);
        if hl <= 0.0 {
            return None;
        }
        // h″ at `limit`: −(g + ÿg) − ω² r_y, with r_y turned by ω·limit
        let (sx, cx) = ph::sin_cos_small(f.omega * limit);
        let (rx1, ry1) = bl.corner_offset_sc(up, s0, c0);
        let ry_l = rx1 * sx + ry1 * cx;
        let curv_l = -(gy0 + b1 * limit) - f.omega * f.omega * ry_l;
        let found = descent(
            |tau| height(up, tau),
            (limit, hl, dl),
            curv_l,
            span,
            c2,
            xtol,
        )?;
        Some((up, found))
    }
}

/// The first descent through zero of a concave height h on (τa, `limit`],
/// from (τa, h(τa), h′(τa)) with h(τa) > 0 or h′(τa) > 0, and h″(τa) =
/// `curv` < 0, |h″| ≤ `c2` over the piece: `Some(None)` if h stays above
/// zero, `None` if rounding leaves it undecided (h′ ≥ 0 past the root).
/// Newton from the root's right (h ≤ 0) stays there on a concave function and
/// converges monotonely; it starts from the root of the parabola at τa, or
/// from one Newton step past it, else from `limit`.
fn descent(
    fd: impl Fn(f64) -> (f64, f64),
    (ta, ha, da): (f64, f64, f64),
    curv: f64,
    limit: f64,
    c2: f64,
    xtol: f64,
) -> Option<Option<f64>> {
    // (a corner just off the ground, h ≤ 0, needs no square root)
    let tq = ta
        + if ha > 0.0 {
            (da + (da * da - 2.0 * curv * ha).max(0.0).sqrt()) / -curv
        } else {
            (da + da.abs()) / -curv
        };
    let mut start = None;
    if tq > ta && tq < limit {
        let (hq, dq) = fd(tq);
        if hq <= 0.0 {
            start = Some((tq, hq, dq));
        } else if dq < 0.0 {
            let tn = tq - hq / dq;
            if tn < limit {
                let (hn, dn) = fd(tn);
                if hn <= 0.0 {
                    start = Some((tn, hn, dn));
                }
            }
        }
    }
    let (mut tau, mut h, mut d) = match start {
        Some(st) => st,
        None => {
            let (hl, dl) = fd(limit);
            if hl > 0.0 {
                // concave and not below zero at either end: no landing
                return Some(None);
            }
            (limit, hl, dl)
        }
    };
    let tol = 0.5 * xtol;
    // Newton's next error is at most c2 e²/(2|h′|), e ≤ 2·step once it is
    // below the step
    for _ in 0..32 {
        if h == 0.0 {
            return Some(Some(tau));
        }
        if d >= 0.0 {
            break;
        }
        let inv_d = 1.0 / d;
        let step = h * inv_d;
        if step <= tol {
            return Some(Some(tau));
        }
        let tn = tau - step;
        let next = -2.0 * c2 * step * step * inv_d;
        if next <= tol && next <= step {
            // the step after this one would be below the tolerance
            return Some(Some(tn));
        }
        let (hn, dn) = fd(tn);
        if hn > 0.0 {
            // rounding put the step before the root: bracket it
            let r = crate::solver::roots::newton(&fd, (tn, hn, dn), (tau, h), xtol);
            return Some(Some(r));
        }
        (tau, h, d) = (tn, hn, dn);
    }
    // (h′ ≥ 0 right of the root cannot happen on a concave h: rounding)
    None
}
