//! A stack at rest (every interface flat and stuck): its contact forces are
//! affine in the ground's acceleration, so they are taken once per state at
//! rest, and a record sample over which every event function stays clear of
//! 0 is passed on them without the chain and its forces (the driver's
//! `rest_interval`).

use super::dynamics::{Contact, forces};
use super::kinematics::{Chain, Modes};
use super::scene::{MAX_BODIES, Scene};

/// How far above 0 every event function of a state at rest must be, as
/// the affine forces give it, for the sample to be passed without its exact
/// scan: their difference to the driver's exact event values is roundoff
/// (about 1e-14 of the carried weight), so the exact scan would find no
/// event either.
const REST_MARGIN: f64 = 1e-9;

/// The contact forces of a stack at rest, affine in the ground's
/// acceleration: per interface, (N_L, N_R, N, T) = c₀ + c_x ẍg + c_y ÿg,
/// from the forces at (0, 0), (1, 0) and (0, 1) (E2, E3 of `dynamics`).
#[derive(Clone, Copy, Debug)]
pub(super) struct RestForces {
    /// The state they belong to.
    pub modes: Modes,
    /// Per interface, (c₀, c_x, c_y) of N_L, N_R, N and T.
    c: [[[f64; 3]; 4]; MAX_BODIES],
}

impl RestForces {
    /// The affine contact forces of the state at rest `modes`, whose chain
    /// is `ch`.
    pub fn new(sc: &Scene, modes: &Modes, ch: &Chain) -> Self {
        let at = |ax: f64, ay: f64| forces(sc, modes, ch, ax, ay).contact;
        let (f0, fx, fy) = (at(0.0, 0.0), at(1.0, 0.0), at(0.0, 1.0));
        let parts = |f: &Contact| [f.nl, f.nr, f.n, f.t];
        let mut c = [[[0.0; 3]; 4]; MAX_BODIES];
        for k in 0..modes.n {
            let (p0, px, py) = (parts(&f0[k]), parts(&fx[k]), parts(&fy[k]));
            for i in 0..4 {
                c[k][i] = [p0[i], px[i] - p0[i], py[i] - p0[i]];
            }
        }
        RestForces { modes: *modes, c }
    }

    /// Whether every event function of the state at rest (a flat corner's
    /// normal force, and μs N − |T| under finite friction, each over the
    /// carried weight, as the driver's event values have them) is above
    /// `REST_MARGIN` under the ground acceleration (ax, ay).
    pub fn clear(&self, sc: &Scene, ax: f64, ay: f64) -> bool {
        let n = self.modes.n;
        (0..n).all(|k| {
            let w = sc.g * sc.carried(k, n);
            let f = |i: usize| {
                let c = self.c[k][i];
                c[0] + c[1] * ax + c[2] * ay
            };
            let cone = match sc.fric[k] {
                Some((mu_s, _)) => (mu_s * f(2) - f(3).abs()) / w,
                None => 1.0,
            };
            f(0) / w > REST_MARGIN && f(1) / w > REST_MARGIN && cone > REST_MARGIN
        })
    }
}
