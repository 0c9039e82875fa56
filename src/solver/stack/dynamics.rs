//! The equations of motion in a contact state, and the contact forces.
//!
//! In the coordinates q a state leaves free (`kinematics`), the bodies'
//! velocities are J q̇ and their accelerations J q̈ + b. Projecting Newton's
//! and Euler's equations of every body on the coordinates (the principle of
//! virtual work; the stuck contacts' reactions do no work) gives
//!
//! ```text
//! M q̈ = Q − Σ_slipping μk σ N e_p,   M = Σ_k J_kᵀ M_k J_k,   Q = Σ_k J_kᵀ (f_k − M_k b_k)   (E1)
//! ```
//!
//! with M_k = diag(m_k, m_k, I_k), f_k = −m_k (ẍg, g + ÿg, 0) (gravity and
//! the ground's inertial force, in the ground's frame), and for each
//! slipping interface its kinetic friction −μk σ N acting on its slip
//! coordinate p (X when flat): the work of the friction pair is F_t δp,
//! since p is the contact's place along the face. N is not known before
//! q̈: the interface carries everything above it, so
//!
//! ```text
//! F_k = Σ_{j ≥ k} m_j (a_j + (ẍg, g + ÿg)),   N_k = n_k · F_k,   T_k = t_k · F_k      (E2)
//! ```
//!
//! which is affine in q̈; (E1) and (E2) for the slipping interfaces are one
//! linear system in (q̈, N). Where a flat interface's two corners share
//! N_k, Euler's equation of body k about its centre splits it: the moment
//! M_k = I_k θ̈_k + Σ_{c above} (P_c − c_k) × F_c of the reactions from below
//! (the forces F_c of the interface above act at its contact points P_c on
//! body k's face) equals Σ_{c = L, R} (P_c − c_k) × N_c n + (P_L − c_k) × T t
//! (a tangential force's moment does not depend on where along the face it
//! acts), which gives N_L, and N_R = N_k − N_L (E3).

use super::kinematics::{Chain, MAX_DOF, Modes, Slip, Touch, add, cross, dot, rot, scale, sub};
use super::scene::MAX_BODIES;
use super::scene::Scene;

/// Largest linear system: every coordinate and a normal force per slipping
/// interface.
pub(super) const MAX_SYS: usize = MAX_DOF + MAX_BODIES;

/// The contact forces of one interface, on the body above it (world units
/// of the stack's relative masses times m/s²).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Contact {
    /// Total normal force N (along the face's normal).
    pub n: f64,
    /// Total tangential force T (along the face).
    pub t: f64,
    /// Normal force at the left corner (flat), or at the pivot (corner on
    /// the left); 0 when open.
    pub nl: f64,
    /// Normal force at the right corner.
    pub nr: f64,
}

/// The accelerations and contact forces of a state.
#[derive(Clone, Copy, Debug)]
pub(super) struct Forces {
    /// q̈.
    pub qdd: [f64; MAX_DOF],
    /// Each body's relative accelerations (Ẍ, Ÿ, φ̈) in its face frame.
    pub rel_acc: [[f64; 3]; MAX_BODIES],
    /// Each interface's forces.
    pub contact: [Contact; MAX_BODIES],
    /// The linear system was singular (no acceleration: a Painlevé case).
    pub singular: bool,
}

/// Gaussian elimination with partial pivoting on the leading `n` × `n`
/// block; false if singular.
pub(super) fn solve(a: &mut [[f64; MAX_SYS]; MAX_SYS], b: &mut [f64; MAX_SYS], n: usize) -> bool {
    for col in 0..n {
        let mut piv = col;
        let mut best = a[col][col].abs();
        for (r, row) in a.iter().enumerate().take(n).skip(col + 1) {
            if row[col].abs() > best {
                best = row[col].abs();
                piv = r;
            }
        }
        if best == 0.0 || !best.is_finite() {
            return false;
        }
        a.swap(col, piv);
        b.swap(col, piv);
        let inv = 1.0 / a[col][col];
        for r in col + 1..n {
            let f = a[r][col] * inv;
            if f != 0.0 {
                for c in col..n {
                    a[r][c] -= f * a[col][c];
                }
                b[r] -= f * b[col];
            }
        }
    }
    for col in (0..n).rev() {
        let mut s = b[col];
        for c in col + 1..n {
            s -= a[col][c] * b[c];
        }
        b[col] = s / a[col][col];
    }
    true
}

