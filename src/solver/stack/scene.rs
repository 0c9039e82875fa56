//! What a stack is: its bodies bottom first, the interface under each, and
//! the constants the solver derives from them once.

use crate::error::{Error, Result};
use crate::io_util::number;
use crate::solver::block::{ASPECT_RANGE, WIDTH_RANGE, aspect_expected, width_expected};
use crate::solver::settings::Friction;

/// Most bodies a stack may have.
pub const MAX_BODIES: usize = 3;

/// One rigid rectangular body of a stack (2-D, per unit thickness).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StackBody {
    /// Width 2B (m).
    pub width: f64,
    /// Height 2H (m).
    pub height: f64,
    /// Mass, relative to the other bodies' (any unit; only ratios matter).
    /// [`StackBody::new`] sets it to width × height (every body of the same
    /// density).
    pub mass: f64,
    /// Horizontal offset (m) of this body's centre from the centre of the
    /// body below at rest (positive to the right); 0 for the base, whose
    /// place on the ground is the origin.
    pub offset: f64,
}

impl StackBody {
    /// A centred body of width 2B = `width` and height 2H = `height` (m),
    /// of the same density as any other body made so (mass = width × height).
    pub fn new(width: f64, height: f64) -> Self {
        StackBody {
            width,
            height,
            mass: width * height,
            offset: 0.0,
        }
    }
}

/// The contact under a body: with the ground for the base, with the top
/// face of the body below otherwise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StackInterface {
    /// Coefficient of restitution e ∈ [0, 1] of impacts at this interface.
    pub restitution: f64,
    /// Friction at this interface (default: infinite).
    pub friction: Friction,
}

impl StackInterface {
    /// An interface with restitution `e` and infinite friction.
    pub fn new(restitution: f64) -> Self {
        StackInterface {
            restitution,
            friction: Friction::Infinite,
        }
    }
}

/// A stack of one to three rigid blocks on the ground, bottom first, with
/// the interface under each body (`interfaces[0]` is the ground's) and
/// optional initial tilts.
#[derive(Clone, Debug, PartialEq)]
pub struct Stack {
    /// The bodies, bottom first.
    pub bodies: Vec<StackBody>,
    /// The interface under each body, bottom first (as many as bodies).
    pub interfaces: Vec<StackInterface>,
    /// Initial rotation of each body relative to the body below (rad, the
    /// ground for the base), about the corner on the side of its sign
    /// (φ > 0: the left corner, as a single block's θ > 0); empty or zeros
    /// for a stack at rest. Velocities start at zero.
    pub initial_tilt: Vec<f64>,
    /// Gravity (m/s²).
    pub g: f64,
}

impl Stack {
    /// A stack of `bodies` (bottom first) whose interfaces all have
    /// restitution `e` and infinite friction, at rest, under gravity `g`.
    pub fn new(bodies: Vec<StackBody>, e: f64, g: f64) -> Self {
        let interfaces = vec![StackInterface::new(e); bodies.len()];
        Stack {
            bodies,
            interfaces,
            initial_tilt: Vec::new(),
            g,
        }
    }

    /// Checks every field; errors name the body or interface (bottom first,
    /// from 1), the field and the accepted range.
    pub fn validate(&self) -> Result<()> {
        let n = self.bodies.len();
        if !(1..=MAX_BODIES).contains(&n) {
            return Err(Error::invalid(
                "stack",
                format!("{n} bodies"),
                &format!("1 to {MAX_BODIES} bodies, bottom first"),
            ));
        }
        if self.interfaces.len() != n {
            return Err(Error::invalid(
                "stack interfaces",
                self.interfaces.len(),
                &format!("one interface under each of the {n} bodies"),
            ));
        }
        if !(self.initial_tilt.is_empty() || self.initial_tilt.len() == n) {
            return Err(Error::invalid(
                "stack initial tilts",
                self.initial_tilt.len(),
                &format!("none, or one per body ({n})"),
            ));
        }
        if !(self.g.is_finite() && self.g > 0.0) {
            return Err(Error::invalid("g", self.g, "a positive gravity in m/s²"));
        }
        for (i, b) in self.bodies.iter().enumerate() {
            let field = |f: &str| format!("body {} {f}", i + 1);
            if !(WIDTH_RANGE.0..=WIDTH_RANGE.1).contains(&b.width) {
                return Err(Error::invalid(
                    &field("width"),
                    number(b.width),
                    &width_expected(),
                ));
            }
            let aspect = b.height / b.width;
            if !(ASPECT_RANGE.0..=ASPECT_RANGE.1).contains(&aspect) {
                return Err(Error::invalid(
                    &field("height"),
                    number(b.height),
                    &format!("a height 2H giving {}", aspect_expected()),
                ));
            }
            if !(b.mass.is_finite() && b.mass > 0.0) {
                return Err(Error::invalid(
                    &field("mass"),
                    number(b.mass),
                    "a positive relative mass",
                ));
            }
            if i == 0 && b.offset != 0.0 {
                return Err(Error::invalid(
                    &field("offset"),
                    number(b.offset),
                    "0 for the base (its place on the ground is the origin)",
                ));
            }
            if i > 0 {
                let below = &self.bodies[i - 1];
                // the footprint [offset − B, offset + B] within the top face
                // [−B_below, B_below] (a hair of rounding allowed)
                let reach = b.offset.abs() + 0.5 * b.width;
                if !(b.offset.is_finite() && reach <= 0.5 * below.width * (1.0 + 1e-12)) {
                    return Err(Error::invalid(
                        &field("footprint"),
                        format!(
                            "width {} m at offset {} m",
                            number(b.width),
                            number(b.offset)
                        ),
                        &format!(
                            "a footprint within the top face of body {i} (width {} m): |offset| \
                             + width/2 ≤ {} m",
                            number(below.width),
                            number(0.5 * below.width)
                        ),
                    ));
                }
            }
        }
        for (i, f) in self.interfaces.iter().enumerate() {
            let field = |f: &str| format!("interface {} {f}", i + 1);
            if !(0.0..=1.0).contains(&f.restitution) {
                return Err(Error::invalid(
                    &field("restitution"),
                    f.restitution,
                    "a coefficient of restitution in [0, 1]",
                ));
            }
            if let Friction::Coulomb { mu_s, mu_k } = f.friction {
                if !(mu_s.is_finite() && mu_s >= 0.0) {
                    return Err(Error::invalid(
                        &field("mu_s"),
                        mu_s,
                        "a static friction coefficient ≥ 0",
                    ));
                }
                if !(mu_k.is_finite() && mu_k >= 0.0 && mu_k <= mu_s) {
                    return Err(Error::invalid(
                        &field("mu_k"),
                        mu_k,
                        "a kinetic friction coefficient in [0, mu_s]",
                    ));
                }
            }
        }
        for (i, &tilt) in self.initial_tilt.iter().enumerate() {
            if !(tilt.is_finite() && tilt.abs() < std::f64::consts::FRAC_PI_2) {
                return Err(Error::invalid(
                    &format!("body {} initial tilt", i + 1),
                    tilt,
                    "an initial rotation with |φ0| < π/2 rad",
                ));
            }
        }
        Ok(())
    }
}

