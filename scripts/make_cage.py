#!/usr/bin/env python3
"""Writes data/cesiumman_cage.obj: a coarse hand-made cage of CesiumMan for the cage demo.

The cage is the boundary of a union of cells of a coarse grid (the grid lines below, chosen by
hand around the bind pose that `cgamesh info data/CesiumMan.glb` boxes in world space): a column
for the body and a bar for the arms. Each boundary cell face becomes two triangles, oriented
outwards, so the cage is closed, edge-manifold and consistently oriented; `cgamesh deform` checks
that it encloses every vertex.

Usage: scripts/make_cage.py [OUT.obj]
"""
import sys

# Grid lines per axis (world space, metres): x front-back, y up, z sideways. CesiumMan's bind pose
# spans x [-0.131, 0.181], y [0, 1.507], z [-0.569, 0.569]: a body within |z| < 0.17 and arms
# hanging down and out from the shoulders (y ≈ 1.06 at |z| = 0.2) to the hands (y ≈ 0.78 at
# |z| = 0.57).
XS = [-0.16, 0.21]
YS = [-0.03, 0.4, 0.72, 0.85, 0.96, 1.1, 1.3, 1.56]
ZS = [-0.62, -0.4, -0.2, 0.2, 0.4, 0.62]


def occupied(i, j, k):
    """Cell (i, j, k) spans XS[i..i+1] × YS[j..j+1] × ZS[k..k+1]."""
    del i  # one cell deep
    body = k == 2
    forearms = k in (0, 4) and j in (2, 3)
    upper_arms = k in (1, 3) and j in (3, 4)
    return body or forearms or upper_arms


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "data/cesiumman_cage.obj"
    n = (len(XS) - 1, len(YS) - 1, len(ZS) - 1)
    cells = {(i, j, k) for i in range(n[0]) for j in range(n[1]) for k in range(n[2]) if occupied(i, j, k)}
    index, vertices, faces = {}, [], []

    def vertex(q):
        if q not in index:
            index[q] = len(vertices)
            vertices.append((XS[q[0]], YS[q[1]], ZS[q[2]]))
        return index[q]

    for (i, j, k) in sorted(cells):
        for axis in range(3):
            for side in (0, 1):
                step = [0, 0, 0]
                step[axis] = 1 if side else -1
                if (i + step[0], j + step[1], k + step[2]) in cells:
                    continue  # an inner face
                b, c = (axis + 1) % 3, (axis + 2) % 3
                corners = []
                for db, dc in ((0, 0), (1, 0), (1, 1), (0, 1)):
                    q = [i, j, k]
                    q[axis] += side
                    q[b] += db
                    q[c] += dc
                    corners.append(vertex(tuple(q)))
                # (b, c) turns counter-clockwise about +axis: outward on the + side.
                if not side:
                    corners = [corners[0], corners[3], corners[2], corners[1]]
                faces.append((corners[0], corners[1], corners[2]))
                faces.append((corners[0], corners[2], corners[3]))
    with open(out, "w") as f:
        f.write("# CesiumMan cage for the cage demo, written by scripts/make_cage.py\n")
        for v in vertices:
            f.write("v %g %g %g\n" % v)
        for t in faces:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))
    print("%s: %d vertices, %d faces" % (out, len(vertices), len(faces)))


if __name__ == "__main__":
    main()
