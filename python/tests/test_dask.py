"""Tests of hsr.dask on a LocalCluster of two worker processes: files byte-identical to
`hsr render --jobs` with a worker killed in the middle of the batch, failures in the summary, arrays
equal to hsr.render's, and `python3 -m hsr.dask`.

The hsr command for the reference renders is $HSR_EXECUTABLE, else build/hsr of the source folder.
"""

import logging
import os
import pathlib
import signal
import subprocess
import sys
import threading
import time

import pytest

distributed = pytest.importorskip("distributed", reason="hsr.dask needs Dask's distributed (python3-distributed)")
numpy = pytest.importorskip("numpy", reason="hsr needs numpy")

import hsr  # noqa: E402
import hsr.dask  # noqa: E402

SOURCE = pathlib.Path(__file__).resolve().parents[2]
MODELS = SOURCE / "models"
HSR = os.environ.get("HSR_EXECUTABLE") or str(SOURCE / "build" / "hsr")
SIZE = "--width 96 --height 96"


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=":0", silence_logs=logging.CRITICAL)
    client = distributed.Client(cluster)
    yield client
    client.close()
    cluster.close()


def good_lines():
    """Lines of a jobs file that all render: four models, three yaws, two algorithms, a turntable
    with its depth, a picture in a subfolder and a line drawing."""
    lines = []
    for model in ["cube.obj", "octahedron.ply", "pyramid.stl", "boxes.scene"]:
        stem = model.split(".")[0]
        for yaw in [0, 40, 80]:
            for algorithm in ["zbuffer", "painter"]:
                lines.append(f"{MODELS / model} --yaw {yaw} --pitch 20 -a {algorithm} {SIZE} "
                             f"-o {stem}-{yaw}-{algorithm}.png")
    lines.append(f"{MODELS / 'tetrahedron.off'} --views 4 {SIZE} -o turn-%02d.png --depth-out turn-depth-%02d.npy")
    lines.append(f"'{MODELS / 'three-polygons.scene'}' -l facecolor {SIZE} -o 'sub folder/three polygons.png'")
    lines.append(f"{MODELS / 'boxes.scene'} -a roberts --edges all --hidden dashed {SIZE} -o boxes-lines.svg")
    return lines


def hsr_jobs(folder, lines):
    """Renders the lines with `hsr render --jobs` in `folder`; returns its files and their bytes."""
    folder.mkdir(parents=True)
    (folder / "sub folder").mkdir()
    (folder / "reference.jobs").write_text("\n".join(lines) + "\n")
    subprocess.run([HSR, "render", "--jobs", "reference.jobs"], cwd=folder, check=True, capture_output=True)
    (folder / "reference.jobs").unlink()
    return files_in(folder)


def files_in(folder):
    return {str(path.relative_to(folder)): path.read_bytes() for path in sorted(folder.rglob("*")) if path.is_file()}


def kill_a_busy_worker(client):
    """SIGKILL to a worker process that has tasks (its nanny starts another); its pid, or None when
    no worker had a task left."""
    busy = [worker for worker, keys in client.processing().items() if keys]
    if not busy:
        return None
    pid = client.run(os.getpid, workers=[busy[0]])[busy[0]]
    os.kill(pid, signal.SIGKILL)
    return pid


