//! Uncertain block parameters: the distributions of a spec's `[uncertainty]`
//! table and the per-analysis draws from them.
//!
//! An engineer rarely knows a statue's coefficient of restitution or a
//! cabinet's friction to two digits. Instead of a grid value, a parameter
//! can be given a distribution; every analysis then draws its own value, and
//! the fragility curve of a case is fitted over those draws (it includes the
//! parameter's uncertainty, as a fragility for a class of objects should).
//!
//! **Reproducibility.** The draws of one analysis come from their own
//! Xoshiro256++ stream, seeded by [`analysis_seed`]`(seed, record, level,
//! case)`. They depend on nothing else (not on the thread that runs the
//! analysis, nor on the shard), so `outcomes.csv` stays byte-identical for
//! any thread count and shard split. Every analysis takes one uniform number
//! per parameter, in the fixed order of [`Property::ALL`], whether or not the
//! parameter is drawn: adding a distribution for one parameter does not
//! change the draws of another.
//!
//! **Sampling.** By inversion, `x = F⁻¹(u)` with `u` uniform in `[0, 1)`; a
//! truncated distribution maps `u` into `[F(min), F(max)]` first, so every
//! draw lies within the bounds and none is rejected.

use crate::detmath as dm;
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// A probability distribution of one block parameter.
///
/// ```
/// use rockfrag::uncertainty::Distribution;
/// let d = Distribution::Uniform { min: 0.0, max: 0.9 };
/// assert_eq!(d.quantile(0.5), 0.45);
/// let ln = Distribution::Lognormal { median: 0.6, beta: 0.15, min: None, max: None };
/// assert!((ln.quantile(0.5) - 0.6).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "dist", rename_all = "lowercase", deny_unknown_fields)]
pub enum Distribution {
    /// Uniform on `[min, max]`.
    Uniform {
        /// Lower bound.
        min: f64,
        /// Upper bound (> min).
        max: f64,
    },
    /// Normal with mean and standard deviation, optionally truncated to
    /// `[min, max]`.
    Normal {
        /// Mean (of the untruncated distribution).
        mean: f64,
        /// Standard deviation (> 0, of the untruncated distribution).
        sd: f64,
        /// Lower truncation bound (default: none).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        min: Option<f64>,
        /// Upper truncation bound (default: none).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        max: Option<f64>,
    },
    /// Lognormal: `median · exp(beta · z)`, z standard normal, optionally
    /// truncated to `[min, max]`.
    Lognormal {
        /// Median (> 0).
        median: f64,
        /// Standard deviation of ln x (> 0), the "β" of fragility practice.
        beta: f64,
        /// Lower truncation bound (default: none).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        min: Option<f64>,
        /// Upper truncation bound (default: none).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        max: Option<f64>,
    },
}

impl Distribution {
    /// The smallest and largest values a draw can take (±∞ when unbounded).
    pub fn support(&self) -> (f64, f64) {
        match *self {
            Distribution::Uniform { min, max } => (min, max),
            Distribution::Normal { min, max, .. } => (
                min.unwrap_or(f64::NEG_INFINITY),
                max.unwrap_or(f64::INFINITY),
            ),
            Distribution::Lognormal { min, max, .. } => {
                (min.unwrap_or(0.0), max.unwrap_or(f64::INFINITY))
            }
        }
    }

