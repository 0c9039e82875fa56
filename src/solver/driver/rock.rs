//! Rock on a stuck pivot: by Taylor series (the default), by Dormand–Prince,
//! or in closed form for the linearised model; and the location of its
//! events (impact, lift-off and holds, slip, overturning) on the dense output.

use super::{Event, Grip, RockState, Run, Segment, State, earliest};
use crate::detmath as dm;
use crate::error::{Error, Result};
use crate::solver::block::Block;
use crate::solver::physics as ph;
use crate::solver::roots::brent;
use crate::solver::scan::{first_descent, first_descent_bounded};
use crate::solver::taylor;
use std::f64::consts::FRAC_PI_2;

impl Run<'_> {
    /// Nonlinear rock over [t, t_end] by DOPRI5; N = 3 also integrates the
    /// ground work for the energy audit.
    pub(super) fn rock_nonlinear<const N: usize>(
        &mut self,
        rs: &mut RockState,
        seg: &Segment,
        t: &mut f64,
        t_end: f64,
    ) -> Result<Option<Event>> {
        let bl = self.given.bl;
        let s = rs.s;
        let seg = *seg;
        let rhs = |tt: f64, y: &[f64; N]| -> [f64; N] {
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
        let (t_stop, event, ye) =
            self.dopri_to_event("rock", rhs, *t, y, t_end, tol, |run, step, ta, tb| {
                let path = |tt: f64| (step.component_at(0, tt), step.component_at(1, tt));
                let trig = |tt: f64| dm::sin_cos(bl.theta_c - s * step.component_at(0, tt));
                let unknown = (f64::NEG_INFINITY, f64::INFINITY);
                // |θ″| of the dense output bounds the searched ψ″ and (π/2 − ψ)″;
                // a dip shallower than the step's error scale for θ is below
                // what the step resolves
                let y0 = step.component_at(0, step.t0);
                let floor = tol.atol[0] + tol.rtol * y0.abs().max(step.y1[0].abs());
                let curv = Some((step.curvature_bound(0), floor));
                run.rock_events(rs, &path, &trig, unknown, curv, &seg, ta, tb, 1)
            })?;
        if N == 3 {
            self.tally.audit.work += ye[N - 1];
        }
        rs.theta = ye[0];
        rs.omega = ye[1];
        *t = t_stop;
        Ok(event)
    }

    /// Nonlinear rock over [t, t_end] by Taylor series ([`taylor`]): one
    /// series per step, usually one step per sample; events are located on
    /// the series. With the energy audit, the ground's work is a series too.
    pub(super) fn rock_taylor(
        &mut self,
        rs: &mut RockState,
        seg: &Segment,
        t: &mut f64,
        t_end: f64,
    ) -> Result<Option<Event>> {
        let bl = self.given.bl;
        let s = rs.s;
        let k = 0.75 / bl.r; // eq. (1): I_O = 4mR²/3
        let (atol_th, atol_om) = (
            self.given.set.atol * bl.theta_c,
            self.given.set.atol * bl.p * bl.theta_c,
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
            self.tally.out.stats.rhs_calls += 1;
            let tol_psi = atol_th + self.given.set.rtol * psi0.abs();
            let tol_dpsi = atol_om + self.given.set.rtol * dpsi0.abs();
            let h = series.step(t_end - t0, tol_psi, tol_dpsi);
            // A step that reaches the segment's end is taken however short:
            // rock entered a hair before a sample (a grazing lift-off at
            // the peak of a record) leaves a remainder of a few ulps.
            if h.is_nan() || (h <= h_min && h < t_end - t0) {
                return Err(Error::Solver {
                    time: t0,
                    message: format!(
                        "Taylor step {} s too small in rock",
                        crate::error::number(h)
                    ),
                });
            }
            self.tally.out.stats.steps_accepted += 1;
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
            // the series' |ψ″| bound lets the event search rule out a double
            // crossing inside the step; a dip shallower than the step's own
            // truncation tolerance is below what the series resolves
            let curv = (range.0 <= 0.0 || range.1 >= FRAC_PI_2)
                .then(|| (series.curvature_bound(t1 - t0), tol_psi));
            let found = self.rock_events(rs, &path, &trig, range, curv, seg, t0, t1, 1);
            let t_stop = found.map_or(t1, |(te, _)| te);
            if self.given.set.audit_energy {
                let w = series.work(bl.r, s, &forcing, bl.g);
                self.tally.audit.work += taylor::eval(&w, t_stop - t0);
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
    pub(super) fn rock_linear(
        &mut self,
        rs: &mut RockState,
        seg: &Segment,
        t: &mut f64,
        t_end: f64,
    ) -> Option<Event> {
        let (ax0, _) = seg.at(*t);
        let (l2, c0, c1) = ph::linear_coeffs(&self.given.bl, rs.s, ax0, seg.a1);
        let lam = l2.sqrt();
        let (th0, om0) = (rs.theta, rs.omega);
        let t0 = *t;
        // θ(τ) = θ0 cosh λτ + (ω0/λ) sinh λτ + (c0/λ²)(cosh λτ − 1) + (c1/λ³)(sinh λτ − λτ),
        // written so that τ = 0 returns (θ0, ω0) exactly and small τ loses no digits
        let path = |tt: f64| {
            let tau = tt - t0;
            let x = lam * tau;
            // one expm1 gives sinh, cosh and cosh − 1 without cancellation
            let em = dm::exp_m1(x);
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
        self.tally.out.stats.steps_accepted += 1;
        let (s, theta_c) = (rs.s, self.given.bl.theta_c);
        let trig = |tt: f64| dm::sin_cos(theta_c - s * path(tt).0);
        let unknown = (f64::NEG_INFINITY, f64::INFINITY);
        // linearised eq. (1): θ″ = (λ²θ0 + c0) cosh λτ + (λω0 + c1/λ) sinh λτ
        // (the closed form above differentiated twice), both growing in τ ≥ 0:
        // their values at the end bound |θ″|. A dip shallower than the nonlinear solvers'
        // tolerance for θ is not sought (as in `rock_taylor`).
        let x_end = lam * (t_end - t0);
        let m2 = ((l2 * th0 + c0).abs() * dm::cosh(x_end)
            + (lam * om0 + c1 / lam).abs() * dm::sinh(x_end))
            * (1.0 + 1e-12);
        let floor = self.given.set.atol * theta_c + self.given.set.rtol * th0.abs();
        let curv = Some((m2, floor));
        if let Some((te, ev)) = self.rock_events(rs, &path, &trig, unknown, curv, seg, t0, t_end, n)
        {
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
    /// and updates the peak rotation and friction demand. With `curv` =
    /// (m2, floor), |θ″| ≤ m2 on the step and the impact and overturning
    /// searches cannot miss a dip deeper than `floor` ([`first_descent_bounded`]);
    /// without it they look for one minimum in each of `n` pieces. Contact forces are
    /// those of eq. (1) at the path's state; the value at `ta` is reused from
    /// the previous step's end when available.
    #[allow(clippy::too_many_arguments)]
    fn rock_events(
        &mut self,
        rs: &mut RockState,
        path: &impl Fn(f64) -> (f64, f64),
        trig: &impl Fn(f64) -> (f64, f64),
        psi_range: (f64, f64),
        curv: Option<(f64, f64)>,
        seg: &Segment,
        ta: f64,
        tb: f64,
        n: usize,
    ) -> Option<(f64, Event)> {
        let s = rs.s;
        let bl = self.given.bl;
        let xtol = 1e-15 * tb.abs().max(1.0);
        // the hot call sites call `rock_contact_at` directly: this closure
        // would be kept out of line and its result returned through memory,
        // stored field by field and read back in pairs (a store-forwarding stall)
        let contact = |tt: f64| rock_contact_at(&bl, s, path, trig, seg, tt);
        let mut best: Option<(f64, Event)> = None;
        // Impact: ψ = sθ reaches 0 (grazing dips included).
        let psi = |tt: f64| {
            let (th, om) = path(tt);
            (s * th, s * om)
        };
        // `psi_range` bounds ψ over the step (infinite when unknown): the
        // searches are skipped when it proves there is nothing to find.
        if psi_range.0 <= 0.0 {
            let te = match curv {
                Some((m2, floor)) => first_descent_bounded(psi, ta, tb, m2, floor, xtol, false),
                None => first_descent(psi, ta, tb, n, xtol),
            };
            earliest(&mut best, te, Event::RockImpact);
        }
        // Overturning: π/2 − ψ reaches 0.
        let over = |tt: f64| {
            let (th, om) = path(tt);
            (FRAC_PI_2 - s * th, -s * om)
        };
        if psi_range.1 >= FRAC_PI_2 {
            let te = match curv {
                Some((m2, floor)) => first_descent_bounded(over, ta, tb, m2, floor, xtol, false),
                None => first_descent(over, ta, tb, n, xtol),
            };
            earliest(&mut best, te, Event::Overturn);
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
            _ => rock_contact_at(&bl, s, path, trig, seg, ta),
        };
        let (mut n0, mut q0) = (c_a.n, release_q(&c_a));
        let mut c_end: Option<ph::RockContact> = None;
        if self.given.fric.finite() {
            let Grip { mu_s, mu_k } = self.given.fric;
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
                let c1 = rock_contact_at(&bl, s, path, trig, seg, t1);
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
            if self.given.fric.finite() {
                break;
            }
            let t1 = if i == n { tb } else { ta + width * i as f64 };
            let c1 = rock_contact_at(&bl, s, path, trig, seg, t1);
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
            _ => rock_contact_at(&bl, s, path, trig, seg, t_stop),
        };
        rs.last = Some((t_stop, c_b));
        let (th_a, om_a) = path(ta);
        let (th_b, om_b) = path(t_stop);
        let mut peak = th_a.abs().max(th_b.abs());
        // a turning point can only raise θmax if ψ's bound exceeds it
        let may_raise = psi_range.1 > self.tally.out.theta_max_over_theta_c * bl.theta_c;
        if om_a * om_b < 0.0 && (may_raise || self.tally.hist.is_some()) {
            let tm = brent(|tt| path(tt).1, ta, t_stop, om_a, om_b, xtol);
            let (th_m, om_m) = path(tm);
            peak = peak.max(th_m.abs());
            if self.tally.hist.is_some() {
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
        if ratio > self.tally.out.theta_max_over_theta_c {
            self.tally.out.theta_max_over_theta_c = ratio.min(FRAC_PI_2 / bl.theta_c);
        }
        // Friction demand |F|/N at the end of the step (N > 0 only); beyond
        // θc it waits in `mu_beyond` until the block is back within θc, so
        // that the fall of an overturning block is left out (`Tally::mu_beyond`)
        let demand = if c_b.n > 0.0 {
            c_b.f.abs() / c_b.n
        } else {
            0.0
        };
        if th_b.abs() <= bl.theta_c {
            self.tally.out.mu_motion = self
                .tally
                .out
                .mu_motion
                .max(demand.max(self.tally.mu_beyond));
            self.tally.mu_beyond = 0.0;
        } else {
            self.tally.mu_beyond = self.tally.mu_beyond.max(demand);
        }
        best
    }
}

/// sinh x − x for |x| < 0.5 by its series (error < 1e-15 relative).
#[inline]
fn sinh_minus_x(x: f64) -> f64 {
    let x2 = x * x;
    x * x2 / 6.0
        * (1.0
            + x2 / 20.0
                * (1.0 + x2 / 42.0 * (1.0 + x2 / 72.0 * (1.0 + x2 / 110.0 * (1.0 + x2 / 156.0)))))
}

/// The contact forces of rock about the corner on side −s at `tt`, on the
/// step's path (θ, θ̇) and its sin φ, cos φ (eq. (1) and its reactions).
#[inline(always)]
fn rock_contact_at(
    bl: &Block,
    s: f64,
    path: &impl Fn(f64) -> (f64, f64),
    trig: &impl Fn(f64) -> (f64, f64),
    seg: &Segment,
    tt: f64,
) -> ph::RockContact {
    let (_, om) = path(tt);
    let (sp, cp) = trig(tt);
    let (ax, ay) = seg.at(tt);
    ph::rock_contact_sc(bl, s, sp, cp, om, ax, ay)
}
