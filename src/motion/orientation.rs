//! Two horizontal components and the direction a block faces.
//!
//! A recorded ground motion comes as two orthogonal horizontal components
//! H1 and H2. A block rocks in one vertical plane; if that plane makes the
//! angle φ with H1 (counted towards H2), the block feels the component of the
//! ground motion along it,
//!
//! ```text
//! a(φ) = cos φ · H1 + sin φ · H2      (and the same for velocity, displacement)
//! ```
//!
//! so a(0°) = H1, a(90°) = H2, a(φ + 180°) = −a(φ). The intensity of a pair
//! that does not depend on how the instrument was turned is **RotDnn**
//! (Boore 2010): the nn-th percentile over φ = 0°, 1°, …, 179° of the peak
//! |a(φ)|; RotD50 (the median) is what current ground-motion models, and so
//! OpenQuake's hazard, predict; RotD100 is the largest peak over directions.
//!
//! Angles are in degrees. Their sines and cosines are reduced to the octant
//! exactly ([`Pair::rotated`]): multiples of 90° give the components
//! themselves (or their negatives) bit for bit, and for whole degrees (any
//! angle whose sum with 90° or 180° is exact) the values at φ, 90° − φ,
//! 180° + φ, … are the same numbers up to order and sign, so a pair's RotD
//! does not change, to the bit, when H1 and H2 are swapped.
//!
//! Reference: Boore, D. M. (2010). Orientation-independent, nongeometric-mean
//! measures of seismic intensity from two horizontal components of motion.
//! *Bull. Seismol. Soc. Am.* 100(4), 1830–1835.

use std::f64::consts::FRAC_1_SQRT_2;
use std::fmt::Write;

use super::io::DT_REL_TOL;
use super::record::Record;
use crate::detmath;
use crate::error::{Error, Result};

/// Number of rotation angles of RotD: 0°, 1°, …, 179° (Boore 2010; the
/// peaks repeat from 180° on, a(φ + 180°) = −a(φ)).
pub const ROTD_ANGLES: usize = 180;

/// What a block's fixed orientation may be, in words: one turn, each
/// direction once (a spec's `grid.orientation` and fixed
/// `uncertainty.orientation`, and `rockfrag simulate --orientation`).
pub const ORIENTATION_EXPECTED: &str = "an angle in degrees in [0, 360)";

/// Whether `deg` is a fixed orientation a study or `simulate` takes
/// ([`ORIENTATION_EXPECTED`]): finite, in [0°, 360°).
pub fn is_orientation(deg: f64) -> bool {
    (0.0..360.0).contains(&deg)
}

/// Two orthogonal horizontal components of one ground motion, sampled
/// together: the same Δt (to [`DT_REL_TOL`] relative) and the same number of
/// samples ([`Pair::check`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Pair {
    /// The first component H1 (φ = 0°).
    pub h1: Record,
    /// The second component H2 (φ = 90°), 90° counter-clockwise from H1.
    pub h2: Record,
}

impl Pair {
    /// A pair from its two components, checked by [`Pair::check`].
    pub fn new(h1: Record, h2: Record) -> Result<Pair> {
        let pair = Pair { h1, h2 };
        pair.check()?;
        Ok(pair)
    }

    /// The pair's name, `H1+H2` from the components' names.
    pub fn name(&self) -> String {
        format!("{}+{}", self.h1.name, self.h2.name)
    }

    /// Checks that both components are valid records ([`Record::validate`])
    /// sampled together: Δt equal to [`DT_REL_TOL`] relative, the same
    /// number of samples, and the same vertical acceleration if both carry
    /// one.
    ///
    /// A mismatch is refused, not repaired. The two components of a record
    /// come from one instrument with one clock; a different Δt or length means
    /// the files are not a pair as given (another station or processing, a
    /// different start time, a trimmed file). Truncating to the shorter would
    /// keep the two misaligned if the start times differ and silently drop
    /// motion; padding would invent it. If the components are known to be
    /// aligned and only trailing samples differ, trim them in the files.
    pub fn check(&self) -> Result<()> {
        self.h1.validate()?;
        self.h2.validate()?;
        self.check_together()
    }