    /// The value whose (truncated) cumulative probability is `u` ∈ [0, 1]:
    /// the inverse CDF, which turns a uniform number into a draw.
    pub fn quantile(&self, u: f64) -> f64 {
        match *self {
            Distribution::Uniform { min, max } => min + u * (max - min),
            Distribution::Normal { mean, sd, min, max } => {
                // z-bounds of the truncation, then inversion of Φ.
                let lo = min.map_or(f64::NEG_INFINITY, |m| (m - mean) / sd);
                let hi = max.map_or(f64::INFINITY, |m| (m - mean) / sd);
                let x = mean + sd * truncated_z(u, lo, hi);
                x.clamp(self.support().0, self.support().1)
            }
            Distribution::Lognormal {
                median,
                beta,
                min,
                max,
            } => {
                // ln x = ln median + β z, z truncated to the bounds' z-values.
                let z = |m: f64| dm::ln(m / median) / beta;
                let lo = min.map_or(f64::NEG_INFINITY, z);
                let hi = max.map_or(f64::INFINITY, z);
                let x = median * dm::exp(beta * truncated_z(u, lo, hi));
                x.clamp(self.support().0, self.support().1)
            }
        }
    }

    /// Checks the distribution's own parameters and that every draw lies in
    /// `[lo, hi]`, the parameter's physical range. `field` names the
    /// parameter in errors (e.g. `restitution`); `what` describes the range.
    pub fn validate(&self, field: &str, lo: f64, hi: f64, what: &str) -> Result<()> {
        let bad = |sub: &str, v: f64, expected: String| {
            Err(Error::invalid(&format!("{field}.{sub}"), v, &expected))
        };
        let finite = |sub: &str, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                bad(sub, v, "a finite number".into())
            }
        };
        match *self {
            Distribution::Uniform { min, max } => {
                finite("min", min)?;
                finite("max", max)?;
                if max <= min {
                    return bad("max", max, format!("a bound above min = {min}"));
                }
            }
            Distribution::Normal { mean, sd, min, max } => {
                finite("mean", mean)?;
                if !(sd.is_finite() && sd > 0.0) {
                    return bad("sd", sd, "a positive standard deviation".into());
                }
                truncation(field, min, max)?;
            }
            Distribution::Lognormal {
                median,
                beta,
                min,
                max,
            } => {
                if !(median.is_finite() && median > 0.0) {
                    return bad("median", median, "a positive median".into());
                }
                if !(beta.is_finite() && beta > 0.0) {
                    return bad("beta", beta, "a positive log standard deviation".into());
                }
                truncation(field, min, max)?;
                if let Some(m) = min.filter(|&m| m <= 0.0) {
                    return bad(
                        "min",
                        m,
                        "a positive bound (a lognormal is positive)".into(),
                    );
                }
            }
        }
        // A support reaching past the parameter's range: name the bound
        // (`min`/`max`), or `dist` for an untruncated unbounded side.
        let outside = |side: &str, bound: f64, expected: String| {
            let sub = if bound.is_finite() || matches!(self, Distribution::Uniform { .. }) {
                side
            } else {
                "dist"
            };
            let value = if bound.is_finite() {
                bound.to_string()
            } else {
                "(unbounded)".into()
            };
            Err(Error::invalid(&format!("{field}.{sub}"), value, &expected))
        };
        let (s_lo, s_hi) = self.support();
        if s_lo < lo {
            return outside(
                "min",
                s_lo,
                if lo == f64::MIN_POSITIVE {
                    format!("a lower bound > 0: {what} (truncate the distribution with `min`)")
                } else {
                    format!("a lower bound ≥ {lo}: {what} (truncate the distribution with `min`)")
                },
            );
        }
        if s_hi > hi {
            return outside(
                "max",
                s_hi,
                format!("an upper bound ≤ {hi}: {what} (truncate the distribution with `max`)"),
            );
        }
        // The truncation must keep some probability, or the inversion is
        // numerically meaningless (bounds many standard deviations out).
        let (p_lo, p_hi) = (self.quantile(0.0), self.quantile(1.0));
        if !(p_lo.is_finite() || p_hi.is_finite()) || p_hi < p_lo {
            return Err(Error::invalid(
                field,
                format!("{self:?}"),
                "a distribution whose bounds keep a range of values",
            ));
        }
        Ok(())
    }
}

