#!/usr/bin/env python3
"""Times cgamesh from Python against the same work in C++ (issue #18, Benchmarks).

    PYTHONPATH=build-release/python /usr/bin/python3 python/bench/skin_bench.py [build-release/bench/cgamesh_bench]

Prints the median time of Model.skin() (cga skinning, all threads) on CesiumMan and on CesiumMan
subdivided past a million vertices (2 422 358, as the C++ benchmark makes it), and of cga.up()
on 10^6 points batched. Each skin() call also composes the 22 global joint transforms and
allocates its output, as the C++ benchmark's frame does (it builds the palette and the output
every iteration). With the benchmark binary, the same script runs BM_SkinCesiumMan and
BM_SkinMillion (mode cga, all threads) right after, and prints the ratios. Build in Release.
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


def median_seconds(f, repeat):
    f()  # warm-up: first-touch page faults, thread pool start
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def cpp_medians(binary):
    """Median real time (s) of the C++ cga skinning frames, all threads, by benchmark name."""
    out = subprocess.run([binary, "--benchmark_filter=BM_Skin(CesiumMan|Million)/mode:0/threads:0",
                          "--benchmark_format=json", "--benchmark_repetitions=5",
                          "--benchmark_report_aggregates_only=true"], capture_output=True, text=True, check=True)
    unit = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3}
    return {b["run_name"].split("/")[0]: b["real_time"] * unit[b["time_unit"]]
            for b in json.loads(out.stdout)["benchmarks"] if b.get("aggregate_name") == "median"}


def main():
    man = cgamesh.load(str(ROOT / "data" / "CesiumMan.glb"))
    big = man
    while big.meshes[0].positions.shape[0] < 1_000_000:
        big = big.subdivided()
    pose = man.pose(time=0.5)
    rows = [("BM_SkinCesiumMan", man, median_seconds(lambda: man.skin(pose), 200)),
            ("BM_SkinMillion", big, median_seconds(lambda: big.skin(pose), 15))]
    points = np.random.default_rng(0).normal(size=(1_000_000, 3))
    up = median_seconds(lambda: cga.up(points), 5)
    cpp = cpp_medians(sys.argv[1]) if len(sys.argv) > 1 else {}
    for name, model, seconds in rows:
        line = f"skin, cga, all threads, {model.meshes[0].positions.shape[0]} vertices: Python {seconds * 1e3:.3f} ms"
        if name in cpp:
            line += f", C++ {cpp[name] * 1e3:.3f} ms, Python / C++ = {seconds / cpp[name]:.3f}"
        print(line)
    print(f"cga.up of 1e6 points (float64 #N×3 -> #N×32): {up * 1e3:.1f} ms ({up * 1e9 / 1e6:.1f} ns a point)")


if __name__ == "__main__":
    main()
