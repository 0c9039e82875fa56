#!/usr/bin/env python3
"""Runs an OpenQuake classical_damage job written from a rockfrag study (`rockfrag export openquake`) and compares OpenQuake's annual rates with rockfrag's risk.csv.

    $OQ/bin/python scripts/check_openquake.py STUDY JOBDIR [--tolerance 0.01] [--emulate]

STUDY: a rockfrag results folder with risk.csv (`rockfrag risk STUDY --hazard FILE --site K`,
the same hazard file and site the job was written from). JOBDIR: job.ini, exposure.xml,
fragility.xml, hazard.csv.

The engine runs as `oq engine --run JOBDIR/job.ini -e csv -p export_dir=...` with
OQ_DISTRIBUTE=no and a private OQ_DATADIR (kept under JOBDIR/oq-run/). Its damages-rlz-000_*.csv
holds, per asset (number 1), the probability of being IN each damage state over
risk_investigation_time T_r; the exceedance of limit state k is the sum over the states at or
above k (never 1 - no_damage: float32) and the annual rate is -ln(1 - p)/T_r, which inverts
OpenQuake's own p = 1 - exp(-rate*T_r) exactly.

--emulate skips the engine: OpenQuake's own functions (openquake.risklib.scientific.classical_damage,
its NRML reader, hdf5.read_csv) on the job's files, with the engine's float32 steps. Seconds
instead of a run; Agrees with the engine
to the 7 digits of its CSV.

Exit status 0 when every case and limit state agrees within the tolerance, 1 otherwise.
"""
import argparse
import configparser
import glob
import math
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rockfrag_io as rio  # noqa: E402

NS = {"n": "http://openquake.org/xmlns/nrml/0.5"}


def read_job(jobdir):
    cp = configparser.ConfigParser()
    cp.read(os.path.join(jobdir, "job.ini"))
    flat = {}
    for s in cp.sections():
        flat.update(cp[s])
    return flat


def asset_taxonomies(jobdir, job):
    root = ET.parse(os.path.join(jobdir, job["exposure_file"])).getroot()
    return {a.get("id"): a.get("taxonomy") for a in root.iter("{%s}asset" % NS["n"])}


def run_engine(jobdir, oq_bin):
    """Runs the job; returns {asset_id: {state: probability}} and the CSV's header comment."""
    run = os.path.join(os.path.abspath(jobdir), "oq-run")
    out = os.path.join(run, "export")
    for f in glob.glob(os.path.join(out, "*")):
        os.remove(f)
    os.makedirs(out, exist_ok=True)
    env = dict(os.environ, OQ_DISTRIBUTE="no", OQ_DATADIR=os.path.join(run, "data"))
    cmd = [oq_bin, "engine", "--run", os.path.join(os.path.abspath(jobdir), "job.ini"),
           "-e", "csv", "-p", "export_dir=" + out]
    p = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    log = p.stdout
    with open(os.path.join(run, "engine.log"), "w") as f:
        f.write(log)
    warnings = [l for l in log.splitlines() if re.search(r"\b(WARNING|ERROR|CRITICAL)\]", l)
                and not re.search(r"running .*--hc|api\.openquake\.org|Disabled distribution"
                                  r"|Sent \d+ classical_damage tasks|Stored [\d.]+ [KMG]?B", l)]
    if p.returncode != 0:
        sys.stderr.write(log[-3000:])
        sys.exit("oq engine failed (exit %d); log in %s/engine.log" % (p.returncode, run))
    files = glob.glob(os.path.join(out, "damages-rlz-000_*.csv"))
    if len(files) != 1:
        sys.exit("expected one damages-rlz-000_*.csv in %s, found %s" % (out, files))
    return read_damages(files[0]), warnings


def read_damages(path):
    with open(path) as f:
        meta = f.readline()
        header = f.readline().strip().split(",")
        rows = [l.strip().split(",") for l in f if l.strip()]
    out = {}
    for r in rows:
        d = dict(zip(header, r))
        out[d["asset_id"]] = {k.split("-", 1)[1]: float(v) for k, v in d.items()
                              if k.startswith("contents-")}
    m = re.search(r"risk_investigation_time=([0-9.eE+-]+)", meta)
    return out, (float(m.group(1)) if m else None)


