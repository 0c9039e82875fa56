//! Solver settings and the description of one analysis.

use super::block::Block;
use super::impact::ImpactLaw;
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// Which rock equation to integrate.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum Model {
    /// The paper's nonlinear eq. (1), integrated by the chosen [`Integrator`]
    /// (a Taylor series by default, or Dormand–Prince 5(4)).
    #[default]
    Nonlinear,
    /// Eq. (1) linearised in θ about θ = 0 (θc kept exact), solved in closed
    /// form over each interval of linear forcing. Fast; accurate for |θ| ≪ θc.
    Linear,
}

/// How the nonlinear rock equation is integrated (slide-rock always uses
/// Dormand–Prince; the linearised model is closed-form).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum Integrator {
    /// Taylor series of order 8 (`taylor::ORDER`) over each
    /// record sample (one sine and cosine per step, the series is its own
    /// dense output), steps cut by the tolerance. Fastest.
    #[default]
    Taylor,
    /// Dormand–Prince 5(4) with dense output and error control, as in
    /// slide-rock: a second, independent integrator of the same equation.
    Dopri5,
}

/// What a rock impact (θ reaching 0 while rocking) leads to when e > 0 under
/// infinite friction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum RockImpact {
    /// The impact law in full: with e > 0 the new corner rebounds and the old
    /// one lifts, so the block flies and rings down on the new corner, bounce
    /// by bounce. The physics, and the default.
    #[default]
    Bounce,
    /// The block keeps rocking on the new corner with θ̇2 = δ(e)·θ̇1,
    /// δ(e) = 1 − 1.5(1 + e) sin²θc (the angular velocity of the paper's rock
    /// impact, eqs. (2)–(3)), and the rebound of the centre of mass is
    /// discarded: no flight. Not physics: a full ring-down on the new corner
    /// conserves the angular momentum about it and ends near Housner's
    /// δ(0)·θ̇1 whatever e, whereas this rule takes e as an extra loss. It is
    /// a reading of the paper's program that reproduces its fall of the
    /// overturning counts with e (studies/notes/e-trend.md). Finite friction
    /// and e = 0 are unaffected.
    Rock,
}

crate::io_util::named!(Model, "model" { Nonlinear => "nonlinear", Linear => "linear" });
crate::io_util::named!(Integrator, "integrator" { Taylor => "taylor", Dopri5 => "dopri5" });
crate::io_util::named!(RockImpact, "rock_impact" { Bounce => "bounce", Rock => "rock" });

/// Contact friction model.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Friction {
    /// Contacts never slip (the paper's assumption).
    #[default]
    Infinite,
    /// Coulomb friction with static μs and kinetic μk ≤ μs.
    Coulomb {
        /// Static coefficient μs.
        mu_s: f64,
        /// Kinetic coefficient μk.
        mu_k: f64,
    },
}

/// Numerical settings of the solver. Plain data with documented defaults.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SolverSettings {
    /// Rock equation (default: nonlinear).
    pub model: Model,
    /// Integrator of the nonlinear rock equation (default: Taylor).
    pub integrator: Integrator,
    /// Relative tolerance of the integrators' error control (default: 1e-8).
    pub rtol: f64,
    /// Absolute tolerance, as a fraction of θc for θ and of p·θc for θ̇
    /// (default: 1e-10).
    pub atol: f64,
    /// Impact law (default: Newton, the paper's).
    pub impact: ImpactLaw,
    /// What a rock impact with e > 0 leads to under infinite friction
    /// (default: `bounce`, the physics; `rock` is a reading of the paper's
    /// program, see [`RockImpact`]).
    pub rock_impact: RockImpact,
    /// Ring-down settle threshold ε (dimensionless, default 1e-6): an impact
    /// whose rebound velocity is below ε·√(gR) is treated as plastic, and a
    /// block within ε·θc of flat whose corners move slower than ε·√(gR)
    /// is set to rest.
    pub settle_tol: f64,
    /// Settle a cascade of shrinking rock impacts at once when bounds prove it
    /// dies out before the ground can lift the block again (e = 0: the
    /// block's later motion is unchanged; e > 0 once its series are closed),
    /// and close the tail of a series of bounces on one corner in closed form
    /// when bounds prove it converges onto rock about that corner (e > 0;
    /// third-order error in the rebound). Under Coulomb friction both apply
    /// only while bounds prove nothing can slip. For a stack
    /// (`solver::stack`): after an impact, a corner moving along its face's
    /// normal slower than 1e-4 √(gR) rests on it (docs/stack.md, "Rules").
    /// Default: true; false follows every impact. See the solver's module
    /// documentation.
    pub settle_cascades: bool,
    /// Largest number of events in one analysis before it is abandoned as
    /// stalled (default: 1,000,000).
    pub max_events: u64,
    /// Track the work of the ground and report the energy residual (default: false).
    pub audit_energy: bool,
    /// Longest free motion followed after the record's end (s, default 60).
    /// A body still moving when the record ends goes on under still ground
    /// (rocking, sliding, flight and impacts as before) until it is at rest
    /// or overturns, so every analysis ends decided; peaks include this
    /// motion. One still moving this long after the record is a solver
    /// failure naming it, never a silent answer. 0 stops at the record's
    /// end, as the paper's program did.
    pub free_motion_max: f64,
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            model: Model::Nonlinear,
            integrator: Integrator::Taylor,
            rtol: 1e-8,
            atol: 1e-10,
            impact: ImpactLaw::Newton,
            rock_impact: RockImpact::Bounce,
            settle_tol: 1e-6,
            settle_cascades: true,
            max_events: 1_000_000,
            audit_energy: false,
            free_motion_max: 60.0,
        }
    }
}

