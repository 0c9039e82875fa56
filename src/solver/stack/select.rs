//! Which contact state follows an event: an enumeration over the states the
//! touching corners allow (a small linear complementarity problem).
//!
//! Each interface's corners are classified from the bodies' poses and
//! velocities: in contact (gap and normal velocity within tolerance),
//! separating, or approaching (then an impact must come first). The states
//! an interface may take follow: both corners in contact allow flat (stuck,
//! or slipping with finite friction), rock about either corner, or open; one
//! corner allows rock about it (stuck or slipping) or open; none allows only
//! open. Every combination over the interfaces, in the order "more contact
//! first, stuck before slipping" with the base's state varying slowest, is
//! tried: its accelerations and contact forces (`dynamics`) must satisfy
//! every unilateral and friction condition of the combination —
//! compressive normal forces, forces within the friction cone where stuck,
//! the slip accelerating in its direction where it starts from zero, and
//! every corner left free but touching accelerating away from its face —
//! and the first that does is the new state. The event that triggered the
//! choice rules out the state it ended ([`Exclude`]), which breaks the tie
//! at the event's instant (where the ending state's condition holds with
//! equality).
//!
//! Lift-off rule under infinite friction (as the single block's): when a
//! pivot's normal force reaches 0 but no state without it is consistent
//! (releasing the corner would not let it rise), the pivot is held (a
//! tensile contact, counted) until its normal force is positive again.

use super::dynamics::forces;
use super::kinematics::{
    Body, Chain, Iface, MAX_DOF, Modes, Rel, Slip, Touch, coords_of, corner_rel, face_of, pivot_of,
    relative_of, rot, sin_cos,
};
use super::scene::MAX_BODIES;
use super::scene::Scene;

/// What the triggering event rules out at one interface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Exclude {
    /// Nothing (the start, or after an impact).
    None,
    /// Flat contact at interface k (a corner's normal force reached 0).
    Flat(usize),
    /// Contact on one corner at interface k (its normal force reached 0).
    Corner(usize),
    /// Sticking at interface k (the friction cone was reached).
    Stick(usize),
    /// Slipping in direction σ at interface k (the slip stopped).
    Slip(usize, f64),
    /// Open at interface k (a corner kept striking its face at one instant
    /// while released: the release is inconsistent within the tolerances).
    Open(usize),
}

/// Why no state could be chosen.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum NoState {
    /// A corner of interface k approaches its face: an impact comes first.
    Approaching(usize),
    /// No combination is consistent (with its description).
    Inconsistent(String),
}

/// The chosen state and its coordinates.
pub(super) struct Chosen {
    pub modes: Modes,
    pub q: [f64; MAX_DOF],
    pub qd: [f64; MAX_DOF],
    /// Interface whose pivot is held by the lift-off rule.
    pub held: Option<usize>,
}

/// Most candidate states of one interface.
const MAX_CAND: usize = 10;

/// How much wider the force and acceleration tolerances are on the second
/// try of a selection ([`select`]): 1e-6 g instead of 1e-9 g.
const TIE_SLACK: f64 = 1e3;

/// A corner's acceleration relative to the face, (d̈_t, d̈_n):
/// d̈ = (Ẍ, Ÿ) + φ̈ Ŝr − φ̇² r, r = R(φ)(sB, −H).
#[inline]
pub(super) fn corner_acc(
    rel: &Rel,
    sp: f64,
    cp: f64,
    b: f64,
    h: f64,
    side: f64,
    acc: &[f64; 3],
) -> [f64; 2] {
    let r = rot(sp, cp, [side * b, -h]);
    let w2 = rel.phid * rel.phid;
    [
        acc[0] - acc[2] * r[1] - w2 * r[0],
        acc[1] + acc[2] * r[0] - w2 * r[1],
    ]
}

