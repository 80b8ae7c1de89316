"""Deformation: the spec of `cgamesh deform` as a dict gives the CLI's result; keys passed as
multivectors; harmonic fields hold their boundary values and the maximum principle."""

import json

import numpy as np
import pytest

import cgamesh
from cgamesh import cga
from conftest import CESIUM, ROOT, read_obj, run_cli, run_cli_json

SPECS = ROOT / "data" / "specs"


@pytest.mark.parametrize("name", ["cesiumman_bend", "cesiumman_handles", "ffd_twist_motor"])
def test_deform_equals_cli(tmp_path, cesium, name):
    spec = json.loads((SPECS / f"{name}.json").read_text())
    positions = cgamesh.deform(cesium, spec)
    summary = run_cli_json("deform", CESIUM, "--spec", SPECS / f"{name}.json", "-o", tmp_path / "cli.obj")
    assert positions.dtype == np.float32 and positions.shape == (summary["vertices"], 3)
    np.testing.assert_array_equal(positions, read_obj(tmp_path / "cli.obj")[summary["mesh"]])
    d = cgamesh.Deformer(cesium, spec)
    assert d.method == summary["method"] and d.mesh == summary["mesh"] and d.space == "world"
    assert [len(h) for h in d.handles] == summary["handle_vertices"]
    d.save(str(tmp_path / "py.glb"))
    run_cli("deform", CESIUM, "--spec", SPECS / f"{name}.json", "-o", tmp_path / "cli.glb")
    assert (tmp_path / "py.glb").read_bytes() == (tmp_path / "cli.glb").read_bytes()
    d.save(str(tmp_path / "py.obj"))  # positions and normals, as the CLI writes them
    assert (tmp_path / "py.obj").read_bytes() == (tmp_path / "cli.obj").read_bytes()
    assert b"\nvn " in (tmp_path / "py.obj").read_bytes()


def test_deformer_keys_as_multivectors(cesium):
    spec = json.loads((SPECS / "cesiumman_bend.json").read_text())
    d = cgamesh.Deformer(cesium, spec)
    keys = d.keys
    assert keys.shape == (len(spec["keys"]), 32)
    np.testing.assert_array_equal(d.apply(), d.apply(keys))
    np.testing.assert_array_equal(d.apply(), d.apply([cga.Multivector(k) for k in keys]))
    # Identity keys keep the rest shape.
    identity = np.zeros_like(keys)
    identity[:, 0] = 1
    np.testing.assert_allclose(d.apply(identity), d.rest_positions, atol=1e-5)
    # A translation key on every handle moves the whole mesh by it.
    t = cga.translator([0.1, 0, 0]).value
    moved = d.apply(np.tile(t, (len(keys), 1)))
    np.testing.assert_allclose(moved - d.rest_positions, np.tile([0.1, 0, 0], (moved.shape[0], 1)), atol=1e-5)
    # The deformed model re-animates with its skin.
    m = d.deformed_model(d.apply())
    assert m.skin(m.pose(time=0.5))[d.mesh].shape == d.rest_positions.shape


def test_bad_specs_name_the_field(cesium):
    with pytest.raises(cgamesh.InvalidInputError, match="spec.method"):
        cgamesh.deform(cesium, {"method": "twist", "handles": [[0], [1]], "keys": [{}, {}]})
    with pytest.raises(cgamesh.InvalidInputError, match=r"spec.keys\[1\].scale"):
        cgamesh.deform(cesium, {"method": "spline", "handles": [[0], [1]], "keys": [{}, {"scale": -1}]})
    with pytest.raises(cgamesh.InvalidInputError, match=r"spec.handles\[1\]"):
        cgamesh.deform(cesium, {"method": "spline", "handles": [[0], [99999999]], "keys": [{}, {}]})
    with pytest.raises(cgamesh.InvalidInputError, match="JSON"):
        cgamesh.deform(cesium, "{not json")


def grid(n):
    """A flat n×n grid in the xy-plane: positions, faces."""
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    v = np.stack([x.ravel(), y.ravel(), np.zeros(n * n)], axis=1)
    f = []
    for i in range(n - 1):
        for j in range(n - 1):
            a = i * n + j
            f += [[a, a + 1, a + n + 1], [a, a + n + 1, a + n]]
    return v, np.array(f, dtype=np.int32)


