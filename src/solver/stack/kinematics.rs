//! The contact state of each interface, the coordinates it leaves free, and
//! the kinematics of the chain of bodies built on them.
//!
//! Interface k carries body k on the top face of body k − 1 (the ground
//! for k = 0). Its *face frame* has its origin O at the centre of that top
//! face and its axes turned by β = θ_{k−1} (β = 0 and O = 0 on the ground):
//! t = (cos β, sin β) along the face, n = (−sin β, cos β) out of it. Body
//! k's pose relative to the face is (X, Y, φ): its centre at (X, Y) in the
//! face frame, turned by φ = θ_k − β. Its corner on side s (−1 left, +1
//! right) sits at d = (X, Y) + R(φ)(sB, −H) in the face frame, so the
//! corner's gap is d_y and its slip along the face is d_x; their rates
//! ḋ = (Ẋ, Ẏ) + φ̇ Ŝ R(φ)(sB, −H) (Ŝ the quarter turn) are the corner's
//! velocity relative to the material point of the face it touches
//! (u_t, u_n), whatever the motion of the body below.
//!
//! Each contact state leaves some of (X, Y, φ) free (the generalised
//! coordinates q of the interface):
//!
//! ```text
//! flat, stuck     (both corners down, no slip)     none         X = X0, Y = H, φ = 0
//! flat, slipping                                   X            Y = H, φ = 0
//! corner c, stuck (rock about corner c)            φ            X = p0 − r_x, Y = −r_y
//! corner c, slipping (slide-rock)                  φ, p         X = p − r_x,  Y = −r_y
//! open (free flight relative to the face)          X, Y, φ
//! ```
//!
//! with r = R(φ)(cB, −H) the pivot's offset from the centre and p its
//! place along the face. So Ẋ = ṗ + φ̇ r_y, Ẏ = −φ̇ r_x and, with q̈ = 0,
//! Ẍ = φ̇² r_x, Ÿ = φ̇² r_y (the pivot's centripetal term).
//!
//! The absolute pose follows up the chain: c_k = O + R(β)(X, Y),
//! θ_k = β + φ, O = c_{k−1} + R(θ_{k−1})(0, H_{k−1}), and for any vector
//! u = R(β)w: u̇ = β̇ Ŝu + R(β)ẇ, ü = β̈ Ŝu − β̇² u + 2β̇ Ŝ R(β)ẇ + R(β)ẅ.
//! Velocities are linear in q̇ (the Jacobian columns `jc`, `jw`) and
//! accelerations are J q̈ plus the part with q̈ = 0 (`ab`, `alb`).

use super::scene::MAX_BODIES;
use super::scene::Scene;
use crate::detmath as dm;
use crate::outcome::Mode;

/// Most generalised coordinates a stack can have (three bodies in flight).
pub(super) const MAX_DOF: usize = 3 * MAX_BODIES;

/// Which corners of a body touch the face below it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Touch {
    /// Both corners (the bottom face lies on the face below).
    Flat,
    /// One corner, on side −1 (left) or +1 (right): the body rocks about it.
    Corner(f64),
    /// None: the body flies relative to the face below.
    Open,
}

/// Whether the touching corners slip along the face.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Slip {
    /// No relative tangential motion.
    Stick,
    /// Slipping in direction σ = ±1 (the sign of the relative velocity),
    /// under kinetic friction μk N.
    Slip(f64),
}

/// The contact state of one interface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Iface {
    /// Which corners touch.
    pub touch: Touch,
    /// Whether they slip (ignored when open).
    pub slip: Slip,
    /// The fixed coordinate of a stuck state: X for flat, the pivot's p
    /// for a corner (m, along the face).
    pub anchor: f64,
    /// The contact is held against a tension that releasing it could not
    /// relieve consistently (lift-off hold or Painlevé hold).
    pub hold: bool,
}

impl Iface {
    /// Flat and stuck at X = `x`.
    pub fn rest(x: f64) -> Self {
        Iface {
            touch: Touch::Flat,
            slip: Slip::Stick,
            anchor: x,
            hold: false,
        }
    }

    /// Number of free coordinates of the state.
    #[inline]
    pub fn dof(&self) -> usize {
        match (self.touch, self.slip) {
            (Touch::Flat, Slip::Stick) => 0,
            (Touch::Flat, Slip::Slip(_)) | (Touch::Corner(_), Slip::Stick) => 1,
            (Touch::Corner(_), Slip::Slip(_)) => 2,
            (Touch::Open, _) => 3,
        }
    }

