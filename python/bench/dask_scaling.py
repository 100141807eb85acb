"""How hsr.dask scales with worker processes on one machine: the same batch rendered in turns by a
LocalCluster of one worker process and by one of two (or the counts given), the median time of each,
and each median against the first.

    PYTHONPATH=build/python /usr/bin/python3 python/bench/dask_scaling.py [--models 200] [--views 6]
        [--size 256] [--repeats 3] [--workers 1 2]

The batch is --models model files × --views turntable views at --size² pixels, zbuffer and
Blinn-Phong, written as PNGs. The model files are copies, under names of their own, of the meshes of
models/ (the bunny and Suzanne once models/fetch-models.sh has fetched them), taken in turn: each
is a model of its own to hsr, loaded once for its views. The clusters are started (and their
workers have imported hsr) before any timing; each run writes into a fresh folder, and the runs of
the clusters alternate, so that a machine that gets busier slows them alike. docs/distributed.md
quotes its results.
"""

import argparse
import os
import pathlib
import platform
import shutil
import statistics
import sys
import tempfile
import time

try:
    import distributed
except ImportError:
    print("skipped: no Dask (Debian's python3-distributed)")
    sys.exit(77)

import hsr
import hsr.dask

SOURCE = pathlib.Path(__file__).resolve().parents[2]
MESHES = ["bunny.obj", "monkey.obj", "cube.obj", "octahedron.ply", "pyramid.stl", "tetrahedron.off"]


def present_meshes() -> list[pathlib.Path]:
    return [SOURCE / "models" / name for name in MESHES if (SOURCE / "models" / name).is_file()]


def model_files(folder: pathlib.Path, count: int) -> list[pathlib.Path]:
    """`count` model files in `folder`: copies of the meshes of models/ that are there, in turn."""
    meshes = present_meshes()
    files = []
    for number in range(count):
        mesh = meshes[number % len(meshes)]
        copy = folder / f"model-{number:03d}-{mesh.name}"
        shutil.copyfile(mesh, copy)
        files.append(copy)
    return files


def warm(client: distributed.Client, workers: int) -> None:
    """Waits for every worker and has each import hsr, so that no timing includes either."""
    client.wait_for_workers(workers)
    client.run(lambda: __import__("hsr.dask") and None)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--models", type=int, default=200)
    parser.add_argument("--views", type=int, default=6)
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    arguments = parser.parse_args()

    with tempfile.TemporaryDirectory(prefix="hsr-dask-scaling-") as scratch:
        scratch = pathlib.Path(scratch)
        (scratch / "models").mkdir()
        models = model_files(scratch / "models", arguments.models)
        batch = hsr.dask.jobs(models, hsr.dask.turntable(arguments.views, pitch=20), width=arguments.size,
                              height=arguments.size)
        print(f"{len(batch)} renders: {arguments.models} models ({', '.join(m.name for m in present_meshes())}"
              f" in turn) x {arguments.views} views at {arguments.size}x{arguments.size}, zbuffer, blinn-phong;"
              f" {platform.node()}, {os.cpu_count()} cores, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
        clusters = {}
        try:
            for workers in arguments.workers:
                clusters[workers] = hsr.dask.local_client(workers)
                warm(clusters[workers], workers)
            seconds = {workers: [] for workers in arguments.workers}
            for repeat in range(arguments.repeats):
                for workers, client in clusters.items():
                    out = scratch / f"out-{workers}-{repeat}"
                    start = time.perf_counter()
                    summary = hsr.dask.render_many(batch, client, out=out, progress=False)
                    took = time.perf_counter() - start
                    if not summary.ok:
                        print(summary, file=sys.stderr)
                        return 1
                    seconds[workers].append(took)
                    print(f"run {repeat + 1}: {workers} worker process{'es' if workers > 1 else ''}: {took:.2f} s "
                          f"({summary.tasks} tasks)", flush=True)
                    shutil.rmtree(out)
        finally:
            for client in clusters.values():
                cluster = client.cluster
                client.close()
                cluster.close()

    first = arguments.workers[0]
    baseline = statistics.median(seconds[first])
    print(f"\n| worker processes | median of {arguments.repeats} (s) | renders/s | speed-up against {first} |")
    print("| ---: | ---: | ---: | ---: |")
    for workers, times in seconds.items():
        median = statistics.median(times)
        print(f"| {workers} | {median:.2f} | {len(batch) / median:.0f} | {baseline / median:.2f}x |")
    for workers in arguments.workers[1:]:
        rounds = [one / other for one, other in zip(seconds[first], seconds[workers])]
        print(f"\n{first} against {workers} in each round: {', '.join(f'{r:.2f}x' for r in rounds)} "
              f"(median {statistics.median(rounds):.2f}x)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
