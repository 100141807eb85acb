"""What a frame costs from Python beyond what hsr bench spends on it: hsr.render() of the bunny at
512x512 (zbuffer + blinn-phong) against the frame loop hsr bench runs (one camera, the plugins made
once, the buffers reused), both timed in this process, alternately. hsr bench itself runs on the same
cell in the same run for comparison; its "total" counts visibility and shading only, without the
clearing and checking of the buffers around them. docs/python.md quotes the result.

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
from hsr import _hsr


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("hsr", help="the hsr executable, for hsr bench")
    parser.add_argument("model", help="the model (models/bunny.obj)")
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--frames", type=int, default=101, help="timed frames (default 101)")
    args = parser.parse_args()

    scene = hsr.load(args.model)
    words = ["loaded-scene", "--width", str(args.size), "--height", str(args.size)]
    loop = _hsr._FrameLoopTimer(scene, words)
    for _ in range(5):
        hsr.render(scene, width=args.size, height=args.size)
        loop.frame_ms()
    python_ms, loop_ms, inside_ms = [], [], []
    for _ in range(args.frames):
        start = time.perf_counter()
        frame = hsr.render(scene, width=args.size, height=args.size)
        python_ms.append((time.perf_counter() - start) * 1e3)
        inside_ms.append(frame.stats["visibility_ms"] + frame.stats["shading_ms"])
        del frame
        loop_ms.append(loop.frame_ms())
    differences = [p - c for p, c in zip(python_ms, loop_ms)]

    with tempfile.TemporaryDirectory() as folder:
        table = os.path.join(folder, "bench.csv")
        subprocess.run([args.hsr, "bench", "--algorithms", "zbuffer", "--models", args.model, "--sizes",
                        str(args.size), "-r", "21", "--csv", table], check=True, capture_output=True)
        with open(table) as f:
            bench_total = float(next(csv.DictReader(f))["total_median_ms"])

    quartiles = statistics.quantiles(differences, n=4)
    print(f"{os.path.basename(args.model)} at {args.size}x{args.size}, zbuffer + blinn-phong, {args.frames} frames "
          "of each, alternately (medians, ms):")
    print(f"  hsr.render() from Python                  {statistics.median(python_ms):8.3f}")
    print(f"  hsr bench's frame loop, in this process   {statistics.median(loop_ms):8.3f}")
    print(f"  Python's cost (the difference, per pair)  {statistics.median(differences):8.3f}"
          f"   (quartiles {quartiles[0]:.3f} .. {quartiles[2]:.3f})")
    print(f"  visibility + shading inside hsr.render()  {statistics.median(inside_ms):8.3f}")
    print(f"  hsr bench's total, same cell, same run    {bench_total:8.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
