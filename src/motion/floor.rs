//! The floor a block stands on: the absolute motion of a floor of a
//! **linear** building, computed from the ground motion by modal
//! superposition.
//!
//! The building is described at the floor by its modes i = 1…m, each a
//! period Tᵢ, a damping ratio ζᵢ and a participation Γφᵢ (the modal
//! participation factor times the mode shape's value at the floor). Each mode
//! is a linear oscillator driven by the ground acceleration ẍg,
//!
//! ```text
//! üᵢ + 2ζᵢωᵢ u̇ᵢ + ωᵢ² uᵢ = −ẍg ,   ωᵢ = 2π/Tᵢ ,   uᵢ(0) = u̇ᵢ(0) = 0,
//! ```
//!
//! (uᵢ relative to the ground), and the floor moves with
//!
//! ```text
//! ẍf = ẍg + Σ Γφᵢ üᵢ = (1 − Σ Γφᵢ) ẍg − Σ Γφᵢ (2ζᵢωᵢ u̇ᵢ + ωᵢ² uᵢ)
//! ẋf = ẋg + Σ Γφᵢ u̇ᵢ
//! xf = xg + Σ Γφᵢ uᵢ
//! ```
//!
//! The acceleration is evaluated in the second form, from the equation of
//! motion: for a single mode with Γφ = 1 the ground term vanishes exactly, so
//! a flexible building whose floor moves much less than the ground loses no
//! digits to the cancellation ẍg + üᵢ.
//!
//! The ground acceleration is linear between samples (the rule the solver
//! uses), and for such a forcing the oscillator's state at the samples obeys
//! an exact recurrence (Nigam and Jennings 1969):
//!
//! ```text
//! [u, u̇]ₖ₊₁ = A [u, u̇]ₖ + b₀ ẍg[k] + b₁ ẍg[k+1]
//! ```
//!
//! with a 2×2 matrix A and vectors b₀, b₁ that depend only on (T, ζ, Δt) and
//! are computed once per mode ([`Oscillator::new`]). It is exact, not a
//! discretisation: its only error is rounding. The floor's samples are at the
//! record's sample times, with the record's Δt. Between samples the solver
//! will take the floor's acceleration as linear, as for any record; the
//! floor's true acceleration is smooth there, so a floor record is as good a
//! description of the floor as its Δt resolves the building's periods (keep
//! Δt ≤ T/10 for the shortest period that matters).
//!
//! The building stays linear. A user with a nonlinear building model computes
//! its floor motions there and feeds them as record files. Only the
//! horizontal component is filtered: a vertical ground acceleration, if the
//! record has one, is carried to the floor unchanged.
//!
//! Reference: Nigam, N. C. and Jennings, P. C. (1969). Calculation of response
//! spectra from strong-motion earthquake records. *Bull. Seismol. Soc. Am.*
//! 59(2), 909–922.

use std::f64::consts::TAU;

use super::record::Record;
use crate::detmath;
use crate::error::{Error, Result};

/// Below this step in radians of the natural frequency, w = ωΔt, the forcing
/// coefficients are summed as a Taylor series; above it, from the closed
/// form. The closed form subtracts nearly equal terms when w is small (the
/// coefficients are O(Δt²) differences of O(1) terms: a relative error of
/// ~1e-16/w³, 1e-7 at w = 1e-3, e.g. T = 10 s at Δt = 0.002 s); the series,
/// at w ≤ 1, converges to rounding in [`SERIES_TERMS`] terms.
const SERIES_BELOW: f64 = 1.0;

/// Terms of the Taylor series of φ₂: at w ≤ 1 and ζ < 1 the norm of wN is
/// below 3, and the first term left out is below 3³⁰/32! ≈ 1e-21.
const SERIES_TERMS: usize = 32;

