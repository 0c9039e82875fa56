//! Slide on both corners (closed form) and slide-rock, rocking on a slipping
//! pivot (Dormand–Prince).

use super::{Event, Run, Segment, SlideRockState, SlideState, earliest};
use crate::detmath as dm;
use crate::error::Result;
use crate::solver::physics as ph;
use crate::solver::roots::brent;
use crate::solver::scan::{first_descent, first_descent_after_release};
use std::f64::consts::FRAC_PI_2;

impl Run<'_> {
    /// Slide on both corners over [t, t_end], in closed form: the relative
    /// acceleration −ẍg − μk σ (g + ÿg) is linear in time.
    pub(super) fn slide(
        &mut self,
        ss: &mut SlideState,
        seg: &Segment,
        t: &mut f64,
        t_end: f64,
    ) -> Option<Event> {
        let mu_k = self.given.fric.mu_k;
        let t0 = *t;
        let (a0, b0) = seg.at(t0);
        let sg = ss.sigma;
        // ẍ = A + Bτ
        let acc0 = -a0 - mu_k * sg * (self.given.bl.g + b0);
        let acc1 = -seg.a1 - mu_k * sg * seg.v1;
        let st = *ss;
        let vel = move |tau: f64| st.v + acc0 * tau + 0.5 * acc1 * tau * tau;
        let span = t_end - t0;
        let xtol = 1e-15 * t_end.abs().max(1.0);
        let fd = |tau: f64| (sg * vel(tau), sg * (acc0 + acc1 * tau));
        // (the velocity is quadratic in τ: one extremum at most, so the
        // one-minimum search cannot miss a double crossing)
        let found = if st.v == 0.0 {
            first_descent_after_release(fd, 0.0, span, 1, xtol)
        } else {
            first_descent(fd, 0.0, span, 1, xtol)
        };
        let tau_end = found.unwrap_or(span);
        if self.given.set.audit_energy {
            // ground and friction work: ∫ v·ẍ dτ (cubic integrand: 3-point Gauss is exact)
            self.tally.audit.work += gauss3(tau_end, |tau| vel(tau) * (acc0 + acc1 * tau));
        }
        ss.x = st.x
            + st.v * tau_end
            + 0.5 * acc0 * tau_end * tau_end
            + acc1 * dm::powi(tau_end, 3) / 6.0;
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
    pub(super) fn slide_rock<const N: usize>(
        &mut self,
        sr: &mut SlideRockState,
        seg: &Segment,
        t: &mut f64,
        t_end: f64,
    ) -> Result<Option<Event>> {
        let mu_k = self.given.fric.mu_k;
        let bl = self.given.bl;
        let (s, sg) = (sr.s, sr.sigma);
        let seg = *seg;
        let rhs = |tt: f64, y: &[f64; N]| -> [f64; N] {
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
        let mut released = sr.vp == 0.0;
        let (t_stop, event, ye) =
            self.dopri_to_event("slide-rock", rhs, *t, y, t_end, tol, |run, step, ta, t1| {
                let xtol = 1e-15 * t1.abs().max(1.0);
                let comp = |i: usize, tt: f64| step.component_at(i, tt);
                let mut best: Option<(f64, Event)> = None;
                // One minimum per step suffices for ψ (and π/2 − ψ): ẍg does not
                // enter slide-rock's ψ″ = sα = −s r c q / den (`physics::slide_rock_accel`;
                // den > 0 before a jam, and N = q I / den > 0 before lift-off,
                // so q > 0), whose sign changes only where s c = sin φ + sσ μk cos φ
                // = 0, at an angle that repels ψ (s c falls as ψ rises there): ψ
                // crosses it at most once, with ψ′ of one sign, so ψ has one
                // extremum at most in a step.
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
                // the slip velocity can only start at 0 on the first step
                released = false;
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
                run.tally.out.theta_max_over_theta_c =
                    run.tally.out.theta_max_over_theta_c.max(ratio);
                best
            })?;
        if N == 5 {
            self.tally.audit.work += ye[4];
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
}

/// ∫₀^T f(τ) dτ by 3-point Gauss–Legendre (exact for polynomials of degree ≤ 5).
#[inline]
fn gauss3(span: f64, f: impl Fn(f64) -> f64) -> f64 {
    let half = 0.5 * span;
    let x = 0.6f64.sqrt();
    half * (5.0 / 9.0 * f(half * (1.0 - x)) + 8.0 / 9.0 * f(half) + 5.0 / 9.0 * f(half * (1.0 + x)))
}