impl SolverSettings {
    /// Record samples of still ground appended after a record sampled every
    /// `dt` to follow the free motion for up to `free_motion_max`.
    pub(crate) fn free_samples(&self, dt: f64) -> usize {
        (self.free_motion_max / dt).ceil() as usize
    }

    /// Checks every field's range; errors name the field and the accepted range.
    pub fn validate(&self) -> Result<()> {
        if !(self.rtol > 0.0 && self.rtol < 1.0) {
            return Err(Error::invalid(
                "rtol",
                self.rtol,
                "a relative tolerance in (0, 1)",
            ));
        }
        if !(self.atol > 0.0 && self.atol < 1.0) {
            return Err(Error::invalid(
                "atol",
                self.atol,
                "an absolute tolerance in (0, 1)",
            ));
        }
        if !(self.settle_tol > 0.0 && self.settle_tol < 1.0) {
            return Err(Error::invalid(
                "settle_tol",
                self.settle_tol,
                "a threshold in (0, 1)",
            ));
        }
        if !(self.free_motion_max.is_finite() && (0.0..=3600.0).contains(&self.free_motion_max)) {
            return Err(Error::invalid(
                "free_motion_max",
                self.free_motion_max,
                "a time in [0, 3600] s (0: stop at the record's end)",
            ));
        }
        if self.max_events == 0 {
            return Err(Error::invalid("max_events", 0, "a positive count"));
        }
        Ok(())
    }
}

/// Initial conditions of the block (default: at rest).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Initial {
    /// Initial rotation θ0 (rad); the block rocks on the corner on the side of θ0.
    pub theta: f64,
    /// Initial angular velocity θ̇0 (rad/s).
    pub theta_dot: f64,
    /// Initial vertical velocity of the centre of mass (m/s). A positive value
    /// throws the block into free flight from its flat rest pose (θ0 must be 0).
    pub y_dot: f64,
    /// Initial horizontal velocity of the centre of mass (m/s), used with `y_dot`.
    pub x_dot: f64,
}

/// One block with its contact properties: everything an analysis needs
/// besides the record and the numerical settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Analysis {
    /// Geometry and gravity.
    pub block: Block,
    /// Coefficient of restitution e ∈ [0, 1].
    pub restitution: f64,
    /// Friction model.
    pub friction: Friction,
    /// Initial conditions.
    pub initial: Initial,
}

impl Analysis {
    /// A block starting at rest, with infinite friction.
    pub fn new(block: Block, restitution: f64) -> Self {
        Analysis {
            block,
            restitution,
            friction: Friction::Infinite,
            initial: Initial::default(),
        }
    }

    /// Checks the restitution, friction and initial conditions.
    pub fn validate(&self) -> Result<()> {
        if !(0.0..=1.0).contains(&self.restitution) {
            return Err(Error::invalid(
                "restitution",
                self.restitution,
                "a coefficient of restitution in [0, 1]",
            ));
        }
        if let Friction::Coulomb { mu_s, mu_k } = self.friction {
            if !(mu_s.is_finite() && mu_s >= 0.0) {
                return Err(Error::invalid(
                    "mu_s",
                    mu_s,
                    "a static friction coefficient ≥ 0",
                ));
            }
            if !(mu_k.is_finite() && mu_k >= 0.0 && mu_k <= mu_s) {
                return Err(Error::invalid(
                    "mu_k",
                    mu_k,
                    "a kinetic friction coefficient in [0, mu_s]",
                ));
            }
        }
        let th = self.initial.theta;
        if !(th.is_finite() && th.abs() < std::f64::consts::FRAC_PI_2) {
            return Err(Error::invalid(
                "theta0",
                th,
                "an initial rotation with |θ0| < π/2 rad",
            ));
        }
        let i = &self.initial;
        if !(i.y_dot.is_finite() && i.y_dot >= 0.0 && i.x_dot.is_finite()) {
            return Err(Error::invalid(
                "y_dot0",
                i.y_dot,
                "a finite upward velocity ≥ 0 in m/s",
            ));
        }
        if i.y_dot > 0.0 && i.theta != 0.0 {
            return Err(Error::invalid(
                "theta0",
                i.theta,
                "0 when the block is thrown (y_dot0 > 0)",
            ));
        }
        if !self.initial.theta_dot.is_finite() {
            return Err(Error::invalid(
                "theta_dot0",
                self.initial.theta_dot,
                "a finite angular velocity in rad/s",
            ));
        }
        Ok(())
    }
}
