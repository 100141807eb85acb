"""Many renders on a Dask cluster: hsr.dask.render_many, and `python3 -m hsr.dask JOBS`.

A batch is a list of jobs, each one `hsr render`: the product of models, cameras, algorithms and
lightings (jobs()), or the lines of an `hsr render --jobs` file (read_jobs_file()). The jobs that
load the same scene (equal hsr.scene_key) go to one task, which loads the model once for all of
them; a model is split over a few tasks only when there are fewer models than worker threads. A
task writes its files exactly as `hsr render` would (each atomically: a temporary name beside the
target, then a rename), or sends the pictures back as numpy arrays. A failing job is recorded in
the summary and the batch goes on. A worker that dies costs its tasks a rerun, which replaces the
same files; the temporary files it left beside the batch's outputs are removed after the batch.

    python3 -m hsr.dask JOBS [--scheduler tcp://HOST:8786 | --workers N]
    python3 -m hsr.dask --model a.obj b.ply --views 6 --width 256 --height 256 --out frames

docs/distributed.md explains it. Dask's distributed package (Debian: python3-distributed) is needed
by this module only; `import hsr` does not import it. It is one file of three parts (the client's,
the workers', the command line's) because the workers import the functions of their tasks by this
module's name, and `python3 -m hsr.dask` runs it as it is.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import functools
import inspect
import itertools
import logging
import math
import multiprocessing
import os
import re
import socket
import stat
import sys
import threading
import time
import uuid
from typing import Any, Callable, Iterable, Mapping, Sequence

import hsr
from hsr import _hsr, _options

try:
    import dask
    import distributed
except ImportError as missing:
    raise ImportError("hsr.dask needs Dask's distributed package (Debian: python3-distributed)") from missing

__all__ = ["Job", "FrameArrays", "Summary", "jobs", "turntable", "read_jobs_file", "render_many", "main"]

# The temporary file of an atomic write by hsr: ".<name>.tmp-<pid>-<random>", the name cut at 200 bytes.
_TEMPORARY_NAME = re.compile(r"\.(.+)\.tmp-[0-9]+-[0-9a-f]{16}", re.DOTALL)

# Tasks a worker thread gets, at most, when a batch has many models: enough that the threads end
# together, few enough that the scheduler's cost per task does not count.
_TASKS_PER_THREAD = 8

# How long local worker processes may take to start, on a busy machine.
_WORKERS_START_SECONDS = 60

_UNGUARDED_SCRIPT = ("local worker processes start by importing the script that started them: in a script, "
                     "run the batch under `if __name__ == \"__main__\":`")

# The limits of an `hsr render --jobs` file (docs/many-frames.md).
_MAX_JOB_FILE_BYTES = 64 << 20

@dataclasses.dataclass(frozen=True, eq=False)
class Job:
    """One render of a batch.

    Either a line of an `hsr render --jobs` file (`words`: its options as hsr render takes them,
    paths taken from the current folder: read_jobs_file() puts the jobs file's folder in front of the
    files the line reads), or a model with keywords of hsr.load and hsr.render and
    the file name of its picture (`model`, `keywords`, `name`: made by jobs()). `origin` names the job in the
    summary: "FILE:LINE" for a line, the picture's name for the others.
    """

    origin: str
    words: tuple[str, ...] = ()
    model: str | None = None
    keywords: Mapping[str, Any] = dataclasses.field(default_factory=dict)
    name: str | None = None

    def command(self, out: str | None = None) -> list[str]:
        """The options of the `hsr render` this job is; its picture goes into folder `out`."""
        if self.model is None:
            return list(self.words)
        words = [_options.model_path(self.model), *_option_words(self.keywords)]
        if out is not None:
            words += ["-o", os.path.join(out, self.name)]
        return words

    def __str__(self) -> str:
        return self.origin


@dataclasses.dataclass(frozen=True, eq=False)
class FrameArrays:
    """A rendered picture sent back from a worker: numpy copies of hsr.render's frame.

    color: (height, width, 3) uint8; depth: (height, width) float32, +inf where nothing is drawn;
    face_id: (height, width, 3) int32 of object, face, instance (-1 where nothing is drawn);
    stats: the frame's statistics.
    """

    color: Any
    depth: Any
    face_id: Any
    stats: dict


@dataclasses.dataclass(eq=False)
class Summary:
    """What a batch did: per job, None when it was done or its one-line error message.

    `frames` holds, per job, the FrameArrays of a batch run with out=None (None for a failed job).
    `removed` counts the temporary files that dead workers left beside the outputs and that were
    removed after the batch.
    """

    jobs: list[Job]
    errors: list[str | None]
    frames: list[FrameArrays | None] | None
    seconds: float
    workers: int
    tasks: int
    removed: int = 0

    @property
    def done(self) -> int:
        return sum(error is None for error in self.errors)

    @property
    def failures(self) -> list[tuple[Job, str]]:
        return [(job, error) for job, error in zip(self.jobs, self.errors) if error is not None]

    @property
    def ok(self) -> bool:
        return self.done == len(self.jobs)

    def __str__(self) -> str:
        lines = [f"{len(self.jobs)} jobs in {self.tasks} tasks on {self.workers} worker threads, "
                 f"{self.seconds:.1f} s: {self.done} done, {len(self.jobs) - self.done} failed"]
        lines += [f"failed: {job.origin}: {error}" for job, error in self.failures]
        if self.removed:
            lines.append(f"removed {self.removed} temporary files that a stopped worker left")
        return "\n".join(lines)


def turntable(views: int, pitch: float = 0.0, yaw: float = 0.0) -> list[dict]:
    """Cameras of a turntable: `views` yaws 360/views degrees apart from `yaw`, as --views does."""
    if views < 1:
        raise hsr.UsageError(f"turntable: {views} views, need at least 1")
    return [{"yaw": yaw + k * 360.0 / views, "pitch": pitch} for k in range(views)]


def jobs(models: Iterable[str | os.PathLike], cameras: Sequence[Mapping[str, Any]] = ({},),
         algorithms: Sequence[str] = ("zbuffer",), lightings: Sequence[str] = ("blinn-phong",), *,
         width: int = 256, height: int = 256, **keywords) -> list[Job]:
    """The jobs of models × cameras × algorithms × lightings, each a width × height picture.

    A camera is a dict of hsr.render's camera keywords: {"yaw": 30, "pitch": 20}, or
    {"eye": (40, 40, 40), "target": (0, 0, 0)}; turntable(N) makes N of them. `keywords` are
    further keywords of hsr.render or hsr.load for every job (zoom=1.5, samples=4, color="#ff8000",
    params={"cull-backfaces": True}); an unknown one is an hsr.UsageError. Each picture is
    named <model name>-<camera number>-<algorithm>-<lighting>.png, e.g. bunny-03-zbuffer-lambert.png
    (characters other than letters, digits, '.', '+' and '-' become '_').
    """
    cameras = list(cameras) or [{}]
    known = _keyword_names(hsr.load) | _keyword_names(hsr.render)
    for options in [*cameras, keywords]:
        unknown = sorted(set(options) - known)
        if unknown:
            raise hsr.UsageError(f"jobs: {unknown[0]!r} is not a keyword of hsr.render or hsr.load")
    digits = max(2, len(str(len(cameras) - 1)))
    made, names = [], {}
    for model, (index, camera), algorithm, lighting in itertools.product(
            [os.fspath(m) for m in models], enumerate(cameras), algorithms, lightings):
        stem = os.path.splitext(os.path.basename(model))[0]
        name = _file_name(f"{stem}-{index:0{digits}d}-{algorithm}-{lighting}") + ".png"
        if name in names:
            raise hsr.UsageError(f"two jobs would write {name}: {names[name]} and {model} "
                                 "(give the models different file names)")
        names[name] = model
        options = {"algorithm": algorithm, "lighting": lighting, **camera, "width": width, "height": height,
                   **keywords}
        made.append(Job(origin=name, model=model, keywords=options, name=name))
    return made


def read_jobs_file(path: str | os.PathLike) -> list[Job]:
    """The jobs of an `hsr render --jobs` file: one line each, '#' comments and blank lines skipped.

    Lines are split as hsr splits them (hsr.split_job_line); a line that cannot be split is an
    hsr.UsageError naming FILE:LINE, as is a file without jobs. The files a line reads are taken from
    the file's folder, those it writes from the current folder (hsr.job_line_arguments).
    """
    shown = os.fspath(path)
    folder = os.path.dirname(os.fsdecode(shown))
    try:
        # Checked before it is opened: opening a FIFO would wait for a writer.
        if not stat.S_ISREG(os.stat(path).st_mode):
            raise hsr.UsageError(f"--jobs '{shown}': is not a regular file (a folder, pipe or device), "
                                 "not a file of renders")
        with open(path, "rb") as file:
            data = file.read(_MAX_JOB_FILE_BYTES + 1)
    except OSError as error:
        raise hsr.Error(f"--jobs '{shown}': cannot read it ({error.strerror})") from None
    if len(data) > _MAX_JOB_FILE_BYTES:
        raise hsr.UsageError(f"--jobs '{shown}': more than a jobs file may hold ({_MAX_JOB_FILE_BYTES} bytes)")
    made = []
    for number, line in enumerate(data.decode("utf-8", "surrogateescape").split("\n"), start=1):
        line = line.removesuffix("\r")
        if not line.strip(" \t") or line.lstrip(" \t").startswith("#"):
            continue
        origin = f"{shown}:{number}"
        try:
            words = hsr.split_job_line(line)
        except hsr.Error as error:
            raise hsr.UsageError(f"{origin}: {error}") from None
        try:
            words = hsr.job_line_arguments(words, folder)
        except hsr.Error:
            pass  # the line's mistake is the job's error when it runs
        made.append(Job(origin=origin, words=tuple(words)))
    if not made:
        raise hsr.UsageError(f"--jobs '{shown}': no jobs in the file (each line holds the options of one render)")
    return made


def render_many(jobs: Sequence[Job] | str | os.PathLike, client: distributed.Client | None = None,
                out: str | os.PathLike | None = ".", *, workers: int | None = None, threads: int | None = 1,
                progress: bool | Callable[[int, int, int], None] = True) -> Summary:
    """Renders the jobs on a Dask cluster and says what each did.

    jobs: from jobs() or read_jobs_file(), or the path of an `hsr render --jobs` file.
    client: a distributed.Client; None: Dask's default client if there is one, else `workers`
        local worker processes (default: one per core) started for this batch.
    out: the folder that the pictures of jobs made by jobs() go into (created if missing); a --jobs
        line writes where it says, from the current folder, as `hsr render --jobs` does. None: no
        files; the pictures come back as arrays in Summary.frames (jobs made by jobs() only).
    threads: the --threads of each render (1: one core each, as each worker thread runs one task;
        None: as the jobs say).
    progress: a progress line on stderr (True), none (False), or a function called with the jobs
        done, the jobs failed and the jobs in all after each task.

    Raises hsr.UsageError before anything runs for jobs that cannot go together: two writing one
    file, arrays asked of --jobs lines. Every other failure is recorded in the summary.
    """
    if isinstance(jobs, (str, os.PathLike)):
        jobs = read_jobs_file(jobs)
    jobs = list(jobs)
    if not jobs:
        raise hsr.UsageError("render_many: no jobs")
    folder = os.getcwd()
    arrays = out is None
    if arrays:
        lines = [job.origin for job in jobs if job.model is None]
        if lines:
            raise hsr.UsageError(f"{lines[0]}: a --jobs line writes files; arrays come back only for "
                                 "jobs made by hsr.dask.jobs() (out=None)")
        out_folder = None
    else:
        out_folder = os.path.abspath(out)
        if any(job.model is not None for job in jobs):
            os.makedirs(out_folder, exist_ok=True)
    for j, job in enumerate(jobs):
        if job.model is not None and threads is not None and "threads" not in job.keywords:
            jobs[j] = dataclasses.replace(job, keywords={**job.keywords, "threads": threads})
    plans = [None if job.model is not None or arrays else _command_plan(job.command()) for job in jobs]
    commands = [job.command(out_folder) if job.model is not None else _with_threads(job.command(), plan, threads)
                for job, plan in zip(jobs, plans)]
    outputs = {} if arrays else _check_outputs(jobs, commands, plans)

    owned = None
    if client is None:
        client = _default_client()
    if client is None:
        owned = local_client(workers)
        client = owned
    try:
        slots = max(1, sum(client.nthreads().values()))
        planned = _plan_tasks(_group_by_scene(jobs, commands), slots)
        tasks = [[j for piece in task for j in piece] for task in planned]
        errors: list[str | None] = [None] * len(jobs)
        frames: list[FrameArrays | None] | None = [None] * len(jobs) if arrays else None
        start = time.monotonic()
        report = _progress_reporter(progress, len(jobs))
        batch = uuid.uuid4().hex[:8]
        keys = [f"hsr-{_file_name(_task_name(jobs[task[0]], plans[task[0]]))}-{batch}-{number}"
                for number, task in enumerate(tasks)]
        # One map for all the tasks: a submit each would cost a round trip to the scheduler.
        if arrays:
            submitted = client.map(_render_arrays, [folder] * len(tasks),
                                   [[(jobs[piece[0]].model, [dict(jobs[j].keywords) for j in piece]) for piece in task]
                                    for task in planned], key=keys)
        else:
            submitted = client.map(_render_files, [folder] * len(tasks),
                                   [[commands[j] for j in task] for task in tasks], key=keys)
        futures = dict(zip(submitted, tasks))
        done = failed = 0
        try:
            # The results of the tasks that finished meanwhile, fetched together: one round trip.
            for finished in distributed.as_completed(futures).batches():
                succeeded = [future for future in finished if future.status == "finished"]
                results = dict(zip(succeeded, client.gather(succeeded)))
                for future in finished:
                    task = futures[future]
                    if future not in results:  # the task failed: its workers died, hsr is missing, ...
                        error = future.exception()
                        message = _one_line(f"the task failed on its worker ({type(error).__name__}: {error})")
                        results[future] = [message] * len(task) if not arrays else [(None, message)] * len(task)
                    for j, result in zip(task, results[future]):
                        if arrays:
                            frames[j], errors[j] = result
                        else:
                            errors[j] = result
                        done += errors[j] is None
                        failed += errors[j] is not None
                report(done, failed)
        except BaseException:
            client.cancel(list(futures))
            raise
        removed = 0 if arrays else _remove_temporaries_everywhere(client, outputs)
        return Summary(jobs=jobs, errors=errors, frames=frames, seconds=time.monotonic() - start,
                       workers=slots, tasks=len(tasks), removed=removed)
    finally:
        if owned is not None:
            cluster = owned.cluster
            owned.close()
            cluster.close()


def local_client(workers: int | None = None) -> distributed.Client:
    """A client of `workers` local worker processes (default: one per core), one thread each, whose
    renders print nothing (the summary has the failures)."""
    count = workers or os.cpu_count() or 1
    if multiprocessing.parent_process() is not None:  # a script without the guard, run again in a worker
        raise hsr.Error(_UNGUARDED_SCRIPT)
    # Dask starts workers with MALLOC_TRIM_THRESHOLD_=65536, which makes glibc hand each picture's
    # buffers back to the system and fault them in again: three to five times the page faults, and about
    # 10 % more time for a batch of small pictures (docs/distributed.md#scaling).
    environment = {name: value for name, value in dask.config.get("distributed.nanny.pre-spawn-environ").items()
                   if name != "MALLOC_TRIM_THRESHOLD_"}
    with dask.config.set({"distributed.nanny.pre-spawn-environ": environment}):
        cluster = distributed.LocalCluster(n_workers=count, threads_per_worker=1, processes=True,
                                           dashboard_address=":0", silence_logs=logging.ERROR)
    client = distributed.Client(cluster)
    try:
        client.wait_for_workers(count, timeout=_WORKERS_START_SECONDS)
    except (TimeoutError, distributed.TimeoutError):
        client.close()
        cluster.close()
        raise hsr.Error(f"the {count} local worker processes did not start within {_WORKERS_START_SECONDS} s"
                        f" ({_UNGUARDED_SCRIPT})") from None
    client.register_worker_plugin(_QuietStandardError())
    return client


class _QuietStandardError(distributed.WorkerPlugin):
    """Points a local worker process's standard error at /dev/null, also in a worker started again
    after one died: hsr prints a line there for each file it writes, which would run over the
    client's progress bar in the same terminal."""

    name = "hsr-quiet-standard-error"

    def setup(self, worker):
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, 2)
        os.close(null)


