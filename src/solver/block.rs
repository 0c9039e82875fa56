//! Block geometry and the derived constants of the rocking problem.

use crate::detmath as dm;
use crate::error::{Error, Result};
use crate::io_util::number;

/// A symmetric rigid block of width 2B and height 2H on a rigid foundation.
/// All dynamic quantities are per unit mass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Block {
    /// Half-width B (m).
    pub b: f64,
    /// Half-height H (m).
    pub h: f64,
    /// Gravity g (m/s²).
    pub g: f64,
    /// Half-diagonal R = √(B² + H²) (m).
    pub r: f64,
    /// Critical angle θc = atan(B/H) (rad).
    pub theta_c: f64,
    /// sin θc.
    pub sin_c: f64,
    /// cos θc.
    pub cos_c: f64,
    /// Centroidal inertia per unit mass, I/m = R²/3 (m²).
    pub inertia: f64,
    /// Frequency parameter p = √(3g/(4R)) (rad/s).
    pub p: f64,
}

/// The base widths 2B a block may have, m: 1 mm to 1 km. Beyond them the
/// rigid-block model has nothing to say (a precariously balanced rock or a
/// monolith is metres wide), and far beyond them the arithmetic fails: from
/// 2B ≈ 10¹⁵⁴ m, R² overflows and the landing search of free flight never
/// ends (`--width 1e200` hung); below 10⁻¹⁰⁰ m the solver's step underflows.
pub const WIDTH_RANGE: (f64, f64) = (1e-3, 1e3);

/// The aspect ratios H/B a block may have: 10⁻³ (a sheet) to 10³ (a
/// needle); from H/B ≈ 10¹⁵⁵ the landing search never ended (`--aspect
/// 1e160` hung).
pub const ASPECT_RANGE: (f64, f64) = (1e-3, 1e3);

/// What [`WIDTH_RANGE`] says, for messages.
pub fn width_expected() -> String {
    format!(
        "a base width 2B in m from {} to {} (1 mm to 1 km: the rigid-block model's range; far \
         beyond it the solver's arithmetic overflows)",
        WIDTH_RANGE.0, WIDTH_RANGE.1
    )
}

/// What [`ASPECT_RANGE`] says, for messages.
pub fn aspect_expected() -> String {
    format!(
        "an aspect ratio H/B from {} to {} (a sheet to a needle; far beyond it the solver's \
         arithmetic overflows)",
        ASPECT_RANGE.0, ASPECT_RANGE.1
    )
}

impl Block {
    /// A block of base width `width` = 2B (m, in [`WIDTH_RANGE`]) and aspect
    /// ratio `aspect` = H/B (in [`ASPECT_RANGE`]), under gravity `g` (m/s²).
    ///
    /// ```
    /// let b = rockfrag::solver::Block::new(0.5, 4.0, 9.81).unwrap();
    /// assert!((b.theta_c - 0.25f64.atan()).abs() < 1e-15);
    /// ```
    pub fn new(width: f64, aspect: f64, g: f64) -> Result<Self> {
        if !(WIDTH_RANGE.0..=WIDTH_RANGE.1).contains(&width) {
            return Err(Error::invalid("width", number(width), &width_expected()));
        }
        if !(ASPECT_RANGE.0..=ASPECT_RANGE.1).contains(&aspect) {
            return Err(Error::invalid("aspect", number(aspect), &aspect_expected()));
        }
        if !(g.is_finite() && g > 0.0) {
            return Err(Error::invalid("g", g, "a positive gravity in m/s²"));
        }
        let b = 0.5 * width;
        let h = aspect * b;
        let r = dm::hypot(b, h);
        let theta_c = dm::atan(b / h);
        // sin θc, cos θc from θc itself, so that the rest→rock test agrees to
        // the last bit with eq. (1) evaluated at θ = 0
        let (sin_c, cos_c) = dm::sin_cos(theta_c);
        Ok(Block {
            b,
            h,
            g,
            r,
            theta_c,
            sin_c,
            cos_c,
            inertia: r * r / 3.0, // I = m R²/3 for a uniform rectangle of half-diagonal R
            p: (0.75 * g / r).sqrt(), // p² = m g R / I_O = 3g/(4R)
        })
    }

    /// sin φ and cos φ of φ = θc − ψ, the angle of the pivot's diagonal from
    /// the vertical while rocking at ψ = sθ ≥ 0 (eq. (1)). On the ground
    /// (ψ = 0, a rock impact or the start of rocking) they are the block's own
    /// sin θc and cos θc, with no trigonometry and the same bits.
    #[inline]
    pub fn phi_sin_cos(&self, psi: f64) -> (f64, f64) {
        if psi == 0.0 {
            (self.sin_c, self.cos_c)
        } else {
            dm::sin_cos(self.theta_c - psi)
        }
    }

    /// Offset (x, y) of corner `side` (+1 right, −1 left) from the centre of
    /// mass when the block is rotated by θ (counter-clockwise positive).
    #[inline]
    pub fn corner_offset(&self, side: f64, theta: f64) -> (f64, f64) {
        let (s, c) = dm::sin_cos(theta);
        // body vector (side·B, −H) rotated by θ
        self.corner_offset_sc(side, s, c)
    }

    /// [`Block::corner_offset`] from sin θ and cos θ already known.
    #[inline]
    pub fn corner_offset_sc(&self, side: f64, s: f64, c: f64) -> (f64, f64) {
        (
            side * self.b * c + self.h * s,
            side * self.b * s - self.h * c,
        )
    }

    /// Inertia about a corner per unit mass, I_O/m = I/m + R² = 4R²/3 (m²)
    /// (parallel axes).
    #[inline]
    pub fn inertia_corner(&self) -> f64 {
        self.inertia + self.r * self.r
    }

    /// Kinetic energy per unit mass relative to the ground.
    #[inline]
    pub fn kinetic(&self, vx: f64, vy: f64, omega: f64) -> f64 {
        0.5 * (vx * vx + vy * vy + self.inertia * omega * omega)
    }
}