def test_files_are_those_of_hsr_jobs_when_a_worker_dies(client, tmp_path, monkeypatch):
    lines = good_lines()
    expected = hsr_jobs(tmp_path / "reference", lines)

    work = tmp_path / "work"
    (work / "sub folder").mkdir(parents=True)
    (work / "broken.obj").write_text("v 1 2\nf 1 2 9\n")
    jobs_file = work / "batch.jobs"
    jobs_file.write_text("# a batch\n\n" + "\n".join(lines[:6]) + "\n"
                         f"broken.obj {SIZE} -o broken.png\n"
                         f"{MODELS / 'cube.obj'} -a zbuffer:no-such-key=1 {SIZE} -o plugin-error.png\n"
                         + "\n".join(lines[6:]) + "\n")
    # What a worker killed while writing leaves: a temporary file of an output, removed after the
    # batch; another program's temporary file stays.
    (work / ".cube-0-zbuffer.png.tmp-4242-0123456789abcdef").write_bytes(b"half a picture")
    (work / ".notes.txt.tmp-4242-0123456789abcdef").write_bytes(b"not the batch's")
    monkeypatch.chdir(work)

    # A worker is killed as soon as one has a task, by a thread of its own: the batch's first
    # results may come back together, too late to find a worker still busy.
    finished_so_far, killed, batch_over = [0], [], threading.Event()

    def progress(done, failed, total):
        finished_so_far[0] = done + failed

    def kill_when_busy():
        while not killed and not batch_over.is_set():
            pid = kill_a_busy_worker(client)
            if pid is not None:
                killed.append((pid, finished_so_far[0]))
            time.sleep(0.002)

    watcher = threading.Thread(target=kill_when_busy)
    watcher.start()
    try:
        summary = hsr.dask.render_many("batch.jobs", client, progress=progress)
    finally:
        batch_over.set()
        watcher.join()
    killed.append((None, None))

    pid, finished = killed[0]
    assert pid is not None and finished < len(lines) // 2, "the batch was half done before a worker was killed"
    assert pid not in client.run(os.getpid).values()
    assert summary.done == len(lines)
    failures = {job.origin: error for job, error in summary.failures}
    assert sorted(failures) == ["batch.jobs:10", "batch.jobs:9"]
    assert "broken.obj" in failures["batch.jobs:9"]
    assert "no-such-key" in failures["batch.jobs:10"]
    assert not summary.ok
    assert "failed: batch.jobs:9: " in str(summary)

    produced = files_in(work)
    for left in ["batch.jobs", "broken.obj", ".notes.txt.tmp-4242-0123456789abcdef"]:
        produced.pop(left)
    assert sorted(produced) == sorted(expected)
    for name, data in expected.items():
        assert produced[name] == data, f"{name} differs from hsr render --jobs"
    assert summary.removed >= 1


def test_arrays_are_those_of_hsr_render(client):
    models = [MODELS / "cube.obj", MODELS / "boxes.scene", MODELS / "missing.obj"]
    batch = hsr.dask.jobs(models, hsr.dask.turntable(3, pitch=20), ["zbuffer", "painter"], width=64, height=48)
    summary = hsr.dask.render_many(batch, client, out=None, progress=False)

    assert len(summary.frames) == len(batch) == 18
    for job, frame, error in zip(summary.jobs, summary.frames, summary.errors):
        if job.model.endswith("missing.obj"):
            assert frame is None and "missing.obj" in error
            continue
        assert error is None
        reference = hsr.render(hsr.load(job.model), **job.keywords)
        assert frame.color.shape == (48, 64, 3)
        numpy.testing.assert_array_equal(frame.color, reference.color)
        numpy.testing.assert_array_equal(frame.depth, reference.depth)
        numpy.testing.assert_array_equal(frame.face_id, reference.face_id)
    assert summary.done == 12


def test_pictures_of_the_product_are_those_of_hsr_render(client, tmp_path):
    batch = hsr.dask.jobs([MODELS / "pyramid.stl"], [{"yaw": 15.5}, {"eye": "3,2,4"}], ["zbuffer"],
                          ["lambert", "blinn-phong"], width=64, height=64, zoom=1.25)
    summary = hsr.dask.render_many(batch, client, out=tmp_path / "frames", progress=False)
    assert summary.ok, str(summary)
    names = sorted(path.name for path in (tmp_path / "frames").iterdir())
    assert names == sorted(job.name for job in batch)
    assert "pyramid-01-zbuffer-lambert.png" in names
    for job in batch:
        reference = tmp_path / "reference.png"
        subprocess.run([HSR, "render", *job.command(), "-o", str(reference)], check=True, capture_output=True)
        assert (tmp_path / "frames" / job.name).read_bytes() == reference.read_bytes(), job.name


def test_two_jobs_writing_one_file_are_refused(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "twice.jobs").write_text(f"{MODELS / 'cube.obj'} -o a.png\n{MODELS / 'pyramid.stl'} --output=a.png\n")
    with pytest.raises(hsr.UsageError, match=r"twice.jobs:2: .*a.png' is written by twice.jobs:1 too"):
        hsr.dask.render_many("twice.jobs", client=None)


