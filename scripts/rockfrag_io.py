"""What the OpenQuake and pelicun prototypes read from a rockfrag results folder.

Standard library only (runs under any python3, the OpenQuake and pelicun venvs too):

- fragility.csv rows (one per case and limit state: median θ, dispersion β, status);
- risk.csv rows (rockfrag's annual rate of each case and limit state);
- the case id of a row (its `case_id` column: the NRML function id and the pelicun id);
- an OpenQuake hazard-curve CSV read as src/risk/hazard.rs reads it (the same levels dropped),
  and the log-log interpolant with the first and last segments' power laws extended, as
  src/risk/integrate.rs integrates it.
"""
import csv
import json
import math
import os
import re

# src/risk/hazard.rs MIN_RATE_PRECISION
MIN_RATE_PRECISION = 1e-3


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def fnv1a64(data):
    """FNV-1a, 64 bits, as src/io_util.rs computes it."""
    h = 0xCBF29CE484222325
    for b in data:
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def check_fit_set(study):
    """Refuses the fit of `study` unless its files are the one set its fragility_set.json
    records (src/fragility/set.rs): a fit interrupted while written, or a file changed or
    replaced since, raises ValueError saying to rerun `rockfrag fragility`. A folder without
    the set file (fitted by an older rockfrag) passes."""
    path = os.path.join(study, "fragility_set.json")
    if not os.path.exists(path):
        return
    with open(path) as f:
        fit = json.load(f)
    rerun = f"rerun `rockfrag fragility {study}` to write a whole set"
    if fit.get("status") != "complete":
        raise ValueError(f"{path}: the fit was interrupted while its files were written; {rerun}")
    for entry in fit.get("files", []):
        with open(os.path.join(study, entry["name"]), "rb") as f:
            data = f.read()
        if len(data) != entry["bytes"] or f"{fnv1a64(data):016x}" != entry["fnv1a64"]:
            raise ValueError(f"{path}: {entry['name']} is not the file this fit wrote; {rerun}")


def fragility_rows(study):
    """fragility.csv rows, in file order (the spec's order: cases, limit states by severity),
    once the fit's files are checked to be one set (check_fit_set)."""
    check_fit_set(study)
    return read_rows(os.path.join(study, "fragility.csv"))


def risk_rows(study):
    return read_rows(os.path.join(study, "risk.csv"))


# `status` of a fitted curve the exports carry: `ok`, or a median outside the stripes
# (the curve is extrapolated there, and flagged). `out-of-order` (a more severe limit state
# more likely than a milder one) is fitted too, but left out of fragility.xml and the exports.
EXPORTED = ("ok", "extrapolated-above", "extrapolated-below")


def fitted(row):
    """(θ, β) of a fragility.csv / risk.csv row as the exports carry it, or None when the row
    has no fit or is left out of them (status out-of-order)."""
    try:
        m, b = float(row["median"]), float(row["beta"])
    except (KeyError, ValueError):
        return None
    if row.get("status", "ok") not in EXPORTED or not (m > 0 and b > 0):
        return None
    return m, b


def case_key(row):
    """A case's key: its id where the file has one (a stack's six case columns are its top
    body's, the same as the top body alone on the ground), else its six case columns."""
    if row.get("case_id"):
        return (row["case_id"],)
    return tuple(row[k] for k in ("aspect", "width", "restitution", "friction", "mu_s", "mu_k"))


def _num(text):
    """A case parameter as src/fragility/nrml.rs writes it in an id: Rust's f64 Display,
    '.' -> 'p', '-' -> 'm', '+' -> 'P', a drawn (empty) parameter 'drawn'."""
    if text == "":
        t = "drawn"
    else:
        x = float(text)
        if math.isinf(x):
            t = "inf" if x > 0 else "-inf"
        elif x == int(x) and abs(x) < 1e16:
            t = str(int(x))
        else:
            t = repr(x)  # shortest round-trip, as Rust's Display
    out = []
    for c in t:
        if c == ".":
            out.append("p")
        elif c == "-":
            out.append("m")
        elif c == "+":
            out.append("P")
        elif c.isascii() and c.isalnum():
            out.append(c)
        else:
            out.append("_")
    return "".join(out)


def function_id(row):
    """The case id of a fragility.csv / risk.csv row: its `case_id` column, which is also the
    NRML fragilityFunction id, the exposure taxonomy and the pelicun component id."""
    return row["case_id"]


def cases(rows):
    """[(case_key, [rows in limit-state order])] in order of first appearance."""
    out = []
    index = {}
    for r in rows:
        k = case_key(r)
        if k not in index:
            index[k] = len(out)
            out.append((k, []))
        out[index[k]][1].append(r)
    return out


def limit_states(rows):
    seen = []
    for r in rows:
        if r["limit_state"] not in seen:
            seen.append(r["limit_state"])
    return seen


