#!/usr/bin/env python3
"""Paper Fig. 3 (Kamarianakis & Papagiannakis): cut CesiumMan in two with a plane while he walks,
re-pose the upper piece's arm with a rotation, a translation and a dilation of two joints, and
save the results as glTF (rigged: they animate again) and OBJ (the re-posed surfaces).

    PYTHONPATH=build/python python3 examples/surgery.py [OUT_DIR]
"""

import pathlib
import sys

import cgamesh

ROOT = pathlib.Path(__file__).resolve().parents[1]
ELBOW, WRIST = "nodes[14]", "nodes[15]"
# Fig. 3D: the elbow rotated by 0.7 rad about (0, 1, 1), moved and shrunk to half; the wrist
# rotated by 0.3 rad.
EDITS = [
    {"joint": ELBOW, "rotate": (0, 1, 1, 40.1), "translate": (0.1, 0, 0), "scale": 0.5},
    {"joint": WRIST, "rotate": (0, 1, 1, 17.2)},
]


def main(out):
    out.mkdir(parents=True, exist_ok=True)
    man = cgamesh.load(str(ROOT / "data" / "CesiumMan.glb"))
    walking = man.pose(time=0.5)  # the first clip at t = 0.5 s

    # The cut: the plane y = 0.9 (normal, offset), placed against the walking pose; capped.
    upper, lower = cgamesh.cut(man, (0, 1, 0, 0.9), pose=walking, cap=True)
    print(f"cut: {upper.stats['intersection_points']} intersection points, "
          f"{upper.stats['faces_out'][0]} + {upper.stats['faces_out'][1]} faces")
    upper.save(str(out / "cesium_upper.glb"))
    lower.save(str(out / "cesium_lower.glb"))

    # Re-posing: both pieces keep the skeleton and the clip; edit two joints on top of it.
    for name, piece in [("upper", upper), ("lower", lower)]:
        reposed = piece.model.pose(time=0.5, edits=EDITS)
        piece.model.save(str(out / f"cesium_{name}_reposed.obj"), pose=reposed)
        # The same edits stored as a clip from the rest pose (t = 0) to the edits (t = 1 s), so a
        # glTF viewer plays the re-posing.
        keys = [(0.0, {"joint": ELBOW, "scale": 1}), (0.0, {"joint": WRIST, "scale": 1})] + [(1.0, e) for e in EDITS]
        piece.model.animate(keys, name="fig3").save(str(out / f"cesium_{name}_reposed.glb"))
    print(f"wrote {', '.join(sorted(p.name for p in out.iterdir()))} to {out}")


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out"))