/// Contact tolerances of body k: touching distance 1e-9 R (m), and the
/// settle speed ε√(gR) (m/s) below which a touching corner rests on its
/// face (as the single block's rest rule).
#[inline]
pub(super) fn tolerances(sc: &Scene, k: usize) -> (f64, f64) {
    (1e-9 * sc.r[k], sc.settle * (sc.g * sc.r[k]).sqrt())
}

/// Chooses the state of every interface for the bodies' poses and
/// velocities `bodies` under ground acceleration (ax, ay).
pub(super) fn select(
    sc: &Scene,
    bodies: &[Body; MAX_BODIES],
    n: usize,
    ax: f64,
    ay: f64,
    exclude: Exclude,
) -> Result<Chosen, NoState> {
    let mut cands = [[Iface::rest(0.0); MAX_CAND]; MAX_BODIES];
    let mut nc = [0usize; MAX_BODIES];
    let mut rels = [Rel::default(); MAX_BODIES];
    // corner in contact (resting on its face), per side (−1, +1)
    let mut contact = [[false; 2]; MAX_BODIES];
    let mut slip_small = [false; MAX_BODIES];
    for k in 0..n {
        let face = face_of(sc, bodies, k);
        let rel = relative_of(&face, &bodies[k]);
        rels[k] = rel;
        let (sp, cp) = sin_cos(rel.phi);
        let (touch, vtol) = tolerances(sc, k);
        // normal speeds: the cascade rule's threshold after an impact
        let vtol_n = vtol.max(sc.rest_after_impact * (sc.g * sc.r[k]).sqrt());
        let mut ut = 0.0;
        for (i, side) in [-1.0, 1.0].into_iter().enumerate() {
            let d = corner_rel(&rel, sp, cp, sc.b[k], sc.h[k], side);
            if d[1] <= touch {
                if d[3] < -vtol_n {
                    return Err(NoState::Approaching(k));
                }
                if d[3] <= vtol_n {
                    contact[k][i] = true;
                    ut = d[2];
                }
            }
        }
        let stick_ok = ut.abs() <= vtol;
        slip_small[k] = stick_ok;
        let mut sigmas = [0.0f64; 2];
        let mut ns = 0;
        if sc.fric[k].is_some() {
            if stick_ok {
                sigmas = [1.0, -1.0];
                ns = 2;
            } else {
                sigmas[0] = ut.signum();
                ns = 1;
            }
        }
        let list = &mut cands[k];
        let mut m = 0;
        let mut push = |f: Iface| {
            let out = match (exclude, f.touch, f.slip) {
                (Exclude::Flat(j), Touch::Flat, _) if j == k => true,
                (Exclude::Corner(j), Touch::Corner(_), _) if j == k => true,
                (Exclude::Stick(j), Touch::Flat | Touch::Corner(_), Slip::Stick) if j == k => true,
                (Exclude::Slip(j, s), Touch::Flat | Touch::Corner(_), Slip::Slip(t))
                    if j == k && s == t =>
                {
                    true
                }
                (Exclude::Open(j), Touch::Open, _) if j == k => true,
                _ => false,
            };
            if !out {
                list[m] = f;
                m += 1;
            }
        };
        let corner = |c: f64, slip: Slip| Iface {
            touch: Touch::Corner(c),
            slip,
            anchor: pivot_of(&rel, sc.b[k], sc.h[k], c),
            hold: false,
        };
        let flat = |slip: Slip| Iface {
            touch: Touch::Flat,
            slip,
            anchor: rel.x,
            hold: false,
        };
        let open = Iface {
            touch: Touch::Open,
            slip: Slip::Stick,
            anchor: 0.0,
            hold: false,
        };
        match contact[k] {
            [true, true] => {
                if stick_ok {
                    push(flat(Slip::Stick));
                    push(corner(-1.0, Slip::Stick));
                    push(corner(1.0, Slip::Stick));
                }
                for &s in &sigmas[..ns] {
                    push(flat(Slip::Slip(s)));
                }
                for &s in &sigmas[..ns] {
                    push(corner(-1.0, Slip::Slip(s)));
                    push(corner(1.0, Slip::Slip(s)));
                }
            }
            [l, r] if l || r => {
                let c = if l { -1.0 } else { 1.0 };
                if stick_ok {
                    push(corner(c, Slip::Stick));
                }
                for &s in &sigmas[..ns] {
                    push(corner(c, Slip::Slip(s)));
                }
            }
            _ => {}
        }
        push(open);
        nc[k] = m;
    }
    // First with the tolerances of an exact state; then, if none is
    // consistent, with tolerances TIE_SLACK times wider: at the instant of
    // the event that ended a state, the state that follows satisfies its
    // conditions with equality, to within the event's location (a released
    // corner's normal acceleration of 2e-8 m/s², against 1e-9 g, ended a
    // statue-on-pedestal analysis; tests/stack_study.rs).
    for slack in [1.0, TIE_SLACK] {
        if let Some(c) = enumerate(
            sc,
            bodies,
            n,
            ax,
            ay,
            &cands,
            &nc,
            &rels,
            &contact,
            &slip_small,
            None,
            slack,
        ) {
            return Ok(c);
        }
        // the lift-off rule: hold the pivot of an infinite-friction corner (the
        // one whose normal force reached 0 first, then any other)
        let first = match exclude {
            Exclude::Corner(k) | Exclude::Open(k) => k,
            _ => 0,
        };
        for k in (first..n).chain(0..first) {
            let single = contact[k][0] != contact[k][1];
            if sc.fric[k].is_some() || !single {
                continue;
            }
            let c = if contact[k][0] { -1.0 } else { 1.0 };
            let mut held = cands;
            let mut nh = nc;
            held[k][0] = Iface {
                touch: Touch::Corner(c),
                slip: Slip::Stick,
                anchor: pivot_of(&rels[k], sc.b[k], sc.h[k], c),
                hold: true,
            };
            nh[k] = 1;
            if let Some(c) = enumerate(
                sc,
                bodies,
                n,
                ax,
                ay,
                &held,
                &nh,
                &rels,
                &contact,
                &slip_small,
                Some(k),
                slack,
            ) {
                return Ok(c);
            }
        }
    }
    Err(NoState::Inconsistent(format!(
        "no contact state of the {n} bodies is consistent (corners in contact, bottom first: {}; \
         after {exclude:?})",
        (0..n)
            .map(|k| match contact[k] {
                [true, true] => "both",
                [true, false] => "left",
                [false, true] => "right",
                _ => "none",
            })
            .collect::<Vec<_>>()
            .join(", ")
    )))
}