/// The truncation bounds of a normal or lognormal: finite, min < max.
fn truncation(field: &str, min: Option<f64>, max: Option<f64>) -> Result<()> {
    for (sub, v) in [("min", min), ("max", max)] {
        if let Some(v) = v.filter(|v| !v.is_finite()) {
            return Err(Error::invalid(
                &format!("{field}.{sub}"),
                v,
                "a finite bound",
            ));
        }
    }
    if let (Some(lo), Some(hi)) = (min, max)
        && hi <= lo
    {
        return Err(Error::invalid(
            &format!("{field}.max"),
            hi,
            &format!("a bound above min = {}", crate::error::number(lo)),
        ));
    }
    Ok(())
}

/// A standard normal z truncated to `[lo, hi]` at cumulative probability `u`
/// of the truncated distribution: Φ⁻¹(Φ(lo) + u·(Φ(hi) − Φ(lo))). Works on
/// the upper tail's mirror when both bounds are above 0, so that far-tail
/// truncations keep their digits; where the tail beyond the nearer bound
/// holds less than [`FAR_TAIL`] (about 37 standard deviations out, where
/// Φ underflows and every draw became the far bound), it inverts the
/// truncated CDF in log-survival space instead ([`far_tail_z`]).
fn truncated_z(u: f64, lo: f64, hi: f64) -> f64 {
    if lo > 0.0 {
        // Mirror: z = −Φ⁻¹(Φ(−lo) − u (Φ(−lo) − Φ(−hi))).
        let (a, b) = (dm::norm_cdf(-lo), dm::norm_cdf(-hi));
        if a < FAR_TAIL {
            return far_tail_z(u, lo, hi);
        }
        return -dm::norm_inv_cdf((a - u * (a - b)).clamp(0.0, 1.0));
    }
    let (a, b) = (dm::norm_cdf(lo), dm::norm_cdf(hi));
    if b < FAR_TAIL {
        // Both bounds far in the lower tail: the mirror of the upper one.
        return -far_tail_z(1.0 - u, -hi, -lo);
    }
    dm::norm_inv_cdf((a + u * (b - a)).clamp(0.0, 1.0))
}

/// Tail mass below which [`truncated_z`] leaves Φ and Φ⁻¹ for
/// [`far_tail_z`]: Φ(−37.5) ≈ 5·10⁻³⁰⁸ is where Φ leaves the normal range
/// of `f64`, and AS 241's Φ⁻¹ is accurate down to about 10⁻³⁰⁰. Every
/// truncation with more mass beyond its nearer bound keeps its draws bit
/// for bit.
const FAR_TAIL: f64 = 1e-300;

/// z·Q(z)/φ(z) for z ≥ 1 (Q = 1 − Φ, φ the density): Laplace's continued
/// fraction Q(z)/φ(z) = 1/(z + 1/(z + 2/(z + 3/(z + …)))), 60 terms from
/// the back (exact to rounding from z ≈ 5 up; it tends to 1 − 1/z²).
fn mills_z(z: f64) -> f64 {
    let mut t = z;
    for k in (1..=60).rev() {
        t = z + k as f64 / t;
    }
    z / t
}

/// ln Q(lo + t) − ln Q(lo) for t ≥ 0, lo ≥ 1, without forming Q:
/// −t (lo + t/2) − ln(1 + t/lo) + ln r(lo + t) − ln r(lo), r = [`mills_z`]
/// (ln Q(z) = −z²/2 − ln √(2π) − ln z + ln r(z)).
fn ln_survival_drop(lo: f64, t: f64) -> f64 {
    -t * (lo + 0.5 * t) - dm::ln_1p(t / lo) + dm::ln(mills_z(lo + t)) - dm::ln(mills_z(lo))
}

