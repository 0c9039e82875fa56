"""rockfrag from Python: Monte Carlo fragility of free-standing rigid blocks.

The functions run the same Rust code as the ``rockfrag`` command line tool, so
a result here equals the CLI's on the same input, bit for bit. Units are SI
(m, s, m/s², rad) except where a docstring says g.

    >>> import rockfrag
    >>> m = rockfrag.motion(seed=1, pga=0.4)            # record 0 at 0.4 g
    >>> o = rockfrag.simulate(m["acc"], m["dt"], width=0.5, aspect=4)
    >>> o["overturned"], o["theta_max_over_theta_c"]

Functions: :func:`motion`, :func:`floor`, :func:`simulate`, :func:`simulate_many`,
:func:`run`, :func:`fragility`, :func:`risk`, :func:`read_outcomes`, :func:`fit`,
:func:`infer`. Bad input raises
``ValueError`` with the CLI's message; files that cannot be read or written
raise ``OSError``; a solver failure raises ``RuntimeError``.
"""

import difflib as _difflib
import json as _json
import math as _math
import operator as _operator
import os as _os
import warnings as _warnings

import numpy as _np

from . import _rockfrag

__version__ = _rockfrag.__version__
__all__ = [
    "motion", "floor", "rotate", "rotd", "simulate", "simulate_many", "simulate_stack", "run", "fragility", "risk", "read_outcomes",
    "fit", "infer", "FitWarning",
]


class FitWarning(UserWarning):
    """A fragility curve that could not be fitted (the message says which and
    what to try: stripes nearer the threshold, more records)."""

#: Standard gravity used to convert accelerations given in g (m/s²).
G_STANDARD = 9.81

_RTOL, _SETTLE_TOL = _rockfrag.solver_defaults()


def motion(seed, pga, index=0, *, dt=None, duration=None, highpass=None):
    """Synthetic ground motion: record ``index`` of ensemble ``seed``.

    The record ``rockfrag motion --seed SEED --pga PGA --index INDEX`` writes
    (same bits): a Clough–Penzien spectrum, modulated and high-passed, scaled
    so that its peak |acc| is exactly ``pga``.

    Parameters
    ----------
    seed : int
        Ensemble seed; record ``index`` of ensemble ``seed`` is always the
        same record.
    pga : float
        Peak ground acceleration, in g (converted with g = 9.81 m/s²).
    index : int
        Index of the record within the ensemble (default 0).
    dt : float, optional
        Sample interval, s (default 0.02); 1/(0.05·dt) must be an integer.
    duration : float, optional
        Record duration, s (default 30).
    highpass : float, optional
        High-pass corner frequency, Hz (default 0.07); 0 disables the filter.

    Returns
    -------
    dict
        ``t`` (s), ``acc`` (m/s²), ``vel`` (m/s), ``disp`` (m): numpy arrays,
        sample k at t = k·dt; ``dt`` (s) and ``name`` (``seed/index``).
    """
    return _rockfrag.motion(_whole(seed, "seed"), float(pga), _whole(index, "index"), dt, duration, highpass)


def _whole(x, what):
    """A seed or index as the extension takes it: a whole number ≥ 0 (an
    int or a numpy integer); 1.5 or 1.0 is refused, not truncated."""
    try:
        n = _operator.index(x)
    except TypeError:
        raise ValueError(
            "invalid %s = %r: expected a whole number ≥ 0 (an int)" % (what, x)
        ) from None
    if n < 0:
        raise ValueError("invalid %s = %d: expected a whole number ≥ 0" % (what, n))
    return n


def _component(record, what):
    """A component of a pair as the extension takes it: a record dict (as
    :func:`motion` and :func:`floor` return, or with ``acc`` and ``dt`` and
    optional ``vel``, ``disp``, ``name``)."""
    try:
        acc, dt = record["acc"], record["dt"]
    except (TypeError, KeyError, IndexError):
        raise TypeError(
            "%s: expected a record dict with 'acc' (m/s²) and 'dt' (s), as motion() "
            "and floor() return, got %r" % (what, type(record).__name__)
        ) from None
    vel, disp = record.get("vel"), record.get("disp")
    return (
        str(record.get("name", what)),
        float(dt),
        _f64(acc, what + "['acc']"),
        None if vel is None else _f64(vel, what + "['vel']"),
        None if disp is None else _f64(disp, what + "['disp']"),
    )


