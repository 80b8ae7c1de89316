"""Living tissue (cgamesh.Tissue): nothing moves without a wound, a tear opens and matches the
CLI's `tear --soft`, mass is conserved, the bake re-poses to the simulated surface, bad options
raise the documented errors."""

import numpy as np
import pytest

import cgamesh
from conftest import CESIUM, run_cli_json

STEPS = [(0.01, 0.90, 2, 0.01, 0.90, 0.06), (-0.03, 1.0, 2, -0.03, 1.0, 0.06)]


def diagonal(model):
    p = model.meshes[0].positions
    return float(np.linalg.norm(p.max(axis=0) - p.min(axis=0)))


def test_nothing_moves_without_a_wound(cesium):
    live = cgamesh.LiveModel(cesium, cesium.pose(time=0.0))
    tissue = cgamesh.Tissue(live, pretension=0.0, gravity=(0, 0, 0))
    assert tissue.particles == 0 and tissue.links == 0
    for t in np.linspace(0.0, 1.0, 6):
        pose = cesium.pose(time=float(t))
        tissue.step(pose, 1 / 90)
        np.testing.assert_allclose(tissue.positions(pose)[0], cesium.skin(pose)[0], atol=1e-6 * diagonal(cesium))


def test_a_tear_opens_as_the_cli_says_and_the_bake_keeps_it(cesium, tmp_path):
    pose = cesium.pose()
    live = cgamesh.LiveModel(cesium, pose)
    tissue = cgamesh.Tissue(live, pretension=0.2, gravity=(0, 0, 0))
    mass = tissue.total_mass
    r = live.tear(STEPS)
    tissue.follow(r)
    assert tissue.total_mass == pytest.approx(mass, rel=1e-9)
    assert tissue.free_particles > 0 and tissue.links > 0
    report = tissue.settle(pose)
    assert report["settled"] and report["substeps"] > 0
    positions = tissue.positions(pose)[0]
    first = r["changes"][0]["first_new_vertex"]
    opening = np.linalg.norm(positions[first:] - live.placed_positions()[0][first:], axis=1)
    # The CLI runs the same library call: the same opening.
    cli = run_cli_json("tear", CESIUM, *sum((["--scalpel", ",".join(map(str, s))] for s in STEPS), []), "--soft",
                       "--tension", "0.2", "--gravity", "0,0,0", "-o", tmp_path / "t.glb")["soft"]
    assert opening.mean() == pytest.approx(cli["mean_opening"], rel=1e-6)
    assert opening.mean() > 0.005
    # The bake animates with the wound: skinned in the pose, it is the simulated surface.
    baked = tissue.bake(pose)
    np.testing.assert_allclose(baked.skin(pose)[0], positions, atol=1e-5 * diagonal(cesium))
    assert len(baked.clips) == len(cesium.clips)


def test_follow_takes_a_list_of_changes_and_select_grows_the_region(cesium):
    pose = cesium.pose()
    live = cgamesh.LiveModel(cesium, pose)
    tissue = cgamesh.Tissue(live, gravity=(0, 0, 0))
    tissue.select(0, (0.0, 1.0, 0.0), 0.1)
    selected = tissue.particles
    assert selected > 0
    r = live.drill((0, 1.3, -0.5), (0, 1.3, 0.5), 0.04)
    tissue.follow(r["changes"])
    assert tissue.particles > selected
    tissue.step(pose, 1 / 90)
    assert np.isfinite(tissue.positions(pose)[0]).all()


def test_bad_options_and_changes_raise(cesium):
    live = cgamesh.LiveModel(cesium)
    with pytest.raises(cgamesh.InvalidInputError, match="pretension"):
        cgamesh.Tissue(live, pretension=1.0)
    with pytest.raises(cgamesh.InvalidInputError, match="substep"):
        cgamesh.Tissue(live, substep=0.0)
    with pytest.raises(cgamesh.InvalidInputError, match="gravity"):
        cgamesh.Tissue(live, gravity=(0, 1))
    tissue = cgamesh.Tissue(live)
    with pytest.raises(cgamesh.InvalidInputError, match="dict"):
        tissue.follow([1, 2])
    with pytest.raises(cgamesh.InvalidInputError):
        tissue.step(cesium.pose(), float("nan"))
    with pytest.raises(cgamesh.InvalidInputError):
        tissue.select(5, (0, 0, 0), 0.1)