/// The z ∈ [lo, hi] (lo ≥ 1) at cumulative probability `u` of a standard
/// normal truncated there, from its log-survival function: Q(z)/Q(lo) =
/// 1 − u (1 − Q(hi)/Q(lo)), i.e. D(t) = ln(1 + u·expm1(D(hi − lo))) with
/// D(t) = ln Q(lo + t) − ln Q(lo) ([`ln_survival_drop`]), solved for
/// t = z − lo by Newton's method (D is concave and decreasing, D′(t) =
/// −z/r(z): from its first step on, the iterates fall monotonically to the
/// root). Good for any lo whose tail Φ cannot hold: the draws spread over
/// the bound's exponential tail, of scale ≈ 1/lo, as they should.
fn far_tail_z(u: f64, lo: f64, hi: f64) -> f64 {
    let span = hi - lo;
    let drop_hi = if span.is_finite() {
        ln_survival_drop(lo, span)
    } else {
        f64::NEG_INFINITY
    };
    let target = dm::ln_1p(u * dm::exp_m1(drop_hi));
    if target == f64::NEG_INFINITY {
        return hi;
    }
    if target == 0.0 {
        return lo;
    }
    // The exponential tail's answer, Newton's first step from t = 0.
    let mut t = (-target * mills_z(lo) / lo).min(span);
    for _ in 0..100 {
        let z = lo + t;
        let slope = -z / mills_z(z);
        let next = (t - (ln_survival_drop(lo, t) - target) / slope).clamp(0.0, span);
        let done = (next - t).abs() <= 4.0 * f64::EPSILON * next;
        t = next;
        if done {
            break;
        }
    }
    lo + t
}

/// A block property that `[uncertainty]` can draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Property {
    /// Base width 2B, m.
    Width,
    /// Aspect ratio H/B.
    Aspect,
    /// Coefficient of restitution e.
    Restitution,
    /// Static friction coefficient μs.
    MuS,
    /// μk/μs, so that μk ≤ μs by construction.
    MuKOverMuS,
}

impl Property {
    /// Every parameter, in the order an analysis draws them.
    pub const ALL: [Property; 5] = [
        Property::Width,
        Property::Aspect,
        Property::Restitution,
        Property::MuS,
        Property::MuKOverMuS,
    ];

    /// The position of the property in [`Property::ALL`]: the index of its
    /// uniform number among an analysis's draws ([`uniforms`]).
    pub fn index(self) -> usize {
        self as usize
    }

    /// The parameter's key in `[uncertainty]`.
    pub fn name(self) -> &'static str {
        match self {
            Property::Width => "width",
            Property::Aspect => "aspect",
            Property::Restitution => "restitution",
            Property::MuS => "mu_s",
            Property::MuKOverMuS => "mu_k_over_mu_s",
        }
    }

    /// The physical range `[lo, hi]` of the parameter and its description.
    pub fn range(self) -> (f64, f64, &'static str) {
        match self {
            Property::Width => (
                f64::MIN_POSITIVE,
                f64::INFINITY,
                "a positive base width 2B in m",
            ),
            Property::Aspect => (
                f64::MIN_POSITIVE,
                f64::INFINITY,
                "a positive aspect ratio H/B",
            ),
            Property::Restitution => (0.0, 1.0, "a coefficient of restitution in [0, 1]"),
            Property::MuS => (0.0, f64::INFINITY, "a static friction coefficient μs ≥ 0"),
            Property::MuKOverMuS => (0.0, 1.0, "a ratio μk/μs in [0, 1]"),
        }
    }
}

/// A property of one body of a stack that `[uncertainty.stack.NAME.BODY]`
/// can draw: the body's own (width, height or aspect, mass or density,
/// offset) and those of the interface it stands on (restitution, friction),
/// as a single block's `[uncertainty]` draws its own and its contact's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StackProperty {
    /// Width 2B, m.
    Width,
    /// Height 2H, m.
    Height,
    /// Aspect ratio H/B (the height is then aspect × width).
    Aspect,
    /// Mass relative to the other bodies' (where the stack gives masses).
    Mass,
    /// Density relative to the other bodies' (where the stack gives none of
    /// its masses: mass = density × width × height).
    Density,
    /// Offset of the body's centre from the centre of the body below, m.
    Offset,
    /// Coefficient of restitution e of the interface under the body.
    Restitution,
    /// μs of the interface under the body (with `mu_k_over_mu_s`).
    MuS,
    /// μk/μs of the interface under the body (with `mu_s`).
    MuKOverMuS,
}