# --- On the workers ------------------------------------------------------------------------------

_folder_condition = threading.Condition()
_folder_users = 0


@contextlib.contextmanager
def _working_folder(folder: str):
    """Runs the body in `folder`, where the batch's relative paths start. A worker process has one
    current folder for all its threads: tasks of one folder run together, another folder waits."""
    global _folder_users
    with _folder_condition:
        while _folder_users and os.getcwd() != folder:
            _folder_condition.wait()
        if os.getcwd() != folder:
            os.chdir(folder)
        _folder_users += 1
    try:
        yield
    finally:
        with _folder_condition:
            _folder_users -= 1
            _folder_condition.notify_all()


def _worker_error(folder: str, error: OSError) -> str:
    return (f"the folder '{folder}' is not there on worker {socket.gethostname()} ({error.strerror}): "
            "the workers need the files at the same paths")


def _render_files(folder: str, commands: list[list[str]]) -> list[str | None]:
    """A task: the commands as `hsr render` runs them, the scene loaded once; per command, None when
    done or the error message."""
    try:
        with _working_folder(folder):
            return hsr.render_commands(commands)
    except OSError as error:
        return [_worker_error(folder, error)] * len(commands)


def _render_arrays(folder: str, groups: list[tuple[str, list[dict]]]) -> list[tuple[FrameArrays | None, str | None]]:
    """A task: for each group of jobs, its model loaded once, then a frame for each job's keywords
    (the jobs of a group share their keywords of hsr.load). Per frame, its arrays (copies, to be
    sent back) or the error message."""
    return [result for model, keywords in groups for result in _render_model_arrays(folder, model, keywords)]