/// q̈ alone (E1, E2): what the integrator needs. Writes `qdd[..dof]`;
/// returns false if the system is singular.
#[inline]
pub(super) fn accelerations(
    sc: &Scene,
    modes: &Modes,
    ch: &Chain,
    ax: f64,
    ay: f64,
    qdd: &mut [f64],
) -> bool {
    let dof = ch.dof;
    let n = ch.n;
    let gv = [ax, sc.g + ay];
    let mut a = [[0.0; MAX_SYS]; MAX_SYS];
    let mut rhs = [0.0; MAX_SYS];
    // M = Σ J_kᵀ M_k J_k and Q = Σ J_kᵀ (f_k − M_k b_k), f_k = −m_k gv
    for k in 0..n {
        let (m, inertia) = (sc.m[k], sc.inertia[k]);
        let fk = scale(-m, add(gv, ch.ab[k]));
        let tk = -inertia * ch.alb[k];
        for i in 0..dof {
            let (ci, wi) = (ch.jc[k][i], ch.jw[k][i]);
            if ci == [0.0, 0.0] && wi == 0.0 {
                continue;
            }
            rhs[i] += dot(ci, fk) + wi * tk;
            for j in i..dof {
                let v = m * dot(ci, ch.jc[k][j]) + inertia * wi * ch.jw[k][j];
                a[i][j] += v;
                if j != i {
                    a[j][i] += v;
                }
            }
        }
    }
    // slipping interfaces: unknown N_i, friction −μk σ N_i on the slip coordinate
    let mut size = dof;
    let mut j0 = 0;
    for i in 0..n {
        let m = &modes.ifs[i];
        if let (Slip::Slip(sigma), Touch::Flat | Touch::Corner(_)) = (m.slip, m.touch) {
            let mu_k = sc.fric[i].map_or(0.0, |f| f.1);
            let p = match m.touch {
                Touch::Corner(_) => j0 + 1,
                _ => j0,
            };
            let row = size;
            a[p][row] += mu_k * sigma;
            // N_i − n_i·Σ_{j≥i} m_j jc_j q̈ = n_i·Σ_{j≥i} m_j (b_j + gv)   (E2)
            let nv = ch.face[i].n();
            a[row][row] = 1.0;
            for k in i..n {
                let m = sc.m[k];
                for l in 0..dof {
                    a[row][l] -= m * dot(nv, ch.jc[k][l]);
                }
                rhs[row] += m * dot(nv, add(ch.ab[k], gv));
            }
            size += 1;
        }
        j0 += m.dof();
    }
    if !solve(&mut a, &mut rhs, size) {
        return false;
    }
    qdd[..dof].copy_from_slice(&rhs[..dof]);
    true
}

/// q̈ and every interface's forces (E1–E3).
pub(super) fn forces(sc: &Scene, modes: &Modes, ch: &Chain, ax: f64, ay: f64) -> Forces {
    let mut out = Forces {
        qdd: [0.0; MAX_DOF],
        rel_acc: [[0.0; 3]; MAX_BODIES],
        contact: [Contact::default(); MAX_BODIES],
        singular: false,
    };
    let n = ch.n;
    let dof = ch.dof;
    if !accelerations(sc, modes, ch, ax, ay, &mut out.qdd) {
        out.singular = true;
        return out;
    }
    let gv = [ax, sc.g + ay];
    // accelerations of every body, and the relative ones
    let mut acc = [[0.0; 2]; MAX_BODIES];
    let mut alpha = [0.0; MAX_BODIES];
    let mut j0 = 0;
    for k in 0..n {
        let mut a = ch.ab[k];
        let mut al = ch.alb[k];
        for j in 0..dof {
            a = add(a, scale(out.qdd[j], ch.jc[k][j]));
            al += ch.jw[k][j] * out.qdd[j];
        }
        acc[k] = a;
        alpha[k] = al;
        let m = &modes.ifs[k];
        let nl = m.dof();
        // (Ẍ, Ÿ, φ̈) = Σ cols q̈ + bias (the local Jacobian of `kinematics::local`)
        let rel = ch.rel[k];
        let (sp, cp) = ch.rtrig[k];
        out.rel_acc[k] = match m.touch {
            Touch::Flat => [if nl == 1 { out.qdd[j0] } else { 0.0 }, 0.0, 0.0],
            Touch::Corner(c) => {
                let r = rot(sp, cp, [c * sc.b[k], -sc.h[k]]);
                let (phdd, pdd) = (out.qdd[j0], if nl == 2 { out.qdd[j0 + 1] } else { 0.0 });
                let w2 = rel.phid * rel.phid;
                [
                    pdd + phdd * r[1] + w2 * r[0],
                    -phdd * r[0] + w2 * r[1],
                    phdd,
                ]
            }
            Touch::Open => [out.qdd[j0], out.qdd[j0 + 1], out.qdd[j0 + 2]],
        };
        j0 += nl;
    }
    // forces top-down (E2) and the flat split (E3)
    let mut f_above = [0.0; 2];
    // contact points and forces of the interface above, on the body above
    let mut above: [([f64; 2], [f64; 2]); 2] = [([0.0; 2], [0.0; 2]); 2];
    for k in (0..n).rev() {
        let f = add(scale(sc.m[k], add(acc[k], gv)), f_above);
        let face = ch.face[k];
        let (nv, tv) = (face.n(), face.t());
        let (nn, tt) = (dot(nv, f), dot(tv, f));
        let ck = ch.body[k].c;
        // the moment about c_k of the reactions from below
        let mut mk = sc.inertia[k] * alpha[k];
        for (p, fc) in above {
            mk += cross(sub(p, ck), fc);
        }
        let m = &modes.ifs[k];
        let mut con = Contact {
            n: nn,
            t: tt,
            nl: 0.0,
            nr: 0.0,
        };
        above = [([0.0; 2], [0.0; 2]); 2];
        match m.touch {
            Touch::Flat => {
                let pl = ch.corner(sc, k, -1.0);
                let pr = ch.corner(sc, k, 1.0);
                // (E3): N_L (P_L − P_R) × n = M_k − T (P_L − c_k) × t − N (P_R − c_k) × n
                let den = cross(sub(pl, pr), nv);
                let nlv = (mk - tt * cross(sub(pl, ck), tv) - nn * cross(sub(pr, ck), nv)) / den;
                con.nl = nlv;
                con.nr = nn - nlv;
                above = [
                    (pl, add(scale(nlv, nv), scale(tt, tv))),
                    (pr, scale(nn - nlv, nv)),
                ];
            }
            Touch::Corner(c) => {
                if c < 0.0 {
                    con.nl = nn;
                } else {
                    con.nr = nn;
                }
                above = [(ch.corner(sc, k, c), f), ([0.0; 2], [0.0; 2])];
            }
            Touch::Open => {}
        }
        out.contact[k] = con;
        f_above = f;
    }
    out
}
