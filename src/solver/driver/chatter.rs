//! The chatter rule (`settle_cascades`, e > 0; infinite friction, or Coulomb
//! friction with Newton's law while nothing slips): the tail of
//! a series of shrinking bounces of one corner is closed in one step, with
//! its drift, rotation and duration summed in closed form (the derivation is
//! in the driver's module documentation).

use super::{Chatter, ChatterImpact, RockState, Run, SeriesEnd, SeriesSums};
use crate::solver::impact::{self, Velocity};
use crate::solver::physics as ph;

/// Longest window, in record samples, over which the bounds are sought (a
/// series closed below `CLOSE_TOL` lasts a few milliseconds).
const MAX_SAMPLES: usize = 8;

impl Run<'_> {
    /// Sums the series of bounces of a corner leaving the ground at `u0`
    /// (m/s) at `t0`, with offset (rx, ry) from G, while the block would rock
    /// about it with θ̇ = `w_p` (the plastic impact's). The flight's ω is
    /// θ̇ + u r_x/I_B (the angular momentum about the corner is the rock's),
    /// θ̇ = w_p + θ̈ τ and the offset turns with θ; the corner falls at
    /// a = g + ÿg + ω² r_y and moves along the ground at a_t = −ẍg − ω² r_x,
    /// which change in a flight at ȧ = d ÿg/dt + ω³ r_x, ȧ_t = −d ẍg/dt + ω³ r_y.
    /// Each flight lasts τ, the root of u τ − a τ²/2 − ȧ τ³/6, drifts
    /// a_t τ²/2 + ȧ_t τ³/6 (the corner leaves each Newton impact with no
    /// tangential velocity), and lands at u − a τ − ȧ τ²/2, of which e
    /// rebounds. Flight by flight until the rest of the series lies inside
    /// one sample of the record, where the forcing is linear; that rest is
    /// summed in closed form ([`geometric_sums`]).
    fn series_sums(&self, t0: f64, u0: f64, w_p: f64, rx: f64, ry: f64) -> SeriesSums {
        let bl = self.given.bl;
        let e = self.given.e;
        let n = self.samples();
        let i_b = bl.inertia_corner();
        let mut k = ((t0 / self.given.dt) as usize).min(n - 2);
        let mut seg = self.segment(k);
        // rock about the corner at the start: eq. (1) as I_B θ̈ = (g + ÿg) r_x − ẍg r_y
        let (ax0, ay0) = seg.at(t0);
        let alpha = ((bl.g + ay0) * rx - ax0 * ry) / i_b;
        let mut sums = SeriesSums::default();
        let (mut t, mut u) = (t0, u0);
        loop {
            while k + 2 < n && t >= (k + 1) as f64 * self.given.dt {
                k += 1;
                seg = self.segment(k);
            }
            let (ax, ay) = seg.at(t);
            // rock's θ̇ and turn since t0; the corner's offset turned by it (to
            // second order in the turn)
            let el = t - t0;
            let w_r = w_p + alpha * el;
            let turn = w_p * el + 0.5 * alpha * el * el;
            let (cx, cy) = (
                rx - turn * ry - 0.5 * turn * turn * rx,
                ry + turn * rx - 0.5 * turn * turn * ry,
            );
            let w = w_r + u * cx / i_b;
            let w2 = w * w;
            let a = bl.g + ay + w2 * cy;
            // the rest of the series, to leading order, inside this sample (or
            // the record's last): summed in closed form
            if t + 2.0 * u / (a * (1.0 - e)) <= (k + 1) as f64 * self.given.dt || k + 2 >= n {
                let rest = geometric_sums(&GeometricStart {
                    e,
                    u,
                    w_r,
                    alpha,
                    r: (cx, cy),
                    i_b,
                    ground: (ax, bl.g + ay),
                    slopes: (seg.a1, seg.v1),
                });
                sums.j += sums.d * rest.duration + rest.j;
                sums.d += rest.d;
                sums.u_tau2 += rest.u_tau2;
                sums.u2_tau += rest.u2_tau;
                sums.at2_tau3 += rest.at2_tau3;
                sums.at_u_tau2 += rest.at_u_tau2;
                sums.duration = t - t0 + rest.duration;
                return sums;
            }
            let at = -ax - w2 * cx;
            let w3 = w2 * w;
            let a_dot = seg.v1 + w3 * cx;
            let at_dot = -seg.a1 + w3 * cy;
            // the flight's time: u − (a/2) τ − (ȧ/6) τ² = 0
            let c = a_dot / 6.0;
            let tau = 2.0 * u / (0.5 * a + (0.25 * a * a + 4.0 * c * u).max(0.0).sqrt());
            let (tau2, tau3) = (tau * tau, tau * tau * tau);
            sums.j += sums.d * tau + at * tau3 / 6.0;
            sums.d += (0.5 * at + at_dot * tau / 6.0) * tau2;
            sums.u_tau2 += u * tau2;
            sums.u2_tau += u * u * tau;
            sums.at2_tau3 += at * at * tau3;
            sums.at_u_tau2 += at * u * tau2;
            t += tau;
            u = e * (a * tau + 0.5 * a_dot * tau2 - u);
        }
    }

    /// The chatter rule: at the impact `imp` of corner `side` at `t` (offset
    /// (rx, ry) from G, the other corner off the ground or lifting) that
    /// leaves the corner rebounding at `u1` ∈ (ε√(gR), CLOSE_TOL·√(gR)] with
    /// velocity `newton`, while the same impact made plastic leaves `plastic`
    /// (rock about the corner), decides from bounds on the coming samples
    /// whether the series converges onto rock about the corner before
    /// anything else can happen. Returns the series' closed-form sums if so.
    pub(super) fn chatter_settles(&self, imp: &ChatterImpact) -> Option<Chatter> {
        let ChatterImpact {
            t,
            theta,
            side,
            rx,
            ry,
            newton,
            u1,
            plastic,
        } = *imp;
        let bl = self.given.bl;
        let n = self.samples();
        let e = self.given.e;
        // rock about corner `side` means θ on the side s = −side
        let s = -side;
        if !(self.given.set.settle_cascades && e > 0.0 && e < 1.0)
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
        let k0 = ((t / self.given.dt) as usize).min(n - 2);
        let (ax0, ay0) = self.segment(k0).at(t);
        // over the window: the smallest g + ÿg, the largest |ẍg|, |g + ÿg| and
        // |d ÿg/dt|, and the smallest N of rock at (θ, ω_p) (affine in the
        // forcing, linear between samples: extremes at the ends and samples)
        let mut gmin = bl.g + ay0;
        let (mut ax_max, mut gy_max, mut rate_v) = (ax0.abs(), (bl.g + ay0).abs(), 0.0_f64);
        // With Coulomb friction (Newton's law, `chatter_due`) the series is
        // that of infinite friction while nothing slips: the caller checked
        // that this impact sticks; the later ones are bounded below, and the
        // rock about the corner over the series by its smallest friction
        // margin μs N − |F| at (θ, ω_p) (concave in the forcing).
        let mu_s = self.given.fric.mu_s;
        let (sp, cp) = bl.phi_sin_cos(psi);
        let rock_c = |ax: f64, ay: f64| ph::rock_contact_sc(&bl, s, sp, cp, plastic.omega, ax, ay);
        let margin = |c: ph::RockContact| {
            if mu_s.is_finite() {
                mu_s * c.n - c.f.abs()
            } else {
                f64::INFINITY
            }
        };
        let c0 = rock_c(ax0, ay0);
        let (mut n_min, mut f_min) = (c0.n, margin(c0));
        for k in k0..(k0 + MAX_SAMPLES).min(n - 1) {
            let seg = self.segment(k);
            let tw = (k + 1) as f64 * self.given.dt;
            let (ax, ay) = seg.at(tw);
            gmin = gmin.min(bl.g + ay);
            ax_max = ax_max.max(ax.abs());
            gy_max = gy_max.max((bl.g + ay).abs());
            rate_v = rate_v.max(seg.v1.abs());
            let c = rock_c(ax, ay);
            n_min = n_min.min(c.n);
            f_min = f_min.min(margin(c));
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
            if mu_s.is_finite() {
                // Rock about the corner does not slip over T: F moves by at most
                // R ω_max² (centripetal, either way) and, like N, by
                // 2 R k Δθ (|ẍg| + |g + ÿg|), so μs N − |F| by (1 + μs) times that.
                let dev_f = bl.r * (w_max * w_max + 2.0 * kk * dtheta * (ax_max + gy_max));
                if f_min <= (1.0 + mu_s) * dev_f {
                    return None;
                }
                // The later impacts stick. Each meets the corner after a flight of
                // τ ≤ 2u/(lo − x) from no tangential velocity (Newton's stick), so
                // at a tangential speed |u_t| ≤ |a_t| τ, |a_t| = |ẍg + ω² r_x| ≤
                // |ẍg| + ω_max² R, and a normal one |u_n| ≥ u √((lo − x)/(lo + x)):
                // ζ = |u_t/u_n| ≤ ζmax. The sticking impulse P = K Δu, Δu =
                // (−u_t, −(1 + e) u_n), has |P_t/P_n| ≤ (c ζ + |b|(1 + e))/(a(1 + e)
                // − |b| ζ) with K⁻¹ = [[a, b], [b, c]] (impact.rs), taken at
                // their worst over the series, in which the corner's offset turns
                // by at most δ = Δθ + k_w h (|Δr_x|, |Δr_y| ≤ R δ).
                let at_max = ax_max + w_max * w_max * bl.r;
                let zeta = 2.0 * at_max / (lo - x) * ((lo + x) / (lo - x)).sqrt();
                let dr = bl.r * (dtheta + dev);
                let (rx_hi, ry_hi) = (rx.abs() + dr, ry.abs() + dr);
                let ry_lo = (ry.abs() - dr).max(0.0);
                let (ka_lo, kb_hi, kc_hi) = (
                    1.0 + ry_lo * ry_lo / i,
                    rx_hi * ry_hi / i,
                    1.0 + rx_hi * rx_hi / i,
                );
                let num = kc_hi * zeta + kb_hi * (1.0 + e);
                let den = ka_lo * (1.0 + e) - kb_hi * zeta;
                if !(den > 0.0 && num <= mu_s * (1.0 - 1e-12) * den) {
                    return None;
                }
            }
            // The later impacts of the series: each meets the corner after a
            // flight of τ = 2u/a with G's velocity changed by (−ẍg τ, −(g + ÿg) τ),
            // so their impulse ratio is the same for every u; one gives the demand.
            let (demand, demand_eq5) = self.later_impact_demand(&newton, rx, ry, u1, ax0, ay0);
            // The series' sums (drift, duration, the third-order sums); the
            // correction they make to rock about the corner, taken at the
            // drift's centroid, is carried back to this impact by
            // `close_series` (module documentation).
            let sums = self.series_sums(t, u1, plastic.omega, rx, ry);
            if sums.duration > t_series {
                // the sums disagree with the bound (cannot happen: they follow
                // the same flights); follow the bounces
                return None;
            }
            // the drift's centroid t* = T − ∫D dt / D
            let lag = if sums.d != 0.0 {
                (sums.j / sums.d).clamp(0.0, sums.duration)
            } else {
                0.0
            };
            return Some(Chatter {
                demand,
                demand_eq5,
                end: SeriesEnd {
                    t: t + sums.duration - lag,
                    sums,
                },
            });
        }
        None
    }
}

