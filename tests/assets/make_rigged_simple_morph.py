#!/usr/bin/env python3
"""Writes rigged_simple_morph.glb: RiggedSimple.glb (skinned, animated) with two morph targets
and an animation of their weights, the case of a skinned head with blend shapes in small.

  target "bulge": every vertex moves outward from the cylinder's axis (dense; no normals)
  target "tip":   only the upper half moves, up and sideways (written sparse; normal displacements)
  mesh.weights [0.25, 0]; node.weights [0.5, 0] (the node's override the mesh's);
  the animation drives both weights LINEAR over the clip's own key times.

Run from tests/assets: python3 make_rigged_simple_morph.py
"""
import json
import struct

src = open("RiggedSimple.glb", "rb").read()
json_len = struct.unpack("<I", src[12:16])[0]
gltf = json.loads(src[20 : 20 + json_len])
bin_start = 20 + json_len + 8
bin_len = struct.unpack("<I", src[20 + json_len : 24 + json_len])[0]
data = bytearray(src[bin_start : bin_start + bin_len])


def accessor_floats(index):
    a = gltf["accessors"][index]
    v = gltf["bufferViews"][a["bufferView"]]
    n = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[a["type"]]
    off = v.get("byteOffset", 0) + a.get("byteOffset", 0)
    stride = v.get("byteStride", 4 * n)
    return [list(struct.unpack_from("<%df" % n, data, off + i * stride)) for i in range(a["count"])]


def add_view(payload):
    while len(data) % 4:
        data.append(0)
    gltf["bufferViews"].append({"buffer": 0, "byteOffset": len(data), "byteLength": len(payload)})
    data.extend(payload)
    return len(gltf["bufferViews"]) - 1


def add_accessor(rows, kind, bounds=False):
    flat = [x for r in rows for x in r]
    a = {"bufferView": add_view(struct.pack("<%df" % len(flat), *flat)), "componentType": 5126,
         "count": len(rows) if kind != "SCALAR" else len(flat), "type": kind}
    if bounds:
        a["min"] = [min(r[c] for r in rows) for c in range(3)]
        a["max"] = [max(r[c] for r in rows) for c in range(3)]
    gltf["accessors"].append(a)
    return len(gltf["accessors"]) - 1


def add_sparse(n, moved, bounds=False):
    """A VEC3 accessor of n rows, zero but for moved = {index: (x, y, z)}."""
    idx = sorted(moved)
    rows = [moved[i] for i in idx]
    a = {"componentType": 5126, "count": n, "type": "VEC3",
         "sparse": {"count": len(idx),
                    "indices": {"bufferView": add_view(struct.pack("<%dI" % len(idx), *idx)), "componentType": 5125},
                    "values": {"bufferView": add_view(struct.pack("<%df" % (3 * len(idx)), *[x for r in rows for x in r]))}}}
    if bounds:
        a["min"] = [min(0.0, min(r[c] for r in rows)) for c in range(3)]
        a["max"] = [max(0.0, max(r[c] for r in rows)) for c in range(3)]
    gltf["accessors"].append(a)
    return len(gltf["accessors"]) - 1


prim = gltf["meshes"][0]["primitives"][0]
pos = accessor_floats(prim["attributes"]["POSITION"])
n = len(pos)
zs = sorted(p[2] for p in pos)
z_mid = zs[n // 2]
bulge = [[0.3 * p[0], 0.3 * p[1], 0.0] for p in pos]
tip = {i: (0.4, 0.0, 0.8) for i, p in enumerate(pos) if p[2] > z_mid}
tip_normals = {i: (0.2, 0.0, -0.1) for i in tip}
prim["targets"] = [
    {"POSITION": add_accessor(bulge, "VEC3", bounds=True)},
    {"POSITION": add_sparse(n, tip, bounds=True), "NORMAL": add_sparse(n, tip_normals)},
]
mesh = gltf["meshes"][0]
mesh["weights"] = [0.25, 0.0]
mesh["extras"] = {"targetNames": ["bulge", "tip"]}
gltf["nodes"][1]["weights"] = [0.5, 0.0]

anim = gltf["animations"][0]
times_accessor = anim["samplers"][0]["input"]
times = [t[0] for t in accessor_floats(times_accessor)]
keys = [[0.0, 0.0], [1.0, 0.5], [0.2, 1.0]][: len(times)]
anim["samplers"].append({"input": times_accessor, "interpolation": "LINEAR",
                         "output": add_accessor(keys, "SCALAR")})
anim["channels"].append({"sampler": len(anim["samplers"]) - 1, "target": {"node": 1, "path": "weights"}})

while len(data) % 4:
    data.append(0)
gltf["buffers"] = [{"byteLength": len(data)}]
text = json.dumps(gltf, separators=(",", ":")).encode()
text += b" " * ((4 - len(text) % 4) % 4)
out = struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(data))
out += struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(data), 0x004E4942) + bytes(data)
open("rigged_simple_morph.glb", "wb").write(out)
print("rigged_simple_morph.glb: %d vertices, times %s, %d tip vertices" % (n, times, len(tip)))
