"""Surgery: cut, tear, drill and LiveModel give the CLI's results (its files, byte for byte) and
consistent vertex origins; bad tools raise the documented errors."""

import numpy as np
import pytest

import cgamesh
from conftest import CESIUM, SPOT, read_obj, run_cli, run_cli_json

PLANE = (0, 1, 0, 0.9)
SCALPEL = [(0.01, 0.90, 2, 0.01, 0.90, 0.06), (-0.005, 0.93, 2, -0.005, 0.93, 0.06),
           (-0.02, 0.96, 2, -0.02, 0.96, 0.06)]


def check_origins(result, model, placed_before):
    """Every vertex's origin: a copy reproduces its old vertex (rest and placed position), an
    edge or face point lies between its old vertices with weights summing to 1."""
    assert len(result.origins) == len(result.model.meshes) == len(result.placed)
    for k, (mesh, origins) in enumerate(zip(result.model.meshes, result.origins)):
        src = int(result.source_mesh[k])
        old = model.meshes[src]
        v, w, kind = origins["vertices"], origins["weights"], origins["kind"]
        n = mesh.positions.shape[0]
        assert v.shape == (n, 3) and v.dtype == np.int32 and w.shape == (n, 3) and kind.shape == (n,)
        assert set(np.unique(kind)) <= {1, 2, 3}
        np.testing.assert_array_equal(kind, (v >= 0).sum(axis=1))
        np.testing.assert_allclose(w.sum(axis=1), 1, atol=1e-5)
        copies = kind == 1
        np.testing.assert_array_equal(mesh.positions[copies], old.positions[v[copies, 0]])
        np.testing.assert_array_equal(result.placed[k][copies], placed_before[src][v[copies, 0]])
        blended = ~copies
        if blended.any():
            lo = placed_before[src][np.where(v[blended] >= 0, v[blended], 0)].min(axis=1)
            hi = placed_before[src][np.where(v[blended] >= 0, v[blended], 0)].max(axis=1)
            p = result.placed[k][blended]
            assert np.all(p >= lo - 1e-5) and np.all(p <= hi + 1e-5)


def test_cut_equals_cli(tmp_path, cesium):
    pose = cesium.pose(time=0.5)
    a, b = cgamesh.cut(cesium, PLANE, pose=pose, cap=True)
    a.save(str(tmp_path / "a.glb"))
    b.save(str(tmp_path / "b.glb"))
    a.save(str(tmp_path / "a.obj"))
    b.save(str(tmp_path / "b.obj"))
    summary = run_cli_json("cut", CESIUM, "--time", "0.5", "--plane", "0,1,0,0.9", "--cap", "-o", tmp_path / "ca.glb",
                           tmp_path / "cb.glb")
    run_cli("cut", CESIUM, "--time", "0.5", "--plane", "0,1,0,0.9", "--cap", "-o", tmp_path / "ca.obj",
            tmp_path / "cb.obj")
    for mine, cli in [("a.glb", "ca.glb"), ("b.glb", "cb.glb"), ("a.obj", "ca.obj"), ("b.obj", "cb.obj")]:
        assert (tmp_path / mine).read_bytes() == (tmp_path / cli).read_bytes(), mine
    assert b"\nvn " in (tmp_path / "a.obj").read_bytes()  # normals skinned into the pose, as the CLI's
    for key in ["new_vertices", "intersection_points", "faces_in", "faces_split", "cap_triangles"]:
        assert a.stats[key] == summary[key], key
    assert list(a.stats["faces_out"]) == summary["faces_out"]
    # Piece A is the side n·x > d.
    assert a.placed[0][:, 1].min() >= 0.9 - 1e-5 and b.placed[0][:, 1].max() <= 0.9 + 1e-5
    check_origins(a, cesium, cesium.skin(pose))
    check_origins(b, cesium, cesium.skin(pose))
    # New vertices on crossed edges lie on the plane as placed.
    on_edges = a.origins[0]["kind"] == 2
    assert on_edges.sum() > 0
    np.testing.assert_allclose(a.placed[0][on_edges, 1], 0.9, atol=1e-5)
    # The pieces re-animate: their models pose and skin like any other.
    assert a.model.skin(a.model.pose(time=1.0))[0].shape == a.model.meshes[0].positions.shape


def test_cut_static_mesh_options(tmp_path, spot):
    box = spot.info()["bounding_box"]
    mid = 0.5 * (box["min"][0] + box["max"][0])
    a, b = cgamesh.cut(spot, [1, 0, 0, mid], own_side_influences=True, rest="parametric", predicates="euclidean")
    run_cli("cut", SPOT, "--plane", f"1,0,0,{mid!r}", "--own-side-influences", "--rest", "parametric", "--euclidean",
            "-o", tmp_path / "a.obj", tmp_path / "b.obj")
    np.testing.assert_array_equal(a.placed[0], read_obj(tmp_path / "a.obj")[0])
    np.testing.assert_array_equal(b.placed[0], read_obj(tmp_path / "b.obj")[0])
    check_origins(a, spot, spot.skin())


