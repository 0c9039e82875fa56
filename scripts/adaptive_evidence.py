#!/usr/bin/env python3
"""The numbers of docs/adaptive.md: analyses an adaptive run needs for a
±5 % band of the median against a fixed 12-level log grid over the same
range, and the coverage of the adaptive 90 % band over seeds.

    python3 scripts/adaptive_evidence.py [--rockfrag target/release/rockfrag]
        [--seeds 50] [--out /tmp/adaptive-evidence] [--svg docs/adaptive.svg]

Cases: the vase of studies/vase.toml at H/B 3, 4, 5 (overturning) and the
default study's H/B 4, e = 0, mu = inf case, all over PGA 0.05-3 g.

Fixed grid: 12 levels log-spaced over 0.05-3 g with 25, 50 and 100 records
(1000 bootstrap replicates), each band averaged over 5 ensembles (seeds
2024.. / 1991..); its need for +-5 % is
(c / 0.05)^2 with c fitted to half-width = c / sqrt(N) over the three record
counts (least squares on ln half-width + ln N / 2).

Adaptive: precision = { median = 0.05, beta = 0.25 }, seeds 1..S (the
ensemble, the draws and the bootstrap); the analyses are the mean over seeds.
Coverage: share of seeds whose 90 % band of the median holds the reference
median, a fixed-grid run with 12 levels x 600 records (7200 analyses, about
20x an adaptive run's) at seed 777777.
"""

import argparse
import csv
import math
import os
import re
import subprocess
import sys

RANGE = (0.05, 3.0)
# ensembles (seeds base, base + 1, ...) each fixed-grid band is averaged over
FIXED_SEEDS = 5
VASE_LEVELS = "[0.1, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5, 0.55, 0.6, 0.7, 0.8]"

VASE_HEAD = """
[uncertainty]
restitution = {{ dist = "uniform", min = 0.2, max = 0.6 }}
mu_s = {{ dist = "lognormal", median = 0.5, beta = 0.15 }}
mu_k_over_mu_s = {{ dist = "uniform", min = 0.75, max = 0.95 }}
"""

CASES = {
    # label: (top-level lines, grid lines, extra tables)
    "vase H/B 3": ("", "width = [0.2]\naspect = [3]", VASE_HEAD),
    "vase H/B 4": ("", "width = [0.2]\naspect = [4]", VASE_HEAD),
    "vase H/B 5": ("", "width = [0.2]\naspect = [5]", VASE_HEAD),
    "default H/B 4 e=0 mu=inf": (
        "",
        'width = [0.5]\naspect = [4]\nrestitution = [0.0]\nfriction = ["inf"]',
        '\n[motion]\npreset = "shenton-jones"\n\n[solver]\nmodel = "nonlinear"\nimpact = "newton"\n',
    ),
}


def grid12():
    lo, hi = RANGE
    return [lo * (hi / lo) ** (i / 11) for i in range(12)]


def spec(name, case, seed, pga, fragility, records=None):
    top, grid, extra = CASES[case]
    rec = f"records = {records}\n" if records else ""
    return (
        f'name = "{name}"\nseed = {seed}\n{rec}{top}\n[grid]\n{grid}\npga = {pga}\n'
        f"{extra.format()}\n[output]\nsummary = false\n\n[fragility]\n{fragility}\n"
    )


def run(exe, text, out, name):
    path = os.path.join(out, name + ".toml")
    with open(path, "w") as f:
        f.write(text)
    res = subprocess.run(
        [exe, "run", path, "--out", os.path.join(out, name), "--force"],
        capture_output=True,
        text=True,
    )
    if res.returncode != 0:
        sys.exit(f"{name}: {res.stderr}")
    return os.path.join(out, name), res.stderr


def fragility_row(folder):
    with open(os.path.join(folder, "fragility.csv")) as f:
        rows = [r for r in csv.DictReader(f) if r["limit_state"] == "overturning"]
    return rows[0]


