#!/usr/bin/env python3
"""Loads a pelicun damage database written from a rockfrag study (`rockfrag export pelicun`) into pelicun 3.10 *unmodified, from its file*, computes the
damage-state probabilities at fixed PGAs and compares P(DS >= k) with rockfrag's
Phi(ln(IM/theta_k)/beta_k) from the study's fragility.csv.

    $PELICUN/bin/python scripts/check_pelicun.py STUDY FOLDER [--samples 1000]
                        [--sampling LHS] [--tolerance 2e-3] [--pga 0.1,0.3,1]

One assessment per PGA: a demand sample (CSV, header `1-PGA-1-1`, a `Units` row `g`) of N
realizations all at that PGA, one block of every component at location 1 direction 1, the DB
loaded with damage.load_model_parameters([csv path], components). pelicun draws the limit-state
capacities of a component perfectly correlated (one uniform per realization, anchored to LS1)
with Latin hypercube sampling by default, so at a fixed demand the share of realizations in
DS >= k is within 1/N of Phi_k (when the curves do not cross): N = 1000 gives <= 1e-3, inside
the 2e-3 tolerance deterministically. With --sampling MonteCarlo the error is binomial,
sqrt(p(1-p)/N) <= 0.5/sqrt(N): N >= 1.3e6 for 2e-3 at 4.5 sigma.

Also checks that every case rockfrag fitted for all limit states (or for all before trailing
ones never exceeded at any stripe, which the export leaves blank) is a component, that no
other is, and that the DB's LS order and values are rockfrag's. Exit 0 on pass, 1 on fail.
"""
import argparse
import glob
import math
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rockfrag_io as rio  # noqa: E402

DEFAULT_PGA = "0.05,0.1,0.2,0.3,0.4,0.5,0.7,1,1.5,2,3"


def find_db(folder):
    csvs = sorted(glob.glob(os.path.join(folder, "*.csv")))
    if len(csvs) != 1:
        sys.exit("%s: expected one damage DB .csv, found %s" % (folder, csvs))
    js = csvs[0][:-4] + ".json"
    return csvs[0], (js if os.path.exists(js) else None)


def demand_edp(demand_type):
    """pelicun's EDP name for a DB's Demand-Type, as pelicun forms it
    (`Peak Ground Acceleration` -> `PGA`, `Peak Spectral Acceleration|1.00`
    -> `SA_1.00`): the demand sample's column must carry it."""
    from pelicun.base import EDP_to_demand_type
    name, _, sub = demand_type.partition("|")
    edp = EDP_to_demand_type[name]
    return "%s_%s" % (edp, sub) if sub else edp