    /// The single block's name for the state (relative to the face below).
    pub fn mode(&self) -> Mode {
        match (self.touch, self.slip) {
            (Touch::Flat, Slip::Stick) => Mode::Rest,
            (Touch::Flat, Slip::Slip(_)) => Mode::Slide,
            (Touch::Corner(_), Slip::Stick) => Mode::Rock,
            (Touch::Corner(_), Slip::Slip(_)) => Mode::SlideRock,
            (Touch::Open, _) => Mode::Flight,
        }
    }
}

/// The contact states of the stack's interfaces (bodies above `n` have
/// overturned and left the scene).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Modes {
    /// Bodies still in the scene.
    pub n: usize,
    /// The interface under each body.
    pub ifs: [Iface; MAX_BODIES],
}

impl Modes {
    /// Total number of generalised coordinates.
    #[inline]
    pub fn dof(&self) -> usize {
        self.ifs[..self.n].iter().map(Iface::dof).sum()
    }

    /// Index of interface k's first coordinate in q.
    #[inline]
    pub fn start(&self, k: usize) -> usize {
        self.ifs[..k].iter().map(Iface::dof).sum()
    }
}

/// A body's absolute pose and velocity in the ground frame (origin at the
/// base's initial centre of footprint, y up).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Body {
    /// Centre of mass (m).
    pub c: [f64; 2],
    /// Rotation θ (rad, counter-clockwise).
    pub th: f64,
    /// Velocity of the centre (m/s).
    pub v: [f64; 2],
    /// Angular velocity (rad/s).
    pub w: f64,
}

/// Pose (X, Y, φ) of a body relative to the face below, and its rates.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Rel {
    /// Place of the centre in the face frame (m).
    pub x: f64,
    /// Height of the centre above the face (m).
    pub y: f64,
    /// Rotation relative to the face (rad).
    pub phi: f64,
    /// Ẋ (m/s).
    pub xd: f64,
    /// Ẏ (m/s).
    pub yd: f64,
    /// φ̇ (rad/s).
    pub phid: f64,
}

/// The quarter turn Ŝ(x, y) = (−y, x).
#[inline]
pub(super) fn perp(v: [f64; 2]) -> [f64; 2] {
    [-v[1], v[0]]
}

/// R(θ)v from sin θ and cos θ.
#[inline]
pub(super) fn rot(s: f64, c: f64, v: [f64; 2]) -> [f64; 2] {
    [c * v[0] - s * v[1], s * v[0] + c * v[1]]
}

/// The 2-D cross product a × b = a_x b_y − a_y b_x.
#[inline]
pub(super) fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

#[inline]
pub(super) fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

#[inline]
pub(super) fn add(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] + b[0], a[1] + b[1]]
}

#[inline]
pub(super) fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

#[inline]
pub(super) fn scale(k: f64, a: [f64; 2]) -> [f64; 2] {
    [k * a[0], k * a[1]]
}

/// sin φ and cos φ, exactly (0, 1) at φ = 0.
#[inline]
pub(super) fn sin_cos(phi: f64) -> (f64, f64) {
    if phi == 0.0 {
        (0.0, 1.0)
    } else {
        dm::sin_cos(phi)
    }
}

/// The face frame of interface k: its angle's sine and cosine, origin and
/// their rates (from the body below, or the ground's).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Face {
    /// sin β.
    pub sb: f64,
    /// cos β (1 on the ground).
    pub cb: f64,
    /// Origin O (m).
    pub o: [f64; 2],
    /// β̇ (rad/s).
    pub bd: f64,
    /// Ȯ (m/s).
    pub od: [f64; 2],
}

impl Face {
    /// The ground's face: fixed, level, origin at 0.
    pub const GROUND: Face = Face {
        sb: 0.0,
        cb: 1.0,
        o: [0.0, 0.0],
        bd: 0.0,
        od: [0.0, 0.0],
    };

    /// The top face of `below`, of half-height `h`.
    #[inline]
    pub fn top_of(below: &Body, h: f64) -> Face {
        let (sb, cb) = sin_cos(below.th);
        let o = rot(sb, cb, [0.0, h]);
        Face {
            sb,
            cb,
            o: add(below.c, o),
            bd: below.w,
            od: add(below.v, scale(below.w, perp(o))),
        }
    }

    /// The outward normal n = (−sin β, cos β).
    #[inline]
    pub fn n(&self) -> [f64; 2] {
        [-self.sb, self.cb]
    }

    /// The tangent t = (cos β, sin β).
    #[inline]
    pub fn t(&self) -> [f64; 2] {
        [self.cb, self.sb]
    }

