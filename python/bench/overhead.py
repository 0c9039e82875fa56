"""Cost of `rockfrag.simulate` from Python against the same analyses inside a
`run` study (one thread each).

The study: 100 records × 4 PGA levels × H/B 2, 4, 6 (1200 analyses, infinite
friction, e = 0). From Python: the same 300 analyses, each record synthesised
by `rockfrag.motion` beforehand (outside the timing, as a notebook holding its
records would), then `simulate` once per analysis; and the same with each
record synthesised inside the timing (once per record and level, as the study
does). The study's time includes
its own record synthesis and writing outcomes.csv; the comparison is per
analysis. Prints min and median over repeats.

    python python/bench/overhead.py [repeats]
"""

import statistics
import sys
import tempfile
import time

import rockfrag

REPEATS = int(sys.argv[1]) if len(sys.argv) > 1 else 7
PGAS = [0.3, 0.6, 0.9, 1.2]
ASPECTS = [2.0, 4.0, 6.0]
RECORDS = 100
SEED = 42
SPEC = {
    "name": "overhead",
    "seed": SEED,
    "records": RECORDS,
    "grid": {"width": [0.5], "aspect": ASPECTS, "restitution": [0.0], "pga": PGAS},
    "output": {"summary": False},
}
N = RECORDS * len(PGAS) * len(ASPECTS)

records = {(p, i): rockfrag.motion(SEED, p, i) for p in PGAS for i in range(RECORDS)}


def python_once():
    t0 = time.perf_counter()
    for (p, i), m in records.items():
        for a in ASPECTS:
            rockfrag.simulate(m["acc"], m["dt"], vel=m["vel"], disp=m["disp"], aspect=a)
    return (time.perf_counter() - t0) / N


def python_with_synthesis_once():
    t0 = time.perf_counter()
    for p in PGAS:
        for i in range(RECORDS):
            m = rockfrag.motion(SEED, p, i)
            for a in ASPECTS:
                rockfrag.simulate(m["acc"], m["dt"], vel=m["vel"], disp=m["disp"], aspect=a)
    return (time.perf_counter() - t0) / N


def study_once():
    with tempfile.TemporaryDirectory() as d:
        t0 = time.perf_counter()
        rockfrag.run(SPEC, out=d + "/s", threads=1)
        return (time.perf_counter() - t0) / N


st, py, pys = [], [], []
for _ in range(REPEATS):
    st.append(study_once())
    py.append(python_once())
    pys.append(python_with_synthesis_once())
rows = (
    ("study (run, 1 thread)", st),
    ("simulate", py),
    ("motion + simulate", pys),
)
for name, xs in rows:
    print(
        "%-22s per analysis: min %6.1f µs, median %6.1f µs; vs study: min %+5.1f %%, median %+5.1f %%"
        % (
            name,
            1e6 * min(xs),
            1e6 * statistics.median(xs),
            100 * (min(xs) / min(st) - 1),
            100 * (statistics.median(xs) / statistics.median(st) - 1),
        )
    )