impl StackProperty {
    /// Every property, in the order an analysis draws them for each body.
    pub const ALL: [StackProperty; 9] = [
        StackProperty::Width,
        StackProperty::Height,
        StackProperty::Aspect,
        StackProperty::Mass,
        StackProperty::Density,
        StackProperty::Offset,
        StackProperty::Restitution,
        StackProperty::MuS,
        StackProperty::MuKOverMuS,
    ];

    /// The position of the property in [`StackProperty::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// The property's key under `[uncertainty.stack.NAME.BODY]`.
    pub fn name(self) -> &'static str {
        match self {
            StackProperty::Width => "width",
            StackProperty::Height => "height",
            StackProperty::Aspect => "aspect",
            StackProperty::Mass => "mass",
            StackProperty::Density => "density",
            StackProperty::Offset => "offset",
            StackProperty::Restitution => "restitution",
            StackProperty::MuS => "mu_s",
            StackProperty::MuKOverMuS => "mu_k_over_mu_s",
        }
    }

    /// The physical range `[lo, hi]` of the property and its description.
    pub fn range(self) -> (f64, f64, &'static str) {
        let positive = f64::MIN_POSITIVE;
        match self {
            StackProperty::Width => (positive, f64::INFINITY, "a positive width 2B in m"),
            StackProperty::Height => (positive, f64::INFINITY, "a positive height 2H in m"),
            StackProperty::Aspect => Property::Aspect.range(),
            StackProperty::Mass => (positive, f64::INFINITY, "a positive relative mass"),
            StackProperty::Density => (positive, f64::INFINITY, "a positive relative density"),
            StackProperty::Offset => (
                f64::NEG_INFINITY,
                f64::INFINITY,
                "a finite offset in m (the footprint within the face below)",
            ),
            // the interface's, as a block's contact with the ground
            StackProperty::Restitution => Property::Restitution.range(),
            StackProperty::MuS => Property::MuS.range(),
            StackProperty::MuKOverMuS => Property::MuKOverMuS.range(),
        }
    }
}

/// The level and case keys' domain tag of a stack's draws: a stack's
/// analysis draws its bodies' properties from a stream of its own, not the
/// block draws' of the same (seed, record, level, case).
const STACK_STREAM: u64 = 0x57AC_D2A5_0B0D_1E50;

/// The uniform numbers of one stack analysis's draws: one per body (up to
/// three, bottom first) and property of [`StackProperty::ALL`], in that
/// order, whatever is drawn (adding a distribution for one property does
/// not change the draws of another), from the stream
/// [`analysis_seed`]`(seed ^ tag, record, level, case)`.
///
/// ```
/// use rockfrag::uncertainty::stack_uniforms;
/// let u = stack_uniforms(1, 0, 0, 3);
/// assert!(u.iter().flatten().all(|&x| (0.0..1.0).contains(&x)));
/// assert_ne!(u, stack_uniforms(1, 1, 0, 3));
/// ```
pub fn stack_uniforms(
    seed: u64,
    record: u64,
    level: u64,
    case: u64,
) -> [[f64; StackProperty::ALL.len()]; 3] {
    let mut rng =
        Xoshiro256PlusPlus::seed_from_u64(analysis_seed(seed ^ STACK_STREAM, record, level, case));
    std::array::from_fn(|_| std::array::from_fn(|_| rng.random::<f64>()))
}

/// How one parameter is given under `[uncertainty]`: a distribution, or (for
/// `mu_s` and `mu_k_over_mu_s`) a fixed number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// The same value for every analysis.
    Fixed(f64),
    /// Drawn per analysis.
    Drawn(Distribution),
}