    /// The part of [`Pair::check`] that rotating relies on (run on every
    /// rotation, so no scan for non-finite values, which would only be
    /// carried into the rotated record): each component's Δt and series
    /// lengths, and the pair sampled together.
    fn check_together(&self) -> Result<()> {
        for h in [&self.h1, &self.h2] {
            if !(h.dt.is_finite() && h.dt > 0.0)
                || h.vel.len() != h.len()
                || h.disp.len() != h.len()
                || h.acc_v.as_ref().is_some_and(|v| v.len() != h.len())
            {
                // the record's own message
                h.validate()?;
            }
        }
        let (d1, d2) = (self.h1.dt, self.h2.dt);
        let bad = |message: String| Error::InvalidRecord {
            name: self.name(),
            message,
        };
        if (d1 - d2).abs() > DT_REL_TOL * d1 {
            return Err(bad(format!(
                "the components are sampled at different intervals (dt = {} s and {} s): \
                 a pair needs one time step; resample one component",
                crate::error::number(d1),
                crate::error::number(d2)
            )));
        }
        if self.h1.len() != self.h2.len() {
            return Err(bad(format!(
                "the components have different lengths ({} and {} samples): a pair's \
                 components start together and have as many samples; trim the longer \
                 one if they are aligned",
                self.h1.len(),
                self.h2.len()
            )));
        }
        if let (Some(v1), Some(v2)) = (&self.h1.acc_v, &self.h2.acc_v)
            && v1 != v2
        {
            return Err(bad(
                "the components carry different vertical accelerations".into()
            ));
        }
        Ok(())
    }

    /// The motion along the direction at `angle_deg` degrees from H1
    /// (towards H2): a(φ) = cos φ·H1 + sin φ·H2 for acceleration, velocity
    /// and displacement. See [`Pair::rotate_into`].
    ///
    /// ```
    /// use rockfrag::motion::{Pair, Record};
    /// let h1 = Record::from_acc("a-H1", 0.01, vec![0.0, 1.0, -0.3]).unwrap();
    /// let h2 = Record::from_acc("a-H2", 0.01, vec![0.0, 0.2, 0.7]).unwrap();
    /// let pair = Pair::new(h1.clone(), h2.clone()).unwrap();
    /// assert_eq!(pair.rotated(0.0).unwrap().acc, h1.acc);
    /// assert_eq!(pair.rotated(90.0).unwrap().acc, h2.acc);
    /// let diagonal = pair.rotated(45.0).unwrap();
    /// assert!((diagonal.acc[1] - 1.2 / 2f64.sqrt()).abs() < 1e-15);
    /// ```
    pub fn rotated(&self, angle_deg: f64) -> Result<Record> {
        let mut out = Record::empty(self.h1.dt);
        self.rotate_into(angle_deg, &mut out)?;
        Ok(out)
    }

    /// As [`Pair::rotated`], into `out`, reusing its buffers.
    ///
    /// The angle is any finite number of degrees, taken modulo 360°. At an
    /// exact multiple of 90° the series are H1, H2, −H1 or −H2 bit for bit;
    /// otherwise each sample is `c·h1 + s·h2` with (s, c) the angle's sine and
    /// cosine. The record has H1's Δt, the vertical acceleration of whichever
    /// component carries one, and the name `H1+H2@φdeg` (φ as given).
    ///
    /// Errors: a non-finite angle, or components that are not sampled
    /// together ([`Pair::check`]; non-finite samples are not looked for on
    /// every rotation: they are carried into the record); `out` is left
    /// unchanged then.
    pub fn rotate_into(&self, angle_deg: f64, out: &mut Record) -> Result<()> {
        self.rotate_scaled_into(None, angle_deg, out)
    }

