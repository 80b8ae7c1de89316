#!/usr/bin/env python3
"""Motor-handle deformation from Python: bend CesiumMan with the spline-aligned spec of
data/specs/cesiumman_bend.json written as a dict, animate the bend by blending its keys, and
solve a harmonic field on the same mesh.

    PYTHONPATH=build/python python3 examples/deform.py [OUT_DIR]
"""

import pathlib
import sys

import numpy as np

import cgamesh
from cgamesh import cga

ROOT = pathlib.Path(__file__).resolve().parents[1]

SPEC = {
    "method": "spline",
    "handles": [{"box": [-1, -1, -1, 1, 0.15, 1]}, {"box": [-1, 1.35, -1, 1, 2, 1]}],
    "basis": "bspline",
    "degree": 3,
    "keys": [
        {},
        {"rotate": [0, 0, -1, 15], "center": [0, 0.5, 0]},
        {"rotate": [0, 0, -1, 30], "center": [0, 0.9, 0]},
        {"rotate": [0, 0, -1, 45], "center": [0, 1.2, 0], "scale": 1.2},
    ],
}


def main(out):
    out.mkdir(parents=True, exist_ok=True)
    man = cgamesh.load(str(ROOT / "data" / "CesiumMan.glb"))

    # One call: the spec's keys, #V×3 float32 positions in world space (the bind pose).
    bent = cgamesh.deform(man, SPEC)
    print(f"deform: {bent.shape[0]} vertices, moved up to {np.abs(bent - man.skin(mode='matrix')[0]).max():.3f}")

    # Bound once, applied per frame: the bend grows from the identity to the spec's keys.
    bender = cgamesh.Deformer(man, SPEC)
    identity = np.tile(cga.Multivector(1.0).value, (len(SPEC["keys"]), 1))
    for i, alpha in enumerate(np.linspace(0, 1, 4)):
        keys = [cga.log_blend(cga.Multivector(a), cga.Multivector(b), alpha) for a, b in zip(identity, bender.keys)]
        frame = bender.apply(keys)
        bender.save(str(out / f"bend_{i}.obj"), frame)
    # The bent rest shape with its rig: it walks again.
    bender.save(str(out / "cesiumman_bend.glb"))

    # A harmonic field on the mesh: 0 at the feet, 1 at the head.
    mesh = man.meshes[0]
    world = man.skin(mode="matrix")[0]
    feet = np.where(world[:, 1] < 0.05)[0]
    head = np.where(world[:, 1] > 1.4)[0]
    field = cgamesh.harmonic_field(mesh.positions, mesh.faces, np.concatenate([feet, head]))
    lam = field.solve(np.concatenate([np.zeros(len(feet)), np.ones(len(head))]))
    print(f"harmonic field: {lam.min():.3f} … {lam.max():.3f} over {lam.shape[0]} vertices")
    print(f"wrote {', '.join(sorted(p.name for p in out.iterdir()))} to {out}")


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out"))