/// The validated stack as the solver uses it: fixed-size arrays of the
/// bodies' constants (no allocation in the time loop).
#[derive(Clone, Copy, Debug)]
pub(super) struct Scene {
    /// Number of bodies.
    pub n: usize,
    /// Half-widths B (m).
    pub b: [f64; MAX_BODIES],
    /// Half-heights H (m).
    pub h: [f64; MAX_BODIES],
    /// Masses (relative).
    pub m: [f64; MAX_BODIES],
    /// Centroidal inertias I = m(B² + H²)/3.
    pub inertia: [f64; MAX_BODIES],
    /// Half-diagonals R = √(B² + H²) (m).
    pub r: [f64; MAX_BODIES],
    /// Critical angles θc = atan(B/H) (rad).
    pub theta_c: [f64; MAX_BODIES],
    /// Frequency parameters p = √(3g/(4R)) (rad/s).
    pub p: [f64; MAX_BODIES],
    /// Offsets of each body's centre from the centre of the top face below
    /// (m, 0 for the base).
    pub offset: [f64; MAX_BODIES],
    /// Restitution of the interface under each body.
    pub e: [f64; MAX_BODIES],
    /// Coulomb friction (μs, μk) of the interface under each body, or
    /// `None` for infinite friction.
    pub fric: [Option<(f64, f64)>; MAX_BODIES],
    /// Initial relative rotation of each body (rad).
    pub tilt: [f64; MAX_BODIES],
    /// Gravity (m/s²).
    pub g: f64,
    /// Settle threshold ε: corners slower than ε√(gR) are at rest on
    /// their face (the single block's rest rule; `settle_tol`).
    pub settle: f64,
    /// Rest threshold ε_r of a corner's normal speed in the choice of the
    /// state after an impact (the stack's cascade rule, `settle_cascades`):
    /// a corner on its face moving along its normal slower than ε_r√(gR)
    /// rests on it. 0 (the rule off): ε applies, as everywhere else.
    pub rest_after_impact: f64,
}

impl Scene {
    /// The constants of a validated stack.
    pub fn new(stack: &Stack) -> Self {
        let mut s = Scene {
            n: stack.bodies.len(),
            b: [0.0; MAX_BODIES],
            h: [0.0; MAX_BODIES],
            m: [0.0; MAX_BODIES],
            inertia: [0.0; MAX_BODIES],
            r: [0.0; MAX_BODIES],
            theta_c: [0.0; MAX_BODIES],
            p: [0.0; MAX_BODIES],
            offset: [0.0; MAX_BODIES],
            e: [0.0; MAX_BODIES],
            fric: [None; MAX_BODIES],
            tilt: [0.0; MAX_BODIES],
            g: stack.g,
            settle: 1e-6,
            rest_after_impact: 0.0,
        };
        for (i, body) in stack.bodies.iter().enumerate() {
            let (b, h) = (0.5 * body.width, 0.5 * body.height);
            s.b[i] = b;
            s.h[i] = h;
            s.m[i] = body.mass;
            s.r[i] = crate::detmath::hypot(b, h);
            // I = m R²/3 for a uniform rectangle of half-diagonal R
            s.inertia[i] = body.mass * s.r[i] * s.r[i] / 3.0;
            s.theta_c[i] = crate::detmath::atan(b / h);
            s.p[i] = (0.75 * stack.g / s.r[i]).sqrt(); // p² = 3g/(4R)
            s.offset[i] = body.offset;
            s.e[i] = stack.interfaces[i].restitution;
            s.fric[i] = match stack.interfaces[i].friction {
                Friction::Infinite => None,
                Friction::Coulomb { mu_s, mu_k } => Some((mu_s, mu_k)),
            };
            s.tilt[i] = stack.initial_tilt.get(i).copied().unwrap_or(0.0);
        }
        s
    }

    /// The mass carried by interface k: body k and every body above it.
    #[inline]
    pub fn carried(&self, k: usize, n: usize) -> f64 {
        self.m[k..n].iter().sum()
    }
}