impl Run<'_> {
    /// The friction demand |P_t/P_n| (and the paper's eq. (5)) of the later
    /// impacts of a bounce series of the corner at (rx, ry) that rebounds at
    /// `u1` with the block's velocity `newton`, under the ground (ẍg, ÿg) =
    /// (`ax`, `ay`): each meets the corner after a flight of τ = 2u/a with G's
    /// velocity changed by (−ẍg τ, −(g + ÿg) τ), so their impulse ratio is
    /// the same for every u; one gives the demand.
    pub(super) fn later_impact_demand(
        &self,
        newton: &Velocity,
        rx: f64,
        ry: f64,
        u1: f64,
        ax: f64,
        ay: f64,
    ) -> (f64, f64) {
        let bl = self.given.bl;
        let a = bl.g + ay + newton.omega * newton.omega * ry;
        let tau = 2.0 * u1 / a;
        let before = Velocity {
            vx: newton.vx - ax * tau,
            vy: newton.vy - (bl.g + ay) * tau,
            omega: newton.omega,
        };
        let r = impact::corner_impact(&bl, &before, rx, ry, self.given.e, self.given.set.impact);
        (
            r.friction_demand(),
            impact::eq5_mu(&bl, &before, rx, ry, self.given.e),
        )
    }

    /// The rock state a closed bounce series leaves at `t0`, the instant it
    /// is closed: `rs`, rock about the corner from the plastic impact, with
    /// the series' correction (module documentation) carried back from the
    /// drift's centroid t* = t0 + L to t0. Rock's state at t* is expanded
    /// about t0 to second order in L (ρ̇ = θ̇ ρ⊥, θ̈ and its rate from eq. (1)
    /// and the ground's slopes), the correction Δ(t*) taken there, and carried
    /// back along rock's linearised motion z′ = M z (z = (δθ, δp), M = [[0,
    /// 1/I_B], [F_θ, 0]], F_θ = −V_θθ):
    ///
    /// ```text
    /// Δ(t0) = [I − M L + (M² − M′) L²/2] Δ(t*)
    /// ```
    ///
    /// The neglected terms are of fifth order in the rebound (L is first
    /// order, Δ second, and the flow's curvature acts on Δ²), so the closure
    /// keeps its fourth-order error, and rock goes on from t0 with no stop at
    /// t*. Also moves the footprint by the drift D.
    pub(super) fn close_series(&mut self, t0: f64, rs: RockState, end: &SeriesEnd) -> RockState {
        let bl = self.given.bl;
        let m = &end.sums;
        let l = end.t - t0;
        let i_b = bl.inertia_corner();
        // ρ = G − B from the pivot's offset r; eq. (1) in these terms:
        // I_B θ̈ = F = −V_θ, V = (g + ÿg) ρ_y + ẍg ρ_x, so F = ẍg ρ_y − (g + ÿg) ρ_x
        // and F_θ = −V_θθ = (g + ÿg) ρ_y + ẍg ρ_x
        let (rx, ry) = bl.corner_offset(-rs.s, rs.theta);
        let (px, py) = (-rx, -ry);
        let k = ((t0 / self.given.dt) as usize).min(self.samples() - 2);
        let seg = self.segment(k);
        let (ax, ay) = seg.at(t0);
        let gy = bl.g + ay;
        let w = rs.omega;
        let alpha = (ax * py - gy * px) / i_b;
        let f_th = gy * py + ax * px;
        // dθ̈/dt = (F_θ θ̇ + ∂F/∂t)/I_B, and dF_θ/dt = (∂F_θ/∂θ) θ̇ + ∂F_θ/∂t
        let alpha_dot = (f_th * w + seg.a1 * py - seg.v1 * px) / i_b;
        let f_th_dot = (gy * px - ax * py) * w + seg.v1 * py + seg.a1 * px;
        // rock at t*: θ̇, the turn, ρ turned by it, and the ground
        let w_s = w + alpha * l + 0.5 * alpha_dot * l * l;
        let (sn, cs) = ph::sin_cos_small(w * l + 0.5 * alpha * l * l);
        let (px_s, py_s) = (px * cs - py * sn, px * sn + py * cs);
        let (ax_s, ay_s) = self.ground_at(end.t);
        let gy_s = bl.g + ay_s;
        let alpha_s = (ax_s * py_s - gy_s * px_s) / i_b;
        let v_tt_s = -gy_s * py_s - ax_s * px_s;
        // the correction at t*: second order I_B Δθ = ρ_y D, Δp = −θ̇ ρ_x D;
        // third order: the corner's mean height Y = Σ u τ²/6 and the products
        // of its velocity (module documentation)
        let y = m.u_tau2 / 6.0;
        let dth_s = (py_s * m.d - 2.0 * w_s * py_s * y) / i_b;
        let q = -px_s * py_s * m.at2_tau3 / 3.0 - (px_s * px_s - py_s * py_s) * m.at_u_tau2 / 6.0
            + px_s * py_s * m.u2_tau / 3.0;
        let dp_s = -w_s * px_s * m.d
            + (alpha_s * py_s + w_s * w_s * px_s) * y
            + (q + v_tt_s * px_s * y) / i_b;
        // carried back to t0: Δ − M L Δ + (M² − M′) L² Δ/2, M² = (F_θ/I_B) I
        let (l2, fi) = (0.5 * l * l, f_th / i_b);
        let dtheta = dth_s - l * dp_s / i_b + l2 * fi * dth_s;
        let dp = dp_s - l * f_th * dth_s + l2 * (fi * dp_s - f_th_dot * dth_s);
        self.x_base += m.d;
        RockState {
            theta: rs.theta + dtheta,
            omega: rs.omega + dp / i_b,
            last: None,
            ..rs
        }
    }
}