def test_tear_equals_cli(tmp_path, cesium):
    pose = cesium.pose(time=0.5)
    torn = cgamesh.tear(cesium, np.array(SCALPEL), pose=pose, open=0.01)
    torn.save(str(tmp_path / "t.glb"))
    args = []
    for s in SCALPEL:
        args += ["--scalpel", ",".join(map(repr, s))]
    summary = run_cli_json("tear", CESIUM, "--time", "0.5", "--open", "0.01", *args, "-o", tmp_path / "c.glb")
    assert (tmp_path / "t.glb").read_bytes() == (tmp_path / "c.glb").read_bytes()
    for key in ["mesh", "new_vertices", "intersection_points", "faces_in", "faces_out", "faces_split"]:
        assert torn.stats[key] == summary[key], key
    np.testing.assert_allclose(torn.stats["path"], summary["path"], rtol=0, atol=1e-12)
    side = torn.stats["side"]
    assert side.shape == (torn.model.meshes[0].positions.shape[0],) and (side == 1).sum() == (side == -1).sum() > 0


def test_drill_equals_cli(tmp_path, cesium):
    pose = cesium.pose(time=0.5)
    d = cgamesh.drill(cesium, tip=(0.01, 0.9, -0.6), base=(0.01, 0.9, 0.6), radius=0.04, pose=pose, wall=True)
    d.save(str(tmp_path / "d.glb"))
    summary = run_cli_json("drill", CESIUM, "--time", "0.5", "--base", "0.01,0.9,0.6", "--tip", "0.01,0.9,-0.6",
                           "--radius", "0.04", "--wall", "-o", tmp_path / "c.glb")
    assert (tmp_path / "d.glb").read_bytes() == (tmp_path / "c.glb").read_bytes()
    for key in ["new_vertices", "faces_in", "faces_out", "rims", "walls", "open_rims", "wall_triangles", "refinements"]:
        assert d.stats[key] == summary[key], key
    check_origins(d, cesium, cesium.skin(pose))


def test_surgery_errors(cesium):
    with pytest.raises(cgamesh.InvalidInputError):
        cgamesh.cut(cesium, (float("nan"), 1, 0, 0))
    with pytest.raises(cgamesh.InvalidInputError, match="zero vector"):
        cgamesh.cut(cesium, (0, 0, 0, 1))
    with pytest.raises(cgamesh.TopologyError):
        cgamesh.cut(cesium, (0, 1, 0, 100))  # the plane misses the model
    with pytest.raises(cgamesh.TopologyError):
        cgamesh.drill(cesium, tip=(5, 5, 5), base=(5, 5, 6), radius=0.01)
    with pytest.raises(cgamesh.InvalidInputError):
        cgamesh.drill(cesium, tip=(0, 1, 0), base=(0, 1, 1), radius=-1)
    with pytest.raises(cgamesh.InvalidInputError):
        cgamesh.tear(cesium, [SCALPEL[0]])  # one step
    with pytest.raises(cgamesh.InvalidInputError, match="rest"):
        cgamesh.cut(cesium, PLANE, rest="exactly")
    with pytest.raises(cgamesh.InvalidInputError):
        cgamesh.cut(cesium, (0, 1, 0))


def test_live_model_cut_in_place(cesium):
    pose = cesium.pose(time=0.5)
    live = cgamesh.LiveModel(cesium, pose)
    before = live.placed_positions()[0].copy()
    r = live.cut(PLANE)
    assert len(r["changes"]) == 1
    ch = r["changes"][0]
    model = live.model
    mesh = model.meshes[0]
    placed = live.placed_positions()[0]
    assert mesh.faces.shape[0] == r["faces_out"]
    n_new = mesh.positions.shape[0] - ch["first_new_vertex"]
    assert ch["first_new_vertex"] == cesium.meshes[0].positions.shape[0] and n_new > 0
    assert ch["origins"]["vertices"].shape == (n_new, 3)
    # Old vertices keep their ids and places; new ones on crossed edges lie on the plane.
    np.testing.assert_array_equal(placed[: ch["first_new_vertex"]], before)
    on_plane = ch["origins"]["kind"] == 2
    np.testing.assert_allclose(placed[ch["first_new_vertex"]:][on_plane, 1], 0.9, atol=1e-5)
    # Each new face is on its piece's side.
    pieces = r["piece_of_new_face"][0]
    centroids = placed[mesh.faces[ch["new_faces"]]].mean(axis=1)
    assert np.all(centroids[pieces == 0, 1] >= 0.9 - 1e-5) and np.all(centroids[pieces == 1, 1] <= 0.9 + 1e-5)
    # The snapshot is a copy: a later drill changes the live model, not it.
    faces = mesh.faces.shape[0]
    d = live.drill(tip=(0.01, 0.9, -0.6), base=(0.01, 0.9, 0.6), radius=0.04)
    assert d["changes"] and model.meshes[0].faces.shape[0] == faces
    assert live.model.meshes[0].faces.shape[0] == d["faces_out"]


def test_live_model_tear(cesium):
    live = cgamesh.LiveModel(cesium, cesium.pose(time=0.5))
    r = live.tear(SCALPEL, open=0.01)
    ch = r["changes"][0]
    assert ch["mesh"] == 0 and len(ch["new_faces"]) > 0 and r["faces_out"] == live.model.meshes[0].faces.shape[0]
    with pytest.raises(cgamesh.TopologyError):
        live.cut((0, 1, 0, 100))
