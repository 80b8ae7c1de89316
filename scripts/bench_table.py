#!/usr/bin/env python3
"""Turns Google Benchmark JSON (cgamesh_bench --benchmark_out=F --benchmark_out_format=json)
into the markdown tables of BENCHMARKS.md, with ratios against the baselines run in the same
binary."""
import json
import re
import sys

MODES = {"0": "cga", "1": "versor", "2": "matrix", "3": "dqs"}


def main(path):
    data = json.load(open(path))
    # The median of a benchmark's repetitions when it was repeated, else its one run.
    rows = {b["name"]: b for b in data["benchmarks"] if b.get("run_type", "iteration") == "iteration"}
    rows.update({re.sub(r"/iterations:\d+|/repeats:\d+", "", b["run_name"]): b
                 for b in data["benchmarks"] if b.get("aggregate_name") == "median"})
    ctx = data["context"]
    print(f"Machine: {ctx.get('num_cpus')} CPUs at {ctx.get('mhz_per_cpu')} MHz, "
          f"{ctx.get('date')}, library build {ctx.get('library_build_type')}\n")

    print("| algebra benchmark | time (ns) |\n|---|---|")
    for name, b in rows.items():
        if not name.startswith(("BM_Skin", "BM_Batch", "BM_Cut", "BM_Tear", "BM_Drill", "BM_Deform", "BM_Render")):
            print(f"| {name} | {b['real_time']:.1f} |")

    # Each table from the benchmarks present (a run may be filtered, e.g. to surgery).
    if "BM_BatchMatrix3x4" in rows:
        base = rows["BM_BatchMatrix3x4"]["items_per_second"]
        print("\n| batch of 8192 points (float) | points/s | time ÷ 3×4 matrix |\n|---|---|---|")
        for name in ("BM_BatchMatrix3x4", "BM_BatchVersorPointMap", "BM_BatchVersorSandwich"):
            ips = rows[name]["items_per_second"]
            print(f"| {name} | {ips / 1e6:.0f} M | {base / ips:.2f} |")

    for model in ("CesiumMan", "Million"):
        sample = next((b for n, b in rows.items() if n.startswith(f"BM_Skin{model}/")), None)
        if sample is None:
            continue

        def skin(mode, threads="1", normals="0", kernel="0", stores="0"):
            return rows.get(f"BM_Skin{model}/mode:{mode}/threads:{threads}/normals:{normals}/kernel:{kernel}"
                            f"/stores:{stores}/real_time")

        bound = sample["stream_vps"]
        two = rows.get(f"BM_StreamBound{model}/threads:2/real_time")
        two = f", 2 threads {two['items_per_second'] / 1e6:.0f} M/s" if two else ""
        # The bound's own row: with --benchmark_enable_random_interleaving its repetitions are
        # spread over the run like the frames', where stream_vps is timed once, at the start.
        row = rows.get(f"BM_StreamBound{model}/threads:1/real_time")
        row_vps = row["items_per_second"] if row else None
        print(f"\n| {model} ({int(sample['vertices'])} vertices; streaming bound {bound / 1e6:.0f} M/s"
              f"{f', its row {row_vps / 1e6:.0f} M/s' if row_vps else ''}{two}) "
              "| vertices/s, 1 thread | of the bound | of the bound's row | ÷ matrix | scalar kernel | vector ÷ scalar "
              "| ÷ avx2 kernel | with normals ÷ without | all threads | ÷ 1 thread |\n|---|---|---|---|---|---|---|---|---|---|---|")
        ref = skin("2")["items_per_second"]
        for mode, label in MODES.items():
            one, scalar, normals, every = skin(mode), skin(mode, kernel="1"), skin(mode, normals="1"), skin(mode, "0")
            avx2 = skin(mode, kernel="3")  # absent (skipped) without AVX2
            ips = one["items_per_second"]
            vs_avx2 = f"{ips / avx2['items_per_second']:.2f}" if avx2 and "items_per_second" in avx2 else "–"
            of_row = f"{ips / row_vps:.2f}" if row_vps else "–"
            print(f"| {label} | {ips / 1e6:.1f} M | {one['of_stream']:.2f} | {of_row} | {ips / ref:.2f} "
                  f"| {scalar['items_per_second'] / 1e6:.1f} M | {ips / scalar['items_per_second']:.2f} | {vs_avx2} "
                  f"| {ips / normals['items_per_second']:.2f} | {every['items_per_second'] / 1e6:.1f} M "
                  f"| {every['items_per_second'] / ips:.2f} |")

    surgery(rows)
    deform(rows)
    pictures(rows)


