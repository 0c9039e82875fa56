//! Bracketed root finding (Brent's method) used to locate events on dense
//! output and on closed-form solutions.

/// Finds a root of `f` in [a, b] given f(a)·f(b) ≤ 0, to an absolute time
/// tolerance `xtol`. Returns the end of the final bracket on the side where f
/// has the sign of f(b) (the "after the event" side), so the event has
/// certainly happened at the returned time.
pub fn brent(mut f: impl FnMut(f64) -> f64, a: f64, b: f64, fa: f64, fb: f64, xtol: f64) -> f64 {
    // Brent (1973), "Algorithms for Minimization without Derivatives", ch. 4.
    let (mut a, mut b, mut fa, mut fb) = (a, b, fa, fb);
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 {
        return b;
    }
    // Keep `after` = the bracket end with sign(f) == sign of original fb.
    let sign_after = fb.signum();
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    for _ in 0..200 {
        if fb.signum() == fc.signum() {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol = 2.0 * f64::EPSILON * b.abs() + 0.5 * xtol;
        let m = 0.5 * (c - b);
        if m.abs() <= tol || fb == 0.0 {
            break;
        }
        if e.abs() >= tol && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * m * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol { d } else { tol.copysign(m) };
        fb = f(b);
    }
    // b and c bracket the root; return whichever lies on the "after" side.
    if fb == 0.0 || fb.signum() == sign_after {
        b
    } else {
        c
    }
}

/// Finds a root of f in [a, b] given f(a)·f(b) ≤ 0 and the derivative:
/// Newton steps kept inside a shrinking bracket, bisection when a step would
/// leave it or converge too slowly (Press et al., *Numerical Recipes*,
/// `rtsafe`). `fd(t)` returns (f, f′); f′ may be approximate (for instance
/// the dense output of θ̇ for θ) since the bracket guarantees convergence.
/// `da` is f′(a), which the caller has already evaluated with f(a).
/// Returns the bracket end on the side of b's sign, like [`brent`].
pub fn newton(
    fd: impl Fn(f64) -> (f64, f64),
    (a, fa, da): (f64, f64, f64),
    (b, fb): (f64, f64),
    xtol: f64,
) -> f64 {
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 {
        return b;
    }
    // Orient so that g = f·sign(fb) is < 0 at xl ("before") and > 0 at xh ("after").
    let sg = fb.signum();
    let (mut xl, mut xh) = (a, b);
    // Start from the first root of the parabola with f(a), f′(a) and f(b):
    // events on smooth paths (a corner's height in flight, an angle) are
    // near-quadratic over a step, and a start at the midpoint would cost
    // a halving per iteration while Newton is still far away.
    let mut t = 0.5 * (a + b);
    let w = b - a;
    let c = 2.0 * (fb - fa - da * w) / (w * w);
    let disc = da * da - 2.0 * c * fa;
    if disc >= 0.0 && c != 0.0 {
        // roots τ = (−da ± √disc)/c; the first in (0, w), computed stably
        let q = -0.5 * (da + disc.sqrt().copysign(da));
        let mut first = w;
        for tau in [q / (0.5 * c), fa / q] {
            if tau.is_finite() && tau > 0.0 && tau < first {
                first = tau;
            }
        }
        if first < w {
            t = a + first;
        }
    } else if c == 0.0 && da != 0.0 {
        let tau = -fa / da;
        if tau > 0.0 && tau < w {
            t = a + tau;
        }
    }
    let mut dx_old = (b - a).abs();
    let mut dx = dx_old;
    let (f, d) = fd(t);
    let (mut g, mut dg) = (sg * f, sg * d);
    for _ in 0..100 {
        if g == 0.0 {
            return t;
        }
        if g < 0.0 {
            xl = t;
        } else {
            xh = t;
        }
        let tol = 2.0 * f64::EPSILON * t.abs() + 0.5 * xtol;
        let newton_leaves = ((t - xh) * dg - g) * ((t - xl) * dg - g) > 0.0;
        if newton_leaves || (2.0 * g).abs() > (dx_old * dg).abs() {
            dx_old = dx;
            dx = 0.5 * (xh - xl);
            t = xl + dx;
        } else {
            dx_old = dx;
            dx = g / dg;
            t -= dx;
        }
        if dx.abs() <= tol || (xh - xl).abs() <= 2.0 * tol {
            break;
        }
        let (f, d) = fd(t);
        g = sg * f;
        dg = sg * d;
    }
    // Return a point on the after side (g ≥ 0) within tolerance of the root.
    let g_t = sg * fd(t).0;
    if g_t >= 0.0 {
        return t;
    }
    let tol = 2.0 * f64::EPSILON * t.abs() + 0.5 * xtol;
    let probe = t + tol.copysign(xh - xl);
    if (probe - xh) * (probe - xl) <= 0.0 && sg * fd(probe).0 >= 0.0 {
        probe
    } else {
        xh
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detmath as dm;

    #[test]
    fn finds_cubic_root_to_tolerance() {
        // x³ − 2 has its root at 2^(1/3); Brent must land within 1e-14.
        let f = |x: f64| x * x * x - 2.0;
        let r = brent(f, 0.0, 2.0, f(0.0), f(2.0), 1e-15);
        assert!((r - dm::cbrt(2.0)).abs() < 1e-14);
        assert!(f(r) >= 0.0, "returned point must be on the after side");
    }

    #[test]
    fn newton_finds_root_with_few_evaluations() {
        // cos t − t has its root at 0.7390851332151607; with the derivative the
        // bracketed Newton lands within 1e-15 and on the after side.
        use std::cell::Cell;
        let n = Cell::new(0);
        let fd = |t: f64| {
            n.set(n.get() + 1);
            (dm::cos(t) - t, -dm::sin(t) - 1.0)
        };
        let r = newton(fd, (0.0, 1.0, -1.0), (1.0, dm::cos(1.0) - 1.0), 1e-15);
        assert!((r - 0.7390851332151607).abs() < 1e-15, "{r}");
        assert!(dm::cos(r) - r <= 0.0);
        assert!(n.get() <= 10, "{} evaluations", n.get());
    }
}