    /// [`Pair::rotate_into`] of the pair with both components scaled by `k`
    /// first (`None`: not scaled), in one pass: each sample is scaled, k·x,
    /// then turned, the arithmetic of [`Record::scaled`] then
    /// [`Pair::rotate_into`], without copying the pair.
    fn rotate_scaled_into(&self, k: Option<f64>, angle_deg: f64, out: &mut Record) -> Result<()> {
        let turn = Turn::new(angle_deg)?;
        self.check_together()?;
        out.name.clear();
        write!(
            out.name,
            "{}+{}@{}deg",
            self.h1.name, self.h2.name, angle_deg
        )
        .expect("writing to a String");
        out.dt = self.h1.dt;
        out.acc_v.clone_from(if self.h1.acc_v.is_some() {
            &self.h1.acc_v
        } else {
            &self.h2.acc_v
        });
        if let (Some(k), Some(v)) = (k, out.acc_v.as_mut()) {
            v.iter_mut().for_each(|x| *x *= k);
        }
        let (h1, h2) = (&self.h1, &self.h2);
        for (o, x1, x2) in [
            (&mut out.acc, &h1.acc, &h2.acc),
            (&mut out.vel, &h1.vel, &h2.vel),
            (&mut out.disp, &h1.disp, &h2.disp),
        ] {
            match k {
                None => turn.apply(x1, x2, |x| x, o),
                Some(k) => turn.apply(x1, x2, |x| x * k, o),
            }
        }
        Ok(())
    }
}

/// A rotation by an angle: exactly onto a component at multiples of 90°.
#[derive(Clone, Copy, Debug)]
enum Turn {
    /// ±H1 (`second` false) or ±H2.
    Axis { second: bool, negate: bool },
    /// cos φ·H1 + sin φ·H2.
    General { cos: f64, sin: f64 },
}

impl Turn {
    fn new(angle_deg: f64) -> Result<Turn> {
        if !angle_deg.is_finite() {
            return Err(Error::invalid(
                "orientation",
                angle_deg,
                "a finite angle in degrees from the first component",
            ));
        }
        let (q, x) = quadrant(angle_deg);
        Ok(if x == 0.0 {
            Turn::Axis {
                second: q % 2 == 1,
                negate: q >= 2,
            }
        } else {
            let (sin, cos) = sin_cos_deg(angle_deg);
            Turn::General { cos, sin }
        })
    }

    /// The turned series of `x1`, `x2`, each sample taken through `scale`
    /// first.
    #[inline]
    fn apply(self, x1: &[f64], x2: &[f64], scale: impl Fn(f64) -> f64, out: &mut Vec<f64>) {
        out.clear();
        match self {
            Turn::Axis { second, negate } => {
                let x = if second { x2 } else { x1 };
                if negate {
                    out.extend(x.iter().map(|&v| -scale(v)));
                } else {
                    out.extend(x.iter().map(|&v| scale(v)));
                }
            }
            Turn::General { cos, sin } => {
                out.extend(
                    x1.iter()
                        .zip(x2)
                        .map(|(&a, &b)| cos * scale(a) + sin * scale(b)),
                );
            }
        }
    }
}

/// The angle reduced to a quarter turn: (q, x) with φ ≡ 90°·q + x (mod
/// 360°), q in 0..4 and |x| ≤ 45°. Exact: fmod is exact, and x = r − 90q
/// subtracts numbers within a factor 2 of each other (Sterbenz) when q ≥ 1.
fn quadrant(angle_deg: f64) -> (u8, f64) {
    let r = angle_deg.rem_euclid(360.0);
    let q = (r / 90.0).round();
    ((q as u8) % 4, r - 90.0 * q)
}

