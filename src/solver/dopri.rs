//! Dormand–Prince 5(4) embedded Runge–Kutta step with Hairer's 4th-order
//! continuous extension (dense output), generic over the state size.
//!
//! Reference: Dormand & Prince (1980); Hairer, Nørsett & Wanner, *Solving
//! Ordinary Differential Equations I*, §II.5–6 (coefficients of DOPRI5 and its
//! `CONTD5` dense output). The stepper is a plain function on arrays: no
//! allocation, no trait objects; the right-hand side is a generic closure.

use crate::detmath as dm;

/// Right-hand side signature: f(t, y) → ẏ.
pub trait Rhs<const N: usize>: FnMut(f64, &[f64; N]) -> [f64; N] {}
impl<const N: usize, F: FnMut(f64, &[f64; N]) -> [f64; N]> Rhs<N> for F {}

// Butcher tableau of DOPRI5 (Dormand & Prince 1980, Table 2).
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
// Error estimate coefficients b − b̂ (5th minus 4th order weights).
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// Dense output coefficients of CONTD5 (Hairer's dopri5.f).
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// One attempted step: the 5th-order solution, its derivative (FSAL), the
/// scaled error norm and the dense-output polynomial.
#[derive(Clone, Copy, Debug)]
pub struct Step<const N: usize> {
    /// Start time of the step.
    pub t0: f64,
    /// Step size.
    pub h: f64,
    /// Solution at t0 + h.
    pub y1: [f64; N],
    /// Derivative at t0 + h (first stage of the next step).
    pub f1: [f64; N],
    /// Scaled RMS error norm (accept if ≤ 1).
    pub err: f64,
    /// Dense output coefficients r1..r5.
    dense: [[f64; N]; 5],
}

impl<const N: usize> Step<N> {
    /// Interpolated state at time t ∈ [t0, t0 + h] (4th-order accurate).
    #[inline]
    pub fn at(&self, t: f64) -> [f64; N] {
        let s = (t - self.t0) / self.h;
        let s1 = 1.0 - s;
        let [r1, r2, r3, r4, r5] = &self.dense;
        std::array::from_fn(|i| r1[i] + s * (r2[i] + s1 * (r3[i] + s * (r4[i] + s1 * r5[i]))))
    }

    /// One component of the interpolated state at time t.
    #[inline]
    pub fn component_at(&self, i: usize, t: f64) -> f64 {
        let s = (t - self.t0) / self.h;
        let s1 = 1.0 - s;
        let d = &self.dense;
        d[0][i] + s * (d[1][i] + s1 * (d[2][i] + s * (d[3][i] + s1 * d[4][i])))
    }

    /// The largest |y_i″(t)| of component i's dense output over the step,
    /// exactly (the polynomial's second derivative is a quadratic in s), so
    /// that an event search on it can rule out a dip between two points.
    #[inline]
    pub fn curvature_bound(&self, i: usize) -> f64 {
        let [_, _, r3, r4, r5] = self.dense.map(|r| r[i]);
        // CONTD5: y = r1 + s r2 + s(1−s) r3 + s²(1−s) r4 + s²(1−s)² r5, whose
        // d²/ds² is −2 r3 + (2 − 6s) r4 + (2 − 12s + 12s²) r5 = q0 + q1 s + q2 s²
        let (q0, q1, q2) = (2.0 * (r4 + r5 - r3), -6.0 * r4 - 12.0 * r5, 12.0 * r5);
        let mut m = q0.abs().max((q0 + q1 + q2).abs());
        if q2 != 0.0 {
            let sv = -q1 / (2.0 * q2);
            if sv > 0.0 && sv < 1.0 {
                m = m.max((q0 + (q1 + q2 * sv) * sv).abs());
            }
        }
        // d²/dt² = (d²/ds²)/h²; a hair over for the rounding of q and of s
        m * (1.0 + 1e-12) / (self.h * self.h)
    }
}