/// Where a bounce series (or its rest) starts, for [`geometric_sums`].
struct GeometricStart {
    /// Coefficient of restitution.
    e: f64,
    /// Rebound of the first flight (m/s).
    u: f64,
    /// θ̇ of rock about the corner (rad/s) and its θ̈ (rad/s²).
    w_r: f64,
    alpha: f64,
    /// The corner's offset from G (m).
    r: (f64, f64),
    /// Inertia about the corner per unit mass, 4R²/3 (m²).
    i_b: f64,
    /// ẍg and g + ÿg (m/s²).
    ground: (f64, f64),
    /// d ẍg/dt and d ÿg/dt (m/s³).
    slopes: (f64, f64),
}

/// The sums of a bounce series under forcing linear in time, in closed form
/// to first order in its small parameters. At zeroth order flight k leaves
/// at uₖ = eᵏu, lasts τₖ = eᵏq (q = 2u/G) and starts at tₖ = q(1 − eᵏ)/(1 − e),
/// so Σ τₖ², Σ τₖ³ … are geometric (s1 = 1/(1 − e), s2 = 1/(1 − e²),
/// s3 = 1/(1 − e³)). To first order the corner's fall and tangential
/// acceleration move along the series, a = G + G_t t + G_u u and
/// a_t = A + A_t t + A_u u (the ground's slopes, the rock's θ̈ and turn, and
/// the flight's ω = θ̇ + u r_x/I_B), and within a flight at ȧ and ȧ_t, which
/// shortens it by c u (c = 2ȧ/(3G²)) and lands it c u faster. Then
///
/// ```text
/// τₖ = q eᵏ [1 + (P − Q_t)(1 − eᵏ) − (Q_u + c u) eᵏ],  P = c u s1, Q_t = G_t q s1/G, Q_u = G_u u/G
/// D  = q²/2 {A [s2 + 2(P − Q_t)(s2 − s3) − 2(Q_u + c u) s3] + A_t q s1 (s2 − s3) + A_u u s3} + ȧ_t q³ s3/6
/// T  = q [s1 + (P − Q_t)(s1 − s2) − (Q_u + c u) s2]
/// ```
///
/// and, to leading order, ∫D dt = A q³ [s2 (s1 − s3)/2 + s3/6] and the
/// third-order sums from the first flight times s3.
fn geometric_sums(g: &GeometricStart) -> SeriesSums {
    let e = g.e;
    let (s1, s2, s3) = (
        1.0 / (1.0 - e),
        1.0 / (1.0 - e * e),
        1.0 / (1.0 - e * e * e),
    );
    let (rx, ry) = g.r;
    let (ax, gy) = g.ground;
    let (ax1, ay1) = g.slopes;
    let (w, u) = (g.w_r, g.u);
    let (w2, w3) = (w * w, w * w * w);
    // fall and tangential acceleration at the start, and their rates along
    // the series (time, rebound) and within a flight
    let big_g = gy + w2 * ry;
    let g_t = ay1 + 2.0 * w * g.alpha * ry + w3 * rx;
    let g_u = 2.0 * w * rx * ry / g.i_b;
    let a = -ax - w2 * rx;
    let a_t = -ax1 - 2.0 * w * g.alpha * rx + w3 * ry;
    let a_u = -2.0 * w * rx * rx / g.i_b;
    let a_dot = ay1 + w3 * rx;
    let at_dot = -ax1 + w3 * ry;
    let q = 2.0 * u / big_g;
    let cu = 2.0 * a_dot * u / (3.0 * big_g * big_g);
    let p = cu * s1;
    let q_t = g_t * q * s1 / big_g;
    let q_u = g_u * u / big_g;
    let (q2, q3) = (q * q, q * q * q);
    let d = 0.5
        * q2
        * (a * (s2 + 2.0 * (p - q_t) * (s2 - s3) - 2.0 * (q_u + cu) * s3)
            + a_t * q * s1 * (s2 - s3)
            + a_u * u * s3)
        + at_dot * q3 * s3 / 6.0;
    let duration = q * (s1 + (p - q_t) * (s1 - s2) - (q_u + cu) * s2);
    SeriesSums {
        duration,
        d,
        j: a * q3 * (0.5 * s2 * (s1 - s3) + s3 / 6.0),
        u_tau2: u * q2 * s3,
        u2_tau: u * u * q * s3,
        at2_tau3: a * a * q3 * s3,
        at_u_tau2: a * u * q2 * s3,
    }
}