    /// World vector → face frame: R(−β)v.
    #[inline]
    pub fn to_face(self, v: [f64; 2]) -> [f64; 2] {
        rot(-self.sb, self.cb, v)
    }
}

/// The face of interface k given the bodies below it.
#[inline]
pub(super) fn face_of(sc: &Scene, bodies: &[Body; MAX_BODIES], k: usize) -> Face {
    if k == 0 {
        Face::GROUND
    } else {
        Face::top_of(&bodies[k - 1], sc.h[k - 1])
    }
}

/// Body k's pose relative to `face`.
pub(super) fn relative_of(face: &Face, body: &Body) -> Rel {
    let w = sub(body.c, face.o);
    let p = face.to_face(w);
    // ẇ − β̇ Ŝ w, in the face frame
    let wd = sub(sub(body.v, face.od), scale(face.bd, perp(w)));
    let pd = face.to_face(wd);
    Rel {
        x: p[0],
        y: p[1],
        phi: body.th - angle_of(face),
        xd: pd[0],
        yd: pd[1],
        phid: body.w - face.bd,
    }
}

/// The angle β of a face, from its sine and cosine (0 on the ground).
#[inline]
fn angle_of(face: &Face) -> f64 {
    if face.sb == 0.0 && face.cb == 1.0 {
        0.0
    } else {
        dm::atan2(face.sb, face.cb)
    }
}

/// Corner `side`'s place d and its rate ḋ in the face frame for the
/// relative pose `rel` of a body of half-sizes (b, h):
/// d = (X, Y) + R(φ)(sB, −H), ḋ = (Ẋ, Ẏ) + φ̇ Ŝ R(φ)(sB, −H).
#[inline]
pub(super) fn corner_rel(rel: &Rel, sp: f64, cp: f64, b: f64, h: f64, side: f64) -> [f64; 4] {
    let r = rot(sp, cp, [side * b, -h]);
    [
        rel.x + r[0],
        rel.y + r[1],
        rel.xd - rel.phid * r[1],
        rel.yd + rel.phid * r[0],
    ]
}

/// The relative pose and rates of interface k's body in state `m` from its
/// coordinates `q`, `qd` (as many as `m.dof()`), the Jacobian columns
/// ∂(Ẋ, Ẏ, φ̇)/∂q̇_j and the relative acceleration with q̈ = 0.
pub(super) struct Local {
    pub rel: Rel,
    pub sp: f64,
    pub cp: f64,
    pub cols: [[f64; 3]; 3],
    pub bias: [f64; 2],
}

/// [`Local`] of body `k` (half-sizes b, h) in state `m`.
#[inline]
pub(super) fn local(m: &Iface, b: f64, h: f64, q: &[f64], qd: &[f64]) -> Local {
    let mut cols = [[0.0; 3]; 3];
    match m.touch {
        Touch::Flat => {
            let (x, xd) = match m.slip {
                Slip::Stick => (m.anchor, 0.0),
                Slip::Slip(_) => {
                    cols[0] = [1.0, 0.0, 0.0];
                    (q[0], qd[0])
                }
            };
            Local {
                rel: Rel {
                    x,
                    y: h,
                    phi: 0.0,
                    xd,
                    yd: 0.0,
                    phid: 0.0,
                },
                sp: 0.0,
                cp: 1.0,
                cols,
                bias: [0.0, 0.0],
            }
        }
        Touch::Corner(c) => {
            let (phi, phid) = (q[0], qd[0]);
            let (sp, cp) = sin_cos(phi);
            // r = R(φ)(cB, −H): the pivot's offset from the centre
            let r = rot(sp, cp, [c * b, -h]);
            let (p, pd) = match m.slip {
                Slip::Stick => (m.anchor, 0.0),
                Slip::Slip(_) => {
                    cols[1] = [1.0, 0.0, 0.0];
                    (q[1], qd[1])
                }
            };
            // X = p − r_x, Y = −r_y: Ẋ = ṗ + φ̇ r_y, Ẏ = −φ̇ r_x
            cols[0] = [r[1], -r[0], 1.0];
            let w2 = phid * phid;
            Local {
                rel: Rel {
                    x: p - r[0],
                    y: -r[1],
                    phi,
                    xd: pd + phid * r[1],
                    yd: -phid * r[0],
                    phid,
                },
                sp,
                cp,
                cols,
                // Ẍ = p̈ + φ̈ r_y + φ̇² r_x, Ÿ = −φ̈ r_x + φ̇² r_y
                bias: [w2 * r[0], w2 * r[1]],
            }
        }
        Touch::Open => {
            let (sp, cp) = sin_cos(q[2]);
            cols[0] = [1.0, 0.0, 0.0];
            cols[1] = [0.0, 1.0, 0.0];
            cols[2] = [0.0, 0.0, 1.0];
            Local {
                rel: Rel {
                    x: q[0],
                    y: q[1],
                    phi: q[2],
                    xd: qd[0],
                    yd: qd[1],
                    phid: qd[2],
                },
                sp,
                cp,
                cols,
                bias: [0.0, 0.0],
            }
        }
    }
}

