"""Two horizontal components from Python: `rotate` turns a pair as
`simulate --motion2 --orientation` and a study do (bit for bit), `rotd` is
the RotD of a pair with a known answer, and a study dict of record pairs
writes the direction and the RotD50 of each analysis."""

import numpy as np
import pytest

import rockfrag
from records import read_csv_text, same_bits


def pair(cli, tmp_path):
    paths = []
    for k, (index, pga) in enumerate([(0, 0.4), (1, 0.3)]):
        path = tmp_path / ("H%d.csv" % (k + 1))
        cli("motion", "--seed", 8, "--pga", pga, "--index", index, "--out", path)
        paths.append(path)
    recs = [read_csv_text(p.read_text()) for p in paths]
    for r in recs:
        r["dt"] = 0.02
    return paths, recs


def test_axes_are_the_components_and_a_turned_block_is_the_cli(cli, tmp_path):
    paths, (h1, h2) = pair(cli, tmp_path)
    for phi, want in [(0, h1), (90, h2)]:
        got = rockfrag.rotate(h1, h2, phi)
        for k in ("acc", "vel", "disp"):
            assert same_bits(got[k], want[k]), (phi, k)
    # a half turn negates the motion exactly
    got = rockfrag.rotate(h1, h2, 180)
    assert same_bits(got["acc"], -h1["acc"])
    # a block facing 30° is the CLI's, to the last bit of every output
    want = cli.json(
        "simulate", "--motion", paths[0], "--motion2", paths[1], "--orientation", 30,
        "--aspect", 3, "--width", 0.4,
    )
    r = rockfrag.rotate(h1, h2, 30)
    got = rockfrag.simulate(r["acc"], r["dt"], vel=r["vel"], disp=r["disp"], aspect=3, width=0.4)
    assert got == want


def test_rotd_of_a_circular_pair_is_its_radius():
    # a circularly polarised pair (cos, sin of one phase): every direction
    # has the same peak, the radius 2 m/s², to the sampling of the phase
    # (1,000 samples a turn: the peak of cos(ωt − φ) is within 1 − cos(π/1000)
    # ≈ 5e-6 of 2)
    t = np.arange(0, 4, 0.001)
    w = 2 * np.pi
    h1 = {"acc": 2 * np.cos(w * t), "dt": 0.001}
    h2 = {"acc": 2 * np.sin(w * t), "dt": 0.001}
    for p in (0, 50, 100):
        assert rockfrag.rotd(h1, h2, p) == pytest.approx(2.0, rel=1e-5)
    # one component alone: peak |a(φ)| = 2|cos φ|, median over 0…179° is
    # 2 cos 45° (Boore 2010's linearly polarised case)
    zero = {"acc": np.zeros_like(t), "dt": 0.001}
    assert rockfrag.rotd(h1, zero, 50) == pytest.approx(2 * np.cos(np.pi / 4), rel=1e-12)
    assert rockfrag.rotd(h1, zero, 100) == 2.0


def test_bad_pairs_are_named():
    a = {"acc": np.ones(10), "dt": 0.01}
    with pytest.raises(ValueError, match="different intervals"):
        rockfrag.rotate(a, {"acc": np.ones(10), "dt": 0.02}, 30)
    with pytest.raises(ValueError, match="different lengths"):
        rockfrag.rotate(a, {"acc": np.ones(9), "dt": 0.01}, 30)
    with pytest.raises(TypeError, match="h2: expected a record dict"):
        rockfrag.rotd(a, np.ones(10))


def test_a_study_of_pairs_writes_directions_and_rotd50(cli, tmp_path):
    paths, _ = pair(cli, tmp_path)
    spec = {
        "name": "pairs",
        "record_files": [[str(paths[0]), str(paths[1])]],
        "grid": {"aspect": [3], "width": [0.4], "restitution": [0.5], "pga": [0.3, 0.6],
                 "orientation": [0, 45, 90]},
    }
    out = rockfrag.run(spec, out=str(tmp_path / "out"))
    cols = rockfrag.read_outcomes(out, as_frame=False)
    assert list(cols["phi"]) == [0.0, 45.0, 90.0] * 2
    assert list(cols["pga_rotd50"]) == [0.3] * 3 + [0.6] * 3
    # the felt component's PGA: at 0° and 90° the pair's factor times each
    # component's peak, so their ratio is the components' ratio 0.4/0.3
    pga = cols["pga"]
    assert pga[0] / pga[2] == pytest.approx(0.4 / 0.3, rel=1e-12)
    assert all(" + " in f for f in cols["record_file"])
