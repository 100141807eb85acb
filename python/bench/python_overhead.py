"""What a frame costs from Python beyond what hsr bench times: hsr.render() of the bunny at 512x512
(zbuffer + blinn-phong), its wall time against the visibility and shading times the same frame
reports, which are what hsr bench's "total" measures. Then hsr bench itself on the same cell, in the
same run, for comparison. docs/python.md quotes the result.

    PYTHONPATH=build/python /usr/bin/python3 python/bench/python_overhead.py build/hsr models/bunny.obj
"""

import argparse
import csv
import os
import statistics
import subprocess
import sys
import tempfile
import time

import hsr


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("hsr", help="the hsr executable, for hsr bench")
    parser.add_argument("model", help="the model (models/bunny.obj)")
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--frames", type=int, default=101, help="timed frames (default 101)")
    args = parser.parse_args()

    scene = hsr.load(args.model)
    for _ in range(5):
        hsr.render(scene, width=args.size, height=args.size)
    walls, inside, overheads = [], [], []
    for _ in range(args.frames):
        start = time.perf_counter()
        frame = hsr.render(scene, width=args.size, height=args.size)
        wall = (time.perf_counter() - start) * 1e3
        stats = frame.stats
        measured = stats["visibility_ms"] + stats["shading_ms"]
        walls.append(wall)
        inside.append(measured)
        overheads.append(wall - measured)

    with tempfile.TemporaryDirectory() as folder:
        table = os.path.join(folder, "bench.csv")
        subprocess.run([args.hsr, "bench", "--algorithms", "zbuffer", "--models", args.model, "--sizes",
                        str(args.size), "-r", "21", "--csv", table], check=True, capture_output=True)
        with open(table) as f:
            bench_total = float(next(csv.DictReader(f))["total_median_ms"])

    print(f"hsr.render, {os.path.basename(args.model)} at {args.size}x{args.size}, zbuffer + blinn-phong, "
          f"{args.frames} frames (medians, ms):")
    print(f"  wall time of the call                    {statistics.median(walls):8.3f}")
    print(f"  visibility + shading inside it           {statistics.median(inside):8.3f}")
    print(f"  Python's cost (wall - inside, per frame) {statistics.median(overheads):8.3f}"
          f"   (quartiles {statistics.quantiles(overheads, n=4)[0]:.3f} .. {statistics.quantiles(overheads, n=4)[2]:.3f})")
    print(f"  hsr bench total, same cell, same run     {bench_total:8.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