def _render_model_arrays(folder: str, model: str, keywords: list[dict]) -> list[tuple[FrameArrays | None, str | None]]:
    import numpy

    try:
        with _working_folder(folder):
            scene = hsr.load(model, **_split_keywords(keywords[0])[0])
    except OSError as error:
        return [(None, _worker_error(folder, error))] * len(keywords)
    except Exception as error:
        return [(None, _one_line(str(error)))] * len(keywords)
    results = []
    for options in keywords:
        try:
            frame = hsr.render(scene, **_split_keywords(options)[1])
            results.append((FrameArrays(color=numpy.array(frame.color), depth=numpy.array(frame.depth),
                                        face_id=numpy.array(frame.face_id), stats=dict(frame.stats)), None))
        except Exception as error:
            results.append((None, _one_line(str(error))))
    return results


def _remove_temporaries(outputs: dict[str, set[str]]) -> int:
    """Removes, in each folder, the temporary files of its outputs: those named
    ".<output>.tmp-<pid>-<random>", where <output> is one of its file names."""
    removed = 0
    for folder, names in outputs.items():
        try:
            entries = os.listdir(folder)
        except OSError:
            continue
        for entry in entries:
            temporary = _TEMPORARY_NAME.fullmatch(entry)
            if temporary and temporary.group(1) in names:
                with contextlib.suppress(FileNotFoundError):
                    os.remove(os.path.join(folder, entry))
                    removed += 1
    return removed


