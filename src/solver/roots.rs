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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_cubic_root_to_tolerance() {
        // x³ − 2 has its root at 2^(1/3); Brent must land within 1e-14.
        let f = |x: f64| x * x * x - 2.0;
        let r = brent(f, 0.0, 2.0, f(0.0), f(2.0), 1e-15);
        assert!((r - 2f64.cbrt()).abs() < 1e-14);
        assert!(f(r) >= 0.0, "returned point must be on the after side");
    }
}
