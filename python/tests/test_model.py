"""Models: loading, arrays (shapes, dtypes, zero copy), info, saving, posing and skinning, each
compared with what the CLI prints or writes for the same model."""

import os
import pathlib
import warnings

import numpy as np
import pytest

import cgamesh
from conftest import CESIUM, RIGGED_FIGURE, ROOT, SPOT, read_obj, run_cli, run_cli_json


def test_meshes_have_documented_shapes_and_dtypes(cesium):
    assert len(cesium.meshes) == 1
    m = cesium.meshes[0]
    v = m.positions.shape[0]
    assert m.positions.shape == (v, 3) and m.positions.dtype == np.float32
    assert m.normals.shape == (v, 3) and m.normals.dtype == np.float32
    assert m.uvs.shape == (v, 2) and m.uvs.dtype == np.float32
    assert m.faces.shape[1] == 3 and m.faces.dtype == np.int32
    assert m.faces.min() >= 0 and m.faces.max() < v
    assert m.joints.shape == (v, 4) and m.joints.dtype == np.uint16
    assert m.weights.shape == (v, 4) and m.weights.dtype == np.float32
    np.testing.assert_allclose(m.weights.sum(axis=1), 1, atol=1e-5)
    assert m.joints.max() < len(m.palette)
    assert m.skinned
    # glTF keeps the file's vertex numbering: the identity.
    assert m.file_index.dtype == np.int32
    np.testing.assert_array_equal(m.file_index, np.arange(v))


def test_mesh_arrays_are_read_only_views_that_keep_the_model_alive():
    model = cgamesh.load(str(CESIUM))
    a = model.meshes[0].positions
    b = model.meshes[0].positions
    assert np.shares_memory(a, b)  # both views of the model's own storage: no copy
    assert not a.flags.writeable
    with pytest.raises(ValueError):
        a[0, 0] = 1
    first = a.copy()
    del model, b
    np.testing.assert_array_equal(a, first)  # still valid: the view holds the model


def test_skeleton_and_clips(cesium):
    sk = cesium.skeleton
    n = len(sk)
    assert len(sk.names) == n and sk.parents.shape == (n,) and sk.parents.dtype == np.int32
    assert all(p < i for i, p in enumerate(sk.parents))
    assert sk.rest_translations.shape == (n, 3) and sk.rest_rotations.shape == (n, 4) and sk.rest_scales.shape == (n, 3)
    np.testing.assert_allclose(np.linalg.norm(sk.rest_rotations, axis=1), 1, atol=1e-6)
    assert sk.find(sk.names[3]) == 3 and sk.find("no such joint") == -1
    info = run_cli_json("info", CESIUM)
    assert [c.name for c in cesium.clips] == [a["name"] for a in info["animations"]]
    assert [c.duration for c in cesium.clips] == [a["duration"] for a in info["animations"]]
    assert sk.names == [j["name"] for j in info["skeleton"]]
    assert list(sk.parents) == [j["parent"] for j in info["skeleton"]]


@pytest.mark.parametrize("path", [CESIUM, RIGGED_FIGURE, SPOT])
def test_info_equals_the_cli(path):
    model = cgamesh.load(str(path))
    assert model.info() == run_cli_json("info", path)
    assert model.warnings == model.info()["warnings"]


def test_save_obj_and_glb_equal_the_cli(tmp_path, cesium):
    # OBJ: the bind pose in world space, byte for byte what `cgamesh pose` writes.
    run_cli("pose", CESIUM, "-o", tmp_path / "cli.obj")
    cesium.save(str(tmp_path / "py.obj"))
    assert (tmp_path / "py.obj").read_bytes() == (tmp_path / "cli.obj").read_bytes()
    lines = (tmp_path / "py.obj").read_text().splitlines()
    normals = np.array([[float(x) for x in line.split()[1:]] for line in lines if line.startswith("vn ")])
    assert normals.shape == cesium.meshes[0].normals.shape  # skinned normals, one per vertex
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1, atol=1e-5)
    # glTF: what `cgamesh convert` writes.
    run_cli("convert", CESIUM, "-o", tmp_path / "cli.glb")
    cesium.save(str(tmp_path / "py.glb"))
    assert (tmp_path / "py.glb").read_bytes() == (tmp_path / "cli.glb").read_bytes()
    again = cgamesh.load(str(tmp_path / "py.glb"))
    np.testing.assert_array_equal(again.meshes[0].positions, cesium.meshes[0].positions)
    np.testing.assert_array_equal(again.meshes[0].faces, cesium.meshes[0].faces)


