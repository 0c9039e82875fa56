//! The chatter rule (`settle_cascades`, e > 0, infinite friction): the tail of
//! a series of shrinking bounces of one corner is closed in one step, with
//! its drift, rotation and duration summed in closed form (the derivation is
//! in the driver's module documentation).

use super::{RockState, Run, SeriesEnd, State};
use crate::solver::impact::{self, Velocity};
use crate::solver::physics as ph;

/// Longest window, in record samples, over which the bounds are sought (a
/// series closed below `CLOSE_TOL` lasts a few milliseconds).
const MAX_SAMPLES: usize = 8;

/// What a closed series leaves to the solver besides the plastic impact.
#[derive(Clone, Copy, Debug)]
pub(super) struct Chatter {
    /// Friction demand |P_t/P_n| of the series' later impacts.
    pub demand: f64,
    /// The same, as the paper's eq. (5) evaluates it.
    pub demand_eq5: f64,
    /// The correction applied at the series' end.
    pub end: SeriesEnd,
}

impl Run<'_> {
    /// Sums the series of bounces of a corner leaving the ground at `u0`
    /// (m/s) at `t0`, from the corner's free fall a = g + ÿg + ω² r_y and its
    /// tangential acceleration a_t = −ẍg − ω² r_x on the record's linear
    /// pieces: returns the corner's drift along the ground (m) and the series'
    /// duration (s). Each flight lasts τ, the root of u τ − a τ²/2 − ȧ τ³/6,
    /// drifts a_t τ²/2 + ȧ_t τ³/6 (the corner leaves each Newton impact with no
    /// tangential velocity), and lands at u − a τ − ȧ τ²/2, of which e
    /// rebounds; the geometric tail below 1e-2·u0 is summed with a and a_t
    /// held.
    fn series_sums(&self, t0: f64, u0: f64, w: f64, rx: f64, ry: f64) -> (f64, f64) {
        let bl = self.bl;
        let e = self.e;
        let n = self.acc.len();
        let (mut t, mut u, mut d) = (t0, u0, 0.0);
        let mut k = ((t0 / self.dt) as usize).min(n - 2);
        let mut seg = self.segment(k);
        let (w2x, w2y) = (w * w * rx, w * w * ry);
        if seg.v1 == 0.0 {
            // no vertical jerk: every flight lasts τₖ = eᵏ τ, τ = 2u0/a, and
            // starts at tₖ = t0 + τ (1 − eᵏ)/(1 − e), where a_t has moved by
            // −ẍg's slope: the sums are geometric
            let (ax, ay) = seg.at(t0);
            let a = bl.g + ay + w2y;
            let at = -ax - w2x;
            let tau = 2.0 * u0 / a;
            let duration = tau / (1.0 - e);
            if t0 + duration <= (k + 1) as f64 * self.dt {
                let (s2, s3) = (1.0 / (1.0 - e * e), 1.0 / (1.0 - e * e * e));
                let tau3 = tau * tau * tau;
                let d = 0.5 * at * tau * tau * s2
                    - seg.a1 * (0.5 * tau3 / (1.0 - e) * (s2 - s3) + tau3 * s3 / 6.0);
                return (d, duration);
            }
        }
        loop {
            while k + 2 < n && t >= (k + 1) as f64 * self.dt {
                k += 1;
                seg = self.segment(k);
            }
            let (ax, ay) = seg.at(t);
            let a = bl.g + ay + w2y;
            let at = -ax - w2x;
            if u < 1e-2 * u0 {
                // the tail, geometric: Σ τ² = τ²/(1 − e²), Σ τ = τ/(1 − e)
                let tau = 2.0 * u / a;
                d += 0.5 * at * tau * tau / (1.0 - e * e);
                t += tau / (1.0 - e);
                return (d, t - t0);
            }
            // the flight's time: u − (a/2) τ − (ȧ/6) τ² = 0, ȧ = d ÿg/dt
            let c = seg.v1 / 6.0;
            let tau = if c == 0.0 {
                2.0 * u / a
            } else {
                2.0 * u / (0.5 * a + (0.25 * a * a + 4.0 * c * u).sqrt())
            };
            d += (0.5 * at - seg.a1 * tau / 6.0) * tau * tau;
            t += tau;
            u = e * (a * tau + 0.5 * seg.v1 * tau * tau - u);
        }
    }

    /// The chatter rule: at an impact of corner `side` (offset (rx, ry) from
    /// G, the other corner off the ground or lifting) that leaves the corner
    /// rebounding at `u1` ∈ (ε√(gR), CLOSE_TOL·√(gR)] with velocity `newton`,
    /// while the same impact made plastic leaves `plastic` (rock about the
    /// corner), decides from bounds on the coming samples whether the series
    /// converges onto rock about the corner before anything else can happen.
    /// Returns the series' closed-form sums if so.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn chatter_settles(
        &self,
        t: f64,
        theta: f64,
        side: f64,
        rx: f64,
        ry: f64,
        newton: &Velocity,
        u1: f64,
        plastic: &Velocity,
    ) -> Option<Chatter> {
        let bl = self.bl;
        let n = self.acc.len();
        let e = self.e;
        // rock about corner `side` means θ on the side s = −side
        let s = -side;
        if !self.set.settle_cascades
            || self.fric.is_some()
            || !(e > 0.0 && e < 1.0)
            || s * theta < 0.0
            || (theta == 0.0 && !(s * plastic.omega > 0.0 && 3.0 * bl.sin_c * bl.sin_c < 1.0))
            || n < 2
        {
            return None;
        }
        let i = bl.inertia;
        // the corner's inverse-mass matrix K⁻¹ = [[a, b], [b, c]] (impact.rs)
        let (ka, kb, kc) = (1.0 + ry * ry / i, -rx * ry / i, 1.0 + rx * rx / i);
        let det = ka * kc - kb * kb;
        // a rebound u⁺ leaves ω off the plastic (rock) value by ΔP = K (0, u⁺):
        // |Δω| = |rx ΔP_n − ry ΔP_t|/I ≤ k_w u⁺
        let k_w = (kb.abs() * ry.abs() + ka * rx.abs()) / (det * i);
        let w0 = plastic.omega.abs();
        let kk = 0.75 / bl.r; // eq. (1): I_O = 4mR²/3
        let psi = s * theta;
        let k0 = ((t / self.dt) as usize).min(n - 2);
        let (ax0, ay0) = self.segment(k0).at(t);
        // over the window: the smallest g + ÿg, the largest |ẍg|, |g + ÿg| and
        // |d ÿg/dt|, and the smallest N of rock at (θ, ω_p) (affine in the
        // forcing, linear between samples: extremes at the ends and samples)
        let mut gmin = bl.g + ay0;
        let (mut ax_max, mut gy_max, mut rate_v) = (ax0.abs(), (bl.g + ay0).abs(), 0.0_f64);
        let (sp, cp) = bl.phi_sin_cos(psi);
        let rock_n =
            |ax: f64, ay: f64| ph::rock_contact_sc(&bl, s, sp, cp, plastic.omega, ax, ay).n;
        let mut n_min = rock_n(ax0, ay0);
        for k in k0..(k0 + MAX_SAMPLES).min(n - 1) {
            let seg = self.segment(k);
            let tw = (k + 1) as f64 * self.dt;
            let (ax, ay) = seg.at(tw);
            gmin = gmin.min(bl.g + ay);
            ax_max = ax_max.max(ax.abs());
            gy_max = gy_max.max((bl.g + ay).abs());
            rate_v = rate_v.max(seg.v1.abs());
            n_min = n_min.min(rock_n(ax, ay));
            let span = tw - t;
            // eq. (1): |θ̈| ≤ k (|ẍg| cosφ + |g + ÿg| |sinφ|), φ = θc − ψ; while
            // ψ ∈ [0, θc] (checked below) |sinφ| ≤ sinθc
            let alpha_max = kk * (ax_max + gy_max * bl.sin_c);
            // every ω of the series, in flight or rock, over a span ≤ `span`
            let w_max = w0 + alpha_max * span + k_w * u1;
            // free flight: the corner falls at a = g + ÿg + ω² r_y ≥ g + ÿg − ω²R
            let lo = gmin - w_max * w_max * bl.r;
            if lo <= 0.0 {
                return None;
            }
            // within one flight (≤ 4u1/lo while x ≤ lo/2) a strays from its start
            // by x = (|d ÿg/dt| + ω³R)·τ (ÿg's slope; r_y turning at ω)
            let x = (rate_v + w_max * w_max * w_max * bl.r) * 4.0 * u1 / lo;
            if x > 0.5 * lo {
                return None;
            }
            // a flight leaving at u lands at most √((lo + x)/(lo − x)) faster, and
            // the impact returns e times that: uₖ ≤ ρᵏ u1
            let rho = e * ((lo + x) / (lo - x)).sqrt();
            if rho >= 1.0 {
                return None;
            }
            // Σ τₖ ≤ Σ 2uₖ/(lo − x): the series ends within T
            let t_series = 2.0 * u1 / ((lo - x) * (1.0 - rho));
            if t_series > span {
                continue;
            }
            // The series strays from rock about the corner along the impact's
            // normal mode only: the corner's height h (≤ u1²/(2(lo − x)), the
            // first flight's apex) moves θ by at most k_w h.
            let dev = k_w * u1 * u1 / (2.0 * (lo - x));
            // The rotation of rock about the corner stays within [ψ_lo, ψ + Δ]
            // over T: ψ(τ) ≥ ψ + vτ − θ̈_max τ²/2 (v = ψ̇ at the start), a
            // concave bound whose least value on [0, T] is at an end.
            let dtheta = w_max * t_series;
            if psi + dtheta + dev > bl.theta_c {
                return None;
            }
            let v = s * plastic.omega;
            let psi_end = psi + v * t_series - 0.5 * alpha_max * t_series * t_series;
            if psi == 0.0 {
                // a rock impact: rock about the new corner leaves ψ = 0 with
                // v > 0 and is positive on (0, T] if it is at T; the old corner,
                // lifted by the rebound's normal mode as well (1 − 3 sin²θc > 0),
                // stays off the ground
                if psi_end <= dev {
                    return None;
                }
            } else if psi.min(psi_end) <= dev {
                return None;
            }
            // rock about the corner keeps N > 0 over T: N moves by at most
            // R (ω_max² − ω_p²) (centripetal) and R (Δθ |θ̈| + sinθc |Δθ̈|)
            if n_min <= bl.r * (w_max * w_max - w0 * w0 + 2.0 * kk * dtheta * (ax_max + gy_max)) {
                return None;
            }
            // The later impacts of the series: each meets the corner after a
            // flight of τ = 2u/a with G's velocity changed by (−ẍg τ, −(g + ÿg) τ),
            // so their impulse ratio is the same for every u; one gives the demand.
            let a = bl.g + ay0 + newton.omega * newton.omega * ry;
            let tau = 2.0 * u1 / a;
            let before = Velocity {
                vx: newton.vx - ax0 * tau,
                vy: newton.vy - (bl.g + ay0) * tau,
                omega: newton.omega,
            };
            let r = impact::corner_impact(&bl, &before, rx, ry, e, self.set.impact);
            let demand = r.friction_demand();
            let demand_eq5 = impact::eq5_mu(&bl, &before, rx, ry, e);
            // The sums: the drift D, and from it the rotation and the angular
            // velocity the series gains against rock about the corner (module
            // documentation): Δθ = −(3/4R²) r_y D, Δθ̇ = (3/4R²) θ̇ r_x D.
            let (dx, duration) = self.series_sums(t, u1, newton.omega, rx, ry);
            if duration > t_series {
                // the sums disagree with the bound (cannot happen: they follow
                // the same flights); follow the bounces
                return None;
            }
            let k_i = 0.75 / (bl.r * bl.r);
            return Some(Chatter {
                demand,
                demand_eq5,
                end: SeriesEnd {
                    t: t + duration,
                    s,
                    dtheta: -k_i * ry * dx,
                    domega_rel: k_i * rx * dx,
                    dx,
                },
            });
        }
        None
    }
}

impl Run<'_> {
    /// Applies the correction of a closed bounce series at its end to the rock
    /// state it left (none if the block has left that rock since).
    pub(super) fn end_series(&mut self, state: &mut State) {
        let Some(end) = self.series_end.take() else {
            return;
        };
        let State::Rock(rs) = *state else {
            return;
        };
        if rs.s != end.s {
            return;
        }
        let before = if self.set.audit_energy {
            self.energy(state)
        } else {
            0.0
        };
        *state = State::Rock(RockState {
            theta: rs.theta + end.dtheta,
            omega: rs.omega + end.domega_rel * rs.omega,
            last: None,
            ..rs
        });
        self.x_base += end.dx;
        if self.set.audit_energy {
            self.jumps += self.energy(state) - before;
        }
        self.note_theta(state);
        self.note_slip(state);
    }
}