def half(row):
    return (float(row["median_hi"]) - float(row["median_lo"])) / (2 * float(row["median"]))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rockfrag", default="target/release/rockfrag")
    ap.add_argument("--seeds", type=int, default=50)
    ap.add_argument("--out", default="/tmp/adaptive-evidence")
    ap.add_argument("--svg", default=None)
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument(
        "--fixed-seeds",
        type=int,
        default=FIXED_SEEDS,
        help="ensembles each fixed-grid band is averaged over",
    )
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    cases = a.cases.split(",")
    levels = "[" + ", ".join(f"{x:.6g}" for x in grid12()) + "]"
    rng = f"{{ min = {RANGE[0]}, max = {RANGE[1]} }}"
    table = []
    curves = {}
    for ci, case in enumerate(cases):
        base_seed = 1991 if case.startswith("default") else 2024
        # fixed grid at three record counts, five ensembles each
        fixed, unfit = [], {}
        for n in (25, 50, 100):
            hs = []
            for k in range(a.fixed_seeds):
                name = f"fixed{ci}-{n}-{k}"
                d, _ = run(
                    a.rockfrag,
                    spec(name, case, base_seed + k, levels, f"bootstrap = 1000\nseed = {k + 1}", n),
                    a.out,
                    name,
                )
                row = fragility_row(d)
                if row["median"] == "":
                    # a separated ensemble (no level where some but not all
                    # overturned) has no band: left out of the mean, counted
                    unfit[n] = unfit.get(n, 0) + 1
                    continue
                hs.append(half(row))
            fixed.append((12 * n, sum(hs) / len(hs)))
        # the vase's own hand-placed levels (studies/vase.toml), 50 records
        hand = None
        if case.startswith("vase"):
            hs = []
            for k in range(a.fixed_seeds):
                name = f"hand{ci}-{k}"
                d, _ = run(
                    a.rockfrag,
                    spec(name, case, base_seed + k, VASE_LEVELS, f"bootstrap = 1000\nseed = {k + 1}", 50),
                    a.out,
                    name,
                )
                hs.append(half(fragility_row(d)))
            h = sum(hs) / len(hs)
            hand = (h, 600 * (h / 0.05) ** 2)
        c = math.exp(sum(math.log(h) + 0.5 * math.log(N) for N, h in fixed) / len(fixed))
        need = (c / 0.05) ** 2
        # reference median
        d, _ = run(
            a.rockfrag,
            spec(f"ref{ci}", case, 777777, levels, "bootstrap = 1000", 600),
            a.out,
            f"ref{ci}",
        )
        ref = fragility_row(d)
        wide = float(ref["median"])
        # the local reference: 7200 analyses on the lattice levels within
        # +-30 % (in ln) of the wide reference's median, where the curve's
        # 50 % point is (a lognormal over 0.05-3 g is not the curve's shape)
        lattice = [RANGE[0] * (RANGE[1] / RANGE[0]) ** (i / 36) for i in range(37)]
        near = [x for x in lattice if abs(math.log(x / wide)) <= 0.3]
        d, _ = run(
            a.rockfrag,
            spec(
                f"local{ci}",
                case,
                777777,
                "[" + ", ".join(f"{x!r}" for x in near) + "]",
                "bootstrap = 1000",
                7200 // len(near),
            ),
            a.out,
            f"local{ci}",
        )
        local = fragility_row(d)
        theta = float(local["median"])
        # adaptive over seeds
        used, covered, covered_wide, halves, statuses = [], 0, 0, [], {}
        rounds = None
        for seed in range(1, a.seeds + 1):
            frag = (
                f"bootstrap = 1000\nseed = {seed}\n"
                "precision = { median = 0.05, beta = 0.25 }"
            )
            d, err = run(
                a.rockfrag, spec(f"ad{ci}-{seed}", case, seed, rng, frag), a.out, f"ad{ci}-{seed}"
            )
            with open(os.path.join(d, "adaptive.csv")) as f:
                row = next(csv.DictReader(f))
            statuses[row["status"]] = statuses.get(row["status"], 0) + 1
            used.append(int(row["analyses"]))
            halves.append(float(row["median_half_width"]))
            lo, hi = float(row["median_lo"]), float(row["median_hi"])
            covered += lo <= theta <= hi
            covered_wide += lo <= wide <= hi
            if rounds is None:
                rounds = [
                    (int(m.group(1)), float(m.group(2)) / 100)
                    for m in re.finditer(r"(\d+) analyses; overturning median \S+ g ±([\d.]+) %", err)
                ]
        mean = sum(used) / len(used)
        table.append(
            (
                case,
                fixed,
                need,
                mean,
                min(used),
                max(used),
                covered,
                len(used),
                theta,
                half(local),
                sum(halves) / len(halves),
                statuses,
                covered_wide,
                wide,
                half(ref),
                hand,
            )
        )
        curves[case] = (fixed, c, rounds)
        print(f"done {case}; fixed-grid ensembles that could not be fitted: {unfit}", file=sys.stderr)
    print(
        "| case | fixed 12-level grid: ± at 300 / 600 / 1200 analyses | fixed need for ±5 % | "
        "adaptive analyses, mean [min–max] | ratio | adaptive ± (mean) | coverage: local "
        "reference θ (±) | coverage: wide 12-level reference θ (±) |"
    )
    print("|---|---|---:|---:|---:|---:|---|---|")
    for case, fixed, need, mean, lo, hi, cov, n, theta, rh, mh, st, covw, wide, wh, hand in table:
        f = " / ".join(f"{100 * h:.1f} %" for _, h in fixed)
        print(
            f"| {case} | {f} | {need:.0f} | {mean:.0f} [{lo}–{hi}] | {mean / need:.2f} | "
            f"{100 * mh:.1f} % | {cov}/{n} = {100 * cov / n:.0f} %: {theta:.4f} g "
            f"(±{100 * rh:.1f} %) | {covw}/{n} = {100 * covw / n:.0f} %: {wide:.4f} g "
            f"(±{100 * wh:.1f} %) |"
        )
    print("statuses:", {t[0]: t[11] for t in table})
    for t in table:
        if t[15]:
            h, need = t[15]
            print(
                f"{t[0]}: the vase's hand-placed 12 levels x 50 records: ±{100 * h:.1f} % with 600 "
                f"analyses, about {need:.0f} for ±5 %"
            )
    if a.svg:
        write_svg(a.svg, curves)