/// One mode of a linear building, as seen at the floor. In a spec, an
/// entry of `[support] floor`: `{ period = 0.8, damping = 0.05,
/// participation = 1.3 }` (`participation` defaults to 1, a one-storey
/// building or a single-degree-of-freedom idealisation).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Mode {
    /// Natural period T (s); positive and finite.
    pub period: f64,
    /// Damping ratio ζ (fraction of critical, dimensionless); 0 ≤ ζ < 1.
    pub damping: f64,
    /// Participation Γφ at the floor (dimensionless): the modal participation
    /// factor times the mode shape's ordinate at the floor (roof of a regular
    /// building, first mode: about 1.3). Any finite value, also negative
    /// (higher modes); zero leaves the mode out.
    #[serde(default = "unit_participation")]
    pub participation: f64,
}

fn unit_participation() -> f64 {
    1.0
}

/// A floor of a linear building: its modes. The default, no modes, is the
/// ground itself.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Floor {
    /// The building's modes at this floor (one is the common case).
    pub modes: Vec<Mode>,
}

impl Floor {
    /// The ground: no building, the floor moves with the ground.
    pub fn ground() -> Floor {
        Floor::default()
    }

    /// A floor with one mode: period `period` (s), damping ratio `damping`,
    /// participation `participation`.
    pub fn one_mode(period: f64, damping: f64, participation: f64) -> Floor {
        Floor {
            modes: vec![Mode {
                period,
                damping,
                participation,
            }],
        }
    }

    /// True if the floor moves with the ground: no mode with a nonzero
    /// participation.
    pub fn is_ground(&self) -> bool {
        self.modes.iter().all(|m| m.participation == 0.0)
    }