/// Tries every combination of the candidates, in order; the first
/// consistent one. `held`: the interface whose pivot may pull; `slack`:
/// the tolerances' factor.
#[allow(clippy::too_many_arguments)]
fn enumerate(
    sc: &Scene,
    bodies: &[Body; MAX_BODIES],
    n: usize,
    ax: f64,
    ay: f64,
    cands: &[[Iface; MAX_CAND]; MAX_BODIES],
    nc: &[usize; MAX_BODIES],
    rels: &[Rel; MAX_BODIES],
    contact: &[[bool; 2]; MAX_BODIES],
    slip_small: &[bool; MAX_BODIES],
    held: Option<usize>,
    slack: f64,
) -> Option<Chosen> {
    let total: usize = nc[..n].iter().product();
    let tol_a = 1e-9 * slack * sc.g;
    'combo: for idx in 0..total {
        let mut ifs = [Iface::rest(0.0); MAX_BODIES];
        let mut rem = idx;
        for k in (0..n).rev() {
            ifs[k] = cands[k][rem % nc[k]];
            rem /= nc[k];
        }
        let modes = Modes { n, ifs };
        let mut q = [0.0; MAX_DOF];
        let mut qd = [0.0; MAX_DOF];
        let mut j0 = 0;
        for k in 0..n {
            j0 += coords_of(
                &ifs[k],
                sc.b[k],
                sc.h[k],
                &rels[k],
                &mut q[j0..],
                &mut qd[j0..],
            );
        }
        let mut ch = Chain::new(sc, &modes, &q, &qd);
        if project(sc, &ch, bodies, &mut qd) {
            ch = Chain::new(sc, &modes, &q, &qd);
        }
        let f = forces(sc, &modes, &ch, ax, ay);
        if f.singular {
            continue;
        }
        for k in 0..n {
            let m = ifs[k];
            let con = f.contact[k];
            let tol_f = 1e-9 * slack * sc.g * sc.carried(k, n);
            let rel = ch.rel[k];
            let (sp, cp) = ch.rtrig[k];
            let acc = |side: f64| corner_acc(&rel, sp, cp, sc.b[k], sc.h[k], side, &f.rel_acc[k]);
            let cone = |t: f64, nn: f64| match sc.fric[k] {
                None => true,
                Some((mu_s, _)) => t.abs() <= mu_s * nn.max(0.0) + tol_f,
            };
            let ok = match (m.touch, m.slip) {
                (Touch::Flat, Slip::Stick) => {
                    con.nl >= -tol_f && con.nr >= -tol_f && cone(con.t, con.n)
                }
                (Touch::Flat, Slip::Slip(s)) => {
                    con.nl >= -tol_f
                        && con.nr >= -tol_f
                        && (!slip_small[k] || s * f.rel_acc[k][0] >= -tol_a)
                }
                (Touch::Corner(c), slip) => {
                    let other = if c < 0.0 { 1 } else { 0 };
                    let free_ok = !contact[k][other] || acc(-c)[1] >= -tol_a;
                    let n_ok = held == Some(k) || con.n >= -tol_f;
                    let slip_ok = match slip {
                        Slip::Stick => held == Some(k) || cone(con.t, con.n),
                        Slip::Slip(s) => !slip_small[k] || s * acc(c)[0] >= -tol_a,
                    };
                    free_ok && n_ok && slip_ok
                }
                (Touch::Open, _) => {
                    (!contact[k][0] || acc(-1.0)[1] >= -tol_a)
                        && (!contact[k][1] || acc(1.0)[1] >= -tol_a)
                }
            };
            if !ok {
                continue 'combo;
            }
        }
        return Some(Chosen { modes, q, qd, held });
    }
    None
}

