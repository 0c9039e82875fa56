"""Studies from Python: `run`, `read_outcomes` and `fit` agree with the CLI and
with `simulate`; a notebook-sized ensemble end to end."""

import csv
import math

import numpy as np
import pytest

import rockfrag

SPEC = {
    "name": "py-small",
    "seed": 11,
    "records": 6,
    "motion": {"duration": 10.0},
    "grid": {"width": [0.5], "aspect": [4], "restitution": [0.0], "pga": [0.2, 0.5, 0.8, 1.1]},
    "fragility": {"im": "pga", "bootstrap": 20},
}

TOML = """
name = "py-small"
seed = 11
records = 6

[motion]
duration = 10.0

[grid]
width = [0.5]
aspect = [4]
restitution = [0.0]
pga = [0.2, 0.5, 0.8, 1.1]

[fragility]
im = "pga"
bootstrap = 20
"""


@pytest.fixture(scope="module")
def dict_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("dict") / "study"
    return rockfrag.run(SPEC, out=out, threads=2)


def test_a_dict_spec_is_the_cli_study_file(cli, tmp_path, dict_run):
    spec = tmp_path / "small.toml"
    spec.write_text(TOML)
    cli("run", spec, "--out", tmp_path / "cli", "--threads", 1)
    want = (tmp_path / "cli" / "outcomes.csv").read_text()
    assert (tmp_path / "cli" / "fragility.csv").read_text() == open(dict_run + "/fragility.csv").read()
    assert open(dict_run + "/outcomes.csv").read() == want
    # a file spec from Python too
    out = rockfrag.run(spec, out=tmp_path / "py-file")
    assert open(out + "/outcomes.csv").read() == want


def test_read_outcomes_types(dict_run):
    cols = rockfrag.read_outcomes(dict_run, as_frame=False)
    assert cols["overturned"].dtype == bool
    assert cols["record"].dtype == np.int64
    assert cols["theta_max_over_theta_c"].dtype == np.float64
    assert len(cols["pga"]) == 6 * 4
    assert np.isnan(cols["overturn_time"][~cols["overturned"]]).all()


def test_read_outcomes_frame(dict_run):
    pd = pytest.importorskip("pandas")
    df = rockfrag.read_outcomes(dict_run)
    assert isinstance(df, pd.DataFrame) and len(df) == 24


def test_a_study_row_is_simulate_on_its_record(dict_run):
    cols = rockfrag.read_outcomes(dict_run, as_frame=False)
    for i in range(len(cols["pga"])):
        m = rockfrag.motion(11, cols["pga"][i], int(cols["record"][i]), duration=10.0)
        o = rockfrag.simulate(m["acc"], m["dt"], vel=m["vel"], disp=m["disp"])
        assert o["overturned"] == cols["overturned"][i]
        assert abs(o["theta_max_over_theta_c"] - cols["theta_max_over_theta_c"][i]) <= 1e-12


def test_sensitivity_adds_a_column_and_changes_nothing_else(tmp_path, dict_run):
    """`[output] sensitivity`: the same outcomes.csv plus `sensitive`, each
    row's the flag `simulate(..., sensitivity=True)` gives on its record
    (the same two solves), and the summary's section."""
    spec = dict(SPEC, output={"sensitivity": True})
    out = rockfrag.run(spec, out=tmp_path / "sens", threads=2)
    cols = rockfrag.read_outcomes(out, as_frame=False)
    plain = rockfrag.read_outcomes(dict_run, as_frame=False)
    assert list(cols) == list(plain)[:-1] + ["sensitive", "error"]
    for k in plain:
        a, b = cols[k], plain[k]
        assert (a.dtype == object and list(a) == list(b)) or np.array_equal(a, b, equal_nan=True), k
    assert cols["sensitive"].dtype == bool
    for i in range(len(cols["pga"])):
        m = rockfrag.motion(11, cols["pga"][i], int(cols["record"][i]), duration=10.0)
        o = rockfrag.simulate(m["acc"], m["dt"], vel=m["vel"], disp=m["disp"], sensitivity=True)
        assert o["sensitivity"]["sensitive"] == cols["sensitive"][i]
    assert "## Sensitivity" in open(out + "/summary.md").read()
    assert "## Sensitivity" not in open(dict_run + "/summary.md").read()


def test_fit_is_the_cli_fragility(dict_run):
    cols = rockfrag.read_outcomes(dict_run, as_frame=False)
    got = rockfrag.fit(cols["pga"], cols["overturned"])
    with open(dict_run + "/fragility.csv") as f:
        row = next(csv.DictReader(f))
    assert row["status"] == got["status"]
    if got["status"] == "ok":
        assert math.isclose(float(row["median"]), got["median"], rel_tol=1e-9)
        assert math.isclose(float(row["beta"]), got["beta"], rel_tol=1e-9)


def test_fit_counts_and_reasons():
    im = [0.2, 0.4, 0.6, 0.8]
    got = rockfrag.fit(im, [1, 4, 6, 9], trials=[10, 10, 10, 10])
    assert got["status"] == "ok" and 0.4 < got["median"] < 0.7 and got["beta"] > 0
    assert got["cov"][0][1] == got["cov"][1][0]
    sep = rockfrag.fit(im, [0, 0, 10, 10], trials=[10] * 4)
    assert sep["status"] == "separated" and math.isnan(sep["median"]) and sep["message"]