/// The coordinates (q, q̇) of interface k's body in state `m` from its
/// relative pose: X, or φ (and the pivot's p when it slips), or (X, Y, φ).
/// Returns how many it wrote.
pub(super) fn coords_of(
    m: &Iface,
    b: f64,
    h: f64,
    rel: &Rel,
    q: &mut [f64],
    qd: &mut [f64],
) -> usize {
    match (m.touch, m.slip) {
        (Touch::Flat, Slip::Stick) => 0,
        (Touch::Flat, Slip::Slip(_)) => {
            q[0] = rel.x;
            qd[0] = rel.xd;
            1
        }
        (Touch::Corner(c), slip) => {
            q[0] = rel.phi;
            qd[0] = rel.phid;
            if let Slip::Slip(_) = slip {
                let (sp, cp) = sin_cos(rel.phi);
                let r = rot(sp, cp, [c * b, -h]);
                // p = X + r_x, ṗ = Ẋ − φ̇ r_y
                q[1] = rel.x + r[0];
                qd[1] = rel.xd - rel.phid * r[1];
                2
            } else {
                1
            }
        }
        (Touch::Open, _) => {
            q[..3].copy_from_slice(&[rel.x, rel.y, rel.phi]);
            qd[..3].copy_from_slice(&[rel.xd, rel.yd, rel.phid]);
            3
        }
    }
}

/// The pivot's place p along the face for corner `c` at the relative pose
/// `rel` (p = X + r_x).
#[inline]
pub(super) fn pivot_of(rel: &Rel, b: f64, h: f64, c: f64) -> f64 {
    let (sp, cp) = sin_cos(rel.phi);
    rel.x + rot(sp, cp, [c * b, -h])[0]
}

/// The chain's kinematics at one state: every body's pose and velocity,
/// the Jacobian of the velocities with respect to q̇ and the accelerations
/// with q̈ = 0.
#[derive(Clone, Copy, Debug)]
pub(super) struct Chain {
    /// Bodies in the scene.
    pub n: usize,
    /// Number of coordinates.
    pub dof: usize,
    /// Absolute poses and velocities.
    pub body: [Body; MAX_BODIES],
    /// sin θ_k, cos θ_k.
    pub trig: [(f64, f64); MAX_BODIES],
    /// Face frame of each interface.
    pub face: [Face; MAX_BODIES],
    /// Relative pose of each body.
    pub rel: [Rel; MAX_BODIES],
    /// sin φ, cos φ of each relative pose.
    pub rtrig: [(f64, f64); MAX_BODIES],
    /// ∂ċ_k/∂q̇_j.
    pub jc: [[[f64; 2]; MAX_DOF]; MAX_BODIES],
    /// ∂θ̇_k/∂q̇_j.
    pub jw: [[f64; MAX_DOF]; MAX_BODIES],
    /// c̈_k with q̈ = 0.
    pub ab: [[f64; 2]; MAX_BODIES],
    /// θ̈_k with q̈ = 0.
    pub alb: [f64; MAX_BODIES],
}