# --- On the client -------------------------------------------------------------------------------

def _default_client() -> distributed.Client | None:
    try:
        return distributed.default_client()
    except ValueError:
        return None


def _one_line(text: str) -> str:
    return " ".join(text.split())


def _file_name(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9.+-]", "_", text)


# hsr.render's keywords whose `hsr render` option has another name.
_RENAMED = {"orthographic": "ortho", "clip_planes": "clip_plane", "sections": "section", "lights": "light"}


@functools.cache
def _keyword_names(function: Callable) -> frozenset[str]:
    return frozenset(name for name, parameter in inspect.signature(function).parameters.items()
                     if parameter.kind == parameter.KEYWORD_ONLY or name in ("algorithm", "lighting"))


def _split_keywords(keywords: Mapping[str, Any]) -> tuple[dict, dict]:
    """Job keywords as those of hsr.load and those of hsr.render (threads goes to both)."""
    load = {k: v for k, v in keywords.items() if k in _keyword_names(hsr.load)}
    render = {k: v for k, v in keywords.items() if k not in load or k == "threads"}
    return load, render


def _option_words(keywords: Mapping[str, Any]) -> list[str]:
    """Keywords of hsr.load and hsr.render as the `hsr render` options they stand for, formatted as
    the package formats them for the core, so that the command renders what the call renders."""
    options = dict(keywords)
    words = ["--algorithm", _options.plugin_spec("algorithm", options.pop("algorithm", "zbuffer"),
                                                 options.pop("params", None)),
             "--lighting", _options.plugin_spec("lighting", options.pop("lighting", "blinn-phong"),
                                                options.pop("lighting_params", None))]
    for listed in ("lights", "plugin_path"):
        if isinstance(options.get(listed), (str, os.PathLike)):
            options[listed] = [options[listed]]
    return words + _options.words(**{_RENAMED.get(k, k): v for k, v in options.items()})


