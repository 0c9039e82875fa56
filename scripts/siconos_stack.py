#!/usr/bin/python3
"""rockfrag's stack solver against Siconos (issue 40, docs/stack.md "Against Siconos").

Runs under the SYSTEM python, which has Debian's python3-siconos (4.4):

    /usr/bin/python3 scripts/siconos_stack.py            # the whole comparison (~1 h on 2 shared cores)
    /usr/bin/python3 scripts/siconos_stack.py --quick    # free rocking only (~8 min)

Siconos model (independent of rockfrag's equations): two rigid rectangles in
2-D, each a LagrangianLinearTIDS with q = (x, y, θ) of its centre in the
ground's frame, M = diag(m, m, m(B² + H²)/3), external force
(−m ẍg(t), −m g, 0): the ground's acceleration as a body force in the ground
frame, as rockfrag writes its equations. Four corner contacts: the base's two
bottom corners on the ground, the top's two bottom corners on the base's top
face (the line through it, in the base's frame). Each contact is a
NewtonImpactFrictionNSL (Newton's restitution e on the normal velocity,
Coulomb friction μ) whose relation is the contact's gap and tangential
velocity, linearised at the start of every step (y = C q + e with C the
Jacobian at q_k: what Moreau–Jean does with a nonlinear scleronomous relation
in its linear Newton option). Integrator: MoreauJeanOSI(θ = 1/2) with a
FrictionContact(2) problem solved by Lemke's method, fixed step h; a run in
which some step's solve failed or gained energy (see siconos_run) is solved
again by NSGS (tolerance 1e-10). Infinite friction is approximated by
μ = 100 (--mu): a single corner impact of these blocks asks for a ratio of
tangential to normal impulse of at most 3 sinθc cosθc / (1 + 3 cos²θc)
(0.49 for the pedestal, physics.md), but in the cascades of small impacts
as a rocking body settles the ratio is far larger: at μ = 10 the base slid
0.8 mm in one (free rocking from tilts 0.1, 0 at h = 1.25e-4; 2 µm at
μ = 100) and the top's history moved 0.45 θc off rockfrag's (0.015 at
μ = 100). The ground's
acceleration enters each step as its mean over the step (the record is
linear between samples, so this is the θ = 1/2 weighting of its ends).

When the top's rotation relative to the base reaches π/2 it has overturned
and leaves the scene, as in rockfrag (docs/stack.md "Rules"): the model is
rebuilt with the base alone from its state; the base's overturning ends the
analysis.

rockfrag side: `rockfrag simulate --stack … --json --history` on the same
records (`rockfrag motion` CSVs). Free rocking uses a still record (a CSV of
zeros with one 0.06 m/s² sample a step after the compared span: the CSV
reader refuses a record of zeros).

Compared per body: θmax/θc (rotation relative to the body below, over its
θc), overturned or not, and the time history of φ/θc (max over the span both
engines follow, rockfrag's rows against Siconos interpolated linearly), at
the step sizes of --steps; Siconos's own step error is the difference between
its two finest steps.
"""

import argparse
import contextlib
import json
import math
import os
import subprocess
import sys
import tempfile
import time

# one BLAS thread: Siconos's small dense solves gain nothing from more, and
# on a shared machine OpenBLAS's spinning threads made a run three times
# slower (wall 3.6 s against 1.2 s for the same 4,000 steps)
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

G = 9.81
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def import_siconos():
    try:
        import siconos.kernel as sk
        import siconos.numerics as sn
    except ImportError as err:
        sys.exit(
            f"siconos_stack.py: cannot import Siconos ({err}); run it with the system "
            "python that has Debian's python3-siconos: /usr/bin/python3 "
            "scripts/siconos_stack.py"
        )
    return sk, sn