def pelicun_probabilities(db, ids, pga, n, sampling, seed, tmp, edp="PGA", unit="g"):
    import pandas as pd
    from pelicun.assessment import Assessment
    demand = os.path.join(tmp, "demand.csv")
    # pelicun reads a floor demand (PFA, PFV) of a component at location k
    # at location k + DemandOffset (its default config: -1, the floor
    # below in its numbering): the sample carries it where pelicun looks
    a = Assessment({"PrintLog": False, "Seed": seed, "Sampling": {"SamplingMethod": sampling}})
    offset = a.options.demand_offset.get(edp, 0)
    with open(demand, "w") as f:
        f.write(",1-%s-%d-1\nUnits,%s\n" % (edp, 1 + offset, unit))
        f.write("".join("%d,%r\n" % (i, pga) for i in range(n)))
    a.demand.load_sample(demand)
    a.asset.load_cmp_model({"marginals": pd.DataFrame(
        {"Units": "ea", "Location": "1", "Direction": "1", "Theta_0": 1.0}, index=list(ids))})
    a.asset.generate_cmp_sample()
    a.damage.load_model_parameters([db], set(ids))
    a.damage.calculate()
    probs = a.damage.ds_model.probabilities().fillna(0.0)
    out = {}
    for key, row in probs.iterrows():
        out[key[0]] = {int(ds): float(p) for ds, p in row.items()}
    return out, list(a.damage.missing_components or [])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("study")
    ap.add_argument("folder")
    ap.add_argument("--samples", type=int, default=1000)
    ap.add_argument("--sampling", default="LHS", choices=["LHS", "LHS_midpoint", "MonteCarlo"])
    ap.add_argument("--tolerance", type=float, default=2e-3)
    ap.add_argument("--pga", default=DEFAULT_PGA)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)
    import pandas as pd

    db, js = find_db(a.folder)
    table = pd.read_csv(db)
    ids = list(table["ID"])
    fails, lines = 0, []

    # rockfrag's curves, by component
    rows = rio.fragility_rows(a.study)
    lss = rio.limit_states(rows)
    expect = {}
    for _, crow in rio.cases(rows):
        by = {r["limit_state"]: rio.fitted(r) for r in crow}
        status = {r["limit_state"]: r.get("status", "ok") for r in crow}
        fits = [by.get(ls) for ls in lss]
        if all(f is not None for f in fits):
            expect[rio.function_id(crow[0])] = fits
            continue
        # the export writes a case without its last limit states when none of
        # them was exceeded at any stripe (blank LS columns after the others)
        kept = next(k for k, f in enumerate(fits) if f is None)
        if kept > 0 and all(f is None and status.get(ls) == "none-overturned"
                            for f, ls in zip(fits[kept:], lss[kept:])):
            expect[rio.function_id(crow[0])] = fits[:kept]
    for cid in expect:
        if cid not in ids:
            lines.append("MISSING  %s: fitted by rockfrag, not in %s" % (cid, os.path.basename(db)))
            fails += 1
    for cid in ids:
        if cid not in expect:
            lines.append("EXTRA    %s: in the DB, not a fully fitted rockfrag case" % cid)
            fails += 1
    # the DB's numbers are rockfrag's (same LS order, same θ, β)
    for _, r in table.iterrows():
        if r["ID"] not in expect:
            continue
        for k, (t, b) in enumerate(expect[r["ID"]], 1):
            t_db, b_db = r.get("LS%d-Theta_0" % k), r.get("LS%d-Theta_1" % k)
            if not (abs(t_db / t - 1) < 1e-12 and abs(b_db / b - 1) < 1e-12):
                lines.append("VALUES   %s LS%d: DB %r, %r; rockfrag %r, %r" % (r["ID"], k, t_db, b_db, t, b))
                fails += 1
        if int(r["Demand-Directional"]) != 1:
            lines.append("DIRECTIONAL %s: Demand-Directional = %s multiplies the PGA by 1.2"
                         % (r["ID"], r["Demand-Directional"]))
            fails += 1
    if js is None:
        lines.append("note: no %s.json beside the CSV (pelicun 3.10 does not read it)" % os.path.basename(db)[:-4])

    pgas = [float(x) for x in a.pga.split(",")]
    # the demand the DB asks for (PGA, SA_1.00, PFA, ...), in its unit:
    # the values of --pga are taken in that unit
    edp = demand_edp(str(table["Demand-Type"].iloc[0]))
    unit = str(table["Demand-Unit"].iloc[0])
    worst = 0.0
    crossed = 0
    lines.append("%-40s %-5s %6s %9s %9s %9s" % ("component", "LS", "PGA g", "rockfrag", "pelicun", "diff"))
    for cid, fits in expect.items():
        # a partial component's blank limit states stay blank in the DB
        row = table[table["ID"] == cid]
        for k in range(len(fits) + 1, len(lss) + 1):
            if not row.empty and not pd.isna(row.iloc[0].get("LS%d-Theta_0" % k)):
                lines.append("VALUES   %s LS%d: the DB has a value rockfrag did not fit" % (cid, k))
                fails += 1
    with tempfile.TemporaryDirectory() as tmp:
        for x in pgas:
            probs, missing = pelicun_probabilities(db, [i for i in ids if i in expect], x,
                                                   a.samples, a.sampling, a.seed, tmp,
                                                   edp, unit)
            for cid in missing:
                lines.append("DROPPED  %s: pelicun left it out (Incomplete or no parameters)" % cid)
                fails += 1
            for cid, fits in expect.items():
                if cid not in probs:
                    continue
                ds = probs[cid]
                for k in range(1, len(fits) + 1):
                    got = sum(p for d, p in ds.items() if d >= k)
                    t, b = fits[k - 1]
                    want = rio.phi(math.log(x / t) / b)
                    # pelicun's anchored capacities: DS >= k iff some LS j >= k is exceeded
                    reach = max(rio.phi(math.log(x / tj) / bj) for tj, bj in fits[k - 1:])
                    if reach - want > a.tolerance:
                        crossed += 1
                    d = got - want
                    worst = max(worst, abs(d))
                    bad = abs(d) > a.tolerance
                    fails += bad
                    if bad or not a.quiet:
                        lines.append("%-40s LS%-3d %6.3g %9.6f %9.6f %+9.6f%s" % (
                            cid[:40], k, x, want, got, d, "  FAIL" if bad else ""))
    if crossed:
        lines.append("note: %d (component, LS, PGA) where a higher limit state's curve lies above "
                     "LSk's by more than the tolerance (crossing curves): pelicun then gives "
                     "P(DS>=k) = max_j>=k Phi_j" % crossed)
    if not a.quiet:
        print("\n".join(lines))
    else:
        keep = [l for l in lines if not l.startswith(("component", "note"))
                and ("FAIL" in l or l.split()[0].isupper())]
        if keep:
            print("\n".join(keep))
    verdict = "PASS" if fails == 0 else "FAIL"
    print("%s pelicun: %d components x %d limit states x %d PGAs, %s N = %d: worst |P(DS>=k) - Phi| = "
          "%.2e (tolerance %.1e), %d failing" % (verdict, len(expect), len(lss), len(pgas),
                                                   a.sampling, a.samples, worst, a.tolerance, fails))
    return 0 if fails == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