def rotate(h1, h2, orientation):
    """The ground motion along a direction, from two horizontal components.

    A block whose rocking plane makes the angle φ = ``orientation`` (degrees,
    from H1 towards H2) with the first component feels cos φ·H1 + sin φ·H2
    (acceleration, velocity and displacement alike): ``rockfrag simulate
    --motion H1 --motion2 H2 --orientation φ`` and a study of record pairs
    turn a pair this way (same bits). φ = 0 and 90 give H1 and H2 exactly.
    See docs/orientation.md.

    Parameters
    ----------
    h1, h2 : dict
        The two components as record dicts (``acc`` in m/s², ``dt`` in s,
        optional ``vel``, ``disp``, ``name``), as :func:`motion` and
        :func:`floor` return; same ``dt`` and length.
    orientation : float
        φ in degrees.

    Returns
    -------
    dict
        ``t``, ``acc``, ``vel``, ``disp``, ``dt``, ``name``: pass ``acc``,
        ``vel`` and ``disp`` to :func:`simulate`.
    """
    return _rockfrag.rotate(_component(h1, "h1"), _component(h2, "h2"), float(orientation))


def rotd(h1, h2, percentile=50.0, *, velocity=False):
    """RotDnn of a pair of horizontal components (Boore 2010).

    The ``percentile`` over the directions 0°, 1°, …, 179° of the peak of
    the rotated acceleration (m/s²), or of the rotated velocity (m/s) with
    ``velocity=True``: RotD50 (the default) is the orientation-independent
    intensity ground-motion models and OpenQuake's hazard give, RotD100 the
    largest peak over directions. A study of record pairs scales each pair
    to its levels by this RotD50.

    Parameters
    ----------
    h1, h2 : dict
        The two components as record dicts (see :func:`rotate`).
    percentile : float
        In [0, 100] (default 50).
    velocity : bool
        Of the velocity instead of the acceleration.

    Returns
    -------
    float
        m/s² (divide by 9.81 for g), or m/s.
    """
    return _rockfrag.rotd(
        _component(h1, "h1"), _component(h2, "h2"), float(percentile), bool(velocity)
    )


def floor(acc, dt, period, damping, participation=1.0, *, vel=None, disp=None, name="record"):
    """The absolute motion of a floor of a linear building under a ground record.

    ``rockfrag floor RECORD --period T --damping Z --participation G`` (same
    bits): each mode is a linear oscillator (T, ζ) driven by the ground,
    solved by the exact recurrence for acceleration linear between samples
    (Nigam and Jennings 1969), and the floor moves with the ground plus
    Σ Γφ·(the mode's relative motion). Same time step and length as the
    record. See docs/floor.md.

    Parameters
    ----------
    acc : array_like
        Ground acceleration, m/s², sample k at t = k·dt.
    dt : float
        Sample interval, s.
    period, damping, participation : float or sequence of float
        The building's modes at the floor: natural period T (s), damping
        ratio ζ in [0, 1) and participation Γφ (the participation factor
        times the mode shape at the floor; default 1). One value per mode;
        a single value of ``damping`` or ``participation`` applies to every
        mode.
    vel, disp : array_like, optional
        Ground velocity (m/s) and displacement (m), both or neither; by
        default integrated from rest by the linear-acceleration rule.
    name : str
        Name of the record in error messages.

    Returns
    -------
    dict
        ``t`` (s), ``acc`` (m/s²), ``vel`` (m/s), ``disp`` (m): the floor's
        absolute motion, ``dt`` and ``name``; pass ``acc``, ``vel`` and
        ``disp`` to :func:`simulate` for a block standing on that floor.
    """
    periods = _np.atleast_1d(_np.asarray(period, dtype=float))
    n = len(periods)

    def per_mode(x, what):
        v = _np.atleast_1d(_np.asarray(x, dtype=float))
        if len(v) == 1:
            return _np.repeat(v, n)
        if len(v) != n:
            raise ValueError(
                "%d %s values for %d periods: give one per mode, or one for all"
                % (len(v), what, n)
            )
        return v

    zeta = per_mode(damping, "damping")
    gamma = per_mode(participation, "participation")
    modes = [(float(t), float(z), float(g)) for t, z, g in zip(periods, zeta, gamma)]
    return _rockfrag.floor(
        _f64(acc, "acc"),
        float(dt),
        None if vel is None else _f64(vel, "vel"),
        None if disp is None else _f64(disp, "disp"),
        str(name),
        modes,
    )


