#!/usr/bin/env python3
"""Turns Google Benchmark JSON (cgamesh_bench --benchmark_out=F --benchmark_out_format=json)
into the markdown tables of BENCHMARKS.md, with ratios against the baselines run in the same
binary."""
import json
import sys

MODES = {"0": "cga", "1": "versor", "2": "matrix", "3": "dqs"}


def main(path):
    data = json.load(open(path))
    rows = {b["name"]: b for b in data["benchmarks"] if b.get("run_type", "iteration") == "iteration"}
    ctx = data["context"]
    print(f"Machine: {ctx.get('num_cpus')} CPUs at {ctx.get('mhz_per_cpu')} MHz, "
          f"{ctx.get('date')}, library build {ctx.get('library_build_type')}\n")

    print("| algebra benchmark | time (ns) |\n|---|---|")
    for name, b in rows.items():
        if not name.startswith("BM_Skin") and not name.startswith("BM_Batch"):
            print(f"| {name} | {b['real_time']:.1f} |")

    base = rows["BM_BatchMatrix3x4"]["items_per_second"]
    print("\n| batch of 8192 points (float) | points/s | time ÷ 3×4 matrix |\n|---|---|---|")
    for name in ("BM_BatchMatrix3x4", "BM_BatchVersorPointMap", "BM_BatchVersorSandwich"):
        ips = rows[name]["items_per_second"]
        print(f"| {name} | {ips / 1e6:.0f} M | {base / ips:.2f} |")

    for model in ("CesiumMan", "Million"):
        sample = next(b for n, b in rows.items() if n.startswith(f"BM_Skin{model}/"))
        print(f"\n| {model} ({int(sample['vertices'])} vertices) | threads | vertices/s | ÷ matrix |\n|---|---|---|---|")
        for threads in ("1", "0"):
            ref = rows[f"BM_Skin{model}/mode:2/threads:{threads}/real_time"]["items_per_second"]
            for mode, label in MODES.items():
                ips = rows[f"BM_Skin{model}/mode:{mode}/threads:{threads}/real_time"]["items_per_second"]
                print(f"| {label} | {'1' if threads == '1' else 'all'} | {ips / 1e6:.1f} M | {ips / ref:.2f} |")


if __name__ == "__main__":
    main(sys.argv[1])
