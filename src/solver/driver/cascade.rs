//! The cascade rule (`settle_cascades`): a cascade of shrinking rock impacts
//! that bounds over the coming samples prove dies out before the ground can
//! lift the block is set to rest at once (the driver's module documentation
//! derives the bounds). With e = 0 the block rocks from impact to impact;
//! with e > 0 each rock impact also starts a series of bounces on the new
//! corner, which the chatter rule closes (`chatter.rs`), and the bounds take
//! in what such a series can change ([`Run::series_bounds`]). Under Coulomb
//! friction the rule applies while nothing in the cascade can slip.

use super::{ChatterImpact, RockState, Run};
use crate::outcome::Mode;
use crate::solver::block::Block;
use crate::solver::impact::{self, ImpactLaw, Velocity};
use crate::solver::physics as ph;

/// Longest window, in record samples, over which the bounds are sought.
const MAX_SAMPLES: usize = 64;

/// Bounds on the forcing over a window of the record, at θ = 0 and θ̇ = 0
/// (all affine in the forcing, which is linear between samples, or concave
/// in it: extremes at the window's ends and at samples).
#[derive(Clone, Copy, Debug)]
struct Window {
    /// The smallest restoring acceleration A_s of eq. (1), either side (rad/s²).
    lo_min: f64,
    /// The largest |ẍg| and |g + ÿg| (m/s²).
    ax_max: f64,
    gy_max: f64,
    /// The smallest N − (g + ÿg)/2 of rock, either side (m/s²).
    n_margin: f64,
    /// With Coulomb friction, the smallest μs N − |F| of rock, either side,
    /// and μs (g + ÿg) − |ẍg| of rest (m/s²; infinite otherwise).
    f_margin: f64,
    rest_margin: f64,
    /// The largest A_s, either side (rad/s²), and the smallest g + ÿg (m/s²).
    a_hi: f64,
    g_min: f64,
    /// The largest |dẍg/dt| and |dÿg/dt| (m/s³).
    rate_a: f64,
    rate_v: f64,
}

impl Window {
    /// Takes in the ground (ẍg, ÿg) = (`ax`, `ay`) of one instant; the
    /// friction margins only with `FRICTION` (μs finite), A_hi and
    /// min(g + ÿg) only for a `BOUNCING` cascade (e > 0).
    #[inline(always)]
    fn include<const FRICTION: bool, const BOUNCING: bool>(
        &mut self,
        bl: &Block,
        mu_s: f64,
        ax: f64,
        ay: f64,
    ) {
        for s in [-1.0, 1.0] {
            let c = ph::rock_contact_sc(bl, s, bl.sin_c, bl.cos_c, 0.0, ax, ay);
            // eq. (1) at θ = 0 on side s: ψ̈ = sθ̈ = −A_s
            self.lo_min = self.lo_min.min(-s * c.alpha);
            self.n_margin = self.n_margin.min(c.n - 0.5 * (bl.g + ay));
            if FRICTION {
                self.f_margin = self.f_margin.min(mu_s * c.n - c.f.abs());
            }
            if BOUNCING {
                self.a_hi = self.a_hi.max(-s * c.alpha);
            }
        }
        if FRICTION {
            self.rest_margin = self.rest_margin.min(mu_s * (bl.g + ay) - ax.abs());
        }
        self.ax_max = self.ax_max.max(ax.abs());
        self.gy_max = self.gy_max.max((bl.g + ay).abs());
        if BOUNCING {
            self.g_min = self.g_min.min(bl.g + ay);
        }
    }
}

/// What a bounce series started by a rock impact of a cascade (e > 0) can
/// do, at most, per power of the speed v of that impact (rad/s), for every
/// v up to the cascade's largest ([`Run::series_bounds`]).
#[derive(Clone, Copy, Debug)]
struct SeriesBounds {
    /// |Δθ| ≤ c_theta v² and |Δθ̇| ≤ c_omega v²: the series' correction to
    /// rock about the new corner (`Run::close_series`).
    c_theta: f64,
    c_omega: f64,
    /// The rotation the corner's bounces add on top of rock, ≤ dev v².
    dev: f64,
}

