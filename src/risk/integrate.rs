//! The risk integral λ_LS = ∫ P(LS | im) |dλ/dim| dim of a lognormal
//! fragility over a hazard curve interpolated log–log (see [`crate::risk`]).

use crate::detmath as dm;

use super::hazard::HazardCurve;

/// Relative accuracy the adaptive quadrature aims at (its error estimate,
/// the sum of |K15 − G7| over the subintervals, is driven below this
/// fraction of the rate).
pub const RELATIVE_TOLERANCE: f64 = 1e-10;

/// Subintervals the quadrature may split into before it stops (its error
/// estimate is then reported as it stands).
const MAX_INTERVALS: usize = 4000;

/// Standard-normal quantiles beyond the integrand's peak at which the lower
/// tail is cut: the integrand there is below e^(−72) of its peak.
const LOWER_CUT_SIGMAS: f64 = 12.0;

/// e-folds of the hazard beyond the highest level at which the upper tail is
/// cut: what is left is at most λ_max·e^(−40) ≈ 4·10⁻¹⁸ λ_max.
const UPPER_CUT_EFOLDS: f64 = 40.0;

/// Grid points of the search for the integrand's peak.
const PEAK_GRID: usize = 20_000;

/// What the risk integral of one fragility curve over one hazard curve gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RiskIntegral {
    /// Annual rate of exceeding the limit state, λ_LS (1/yr).
    pub rate: f64,
    /// Of it, the part from intensities below the hazard curve's lowest
    /// level (its first segment's power law extended down), 1/yr.
    pub below: f64,
    /// Of it, the part from intensities above its highest level (its last
    /// segment's power law extended up), 1/yr.
    pub above: f64,
    /// The intensity at which the integrand P(LS | im)·(−dλ/d ln im) (the
    /// rate's density over ln im, its deaggregation) peaks, with the
    /// hazard's log-slope smoothed between the levels (see [`crate::risk`]).
    pub peak_im: f64,
    /// The quadrature's error estimate (1/yr).
    pub error: f64,
    /// Of `above`, the shaking above the highest level that a flat last
    /// segment leaves without a distribution (the rate of exceeding the
    /// highest level), counted at that level: λ_top·P(LS | im_top), a lower
    /// bound on its contribution (1/yr; 0 when the last segment falls).
    pub flat_top: f64,
}

impl RiskIntegral {
    /// Share of the rate from below the hazard curve's lowest level.
    pub fn share_below(&self) -> f64 {
        self.below / self.rate
    }

    /// Share of the rate from above the hazard curve's highest level.
    pub fn share_above(&self) -> f64 {
        self.above / self.rate
    }
}

/// One piece of the integration range in u = ln im, on which the hazard is
/// the power law λ(u) = exp(l − k (u − u_ref)).
#[derive(Clone, Copy, Debug)]
struct Piece {
    a: f64,
    b: f64,
    u_ref: f64,
    l_ref: f64,
    k: f64,
}

/// Where each piece lies: the lower tail, a segment of the curve, the upper tail.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Part {
    Below,
    Inside,
    Above,
}

/// A lognormal fragility P(LS | im) = Φ((ln im − ln θ)/β) over a hazard
/// curve: the integrand and its pieces.
struct Integrand<'a> {
    ln_median: f64,
    beta: f64,
    /// λ_top·P(LS | im_top) when the last segment is flat (see
    /// [`RiskIntegral::flat_top`]), else 0.
    top_atom: f64,
    pieces: Vec<(Part, Piece)>,
    /// Midpoints (in u) of the hazard's segments and their log-slopes.
    midpoints: Vec<(f64, f64)>,
    /// The log–log interpolated hazard.
    hazard: &'a HazardCurve,
}

