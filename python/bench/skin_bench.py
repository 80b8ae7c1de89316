#!/usr/bin/env python3
"""Times cgamesh from Python against the same work in C++ (issue #18, Benchmarks).

    PYTHONPATH=build/python python3 python/bench/skin_bench.py [build/bench/cgamesh_bench]

Prints the median time of Model.skin() on CesiumMan (cga skinning, all threads; each call also
composes the 22 global joint transforms, which the C++ benchmark does once) and of cga.up() on 10^6
points batched; with the benchmark binary, also the C++ time of the same skinning
(BM_SkinCesiumMan/mode:0/threads:0) and the ratio. Build in Release for meaningful numbers.
"""

import json
import pathlib
import subprocess
import sys
import time

import numpy as np

import cgamesh
from cgamesh import cga

ROOT = pathlib.Path(__file__).resolve().parents[2]


def median_seconds(f, repeat=50):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def main():
    man = cgamesh.load(str(ROOT / "data" / "CesiumMan.glb"))
    pose = man.pose(time=0.5)
    skin = median_seconds(lambda: man.skin(pose))
    print(f"python skin CesiumMan ({man.meshes[0].positions.shape[0]} vertices): {skin * 1e6:.1f} us")
    points = np.random.default_rng(0).normal(size=(1_000_000, 3))
    up = median_seconds(lambda: cga.up(points), repeat=5)
    print(f"python cga.up of 1e6 points: {up * 1e3:.1f} ms")
    if len(sys.argv) > 1:
        out = subprocess.run([sys.argv[1], "--benchmark_filter=BM_SkinCesiumMan/mode:0/threads:0",
                              "--benchmark_format=json", "--benchmark_repetitions=5",
                              "--benchmark_report_aggregates_only=true"], capture_output=True, text=True, check=True)
        runs = [b for b in json.loads(out.stdout)["benchmarks"] if b.get("aggregate_name") == "median"]
        cpp = runs[0]["real_time"] * {"ns": 1e-9, "us": 1e-6, "ms": 1e-3}[runs[0]["time_unit"]]
        print(f"C++ skin CesiumMan: {cpp * 1e6:.1f} us; Python / C++ = {skin / cpp:.2f}")


if __name__ == "__main__":
    main()
