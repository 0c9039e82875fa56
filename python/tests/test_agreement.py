"""The Python functions give the CLI's results on the same input, bit for bit."""

import csv

import numpy as np
import pytest

import rockfrag
from records import read_csv_text, same_bits

# (seed, pga in g, index): five records; the first and fourth overturn the
# default block, the others rock (44 to 171 impacts).
RECORDS = [(5, 0.9, 1), (1, 0.5, 1), (2, 0.8, 0), (3, 1.2, 2), (7, 0.4, 3)]


@pytest.mark.parametrize("seed,pga,index", RECORDS[:3])
def test_motion_is_the_cli_record_bit_for_bit(cli, seed, pga, index):
    want = read_csv_text(cli("motion", "--seed", seed, "--pga", pga, "--index", index).stdout)
    got = rockfrag.motion(seed, pga, index)
    for k in ("t", "acc", "vel", "disp"):
        assert same_bits(got[k], want[k]), k
    assert got["dt"] == 0.02
    assert np.max(np.abs(got["acc"])) == pga * 9.81


def test_motion_settings_are_the_cli_flags(cli):
    flags = ["--dt", 0.01, "--duration", 12, "--highpass", 0.1]
    want = read_csv_text(cli("motion", "--seed", 5, "--pga", 0.3, *flags).stdout)
    got = rockfrag.motion(5, 0.3, dt=0.01, duration=12, highpass=0.1)
    for k in ("t", "acc", "vel", "disp"):
        assert same_bits(got[k], want[k]), k


@pytest.mark.parametrize("seed,pga,index", RECORDS)
def test_simulate_is_the_cli_outcome(cli, seed, pga, index):
    want = cli.json("simulate", "--seed", seed, "--pga", pga, "--index", index)
    m = rockfrag.motion(seed, pga, index)
    got = rockfrag.simulate(m["acc"], m["dt"], vel=m["vel"], disp=m["disp"])
    assert got == want
    assert abs(got["theta_max_over_theta_c"] - want["theta_max_over_theta_c"]) <= 1e-12


@pytest.mark.parametrize("seed,pga,index", RECORDS)
def test_sensitivity_is_the_cli_sensitivity(cli, seed, pga, index):
    want = cli.json("simulate", "--seed", seed, "--pga", pga, "--index", index, "--sensitivity")
    got = rockfrag.simulate(**_args(seed, pga, index), sensitivity=True)
    assert got == want and set(got["sensitivity"]) == {
        "sensitive", "overturned", "theta_max_over_theta_c", "overturn_time"
    }
    plain = rockfrag.simulate(**_args(seed, pga, index))
    assert "sensitivity" not in plain and plain == {k: v for k, v in got.items() if k != "sensitivity"}
    many = rockfrag.simulate_many([rockfrag.motion(seed, pga, index)], sensitivity=True)
    assert many == [got]


def test_the_five_records_overturn_and_survive(cli):
    seen = {rockfrag.simulate(**_args(*r))["overturned"] for r in RECORDS}
    assert seen == {True, False}


def _args(seed, pga, index):
    m = rockfrag.motion(seed, pga, index)
    return dict(acc=m["acc"], dt=m["dt"], vel=m["vel"], disp=m["disp"])


@pytest.mark.parametrize(
    "py,flags",
    [
        (dict(width=1.0, aspect=6.0, restitution=0.6), ["--width", 1, "--aspect", 6, "--restitution", 0.6]),
        (dict(mu_s=0.5, mu_k=0.4), ["--mu-s", 0.5, "--mu-k", 0.4]),
        (dict(model="linear"), ["--model", "linear"]),
        (dict(integrator="dopri5", rtol=1e-9), ["--integrator", "dopri5", "--rtol", 1e-9]),
        (dict(restitution=0.8, impact="energetic", rock_impact="rock"),
         ["--restitution", 0.8, "--impact", "energetic", "--rock-impact", "rock"]),
        (dict(theta0=0.05, theta_dot0=-0.1, audit_energy=True, follow_cascades=True),
         ["--theta0", 0.05, "--theta-dot0", -0.1, "--audit-energy", "--follow-cascades"]),
    ],
)
def test_keywords_are_the_cli_flags(cli, tmp_path, py, flags):
    m = rockfrag.motion(2, 0.6, 0)
    path = tmp_path / "m.csv"
    path.write_text(cli("motion", "--seed", 2, "--pga", 0.6).stdout)
    want = cli.json("simulate", "--motion", path, *flags)
    assert rockfrag.simulate(m["acc"], m["dt"], vel=m["vel"], disp=m["disp"], **py) == want


def test_acc_alone_is_the_cli_on_a_t_acc_file(cli, tmp_path):
    m = rockfrag.motion(3, 0.9, 1)
    path = tmp_path / "two.csv"
    path.write_text("t,acc\n" + "".join("%r,%r\n" % (float(t), float(a)) for t, a in zip(m["t"], m["acc"])))
    want = cli.json("simulate", "--motion", path)
    assert rockfrag.simulate(m["acc"], 0.02) == want


def test_history_is_the_cli_history(cli, tmp_path):
    hist = tmp_path / "h.csv"
    cli("simulate", "--seed", 1, "--pga", 0.5, "--index", 1, "--history", hist)
    rows = list(csv.reader(hist.open()))
    m = rockfrag.motion(1, 0.5, 1)
    got = rockfrag.simulate(m["acc"], m["dt"], vel=m["vel"], disp=m["disp"], history=True)["history"]
    assert len(got["t"]) == len(rows) - 1
    for j, k in enumerate(rows[0]):
        want = [r[j] for r in rows[1:]]
        if k == "mode":
            assert list(got["mode"]) == want
        else:
            assert same_bits(got[k], [float(x) for x in want]), k


def test_simulate_many_is_simulate_on_each(cli):
    records = [rockfrag.motion(*r) for r in RECORDS]
    one = [rockfrag.simulate(r["acc"], r["dt"], vel=r["vel"], disp=r["disp"]) for r in records]
    assert rockfrag.simulate_many(records) == one
    assert rockfrag.simulate_many(records, threads=1) == one
    # arrays with dt: velocity and displacement integrated from acc
    plain = [rockfrag.simulate(r["acc"], 0.02, restitution=0.5) for r in records]
    assert rockfrag.simulate_many([r["acc"] for r in records], 0.02, restitution=0.5) == plain


def test_the_solver_releases_the_gil():
    """Python keeps running while a worker thread is inside simulate_many."""
    import threading
    import time

    records = [rockfrag.motion(*RECORDS[k % 5]) for k in range(1000)]
    span = {}

    def work():
        span["start"] = time.perf_counter()
        rockfrag.simulate_many(records, threads=1)
        span["end"] = time.perf_counter()

    worker = threading.Thread(target=work)
    ticks = []
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    inside = [t for t in ticks if span["start"] < t < span["end"]]
    # Held, the GIL would stop this loop for the whole call.
    assert len(inside) >= 5, (len(inside), span["end"] - span["start"])