/// Error scales: component i is measured against `atol[i] + rtol·max(|y0_i|, |y1_i|)`.
#[derive(Clone, Copy, Debug)]
pub struct Tolerance<const N: usize> {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance per component (in that component's units).
    pub atol: [f64; N],
}

/// Attempts one DOPRI5 step of size h from (t0, y0) with derivative f0 = f(t0, y0).
#[inline]
pub fn attempt<const N: usize>(
    f: &mut impl Rhs<N>,
    t0: f64,
    y0: &[f64; N],
    f0: &[f64; N],
    h: f64,
    tol: &Tolerance<N>,
) -> Step<N> {
    let comb = |terms: &[(f64, &[f64; N])]| -> [f64; N] {
        std::array::from_fn(|i| {
            let mut s = y0[i];
            for (a, k) in terms {
                s += h * a * k[i];
            }
            s
        })
    };
    let k1 = *f0;
    let k2 = f(t0 + C2 * h, &comb(&[(A21, &k1)]));
    let k3 = f(t0 + C3 * h, &comb(&[(A31, &k1), (A32, &k2)]));
    let k4 = f(t0 + C4 * h, &comb(&[(A41, &k1), (A42, &k2), (A43, &k3)]));
    let k5 = f(
        t0 + C5 * h,
        &comb(&[(A51, &k1), (A52, &k2), (A53, &k3), (A54, &k4)]),
    );
    let k6 = f(
        t0 + h,
        &comb(&[(A61, &k1), (A62, &k2), (A63, &k3), (A64, &k4), (A65, &k5)]),
    );
    let y1 = comb(&[(A71, &k1), (A73, &k3), (A74, &k4), (A75, &k5), (A76, &k6)]);
    let k7 = f(t0 + h, &y1);
    let mut sum = 0.0;
    for i in 0..N {
        let e = h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
        let sc = tol.atol[i] + tol.rtol * y0[i].abs().max(y1[i].abs());
        sum += (e / sc) * (e / sc);
    }
    let err = (sum / N as f64).sqrt();
    let r2: [f64; N] = std::array::from_fn(|i| y1[i] - y0[i]);
    let r3: [f64; N] = std::array::from_fn(|i| h * k1[i] - r2[i]);
    let r4: [f64; N] = std::array::from_fn(|i| r2[i] - h * k7[i] - r3[i]);
    let r5: [f64; N] = std::array::from_fn(|i| {
        h * (D1 * k1[i] + D3 * k3[i] + D4 * k4[i] + D5 * k5[i] + D6 * k6[i] + D7 * k7[i])
    });
    Step {
        t0,
        h,
        y1,
        f1: k7,
        err,
        dense: [*y0, r2, r3, r4, r5],
    }
}

/// Step-size factor from an error norm (safety 0.9, exponent 1/5, bounded).
#[inline]
pub fn step_factor(err: f64) -> f64 {
    if err == 0.0 {
        5.0
    } else {
        (0.9 * dm::powf(err, -0.2)).clamp(0.2, 5.0)
    }
}

/// Adaptive DOPRI5 stepping over one interval of smooth forcing [t, t_end]:
/// [`Stepper::step`] returns the next accepted step (the caller inspects it
/// for events and then calls [`Stepper::accept`], or stops at an event), so
/// every integrated mode shares one step-size controller.
#[derive(Clone, Copy, Debug)]
pub struct Stepper<const N: usize> {
    /// Current time.
    pub t: f64,
    /// Current state.
    pub y: [f64; N],
    /// Step size to try next (carried between intervals by the caller).
    pub h: f64,
    f0: [f64; N],
    t_end: f64,
    tol: Tolerance<N>,
    h_min: f64,
    /// Interval length scale: the interval ends within 1e-12 of it.
    span: f64,
    /// Work done so far.
    pub counts: StepCounts,
}

/// Counters updated by the stepper.
#[derive(Clone, Copy, Debug, Default)]
pub struct StepCounts {
    /// Right-hand-side evaluations.
    pub rhs_calls: u64,
    /// Accepted steps.
    pub accepted: u64,
    /// Rejected steps.
    pub rejected: u64,
}

impl<const N: usize> Stepper<N> {
    /// Starts at (t, y) with trial step h; `span` is the sample interval (s).
    pub fn new(
        f: &mut impl Rhs<N>,
        t: f64,
        y: [f64; N],
        t_end: f64,
        h: f64,
        tol: Tolerance<N>,
        span: f64,
    ) -> Self {
        Stepper {
            t,
            y,
            h,
            f0: f(t, &y),
            t_end,
            tol,
            h_min: 1e-14 * span.max(1.0),
            span,
            counts: StepCounts {
                rhs_calls: 1,
                ..StepCounts::default()
            },
        }
    }