# ---------------------------------------------------------------- lognormal helpers

def phi(z):
    """Standard normal CDF."""
    return 0.5 * math.erfc(-z / math.sqrt(2.0))


def moments_to_lognormal(mean, stddev):
    """NRML (mean, stddev) of the intensity -> (θ, β) (nrml.rs moments_to_lognormal)."""
    cv2 = (stddev / mean) ** 2
    b2 = math.log1p(cv2)
    return mean * math.exp(-0.5 * b2), math.sqrt(b2)


def lognormal_to_moments(theta, beta):
    b2 = beta * beta
    mean = theta * math.exp(0.5 * b2)
    return mean, mean * math.sqrt(math.expm1(b2))


# ---------------------------------------------------------------- hazard

def _metadata(line, key):
    m = re.search(r"(?<![A-Za-z0-9_])%s\s*=\s*('([^']*)'|\"([^\"]*)\"|([^,\"'\s]+))" % key, line)
    if not m:
        return None
    return next(g for g in m.groups()[1:] if g is not None)


def _rate_precision(text, poe, lambda_t):
    mantissa = re.split("[eE]", text)[0]
    digits = len("".join(c for c in mantissa if c.isdigit()).lstrip("0")) or 1
    half_ulp = 0.5 * poe * 10.0 ** (1 - digits)
    return half_ulp / ((1.0 - poe) * lambda_t) if lambda_t > 0 else 0.0


class Hazard:
    """A hazard curve as rockfrag reads an OpenQuake CSV (src/risk/hazard.rs read_openquake):
    annual rates -ln(1-poe)/T, the low levels with poe = 1 or too close to 1 for the file's
    digits dropped, the zero rates at the top dropped."""

    def __init__(self, path, site=0):
        with open(path) as f:
            lines = [l.strip() for l in f if l.strip()]
        meta = lines[0]
        if not (meta.startswith("#") and "imt=" in meta):
            raise SystemExit("%s: not an OpenQuake hazard-curve CSV (no '# ... imt=' line)" % path)
        self.imt = _metadata(meta, "imt")
        self.investigation_time = float(_metadata(meta, "investigation_time"))
        names = [n.strip() for n in lines[1].split(",")]
        rows = [l for l in lines[2:] if not l.startswith("#")]
        if site >= len(rows):
            raise SystemExit("%s: --site %d but %d site rows" % (path, site, len(rows)))
        fields = [x.strip() for x in rows[site].split(",")]
        self.lon = float(fields[names.index("lon")])
        self.lat = float(fields[names.index("lat")])
        self.depth = float(fields[names.index("depth")]) if "depth" in names else 0.0
        pts, prec = [], []
        T = self.investigation_time
        for c, n in enumerate(names):
            if n.startswith("poe-"):
                x = float(n[4:])
                p = float(fields[c])
                lam = -math.log1p(-p) / T if p < 1 else math.inf
                prec.append(_rate_precision(fields[c], p, lam * T) if p < 1 else math.inf)
                pts.append((x, lam))
        self.all_levels = pts
        low = 0
        while low < len(prec) and (prec[low] > MIN_RATE_PRECISION or math.isnan(prec[low])):
            low += 1
        kept = pts[low:]
        positive = 0
        while positive < len(kept) and kept[positive][1] > 0:
            positive += 1
        self.dropped_low = low
        self.dropped_high = len(kept) - positive
        kept = kept[:positive]
        if len(kept) < 2:
            raise SystemExit("%s: fewer than 2 usable levels" % path)
        self.iml = [p[0] for p in kept]
        self.rate = [p[1] for p in kept]
        self.scale = {"PGA": 1.0, "PGV": 0.01}.get(self.imt, 1.0)  # to the fit's unit

    def rate_at(self, x):
        """λ(x) interpolated log-log, first and last segments extended (HazardCurve::rate_at).
        x in the hazard file's unit."""
        iml, rate = self.iml, self.rate
        n = len(iml)
        i = 0
        while i < n and iml[i] <= x:
            i += 1
        i = min(max(i, 1), n - 1) - 1
        u0, u1 = math.log(iml[i]), math.log(iml[i + 1])
        l0, l1 = math.log(rate[i]), math.log(rate[i + 1])
        return math.exp(l0 + (l1 - l0) * (math.log(x) - u0) / (u1 - u0))

    def last_slope(self):
        n = len(self.iml)
        return -(math.log(self.rate[n - 1]) - math.log(self.rate[n - 2])) / (
            math.log(self.iml[n - 1]) - math.log(self.iml[n - 2]))


def level_text(x, sig=7):
    """A level as OpenQuake writes a column name (poe-%.7f), with at least `sig` significant
    digits (more decimals for levels below 0.1)."""
    decimals = max(7, sig - int(math.floor(math.log10(x))) - 1)
    return "%.*f" % (decimals, x)