impl Run<'_> {
    /// The cascade rule (module documentation): true if the rock impacts that
    /// follow a rock impact at `t`, leaving the block in `rs` (θ = 0 for
    /// e = 0; for e > 0 the rock state its closed bounce series leaves),
    /// provably die out before the ground can lift the block. Then the
    /// cascade's friction demand is noted and the caller sets the block to
    /// rest. `series` is the impact at which the chatter rule closed this
    /// impact's bounce series (e > 0).
    ///
    /// Under Coulomb friction the cascade is the same motion, impulse for
    /// impulse, as long as nothing slips (a sticking impact gives the
    /// infinite-friction impulse): its rock impacts strike at θ = 0, where
    /// the new corner moves straight down, so each asks for eq. (8)'s
    /// μ_imp whatever its speed, and sticks if μ_imp < μs; its bounces rock
    /// on a stuck corner while μs N − |F| > 0 (bounded below over the window
    /// like N); with e > 0 the impacts of its bounce series stick (bounded
    /// as in the chatter rule); and the rest it is set to must not break
    /// into sliding before the cascade would have ended, |ẍg| < μs (g + ÿg).
    pub(super) fn cascade_settles(
        &mut self,
        t: f64,
        rs: &RockState,
        series: Option<&ChatterImpact>,
    ) -> bool {
        let bl = self.given.bl;
        // Housner's ratio of angular velocities at a rock impact with e = 0
        // (with e > 0, that of the plastic impact that closes its series)
        let eta = impact::rock_impact_ratio(&bl, 0.0);
        let n = self.samples();
        let bouncing = self.given.e > 0.0;
        if !(self.given.set.settle_cascades && eta > 0.0 && eta < 1.0)
            || n < 2
            || (!bouncing && rs.theta != 0.0)
            // e > 0: only after a series the chatter rule closed, whose
            // analysis takes Newton's stick at every bounce (e < 1 there)
            || (bouncing && (series.is_none() || self.given.set.impact != ImpactLaw::Newton))
        {
            return false;
        }
        // μs, or infinity under infinite friction; the rock impacts must
        // stick: paper eq. (8), their friction demand, below μs
        let mu_s = self.given.fric.mu_s;
        if self.given.fric.finite() && impact::rock_impact_mu(&bl) >= mu_s {
            return false;
        }
        // one copy of the bounds per kind of cascade, each with only its own
        // terms (the e = 0, infinite-friction one as lean as it always was)
        match (mu_s.is_finite(), bouncing) {
            (false, false) => self.cascade_bounds::<false, false>(t, rs, series, eta, mu_s),
            (false, true) => self.cascade_bounds::<false, true>(t, rs, series, eta, mu_s),
            (true, false) => self.cascade_bounds::<true, false>(t, rs, series, eta, mu_s),
            (true, true) => self.cascade_bounds::<true, true>(t, rs, series, eta, mu_s),
        }
    }

    /// The bounds of [`Run::cascade_settles`] over the coming samples, for
    /// Housner's ratio `eta` and static friction `mu_s` (`FRICTION`: finite),
    /// of a cascade whose rock impacts bounce (`BOUNCING`: e > 0) or not.
    fn cascade_bounds<const FRICTION: bool, const BOUNCING: bool>(
        &mut self,
        t: f64,
        rs: &RockState,
        series: Option<&ChatterImpact>,
        eta: f64,
        mu_s: f64,
    ) -> bool {
        let bl = self.given.bl;
        let n = self.samples();
        let bouncing = BOUNCING;
        let u0 = rs.omega.abs();
        // e > 0: the rotation the series left, on the side the block rocks
        let psi0 = rs.s * rs.theta;
        let kk = 0.75 / bl.r; // eq. (1): I_O = 4mR²/3
        // Over the window: the smallest A_s (either side), the largest |ẍg| and
        // |g + ÿg|, the smallest N − (g + ÿg)/2 at θ = 0, θ̇ = 0 (all affine in
        // the forcing, which is linear between samples, so extremes are at the
        // window's ends and at samples), and the largest |dA_s/dt|.
        // With Coulomb friction also the smallest friction margins: μs N − |F|
        // of rock at θ = 0, θ̇ = 0 on either side, and μs (g + ÿg) − |ẍg| of
        // rest (concave in the forcing: least at the window's ends and samples).
        let mut w = Window {
            lo_min: f64::INFINITY,
            ax_max: 0.0,
            gy_max: 0.0,
            n_margin: f64::INFINITY,
            f_margin: f64::INFINITY,
            rest_margin: f64::INFINITY,
            a_hi: 0.0,
            g_min: f64::INFINITY,
            rate_a: 0.0,
            rate_v: 0.0,
        };
        let mut rate = 0.0_f64;
        let k0 = ((t / self.given.dt) as usize).min(n - 2);
        let k_end = (k0 + MAX_SAMPLES).min(n - 1);
        // the window's farthest end: a cascade bound past it never fits (the
        // bounds only grow with the window)
        let t_far = k_end as f64 * self.given.dt;
        let at_start = self.segment(k0).at(t);
        w.include::<FRICTION, BOUNCING>(&bl, mu_s, at_start.0, at_start.1);
        for k in k0..k_end {
            let seg = self.segment(k);
            let tw = (k + 1) as f64 * self.given.dt;
            let (ax, ay) = seg.at(tw);
            w.include::<FRICTION, BOUNCING>(&bl, mu_s, ax, ay);
            let Window {
                lo_min,
                ax_max,
                gy_max,
                n_margin,
                f_margin,
                rest_margin,
                a_hi,
                ..
            } = w;
            rate = rate.max(kk * (seg.v1.abs() * bl.sin_c + seg.a1.abs() * bl.cos_c));
            if bouncing {
                w.rate_a = w.rate_a.max(seg.a1.abs());
                w.rate_v = w.rate_v.max(seg.v1.abs());
            }
            // (with Coulomb friction: rock at θ = 0 would slip, or rest slide)
            if lo_min <= 0.0 || n_margin <= 0.0 || f_margin <= 0.0 || rest_margin <= 0.0 {
                // the ground can lift the block within the window, or the
                // pivot's normal force comes near 0 (bounds on N below)
                return false;
            }
            // e > 0: an excursion leaving θ = 0 at u from a rotation ψ0 left by
            // its series (|ψ0| small) rises no higher, lasts no longer and
            // lands no faster than one leaving ψ = 0 at U, U² = u² + 2 A_hi |ψ0|
            // (the bounds below, with u → U): the cascade starts at U0.
            let u0 = if bouncing {
                (u0 * u0 + 2.0 * a_hi * psi0.abs()).sqrt()
            } else {
                u0
            };
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
            let rho = if bouncing {
                // e > 0: the bounce series of each rock impact changes rock about
                // the new corner by |Δθ| ≤ c_θ v², |Δθ̇| ≤ c_ω v² (v: the impact's
                // speed, at most the cascade's fastest landing v_top), so the next
                // excursion leaves at u ≤ (η + c_ω v) v from |ψ0| ≤ c_θ v²: its
                // U ≤ η_e v, η_e² = (η + c_ω v_top)² + 2 A_hi c_θ
                let v_top = u0 * ((lo_min + x) / (lo_min - x)).sqrt();
                let Some(sb) = self.series_bounds(v_top, &w, psi_m, a_hi + x, eta, mu_s) else {
                    return false;
                };
                let eta_w = eta + sb.c_omega * v_top;
                let eta_e = (eta_w * eta_w + 2.0 * a_hi * sb.c_theta).sqrt();
                if psi_m + sb.dev * v_top * v_top
                    > self.tally.out.theta_max_over_theta_c * bl.theta_c
                {
                    // the cascade might set the peak rotation: follow it
                    return false;
                }
                eta_e * ((lo_min + x) / (lo_min - x)).sqrt()
            } else {
                eta * ((lo_min + x) / (lo_min - x)).sqrt()
            };
            if rho >= 1.0 {
                // a longer window only widens the bounds
                return false;
            }
            // Σ τₙ ≤ Σ 2uₙ/(lo_min − x) with uₙ ≤ ρⁿ u0
            let t_cascade = 2.0 * u0 / ((lo_min - x) * (1.0 - rho));
            if t + t_cascade > t_far {
                return false;
            }
            if t + t_cascade > tw {
                continue;
            }
            if psi_m > self.tally.out.theta_max_over_theta_c * bl.theta_c {
                // the cascade might set the peak rotation: follow it
                return false;
            }
            // The pivot stays in compression: N (eq. (1)'s reactions) exceeds
            // (g + ÿg)/2 over the window at θ = 0, θ̇ = 0 by n_margin, and a
            // bounce changes it by at most R u0² (the centripetal term) plus
            // R (ψm |θ̈| + sinθc |Δθ̈|) ≤ 2 R k ψm (|ẍg| + |g + ÿg|). (With
            // e > 0 the centripetal term takes the fastest landing.)
            let w2 = u0 * u0 * (lo_min + x) / (lo_min - x);
            let w2_n = if bouncing { w2 } else { u0 * u0 };
            if n_margin <= bl.r * (w2_n + 2.0 * kk * psi_m * (ax_max + gy_max)) {
                return false;
            }
            // Under Coulomb friction the bounces stick: F and N move from their
            // values at θ = 0, θ̇ = 0 by at most R w² (centripetal; w bounds every
            // speed of the cascade, its fastest landing) plus
            // R (ψm |θ̈| + |Δθ̈|) ≤ 2 R k ψm (|ẍg| + |g + ÿg|) each, so
            // μs N − |F| falls by at most (1 + μs) times that.
            if FRICTION {
                let dev = bl.r * (w2 + 2.0 * kk * psi_m * (ax_max + gy_max));
                if f_margin <= (1.0 + mu_s) * dev {
                    return false;
                }
            }
            // The cascade's friction demand: the contact forces at θ = 0,
            // θ̇ = 0 on either side at its two ends.
            let k1 = (((t + t_cascade) / self.given.dt) as usize).clamp(k0, k);
            let ends = [at_start, self.segment(k1).at(t + t_cascade)];
            let mut demand = 0.0_f64;
            for (ax, ay) in ends {
                for s in [-1.0, 1.0] {
                    let c = ph::rock_contact_sc(&bl, s, bl.sin_c, bl.cos_c, 0.0, ax, ay);
                    demand = demand.max(c.f.abs() / c.n);
                }
            }
            self.tally.out.mu_motion = self.tally.out.mu_motion.max(demand);
            // e > 0: the later impacts of its bounce series, on either corner
            // (mirror images), as the chatter rule takes them, at its two ends
            if let Some(&ChatterImpact {
                newton, rx, ry, u1, ..
            }) = series
            {
                let mirror = Velocity {
                    vx: -newton.vx,
                    vy: newton.vy,
                    omega: -newton.omega,
                };
                for (ax, ay) in ends {
                    for (v, rx) in [(newton, rx), (mirror, -rx)] {
                        let (d, d5) = self.later_impact_demand(&v, rx, ry, u1, ax, ay);
                        self.tally.out.mu_impact = self.tally.out.mu_impact.max(d);
                        self.tally.out.mu_impact_eq5 = self.tally.out.mu_impact_eq5.max(d5);
                    }
                }
            }
            // The cascade's duration, counted as rock rather than rest. On
            // the ground frozen at the cascade's start, side s restores at
            // A(ψ) = k[(g + ÿg) sin(θc − ψ) − s ẍg cos(θc − ψ)] = A_s − c_s ψ
            // + O(ψ²), so a bounce leaving at u lands at u after
            // (2/λ) atanh(uλ/A_s) = 2u/A_s + (2/3) c_s u³/A_s³ + O(u⁵),
            // λ² = c_s; the bounces alternate sides, bounce n leaving at
            // uₙ = ηⁿu0, so the sum is geometric (module documentation). It
            // ends within the window, where rest cannot break (capped at the
            // bound `t_cascade`, which it is below: A_s ≥ lo_min, η ≤ ρ).
            // (With e > 0, to leading order: its series change each bounce
            // by O(u²).)
            let u0 = rs.omega.abs();
            let (ax, gy) = (at_start.0, bl.g + at_start.1);
            let a_s = |s: f64| kk * (gy * bl.sin_c - s * ax * bl.cos_c);
            let c_s = |s: f64| kk * (gy * bl.cos_c + s * ax * bl.sin_c);
            let (a0, a1) = (a_s(rs.s), a_s(-rs.s));
            let (e2, e3) = (eta * eta, eta * eta * eta);
            let t_rock = (2.0 * u0 * (1.0 / a0 + eta / a1) / (1.0 - e2)
                + 2.0 / 3.0 * u0 * u0 * u0 / (1.0 - e3 * e3)
                    * (c_s(rs.s) / (a0 * a0 * a0) + e3 * c_s(-rs.s) / (a1 * a1 * a1)))
                .min(t_cascade);
            self.tally.out.time_in_mode[Mode::Rock.index()] += t_rock;
            self.tally.out.time_in_mode[Mode::Rest.index()] -= t_rock;
            // until the run ends, `end_time` holds when the last settled
            // cascade ends: a run that stops at rest after the record lasts
            // at least that long (its time in rest stays ≥ 0)
            self.tally.out.end_time = self.tally.out.end_time.max(t + t_rock);
            return true;
        }
        false
    }

    /// Bounds on a bounce series that a rock impact of a cascade (e > 0) at
    /// speed v ≤ `v_top` starts on the new corner, over the window `w`
    /// (rotations within `psi_m` of θ = 0, restoring accelerations of rock at
    /// most `a_up`), per power of v; `None` if they cannot be had, or if the
    /// series might not end before the block rocks back onto the old corner,
    /// or (μs finite) one of its impacts might slip.
    ///
    /// The corner strikes at 2B v (the base's length times θ̇) and rebounds
    /// at u_B ≤ e 2B v. Every ω of the series is at most v_top + k_w u_B
    /// (the rock's speed, at most the cascade's fastest landing, and the
    /// rebound's, `chatter_settles`), so as in the chatter rule the corner
    /// falls at a ≥ lo_B = min(g + ÿg) − ω²R, a strays within a flight by
    /// x_B, and the rebounds shrink by ρ_B = e √((lo_B + x_B)/(lo_B − x_B)).
    /// With τₖ ≤ c_τ uₖ, c_τ = 2/(lo_B − x_B), uₖ ≤ ρ_Bᵏ u_B, the sums of
    /// [`SeriesSums`](super::SeriesSums) are bounded by geometric sums
    /// (Σ τₖᵐ ≤ (c_τ u_B)ᵐ/(1 − ρ_Bᵐ), …), and so, term by term with
    /// |ρ_x|, |ρ_y| ≤ R, the correction `close_series` makes: its Δθ and Δθ̇
    /// at the drift's centroid and carried back by at most the series'
    /// duration. The series must end, with rock about the new corner still
    /// on its side above the bounces' own lift k_w h, before that rock can
    /// return: ψ(τ) ≥ u′τ − a_up τ²/2 − c_θ v² (u′ ≥ (η − c_ω v) v, the
    /// plastic impact's speed less the correction) must exceed k_w h at the
    /// series' longest duration T (a concave bound, so on all of (0, T]).
    fn series_bounds(
        &self,
        v_top: f64,
        w: &Window,
        psi_m: f64,
        a_up: f64,
        eta: f64,
        mu_s: f64,
    ) -> Option<SeriesBounds> {
        let bl = self.given.bl;
        let (e, r, i) = (self.given.e, bl.r, bl.inertia);
        let i_b = bl.inertia_corner();
        let kk = 0.75 / r; // eq. (1): I_O = 4mR²/3
        // the corner's offset from G within ψm of θ = 0: |r_x| ≤ B + H ψm,
        // |r_y| ≤ H + B ψm, |r_y| ≥ H − B ψm; K⁻¹ = [[a, b], [b, c]] as in
        // impact.rs, det K⁻¹ = 1 + R²/I
        let (rx_hi, ry_hi, ry_lo) = (
            bl.b + bl.h * psi_m,
            bl.h + bl.b * psi_m,
            bl.h - bl.b * psi_m,
        );
        let det = 1.0 + r * r / i;
        let (ka_hi, ka_lo, kb_hi, kc_hi) = (
            1.0 + ry_hi * ry_hi / i,
            1.0 + ry_lo * ry_lo / i,
            rx_hi * ry_hi / i,
            1.0 + rx_hi * rx_hi / i,
        );
        // a rebound u⁺ moves ω off rock's by at most k_w u⁺ (`chatter_settles`)
        let k_w = (kb_hi * ry_hi + ka_hi * rx_hi) / (det * i);
        let u_b = 2.0 * bl.b * e * v_top;
        let w_f = v_top + k_w * u_b;
        let lo = w.g_min - w_f * w_f * r;
        if lo <= 0.0 {
            return None;
        }
        let x = (w.rate_v + w_f * w_f * w_f * r) * 4.0 * u_b / lo;
        if x > 0.5 * lo {
            return None;
        }
        let rho = e * ((lo + x) / (lo - x)).sqrt();
        if rho >= 1.0 {
            return None;
        }
        let c_tau = 2.0 / (lo - x);
        let (u2, u3) = (u_b * u_b, u_b * u_b * u_b);
        let s1 = c_tau * u_b / (1.0 - rho);
        let s2 = c_tau * c_tau * u2 / (1.0 - rho * rho);
        let s3 = c_tau * c_tau * c_tau * u3 / (1.0 - rho * rho * rho);
        // Σ uₖ τₖ² and Σ uₖ² τₖ
        let su_t2 = c_tau * c_tau * u3 / (1.0 - rho * rho * rho);
        let su2_t = c_tau * u3 / (1.0 - rho * rho * rho);
        // the corner's tangential acceleration a_t = −ẍg − ω² r_x and its rate
        let at = w.ax_max + w_f * w_f * r;
        let at_dot = w.rate_a + w_f * w_f * w_f * r;
        // the sums: drift D, Y = Σ u τ²/6, Q (module documentation)
        let d = 0.5 * at * s2 + at_dot * s3 / 6.0;
        let y = su_t2 / 6.0;
        let q = r * r * (su2_t + at * at * s3) / 3.0 + r * r * at * su_t2 / 6.0;
        // |θ̈|, |V_θθ| = |F_θ| and dF_θ/dt near θ = 0
        let alpha = kk * (w.ax_max + w.gy_max);
        let f_th = (w.gy_max + w.ax_max) * r;
        let f_th_dot = f_th * w_f + (w.rate_v + w.rate_a) * r;
        // the correction at the centroid (`close_series`) and carried back
        // over at most the series' duration
        let dth_s = (r * d + 2.0 * w_f * r * y) / i_b;
        let dp_s = w_f * r * d + (alpha * r + w_f * w_f * r) * y + (q + f_th * r * y) / i_b;
        let (l, fi) = (s1, f_th / i_b);
        let dtheta = dth_s + l * dp_s / i_b + 0.5 * l * l * fi * dth_s;
        let dp = dp_s + l * f_th * dth_s + 0.5 * l * l * (fi * dp_s + f_th_dot * dth_s);
        let v2 = v_top * v_top;
        let bounds = SeriesBounds {
            c_theta: dtheta / v2,
            c_omega: dp / (i_b * v2),
            // the bounces' own lift: k_w times the first flight's apex
            dev: k_w * u2 / (2.0 * (lo - x)) / v2,
        };
        // rock about the new corner is still on its side, above the bounces'
        // lift, when the series ends (per v²: every term scales as v²)
        let t_hat = s1 / v_top;
        let lead = (eta - bounds.c_omega * v_top) * t_hat - 0.5 * a_up * t_hat * t_hat;
        if lead <= bounds.c_theta + bounds.dev {
            return None;
        }
        if mu_s.is_finite() {
            // the series' impacts stick (`chatter_settles`): ζ = |u_t/u_n| ≤
            // 2|a_t|/(lo − x) √((lo + x)/(lo − x)), |P_t/P_n| ≤ (c ζ + |b|(1 + e))
            // /(a(1 + e) − |b| ζ)
            let zeta = 2.0 * at / (lo - x) * ((lo + x) / (lo - x)).sqrt();
            let num = kc_hi * zeta + kb_hi * (1.0 + e);
            let den = ka_lo * (1.0 + e) - kb_hi * zeta;
            if !(den > 0.0 && num <= mu_s * (1.0 - 1e-12) * den) {
                return None;
            }
        }
        Some(bounds)
    }
}