    /// Checks every mode: 0 < T < ∞, 0 ≤ ζ < 1, |Γφ| ≤ [`MAX_PARTICIPATION`],
    /// and T within [`MIN_PERIOD`]–[`MAX_PERIOD`] s for a mode that takes
    /// part (Γφ ≠ 0). Errors name the
    /// mode as `floor[i].period`, `floor[i].damping` or
    /// `floor[i].participation` (0-based i).
    pub fn validate(&self) -> Result<()> {
        for (i, m) in self.modes.iter().enumerate() {
            check_period(|| format!("floor[{i}].period"), m.period)?;
            check_damping(|| format!("floor[{i}].damping"), m.damping)?;
            // NaN is refused too: it is not within the bound.
            if m.participation.is_nan() || m.participation.abs() > MAX_PARTICIPATION {
                return Err(Error::invalid(
                    &format!("floor[{i}].participation"),
                    m.participation,
                    &format!(
                        "a participation Γφ from −{MAX_PARTICIPATION} to {MAX_PARTICIPATION} (0 \
                         leaves the mode out): the participation factor times the mode shape's \
                         ordinate at the floor, whatever the shape's normalisation, about 1.3 \
                         at the roof of a regular building (4/π for a uniform shear building, \
                         1.57 for a cantilever), smaller for higher modes; a larger value \
                         multiplies the floor's acceleration (10⁵ gave 3·10⁴ g)"
                    ),
                ));
            }
            if m.participation != 0.0 && !(MIN_PERIOD..=MAX_PERIOD).contains(&m.period) {
                return Err(Error::invalid(
                    &format!("floor[{i}].period"),
                    m.period,
                    &format!(
                        "a building's natural period from {MIN_PERIOD} to {MAX_PERIOD} s \
                         (0.05–10 s for real buildings)"
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Largest |Γφ| a mode may have at a floor: the first mode's is about 1.3
/// at the roof of a regular building and at most about 1.6 (a flexural
/// cantilever), the higher modes' smaller; 3 leaves room for odd buildings
/// and refuses a factor typed for a shape or a mass (10⁵ made the floor
/// accelerate at 3·10⁴ g).
pub const MAX_PARTICIPATION: f64 = 3.0;

/// Shortest natural period of a floor mode (s): stiffer than any building
/// (0.05 s is a stiff low-rise); at 10⁻³⁰⁰ s ω² overflowed and the floor
/// stood still.
pub const MIN_PERIOD: f64 = 1e-3;

/// Longest natural period of a floor mode (s): longer than any building
/// (about 10 s for a supertall one, 3–5 s base-isolated).
pub const MAX_PERIOD: f64 = 100.0;

// The field names are built only on error: validation runs for every floor
// record and must not allocate.
fn check_period(field: impl FnOnce() -> String, period: f64) -> Result<()> {
    if period.is_finite() && period > 0.0 && (TAU / period).is_finite() {
        Ok(())
    } else {
        Err(Error::invalid(
            &field(),
            period,
            "a positive, finite natural period T in s",
        ))
    }
}

fn check_damping(field: impl FnOnce() -> String, damping: f64) -> Result<()> {
    if (0.0..1.0).contains(&damping) {
        Ok(())
    } else {
        Err(Error::invalid(
            &field(),
            damping,
            "a damping ratio ζ with 0 ≤ ζ < 1 (an underdamped mode; 0.05 is usual)",
        ))
    }
}

/// The state of one modal oscillator, relative to the ground.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OscillatorState {
    /// Relative displacement u (m).
    pub disp: f64,
    /// Relative velocity u̇ (m/s).
    pub vel: f64,
}

/// The exact one-step map of a linear oscillator (T, ζ) under a ground
/// acceleration linear between samples Δt apart (Nigam and Jennings 1969):
///
/// ```text
/// [u, u̇]ₖ₊₁ = a [u, u̇]ₖ + b0 ẍg[k] + b1 ẍg[k+1]
/// ```
///
/// With w = ωΔt, N = [[0, 1], [−1, −2ζ]] (the equation of motion in the
/// scaled state y = [ωu, u̇]), β = √(1−ζ²):
///
/// ```text
/// a  = e^{wN} = e^{−ζw} [cos βw · I + (sin βw / β)(N + ζI)]   (scaled)
/// b0 = −Δt (φ₁(wN) − φ₂(wN)) e₂ ,  b1 = −Δt φ₂(wN) e₂            (scaled)
/// φ₁(X) = X⁻¹(e^X − I) ,  φ₂(X) = X⁻¹(φ₁(X) − I) ,  e₂ = [0, 1]
/// ```
///
/// Back in (u, u̇), a₀₁ is divided by ω, a₁₀ multiplied by ω and the first
/// entries of b0, b1 divided by ω; with ωd = ω√(1−ζ²) the matrix is Nigam
/// and Jennings':
///
/// ```text
/// a = e^{−ζωΔt} [[cos ωdΔt + (ζω/ωd) sin ωdΔt,  (sin ωdΔt)/ωd              ],
///                [−(ω²/ωd) sin ωdΔt,           cos ωdΔt − (ζω/ωd) sin ωdΔt]]
/// ```
///
/// and b0, b1 are their forcing coefficients written with the φ-functions of
/// the matrix exponential. For w < 1 φ₂ is summed as its Taylor series,
/// which keeps full precision where the closed form cancels (long periods,
/// fine steps).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Oscillator {
    /// Sample interval Δt (s).
    pub dt: f64,
    /// Natural circular frequency ω = 2π/T (rad/s).
    pub omega: f64,
    /// Damping ratio ζ (dimensionless).
    pub damping: f64,
    /// The state transition matrix e^{MΔt} acting on (u, u̇): row 0 gives u
    /// (entries in 1 and s), row 1 gives u̇ (1/s² and 1).
    pub a: [[f64; 2]; 2],
    /// Coefficients of ẍg at sample k in (u, u̇)ₖ₊₁ (s², s).
    pub b0: [f64; 2],
    /// Coefficients of ẍg at sample k + 1 in (u, u̇)ₖ₊₁ (s², s).
    pub b1: [f64; 2],
    /// 2ζω (1/s): damping force per unit mass and relative velocity.
    pub two_zeta_omega: f64,
    /// ω² (1/s²): restoring force per unit mass and relative displacement.
    pub omega_sq: f64,
}

impl Oscillator {
    /// The recurrence of the oscillator of period `period` (s) and damping
    /// ratio `damping` for samples `dt` (s) apart. Refuses T ≤ 0 or not
    /// finite, ζ outside [0, 1), Δt ≤ 0 or not finite.
    ///
    /// ```
    /// use rockfrag::motion::{Oscillator, OscillatorState};
    /// // a constant ground acceleration of 1 m/s² held for 200 s: a damped
    /// // oscillator settles at u = −1/ω²
    /// let osc = Oscillator::new(1.0, 0.05, 0.01).unwrap();
    /// let mut s = OscillatorState::default();
    /// for _ in 0..20_000 {
    ///     s = osc.step(s, 1.0, 1.0);
    /// }
    /// assert!((s.disp * osc.omega_sq + 1.0).abs() < 1e-12);
    /// assert!(Oscillator::new(1.0, 1.0, 0.01).is_err());
    /// ```
    pub fn new(period: f64, damping: f64, dt: f64) -> Result<Oscillator> {
        Oscillator::check(period, damping, dt)?;
        let omega = TAU / period;
        let w = omega * dt;
        let z = damping;
        let (phi, phi1, phi2) = scaled_map(w, z, w < SERIES_BELOW);
        // forcing −ẍg: y(Δt) = a y + Δt(φ₁−φ₂)e₂·(−ẍg[k]) + Δtφ₂e₂·(−ẍg[k+1]);
        // then back to u = y₀/ω
        let b0s = [-(dt * (phi1[0] - phi2[0])), -(dt * (phi1[1] - phi2[1]))];
        let b1s = [-(dt * phi2[0]), -(dt * phi2[1])];
        Ok(Oscillator {
            dt,
            omega,
            damping,
            a: [
                [phi[0][0], phi[0][1] / omega],
                [phi[1][0] * omega, phi[1][1]],
            ],
            b0: [b0s[0] / omega, b0s[1]],
            b1: [b1s[0] / omega, b1s[1]],
            two_zeta_omega: 2.0 * z * omega,
            omega_sq: omega * omega,
        })
    }

    /// The checks of [`Oscillator::new`], without computing anything.
    fn check(period: f64, damping: f64, dt: f64) -> Result<()> {
        check_period(|| "period".into(), period)?;
        check_damping(|| "damping".into(), damping)?;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(Error::invalid(
                "dt",
                dt,
                "a positive, finite sample interval in s",
            ));
        }
        if !(TAU / period * dt).is_finite() {
            return Err(Error::invalid(
                "period",
                period,
                "a period not so short that 2πΔt/T overflows",
            ));
        }
        Ok(())
    }

    /// The state at the next sample, from the state `s` at this one and the
    /// ground accelerations `acc0` here and `acc1` there (m/s²). Eight
    /// multiplications and six additions; the same operations in the same
    /// order on every platform (no fused multiply–add).
    #[inline(always)]
    pub fn step(&self, s: OscillatorState, acc0: f64, acc1: f64) -> OscillatorState {
        let [[a00, a01], [a10, a11]] = self.a;
        OscillatorState {
            disp: (a00 * s.disp + a01 * s.vel) + (self.b0[0] * acc0 + self.b1[0] * acc1),
            vel: (a10 * s.disp + a11 * s.vel) + (self.b0[1] * acc0 + self.b1[1] * acc1),
        }
    }

    /// Spring and damper force per unit mass, 2ζω u̇ + ω² u (m/s²): the
    /// oscillator's absolute acceleration is its negative.
    #[inline(always)]
    pub fn restoring(&self, s: OscillatorState) -> f64 {
        self.two_zeta_omega * s.vel + self.omega_sq * s.disp
    }

    /// Relative acceleration ü = −ẍg − 2ζω u̇ − ω² u (m/s²) in state `s`
    /// under ground acceleration `ground_acc` (m/s²).
    #[inline(always)]
    pub fn rel_acc(&self, s: OscillatorState, ground_acc: f64) -> f64 {
        -ground_acc - self.restoring(s)
    }
}

/// The one-step map in the scaled state y = [ωu, u̇], for which
/// ẏ = ω N y + e₂ f with N = [[0, 1], [−1, −2ζ]]: (e^{wN}, φ₁(wN)e₂,
/// φ₂(wN)e₂). φ₂ by its Taylor series if `series`, else by the closed form.
fn scaled_map(w: f64, z: f64, series: bool) -> ([[f64; 2]; 2], [f64; 2], [f64; 2]) {
    let (e, c, s_over_beta) = decay_turn(w, z);
    let phi = [
        [e * (c + z * s_over_beta), e * s_over_beta],
        [-(e * s_over_beta), e * (c - z * s_over_beta)],
    ];
    // X r = wN r
    let x = |r: [f64; 2]| [w * r[1], w * (-r[0] - 2.0 * z * r[1])];
    let phi2 = if series {
        // 2φ₂(X)e₂ = e₂ + X/3 (e₂ + X/4 (e₂ + …)), Horner from the tail
        let mut r = [0.0, 1.0];
        for d in (3..SERIES_TERMS + 3).rev() {
            let xr = x(r);
            r = [xr[0] / d as f64, 1.0 + xr[1] / d as f64];
        }
        [r[0] / 2.0, r[1] / 2.0]
    } else {
        // N⁻¹ = [[−2ζ, −1], [1, 0]]; φ₁e₂ = N⁻¹(e^X − I)e₂ / w, then
        // φ₂e₂ = N⁻¹(φ₁e₂ − e₂) / w
        let q = [phi[0][1], phi[1][1] - 1.0];
        let p1 = [(-2.0 * z * q[0] - q[1]) / w, q[0] / w];
        let d = [p1[0], p1[1] - 1.0];
        [(-2.0 * z * d[0] - d[1]) / w, d[0] / w]
    };
    // φ₁e₂ = e₂ + X φ₂e₂ (no subtraction of nearly equal terms)
    let xp = x(phi2);
    (phi, [xp[0], 1.0 + xp[1]], phi2)
}

/// (e^{−ζw}, cos βw, sin(βw)/β) with β = √(1−ζ²): the only transcendental
/// functions of the floor filter, evaluated once per mode.
// Through detmath (libm): the same bits on every platform.
fn decay_turn(w: f64, zeta: f64) -> (f64, f64, f64) {
    let beta = (1.0 - zeta * zeta).sqrt();
    let (s, c) = detmath::sin_cos(beta * w);
    (detmath::exp(-zeta * w), c, s / beta)
}

/// The absolute motion of `floor` under the ground motion `ground`: a new
/// record with the ground's Δt, length, name and vertical acceleration (see
/// [`floor_into`]).
///
/// ```
/// use rockfrag::motion::{Floor, Record, floor_record};
/// let ground = Record::from_acc("g", 0.01, vec![0.0, 1.0, -0.5, 0.25]).unwrap();
/// assert_eq!(floor_record(&ground, &Floor::ground()).unwrap(), ground);
/// let roof = floor_record(&ground, &Floor::one_mode(0.8, 0.05, 1.3)).unwrap();
/// assert_eq!(roof.len(), ground.len());
/// ```
pub fn floor_record(ground: &Record, floor: &Floor) -> Result<Record> {
    let mut out = Record {
        name: String::new(),
        dt: ground.dt,
        acc: Vec::with_capacity(ground.len()),
        vel: Vec::with_capacity(ground.len()),
        disp: Vec::with_capacity(ground.len()),
        acc_v: None,
    };
    floor_into(ground, floor, &mut out)?;
    Ok(out)
}

/// As [`floor_record`], into `out`, reusing its buffers (no allocation once
/// they have grown to the record's length).
///
/// Sample k of the floor (module docs):
/// `acc = (1 − ΣΓφ)·ẍg − Σ Γφ (2ζω u̇ + ω² u)`, `vel = ẋg + Σ Γφ u̇`,
/// `disp = xg + Σ Γφ u`, the modes added in order, each oscillator starting
/// at rest at sample 0. Modes with zero participation are skipped, so a floor
/// without a nonzero participation gives `ground` bit for bit. The ground's
/// velocity and displacement are used as given (for a file with its own
/// `vel`, `disp` columns, those). The name is the ground's; the vertical
/// acceleration, if any, is the ground's, unchanged.
///
/// Errors: the ground record's [`Record::validate_forcing`] errors or
/// series of different lengths (non-finite velocities or displacements are
/// not looked for: they would stay in the floor's), or the floor's
/// [`Floor::validate`] errors; `out` is left unchanged then.
pub fn floor_into(ground: &Record, floor: &Floor, out: &mut Record) -> Result<()> {
    ground.validate_forcing()?;
    if ground.vel.len() != ground.len() || ground.disp.len() != ground.len() {
        return Err(Error::InvalidRecord {
            name: ground.name.clone(),
            message: "acc, vel and disp have different lengths".into(),
        });
    }
    floor.validate()?;
    let active = || floor.modes.iter().filter(|m| m.participation != 0.0);
    if active().next().is_none() {
        out.clone_from(ground);
        return Ok(());
    }
    // everything checked before `out` is touched
    for m in active() {
        Oscillator::check(m.period, m.damping, ground.dt)?;
    }
    let sum: f64 = active().map(|m| m.participation).sum();
    let keep = 1.0 - sum;
    out.name.clone_from(&ground.name);
    out.dt = ground.dt;
    out.acc_v.clone_from(&ground.acc_v);
    out.acc.clear();
    out.acc.extend(ground.acc.iter().map(|a| keep * a));
    out.vel.clone_from(&ground.vel);
    out.disp.clone_from(&ground.disp);
    for m in active() {
        let osc = Oscillator::new(m.period, m.damping, ground.dt)?;
        add_mode(&osc, m.participation, ground, out);
    }
    Ok(())
}

/// Adds one mode's share to the floor's series (sample 0 is at rest: nothing
/// to add).
fn add_mode(osc: &Oscillator, gamma: f64, ground: &Record, out: &mut Record) {
    let mut s = OscillatorState::default();
    let ag = &ground.acc;
    let rows = out.acc[1..]
        .iter_mut()
        .zip(&mut out.vel[1..])
        .zip(&mut out.disp[1..]);
    for (((acc, vel), disp), pair) in rows.zip(ag.windows(2)) {
        s = osc.step(s, pair[0], pair[1]);
        *acc -= gamma * osc.restoring(s);
        *vel += gamma * s.vel;
        *disp += gamma * s.disp;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The series and the closed form of φ₁e₂, φ₂e₂ agree where both are
    /// accurate (w around the switch, 0.3…3): to 1e-14 of the larger entry
    /// of each (a few ulps; the closed form loses ~1/w³ of them at w = 0.3). A
    /// sign or index slip in either would show as an O(1) difference.
    #[test]
    fn series_and_closed_form_agree_around_the_switch() {
        for z in [0.0, 0.02, 0.05, 0.3, 0.9, 0.999] {
            for w in [0.3, 0.6, 0.9, 0.999, 1.0, 1.5, 3.0] {
                let (_, s1, s2) = scaled_map(w, z, true);
                let (_, c1, c2) = scaled_map(w, z, false);
                for (s, c) in [(s1, c1), (s2, c2)] {
                    let scale = s[0].abs().max(s[1].abs());
                    for i in 0..2 {
                        assert!(
                            (s[i] - c[i]).abs() <= 1e-14 * scale,
                            "z {z} w {w}: series {s:?}, closed {c:?}"
                        );
                    }
                }
            }
        }
    }

    /// Small-step limit: the coefficients tend to the linear-acceleration
    /// rule's, u ≈ −Δt²(2ẍg[k] + ẍg[k+1])/6, u̇ ≈ −Δt(ẍg[k] + ẍg[k+1])/2,
    /// with relative corrections O(w) (here w = 2π·1e-5, so 1e-4 bounds them).
    #[test]
    fn tiny_steps_reduce_to_the_linear_acceleration_rule() {
        let dt = 1e-5;
        let osc = Oscillator::new(1.0, 0.05, dt).unwrap();
        let near = |x: f64, y: f64| (x - y).abs() <= 1e-4 * y.abs();
        assert!(near(osc.b0[0], -dt * dt / 3.0), "{:e}", osc.b0[0]);
        assert!(near(osc.b1[0], -dt * dt / 6.0), "{:e}", osc.b1[0]);
        assert!(near(osc.b0[1], -dt / 2.0));
        assert!(near(osc.b1[1], -dt / 2.0));
    }
}
