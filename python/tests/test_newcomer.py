"""What a newcomer meets in Python (issue 37): seeds that are not whole
numbers, spec dicts holding numpy values or NaN, the DataFrame the README
promises, a fit that cannot be made, and a refit that keeps the study's
bootstrap."""

import warnings

import numpy as np
import pytest

import rockfrag

SPEC = {
    "name": "py-newcomer",
    "seed": 3,
    "records": 6,
    "motion": {"duration": 8.0},
    "grid": {"width": [0.5], "aspect": [4], "restitution": [0.0], "friction": ["inf"],
             "pga": [0.3, 0.6, 0.9, 1.2]},
    "fragility": {"bootstrap": 40},
}


def test_seeds_and_indexes_must_be_whole_numbers():
    """`motion(seed=1.5)` used to return record 0 of seed 1 (int(1.5)):
    a seed or index that is not a whole number is refused; numpy
    integers are whole numbers."""
    for bad in (1.5, 1.0, "1", -1):
        with pytest.raises(ValueError, match="seed = .*expected a whole number"):
            rockfrag.motion(seed=bad, pga=0.3)
    with pytest.raises(ValueError, match="index = 2.5"):
        rockfrag.motion(seed=1, pga=0.3, index=2.5)
    a = rockfrag.motion(seed=np.int64(7), pga=0.3, index=np.uint8(2))
    b = rockfrag.motion(seed=7, pga=0.3, index=2)
    assert np.array_equal(a["acc"], b["acc"])


def test_spec_dicts_take_numpy_values_and_refuse_nan(tmp_path):
    """A spec dict built with numpy (an array of levels, numpy scalars) runs
    as the same dict of plain numbers, to the byte; a NaN is refused naming
    its key, not with a JSON message."""
    spec = dict(SPEC, seed=np.int64(3), grid=dict(SPEC["grid"], pga=np.array([0.3, 0.6, 0.9, 1.2]),
                                                   width=[np.float64(0.5)]))
    a = rockfrag.run(spec, out=tmp_path / "numpy")
    b = rockfrag.run(SPEC, out=tmp_path / "plain")
    assert (tmp_path / "numpy" / "outcomes.csv").read_bytes() == (tmp_path / "plain" / "outcomes.csv").read_bytes()
    assert a.endswith("numpy") and b.endswith("plain")
    bad = dict(SPEC, grid=dict(SPEC["grid"], pga=[0.3, float("nan")]))
    with pytest.raises(ValueError, match=r"spec\['grid'\]\['pga'\]\[1\] = nan: expected a finite number"):
        rockfrag.run(bad, out=tmp_path / "nan")
    assert not (tmp_path / "nan").exists()


def test_read_outcomes_returns_a_dataframe(tmp_path):
    """pandas is a dependency: read_outcomes returns the DataFrame the README
    promises (it returned a dict where pandas was missing)."""
    import pandas as pd
    from pathlib import Path

    pyproject = (Path(__file__).resolve().parents[2] / "pyproject.toml").read_text()
    deps = pyproject.split("dependencies = [", 1)[1].split("]", 1)[0]
    assert '"pandas' in deps, "pandas is not a dependency: pip install . would leave it out"
    folder = rockfrag.run(SPEC, out=tmp_path / "s")
    df = rockfrag.read_outcomes(folder)
    assert isinstance(df, pd.DataFrame) and len(df) == 4 * 6
    assert df["overturned"].dtype == bool


def test_fit_on_separated_data_warns():
    """Data that jump from none to all overturned between two stripes
    cannot be fitted: fit() returns the status and raises the FitWarning
    the README describes (it returned the status silently)."""
    with pytest.warns(rockfrag.FitWarning, match="separated"):
        f = rockfrag.fit([0.2, 0.4, 0.6], [0, 0, 10], trials=[10, 10, 10])
    assert f["status"] == "separated" and np.isnan(f["median"])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert rockfrag.fit([0.2, 0.4, 0.6], [1, 5, 9], trials=[10, 10, 10])["status"] == "ok"


def test_fragility_keeps_the_studys_bootstrap(tmp_path):
    """A refit without `bootstrap` draws the study's own replicates (40
    here), not the default's; one with fewer than the fit it replaces says
    so; and it returns the table, as risk() does."""
    folder = rockfrag.run(SPEC, out=tmp_path / "s")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        table = rockfrag.fragility(folder)
    assert not [w for w in caught if "bootstrap replicates" in str(w.message)]
    fitted = table["boot_replicates"][~np.isnan(table["boot_replicates"])]
    assert len(fitted) > 0 and set(fitted) == {40.0}
    assert table["path"].endswith("fragility.csv")
    with pytest.warns(UserWarning, match="40 bootstrap replicates; this one has 10"):
        table = rockfrag.fragility(folder, bootstrap=10)
    fitted = table["boot_replicates"][~np.isnan(table["boot_replicates"])]
    assert len(fitted) > 0 and set(fitted) == {10.0}