impl Value {
    /// The value at cumulative probability `u` (a fixed value ignores `u`).
    pub fn at(&self, u: f64) -> f64 {
        match self {
            Value::Fixed(x) => *x,
            Value::Drawn(d) => d.quantile(u),
        }
    }

    /// Whether the value is drawn.
    pub fn is_drawn(&self) -> bool {
        matches!(self, Value::Drawn(_))
    }
}

impl Serialize for Value {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            Value::Fixed(x) => s.serialize_f64(*x),
            Value::Drawn(d) => d.serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for Value {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Raw {
            Number(f64),
            Table(toml::Table),
        }
        match Raw::deserialize(d).map_err(|_| {
            serde::de::Error::custom(
                "expected a number or a distribution table such as \
                 { dist = \"uniform\", min = 0.0, max = 0.9 }",
            )
        })? {
            Raw::Number(x) => Ok(Value::Fixed(x)),
            Raw::Table(t) => Distribution::deserialize(toml::Value::Table(t))
                .map(Value::Drawn)
                .map_err(|e| {
                    serde::de::Error::custom(format!(
                        "{} (dist = \"uniform\" with min, max; \"normal\" with mean, sd and \
                         optional min, max; \"lognormal\" with median, beta and optional min, max)",
                        e.message().trim()
                    ))
                }),
        }
    }
}

/// The seed of the parameter draws of one analysis: splitmix64 finalisers
/// chained over (seed, record, level, case), after a domain tag so that
/// these streams are not the ground-motion streams of the same seed.
///
/// ```
/// use rockfrag::uncertainty::analysis_seed;
/// assert_ne!(analysis_seed(1, 0, 0, 0), analysis_seed(1, 0, 0, 1));
/// assert_ne!(analysis_seed(1, 0, 1, 0), analysis_seed(1, 1, 0, 0));
/// ```
pub fn analysis_seed(seed: u64, record: u64, level: u64, case: u64) -> u64 {
    // "rockfrag:uncertainty" domain tag (an arbitrary odd constant).
    let mut z = seed ^ 0x5EED_0F0B_1EC7_D2A1;
    for x in [record, level, case] {
        z = splitmix64(z ^ splitmix64(x));
    }
    z
}

/// The level and case keys of the orientation draws in [`analysis_seed`]:
/// no level or case has this number, so the direction the blocks face under
/// a record is drawn from a stream of its own.
const ORIENTATION_STREAM: u64 = u64::MAX;

/// The uniform number in [0, 1) that the direction φ of ensemble member
/// `record` is drawn with (see `Orientation` in the spec): one per record,
/// the same at every level (the object faces the same way as the shaking
/// grows) and for every case (the cases share their orientations as they
/// share their records).
///
/// ```
/// use rockfrag::uncertainty::orientation_uniform;
/// let u = orientation_uniform(1, 3);
/// assert!((0.0..1.0).contains(&u));
/// assert_ne!(u, orientation_uniform(1, 4));
/// ```
pub fn orientation_uniform(seed: u64, record: u64) -> f64 {
    let stream = analysis_seed(seed, record, ORIENTATION_STREAM, ORIENTATION_STREAM);
    Xoshiro256PlusPlus::seed_from_u64(stream).random::<f64>()
}