def test_harmonic_field(cesium):
    v, f = grid(12)
    left = np.where(v[:, 0] == 0)[0]
    right = np.where(v[:, 0] == 1)[0]
    h = cgamesh.harmonic_field(v, f, np.concatenate([left, right]))
    assert h.vertex_count == v.shape[0]
    values = np.concatenate([np.zeros(len(left)), np.ones(len(right))])
    x = h.solve(values)
    assert x.shape == (v.shape[0],) and x.dtype == np.float64
    np.testing.assert_array_equal(x[left], 0)
    np.testing.assert_array_equal(x[right], 1)
    assert x.min() >= 0 and x.max() <= 1  # maximum principle (mean-value weights)
    two = h.solve(np.stack([values, 1 - values], axis=1))
    assert two.shape == (v.shape[0], 2)
    np.testing.assert_allclose(two[:, 0] + two[:, 1], 1, atol=1e-9)
    with pytest.raises(cgamesh.InvalidInputError):
        h.solve(np.zeros(3))
    with pytest.raises(cgamesh.InvalidInputError):
        cgamesh.harmonic_field(v, f, [])


def test_motor_blend():
    rest = np.random.default_rng(1).normal(size=(50, 3))
    weights = np.zeros((50, 2))
    weights[:25, 0] = 1
    weights[25:, 1] = 1
    identity = cga.Multivector(1.0)
    blend = cgamesh.MotorBlend(rest, weights, [identity, identity])
    assert blend.vertex_count == 50 and blend.key_count == 2
    t, r = cga.translator([0.5, 0, 0]), cga.rotor([0, 0, 1], 0.4)
    out = blend.deform([t, r])
    assert out.dtype == np.float32 and out.shape == (50, 3)
    np.testing.assert_allclose(out[:25], rest[:25] + [0.5, 0, 0], atol=1e-5)
    np.testing.assert_allclose(out[25:], cga.down(cga.sandwich(r, cga.up(rest[25:]))), atol=1e-5)
    np.testing.assert_array_equal(out, blend.deform(np.stack([t.value, r.value])))
    with pytest.raises(cgamesh.InvalidInputError):
        blend.deform([t])


def test_fabrik():
    chain = np.array([[0, 0, 0], [0, 1, 0], [0, 2, 0]], dtype=float)
    r = cgamesh.fabrik(chain, [1, 1, 0])
    assert r["reached"] and r["distance"] < 1e-6
    j = r["joints"]
    np.testing.assert_allclose(j[0], chain[0], atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(np.diff(j, axis=0), axis=1), [1, 1], atol=1e-9)
    # Each motor takes its rest joint to the solved one.
    for i in range(3):
        m = cga.Multivector(r["motors"][i])
        np.testing.assert_allclose(cga.down(cga.sandwich(m, cga.up(chain[i]))), j[i], atol=1e-9)
    far = cgamesh.fabrik(chain, [0, 10, 0])
    assert not far["reached"] and far["distance"] == pytest.approx(8)
    with pytest.raises(cgamesh.InvalidInputError):
        cgamesh.fabrik(chain[:1], [1, 1, 0])


def test_fit_bspline_motors():
    t = np.linspace(0, 1, 9)
    keys = [cga.translator([0, 0, s]) * cga.rotor([0, 0, 1], s) for s in t]  # a screw along z
    fit = cgamesh.fit_bspline_motors(keys, t, 4)
    assert fit["control"].shape == (4, 32)
    assert fit["rms_residual"] < 1e-9 and fit["max_residual"] < 1e-9  # logs linear in t: fitted exactly
    with pytest.raises(cgamesh.InvalidInputError):
        cgamesh.fit_bspline_motors(keys, t[:3], 4)


def test_deform_a_mesh(spot):
    spec = {"method": "harmonic", "handles": [[0], [100]], "keys": [{}, {"translate": [0, 0.2, 0]}]}
    from_mesh = cgamesh.deform(spot.meshes[0], spec)
    np.testing.assert_array_equal(from_mesh, cgamesh.deform(spot, spec))
    # Handle indices are the OBJ's `v` lines: each moves every loaded vertex split from it.
    index = spot.meshes[0].file_index
    moved, kept = np.flatnonzero(index == 100), np.flatnonzero(index == 0)
    assert moved.size >= 1 and kept.size >= 1
    np.testing.assert_allclose(from_mesh[moved], spot.meshes[0].positions[moved] + [0, 0.2, 0], atol=1e-6)
    np.testing.assert_array_equal(from_mesh[kept], spot.meshes[0].positions[kept])