@contextlib.contextmanager
def c_output_to(path):
    """Sends the C++ library's stdout and stderr (its solver warnings and
    debug prints) to `path` while Siconos runs."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = os.dup(1), os.dup(2)
    with open(path, "ab") as f:
        os.dup2(f.fileno(), 1)
        os.dup2(f.fileno(), 2)
    try:
        yield
    finally:
        sys.stdout.flush()
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        os.close(saved[0])
        os.close(saved[1])


def rot(th, r):
    c, s = math.cos(th), math.sin(th)
    return np.array([r[0] * c - r[1] * s, r[0] * s + r[1] * c])


def drot(th, r):
    c, s = math.cos(th), math.sin(th)
    return np.array([-r[0] * s - r[1] * c, r[0] * c - r[1] * s])


class Stack:
    """Two bodies, bottom first: widths 2B, heights 2H, masses (relative)."""

    def __init__(self, text, masses=None):
        self.dims = []
        for item in text.split(","):
            w, h = item.lower().split("x")
            self.dims.append((float(w) / 2, float(h) / 2))
        if len(self.dims) != 2:
            sys.exit("siconos_stack.py: --stack takes two bodies, bottom first")
        self.masses = masses or [4 * b * h for b, h in self.dims]
        self.theta_c = [math.atan(b / h) for b, h in self.dims]
        self.text = text

    def initial(self, tilts):
        """Poses q = (x, y, θ) of the bodies released from `tilts`, each
        relative to the body below, about the corner on the side of its sign
        (rockfrag's --tilts)."""
        (b1, h1), (b2, h2) = self.dims
        t1, t2 = tilts
        s1 = 1.0 if t1 >= 0 else -1.0
        c1 = np.array([-s1 * b1, 0.0]) - rot(t1, [-s1 * b1, -h1])
        s2 = 1.0 if t2 >= 0 else -1.0
        th2 = t1 + t2
        pivot = c1 + rot(t1, [-s2 * b2, h1])
        c2 = pivot - rot(th2, [-s2 * b2, -h2])
        return [np.array([c1[0], c1[1], t1]), np.array([c2[0], c2[1], th2])]


def ground_update(rel, r, q):
    """The base's corner r (body frame) on the ground: gap and slip."""
    C, e = rel.C(), rel.e()
    d = drot(q[2], r)
    p = q[0:2] + rot(q[2], r)
    C[0, 0], C[0, 1], C[0, 2] = 0.0, 1.0, d[1]
    C[1, 0], C[1, 1], C[1, 2] = 1.0, 0.0, d[0]
    e[0] = p[1] - C[0].dot(q)
    e[1] = -C[1].dot(q)


def face_update(rel, r, h_below, q):
    """The top's corner r on the base's top face: the gap along the face's
    normal, the slip along it relative to the base's material point."""
    C, e = rel.C(), rel.e()
    c1, t1, c2, t2 = q[0:2], q[2], q[3:5], q[5]
    n = np.array([-math.sin(t1), math.cos(t1)])
    t = np.array([math.cos(t1), math.sin(t1)])
    d = c2 + rot(t2, r) - c1
    dr = drot(t2, r)
    w = np.array([-d[1], d[0]])
    C[0, :] = [-n[0], -n[1], -n.dot(w), n[0], n[1], n.dot(dr)]
    C[1, :] = [-t[0], -t[1], -t.dot(w), t[0], t[1], t.dot(dr)]
    e[0] = n.dot(d) - h_below - C[0].dot(q)
    e[1] = -C[1].dot(q)


def siconos_run(stack, acc, dt, t_end, h, e, mu, tilts=(0.0, 0.0), log=os.devnull, energy=None,
                solver="LEMKE"):
    """One analysis by Moreau–Jean: returns times, φ per body (relative to
    the body below; NaN once it has overturned), overturn times, and the
    number of steps whose friction problem the solver reported unsolved, and
    the number of steps that gained energy: whose mechanical energy in the
    ground's frame (kinetic plus gravity's potential) rose by more than the
    ground's work over the step (Σ −m ẍg Δx) plus 1e-4 of the stack's mgR.
    Moreau–Jean conserves energy to O(h³) between impacts and an impact of
    e ≤ 1 at stuck contacts cannot add it, so such a step is a wrong solve.
    With a list `energy`, appends each step's mechanical energy."""
    sk, sn = import_siconos()
    n_steps = int(round(t_end / h))
    times = np.arange(1, n_steps + 1) * h
    phi = np.full((n_steps, 2), np.nan)
    over = [None, None]
    state = [(q, np.zeros(3)) for q in stack.initial(tilts)]

    # the record's mean over each step: the record is linear between its
    # samples and every step lies between two of them (h divides dt), so
    # the mean is that of the step's ends (the θ = 1/2 weighting)
    if abs(dt / h - round(dt / h)) > 1e-9:
        sys.exit(f"siconos_stack.py: step {h} s does not divide the record's dt {dt} s")
    ends = np.interp(np.arange(n_steps + 1) * h, np.arange(len(acc)) * dt, acc)
    felt = 0.5 * (ends[:-1] + ends[1:])

    step, t0 = 0, 0.0
    gains = 0
    scale = sum(m * G * math.hypot(b, hh) for m, (b, hh) in zip(stack.masses, stack.dims))
    before = open(log).read().count("solver warning") if os.path.exists(log) else 0
    with c_output_to(log):
        while step < n_steps:
            nb = len(state)
            nsds = sk.NonSmoothDynamicalSystem(t0, t_end)
            dss = []
            for k in range(nb):
                b, hh = stack.dims[k]
                m = stack.masses[k]
                inertia = m * (b * b + hh * hh) / 3.0
                q, v = state[k]
                ds = sk.LagrangianLinearTIDS(list(q), list(v), np.diag([m, m, inertia]))
                ds.setFExtPtr([0.0, -m * G, 0.0])
                nsds.insertDynamicalSystem(ds)
                dss.append(ds)
            contacts = []
            b1, h1 = stack.dims[0]
            for sx in (-1.0, 1.0):
                rel = sk.LagrangianLinearTIR(np.zeros((2, 3)), np.zeros(2))
                nsds.link(sk.Interaction(sk.NewtonImpactFrictionNSL(e, 0.0, mu, 2), rel), dss[0])
                contacts.append(("ground", rel, np.array([sx * b1, -h1])))
            if nb == 2:
                b2, h2 = stack.dims[1]
                for sx in (-1.0, 1.0):
                    rel = sk.LagrangianLinearTIR(np.zeros((2, 6)), np.zeros(2))
                    nsl = sk.NewtonImpactFrictionNSL(e, 0.0, mu, 2)
                    nsds.link(sk.Interaction(nsl, rel), dss[0], dss[1])
                    contacts.append(("face", rel, np.array([sx * b2, -h2])))

            def update():
                q1 = np.array(dss[0].q())
                q = np.concatenate([q1, np.array(dss[1].q())]) if nb == 2 else q1
                for kind, rel, r in contacts:
                    if kind == "ground":
                        ground_update(rel, r, q1)
                    else:
                        face_update(rel, r, h1, q)

            update()
            osnspb = sk.FrictionContact(2, getattr(sn, "SICONOS_FRICTION_2D_" + solver))
            if solver == "NSGS":
                osnspb.numericsSolverOptions().dparam[sn.SICONOS_DPARAM_TOL] = 1e-10
                osnspb.numericsSolverOptions().iparam[sn.SICONOS_IPARAM_MAX_ITER] = 100000
            sim = sk.TimeStepping(
                nsds,
                sk.TimeDiscretisation(t0, h),
                sk.MoreauJeanOSI(0.5),
                osnspb,
            )
            sim.setNewtonOptions(sk.SICONOS_TS_LINEAR)
            fext = [ds.fExt() for ds in dss]
            rebuild = False

            def mechanical():
                total, xs = 0.0, []
                for k in range(nb):
                    b, hh = stack.dims[k]
                    m = stack.masses[k]
                    v, q = dss[k].velocity(), dss[k].q()
                    total += 0.5 * m * (v[0] ** 2 + v[1] ** 2)
                    total += 0.5 * m * (b * b + hh * hh) / 3.0 * v[2] ** 2
                    total += m * G * q[1]
                    xs.append(q[0])
                return total, xs

            e_before, x_before = mechanical()
            while step < n_steps:
                a = felt[step]
                for k in range(nb):
                    fext[k][0] = -stack.masses[k] * a  # ground frame: −m ẍg
                update()
                sim.computeOneStep()
                q1 = dss[0].q()
                phi[step, 0] = q1[2]
                if nb == 2:
                    phi[step, 1] = dss[1].q()[2] - q1[2]
                e_after, x_after = mechanical()
                work = sum(-stack.masses[k] * a * (x_after[k] - x_before[k]) for k in range(nb))
                if e_after - e_before - work > 1e-4 * scale:
                    gains += 1
                e_before, x_before = e_after, x_after
                if energy is not None:
                    energy.append(e_after)
                step += 1
                sim.nextStep()
                if abs(phi[step - 1, 0]) >= math.pi / 2:
                    over[0] = times[step - 1]
                    if over[1] is None:
                        over[1] = times[step - 1]
                    step = n_steps
                    break
                if nb == 2 and abs(phi[step - 1, 1]) >= math.pi / 2:
                    # the top has overturned: it leaves the scene
                    over[1] = times[step - 1]
                    state = [(np.array(dss[0].q()), np.array(dss[0].velocity()))]
                    t0 = step * h
                    rebuild = True
                    break
            if not rebuild:
                break
    after = open(log).read().count("solver warning")
    return times, phi, over, after - before, gains


def rockfrag(binary, stack, record, e, workdir, tag, tilts=None, scale=None):
    """`rockfrag simulate --stack` on `record` (times `scale`): its JSON
    outcome and history."""
    hist = os.path.join(workdir, f"{tag}.history.csv")
    cmd = [
        binary, "simulate", "--stack", stack.text, "--motion", record,
        "--restitution", str(e), "--json", "--history", hist,
        # Siconos stops at the record's end: rockfrag does too here, so that
        # both engines answer the same question (the motion after the record
        # is compared in the free-rocking group)
        "--free-motion-max", "0",
    ]
    if tilts is not None:
        cmd += ["--tilts", f"{tilts[0]},{tilts[1]}"]
    if scale is not None:
        cmd += ["--scale", repr(scale)]
    run = subprocess.run(cmd, capture_output=True, text=True)
    if not run.stdout.strip():
        sys.exit(f"siconos_stack.py: {' '.join(cmd)} failed: {run.stderr}")
    out = json.loads(run.stdout)
    data = np.genfromtxt(hist, delimiter=",", names=True, dtype=None, encoding=None)
    return out, data


def spread(binary, stack, record, e, workdir, tag, eps):
    """rockfrag's own sensitivity: per body, its θmax/θc and overturning
    under the record scaled by 1 − eps and 1 + eps (a perturbation far
    smaller than Moreau–Jean's O(h) error)."""
    answers = []
    for scale in (1.0 - eps, 1.0 + eps):
        out, _ = rockfrag(binary, stack, record, e, workdir, f"{tag}s", None, scale)
        answers.append([(b["theta_max_over_theta_c"], b["overturned"]) for b in out["bodies"]])
    return [[a[k] for a in answers] for k in range(2)]


def record_csv(binary, seed, pga, index, duration, workdir):
    path = os.path.join(workdir, f"rec_s{seed}_p{pga}_i{index}.csv")
    subprocess.run(
        [binary, "motion", "--seed", str(seed), "--pga", str(pga), "--index", str(index),
         "--duration", str(duration), "--out", path],
        check=True, capture_output=True,
    )
    return path


def still_csv(duration, workdir):
    path = os.path.join(workdir, f"still_{duration}.csv")
    n = int(round(duration / 0.01))
    with open(path, "w") as f:
        f.write("t,acc\n")
        for i in range(n + 2):
            f.write(f"{i * 0.01:.2f},{0.06 if i == n + 1 else 0.0}\n")
    return path, n * 0.01


def read_acc(path):
    data = np.genfromtxt(path, delimiter=",", names=True)
    t = data["t"]
    return data["acc"], float(t[1] - t[0])


def compare(stack, rf, rf_hist, sic, t_span, rf_spread=None):
    """Per body: θmax/θc and overturning of each engine, and the max over the
    compared span of |Δφ|/θc between each Siconos step and rockfrag and
    between Siconos's successive steps."""
    rows = []
    t_r = np.asarray(rf_hist["t"], dtype=float)
    for k in range(2):
        tc = stack.theta_c[k]
        body = rf["bodies"][k]
        phi_r = np.asarray(rf_hist[f"phi_{k + 1}"], dtype=float)
        entry = {
            "rf_theta": body["theta_max_over_theta_c"],
            "rf_over": body["overturned"],
            "sic_theta": [],
            "sic_over": [],
            "hist_vs_rf": [],
            "hist_vs_next": [],
        }
        # span both engines follow: until the first overturning in either
        end = t_span
        for times, phi, over, *_ in sic:
            for o in over:
                if o is not None:
                    end = min(end, o)
        for o in (rf["bodies"][0]["overturn_time"], rf["bodies"][1]["overturn_time"]):
            if o is not None:
                end = min(end, o)
        mask = (t_r <= end - 0.05) & np.isfinite(phi_r)
        interp = []
        for times, phi, over, *_ in sic:
            p = phi[:, k]
            ok = np.isfinite(p)
            entry["sic_theta"].append(float(np.nanmax(np.abs(p))) / tc if ok.any() else 0.0)
            entry["sic_over"].append(over[k] is not None)
            tt = np.concatenate([[0.0], times[ok]])
            pp = np.concatenate([[phi_r[0] if len(phi_r) else 0.0], p[ok]])
            interp.append(np.interp(t_r[mask], tt, pp))
        for i, s in enumerate(interp):
            diff = np.abs(s - phi_r[mask]) / tc
            entry["hist_vs_rf"].append(float(diff.max()) if diff.size else 0.0)
            if i + 1 < len(interp):
                d2 = np.abs(s - interp[i + 1]) / tc
                entry["hist_vs_next"].append(float(d2.max()) if d2.size else 0.0)
        entry["span"] = float(end)
        if rf_spread is not None:
            entry["rf_spread"] = rf_spread[k]
        rows.append(entry)
    # θmax/θc of a body that overturned is π/2/θc in rockfrag: compare it
    # only where neither engine says it overturned
    return rows


def fmt(x, nd=3):
    return f"{x:.{nd}f}"


def table_row(label, rows, warnings):
    """One markdown row: per body the θmax/θc of rockfrag, of Siconos at each
    step (OT: overturned), the history difference max |Δφ|/θc to rockfrag at
    each step, and Siconos's own between its two finest steps."""
    cells = [label]
    for r in rows:
        cells.append("OT" if r["rf_over"] else fmt(r["rf_theta"]))
        cells.append(" ".join("OT" if o else fmt(t) for t, o in zip(r["sic_theta"], r["sic_over"])))
        cells.append(" ".join(fmt(d) for d in r["hist_vs_rf"]))
        cells.append(fmt(r["hist_vs_next"][-1]))
        if "rf_spread" in r:
            cells.append(" ".join("OT" if o else fmt(t) for t, o in r["rf_spread"]))
    cells.append(str(warnings))
    return "| " + " | ".join(cells) + " |"


def header(steps, eps):
    s = ", ".join(f"{h:g}" for h in steps)
    print(f"Siconos steps h = {s} s (left to right); history: max over time of |Δφ|/θc, "
          "against rockfrag at each step, and Siconos's own between its two finest steps"
          + (f"; rockfrag × (1 ∓ {eps:g}): rockfrag on the record scaled by 1 − {eps:g} and "
             f"1 + {eps:g}" if eps else "") + "; OT: overturned.")
    print()
    head = "| analysis |"
    for body in ("base", "top"):
        head += (f" {body} θmax/θc rockfrag | {body} θmax/θc Siconos | {body} history vs "
                 f"rockfrag | {body} history, Siconos own |")
        if eps:
            head += f" {body} rockfrag × (1 ∓ {eps:g}) |"
    head += " Siconos: runs redone by NSGS; steps unconverged; steps gaining energy |"
    print(head)
    print("|" + "---|" * (12 if eps else 10))


def summary(results):
    """Counts over the analyses: overturning agreement at the finest step;
    θmax/θc differences against Siconos's own step error (the largest
    difference between its successive steps' answers, or 0.005); and, of
    the rest, those where rockfrag's own answer moves as much under the
    record scaled by 1 ∓ eps (the analysis is ill-conditioned)."""
    lines = []
    for k, body in enumerate(("base", "top")):
        agree = sum(r["bodies"][k]["rf_over"] == r["bodies"][k]["sic_over"][-1] for r in results)
        d_rf, d_own, within, sensitive, other = [], [], 0, 0, []
        for r in results:
            b = r["bodies"][k]
            if b["rf_over"] or b["sic_over"][-1]:
                continue
            a = abs(b["sic_theta"][-1] - b["rf_theta"])
            o = max(abs(x - y) for x, y in zip(b["sic_theta"][1:], b["sic_theta"][:-1]))
            d_rf.append(a)
            d_own.append(o)
            if a <= max(o, 0.005):
                within += 1
            elif "rf_spread" in b and (
                any(ov for _, ov in b["rf_spread"])
                or max(abs(t - b["rf_theta"]) for t, _ in b["rf_spread"]) >= 0.5 * a
            ):
                sensitive += 1
            else:
                other.append(r["analysis"])
        line = f"{body}: overturned alike (finest step) in {agree} of {len(results)}"
        if d_rf:
            line += (
                f"; θmax/θc where neither overturned ({len(d_rf)}): |Siconos − rockfrag| at the "
                f"finest step median {np.median(d_rf):.4f}, max {max(d_rf):.4f}; within Siconos's "
                f"own step error (its answers' largest change between successive steps, or "
                f"0.005) in {within}"
            )
            if sensitive:
                line += f", and where rockfrag's own answer moves by half as much or more "
                line += f"under the record × (1 ∓ eps) in {sensitive} more"
            if other:
                line += f"; not explained: {', '.join(other)}"
        lines.append(line)
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rockfrag", default=os.path.join(ROOT, "target", "release", "rockfrag"))
    ap.add_argument("--stack", default="0.6x1.0,0.3x1.2",
                    help="2B x 2H of base and top, m (statue-on-pedestal's)")
    ap.add_argument("--steps", default="5e-4,2.5e-4,1.25e-4,6.25e-5",
                    help="Siconos step sizes h of the records' analyses, s")
    ap.add_argument("--free-steps", default="2.5e-4,1.25e-4,6.25e-5,3.125e-5",
                    help="Siconos step sizes h of free rocking, s")
    ap.add_argument("--mu", type=float, default=100.0,
                    help="Siconos's μ standing for infinite friction")
    ap.add_argument("--seed", type=int, default=40)
    ap.add_argument("--records", type=int, default=10)
    ap.add_argument("--first-record", type=int, default=0,
                    help="index of the first record (run a part of the table)")
    ap.add_argument("--pgas", default="0.45,0.6", help="record intensities, g")
    ap.add_argument("--duration", type=float, default=12.0, help="record duration, s")
    ap.add_argument("--restitution", type=float, default=0.0, help="e of the records' analyses")
    ap.add_argument("--free-e", default="0,0.2", help="e of the free-rocking analyses")
    ap.add_argument("--quick", action="store_true", help="free rocking only")
    ap.add_argument("--skip-free", action="store_true", help="records only")
    ap.add_argument("--eps", type=float, default=1e-4,
                    help="rockfrag's sensitivity: the record scaled by 1 ∓ eps")
    ap.add_argument("--json", help="also write every number to this file")
    args = ap.parse_args()
    if not os.path.exists(args.rockfrag):
        sys.exit(f"siconos_stack.py: no rockfrag binary at {args.rockfrag}: cargo build --release")
    import_siconos()
    stack = Stack(args.stack)
    work = tempfile.mkdtemp(prefix="siconos_stack_")
    log = os.path.join(work, "siconos.log")
    print(f"stack {args.stack} (θc {stack.theta_c[0]:.4f}, {stack.theta_c[1]:.4f} rad), "
          f"μ = {args.mu:g} for infinite friction; work in {work}")
    groups = []
    if not args.skip_free:
        still, span = still_csv(4.0, work)
        free = []
        for e in [float(x) for x in args.free_e.split(",")]:
            for tilts in [(0.1, 0.0), (0.0, 0.15), (0.05, 0.1)]:
                free.append((f"free, tilts {tilts[0]:g},{tilts[1]:g}, e {e:g}", still, span, e,
                             tilts))
        groups.append(("Free rocking, 4 s", [float(s) for s in args.free_steps.split(",")], free,
                       None))
    if not args.quick:
        recs = []
        for pga in [float(x) for x in args.pgas.split(",")]:
            for i in range(args.first_record, args.first_record + args.records):
                rec = record_csv(args.rockfrag, args.seed, pga, i, args.duration, work)
                recs.append((f"record {i}, {pga:g} g", rec, args.duration, args.restitution,
                             None))
        last = args.first_record + args.records - 1
        groups.append((f"Records (rockfrag motion --seed {args.seed} --duration "
                       f"{args.duration:g}, indexes {args.first_record}–{last}), "
                       f"e {args.restitution:g}",
                       [float(s) for s in args.steps.split(",")], recs, args.eps))
    out = {"stack": args.stack, "mu": args.mu, "groups": []}
    n = 0
    for title, steps, analyses, eps in groups:
        print()
        print(f"{title}:")
        header(steps, eps)
        results = []
        for label, rec, span, e, tilts in analyses:
            n += 1
            acc, dt = read_acc(rec)
            rf, hist = rockfrag(args.rockfrag, stack, rec, e, work, f"a{n}", tilts)
            t0 = time.time()
            sic, redone = [], 0
            for h in steps:
                run = siconos_run(stack, acc, dt, span, h, e, args.mu, tilts or (0.0, 0.0), log)
                if run[4] or run[3]:
                    # Lemke's answer gained energy (or failed) at some step:
                    # solve again by NSGS at tolerance 1e-10
                    redo = siconos_run(stack, acc, dt, span, h, e, args.mu, tilts or (0.0, 0.0),
                                       log, solver="NSGS")
                    redone += 1
                    run = redo
                sic.append(run)
            rf_spread = spread(args.rockfrag, stack, rec, e, work, f"a{n}", eps) if eps else None
            rows = compare(stack, rf, hist, sic, span, rf_spread)
            warnings = f"{redone}; {sum(s[3] for s in sic)}; {sum(s[4] for s in sic)}"
            print(table_row(label, rows, warnings), flush=True)
            if rf.get("failure"):
                print(f"  (rockfrag did not finish: {rf['failure']})")
            results.append({"analysis": label, "rockfrag_failure": rf.get("failure"),
                            "siconos_seconds": time.time() - t0, "bodies": rows,
                            "redone_by_nsgs": redone,
                            "solver_failures": sum(s[3] for s in sic),
                            "energy_gaining_steps": sum(s[4] for s in sic)})
            if args.json:
                # written after every analysis: a long run stopped keeps its numbers
                with open(args.json, "w") as f:
                    json.dump({**out, "groups": out["groups"] + [
                        {"title": title, "steps": steps, "results": results}]}, f, indent=1)
        print()
        for line in summary(results):
            print(line)
        out["groups"].append({"title": title, "steps": steps, "results": results})
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