def _command_plan(command: Sequence[str]) -> dict | None:
    """What hsr says of one `hsr render` command line (hsr._hsr.command_plan): the files it writes,
    its model's name, its kind of plugin; None for a command with a mistake, which then fails on its
    worker and is recorded with the others."""
    try:
        return _hsr.command_plan(list(command))
    except hsr.Error:
        return None


def _task_name(job: Job, plan: dict | None) -> str:
    """The model's name, to name a task by in Dask's dashboard."""
    if job.model is not None:
        return os.path.splitext(os.path.basename(job.model))[0]
    return plan["model"] if plan else "render"


def _with_threads(command: list[str], plan: dict | None, threads: int | None) -> list[str]:
    """A command with --threads set, unless it has it or draws lines (hidden-line plugins take no
    --threads)."""
    if threads is None or plan is None or plan["threads_given"] or not plan["hidden_surface"]:
        return command
    return [*command, "--threads", str(threads)]


def _check_outputs(jobs: list[Job], commands: list[list[str]], plans: list[dict | None]) -> dict[str, set[str]]:
    """Refuses two jobs that write one file. Returns, by folder, the names of the files written
    there."""
    writers: dict[str, str] = {}
    outputs: dict[str, set[str]] = {}
    for job, command, plan in zip(jobs, commands, plans):
        # A job made by jobs() names one file, its last word.
        named = [command[-1]] if job.model is not None else plan["files"] if plan else []
        for path in named:
            if path in writers and writers[path] != job.origin:
                raise hsr.UsageError(f"{job.origin}: '{path}' is written by {writers[path]} too")
            writers[path] = job.origin
            outputs.setdefault(os.path.dirname(path), set()).add(os.path.basename(path))
    return outputs


