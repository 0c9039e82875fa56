"""Bad input raises Python exceptions with the CLI's messages."""

import numpy as np
import pytest

import rockfrag

ACC = np.sin(np.linspace(0, 20, 501))


def cli_error(cli, *args):
    p = cli(*args, check=False)
    assert p.returncode != 0
    return p.stderr.strip().removeprefix("error: ")


def test_bad_block_is_a_value_error():
    with pytest.raises(ValueError, match=r"^invalid width = -1: expected a base width 2B in m from 0.001 to 1000 "):
        rockfrag.simulate(ACC, 0.02, width=-1)
    with pytest.raises(ValueError, match=r"invalid restitution = 1.5"):
        rockfrag.simulate(ACC, 0.02, restitution=1.5)
    with pytest.raises(ValueError, match="mu_k 0.8 is larger than mu_s 0.5"):
        rockfrag.simulate(ACC, 0.02, mu_s=0.5, mu_k=0.8)
    with pytest.raises(ValueError, match="invalid rtol = 2"):
        rockfrag.simulate(ACC, 0.02, rtol=2)
    with pytest.raises(ValueError, match="invalid model = 'cubic': expected one of nonlinear, linear"):
        rockfrag.simulate(ACC, 0.02, model="cubic")


def test_unknown_keyword_is_a_type_error():
    with pytest.raises(TypeError, match=r"unknown keyword\(s\) rtl \(did you mean rtol\?\)"):
        rockfrag.simulate(ACC, 0.02, rtl=1e-6)


def test_bad_record_is_a_value_error():
    bad = ACC.copy()
    bad[7] = np.nan
    with pytest.raises(ValueError, match=r"^invalid record rec: acc sample 7 is NaN$"):
        rockfrag.simulate(bad, 0.02, name="rec")
    with pytest.raises(ValueError, match="1 samples; at least 2 are needed"):
        rockfrag.simulate([0.0], 0.02)
    with pytest.raises(ValueError, match="dt = -0.02 must be positive"):
        rockfrag.simulate(ACC, -0.02)
    with pytest.raises(ValueError, match="give both vel and disp"):
        rockfrag.simulate(ACC, 0.02, vel=ACC)
    with pytest.raises(ValueError, match="one-dimensional"):
        rockfrag.simulate(np.zeros((3, 3)), 0.02)


def test_bad_motion_is_a_value_error(cli):
    with pytest.raises(ValueError, match="invalid pga = -1"):
        rockfrag.motion(1, -1.0)
    # A PGA meant in cm/s² is refused, as by the CLI.
    with pytest.raises(ValueError, match=r"invalid pga = 300: expected a peak ground acceleration in g"):
        rockfrag.motion(1, 300.0)
    cli_error(cli, "motion", "--seed", 1, "--pga", 300)
    # A step that misfits the frequency grid is no longer an error: the
    # default model's grid is one FFT over the whole record, whatever dt;
    # the CLI and Python give the same record at such a step.
    want = cli("motion", "--seed", 1, "--pga", 0.3, "--dt", 0.03).stdout.splitlines()[2]
    got = rockfrag.motion(1, 0.3, dt=0.03)
    assert [float(x) for x in want.split(",")] == [got[k][1] for k in ("t", "acc", "vel", "disp")]


def test_a_bad_spec_gives_the_cli_message(cli, tmp_path):
    spec = tmp_path / "bad.toml"
    spec.write_text('name = "bad"\nrecords = 2\n\n[grid]\naspect = [-4]\npga = [0.3]\n')
    want = cli_error(cli, "run", spec, "--out", tmp_path / "cli")
    with pytest.raises(ValueError) as e:
        rockfrag.run(spec, out=tmp_path / "py")
    assert str(e.value) == want


def test_a_missing_spec_is_an_os_error_with_the_cli_message(cli, tmp_path):
    spec = tmp_path / "missing.toml"
    want = cli_error(cli, "run", spec)
    with pytest.raises(OSError) as e:
        rockfrag.run(spec)
    assert str(e.value) == want


def test_a_bad_dict_spec_is_a_value_error(tmp_path):
    with pytest.raises(ValueError, match="aspect"):
        rockfrag.run({"name": "d", "records": 2, "grid": {"aspect": [-4], "pga": [0.3]}}, out=tmp_path)
    with pytest.raises(ValueError, match="threads"):
        rockfrag.run({"name": "d"}, out=tmp_path, threads=0)


def test_bad_fit_input_is_a_value_error():
    with pytest.raises(ValueError, match="invalid im = -0.1"):
        rockfrag.fit([-0.1, 0.2], [0, 1], trials=[1, 1])
    with pytest.raises(ValueError, match="cannot exceed"):
        rockfrag.fit([0.1, 0.2], [3, 1], trials=[1, 1])
    with pytest.raises(ValueError, match="different lengths"):
        rockfrag.fit([0.1, 0.2], [True])