/// The splitmix64 finaliser (Steele, Lea and Flood 2014).
fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The largest uniform number [`uniforms`] gives, 1 − 2⁻⁵³ (53 random bits
/// times 2⁻⁵³): the upper end of the values a draw can take is the
/// quantile here, finite for an unbounded distribution (a lognormal's is
/// about median·e^(8.2β)), not the quantile at 1 (+∞).
///
/// ```
/// use rockfrag::uncertainty::{Distribution, U_MAX};
/// let mu_s = Distribution::Lognormal { median: 0.5, beta: 0.15, min: None, max: None };
/// assert_eq!(mu_s.quantile(1.0), f64::INFINITY);
/// assert!(mu_s.quantile(U_MAX) < 2.0);
/// ```
pub const U_MAX: f64 = 1.0 - f64::EPSILON / 2.0;

/// One uniform number in [0, 1) per parameter of [`Property::ALL`], for the
/// analysis seeded by `seed` (see [`analysis_seed`]).
pub fn uniforms(seed: u64) -> [f64; 5] {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    std::array::from_fn(|_| rng.random::<f64>())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Truncated draws stay inside their bounds at the extreme uniforms, and
    /// the median of a symmetric truncation is the mean.
    #[test]
    fn truncated_normal_stays_in_bounds() {
        let d = Distribution::Normal {
            mean: 0.5,
            sd: 0.02,
            min: Some(0.4),
            max: Some(0.6),
        };
        for u in [0.0, 1e-12, 0.5, 1.0 - 1e-12, 1.0] {
            let x = d.quantile(u);
            assert!((0.4..=0.6).contains(&x), "u = {u}: {x}");
        }
        assert!((d.quantile(0.5) - 0.5).abs() < 1e-12);
        // A one-sided truncation far in the upper tail (bounds 3σ and 4σ).
        let tail = Distribution::Normal {
            mean: 0.0,
            sd: 1.0,
            min: Some(3.0),
            max: Some(4.0),
        };
        for u in [0.0, 0.3, 0.9, 1.0] {
            let x = tail.quantile(u);
            assert!((3.0..=4.0).contains(&x), "u = {u}: {x}");
        }
    }

    /// The sample mean of 20,000 draws of U(0, 0.9) is within 4 standard
    /// errors (σ = 0.9/√12 ≈ 0.26, SE ≈ 0.0018) of 0.45; a lognormal's
    /// sample median is within 2 % of its median.
    #[test]
    fn draws_follow_their_distribution() {
        let n = 20_000;
        let u: Vec<f64> = (0..n)
            .map(|i| uniforms(analysis_seed(7, i, 0, 0))[2])
            .collect();
        let uni = Distribution::Uniform { min: 0.0, max: 0.9 };
        let mean = u.iter().map(|&x| uni.quantile(x)).sum::<f64>() / n as f64;
        assert!(
            (mean - 0.45).abs() < 4.0 * 0.26 / (n as f64).sqrt(),
            "{mean}"
        );
        let ln = Distribution::Lognormal {
            median: 0.6,
            beta: 0.15,
            min: None,
            max: None,
        };
        let mut x: Vec<f64> = u.iter().map(|&v| ln.quantile(v)).collect();
        x.sort_by(f64::total_cmp);
        let med = x[n as usize / 2];
        assert!((med / 0.6 - 1.0).abs() < 0.02, "{med}");
    }

    /// [`U_MAX`] is what the generator gives for a stream of all ones in
    /// its 53 top bits, and every uniform is below 1.
    #[test]
    fn u_max_is_the_largest_uniform() {
        assert_eq!(U_MAX, ((1u64 << 53) - 1) as f64 / (1u64 << 53) as f64);
        const { assert!(U_MAX < 1.0) };
        for s in 0..1000 {
            assert!(uniforms(s).iter().all(|&u| (0.0..=U_MAX).contains(&u)));
        }
    }

    #[test]
    fn validation_names_the_field() {
        let e = Distribution::Uniform { min: 0.0, max: 1.2 }
            .validate("restitution", 0.0, 1.0, "e in [0, 1]")
            .unwrap_err()
            .to_string();
        assert!(e.contains("restitution.max") && e.contains("1.2"), "{e}");
        let e = Distribution::Normal {
            mean: 0.5,
            sd: 0.1,
            min: None,
            max: None,
        }
        .validate("width", f64::MIN_POSITIVE, f64::INFINITY, "2B > 0")
        .unwrap_err()
        .to_string();
        assert!(e.contains("width.dist") && e.contains("min"), "{e}");
    }
}