def _remove_temporaries_everywhere(client: distributed.Client, outputs: dict[str, set[str]]) -> int:
    """Removes the temporary files of the batch's outputs that a stopped worker left, as seen from
    the client and from every worker (whose disks may differ)."""
    removed = _remove_temporaries(outputs)
    with contextlib.suppress(Exception):
        counts = client.run(_remove_temporaries, outputs, on_error="ignore")
        removed += sum(n for n in counts.values() if isinstance(n, int))
    return removed


def _group_by_scene(jobs: list[Job], commands: list[list[str]]) -> list[list[int]]:
    """The job numbers of each scene load, in the order of each scene's first job. A command that
    hsr cannot key (its options are wrong) is a group of its own, to fail on its worker."""
    groups: dict[str, list[int]] = {}
    keys: dict[tuple[str, ...], str] = {}  # jobs made by jobs() share a model and its load options
    for j, (job, command) in enumerate(zip(jobs, commands)):
        if job.model is not None:
            command = [_options.model_path(job.model), *_options.words(**_split_keywords(job.keywords)[0])]
        try:
            key = keys.get(tuple(command)) or keys.setdefault(tuple(command), hsr.scene_key(command))
        except Exception:
            key = f"\0job {j}"
        groups.setdefault(key, []).append(j)
    return list(groups.values())


