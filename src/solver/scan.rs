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
        if let Some(r) = piece(&fd, (ta, fa, da), (tb, fb, db), xtol) {
            return Some(r);
        }
        ta = tb;
        fa = fb;
        da = db;
    }
    None
}

/// As [`first_descent`] in one piece, for a function whose second
/// derivative is bounded, |f″| ≤ `m2` on [a, b] (a polynomial's, from its
/// coefficients), with a check that no earlier descent hides before the one
/// found (or before b, if none): two crossings inside one piece, which the
/// one-minimum search cannot see. [a, r] is swept in pieces that the bound
/// proves free of a descent: f > 0 inside a piece with positive ends, f
/// decreasing in the last piece, which ends at the descent found; a piece
/// it cannot prove so is halved, and after a proven piece the width doubles
/// again. Pieces are not halved below the width at which a dip between
/// positive ends is at most `floor` deep (m2 w²/8 ≤ floor): there the
/// one-minimum check decides. The answer is that of the one-piece search
/// (to the bit) unless a descent is found before it. `released` as in
/// [`first_descent_after_release`].
///
/// A start below zero and rising (f(a) < 0 < f′(a): the state a closed
/// bounce series leaves, carried back along the linearised motion, can lie
/// a hair below the ground) is departing, as the one-piece search takes it:
/// the descent sought is the first after f's first return to ≥ 0, which the
/// same sweep on −f finds (without one, the one-piece answer: a descent at
/// once unless it finds f above zero).
pub fn first_descent_bounded(
    fd: impl Fn(f64) -> (f64, f64),
    a: f64,
    b: f64,
    m2: f64,
    floor: f64,
    xtol: f64,
    released: bool,
) -> Option<f64> {
    let (fa, da) = fd(a);
    let (fa, da) = if released {
        (0.0, da.max(0.0))
    } else {
        (fa, da)
    };
    let (fb, db) = fd(b);
    if fa < 0.0 && da > 0.0 {
        let neg = |t: f64| {
            let (f, d) = fd(t);
            (-f, -d)
        };
        return match bounded((a, -fa, -da), (b, -fb, -db), &neg, m2, floor, xtol) {
            Some(up) if up < b => {
                // f(up) ≥ 0 (the "after" side of −f ≤ 0): on from there as released
                let (_, du) = fd(up);
                bounded((up, 0.0, du.max(0.0)), (b, fb, db), &fd, m2, floor, xtol)
            }
            // no return to ≥ 0 (deeper than `floor`): the one-piece answer
            _ => piece(&fd, (a, fa, da), (b, fb, db), xtol),
        };
    }
    bounded((a, fa, da), (b, fb, db), &fd, m2, floor, xtol)
}

/// [`first_descent_bounded`] given f, f′ at both ends.
fn bounded(
    (a, fa0, da0): (f64, f64, f64),
    (b, fb0, db0): (f64, f64, f64),
    fd: &impl Fn(f64) -> (f64, f64),
    m2: f64,
    floor: f64,
    xtol: f64,
) -> Option<f64> {
    let found = piece(fd, (a, fa0, da0), (b, fb0, db0), xtol);
    let end = found.unwrap_or(b);
    if end <= a {
        return found;
    }
    // the interpolation bound: a dip between positive ends is at most m2 w²/8 deep
    let w_min = (8.0 * floor / m2).sqrt().max(1e-12 * (b - a)).max(xtol);
    let (mut ta, mut fa, mut da) = (a, fa0, da0);
    let mut w = end - a;
    loop {
        let tb = if ta + w >= end { end } else { ta + w };
        let wi = tb - ta;
        let (fb, db) = if tb == b { (fb0, db0) } else { fd(tb) };
        let proven = if fb > 0.0 {
            positive_inside((fa, da), (fb, db), wi, m2)
        } else {
            // f′ ≤ min(da + m2 u, db + m2 (wi − u)) ≤ (da + db + m2 wi)/2
            da + db + m2 * wi < 0.0
        };
        if !proven && wi > w_min {
            w = 0.5 * wi;
            continue;
        }
        if tb == end && fb <= 0.0 {
            // the last piece, decreasing to the descent found (or too narrow
            // to hide another)
            return found;
        }
        if (fb <= 0.0 || !proven)
            && let Some(t) = piece(fd, (ta, fa, da), (tb, fb, db), xtol)
            && t < end
        {
            return Some(t);
        }
        if tb >= end {
            return found;
        }
        (ta, fa, da) = (tb, fb, db);
        w = 2.0 * wi;
    }
}

/// Whether f > 0 on (0, w) follows from f, f′ at both ends (f(0) ≥ 0,
/// f(w) > 0) and |f″| ≤ m2: on the first half f ≥ f0 + d0 u − m2 u²/2, on the
/// second f ≥ f1 − d1 v − m2 v²/2 (v = w − u), both concave, so each is
/// checked at the ends of its half (Taylor's theorem with the remainder bound).
#[inline]
fn positive_inside((f0, d0): (f64, f64), (f1, d1): (f64, f64), w: f64, m2: f64) -> bool {
    let h = 0.5 * w;
    let q = 0.5 * m2 * h * h;
    let first = (f0 > 0.0 || (f0 == 0.0 && d0 > 0.0)) && f0 + d0 * h - q > 0.0;
    let second = f1 - d1 * h - q > 0.0;
    first && second
}