    /// The next accepted step, `Ok(None)` once t_end is reached, or
    /// `Err(t)` if the step size underflows at time t.
    pub fn step(&mut self, f: &mut impl Rhs<N>) -> Result<Option<Step<N>>, f64> {
        let counts = &mut self.counts;
        loop {
            let remaining = self.t_end - self.t;
            if remaining <= 1e-12 * self.span {
                return Ok(None);
            }
            let clipped = self.h >= remaining * 0.999;
            let h = if clipped { remaining } else { self.h };
            let step = attempt(f, self.t, &self.y, &self.f0, h, &self.tol);
            counts.rhs_calls += 6;
            if step.err.is_nan() || step.err > 1.0 {
                counts.rejected += 1;
                let fac = if step.err.is_finite() {
                    step_factor(step.err).min(0.9)
                } else {
                    0.2
                };
                self.h = h * fac;
                if self.h < self.h_min {
                    return Err(self.t);
                }
                continue;
            }
            counts.accepted += 1;
            let fac = step_factor(step.err);
            // a step shortened to land on t_end does not shrink the next one
            if !(clipped && fac >= 1.0) {
                self.h = h * fac;
            }
            return Ok(Some(step));
        }
    }

    /// Moves to the end of an accepted step.
    pub fn accept(&mut self, step: &Step<N>) {
        self.t = step.t0 + step.h;
        self.y = step.y1;
        self.f0 = step.f1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_exponential_to_fifth_order() {
        // ẏ = y from y(0) = 1 over [0, 1] with 50 fixed steps: global error of a
        // 5th-order method ~ C·h⁵ ≈ 1e-10; we require 1e-9.
        let tol = Tolerance {
            rtol: 1.0,
            atol: [1.0],
        };
        let mut f = |_t: f64, y: &[f64; 1]| [y[0]];
        let (mut t, mut y) = (0.0, [1.0]);
        let mut f0 = f(t, &y);
        let h = 0.02;
        for _ in 0..50 {
            let s = attempt(&mut f, t, &y, &f0, h, &tol);
            // dense output at the midpoint is 4th-order accurate
            let mid = s.at(t + 0.5 * h)[0];
            assert!((mid - dm::exp(t + 0.5 * h)).abs() < 1e-9 * mid);
            t += h;
            y = s.y1;
            f0 = s.f1;
        }
        assert!((y[0] - dm::exp(1.0)).abs() < 1e-9);
    }

    #[test]
    fn curvature_bound_is_the_dense_outputs_largest_second_derivative() {
        // ÿ = −y (y = cos t) over one long step: the dense output's y″, by
        // central differences on a fine grid, reaches the bound and never
        // exceeds it
        let tol = Tolerance {
            rtol: 1.0,
            atol: [1.0, 1.0],
        };
        let mut f = |_t: f64, y: &[f64; 2]| [y[1], -y[0]];
        let y0 = [1.0, 0.0];
        let f0 = f(0.0, &y0);
        let h = 0.7;
        let st = attempt(&mut f, 0.0, &y0, &f0, h, &tol);
        let m2 = st.curvature_bound(0);
        let d = 1e-4 * h;
        let mut largest: f64 = 0.0;
        for k in 1..1000 {
            let t = h * k as f64 / 1000.0;
            let y = |t: f64| st.component_at(0, t);
            let ydd = (y(t + d) - 2.0 * y(t) + y(t - d)) / (d * d);
            largest = largest.max(ydd.abs());
        }
        assert!(largest <= m2 * (1.0 + 1e-5), "{largest} > {m2}");
        assert!(largest >= m2 * (1.0 - 1e-2), "{largest} ≪ {m2}");
        // and it is close to the true |ÿ| = |cos t| ≤ 1
        assert!((m2 - 1.0).abs() < 1e-2, "{m2}");
    }
}