def _plan_tasks(groups: list[list[int]], slots: int) -> list[list[list[int]]]:
    """Tasks, each a list of groups of jobs that share a scene load. When there are fewer groups than
    worker threads, each group is split in a few pieces so that every thread has work; when there
    are many more, they are packed into _TASKS_PER_THREAD tasks a thread, of about the same number
    of jobs, so that the scheduler's cost per task stays small beside the renders. Largest first,
    so that the last task to start is short."""
    pieces = max(1, math.ceil(slots / len(groups)))
    split = []
    for group in groups:
        count = min(pieces, len(group))
        size = math.ceil(len(group) / count)
        split += [group[at:at + size] for at in range(0, len(group), size)]
    split.sort(key=len, reverse=True)
    bins = slots * _TASKS_PER_THREAD
    if len(split) <= bins:
        return [[piece] for piece in split]
    tasks: list[list[list[int]]] = [[] for _ in range(bins)]
    sizes = [0] * bins
    for piece in split:  # each to the task with the fewest jobs so far
        smallest = sizes.index(min(sizes))
        tasks[smallest].append(piece)
        sizes[smallest] += len(piece)
    return sorted(tasks, key=lambda task: -sum(map(len, task)))


def _progress_reporter(progress: bool | Callable[[int, int, int], None], total: int) -> Callable[[int, int], None]:
    """A function of (done, failed) that shows the progress as `progress` asks."""
    if callable(progress):
        return lambda done, failed: progress(done, failed, total)
    if not progress:
        return lambda done, failed: None
    start = time.monotonic()
    on_terminal = sys.stderr.isatty()
    last = [0.0]

    def show(done: int, failed: int) -> None:
        now = time.monotonic()
        finished = done + failed == total
        if not on_terminal and not finished and now - last[0] < 10:
            return  # in a log, a line every 10 s
        last[0] = now
        width = 30
        filled = width * (done + failed) // total
        line = (f"[{'#' * filled}{'.' * (width - filled)}] {done + failed}/{total} jobs"
                f"{f', {failed} failed' if failed else ''}, {now - start:.1f} s")
        if on_terminal:
            sys.stderr.write("\r" + line + ("\n" if finished else ""))
        else:
            sys.stderr.write(line + "\n")
        sys.stderr.flush()

    return show


# --- python3 -m hsr.dask ---------------------------------------------------------------------------

class _Parser(argparse.ArgumentParser):
    def error(self, message: str):
        raise hsr.UsageError(message)