impl Chain {
    /// The kinematics of state `modes` at coordinates `q`, rates `qd`.
    pub fn new(sc: &Scene, modes: &Modes, q: &[f64], qd: &[f64]) -> Self {
        let n = modes.n;
        let mut ch = Chain {
            n,
            dof: 0,
            body: [Body::default(); MAX_BODIES],
            trig: [(0.0, 1.0); MAX_BODIES],
            face: [Face::GROUND; MAX_BODIES],
            rel: [Rel::default(); MAX_BODIES],
            rtrig: [(0.0, 1.0); MAX_BODIES],
            jc: [[[0.0; 2]; MAX_DOF]; MAX_BODIES],
            jw: [[0.0; MAX_DOF]; MAX_BODIES],
            ab: [[0.0; 2]; MAX_BODIES],
            alb: [0.0; MAX_BODIES],
        };
        let mut j0 = 0;
        for k in 0..n {
            let m = &modes.ifs[k];
            let nl = m.dof();
            let loc = local(m, sc.b[k], sc.h[k], &q[j0..j0 + nl], &qd[j0..j0 + nl]);
            let dof = j0 + nl;
            // the face frame and its Jacobian and bias (from body k − 1)
            let (face, jo, jb, ao, alo) = if k == 0 {
                (
                    Face::GROUND,
                    [[0.0; 2]; MAX_DOF],
                    [0.0; MAX_DOF],
                    [0.0; 2],
                    0.0,
                )
            } else {
                let below = ch.body[k - 1];
                let (sb, cb) = ch.trig[k - 1];
                let o = rot(sb, cb, [0.0, sc.h[k - 1]]);
                let po = perp(o);
                let w = below.w;
                let mut jo = [[0.0; 2]; MAX_DOF];
                for (j, col) in jo.iter_mut().enumerate().take(j0) {
                    // Ȯ = ċ + θ̇ Ŝo
                    *col = add(ch.jc[k - 1][j], scale(ch.jw[k - 1][j], po));
                }
                let face = Face {
                    sb,
                    cb,
                    o: add(below.c, o),
                    bd: w,
                    od: add(below.v, scale(w, po)),
                };
                // Ö (q̈ = 0) = c̈ + θ̈ Ŝo − θ̇² o
                let ao = add(
                    add(ch.ab[k - 1], scale(ch.alb[k - 1], po)),
                    scale(-w * w, o),
                );
                (face, jo, ch.jw[k - 1], ao, ch.alb[k - 1])
            };
            let (sb, cb) = (face.sb, face.cb);
            let rel = loc.rel;
            let u = rot(sb, cb, [rel.x, rel.y]);
            let pu = perp(u);
            let wd = rot(sb, cb, [rel.xd, rel.yd]); // R(β)ẇ
            // θ_k = β + φ: its sine and cosine by the angle sum
            let (sp, cp) = (loc.sp, loc.cp);
            let trig = (sb * cp + cb * sp, cb * cp - sb * sp);
            let th = if k == 0 {
                rel.phi
            } else {
                ch.body[k - 1].th + rel.phi
            };
            let mut v = face.od;
            v = add(add(v, scale(face.bd, pu)), wd);
            let w = face.bd + rel.phid;
            // Jacobian columns: the face's, then this interface's own
            for j in 0..dof {
                let (mut c, mut wj) = if j < j0 {
                    (add(jo[j], scale(jb[j], pu)), jb[j])
                } else {
                    ([0.0; 2], 0.0)
                };
                if j >= j0 {
                    let col = loc.cols[j - j0];
                    c = add(c, rot(sb, cb, [col[0], col[1]]));
                    wj += col[2];
                }
                ch.jc[k][j] = c;
                ch.jw[k][j] = wj;
            }
            // c̈ (q̈ = 0) = Ö + β̈ Ŝu − β̇² u + 2β̇ R(β)Ŝẇ + R(β)ẅ
            let bd = face.bd;
            let mut a = add(ao, scale(alo, pu));
            a = add(a, scale(-bd * bd, u));
            a = add(a, scale(2.0 * bd, perp(wd)));
            a = add(a, rot(sb, cb, loc.bias));
            ch.ab[k] = a;
            ch.alb[k] = alo;
            ch.body[k] = Body {
                c: add(face.o, u),
                th,
                v,
                w,
            };
            ch.trig[k] = trig;
            ch.face[k] = face;
            ch.rel[k] = rel;
            ch.rtrig[k] = (sp, cp);
            j0 = dof;
        }
        ch.dof = j0;
        ch
    }

    /// World position of body k's corner on `side` (±1).
    #[inline]
    pub fn corner(&self, sc: &Scene, k: usize, side: f64) -> [f64; 2] {
        let (s, c) = self.trig[k];
        add(self.body[k].c, rot(s, c, [side * sc.b[k], -sc.h[k]]))
    }
}

/// The absolute poses of a stack at rest with each body tilted by `tilt`
/// about the corner on the side of the tilt's sign (the chain of rock
/// states with zero rates, or flat where the tilt is 0).
pub(super) fn initial_modes(sc: &Scene) -> Modes {
    let mut ifs = [Iface::rest(0.0); MAX_BODIES];
    for (k, m) in ifs.iter_mut().enumerate().take(sc.n) {
        let x0 = sc.offset[k];
        let tilt = sc.tilt[k];
        *m = if tilt == 0.0 {
            Iface::rest(x0)
        } else {
            // φ > 0 pivots on the left corner (c = −1), as θ > 0 for a block
            let c = -tilt.signum();
            Iface {
                touch: Touch::Corner(c),
                slip: Slip::Stick,
                anchor: x0 + c * sc.b[k],
                hold: false,
            }
        };
    }
    Modes { n: sc.n, ifs }
}