def write_svg(path, curves):
    """Median band half-width against analyses (log-log): the fixed grid's
    three runs and its 1/sqrt(N) line, and one adaptive run's rounds (seed 1)."""
    W, H, L, B, T, R = 640, 420, 70, 50, 20, 170
    x0, x1, y0, y1 = math.log(20), math.log(5000), math.log(0.02), math.log(0.5)
    X = lambda n: L + (math.log(n) - x0) / (x1 - x0) * (W - L - R)
    Y = lambda h: H - B - (math.log(h) - y0) / (y1 - y0) * (H - B - T)
    colours = ["#1b9e77", "#d95f02", "#7570b3", "#e7298a"]
    s = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" '
        'font-family="sans-serif" font-size="12">',
        f'<rect width="{W}" height="{H}" fill="white"/>',
    ]
    for n in (20, 50, 100, 200, 500, 1000, 2000, 5000):
        s.append(f'<line x1="{X(n):.1f}" y1="{T}" x2="{X(n):.1f}" y2="{H - B}" stroke="#eee"/>')
        s.append(f'<text x="{X(n):.1f}" y="{H - B + 16}" text-anchor="middle">{n}</text>')
    for h in (0.02, 0.05, 0.1, 0.2, 0.5):
        s.append(f'<line x1="{L}" y1="{Y(h):.1f}" x2="{W - R}" y2="{Y(h):.1f}" stroke="#eee"/>')
        s.append(f'<text x="{L - 6}" y="{Y(h) + 4:.1f}" text-anchor="end">±{100 * h:g} %</text>')
    s.append(
        f'<line x1="{L}" y1="{Y(0.05):.1f}" x2="{W - R}" y2="{Y(0.05):.1f}" stroke="black" '
        'stroke-dasharray="4 3"/>'
    )
    s.append(f'<text x="{(L + W - R) / 2}" y="{H - 12}" text-anchor="middle">analyses per case</text>')
    s.append(
        f'<text transform="translate(16,{(H - B + T) / 2}) rotate(-90)" text-anchor="middle">'
        "half-width of the median's 90 % band</text>"
    )
    for i, (case, (fixed, c, rounds)) in enumerate(curves.items()):
        col = colours[i % 4]
        s.append(
            f'<line x1="{X(200):.1f}" y1="{Y(c / math.sqrt(200)):.1f}" x2="{X(5000):.1f}" '
            f'y2="{Y(c / math.sqrt(5000)):.1f}" stroke="{col}" stroke-dasharray="6 3"/>'
        )
        for n, h in fixed:
            s.append(f'<rect x="{X(n) - 4:.1f}" y="{Y(h) - 4:.1f}" width="8" height="8" fill="{col}"/>')
        pts = [(n, h) for n, h in rounds if 20 <= n <= 5000 and 0.02 <= h <= 0.5]
        if pts:
            s.append(
                f'<polyline fill="none" stroke="{col}" stroke-width="2" points="'
                + " ".join(f"{X(n):.1f},{Y(h):.1f}" for n, h in pts)
                + '"/>'
            )
            for n, h in pts:
                s.append(f'<circle cx="{X(n):.1f}" cy="{Y(h):.1f}" r="3" fill="{col}"/>')
        s.append(f'<text x="{W - R + 10}" y="{T + 20 + 18 * i}" fill="{col}">{case}</text>')
    k = T + 20 + 18 * len(curves) + 10
    s.append(f'<text x="{W - R + 10}" y="{k}">■ fixed 12-level grid</text>')
    s.append(f'<text x="{W - R + 10}" y="{k + 16}">- - its 1/√N line</text>')
    s.append(f'<text x="{W - R + 10}" y="{k + 32}">●─ adaptive rounds</text>')
    s.append(f'<text x="{W - R + 10}" y="{k + 48}">   (seed 1)</text>')
    s.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(s) + "\n")


if __name__ == "__main__":
    main()