/// Projects the bodies' velocities on the state's admissible velocities in
/// the kinetic-energy metric: q̇ = (JᵀMJ)⁻¹ JᵀM V, the admissible velocity
/// nearest to V, which never has more kinetic energy than V (a corner
/// taken as resting while it still moves at less than the settle speed
/// loses that motion; the bodies above keep their own). False if the
/// state has no free coordinate or the system is singular.
fn project(sc: &Scene, ch: &Chain, bodies: &[Body; MAX_BODIES], qd: &mut [f64; MAX_DOF]) -> bool {
    use super::dynamics::{MAX_SYS, solve};
    let dof = ch.dof;
    if dof == 0 {
        return false;
    }
    let mut a = [[0.0; MAX_SYS]; MAX_SYS];
    let mut b = [0.0; MAX_SYS];
    for k in 0..ch.n {
        let (m, inertia) = (sc.m[k], sc.inertia[k]);
        for i in 0..dof {
            let (ci, wi) = (ch.jc[k][i], ch.jw[k][i]);
            b[i] +=
                m * (ci[0] * bodies[k].v[0] + ci[1] * bodies[k].v[1]) + inertia * wi * bodies[k].w;
            for j in 0..dof {
                let cj = ch.jc[k][j];
                a[i][j] += m * (ci[0] * cj[0] + ci[1] * cj[1]) + inertia * wi * ch.jw[k][j];
            }
        }
    }
    if !solve(&mut a, &mut b, dof) {
        return false;
    }
    qd[..dof].copy_from_slice(&b[..dof]);
    true
}