def emulate(jobdir, job):
    """OpenQuake's classical_damage on the job's files, in process."""
    import numpy
    try:  # the engine venv has fiona; oq_env.sh's reader-only venv does not: stub it there
        import fiona  # noqa: F401
    except ImportError:
        import types
        sys.modules["fiona"] = types.ModuleType("fiona")
        pk = types.ModuleType("openquake.hazardlib.geo.packager")
        pk.fiona = None
        sys.modules["openquake.hazardlib.geo.packager"] = pk
    from openquake.baselib import hdf5
    from openquake.hazardlib import nrml
    from openquake.risklib import read_nrml, scientific  # noqa: F401 (registers the converters)
    wrapper = hdf5.read_csv(os.path.join(jobdir, job["hazard_curves_csv"]),
                            dtypedict={None: numpy.float32})
    T_h = wrapper.investigation_time  # the CSV's header, not job.ini (get_pmap_from_csv)
    names = [n for n in wrapper.dtype.names if n.startswith("poe-")]
    imls = [float(n[4:]) for n in names]
    poe32 = numpy.array([wrapper.array[n][0] for n in names], numpy.float32)
    pne = (1.0 - poe32).astype(numpy.float32)          # MapArray.__invert__
    pne[pne == 0.0] = 1.11e-16                          # MapArray.to_rates
    rates = (-numpy.log(pne)).astype(numpy.float32)
    poes = 1.0 - numpy.exp(-rates.astype(numpy.float64))  # CurveGetter.get_hazard/to_probs
    T_r = float(job.get("risk_investigation_time", T_h))
    model = nrml.to_python(os.path.join(jobdir, job["contents_fragility_file"]))
    disc = int(job.get("continuous_fragility_discretization", 20))
    spi = int(job.get("steps_per_interval", 1))
    by_id = {}
    for (imt, fid), ffl in model.items():
        ffs = ffl.build(model.limitStates, disc, spi)
        d = scientific.classical_damage(ffs, imls, poes.copy(), T_h, T_r, spi)
        by_id[fid] = dict(zip(["no_damage"] + list(model.limitStates),
                              numpy.asarray(d, numpy.float32).astype(float)))
    tax = asset_taxonomies(jobdir, job)
    return {aid: by_id[t] for aid, t in tax.items()}, T_r


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("study")
    ap.add_argument("jobdir")
    ap.add_argument("--tolerance", type=float, default=0.01, help="relative (default 0.01)")
    ap.add_argument("--emulate", action="store_true", help="OpenQuake's functions, not the engine")
    ap.add_argument("--oq", default=os.path.join(os.path.dirname(sys.executable), "oq"),
                    help="the oq command (default: beside this python)")
    ap.add_argument("--quiet", action="store_true", help="only the final line")
    a = ap.parse_args(argv)

    job = read_job(a.jobdir)
    tax = asset_taxonomies(a.jobdir, job)
    warnings = []
    if a.emulate:
        (damages, T_r) = emulate(a.jobdir, job)
        source = "OpenQuake functions (emulated)"
    else:
        (damages, T_r), warnings = run_engine(a.jobdir, a.oq)
        source = "oq engine"
    if T_r is None:
        T_r = float(job.get("risk_investigation_time", job.get("investigation_time")))

    risk = rio.risk_rows(a.study)
    by_case = {}
    for r in risk:
        by_case.setdefault(rio.function_id(r), []).append(r)
    fails, lines, worst, observed = 0, [], 0.0, 0
    lines.append("%-48s %-12s %12s %12s %9s" % ("function (asset)", "limit state", "rockfrag/yr",
                                                "openquake/yr", "diff"))
    seen = set()
    for aid, fid in tax.items():
        states = damages[aid]
        ls_names = [s for s in states if s != "no_damage"]
        rows = {r["limit_state"]: r for r in by_case.get(fid, [])}
        for k, ls in enumerate(ls_names):
            p = sum(states[s] for s in ls_names[k:])
            rate = -math.log1p(-p) / T_r
            r = rows.get(ls)
            if r is not None and r.get("annual_rate", "") == "" and r.get("status", "ok") not in rio.EXPORTED:
                # A limit state rockfrag could not fit: the model carries its observed
                # fractions (a discrete function); there is no rockfrag rate to compare with.
                lines.append("%-48s %-12s %12s %12.5e %9s" % (
                    fid + " (" + aid + ")", ls, "-", rate, "observed (not fitted: %s)" % r["status"]))
                observed += 1
                continue
            if r is None or r.get("annual_rate", "") == "":
                lines.append("%-48s %-12s %12s %12.5e %9s" % (fid + " (" + aid + ")", ls, "-", rate, "no rate"))
                fails += 1
                continue
            ref = float(r["annual_rate"])
            diff = rate / ref - 1.0
            worst = max(worst, abs(diff))
            bad = abs(diff) > a.tolerance
            fails += bad
            seen.add((fid, ls))
            lines.append("%-48s %-12s %12.5e %12.5e %+8.3f%%%s" % (
                fid + " (" + aid + ")", ls, ref, rate, 100 * diff, "  FAIL" if bad else ""))
    missing = [(rio.function_id(r), r["limit_state"]) for r in risk
               if r.get("annual_rate", "") != "" and (rio.function_id(r), r["limit_state"]) not in seen]
    for fid, ls in missing:
        lines.append("%-48s %-12s rockfrag has a rate, the job has no asset" % (fid, ls))
    fails += len(missing)
    if not a.quiet:
        print("\n".join(lines))
        for w in warnings:
            print("engine: " + w)
    n = len(seen)
    verdict = "PASS" if fails == 0 else "FAIL"
    print("%s openquake: %d rates (%s, T_r = %g yr) within %.2g %% of rockfrag: worst %.3f %%, %d failing%s"
          % (verdict, n, source, T_r, 100 * a.tolerance, 100 * worst, fails,
             "; %d limit states observed, not fitted (no rockfrag rate)" % observed if observed else ""))
    return 0 if fails == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