def _setup(width, aspect, restitution, mu_s, mu_k, solver, named):
    """The solver setup; ``named`` lists the caller's own keywords, for the
    message of a misspelt one."""
    solver = dict(solver)
    args = dict(
        theta0=0.0,
        theta_dot0=0.0,
        rtol=None,
        settle_tol=None,
        follow_cascades=False,
        model="nonlinear",
        integrator="taylor",
        impact="newton",
        rock_impact="bounce",
        g=G_STANDARD,
        audit_energy=False,
    )
    unknown = sorted(set(solver) - set(args))
    if unknown:
        known = list(named) + sorted(args)
        hints = []
        for u in unknown:
            close = _difflib.get_close_matches(u, known, n=1)
            hints.append("%s (did you mean %s?)" % (u, close[0]) if close else u)
        raise TypeError(
            "unknown keyword(s) %s: expected one of %s, or the solver's %s"
            % (", ".join(hints), ", ".join(named), ", ".join(sorted(args)))
        )
    args.update(solver)
    return _rockfrag.Setup(
        float(width),
        float(aspect),
        float(restitution),
        None if mu_s is None else float(mu_s),
        None if mu_k is None else float(mu_k),
        float(args["theta0"]),
        float(args["theta_dot0"]),
        None if args["rtol"] is None else float(args["rtol"]),
        None if args["settle_tol"] is None else float(args["settle_tol"]),
        bool(args["follow_cascades"]),
        str(args["model"]),
        str(args["integrator"]),
        str(args["impact"]),
        str(args["rock_impact"]),
        float(args["g"]),
        bool(args["audit_energy"]),
    )


def _spec(spec):
    """A study as the extension takes it: (path, None) for a spec file,
    (None, JSON) for a dict of the spec's fields, (None, None) for the
    built-in paper study. numpy arrays and scalars in the dict are taken as
    lists and numbers; a NaN or infinite number is refused naming its key."""
    if isinstance(spec, dict):
        return None, _json.dumps(_plain(spec, "spec"), allow_nan=False)
    return (None if spec is None else _os.fspath(spec)), None


def _plain(value, where):
    """`value` (a spec dict or part of it) with numpy arrays and scalars
    made lists and Python numbers; `where` names it in errors
    (``spec['grid']['pga'][2]``)."""
    if isinstance(value, dict):
        return {k: _plain(v, "%s[%r]" % (where, k)) for k, v in value.items()}
    if isinstance(value, _np.ndarray):
        value = value.tolist()
    elif isinstance(value, _np.generic):
        value = value.item()
    if isinstance(value, (list, tuple)):
        return [_plain(v, "%s[%d]" % (where, i)) for i, v in enumerate(value)]
    if isinstance(value, float) and not _math.isfinite(value):
        raise ValueError(
            "invalid %s = %r: expected a finite number (a spec has no NaN or infinite values; "
            "leave the field out for its default)" % (where, value)
        )
    return value


def _threads(threads):
    """Worker threads as the extension takes them: 0 for one per core."""
    if threads is None:
        return 0
    if int(threads) < 1:
        raise ValueError("invalid threads = %s: expected a whole number of threads ≥ 1" % threads)
    return int(threads)


def _f64(x, what):
    if x is None:
        return None
    a = _np.ascontiguousarray(x, dtype=_np.float64)
    if a.ndim != 1:
        raise ValueError("%s must be one-dimensional, not of shape %s" % (what, a.shape))
    return a


def simulate(
    acc,
    dt,
    *,
    width=0.5,
    aspect=4.0,
    restitution=0.0,
    mu_s=None,
    mu_k=None,
    vel=None,
    disp=None,
    history=False,
    sensitivity=False,
    name="record",
    **solver,
):
    """One block under one ground-motion record: ``rockfrag simulate --json``.

    Parameters
    ----------
    acc : array_like
        Horizontal ground acceleration, m/s², sample k at t = k·dt (linear
        between samples).
    dt : float
        Sample interval, s.
    width : float
        Base width 2B of the block, m (default 0.5).
    aspect : float
        Aspect ratio H/B (default 4).
    restitution : float
        Coefficient of restitution e in [0, 1] (default 0).
    mu_s, mu_k : float, optional
        Static and kinetic friction coefficients; giving ``mu_s`` selects
        Coulomb friction (``mu_k`` defaults to ``mu_s``); without it contacts
        never slip (the CLI's ``--friction inf``).
    vel, disp : array_like, optional
        Ground velocity (m/s) and displacement (m), both or neither; by
        default integrated from rest by the linear-acceleration rule.
    history : bool
        Also return the time history under key ``history``: arrays ``t`` (s),
        ``mode`` (after each instant), ``theta`` (rad), ``theta_dot``
        (rad/s), ``x``, ``y`` (m, of the centre of mass relative to the
        ground), ``x_dot``, ``y_dot`` (m/s), ``N``, ``F`` (normal and
        horizontal reactions per unit mass, m/s²): the columns of the CLI's
        ``--history`` CSV; ``event`` marks event rows (bool).
    sensitivity : bool
        Also solve the run under the record scaled by 1 + 1e-9 (one more
        solve: twice the time) and return under key ``sensitivity`` what
        ``simulate --sensitivity --json`` gives: ``sensitive`` (overturning
        flipped, θmax/θc moved by more than 1e-3, or the overturning time by
        more than 0.01 s: a run decided by a hair), and the perturbed run's
        ``overturned``, ``theta_max_over_theta_c`` and ``overturn_time``.
    name : str
        Name of the record in error messages.
    **solver
        The CLI's solver flags: ``theta0`` (rad, default 0), ``theta_dot0``
        (rad/s, default 0), ``rtol`` (default %(rtol)g), ``settle_tol``
        (default %(settle)g), ``follow_cascades`` (False), ``model``
        ("nonlinear" | "linear"), ``integrator`` ("taylor" | "dopri5"),
        ``impact`` ("newton" | "energetic"), ``rock_impact`` ("bounce" |
        "rock"), ``g`` (m/s², 9.81), ``audit_energy`` (False).

    Returns
    -------
    dict
        The keys of ``simulate --json``: ``overturned``, ``overturn_time``
        (s or None), ``theta_max_over_theta_c``, ``mu_motion``,
        ``mu_impact``, ``impacts``, ``time_in_mode`` (s, by mode), ``stats``…
    """
    setup = _setup(width, aspect, restitution, mu_s, mu_k, solver, _SIMULATE_KEYWORDS)
    return _rockfrag.simulate_one(
        setup,
        _f64(acc, "acc"),
        float(dt),
        _f64(vel, "vel"),
        _f64(disp, "disp"),
        str(name),
        bool(history),
        bool(sensitivity),
    )


