//! Rest: the exact start of rocking or of sliding on the linear forcing.

use super::{Event, Run, Segment};

impl Run<'_> {
    /// Rest: find the first time in [t, t_end] where |ẍg| > (g + ÿg)·B/H
    /// (exact on linear forcing: both sides of the inequality are linear in t).
    pub(super) fn rest(&mut self, seg: &Segment, t: &mut f64, t_end: f64) -> Option<Event> {
        let (sc, cc, g) = (self.given.bl.sin_c, self.given.bl.cos_c, self.given.bl.g);
        // f = cosθc·s·ẍg − sinθc·(g + ÿg) ∝ s·θ̈ of eq. (1) at θ = 0 (same
        // floating-point operations, so f > 0 ⇔ the block departs)
        let stuck = self.rules.stuck_at == Some(*t);
        let found = first_exceedance(seg, t, t_end, stuck, |s, ax, ay| {
            cc * (s * ax) - sc * (g + ay)
        });
        found.map(Event::StartRock)
    }

    /// Rest with μs ≤ B/H: find the first time in [t, t_end] where
    /// |ẍg| > μs (g + ÿg) (Shenton 1996), exact on the linear forcing. The
    /// block then slides opposite to the ground's acceleration.
    pub(super) fn rest_slide(
        &mut self,
        seg: &Segment,
        t: &mut f64,
        t_end: f64,
        mu_s: f64,
    ) -> Option<Event> {
        let g = self.given.bl.g;
        let stuck = self.rules.stuck_at == Some(*t);
        let found = first_exceedance(seg, t, t_end, stuck, |s, ax, ay| s * ax - mu_s * (g + ay));
        found.map(|s| Event::StartSlide(-s))
    }

    /// True if |ẍg(t)| > μs (g + ÿg(t)): friction cannot hold the block at rest.
    pub(super) fn slide_exceeded(&self, seg: &Segment, t: f64, mu_s: f64) -> bool {
        let (ax, ay) = seg.at(t);
        ax.abs() > mu_s * (self.given.bl.g + ay)
    }
}

/// Smallest motion (m) a departure from rest must be able to make to be
/// taken: a picometre, far below anything physical or measurable.
const MIN_EXCURSION: f64 = 1e-12;

/// The first time in [t, t_end] at which f(s, ẍg, ÿg) > 0 for s = +1 or −1,
/// where f is linear in the (linear) forcing, so the crossing is exact.
/// Moves `t` to that time (or to t_end) and returns the side s. `stuck`:
/// rest was left and re-entered at `t` itself (the motion it broke into
/// found nothing to do, f > 0 only within rounding), so f > 0 at `t` does
/// not count and the segment is left to the next one.
fn first_exceedance(
    seg: &Segment,
    t: &mut f64,
    t_end: f64,
    stuck: bool,
    f: impl Fn(f64, f64, f64) -> f64,
) -> Option<f64> {
    if *t >= t_end {
        // Nothing left of this segment: the next one decides at the same
        // instant, from its own (exact) sample rather than this segment's
        // extrapolated end.
        return None;
    }
    let (ax0, ay0) = seg.at(*t);
    let (ax1, ay1) = seg.at(t_end);
    let mut best: Option<(f64, f64)> = None;
    for s in [1.0, -1.0] {
        let (f0, f1) = (f(s, ax0, ay0), f(s, ax1, ay1));
        // f starts positive and falls to 0 within the segment after a
        // window w: the block departs and comes back, moving about
        // f0·w²/2 (m; f is an acceleration, m/s²). Below a picometre that is
        // no motion at all (a peak within ulps of the threshold, met at a
        // sample), and taking it would start rock (or slide), return to rest
        // at the same instant, and loop there.
        let w = (t_end - *t) * (f0 / (f0 - f1));
        let tc = if stuck && f1 <= f0 {
            // At the threshold within rounding and falling: no departure.
            None
        } else if f0 > 0.0 && (f1 > 0.0 || 0.5 * f0 * w * w > MIN_EXCURSION) {
            Some(*t)
        } else if f0 > 0.0 {
            None
        } else if f1 > 0.0 {
            Some(*t + (t_end - *t) * (f0 / (f0 - f1)))
        } else {
            None
        };
        // Stuck: f is 0 at t within rounding, so departure comes strictly
        // later, once f has risen (a billionth of the segment on at least;
        // within ulps of the segment's end it is the next segment's
        // business).
        let tc = match tc {
            Some(c) if stuck => Some(c.max(*t + 1e-9 * (t_end - *t))).filter(|&c| c > *t),
            tc => tc,
        };
        if let Some(tc) = tc
            && best.is_none_or(|(tb, _)| tc < tb)
        {
            best = Some((tc, s));
        }
    }
    *t = best.map_or(t_end, |(tc, _)| tc);
    best.map(|(_, s)| s)
}