/// (sin φ, cos φ) of an angle in degrees, through the octant: the only
/// transcendental functions of this module, and only on |x| < 45° (π/4); at
/// |x| = 45° both are 1/√2 (correctly rounded), so that diagonal directions
/// weigh the components equally, to the bit.
// Through detmath (libm): the same bits on every platform.
fn sin_cos_deg(angle_deg: f64) -> (f64, f64) {
    let (q, x) = quadrant(angle_deg);
    let (s, c) = if x == 0.0 {
        (0.0, 1.0)
    } else if x.abs() == 45.0 {
        (FRAC_1_SQRT_2.copysign(x), FRAC_1_SQRT_2)
    } else {
        detmath::sin_cos(x.to_radians())
    };
    match q {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// The peak |a(φ)| = max over samples of |cos φ·x1 + sin φ·x2| at each of
/// the angles φ = 0°, 1°, …, 179° (units of the series). At every angle it
/// equals the peak of [`Pair::rotated`]'s series bit for bit. Errors if the
/// lengths differ.
pub fn rotated_peaks(x1: &[f64], x2: &[f64]) -> Result<[f64; ROTD_ANGLES]> {
    if x1.len() != x2.len() {
        return Err(Error::invalid(
            "rotated series",
            format!("lengths {} and {}", x1.len(), x2.len()),
            "two series of the same length",
        ));
    }
    let mut cos = [0.0; ROTD_ANGLES];
    let mut sin = [0.0; ROTD_ANGLES];
    for (i, (c, s)) in cos.iter_mut().zip(sin.iter_mut()).enumerate() {
        (*s, *c) = sin_cos_deg(i as f64);
    }
    let mut peak = [0.0_f64; ROTD_ANGLES];
    // all angles per sample: the inner loop runs over independent lanes
    let project = |peak: &mut [f64; ROTD_ANGLES], a: f64, b: f64| {
        for ((p, c), s) in peak.iter_mut().zip(&cos).zip(&sin) {
            *p = p.max((c * a + s * b).abs());
        }
    };
    // A sparse pass first: every PEAK_STRIDE-th sample bounds every peak
    // from below by `low`, the smallest of its peaks.
    for (a, b) in x1.iter().zip(x2).step_by(PEAK_STRIDE) {
        project(&mut peak, *a, *b);
    }
    let low = peak.iter().copied().fold(f64::INFINITY, f64::min);
    // Then only the samples that can reach `low`: |cos φ·a + sin φ·b| ≤
    // |(a, b)| (Cauchy–Schwarz), so a sample with |(a, b)| < low projects
    // below every peak at every angle and cannot change a maximum. The
    // margins cover the rounding of a² + b², of low², of the projection and
    // of cos² + sin² (a few ulps each): a sample is skipped only if its
    // computed projection is certainly below `low`, so the peaks are those
    // of every sample, bit for bit (a maximum is exact).
    let bound = low * low * (1.0 - 2.0 * f64::EPSILON);
    for (a, b) in x1.iter().zip(x2) {
        if (a * a + b * b) * (1.0 + 16.0 * f64::EPSILON) >= bound {
            project(&mut peak, *a, *b);
        }
    }
    Ok(peak)
}

/// The stride of [`rotated_peaks`]'s first, sparse pass: short enough that
/// the strong phase of a record gives it peaks near the final ones (a
/// record at 0.005–0.02 s has several samples per half cycle of its
/// dominant motion), long enough to cost an eighth of a full pass.
const PEAK_STRIDE: usize = 8;

/// RotDnn of two series: the `percentile`-th percentile (0…100) of
/// [`rotated_peaks`], interpolated linearly between the sorted peaks at
/// position p/100·179 (numpy's default; with 180 angles RotD50 is the mean of
/// the 90th and 91st smallest peaks, RotD100 the largest, RotD00 the
/// smallest).
pub fn rotd_series(x1: &[f64], x2: &[f64], percentile: f64) -> Result<f64> {
    if !(0.0..=100.0).contains(&percentile) {
        return Err(Error::invalid(
            "percentile",
            percentile,
            "a percentile from 0 to 100 (50 for RotD50)",
        ));
    }
    let mut peaks = rotated_peaks(x1, x2)?;
    peaks.sort_by(f64::total_cmp);
    let pos = percentile / 100.0 * (ROTD_ANGLES - 1) as f64;
    let lo = pos.floor() as usize;
    let frac = pos - lo as f64;
    Ok(if frac == 0.0 {
        peaks[lo]
    } else {
        peaks[lo] + frac * (peaks[lo + 1] - peaks[lo])
    })
}

/// RotDnn PGA of a pair (m/s²): [`rotd_series`] of the two accelerations;
/// `rotd(pair, 50.0)` is RotD50, `rotd(pair, 100.0)` RotD100. Errors: the
/// pair's [`Pair::check`] errors, a percentile outside 0…100.
///
/// ```
/// use rockfrag::motion::{Pair, Record, rotd};
/// let h1 = Record::from_acc("H1", 0.01, vec![0.0, 2.0, -1.0]).unwrap();
/// let h2 = Record::from_acc("H2", 0.01, vec![0.0; 3]).unwrap();
/// let pair = Pair::new(h1, h2).unwrap();
/// // peak |a(φ)| = 2 |cos φ|: the median over 0°…179° is 2 cos 45°
/// assert!((rotd(&pair, 50.0).unwrap() - 2f64.sqrt()).abs() < 1e-15);
/// assert_eq!(rotd(&pair, 100.0).unwrap(), 2.0);
/// ```
pub fn rotd(pair: &Pair, percentile: f64) -> Result<f64> {
    // the full check: RotD is computed once per pair, in 180 passes over it
    pair.check()?;
    rotd_series(&pair.h1.acc, &pair.h2.acc, percentile)
}

/// A record pair with its RotD50 peaks, measured once: scaling a pair by
/// k > 0 scales every rotated peak by k, so the factor that brings it to a
/// RotD50 level is target/RotD50.
#[derive(Clone, Debug, PartialEq)]
pub struct MeasuredPair {
    /// The two components.
    pub pair: Pair,
    /// RotD50 of the acceleration (PGA), m/s².
    pub pga: f64,
    /// RotD50 of the velocity (PGV), m/s.
    pub pgv: f64,
}

impl MeasuredPair {
    /// Checks `pair` and measures its RotD50 PGA and PGV.
    pub fn new(pair: Pair) -> Result<MeasuredPair> {
        let pga = rotd(&pair, 50.0)?;
        let pgv = rotd_series(&pair.h1.vel, &pair.h2.vel, 50.0)?;
        Ok(MeasuredPair { pair, pga, pgv })
    }

    /// The motion along `angle_deg` of the pair scaled by `k`: both
    /// components scaled first, then turned ([`Pair::rotated`]), the order
    /// `rockfrag simulate --motion2` and a study share, so both give the
    /// same bits.
    ///
    /// ```
    /// use rockfrag::motion::{MeasuredPair, Pair, Record};
    /// let h1 = Record::from_acc("H1", 0.01, vec![0.0, 1.0, -0.5]).unwrap();
    /// let h2 = Record::from_acc("H2", 0.01, vec![0.0, 0.5, 1.0]).unwrap();
    /// let m = MeasuredPair::new(Pair::new(h1.clone(), h2).unwrap()).unwrap();
    /// assert_eq!(m.felt(2.0, 0.0).unwrap().acc, h1.scaled(2.0).acc);
    /// ```
    pub fn felt(&self, k: f64, angle_deg: f64) -> Result<Record> {
        // one pass, no copy of the pair: the same bits as
        // `Pair { h1: h1.scaled(k), h2: h2.scaled(k) }.rotated(angle_deg)`
        let mut out = Record::empty(self.pair.h1.dt);
        self.pair.rotate_scaled_into(Some(k), angle_deg, &mut out)?;
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every sample at every angle: what [`rotated_peaks`] must equal.
    fn peaks_brute_force(x1: &[f64], x2: &[f64]) -> [f64; ROTD_ANGLES] {
        let mut peak = [0.0_f64; ROTD_ANGLES];
        for (a, b) in x1.iter().zip(x2) {
            for (i, p) in peak.iter_mut().enumerate() {
                let (s, c) = sin_cos_deg(i as f64);
                *p = p.max((c * a + s * b).abs());
            }
        }
        peak
    }

    /// The filtered peaks are the brute-force peaks bit for bit: on
    /// records (where most samples are skipped), on a circular pair (every
    /// sample at the same radius: none can be skipped, and rounding decides
    /// which is largest), on a pair with a zero component (the smallest
    /// peak is 0: nothing is skipped), on a single spike and on samples a
    /// few ulps apart. A filter that skips samples 5 % inside the bound
    /// fails it; the few-ulp margins themselves are argued in
    /// [`rotated_peaks`], not exercised here.
    #[test]
    fn filtered_peaks_are_the_brute_force_peaks() {
        use crate::motion::{SynthesisSettings, synthesize};
        let settings = SynthesisSettings::default();
        let mut cases: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
        for k in 0..6 {
            let h1 = synthesize(&settings, 3, 2 * k, 3.0).unwrap();
            let h2 = synthesize(&settings, 3, 2 * k + 1, 1.0 + k as f64).unwrap();
            cases.push((h1.vel.clone(), h2.vel.clone()));
            cases.push((h1.acc, h2.acc));
        }
        let n = 2000;
        let phase = |i: usize| i as f64 * 0.0137;
        let (sin, cos): (Vec<f64>, Vec<f64>) = (0..n).map(|i| detmath::sin_cos(phase(i))).unzip();
        cases.push((
            cos.iter().map(|c| 2.0 * c).collect(),
            sin.iter().map(|s| 2.0 * s).collect(),
        ));
        cases.push((sin, vec![0.0; n]));
        let mut spike = vec![0.0; n];
        spike[n / 3] = 1.5;
        cases.push((spike.clone(), spike.iter().map(|x| -0.5 * x).collect()));
        // values a few ulps apart
        let r = 1.0 / 3.0;
        let near: Vec<f64> = (0..n)
            .map(|i| {
                r * (1.0 + (i % 7) as f64 * f64::EPSILON * if i % 2 == 0 { 1.0 } else { -1.0 })
            })
            .collect();
        cases.push((near.clone(), near.iter().rev().copied().collect()));
        for (k, (x1, x2)) in cases.iter().enumerate() {
            let got = rotated_peaks(x1, x2).unwrap();
            let want = peaks_brute_force(x1, x2);
            assert!(
                got.iter()
                    .zip(&want)
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
                "case {k}"
            );
        }
    }

    /// The octant reduction is exact at the axes and symmetric: sin φ =
    /// cos(90° − φ) to the bit, and a half turn negates both exactly.
    /// `felt` (scaled and turned in one pass) gives the bits of the pair's
    /// components scaled first and then turned, on and off the axes, with a
    /// vertical acceleration too.
    #[test]
    fn felt_is_scaled_then_turned_bit_for_bit() {
        use crate::motion::{SynthesisSettings, synthesize};
        let settings = SynthesisSettings::default();
        let mut h1 = synthesize(&settings, 9, 0, 3.0).unwrap();
        let h2 = synthesize(&settings, 9, 1, 2.0).unwrap();
        for vertical in [false, true] {
            if vertical {
                h1.acc_v = Some(h1.acc.iter().map(|a| 0.3 * a).collect());
            }
            let m = MeasuredPair {
                pair: Pair {
                    h1: h1.clone(),
                    h2: h2.clone(),
                },
                pga: 1.0,
                pgv: 1.0,
            };
            for k in [0.37, 1.0, 2.9] {
                for angle in [0.0, 33.0, 90.0, 180.0, 271.5, -90.0] {
                    let old = Pair {
                        h1: h1.clone().scaled(k),
                        h2: h2.clone().scaled(k),
                    }
                    .rotated(angle)
                    .unwrap();
                    let new = m.felt(k, angle).unwrap();
                    let bits = |r: &Record| {
                        [
                            &r.acc,
                            &r.vel,
                            &r.disp,
                            r.acc_v.as_ref().unwrap_or(&Vec::new()),
                        ]
                        .map(|v| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>())
                    };
                    assert_eq!(bits(&new), bits(&old), "k {k}, angle {angle}");
                    assert_eq!((new.name, new.dt), (old.name, old.dt));
                }
            }
        }
    }

    #[test]
    fn degrees_reduce_exactly() {
        assert_eq!(sin_cos_deg(0.0), (0.0, 1.0));
        assert_eq!(sin_cos_deg(90.0), (1.0, -0.0));
        assert_eq!(sin_cos_deg(180.0), (-0.0, -1.0));
        assert_eq!(sin_cos_deg(-90.0), (-1.0, 0.0));
        for i in -1600..1600 {
            let phi = i as f64 * 0.25;
            let (s, c) = sin_cos_deg(phi);
            let (s2, c2) = sin_cos_deg(90.0 - phi);
            assert_eq!((s, c), (c2, s2), "{phi}");
            let (s3, c3) = sin_cos_deg(phi + 180.0);
            assert_eq!((s3, c3), (-s, -c), "{phi}");
            // against radians directly: the radian argument of |φ| ≤ 400°
            // (7 rad) is itself rounded by up to 4.4e-16, and the results by
            // half an ulp each
            let (se, ce) = detmath::sin_cos(phi.to_radians());
            assert!((s - se).abs() < 1e-15 && (c - ce).abs() < 1e-15, "{phi}");
        }
    }
}