def _arguments() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="python3 -m hsr.dask",
        description="Render many frames with hsr on a Dask cluster: the lines of an `hsr render --jobs` "
                    "file, or models x cameras x algorithms x lightings. Progress on stderr, the summary "
                    "on stdout; exit status 0 when every job was done, 1 when one failed, 2 for a "
                    "mistake in the command line (docs/distributed.md).")
    parser.add_argument("jobs", nargs="?", metavar="JOBS",
                        help="a file of `hsr render` lines, as for hsr render --jobs")
    parser.add_argument("--model", nargs="+", default=[], metavar="MODEL", help="instead of JOBS: models to render")
    parser.add_argument("--views", type=int, default=1, help="with --model: a turntable of N views (default 1)")
    parser.add_argument("--yaw", type=float, default=0.0, help="with --model: the first view's yaw, degrees")
    parser.add_argument("--pitch", type=float, default=0.0, help="with --model: the pitch of every view, degrees")
    parser.add_argument("--algorithm", nargs="+", default=["zbuffer"], metavar="NAME",
                        help="with --model: hidden-surface plugins, NAME[:key=value,...] (default zbuffer)")
    parser.add_argument("--lighting", nargs="+", default=["blinn-phong"], metavar="NAME",
                        help="with --model: lighting plugins (default blinn-phong)")
    parser.add_argument("--width", type=int, default=256, help="with --model: picture width (default 256)")
    parser.add_argument("--height", type=int, default=256, help="with --model: picture height (default 256)")
    parser.add_argument("--out", default=".", metavar="DIR",
                        help="with --model: the folder for the pictures (default: the current folder); "
                             "a JOBS line writes where it says, from the current folder")
    parser.add_argument("--scheduler", metavar="ADDRESS", help="a Dask scheduler, tcp://HOST:8786 "
                        "(default: local worker processes)")
    parser.add_argument("--workers", type=int, metavar="N", help="without --scheduler: N local worker "
                        "processes (default: one per core)")
    parser.add_argument("--threads", type=int, default=1, metavar="N",
                        help="--threads of each render unless its line says (default 1; 0: all cores)")
    parser.add_argument("--wait-for", type=int, default=1, metavar="N",
                        help="with --scheduler: wait until N workers have joined before the batch "
                             "starts, so that it is split for them all (default 1)")
    parser.add_argument("--timeout", type=float, default=20.0, metavar="SECONDS",
                        help="how long to try to reach the scheduler (default 20)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """`python3 -m hsr.dask`: returns the exit status."""
    try:
        arguments = _arguments().parse_args(argv)
        if bool(arguments.jobs) == bool(arguments.model):
            raise hsr.UsageError("give a JOBS file or --model, one of the two")
        if arguments.scheduler and arguments.workers:
            raise hsr.UsageError("--workers starts local workers: it does not go with --scheduler")
        if arguments.workers is not None and arguments.workers < 1:
            raise hsr.UsageError(f"--workers {arguments.workers}: need at least 1")
        if arguments.jobs:
            batch = read_jobs_file(arguments.jobs)
        else:
            batch = jobs(arguments.model, turntable(arguments.views, arguments.pitch, arguments.yaw),
                         arguments.algorithm, arguments.lighting, width=arguments.width, height=arguments.height)
        if arguments.wait_for < 1:
            raise hsr.UsageError(f"--wait-for {arguments.wait_for}: need at least 1")
        client = _connect(arguments.scheduler, arguments.timeout) if arguments.scheduler else None
        try:
            if client is not None and len(client.nthreads()) < arguments.wait_for:
                print(f"hsr.dask: waiting for {arguments.wait_for} workers to join {arguments.scheduler}",
                      file=sys.stderr, flush=True)
                client.wait_for_workers(arguments.wait_for)
            summary = render_many(batch, client, out=arguments.out, workers=arguments.workers,
                                  threads=arguments.threads, progress=not arguments.quiet)
        finally:
            if client is not None:
                client.close()
    except hsr.UsageError as error:
        print(f"hsr.dask: error: {_one_line(str(error))} (see python3 -m hsr.dask --help)", file=sys.stderr)
        return 2
    except (hsr.Error, OSError) as error:
        print(f"hsr.dask: error: {_one_line(str(error))}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("hsr.dask: error: interrupted", file=sys.stderr)
        return 130
    print(summary)
    return 0 if summary.ok else 1


def _connect(address: str, timeout: float) -> distributed.Client:
    try:
        return distributed.Client(address, timeout=timeout)
    except Exception as error:
        reason = _one_line(str(error)) or type(error).__name__
        raise hsr.Error(f"--scheduler '{address}': cannot reach it ({reason})") from None


if __name__ == "__main__":
    # Run as hsr.dask, not as __main__, so that the tasks' functions are found by name on the workers.
    from hsr import dask as _module

    sys.exit(_module.main())