simulate.__doc__ = simulate.__doc__ % {"rtol": _RTOL, "settle": _SETTLE_TOL}

def simulate_stack(
    acc,
    dt,
    blocks,
    *,
    masses=None,
    offsets=None,
    restitution=0.0,
    friction=None,
    tilts=None,
    name="record",
    rtol=None,
    g=G_STANDARD,
):
    """A stack of one to three blocks under one record: ``rockfrag simulate
    --stack … --json`` (docs/stack.md).

    Parameters
    ----------
    acc, dt
        Ground acceleration (m/s²) and its sample interval (s), as for
        :func:`simulate`.
    blocks : list of (width, height)
        Each body's 2B and 2H in m, bottom first (e.g. a pedestal and its
        statue ``[(0.6, 1.0), (0.3, 1.2)]``).
    masses, offsets : list of float, optional
        Per body: mass (default: the same density, mass ∝ width × height) and
        horizontal offset (m) of its centre from the centre of the body below.
    restitution : float or list of float
        e of the interface under each body (the ground's first); one number
        for all.
    friction : None or list
        Per interface: ``None`` or ``"inf"`` (no slip), a number μ, or a
        pair ``(mu_s, mu_k)``; ``None`` for the whole list: no interface slips.
    tilts : list of float, optional
        Initial rotation of each body relative to the one below (rad).
    rtol : float, optional
        Relative tolerance of the integrator (default: the solver's).

    Returns
    -------
    dict
        ``bodies`` (per body ``theta_max_over_theta_c``, ``overturned``, …),
        ``first_overturned`` and ``failure``. A ``failure`` (the motion left
        the modes the stack solver models) is also raised as a
        ``RuntimeWarning``: the numbers then cover only the motion before it.
    """
    n = len(blocks)
    bodies = []
    for i, b in enumerate(blocks):
        try:
            w, h = b
            bodies.append((float(w), float(h)))
        except (TypeError, ValueError):
            raise ValueError(f"blocks[{i}] = {b!r}: expected (width, height) in m") from None
    e = [float(restitution)] * n if _np.isscalar(restitution) else [float(x) for x in restitution]

    def one(i, f):
        if f is None or (isinstance(f, str) and f.lower() == "inf"):
            return None
        if _np.isscalar(f):
            return (float(f), float(f))
        try:
            s, k = f
            return (float(s), float(k))
        except (TypeError, ValueError):
            raise ValueError(f"friction[{i}] = {f!r}: expected None, 'inf', mu or (mu_s, mu_k)") from None

    mu = [None] * n if friction is None else [one(i, f) for i, f in enumerate(friction)]
    floats = lambda v: None if v is None else [float(x) for x in v]
    out = _rockfrag.simulate_stack(
        bodies,
        floats(masses),
        floats(offsets),
        e,
        mu,
        floats(tilts),
        _f64(acc, "acc"),
        float(dt),
        str(name),
        _RTOL if rtol is None else float(rtol),
        float(g),
    )
    if out.get("failure"):
        _warnings.warn(
            f"the stack's analysis did not finish: {out['failure']}; its numbers cover only the motion before",
            RuntimeWarning,
            stacklevel=2,
        )
    return out