def test_a_jobs_line_reads_from_the_files_folder_and_writes_into_the_current_one(client, tmp_path, monkeypatch):
    (tmp_path / "batch").mkdir()
    (tmp_path / "batch" / "cube.obj").write_bytes((MODELS / "cube.obj").read_bytes())
    (tmp_path / "batch" / "here.jobs").write_text(f"cube.obj {SIZE} -o cube.png\n{MODELS / 'pyramid.stl'} {SIZE}\n"
                                                  "cube.obj --no-such-option\n")
    monkeypatch.chdir(tmp_path)
    jobs = hsr.dask.read_jobs_file("batch/here.jobs")
    assert jobs[0].words == ("--model=batch/cube.obj", *SIZE.split(), "-o", "cube.png")
    assert jobs[1].words == (str(MODELS / "pyramid.stl"), *SIZE.split())
    assert jobs[2].words == ("cube.obj", "--no-such-option")  # its mistake is its error when it runs
    summary = hsr.dask.render_many(jobs[:2], client, progress=False)
    assert summary.ok, summary.failures
    assert sorted(path.name for path in tmp_path.iterdir()) == ["batch", "cube.png", "pyramid.png"]


def run_module(*arguments, cwd):
    package_folder = str(pathlib.Path(hsr.__file__).resolve().parents[1])
    environment = dict(os.environ, PYTHONPATH=os.pathsep.join([package_folder, os.environ.get("PYTHONPATH", "")]))
    return subprocess.run([sys.executable, "-m", "hsr.dask", *arguments], cwd=cwd, env=environment,
                          capture_output=True, text=True, timeout=120)


def test_command_line(tmp_path):
    (tmp_path / "all.jobs").write_text(f"{MODELS / 'cube.obj'} {SIZE} -o cube.png\n"
                                       f"{MODELS / 'octahedron.ply'} --views 2 {SIZE} -o octahedron-%d.png\n"
                                       f"{MODELS / 'missing.obj'} {SIZE} -o missing.png\n")
    run = run_module("all.jobs", "--workers", "2", cwd=tmp_path)
    assert run.returncode == 1, run.stderr
    assert "Traceback" not in run.stderr
    assert "3 jobs in" in run.stdout and "2 done, 1 failed" in run.stdout
    assert "failed: all.jobs:3: " in run.stdout
    assert "3/3 jobs, 1 failed" in run.stderr  # the progress line
    assert sorted(path.name for path in tmp_path.iterdir()) == ["all.jobs", "cube.png", "octahedron-0.png",
                                                                "octahedron-1.png"]

    run = run_module("--model", str(MODELS / "cube.obj"), "--views", "2", "--width", "64", "--height", "64",
                     "--out", "frames", "--workers", "1", "--quiet", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert run.stderr == ""
    assert sorted(path.name for path in (tmp_path / "frames").iterdir()) == [
        "cube-00-zbuffer-blinn-phong.png", "cube-01-zbuffer-blinn-phong.png"]


@pytest.mark.parametrize("arguments, message", [
    (["no-such.jobs"], "--jobs 'no-such.jobs': cannot read it"),
    (["all.jobs", "--scheduler", "garbage::x"], "--scheduler 'garbage::x': cannot reach it"),
    (["all.jobs", "--scheduler", "tcp://127.0.0.1:1", "--timeout", "1"], "cannot reach it"),
    (["all.jobs", "--bogus"], "unrecognized arguments: --bogus"),
    (["--workers", "2"], "give a JOBS file or --model"),
])
def test_bad_input_is_one_line(tmp_path, arguments, message):
    (tmp_path / "all.jobs").write_text(f"{MODELS / 'cube.obj'} -o cube.png\n")
    run = run_module(*arguments, cwd=tmp_path)
    assert run.returncode in (1, 2)
    assert run.stdout == ""
    assert run.stderr.count("\n") == 1 and run.stderr.startswith("hsr.dask: error: "), run.stderr
    assert message in run.stderr
