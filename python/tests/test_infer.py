"""`rockfrag.infer` runs `rockfrag infer`: the same numbers from a file or from
rows in memory, bad surveys refused naming where."""

import json
import math

import numpy as np
import pytest

import rockfrag

# 2 kinds × 4 records × 5 levels × 6 draws = 240 analyses of 8-s records.
SPEC = {
    "name": "py-infer",
    "seed": 9,
    "records": 4,
    "motion": {"duration": 8.0},
    "grid": {"pga": [0.15, 0.25, 0.4, 0.65, 1.0]},
    "uncertainty": {
        "restitution": {"dist": "uniform", "min": 0.0, "max": 0.4},
        "mu_s": {"dist": "lognormal", "median": 0.6, "beta": 0.15, "min": 0.3, "max": 1.2},
        "mu_k_over_mu_s": {"dist": "uniform", "min": 0.75, "max": 0.95},
    },
    "infer": {"draws": 6, "seating": 0.3, "bootstrap": 20},
}

TOML = """
name = "py-infer"
seed = 9
records = 4

[motion]
duration = 8.0

[grid]
pga = [0.15, 0.25, 0.4, 0.65, 1.0]

[uncertainty]
restitution = { dist = "uniform", min = 0.0, max = 0.4 }
mu_s = { dist = "lognormal", median = 0.6, beta = 0.15, min = 0.3, max = 1.2 }
mu_k_over_mu_s = { dist = "uniform", min = 0.75, max = 0.95 }

[infer]
draws = 6
seating = 0.3
bootstrap = 20
"""

ROWS = [
    {"name": "slender", "width": 0.3, "aspect": 5, "count": 12, "overturned": 7},
    {"name": "squat", "width": 0.5, "aspect": 2.5, "count": 10, "overturned": 1},
]

SURVEY = "name,width,aspect,count,overturned\nslender,0.3,5,12,7\nsquat,0.5,2.5,10,1\n"


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("infer")
    (d / "spec.toml").write_text(TOML)
    (d / "survey.csv").write_text(SURVEY)
    return d


def test_infer_is_the_cli(cli, files):
    """From files: inference.json and posterior.csv byte-identical to the
    CLI's, and the dict returned holds the files' numbers exactly."""
    cli(
        "infer", "survey.csv", "--study", "spec.toml", "--out", "cli", "--threads", 1,
        cwd=files,
    )
    got = rockfrag.infer(
        files / "survey.csv", files / "spec.toml", out=files / "py", threads=2
    )
    for name in ("inference.json", "posterior.csv"):
        cli_bytes = (files / "cli" / name).read_bytes()
        py_bytes = (files / "py" / name).read_bytes()
        if name == "inference.json":
            # the file paths differ (relative for the CLI, absolute here)
            a, b = json.loads(cli_bytes), json.loads(py_bytes)
            for k in ("spec", "observations"):
                a.pop(k), b.pop(k)
            assert a == b
        else:
            assert cli_bytes == py_bytes
    want = json.loads((files / "py" / "inference.json").read_text())
    for key in ("joint", "naive", "analyses", "effective_records", "kinds"):
        assert got[key] == want[key]
    assert got["analyses"] == 2 * 4 * 5 * 6
    assert got["analyses_run"] == got["analyses"]
    post = got["posterior"]
    assert set(post) >= {"im", "prior", "likelihood", "posterior", "cdf", "naive_posterior"}
    # the posterior CDF ends at 1 (the trapezoidal normalisation, to rounding)
    assert abs(post["cdf"][-1] - 1.0) < 1e-12
    assert np.all(np.diff(post["im"]) > 0)
    j = got["joint"]
    assert 0.15 <= j["p05"] <= j["median"] <= j["p95"] <= 1.0
    assert (files / "py" / "figures" / "inference.svg").exists()


def test_rows_in_memory_and_a_dict_spec_give_the_same_numbers(files):
    """Rows as dicts, as columns, and a dict spec: the file's numbers, and a
    rerun into the same folder reuses every level."""
    want = json.loads((files / "py" / "inference.json").read_text())
    got = rockfrag.infer(ROWS, SPEC, out=files / "mem", figure=False)
    for key in ("joint", "naive", "kinds", "analyses"):
        assert got[key] == want[key]
    assert got["observations"] == "<observations>"
    columns = {k: [r[k] for r in ROWS] for k in ROWS[0]}
    again = rockfrag.infer(columns, SPEC, out=files / "mem", figure=False)
    assert again["joint"] == want["joint"]
    assert (again["analyses_run"], again["resumed_levels"]) == (0, 5)


def test_a_kind_of_its_own_friction_is_simulated_so(files):
    """An optional column given for one kind only: the other's cell is empty
    and takes the spec's distribution."""
    rows = [dict(ROWS[0], mu_s=math.inf), dict(ROWS[1])]
    got = rockfrag.infer(rows, SPEC, out=files / "own", figure=False, threads=1)
    assert [k["friction"] for k in got["kinds"]][0] == "inf"
    assert got["kinds"][1]["friction"] != "inf"


def test_bad_observations_name_the_row_and_column(files):
    bad = [dict(ROWS[0], overturned=13)]
    with pytest.raises(ValueError, match=r"<observations>:2:.*column 5 \(overturned\).*\"13\""):
        rockfrag.infer(bad, SPEC, out=files / "bad", figure=False)
    with pytest.raises(ValueError, match=r"colour.*not a survey column"):
        rockfrag.infer([dict(ROWS[0], colour="grey")], SPEC, out=files / "bad", figure=False)
    with pytest.raises(ValueError, match="expected log-uniform"):
        rockfrag.infer(ROWS, SPEC, out=files / "bad", prior="flat")
    with pytest.raises(OSError, match="nowhere.csv"):
        rockfrag.infer(files / "nowhere.csv", SPEC, out=files / "bad")


def test_two_ims_give_the_cli_joint_posterior(cli, files):
    """``im=["pga", "pgv"]`` is ``--im pga,pgv``: the same posterior_2d.csv
    bytes and ``two_im``; its marginal over PGA is the one-IM posterior to
    1e-9 of its peak (trapezoid rule over ln PGV); a repeated IM is refused
    naming the value."""
    cli(
        "infer", "survey.csv", "--study", "spec.toml", "--out", "cli2", "--im", "pga,pgv",
        cwd=files,
    )
    got = rockfrag.infer(
        files / "survey.csv", files / "spec.toml", out=files / "py2", im=["pga", "pgv"]
    )
    name = "posterior_2d.csv"
    assert (files / "cli2" / name).read_bytes() == (files / "py2" / name).read_bytes()
    two = got["two_im"]
    assert (two["im1"], two["im2"]) == ("pga", "pgv")
    assert two["im1_marginal"]["median"] == got["joint"]["median"]
    j = got["posterior_2d"]
    x, y, d = j["iml1"], j["iml2"], j["density"]
    ny = int(np.sum(x == x[0]))
    post = got["posterior"]
    for i in range(len(post["im"])):
        s = slice(i * ny, (i + 1) * ny)
        f = d[s] * x[s] * y[s]
        integral = np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(np.log(y[s])))
        want = post["posterior"][i] * post["im"][i]
        assert abs(integral - want) <= 1e-9 * np.max(post["posterior"] * post["im"])
    with pytest.raises(ValueError, match="pga,pga"):
        rockfrag.infer(files / "survey.csv", files / "spec.toml", out=files / "py3", im="pga,pga")
