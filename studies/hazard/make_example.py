"""Writes hazard_curve-mean-PGA_example.csv: an ILLUSTRATIVE hazard curve in
OpenQuake's hazard-curve CSV layout (engine 3.x export), for three made-up
sites. It is not the result of a hazard calculation for any real place.

Each site's annual rate of exceeding PGA a (g) is the smooth, monotone form

    lambda(a) = nu * (1 + a/a0)**(-k) * exp(-a/a1)

(nu: rate of events with any shaking; a power law of slope k above a0 that
steepens beyond a1, as hazard curves do). Site 0 is set to a high-seismicity
level: about 1/500 per year at 0.4 g and 1/5,000 per year at 1 g. The
probability of exceedance in the investigation time T is 1 - exp(-lambda*T),
written as OpenQuake writes it (%.6E; levels as poe-%.7f; lon, lat, depth %.5f).

    python3 studies/hazard/make_example.py > studies/hazard/hazard_curve-mean-PGA_example.csv
"""
import math
import sys

T = 50.0
# (lon, lat), (nu per year, a0 g, k, a1 g)
SITES = [
    ((15.0, 40.0), (0.6, 0.03, 2.0, 1.0)),
    ((15.25, 40.0), (0.3, 0.03, 2.2, 0.8)),
    ((15.5, 40.0), (0.15, 0.02, 2.4, 0.6)),
]
N = 25
IMLS = [0.005 * (5.0 / 0.005) ** (i / (N - 1)) for i in range(N)]


def rate(a, nu, a0, k, a1):
    return nu * (1.0 + a / a0) ** (-k) * math.exp(-a / a1)


lines = [
    "#" + "," * (2 + N)
    + "\"generated_by='rockfrag studies/hazard/make_example.py (illustrative, not an "
    "OpenQuake run)', kind='mean', investigation_time=%.1f, imt='PGA'\"" % T,
    "lon,lat,depth," + ",".join("poe-%.7f" % x for x in IMLS),
]
for (lon, lat), p in SITES:
    poe = [-math.expm1(-rate(a, *p) * T) for a in IMLS]
    lines.append("%.5f,%.5f,%.5f," % (lon, lat, 0.0) + ",".join("%.6E" % q for q in poe))
sys.stdout.write("\n".join(lines) + "\n")
