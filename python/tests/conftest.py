"""Fixtures: the `rockfrag` CLI binary the Python results are compared with."""

import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli():
    """Runs the CLI (ROCKFRAG_BIN, else target/release/rockfrag, built if absent)."""
    path = os.environ.get("ROCKFRAG_BIN")
    if path is None:
        path = ROOT / "target" / "release" / "rockfrag"
        if not path.exists():
            subprocess.run(
                ["cargo", "build", "--release", "--bin", "rockfrag"], cwd=ROOT, check=True
            )
    path = str(path)

    def run(*args, check=True, cwd=None):
        p = subprocess.run(
            [path, *map(str, args)], capture_output=True, text=True, cwd=cwd
        )
        if check and p.returncode != 0:
            raise AssertionError("rockfrag %s failed: %s" % (" ".join(map(str, args)), p.stderr))
        return p

    run.json = lambda *args: json.loads(run(*args, "--json").stdout)
    return run