def test_static_mesh_round_trip(tmp_path, spot):
    assert not spot.meshes[0].skinned
    # OBJ: each vertex is numbered by its `v` line, seam copies sharing one.
    index = spot.meshes[0].file_index
    assert index.shape == (spot.meshes[0].positions.shape[0],)
    assert index.min() >= 0 and len(np.unique(index)) < len(index)
    assert spot.meshes[0].joints.shape == (0, 4)
    spot.save(str(tmp_path / "spot.ply"))
    run_cli("pose", SPOT, "-o", tmp_path / "cli.ply")
    assert (tmp_path / "spot.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()


@pytest.mark.parametrize("mode", ["cga", "versor", "matrix", "dqs"])
def test_skin_equals_cli_pose(tmp_path, cesium, mode):
    elbow, wrist = "nodes[14]", "nodes[15]"
    edits = [f"{elbow}:rotate=0,1,1,40.1", {"joint": elbow, "translate": (0.1, 0, 0), "scale": 0.5},
             {"joint": cesium.skeleton.find(wrist), "rotate": [0, 1, 1, 17.2]}]
    pose = cesium.pose(clip=0, time=0.5, blend="log", edits=edits)
    assert len(pose) == len(cesium.skeleton)
    out = cesium.skin(pose, mode=mode)
    assert len(out) == 1 and out[0].dtype == np.float32 and out[0].shape == cesium.meshes[0].positions.shape
    run_cli("pose", CESIUM, "--anim", "0", "--time", "0.5", "--blend", "log", "--set", f"{elbow}:rotate=0,1,1,40.1",
            "--set", f"{elbow}:translate=0.1,0,0", "--set", f"{elbow}:scale=0.5", "--set", f"{wrist}:rotate=0,1,1,17.2",
            "--skinning", mode, "-o", tmp_path / "cli.obj")
    np.testing.assert_array_equal(out[0], read_obj(tmp_path / "cli.obj")[0])


@pytest.mark.parametrize("mode", ["cga", "versor", "matrix", "dqs"])
def test_skin_with_normals_gives_the_cli_pose_normals(tmp_path, cesium, mode):
    pose = cesium.pose(clip=0, time=0.5)
    positions, normals = cesium.skin(pose, mode=mode, normals=True)
    np.testing.assert_array_equal(positions[0], cesium.skin(pose, mode=mode)[0])
    assert normals[0].dtype == np.float32 and normals[0].shape == positions[0].shape
    np.testing.assert_allclose(np.linalg.norm(normals[0], axis=1), 1.0, atol=1e-5)
    # Turned, not the rest normals.
    assert np.abs(normals[0] - cesium.meshes[0].normals).max() > 0.5
    run_cli("pose", CESIUM, "--anim", "0", "--time", "0.5", "--skinning", mode, "-o", tmp_path / "cli.obj")
    vn = np.array([line.split()[1:] for line in (tmp_path / "cli.obj").read_text().splitlines()
                   if line.startswith("vn ")], dtype=np.float32)
    np.testing.assert_array_equal(normals[0], vn)


def test_pose_defaults_follow_the_cli(tmp_path, cesium):
    bind = cesium.skin()
    np.testing.assert_array_equal(bind[0], cesium.skin(cesium.pose())[0])
    run_cli("pose", CESIUM, "--time", "1.0", "-o", tmp_path / "t.obj")  # --time alone: the first clip
    np.testing.assert_array_equal(cesium.skin(cesium.pose(time=1.0))[0], read_obj(tmp_path / "t.obj")[0])
    np.testing.assert_array_equal(cesium.skin(cesium.pose(clip=cesium.clips[0].name, time=1.0))[0],
                                  read_obj(tmp_path / "t.obj")[0])
    # The bind pose is the box info reports.
    box = cesium.info()["bounding_box"]
    np.testing.assert_allclose(cesium.skin(mode="matrix")[0].min(axis=0), box["min"], atol=1e-6)
    np.testing.assert_allclose(cesium.skin(mode="matrix")[0].max(axis=0), box["max"], atol=1e-6)


def test_pose_past_a_clips_end_warns_as_the_cli_does(tmp_path, cesium):
    end = cesium.clips[0].duration
    with pytest.warns(UserWarning, match="past the end of clip"):
        late = cesium.pose(time=end + 3)
    np.testing.assert_array_equal(cesium.skin(late)[0], cesium.skin(cesium.pose(time=end))[0])
    cli = run_cli_json("pose", CESIUM, "--time", str(end + 3), "-o", tmp_path / "late.obj")
    assert any("past the end of clip" in w for w in cli["warnings"])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cesium.pose(time=end)


def test_subdivided_keeps_the_old_vertices_and_their_skinning(cesium):
    m = cesium.meshes[0]
    v, f = m.positions.shape[0], m.faces.shape[0]
    big = cesium.subdivided(2)
    b = big.meshes[0]
    assert b.faces.shape == (16 * f, 3) and b.positions.shape[0] > 4 * v
    np.testing.assert_array_equal(b.positions[:v], m.positions)
    assert (b.file_index[v:] == -1).all() and (b.file_index[:v] == m.file_index).all()
    np.testing.assert_allclose(b.weights.sum(axis=1), 1, atol=1e-5)
    pose = cesium.pose(time=0.5)
    np.testing.assert_allclose(big.skin(pose)[0][:v], cesium.skin(pose)[0], atol=1e-6)
    assert cesium.subdivided(0).meshes[0].positions.shape == m.positions.shape
    with pytest.raises(cgamesh.InvalidInputError):
        cesium.subdivided(-1)


def test_skin_returns_arrays_that_own_their_memory(cesium):
    a = cesium.skin()[0]
    assert a.flags.writeable and a.flags.c_contiguous
    assert not np.shares_memory(a, cesium.meshes[0].positions)


def test_animate_equals_cli(tmp_path, cesium):
    keys = [(0, "nodes[13]:rotate=1,0,0,0"), (1, {"joint": "nodes[13]", "rotate": (1, 0, 0, -70)}),
            (2, "nodes[13]:rotate=1,0,0,0")]
    waved = cesium.animate(keys, blend="log", fps=30, name="wave")
    assert [c.name for c in waved.clips][-1] == "wave" and len(waved.clips) == len(cesium.clips) + 1
    assert waved.clips[-1].duration == pytest.approx(2.0)
    waved.save(str(tmp_path / "py.glb"))
    run_cli("animate", CESIUM, "-o", tmp_path / "cli.glb", "--blend", "log", "--fps", "30", "--name", "wave",
            "--key", "0:nodes[13]:rotate=1,0,0,0", "--key", "1:nodes[13]:rotate=1,0,0,-70",
            "--key", "2:nodes[13]:rotate=1,0,0,0")
    assert (tmp_path / "py.glb").read_bytes() == (tmp_path / "cli.glb").read_bytes()


def test_missing_and_truncated_files_raise_file_error(tmp_path):
    with pytest.raises(cgamesh.FileError, match="missing.glb"):
        cgamesh.load(str(tmp_path / "missing.glb"))
    truncated = tmp_path / "truncated.glb"
    truncated.write_bytes(CESIUM.read_bytes()[:1000])
    with pytest.raises(cgamesh.FileError):
        cgamesh.load(str(truncated))
    assert issubclass(cgamesh.FileError, cgamesh.InvalidInputError)
    assert issubclass(cgamesh.InvalidInputError, cgamesh.Error)


def test_bad_values_raise_invalid_input_and_write_nothing(tmp_path, cesium):
    with pytest.raises(cgamesh.InvalidInputError, match="nodes"):
        cesium.pose(edits=["no_such_joint:rotate=0,0,1,10"])
    with pytest.raises(cgamesh.InvalidInputError, match="scale"):
        cesium.pose(edits=[{"joint": 0, "scale": -1}])
    with pytest.raises(cgamesh.InvalidInputError, match="blend"):
        cesium.pose(clip=0, blend="cubic")
    with pytest.raises(cgamesh.InvalidInputError):
        cesium.pose(clip=5)
    with pytest.raises(cgamesh.InvalidInputError, match="mode"):
        cesium.skin(mode="lbs")
    with pytest.raises(cgamesh.InvalidInputError):
        cesium.save(str(tmp_path / "model.stl"))
    assert not (tmp_path / "model.stl").exists()


def test_write_error_leaves_nothing(tmp_path, cesium):
    target = tmp_path / "no_dir" / "model.glb"
    with pytest.raises(cgamesh.WriteError):
        cesium.save(str(target))
    assert not target.parent.exists()
    os.chmod(tmp_path, 0o500)
    try:
        if os.access(tmp_path, os.W_OK):
            pytest.skip("running as root: a read-only directory is writable")
        with pytest.raises(cgamesh.WriteError):
            cesium.save(str(tmp_path / "model.glb"))
    finally:
        os.chmod(tmp_path, 0o700)
    assert list(pathlib.Path(tmp_path).iterdir()) == []


def test_calls_from_threads_agree(cesium):
    # skin and load release the GIL: concurrent calls run in parallel and give the same results.
    from concurrent.futures import ThreadPoolExecutor

    pose = cesium.pose(time=0.25)
    expected = cesium.skin(pose)[0]
    with ThreadPoolExecutor(4) as pool:
        results = list(pool.map(lambda _: cesium.skin(pose)[0], range(8)))
        models = list(pool.map(lambda _: cgamesh.load(str(CESIUM)), range(4)))
    for r in results:
        np.testing.assert_array_equal(r, expected)
    for m in models:
        np.testing.assert_array_equal(m.meshes[0].positions, cesium.meshes[0].positions)


def test_morph_targets_and_weights():
    model = cgamesh.load(ROOT / "tests" / "assets" / "rigged_simple_morph.glb")
    mesh = model.meshes[0]
    assert [t.name for t in mesh.morph_targets] == ["bulge", "tip"]
    bulge, tip = mesh.morph_targets
    assert bulge.positions.shape == mesh.positions.shape and bulge.positions.dtype == np.float32
    assert bulge.normals.shape == (0, 3) and tip.normals.shape == mesh.positions.shape
    assert not bulge.positions.flags.writeable
    np.testing.assert_array_equal(mesh.morph_weights, [0.5, 0.0])  # the node's weights override the mesh's
    np.testing.assert_array_equal(model.morph_weights()[0], [0.5, 0.0])
    clip_weights = model.morph_weights(model.pose(time=0.6))[0]
    set_tip = model.pose(time=0.6, morph_weights={"tip": 0.8})
    np.testing.assert_array_equal(model.morph_weights(set_tip)[0], np.float32([clip_weights[0], 0.8]))

    # Skinning is affine per vertex in its rest position, so the targets' effects add up.
    def skinned(w):
        return model.skin(model.pose(time=0.6, morph_weights={0: w}), mode="matrix")[0].astype(np.float64)

    none, one, two, both = skinned([0, 0]), skinned([1, 0]), skinned([0, 1]), skinned([1, 1])
    assert np.abs(one - none).max() > 0.1 and np.abs(two - none).max() > 0.1
    np.testing.assert_allclose(both - none, (one - none) + (two - none), atol=1e-4)
    np.testing.assert_array_equal(model.skin(set_tip)[0], model.skin(model.pose(time=0.6, morph_weights={0: [
        clip_weights[0], 0.8]}))[0])


def test_morph_weights_equal_the_cli(tmp_path):
    path = ROOT / "tests" / "assets" / "rigged_simple_morph.glb"
    model = cgamesh.load(path)
    pose = model.pose(clip=0, time=0.6, morph_weights={"tip": 0.8, "bulge": -0.5})
    run_cli("pose", path, "--anim", "0", "--time", "0.6", "--morph", "tip=0.8", "--morph", "bulge=-0.5", "-o",
            tmp_path / "cli.obj")
    np.testing.assert_array_equal(model.skin(pose)[0], read_obj(tmp_path / "cli.obj")[0])
    assert run_cli_json("pose", path, "--morph", "tip=1", "-o", tmp_path / "b.obj")["pose"]["morph"] == ["tip=1"]


@pytest.mark.parametrize("weights, message", [({"smile": 1.0}, "'bulge', 'tip'"), ({3: [0, 0]}, "1 meshes"),
                                              ({0: [1.0]}, "2 morph targets"), ({"tip": float("nan")}, "NaN")])
def test_bad_morph_weights_raise_invalid_input(weights, message):
    model = cgamesh.load(ROOT / "tests" / "assets" / "rigged_simple_morph.glb")
    with pytest.raises(cgamesh.InvalidInputError, match=message):
        model.pose(morph_weights=weights)
