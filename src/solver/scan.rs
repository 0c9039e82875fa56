//! Locating the first descent of a smooth scalar function through zero on an
//! interval, including grazing contacts where the function dips below zero
//! and returns between the two ends.

use super::roots::{brent, newton};

/// Finds the earliest τ ∈ (a, b] at which `f` reaches ≤ 0, where `fd(τ)`
/// returns (f, f′). `f(a)` is taken as non-negative (a contact that starts at
/// zero must be departing: f′(a) ≥ 0). The interval is examined in `n` equal
/// pieces; inside each piece an interior minimum is found from f′ and checked,
/// so a dip below zero between the ends is not missed as long as f′ changes
/// sign at most once per piece. Returns the time on the "after" side.
pub fn first_descent(
    fd: impl Fn(f64) -> (f64, f64),
    a: f64,
    b: f64,
    n: usize,
    xtol: f64,
) -> Option<f64> {
    descent(fd, a, b, n, xtol, false)
}

/// As [`first_descent`], for a contact that has just been released: the start
/// is taken as exactly touching and not approaching (f(a) = 0, f′(a) ≥ 0),
/// so rounding in f(a) or f′(a) cannot register as an immediate descent.
pub fn first_descent_after_release(
    fd: impl Fn(f64) -> (f64, f64),
    a: f64,
    b: f64,
    n: usize,
    xtol: f64,
) -> Option<f64> {
    descent(fd, a, b, n, xtol, true)
}

fn descent(
    fd: impl Fn(f64) -> (f64, f64),
    a: f64,
    b: f64,
    n: usize,
    xtol: f64,
    released: bool,
) -> Option<f64> {
    let n = n.max(1);
    let width = (b - a) / n as f64;
    let (mut ta, (mut fa, mut da)) = (a, fd(a));
    if released {
        fa = 0.0;
        da = da.max(0.0);
    }
    for i in 1..=n {
        let tb = if i == n { b } else { a + width * i as f64 };
        let (fb, db) = fd(tb);
        if fb <= 0.0 {
            if fa > 0.0 {
                return Some(newton(&fd, (ta, fa, da), (tb, fb), xtol));
            }
            // Started touching and not approaching: the function may have
            // risen and come back inside the piece. Find a point above zero
            // (at the maximum, or by halving towards the start, which also
            // covers a start with f′ = 0 and f″ > 0), then the descent after it.
            if da >= 0.0 {
                if da > 0.0 && db < 0.0 {
                    // the secant root of f′ (the apex of a near-parabola, as
                    // in a short flight) is usually above zero already
                    let ts = ta + da * (tb - ta) / (da - db);
                    if ts > ta && ts < tb {
                        let (fs, ds) = fd(ts);
                        if fs > 0.0 {
                            return Some(newton(&fd, (ts, fs, ds), (tb, fb), xtol));
                        }
                    }
                    let tm = brent(|t| fd(t).1, ta, tb, da, db, xtol);
                    let (fm, dm) = fd(tm);
                    if fm > 0.0 {
                        return Some(newton(&fd, (tm, fm, dm), (tb, fb), xtol));
                    }
                }
                let mut tm = tb;
                for _ in 0..64 {
                    tm = ta + 0.5 * (tm - ta);
                    let (fm, dm) = fd(tm);
                    if fm > 0.0 {
                        return Some(newton(&fd, (tm, fm, dm), (tb, fb), xtol));
                    }
                }
            }
            return Some(ta);
        }
        if da < 0.0 && db > 0.0 {
            // Interior minimum: grazing check.
            let tm = brent(|t| fd(t).1, ta, tb, da, db, xtol);
            let fm = fd(tm).0;
            if fm <= 0.0 {
                if fa > 0.0 {
                    return Some(newton(&fd, (ta, fa, da), (tm, fm), xtol));
                }
                return Some(ta);
            }
        }
        ta = tb;
        fa = fb;
        da = db;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_a_grazing_dip_between_positive_ends() {
        // f = (τ − 0.5)² − 1e-6 dips below zero only on (0.499, 0.501): both ends
        // are positive, so only the interior-minimum check can find it.
        let fd = |t: f64| ((t - 0.5) * (t - 0.5) - 1e-6, 2.0 * (t - 0.5));
        let r = first_descent(fd, 0.0, 1.0, 1, 1e-15).unwrap();
        assert!((r - 0.499).abs() < 1e-12, "{r}");
    }

    #[test]
    fn finds_the_return_of_a_start_with_zero_slope() {
        // f = τ²/2 − τ³ (f(0) = f′(0) = 0, f″(0) > 0) returns to zero at τ = 1/2:
        // the sliver of motion after a start exactly at a threshold.
        let fd = |t: f64| (0.5 * t * t - t * t * t, t - 3.0 * t * t);
        let r = first_descent(fd, 0.0, 1.0, 1, 1e-15).unwrap();
        assert!((r - 0.5).abs() < 1e-14, "{r}");
    }

    #[test]
    fn finds_a_micro_bounce_from_a_touching_start() {
        // A corner leaving the ground at 1e-6 m/s under g returns after 2v/g.
        let (v, g) = (1e-6, 9.81);
        let fd = |t: f64| (v * t - 0.5 * g * t * t, v - g * t);
        let r = first_descent(fd, 0.0, 0.01, 1, 1e-18).unwrap();
        assert!((r - 2.0 * v / g).abs() < 1e-15, "{r}");
    }
}