_SIMULATE_KEYWORDS = (
    "width", "aspect", "restitution", "mu_s", "mu_k", "vel", "disp", "history", "sensitivity", "name",
)
_SIMULATE_MANY_KEYWORDS = (
    "width", "aspect", "restitution", "mu_s", "mu_k", "threads", "sensitivity",
)


def simulate_many(
    records,
    dt=None,
    *,
    width=0.5,
    aspect=4.0,
    restitution=0.0,
    mu_s=None,
    mu_k=None,
    threads=None,
    sensitivity=False,
    **solver,
):
    """One block under each of many records, in parallel (rayon, GIL released).

    Parameters
    ----------
    records : iterable
        Each a 1-D array of ground acceleration (m/s², with ``dt``), or a dict
        with ``acc`` and ``dt`` and optionally ``vel``, ``disp`` and ``name``
        (what :func:`motion` returns).
    dt : float, optional
        Sample interval (s) of records given as arrays.
    threads : int, optional
        Worker threads (default: one per core). Results do not depend on it.
    width, aspect, restitution, mu_s, mu_k, sensitivity, **solver
        As for :func:`simulate`.

    Returns
    -------
    list of dict
        The outcome of each record, in order, as :func:`simulate` gives it.
    """
    setup = _setup(width, aspect, restitution, mu_s, mu_k, solver, _SIMULATE_MANY_KEYWORDS)
    items = []
    for i, r in enumerate(records):
        if isinstance(r, dict):
            rdt = r.get("dt", dt)
            if rdt is None:
                raise ValueError("record %d has no dt: give it in the dict or as dt=" % i)
            items.append(
                (
                    _f64(r["acc"], "acc"),
                    float(rdt),
                    _f64(r.get("vel"), "vel"),
                    _f64(r.get("disp"), "disp"),
                    str(r.get("name", i)),
                )
            )
        else:
            if dt is None:
                raise ValueError("records given as arrays need dt=")
            items.append((_f64(r, "acc"), float(dt), None, None, str(i)))
    return _rockfrag.simulate_many(
        setup, items, _threads(threads), bool(sensitivity)
    )


def run(spec=None, out=None, threads=None):
    """Runs a study, as ``rockfrag run`` does, and returns its output folder.

    Parameters
    ----------
    spec : str, os.PathLike or dict, optional
        A study spec file (TOML), or a dict with the spec's fields (tables as
        nested dicts, e.g. ``{"name": "s", "seed": 1, "records": 10,
        "grid": {"aspect": [4], "pga": [0.3, 0.6]}}``); record files in a
        dict are relative to the working directory. Default: the paper's
        study, built in.
        ``"output": {"sensitivity": True}`` solves every analysis a second
        time under its record scaled by 1 + 1e-9 and adds the ``sensitive``
        column (see :func:`simulate`'s ``sensitivity``) and its share per
        case and stripe to ``summary.md``; it doubles the run time.
    out : str or os.PathLike, optional
        Output folder (default ``results/<study name>``). Rerunning into a
        folder holding an interrupted run of the same study resumes it.
    threads : int, optional
        Worker threads (default: one per core). Results do not depend on it.

    Returns
    -------
    str
        The output folder: ``outcomes.csv``, ``summary.md``,
        ``manifest.json`` and, when the spec asks, the fragility files and
        figures. Read the outcomes with :func:`read_outcomes`.
    """
    path, js = _spec(spec)
    folder, unfitted = _rockfrag.run(
        path, js, None if out is None else _os.fspath(out), _threads(threads)
    )
    for message in unfitted:
        _warnings.warn(message, FitWarning, stacklevel=2)
    return folder


