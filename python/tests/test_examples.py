"""The example scripts run, and the surgery example's re-posed pieces are what the CLI poses."""

import os
import subprocess
import sys

import numpy as np

import cgamesh
from conftest import ROOT, read_obj, run_cli


def run_example(name, out):
    r = subprocess.run([sys.executable, str(ROOT / "examples" / name), str(out)], capture_output=True, text=True,
                       env=os.environ.copy())
    assert r.returncode == 0, r.stdout + r.stderr
    return r.stdout


def test_surgery_example(tmp_path):
    run_example("surgery.py", tmp_path)
    for name in ["upper", "lower"]:
        piece = tmp_path / f"cesium_{name}.glb"
        assert cgamesh.load(str(piece)).meshes
        run_cli("pose", piece, "--time", "0.5", "--set", "nodes[14]:rotate=0,1,1,40.1", "--set",
                "nodes[14]:translate=0.1,0,0", "--set", "nodes[14]:scale=0.5", "--set", "nodes[15]:rotate=0,1,1,17.2",
                "-o", tmp_path / f"cli_{name}.obj")
        # The CLI reads the piece back from its glTF (float inverse binds): equal to float precision.
        np.testing.assert_allclose(read_obj(tmp_path / f"cesium_{name}_reposed.obj")[0],
                                   read_obj(tmp_path / f"cli_{name}.obj")[0], atol=2e-6)
        reposed = cgamesh.load(str(tmp_path / f"cesium_{name}_reposed.glb"))
        assert reposed.clips[-1].name == "fig3"


def test_deform_example(tmp_path):
    out = run_example("deform.py", tmp_path)
    assert "harmonic field: 0.000 … 1.000" in out
    frames = [read_obj(tmp_path / f"bend_{i}.obj")[0] for i in range(4)]
    man = cgamesh.load(str(ROOT / "data" / "CesiumMan.glb"))
    np.testing.assert_allclose(frames[0], man.skin(mode="matrix")[0], atol=1e-5)  # identity keys: the bind pose
    assert np.abs(frames[3] - frames[0]).max() > 0.1
    assert cgamesh.load(str(tmp_path / "cesiumman_bend.glb")).clips