# The seed's Python on a ~3k-vertex arm (paper section 4.3), milliseconds.
SEED_MS = {"Cut": 4666.0, "Tear": 2437.0, "Drill": 274.0}


def ms(b):
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b.get("time_unit", "ns")]
    return b["real_time"] * scale


def pictures(rows):
    rows = {n.replace("/real_time", ""): b for n, b in rows.items()}
    if "BM_RenderCesiumMan" not in rows:
        return
    print("\n| picture (1280×960, 4× MSAA) | faces | time | pictures/s |\n|---|---|---|---|")
    for name, label in (("BM_RenderCesiumMan", "CesiumMan"), ("BM_RenderMillion", "CesiumMan subdivided")):
        if name in rows:
            t = ms(rows[name])
            print(f"| {label} | {int(rows[name]['faces'])} | {t:.1f} ms | {1000 / t:.1f} |")
    if "BM_RenderSetup" in rows:
        print(f"| set-up once (EGL context, shaders) | | {ms(rows['BM_RenderSetup']):.1f} ms | |")


def surgery(rows):
    print("\n| operation | model | faces | new model: cga | euclidean | ÷ | in place: cga | euclidean | ÷ "
          "| seed ÷ cga (new, in place) |\n|---|---|---|---|---|---|---|---|---|---|")
    for op in ("Cut", "Tear", "Drill"):
        for model in ("CesiumMan", "Ogre", "Million"):
            ga = rows.get(f"BM_{op}{model}/0/0" if op == "Cut" else f"BM_{op}{model}/0")
            eu = rows.get(f"BM_{op}{model}/1/0" if op == "Cut" else f"BM_{op}{model}/1")
            live_ga = rows.get(f"BM_{op}InPlace{model}/0/manual_time")
            live_eu = rows.get(f"BM_{op}InPlace{model}/1/manual_time")
            if not ga or not eu or ga.get("error_occurred") or not live_ga or not live_eu:
                continue
            seed = (f"{SEED_MS[op] / ms(ga):,.0f}×, {SEED_MS[op] / ms(live_ga):,.0f}×" if model == "CesiumMan" else "")
            print(f"| {op.lower()} | {model} | {int(ga.get('faces', 0))} | {ms(ga):.3f} ms | {ms(eu):.3f} ms | "
                  f"{ms(ga) / ms(eu):.2f} | {ms(live_ga):.3f} ms | {ms(live_eu):.3f} ms | "
                  f"{ms(live_ga) / ms(live_eu):.2f} | {seed} |")
    for model in ("CesiumMan", "Ogre", "Million"):
        cap = rows.get(f"BM_Cut{model}/0/1")
        if cap and not cap.get("error_occurred"):
            print(f"| cut + cap | {model} | {int(cap.get('faces', 0))} | {ms(cap):.3f} ms | | | | | | |")


def deform(rows):
    print("\n| deformation | vertices | time | frames/s |\n|---|---|---|---|")
    for name, b in rows.items():
        if name.startswith("BM_Deform") and not b.get("error_occurred"):
            fps = f"{b['fps']:.0f}" if "fps" in b else ""
            print(f"| {name} | {int(b.get('vertices', 0)) or ''} | {ms(b):.2f} ms | {fps} |")


if __name__ == "__main__":
    main(sys.argv[1])