def fragility(folder, *, out=None, **options):
    """Fits fragility curves to a finished study folder, as ``rockfrag
    fragility`` does, with limit states and the bootstrap.

    Parameters
    ----------
    folder : str or os.PathLike
        A finished run's folder (``outcomes.csv``, ``manifest.json``).
    out : str or os.PathLike, optional
        Folder for the fragility files (default ``folder``, whose
        ``summary.md`` then gets the new curves).
    **options
        The spec's ``[fragility]`` fields: ``im`` ("pga", "pgv", ...),
        ``bootstrap`` (replicates, 0 for none), ``unit`` ("record" |
        "analysis"), ``seed``, ``confidence``, ``grid_points`` and
        ``limit_state``, a list of dicts such as ``{"name": "rocking",
        "measure": "theta_max_over_theta_c", "exceeds": 0.2}`` (default: the
        study's own, else overturning). Parameters drawn per analysis are
        pooled as by the CLI.

        ``bootstrap`` defaults to the study's own ``[fragility] bootstrap``
        (1000 without one); a fit that replaces one of more replicates in
        the folder it writes to warns (``UserWarning``) that its bands are
        noisier.

    Returns
    -------
    dict of numpy.ndarray or list
        The columns of ``fragility.csv`` by name, as :func:`risk` returns
        ``risk.csv``'s (numbers as float arrays, NaN where empty; text as
        lists: ``case_id``, ``limit_state``, ``median``, ``beta``,
        ``median_lo``, ``median_hi``, ``status``, …), and ``path``, the
        file's path (``fragility_curves.csv``, ``fragility_bootstrap.csv``
        and ``fragility.xml`` are beside it). Each curve that could not be
        fitted raises a :class:`FitWarning` saying why and what to try.
    """
    known = {"im", "bootstrap", "unit", "seed", "confidence", "grid_points", "limit_state"}
    unknown = sorted(set(options) - known)
    if unknown:
        hints = []
        for u in unknown:
            close = _difflib.get_close_matches(u, sorted(known) + ["out"], n=1)
            hints.append("%s (did you mean %s?)" % (u, close[0]) if close else u)
        raise TypeError(
            "unknown keyword(s) %s: expected one of out, %s" % (", ".join(hints), ", ".join(sorted(known)))
        )
    csv, _text, unfitted, fewer = _rockfrag.fragility(
        _os.fspath(folder), _json.dumps(_plain(options, "options")), None if out is None else _os.fspath(out)
    )
    if fewer:
        _warnings.warn(fewer, UserWarning, stacklevel=2)
    for message in unfitted:
        _warnings.warn(message, FitWarning, stacklevel=2)
    return _table(csv)


def _table(path):
    """A CSV file rockfrag wrote, as a dict of its columns by name: numbers
    as float arrays (NaN where empty), text as lists; and ``path``."""
    import csv as _csv

    with open(path, newline="") as f:
        rows = list(_csv.reader(f))
    header, body = rows[0], rows[1:]
    table = {"path": str(path)}
    for i, name in enumerate(header):
        values = [r[i] for r in body]
        try:
            table[name] = _np.array([float(v) if v != "" else _np.nan for v in values])
        except ValueError:
            table[name] = values
    return table


def risk(folder, hazard, *, site=None, years=50.0, out=None):
    """The annual rate of each fitted curve at a site, as ``rockfrag risk``
    computes it: the fragility of ``folder`` integrated over a hazard curve.

    Parameters
    ----------
    folder : str or os.PathLike
        A folder holding ``fragility.csv`` (and ``fragility_bootstrap.csv``
        for the 90 % band), e.g. from :func:`fragility`.
    hazard : str or os.PathLike
        OpenQuake's hazard-curve CSV for the fit's IM, or a plain CSV
        ``iml,annual_rate`` (IML in the fit's unit).
    site : int, optional
        The 0-based data row of an OpenQuake file (default 0).
    years : float
        Exposure time for the probability 1 − exp(−λN) (default 50).
    out : str or os.PathLike, optional
        Folder for ``risk.csv``, ``risk_hazard.csv`` and ``figures/risk.svg``
        (default ``folder``, whose ``summary.md`` then gets its ``## Risk``
        section), as ``rockfrag risk --out`` writes them (one code path).

    Returns
    -------
    dict of numpy.ndarray or list
        The columns of ``risk.csv`` by name (numbers as float arrays, NaN
        where empty; text as lists), and ``path``, the file's path.
    """
    path = _rockfrag.risk(
        _os.fspath(folder),
        _os.fspath(hazard),
        None if site is None else _whole(site, "site"),
        float(years),
        None if out is None else _os.fspath(out),
    )
    return _table(path)


def _column(kind, values):
    """A column of ``outcomes.csv`` as rockfrag's reader types it (``kind``:
    flag, count, number or text; values as the file holds them)."""
    if kind == "flag":
        if all(v != "" for v in values):
            return _np.array([v == "true" for v in values], dtype=bool)
        return _np.array([None if v == "" else v == "true" for v in values], dtype=object)
    if kind == "count" and all(v != "" for v in values):
        return _np.array([int(v) for v in values], dtype=_np.int64)
    if kind in ("count", "number"):
        return _np.array([float(v) if v != "" else _np.nan for v in values], dtype=_np.float64)
    return _np.array(values, dtype=object)