/// The search on one piece [ta, tb] given f and f′ at its ends: the time of
/// the descent found in it, or `None` to go on to the next piece.
#[inline]
fn piece(
    fd: &impl Fn(f64) -> (f64, f64),
    (ta, fa, da): (f64, f64, f64),
    (tb, fb, db): (f64, f64, f64),
    xtol: f64,
) -> Option<f64> {
    let fd = |t: f64| fd(t);
    if fb <= 0.0 {
        if fa > 0.0 {
            return Some(newton(fd, (ta, fa, da), (tb, fb), xtol));
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
                        return Some(newton(fd, (ts, fs, ds), (tb, fb), xtol));
                    }
                }
                let tm = brent(|t| fd(t).1, ta, tb, da, db, xtol);
                let (fm, dm) = fd(tm);
                if fm > 0.0 {
                    return Some(newton(fd, (tm, fm, dm), (tb, fb), xtol));
                }
            }
            let mut tm = tb;
            for _ in 0..64 {
                tm = ta + 0.5 * (tm - ta);
                let (fm, dm) = fd(tm);
                if fm > 0.0 {
                    return Some(newton(fd, (tm, fm, dm), (tb, fb), xtol));
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
                return Some(newton(fd, (ta, fa, da), (tm, fm), xtol));
            }
            return Some(ta);
        }
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

    #[test]
    fn finds_the_first_of_two_crossings_inside_one_step() {
        // f = (τ − 0.3)(τ − 0.4)(τ + 0.1) = τ³ − 0.6τ² + 0.05τ + 0.012: f > 0 and
        // f′ > 0 at both ends, below zero on (0.3, 0.4), f′ changing sign twice.
        // One piece with one minimum check misses it; |f″| = |6τ − 1.2| ≤ 4.8
        // on [0, 1] lets the bounded search find the first crossing, τ = 0.3.
        let fd = |t: f64| {
            (
                ((t - 0.6) * t + 0.05) * t + 0.012,
                (3.0 * t - 1.2) * t + 0.05,
            )
        };
        assert_eq!(first_descent(fd, 0.0, 1.0, 1, 1e-15), None);
        let r = first_descent_bounded(fd, 0.0, 1.0, 4.8, 1e-12, 1e-15, false).unwrap();
        // the root is simple (f′(0.3) = −0.04), so 1e-15 in τ is ~1e-16 in f
        assert!((r - 0.3).abs() < 1e-14, "{r}");
        assert!(fd(r).0 <= 0.0, "returned point must be on the after side");
    }

    #[test]
    fn a_start_below_zero_and_rising_is_departing() {
        // f = (τ − 0.1)(τ − 0.3)(τ − 0.4): f(0) < 0 < f′(0) and f(1) > 0; f rises
        // through 0 at 0.1, descends at 0.3 and rises again at 0.4. The
        // one-piece search takes the start as departing and sees nothing; the
        // bounded search finds the descent after the rise, not the start.
        let fd = |t: f64| {
            (
                (t - 0.1) * (t - 0.3) * (t - 0.4),
                (3.0 * t - 1.6) * t + 0.19,
            )
        };
        assert_eq!(first_descent(fd, 0.0, 1.0, 1, 1e-15), None);
        let r = first_descent_bounded(fd, 0.0, 1.0, 4.4, 1e-12, 1e-15, false).unwrap();
        assert!((r - 0.3).abs() < 1e-14, "{r}");
        // f = −(τ − 0.1)(τ − 0.3) rises through 0 at 0.1 and descends at 0.3
        // with f(1) < 0: the descent is at 0.3, not at the start below zero
        let fd = |t: f64| (-(t - 0.1) * (t - 0.3), 0.4 - 2.0 * t);
        let r = first_descent_bounded(fd, 0.0, 1.0, 2.0, 1e-12, 1e-15, false).unwrap();
        assert!((r - 0.3).abs() < 1e-14, "{r}");
        // rising through zero and staying up: no descent
        let fd = |t: f64| (t - 0.1, 1.0);
        assert_eq!(
            first_descent_bounded(fd, 0.0, 1.0, 0.0, 1e-12, 1e-15, false),
            None
        );
    }

    #[test]
    fn bounded_search_keeps_the_single_crossing_and_grazing_answers() {
        // The cases above, through the bounded search (|f″| bounds: 2, 3 − 6τ
        // → 3 on [0, 1], g): the same times to the same tolerances.
        let fd = |t: f64| ((t - 0.5) * (t - 0.5) - 1e-6, 2.0 * (t - 0.5));
        let r = first_descent_bounded(fd, 0.0, 1.0, 2.0, 1e-12, 1e-15, false).unwrap();
        assert!((r - 0.499).abs() < 1e-12, "{r}");
        let fd = |t: f64| (0.5 * t * t - t * t * t, t - 3.0 * t * t);
        let r = first_descent_bounded(fd, 0.0, 1.0, 5.0, 1e-12, 1e-15, false).unwrap();
        assert!((r - 0.5).abs() < 1e-14, "{r}");
        let (v, g) = (1e-6, 9.81);
        let fd = |t: f64| (v * t - 0.5 * g * t * t, v - g * t);
        let r = first_descent_bounded(fd, 0.0, 0.01, g, 1e-18, 1e-18, true).unwrap();
        assert!((r - 2.0 * v / g).abs() < 1e-15, "{r}");
        // and a function that stays positive is searched to the end: None
        let fd = |t: f64| ((t - 0.5) * (t - 0.5) + 1e-9, 2.0 * (t - 0.5));
        assert_eq!(
            first_descent_bounded(fd, 0.0, 1.0, 2.0, 1e-12, 1e-15, false),
            None
        );
    }
}
