"""Shared fixtures: the repository's models, the built CLI, and readers for the files it writes.

Run by ctest (python_tests) with PYTHONPATH at the build's package directory and CGAMESH_CLI at
the built `cgamesh` binary; by hand: PYTHONPATH=build/python CGAMESH_CLI=build/apps/cli/cgamesh
python3 -m pytest python/tests.
"""

import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

ROOT = pathlib.Path(os.environ.get("CGAMESH_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
CESIUM = ROOT / "data" / "CesiumMan.glb"
RIGGED_FIGURE = ROOT / "tests" / "assets" / "RiggedFigure.glb"
SPOT = ROOT / "tests" / "assets" / "spot.obj"


def cli_path():
    path = os.environ.get("CGAMESH_CLI", str(ROOT / "build" / "apps" / "cli" / "cgamesh"))
    if not os.path.exists(path):
        pytest.skip("the cgamesh CLI is not built (set CGAMESH_CLI)")
    return path


def run_cli(*args, cwd=None):
    """Runs the CLI; returns its stdout. Fails the test on a non-zero exit."""
    r = subprocess.run([cli_path(), *map(str, args)], capture_output=True, text=True, cwd=cwd)
    assert r.returncode == 0, f"cgamesh {' '.join(map(str, args))}\n{r.stdout}\n{r.stderr}"
    return r.stdout


def run_cli_json(*args, cwd=None):
    return json.loads(run_cli(*args, "--json", cwd=cwd))


def read_obj(path):
    """The `v` lines of an OBJ the CLI wrote, per `o` group: a list of #V×3 float32 arrays."""
    groups = []
    for line in pathlib.Path(path).read_text().splitlines():
        if line.startswith("o "):
            groups.append([])
        elif line.startswith("v "):
            groups[-1].append([float(x) for x in line.split()[1:4]])
    return [np.array(g, dtype=np.float32).reshape(-1, 3) for g in groups]


@pytest.fixture(scope="session")
def cesium():
    import cgamesh

    return cgamesh.load(str(CESIUM))


@pytest.fixture(scope="session")
def figure():
    import cgamesh

    return cgamesh.load(str(RIGGED_FIGURE))


@pytest.fixture(scope="session")
def spot():
    import cgamesh

    return cgamesh.load(str(SPOT))