def read_outcomes(folder, *, as_frame=True):
    """The outcomes of a study folder (its ``outcomes.csv``), one row per analysis.

    Parameters
    ----------
    folder : str or os.PathLike
        A study's output folder (what :func:`run` returns), or the path of an
        ``outcomes.csv``.
    as_frame : bool
        Return a pandas DataFrame (default; pandas is a dependency of the
        package), or with False a dict of numpy arrays.

    Returns
    -------
    pandas.DataFrame or dict
        The columns of ``outcomes.csv`` (``aspect``, ``width``, ``pga`` in g,
        ``overturned``, ``theta_max_over_theta_c``, …; docs/outputs.md
        describes each): booleans as bool, counts as int64, numbers as
        float64 (empty cells NaN), text as objects.
    """
    path = _os.fspath(folder)
    if _os.path.isdir(path):
        path = _os.path.join(path, "outcomes.csv")
    # The library's reader: the file is checked as every rockfrag stage
    # reads it (columns by name, typed values, errors naming the line).
    cols = {name: _column(kind, values) for name, kind, values in _rockfrag.read_outcomes(path)}
    if not as_frame:
        return cols
    try:
        import pandas as pd
    except ImportError:
        raise ImportError(
            "read_outcomes returns a pandas DataFrame and pandas is not installed (it is a "
            "dependency of rockfrag: `pip install pandas`), or pass as_frame=False for a dict "
            "of numpy arrays"
        ) from None
    return pd.DataFrame(cols)


def fit(im, overturned, trials=None):
    """Fits a lognormal fragility P(overturn | IM = x) = Φ(ln(x/θ)/β).

    Maximum likelihood (probit GLM, Baker 2015), the fit of ``rockfrag
    fragility``.

    Parameters
    ----------
    im : array_like
        Intensity of each analysis (or of each stripe, with ``trials``), in
        the IM's unit (e.g. PGA in g); finite and > 0.
    overturned : array_like
        Without ``trials``: whether each analysis overturned (bool). With
        ``trials``: how many analyses overturned at each intensity.
    trials : array_like, optional
        Analyses at each intensity.

    Returns
    -------
    dict
        ``status`` ("ok"; "extrapolated-above" or "extrapolated-below" when
        the fitted median lies above the strongest intensity or below the
        weakest, as in ``fragility.csv``; or why no lognormal can be fitted:
        "separated", "none-overturned", …, with ``message``), ``median`` θ (IM unit),
        ``beta`` β, their standard errors ``se_median``, ``se_beta``,
        ``se_ln_median``, the probit coefficients ``a``, ``b`` with ``cov``,
        ``loglik`` and ``iterations``. Numbers are NaN when not fitted,
        and a :class:`FitWarning` gives the message (which data, what to
        try), as for the curves of :func:`run` and :func:`fragility`.
    """
    im = _np.asarray(im, dtype=_np.float64).ravel()
    z = _np.asarray(overturned).ravel()
    if len(z) != len(im):
        raise ValueError(
            "im and overturned have different lengths (%d, %d)" % (len(im), len(z))
        )
    if trials is None:
        levels, inverse = _np.unique(im, return_inverse=True)
        n = _np.bincount(inverse, minlength=len(levels))
        k = _np.bincount(inverse, weights=z.astype(bool), minlength=len(levels))
        im, n, z = levels, n, k
    else:
        n = _np.asarray(trials).ravel()
        if len(n) != len(im):
            raise ValueError(
                "im and trials have different lengths (%d, %d)" % (len(im), len(n))
            )
        if (n < 0).any() or (z < 0).any():
            raise ValueError("trials and overturned must be counts ≥ 0")
    result = _rockfrag.fit(
        [float(x) for x in im], [int(x) for x in n], [int(x) for x in z]
    )
    if result["status"].startswith("extrapolated"):
        # fitted, but the median lies beyond the intensities given
        _warnings.warn(
            "fitted, but %s (%s)" % (result["message"], result["status"]), FitWarning, stacklevel=2
        )
    elif result["status"] != "ok":
        _warnings.warn(
            "not fitted (%s): %s" % (result["status"], result["message"]), FitWarning, stacklevel=2
        )
    return result


#: The survey's columns in the order :func:`infer` writes rows given in memory.
_SURVEY_COLUMNS = ("name", "width", "aspect", "count", "overturned", "restitution", "mu_s", "mu_k", "slid")


def _survey_cell(v, column, row):
    if v is None or (isinstance(v, float) and _np.isnan(v)):
        return ""
    if isinstance(v, float) and _np.isinf(v) and v > 0:
        return "inf"
    text = repr(v) if isinstance(v, float) else str(v)
    if any(c in text for c in ",\n\r"):
        raise ValueError(
            "observation row %d, column %s: %r holds a comma or a line break" % (row + 1, column, v)
        )
    return text


