#!/usr/bin/env python3
"""FEMA P-58's unanchored furniture beside rockfrag (issue 38, item 6).

FEMA P-58 gives the overturning of unanchored bookcases and file cabinets
as lognormal fragilities against peak floor velocity (PFV), beta = 0.5.
This runs each object as a block (2B = its depth, 2H = its height; e and
mu drawn as in studies/vase.toml) on the roof (participation 1.3, 5 %
damping) of buildings of three first-mode periods, under the default
firm-soil ground-motion model, fits the overturning against PFV, PFA and
the ground's Sa(T1) without solving again (`rockfrag fragility DIR --im`),
and prints rockfrag's medians and beta beside FEMA's (the table of
docs/floor.md, "FEMA P-58's furniture"). It also exports the T = 0.8 s
bookcases as a pelicun library (`rockfrag export pelicun`).

    python3 scripts/fema_furniture.py [--rockfrag target/release/rockfrag] [--out /tmp/fema]
"""

import argparse
import csv
import os
import subprocess
import sys

# (name, depth 2B m, height 2H m, FEMA median PFV m/s)
OBJECTS = [
    ("bookcase 0.737 m", 0.321, 0.737, 0.724),
    ("bookcase 1.041 m", 0.321, 1.041, 0.493),
    ("bookcase 1.422 m", 0.321, 1.422, 0.361),
    ("bookcase 1.803 m", 0.321, 1.803, 0.290),
    ("bookcase 2.064 m", 0.321, 2.064, 0.251),
    ("file cabinet 0.610 m", 0.381, 0.610, 1.229),
    ("file cabinet 1.321 m", 0.381, 1.321, 0.498),
    ("file cabinet 1.333 m", 0.472, 1.333, 0.688),
    ("file cabinet 1.721 m", 0.472, 1.721, 0.526),
]
PERIODS = [0.3, 0.8, 1.5]
LEVELS = "[0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0, 1.2, 1.5, 2.0]"

SPEC = """name = "fema-{tag}"
seed = 58
records = 40

[support]
floor = [{{ period = {period}, damping = 0.05, participation = 1.3 }}]

[grid]
width = [{width}]
aspect = [{aspects}]
pga = {levels}

[uncertainty]
restitution = {{ dist = "uniform", min = 0.2, max = 0.6 }}
mu_s = {{ dist = "lognormal", median = 0.5, beta = 0.15 }}
mu_k_over_mu_s = {{ dist = "uniform", min = 0.75, max = 0.95 }}

[output]
summary = false

[fragility]
bootstrap = 200
"""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rockfrag", default="target/release/rockfrag")
    ap.add_argument("--out", default="/tmp/fema")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    widths = sorted({o[1] for o in OBJECTS})
    fits = {}
    for period in PERIODS:
        for width in widths:
            objs = [o for o in OBJECTS if o[1] == width]
            tag = f"T{period}-w{width}"
            spec = os.path.join(a.out, tag + ".toml")
            aspects = ", ".join(repr(h / w) for _, w, h, _ in objs)
            with open(spec, "w") as f:
                f.write(SPEC.format(tag=tag, period=period, width=width, aspects=aspects, levels=LEVELS))
            d = os.path.join(a.out, tag)
            subprocess.run([a.rockfrag, "run", spec, "--out", d, "--force"], check=True, capture_output=True)
            for im in ["pfv", "pfa", f"sa({period})"]:
                o = os.path.join(d, "im-" + im.replace("(", "").replace(")", ""))
                subprocess.run(
                    [a.rockfrag, "fragility", d, "--im", im, "--out", o],
                    check=True,
                    capture_output=True,
                )
                with open(os.path.join(o, "fragility.csv")) as f:
                    for r in csv.DictReader(f):
                        if r["limit_state"] != "overturning":
                            continue
                        name = next(n for n, w, h, _ in objs if abs(float(r["aspect"]) - h / w) < 1e-9)
                        fits[(name, period, im.split("(")[0])] = r
    print("| object | FEMA P-58 PFV median (β 0.5) | " + " | ".join(
        f"T1 = {p} s: PFV median [90 %], β (β against PFA, Sa(T1))" for p in PERIODS) + " |")
    print("|---|---:|" + "---|" * len(PERIODS))
    for name, w, h, fema in OBJECTS:
        cells = []
        for p in PERIODS:
            r = fits.get((name, p, "pfv"))
            betas = ", ".join(f"{float(fits[(name, p, im)]['beta']):.2f}" for im in ["pfa", "sa"])
            if r["status"] != "ok":
                # e.g. extrapolated-above: too few overturned up to 2 g of ground PGA
                cells.append(f"{r['status']} ({r['n_exceeded']} of {r['n_analyses']} overturned)")
                continue
            cells.append(f"{float(r['median']):.3f} m/s [{float(r['median_lo']):.3f}, "
                         f"{float(r['median_hi']):.3f}], {float(r['beta']):.2f} ({betas})")
        print(f"| {name} (2B {w} m, H/B {h / w:.2f}) | {fema} m/s | " + " | ".join(cells) + " |")
    # ratio rockfrag / FEMA of the PFV medians
    for p in PERIODS:
        rs = [float(fits[(n, p, "pfv")]["median"]) / fema for n, _, _, fema in OBJECTS
              if fits[(n, p, "pfv")]["status"] == "ok"]
        if rs:
            print(f"T1 = {p} s: rockfrag's PFV median / FEMA's: {min(rs):.2f} to {max(rs):.2f}", file=sys.stderr)
    d = os.path.join(a.out, "T0.8-w0.321", "im-pfv")
    lib = os.path.join(a.out, "pelicun-bookcases")
    subprocess.run([a.rockfrag, "export", "pelicun", d, "--out", lib], check=True)
    print(f"pelicun library of the T1 = 0.8 s bookcases: {lib}", file=sys.stderr)


if __name__ == "__main__":
    main()
