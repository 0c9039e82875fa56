"""A floor of a linear building from Python: `floor` is `rockfrag floor` bit
for bit, a block on it is `simulate --floor-period …`, and a study dict with
`support` writes the floor's peaks."""

import numpy as np

import rockfrag
from records import read_csv_text, same_bits


def ground(cli, tmp_path):
    path = tmp_path / "ground.csv"
    cli("motion", "--seed", 5, "--pga", 0.4, "--index", 1, "--out", path)
    return path, read_csv_text(path.read_text())


def test_floor_is_the_cli_record_bit_for_bit(cli, tmp_path):
    path, g = ground(cli, tmp_path)
    flags = ["--period", 0.8, "--period", 0.25, "--damping", 0.05]
    flags += ["--participation", 1.3, "--participation", -0.4]
    want = read_csv_text(cli("floor", path, *flags).stdout)
    got = rockfrag.floor(
        g["acc"], 0.02, [0.8, 0.25], 0.05, [1.3, -0.4], vel=g["vel"], disp=g["disp"]
    )
    for k in ("t", "acc", "vel", "disp"):
        assert same_bits(got[k], want[k]), k
    # the roof of a building with its first mode near the record's content
    # amplifies it: PFA/PGA well above 1
    assert np.max(np.abs(got["acc"])) > 1.2 * np.max(np.abs(g["acc"]))


def test_zero_participation_is_the_ground_bit_for_bit(cli, tmp_path):
    _, g = ground(cli, tmp_path)
    got = rockfrag.floor(g["acc"], 0.02, 0.8, 0.05, 0.0, vel=g["vel"], disp=g["disp"])
    for k in ("acc", "vel", "disp"):
        assert same_bits(got[k], g[k]), k


def test_a_block_on_the_floor_is_the_cli_simulate(cli, tmp_path):
    path, g = ground(cli, tmp_path)
    flags = ["--floor-period", 0.8, "--floor-damping", 0.05, "--floor-participation", 1.3]
    want = cli.json("simulate", "--motion", path, "--aspect", 3, "--width", 0.6, *flags)
    f = rockfrag.floor(g["acc"], 0.02, 0.8, 0.05, 1.3, vel=g["vel"], disp=g["disp"])
    got = rockfrag.simulate(f["acc"], f["dt"], vel=f["vel"], disp=f["disp"], aspect=3, width=0.6)
    assert got == want


def test_bad_modes_name_the_field():
    acc = np.zeros(10)
    for kwargs, field in [
        (dict(period=-1.0, damping=0.05), "floor[0].period"),
        (dict(period=0.8, damping=1.0), "floor[0].damping"),
    ]:
        try:
            rockfrag.floor(acc, 0.02, **kwargs)
        except ValueError as e:
            assert field in str(e), str(e)
        else:
            raise AssertionError("accepted %s" % kwargs)


def test_a_study_on_a_floor_writes_its_peaks(tmp_path):
    spec = {
        "name": "py-floor",
        "seed": 4,
        "records": 3,
        "motion": {"duration": 10.0},
        "support": {"floor": [{"period": 0.8, "damping": 0.05, "participation": 1.3}]},
        "grid": {"width": [0.6], "aspect": [3], "restitution": [0.3], "pga": [0.3]},
    }
    out = rockfrag.run(spec, out=tmp_path / "s", threads=1)
    rows = rockfrag.read_outcomes(out, as_frame=False)
    assert np.all(rows["pga"] == 0.3)
    # the floor's peak is measured on the filtered record: positive, and not
    # the ground's
    assert np.all(rows["pfa"] > 0) and np.all(rows["pfa"] != rows["pga"])
    assert np.all(rows["pfv"] > 0)