def _survey_csv(rows):
    """CSV text of a survey given as rows (dicts) or columns (a dict of
    sequences, or a pandas DataFrame)."""
    if hasattr(rows, "to_dict"):  # a pandas DataFrame
        rows = rows.to_dict("records")
    elif isinstance(rows, dict):
        columns = list(rows)
        n = {len(rows[c]) for c in columns}
        if len(n) > 1:
            raise ValueError("observation columns of different lengths: %s" % sorted(n))
        rows = [{c: rows[c][i] for c in columns} for i in range(n.pop() if n else 0)]
    rows = [dict(r) for r in rows]
    keys = {k for r in rows for k in r}
    # Known columns in the survey's order, then any others (which the
    # library refuses, naming them).
    header = [c for c in _SURVEY_COLUMNS if c in keys] + sorted(keys - set(_SURVEY_COLUMNS))
    lines = [",".join(header)]
    for i, r in enumerate(rows):
        lines.append(",".join(_survey_cell(r.get(c), c, i) for c in header))
    return "\n".join(lines) + "\n"


def infer(
    observations,
    study,
    *,
    out=None,
    prior="log-uniform",
    im=None,
    threads=None,
    figure=True,
):
    """The intensity a site felt, inferred from what overturned there: ``rockfrag infer``.

    Every kind of object in the survey is simulated on every record and
    intensity level of the study, its uncertain properties drawn for each
    analysis; the likelihood of the survey is the mean over records of the
    product over kinds (every object at the site felt the same motion). The
    naive product of each kind's fitted fragility curve is computed beside it.

    Parameters
    ----------
    observations : str, os.PathLike, list of dict, dict of sequences or DataFrame
        The survey: a CSV file ``name,width,aspect,count,overturned``
        (optional ``restitution,mu_s,mu_k,slid``), one row per kind of
        object, ``width`` the base width 2B (m) and ``aspect`` H/B; or its
        rows in memory (errors then name ``<observations>``, its first row on
        line 2; a missing or None optional value takes the spec's).
    study : str, os.PathLike or dict
        The study spec (file or dict of its fields, as for :func:`run`): the
        records or ground-motion model, the intensity levels, the solver, the
        ``[uncertainty]`` of the objects' properties and ``[infer]``'s draws.
    out : str or os.PathLike, optional
        Output folder (default ``results/<survey file stem>``, or
        ``results/observations`` for rows in memory). Rerunning into it
        reuses the simulations.
    prior : str
        ``"log-uniform"`` over the levels (default), or
        ``"hazard=FILE"`` / ``"hazard=FILE,site=K"``: the density of the IM
        given shaking above the lowest level from a hazard curve (OpenQuake
        CSV or ``iml,annual_rate``).
    im : str or sequence of two str, optional
        ``"pga"`` (g) or ``"pgv"`` (m/s); default the levels' IM. Two IMs
        (``["pga", "pgv"]`` or ``"pga,pgv"``) also give their joint
        posterior (``posterior_2d.csv``, ``inference.json``'s ``two_im``;
        the second IM's prior is the records' spread of IM2/IM1).
    threads : int, optional
        Worker threads (default: one per core). Results do not depend on it.
    figure : bool
        Draw ``figures/inference.svg`` (default True).

    Returns
    -------
    dict
        ``inference.json`` as the CLI writes it: ``joint`` and ``naive`` (or
        None) each with ``median``, ``p05``, ``p95``, ``mode`` and
        ``mc_error`` (the bootstrap's standard deviation of each), ``im``,
        ``im_unit``, ``analyses``, ``effective_records``, ``kinds`` (each
        kind's counts, draws and fitted fragility), …; ``posterior``: the
        columns of ``posterior.csv`` as numpy arrays (``im``, ``prior``,
        ``likelihood``, ``posterior``, ``cdf``, ``naive_likelihood``,
        ``naive_posterior``, ``naive_cdf``); with two IMs, ``two_im`` (both
        marginals, the correlation, the posterior of IM2/IM1 against its
        prior, ``report``) and ``posterior_2d`` (``iml1``, ``iml2``,
        ``density``, ``credible``); ``out`` the folder;
        ``analyses_run`` and ``resumed_levels`` (0 and all on a rerun).
    """
    obs_path = obs_csv = None
    if isinstance(observations, (str, _os.PathLike)):
        obs_path = _os.fspath(observations)
    else:
        obs_csv = _survey_csv(observations)
    path, js = _spec(study)
    got = _rockfrag.infer(
        obs_path,
        obs_csv,
        path,
        js,
        None if out is None else _os.fspath(out),
        str(prior),
        None if im is None else (
            str(im) if isinstance(im, str) else ",".join(str(i) for i in im)
        ),
        _threads(threads),
        bool(figure),
    )
    result = _json.loads(got.pop("inference_json"))
    result.update(got)
    return result