def test_notebook_sized_example():
    """An ensemble in a notebook: 10 records × 5 PGA levels, fitted."""
    pgas = [0.2, 0.4, 0.6, 0.8, 1.0]
    records = [rockfrag.motion(2024, pga, i, duration=15.0) for pga in pgas for i in range(10)]
    outcomes = rockfrag.simulate_many(records, width=0.5, aspect=4.0, restitution=0.0)
    im = np.repeat(pgas, 10)
    overturned = np.array([o["overturned"] for o in outcomes])
    assert 0 < overturned.sum() < len(overturned)
    f = rockfrag.fit(im, overturned)
    assert f["status"] in ("ok", "separated", "extrapolated-above", "extrapolated-below")
    if f["status"] != "separated":
        assert 0.1 < f["median"] < 3.0


def test_fragility_and_risk_from_python_equal_the_cli(cli, tmp_path):
    """`fragility` (limit states, bootstrap) writes the same fragility.csv as
    `rockfrag fragility` with the same settings, byte for byte, and `risk`
    the same risk.csv as `rockfrag risk`: the same library code runs."""
    folder = rockfrag.run(SPEC, out=tmp_path / "study")
    states = [
        {"name": "rocking", "measure": "theta_max_over_theta_c", "exceeds": 0.2},
        {"name": "overturning", "measure": "overturned"},
    ]
    py = tmp_path / "py"
    table = rockfrag.fragility(folder, out=py, bootstrap=30, seed=4, limit_state=states)
    assert table["path"] == str(py / "fragility.csv")
    assert table["limit_state"][:2] == ["rocking", "overturning"] and table["median"].dtype == float
    cli_dir = tmp_path / "cli"
    cli(
        "fragility", folder, "--out", cli_dir, "--bootstrap", 30, "--seed", 4,
        "--limit-state", "rocking=theta_max_over_theta_c>0.2", "--limit-state", "overturning=overturned",
    )
    assert (py / "fragility.csv").read_bytes() == (cli_dir / "fragility.csv").read_bytes()
    hazard = rockfrag.__file__.rsplit("/python/", 1)[0] + "/studies/hazard/hazard_curve-mean-PGA_example.csv"
    r = rockfrag.risk(py, hazard, out=tmp_path / "risk-py")
    cli("risk", cli_dir, "--hazard", hazard, "--out", tmp_path / "risk-cli")
    assert (tmp_path / "risk-py" / "risk.csv").read_bytes() == (tmp_path / "risk-cli" / "risk.csv").read_bytes()
    assert np.all(r["annual_rate"][~np.isnan(r["annual_rate"])] > 0)


def test_unfitted_curves_warn_and_misspelt_keywords_are_named(tmp_path):
    """A curve that cannot be fitted (no run rocks at 0.05 g) is a FitWarning
    naming it and what to try; a misspelt keyword names the keyword it
    resembles and lists the function's own keywords, not only the solver's."""
    spec = dict(SPEC, name="py-flat", grid=dict(SPEC["grid"], pga=[0.02, 0.05]))
    with pytest.warns(rockfrag.FitWarning, match="not fitted"):
        rockfrag.run(spec, out=tmp_path / "flat")
    with pytest.raises(TypeError, match=r"witdh \(did you mean width\?\).*aspect.*theta0"):
        rockfrag.simulate([0.0, 1.0, 0.0], 0.01, witdh=0.5)
    with pytest.raises(TypeError, match=r"bootstrp \(did you mean bootstrap\?\)"):
        rockfrag.fragility(tmp_path / "flat", bootstrp=10)


def test_fit_beyond_the_stripes_warns_as_fitted():
    """A median above the strongest intensity is a fit, flagged: the status
    says `extrapolated-above` and the FitWarning says it was fitted and
    extrapolated (not "not fitted"), with the strongest stripe named."""
    with pytest.warns(rockfrag.FitWarning, match=r"fitted, but median above the strongest stripe \(0\.600\)"):
        f = rockfrag.fit([0.2, 0.4, 0.6], [0, 1, 3], trials=[10, 10, 10])
    assert f["status"] == "extrapolated-above" and f["median"] > 0.6


def test_simulate_stack_with_an_immovable_base_is_the_single_block():
    # a base 10 m wide, 0.5 m high and 1e12 times heavier cannot move: the
    # statue on it rocks as the single block on the ground (the solver-level
    # limit test, tests/stack.rs, holds to 1e-9; 1e-7 here allows for the
    # record passing through numpy)
    rec = rockfrag.motion(seed=3, pga=0.4, index=1)
    out = rockfrag.simulate_stack(
        rec["acc"], rec["dt"], [(10.0, 0.5), (0.5, 2.0)], masses=[1e12, 1.0], restitution=0.0
    )
    one = rockfrag.simulate(rec["acc"], rec["dt"], width=0.5, aspect=4.0, restitution=0.0)
    assert out["failure"] is None
    top = out["bodies"][1]
    assert top["overturned"] == one["overturned"]
    assert abs(top["theta_max_over_theta_c"] - one["theta_max_over_theta_c"]) < 1e-7
    assert out["bodies"][0]["theta_max_over_theta_c"] < 1e-6


def test_simulate_stack_names_bad_input():
    rec = rockfrag.motion(seed=3, pga=0.4, index=1)
    with pytest.raises(ValueError, match="friction: 1 values for 2 bodies"):
        rockfrag.simulate_stack(rec["acc"], rec["dt"], [(0.6, 1.0), (0.3, 1.2)], friction=[0.5])
    with pytest.raises(ValueError, match=r"blocks\[1\]"):
        rockfrag.simulate_stack(rec["acc"], rec["dt"], [(0.6, 1.0), 0.3])
    with pytest.raises(ValueError, match="height"):
        rockfrag.simulate_stack(rec["acc"], rec["dt"], [(0.6, 1.0), (0.3, -1.2)])