impl<'a> Integrand<'a> {
    fn new(hazard: &'a HazardCurve, median: f64, beta: f64) -> Integrand<'a> {
        let u: Vec<f64> = hazard.iml.iter().map(|&x| dm::ln(x)).collect();
        let l: Vec<f64> = hazard.rate.iter().map(|&r| dm::ln(r)).collect();
        let n = u.len();
        // k = −d ln λ/du of a segment: +0 (not −0) on a flat one, whose
        // integrand is then +0 (a −0 sum gave the return period −∞).
        let segment = |i: usize| Piece {
            a: u[i],
            b: u[i + 1],
            u_ref: u[i],
            l_ref: l[i],
            k: (l[i] - l[i + 1]) / (u[i + 1] - u[i]),
        };
        let ln_median = dm::ln(median);
        let mut pieces = Vec::with_capacity(n + 1);
        // Below: the first segment's power law, down to where Φ has made
        // the integrand negligible (its peak is near z = −kβ).
        let first = segment(0);
        let cut = ln_median - beta * (first.k * beta + LOWER_CUT_SIGMAS);
        if first.k > 0.0 && cut < u[0] {
            pieces.push((
                Part::Below,
                Piece {
                    a: cut,
                    b: u[0],
                    ..first
                },
            ));
        }
        pieces.extend((0..n - 1).map(|i| (Part::Inside, segment(i))));
        // Above: the last segment's power law. A flat last segment says that
        // λ_top of shaking exceeds the highest level, not by how much: it
        // is counted at that level (`top_atom`), a lower bound.
        let last = segment(n - 2);
        let top_atom = if last.k > 0.0 {
            0.0
        } else {
            hazard.rate[n - 1] * dm::norm_cdf((u[n - 1] - ln_median) / beta)
        };
        if last.k > 0.0 {
            pieces.push((
                Part::Above,
                Piece {
                    a: u[n - 1],
                    b: u[n - 1] + UPPER_CUT_EFOLDS / last.k,
                    ..last
                },
            ));
        }
        Integrand {
            ln_median,
            beta,
            top_atom,
            pieces,
            midpoints: (0..n - 1)
                .map(|i| ((u[i] + u[i + 1]) / 2.0, segment(i).k))
                .collect(),
            hazard,
        }
    }

    /// P(LS | e^u)·k̃(u)·λ(u), with the log-slope k̃ linear between the
    /// segments' midpoints: the integrand with the jumps at the levels
    /// smoothed out, for locating its peak.
    fn smoothed(&self, u: f64) -> f64 {
        let m = &self.midpoints;
        let j = m.partition_point(|p| p.0 <= u);
        let k = if j == 0 {
            m[0].1
        } else if j == m.len() {
            m[m.len() - 1].1
        } else {
            let ((u0, k0), (u1, k1)) = (m[j - 1], m[j]);
            k0 + (k1 - k0) * (u - u0) / (u1 - u0)
        };
        let p = dm::norm_cdf((u - self.ln_median) / self.beta);
        if p == 0.0 {
            return 0.0;
        }
        p * k * self.hazard.rate_at(dm::exp(u))
    }

    /// P(LS | e^u)·(−dλ/du) on `piece`.
    fn value(&self, piece: &Piece, u: f64) -> f64 {
        let p = dm::norm_cdf((u - self.ln_median) / self.beta);
        if p == 0.0 {
            return 0.0;
        }
        p * piece.k * dm::exp(piece.l_ref - piece.k * (u - piece.u_ref))
    }
}

/// Gauss–Kronrod 7–15 nodes on [−1, 1] (non-negative half; QUADPACK's qk15).
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
/// Kronrod weights of [`XGK`].
const WGK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_8,
];
/// Gauss weights of the 7-point rule (nodes `XGK[1]`, `XGK[3]`, `XGK[5]`, `XGK[7]`).
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// The 15-point Kronrod estimate of ∫ f over [a, b] and |K15 − G7|.
fn kronrod(f: impl Fn(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let (c, h) = ((a + b) / 2.0, (b - a) / 2.0);
    let fc = f(c);
    let (mut k, mut g) = (WGK[7] * fc, WG[3] * fc);
    for j in 0..7 {
        let pair = f(c - h * XGK[j]) + f(c + h * XGK[j]);
        k += WGK[j] * pair;
        if j % 2 == 1 {
            g += WG[j / 2] * pair;
        }
    }
    (k * h, ((k - g) * h).abs())
}

/// λ_LS of a lognormal fragility (median θ, dispersion β, in the hazard's
/// unit) over `hazard`, with the shares from beyond its ends and the
/// intensity that drives it. See [`crate::risk`] for the method.
///
/// ```
/// use rockfrag::risk::{HazardCurve, risk_integral};
/// // λ(a) = 1e-3·a^-2.5 (a in g) and θ = 1 g, β = 0.3:
/// // closed form k0·θ^-k·exp(k²β²/2) = 1e-3·exp(2.5²·0.3²/2) ≈ 1.3248e-3 per year.
/// let iml = [0.05, 0.1, 0.2, 0.5, 1.0, 2.0];
/// let rate: Vec<f64> = iml.iter().map(|a: &f64| 1e-3 * a.powf(-2.5)).collect();
/// let h = HazardCurve::from_rates("power law".as_ref(), &iml, &rate)?;
/// let r = risk_integral(&h, 1.0, 0.3);
/// let exact = 1e-3 * (2.5f64 * 2.5 * 0.3 * 0.3 / 2.0).exp();
/// assert!((r.rate / exact - 1.0).abs() < 1e-9);
/// # Ok::<(), rockfrag::Error>(())
/// ```
pub fn risk_integral(hazard: &HazardCurve, median: f64, beta: f64) -> RiskIntegral {
    let f = Integrand::new(hazard, median, beta);
    let (rate, below, above, error) = quadrature(&f);
    // With nothing but shaking counted at a flat curve's highest level,
    // that level drives the rate.
    let peak_im = if rate == 0.0 && f.top_atom > 0.0 {
        hazard.iml[hazard.iml.len() - 1]
    } else {
        dm::exp(peak(&f))
    };
    RiskIntegral {
        rate: rate + f.top_atom,
        below,
        above: above + f.top_atom,
        peak_im,
        error,
        flat_top: f.top_atom,
    }
}

/// λ_LS alone (no peak): for the bootstrap replicates.
pub fn annual_rate(hazard: &HazardCurve, median: f64, beta: f64) -> f64 {
    let f = Integrand::new(hazard, median, beta);
    quadrature(&f).0 + f.top_atom
}

/// The integrand P(LS | im)·(−dλ/d ln im) at each of `ims` (1/yr per unit
/// of ln im): the rate's deaggregation over intensity, with the hazard
/// extended beyond its ends as the integral extends it.
pub fn deaggregation(hazard: &HazardCurve, median: f64, beta: f64, ims: &[f64]) -> Vec<f64> {
    let f = Integrand::new(hazard, median, beta);
    let first = dm::ln(hazard.iml[0]);
    ims.iter()
        .map(|&x| {
            let u = dm::ln(x);
            // Beyond the cuts: the outermost pieces' power laws (the same
            // as the first and last segments').
            let outer = if u < first {
                f.pieces.first()
            } else {
                f.pieces.last()
            };
            let piece = f.pieces.iter().find(|(_, p)| p.a <= u && u < p.b).or(outer);
            piece.map_or(0.0, |(_, p)| f.value(p, u))
        })
        .collect()
}

/// The integrand as [`deaggregation`] gives it, but with the hazard's
/// log-slope varying linearly between its segments' midpoints, as the peak
/// (`peak_im`) is located: the same curve without the jumps at the hazard's
/// levels, where the log–log interpolant's slope jumps (drawn, those make
/// a sawtooth of a smooth deaggregation). For figures; the rate itself is
/// the integral of [`deaggregation`].
pub fn deaggregation_smoothed(
    hazard: &HazardCurve,
    median: f64,
    beta: f64,
    ims: &[f64],
) -> Vec<f64> {
    let f = Integrand::new(hazard, median, beta);
    ims.iter().map(|&x| f.smoothed(dm::ln(x))).collect()
}

/// Globally adaptive Gauss–Kronrod over the pieces: the subinterval with the
/// largest error estimate is halved until the summed estimate is below
/// [`RELATIVE_TOLERANCE`] of the total. Returns (total, below, above, error).
fn quadrature(f: &Integrand) -> (f64, f64, f64, f64) {
    struct Cell {
        part: Part,
        piece: Piece,
        a: f64,
        b: f64,
        value: f64,
        error: f64,
    }
    let eval = |part: Part, piece: Piece, a: f64, b: f64| {
        let (value, error) = kronrod(|u| f.value(&piece, u), a, b);
        Cell {
            part,
            piece,
            a,
            b,
            value,
            error,
        }
    };
    let mut cells: Vec<Cell> = f
        .pieces
        .iter()
        .map(|&(part, p)| eval(part, p, p.a, p.b))
        .collect();
    loop {
        let total: f64 = cells.iter().map(|c| c.value).sum();
        let error: f64 = cells.iter().map(|c| c.error).sum();
        if error <= RELATIVE_TOLERANCE * total.abs() || cells.len() >= MAX_INTERVALS {
            let part_sum = |part: Part| {
                // a fold from +0: an empty f64 sum is −0
                cells
                    .iter()
                    .filter(|c| c.part == part)
                    .fold(0.0, |s, c| s + c.value)
            };
            return (total, part_sum(Part::Below), part_sum(Part::Above), error);
        }
        let worst = (0..cells.len())
            .max_by(|&i, &j| cells[i].error.total_cmp(&cells[j].error))
            .expect("at least one segment");
        let c = cells.swap_remove(worst);
        let mid = (c.a + c.b) / 2.0;
        cells.push(eval(c.part, c.piece, c.a, mid));
        cells.push(eval(c.part, c.piece, mid, c.b));
    }
}

/// The u = ln im at which the integrand peaks, with the hazard's log-slope
/// k taken as varying linearly between the segments' midpoints (constant
/// beyond the first and last): the log–log interpolant's slope jumps at
/// the levels, and so does the integrand, which would pin its maximum to
/// whichever level the hazard steepens at. A grid of [`PEAK_GRID`] points
/// over the integration range finds the highest cell; golden-section search
/// over its two neighbours refines it.
fn peak(f: &Integrand) -> f64 {
    const INV_PHI: f64 = 0.618_033_988_749_894_8;
    let (Some(first), Some(last)) = (f.pieces.first(), f.pieces.last()) else {
        return f64::NAN;
    };
    let (lo, hi) = (first.1.a, last.1.b);
    let g = |u: f64| f.smoothed(u);
    let h = (hi - lo) / PEAK_GRID as f64;
    let best = (0..=PEAK_GRID)
        .map(|i| lo + h * i as f64)
        .map(|u| (g(u), u))
        .fold(
            (f64::NEG_INFINITY, lo),
            |a, b| if b.0 > a.0 { b } else { a },
        );
    let (mut a, mut b) = ((best.1 - h).max(lo), (best.1 + h).min(hi));
    let (mut c, mut d) = (b - INV_PHI * (b - a), a + INV_PHI * (b - a));
    let (mut gc, mut gd) = (g(c), g(d));
    while b - a > 1e-12 * (1.0 + a.abs()) {
        if gc >= gd {
            b = d;
            (d, gd) = (c, gc);
            c = b - INV_PHI * (b - a);
            gc = g(c);
        } else {
            a = c;
            (c, gc) = (d, gd);
            d = a + INV_PHI * (b - a);
            gd = g(d);
        }
    }
    let u = (a + b) / 2.0;
    if g(u) >= best.0 { u } else { best.1 }
}
