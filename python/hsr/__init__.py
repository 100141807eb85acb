"""hsr: hidden-surface and hidden-line removal, from Python.

    import hsr
    scene = hsr.load("models/bunny.obj")
    frame = hsr.render(scene, algorithm="zbuffer", lighting="blinn-phong", width=512, height=512)
    frame.color, frame.depth, frame.face_id      # numpy views of hsr's own buffers
    frame.save("bunny.png")

Every function takes the options of `hsr render` as keywords ('_' for '-'), with the same defaults,
checks and messages; plugins are found as the hsr executable finds them (its plugin folder, then
$HSR_PLUGIN_PATH, then plugin_path=[...]). Rendering releases the GIL, so threads render at once.
docs/python.md describes the package; hsr.dask renders batches on many processes or machines.
"""

import collections.abc
import dataclasses
import os
import typing

from . import _hsr, _options
from ._hsr import Error, Frame, LimitError, Lines, PluginError, Scene, UsageError
from ._paths import plugin_dir as _plugin_dir

__all__ = [
    "Error", "UsageError", "LimitError", "PluginError", "Scene", "Mesh", "Frame", "Lines", "Step", "Steps",
    "plugins", "load", "render", "lines", "steps", "limits", "set_limits", "split_job_line",
    "job_line_arguments", "scene_key", "render_commands",
]

_hsr.set_builtin_plugin_dirs([_plugin_dir])


def plugins(plugin_path=None):
    """Every plugin found: a list of dicts with kind ("hidden-surface", "hidden-line", "lighting"),
    name, version, abi (major, minor), description, path and parameters, each a dict of name, type
    (bool, int, float, enum, color), default, min and max (numbers), choices (enum) and help."""
    return _hsr.plugins(_plugin_paths(plugin_path))


def load(path=None, *, crease_angle=None, color=None, opacity=None, repeat=None, repeat_gap=None,
         repeat_jitter=None, surface=None, range=None, heightmap=None, heightmap_height=None,
         random_triangles=None, seed=None, threads=None):
    """Load a scene once, for any number of renders: a model file (.obj, .off, .ply, .stl, .gltf,
    .glb) or a .scene file, or, instead of a path, a surface, a height map or random triangles.

    crease_angle     degrees: corner normals smooth across edges sharper than this (default 40)
    color            the model's colour, "r/g/b", "#rrggbb" or three numbers in [0, 1], over the
                     file's own colours
    opacity          of a single model, 0 to 1 (the a-buffer and ray casting show it)
    repeat           the model repeated into a grid, "CxRxL" or (columns, rows, layers), stored once
                     and drawn as instances; repeat_gap (fraction of the model's size, default 0.25)
                     and repeat_jitter (degrees of random yaw, default 0) place the copies
    surface, range   z = f(x, y) in muParser syntax over "x0:x1,y0:y1" instead of a file
    heightmap        a greyscale PNG as a terrain; heightmap_height its height (default: automatic)
    random_triangles N random triangles; seed the random seed (default 1)
    threads          threads for loading (default: one per core)

    Raises hsr.Error (hsr.UsageError, a ValueError, for bad options) with the message hsr render
    gives; the limits (hsr.limits()) hold.
    """
    words = [] if path is None else [_options.model_path(path)]
    words += _options.words(crease_angle=crease_angle, color=color, opacity=opacity, repeat=repeat,
                            repeat_gap=repeat_gap, repeat_jitter=repeat_jitter, surface=surface, range=range,
                            heightmap=heightmap, heightmap_height=heightmap_height,
                            random_triangles=random_triangles, seed=seed, threads=threads)
    return _hsr.load(words)


def render(scene, algorithm="zbuffer", lighting="blinn-phong", *, params=None, lighting_params=None,
           width=None, height=None, yaw=None, pitch=None, zoom=None, fov=None, orthographic=None,
           eye=None, target=None, up=None, camera=None, near=None, clip_planes=None, sections=None,
           lights=None, background=None, samples=None, step=None, threads=None, plugin_path=None):
    """Render a shaded picture of the scene with a hidden-surface plugin and a lighting model.

    algorithm        the hidden-surface plugin (hsr.plugins()), optionally with its parameters as
                     hsr render writes them: "zbuffer:depth-test=greater"
    lighting         the lighting model, likewise: "blinn-phong", "lambert", "facecolor", ...
    params           the algorithm's parameters as a dict, {"depth-test": "greater"} ('_' for '-')
    lighting_params  the lighting model's, likewise
    width, height    pixels (default 1024 each, or the .scene file's)
    yaw, pitch       degrees the camera orbits the model by (default 0: looking down -z)
    zoom             magnification; 1 fits the model to the view
    fov              vertical field of view of the perspective projection, degrees (default 35)
    orthographic     True for an orthographic projection
    eye, target, up  a look-at camera instead of the orbit: three numbers each (target default: the
                     centre of the model's bounds; up default 0,1,0)
    camera           a camera of the model file (glTF), by name or index
    near             view-space distance of the near plane
    clip_planes      planes (a, b, c, d): what lies where a*x + b*y + c*z + d < 0 is cut away
    sections         heights z: the model cut at z (what lies above is removed)
    lights           lights as hsr render --light takes them, e.g. ["dir:1,1,1", "point:0,2,0,intensity=0.5"];
                     default: the .scene file's, else one light over the viewer's shoulder
    background       "r/g/b", "#rrggbb" or three numbers in [0, 1]; "none" for a transparent
                     background (frame.color then has an alpha channel)
    samples          supersampling: 1, 2, 4, 8 or 16 samples per pixel
    step             stop the algorithm after this step (1-based); hsr.steps() walks them all
    threads          threads for visibility and shading (default: one per core)
    plugin_path      extra folders to search for plugins

    Returns an hsr.Frame: .color (H x W x 3, or x 4, uint8), .depth (H x W float32, the distance
    along the view axis, +inf where nothing is drawn), .face_id (H x W x 3 int32: object, face,
    instance, -1 where nothing is drawn), .normal, .stats, .save(path). The arrays are read-only
    views of the frame's buffers (.copy() one to change it). Raises hsr.Error with hsr render's
    message.
    """
    words = _view_words(algorithm, params, width, height, yaw, pitch, zoom, fov, orthographic, eye, target, up,
                        camera, near, clip_planes, sections, plugin_path)
    words += ["--lighting", _options.plugin_spec("lighting", lighting, lighting_params)]
    words += _options.words(light=_listed(lights), background=background, samples=samples, step=step,
                            threads=threads)
    return _hsr.render(scene, words)


def lines(scene, algorithm="appel", *, params=None, width=None, height=None, yaw=None, pitch=None, zoom=None,
          fov=None, orthographic=None, eye=None, target=None, up=None, camera=None, near=None, clip_planes=None,
          sections=None, edges=None, crease_angle=None, hidden=None, line_color=None, line_width=None,
          background=None, plugin_path=None):
    """Draw the scene's visible edges with a hidden-line plugin.

    algorithm    the hidden-line plugin: "appel", "roberts", "floating-horizon", optionally with its
                 parameters as hsr render writes them; params its parameters as a dict
    width, height, yaw, pitch, zoom, fov, orthographic, eye, target, up, camera, near, clip_planes,
    sections and plugin_path as render() takes them. Besides them:
    edges        "features" (silhouettes, creases and boundaries; default) or "all"
    crease_angle degrees: an edge between faces turned further than this is a crease (default 40)
    hidden       "hidden" (left out; default) or "dashed" (drawn dashed, and returned)
    line_color, line_width, background   how .svg() and .save() draw the lines

    Returns an hsr.Lines: .segments (N x 4 float32: x0, y0, x1, y1 in pixels, y down), .qi (N int32:
    0 visible, n > 0 behind n faces, -1 hidden), .edge, .flags, .visible and .hidden (the segments of
    each), .stats, .svg() and .save(path) (.svg or .png).
    """
    words = _view_words(algorithm, params, width, height, yaw, pitch, zoom, fov, orthographic, eye, target, up,
                        camera, near, clip_planes, sections, plugin_path)
    words += _options.words(edges=edges, crease_angle=crease_angle, hidden=hidden, line_color=line_color,
                            line_width=line_width, background=background)
    return _hsr.lines(scene, words)


@dataclasses.dataclass(frozen=True)
class Step:
    """One step of a hidden-surface algorithm, as hsr view shows it.

    index    1-based; total the steps of the whole run
    type     what kind of step ("triangle", "node", "span", ...), text what it did, in words
    face, instance, level   the triangle and instance it worked on, its level in a hierarchy (or None)
    frame    the picture as the algorithm left it after this step (an hsr.Frame)
    lines    (N x 4 float32) the lines the algorithm drew to show the step, in pixels; roles what
             each is (an hsr_step_role of the SDK)
    buffers  the plugin's own buffers at this step, by name (H x W float32)
    pixels_written, pixels_rejected   by the depth test in this step
    """
    index: int
    total: int
    type: str
    text: str
    face: typing.Optional[int]
    instance: int
    level: typing.Optional[int]
    frame: Frame
    lines: typing.Any
    roles: typing.List[int]
    buffers: typing.Dict[str, typing.Any]
    pixels_written: int
    pixels_rejected: int


class Steps(collections.abc.Sequence):
    """The steps of one run of a hidden-surface algorithm, rendered on demand: steps[k] is step k + 1.
    Each step is a render that stops there, so walking all of them costs time quadratic in their
    number: fine for the small scenes of a lesson, slow for a large mesh."""

    def __init__(self, run):
        self._run = run
        first = self._make(1)
        self._total = first.total
        self._first = first

    def _make(self, index):
        frame, record, total = self._run.step(index)
        return Step(index=record["index"], total=total, type=record["type"], text=record["text"],
                    face=record["face"], instance=record["instance"], level=record["level"], frame=frame,
                    lines=record["lines"], roles=list(record["roles"]), buffers=dict(record["buffers"]),
                    pixels_written=record["pixels_written"], pixels_rejected=record["pixels_rejected"])

    def __len__(self):
        return self._total

    def __getitem__(self, k):
        if isinstance(k, slice):
            return [self[i] for i in range(*k.indices(self._total))]
        if not isinstance(k, int):
            raise TypeError(f"step indices are integers, not {type(k).__name__}")
        if k < 0:
            k += self._total
        if not 0 <= k < self._total:
            raise IndexError(f"step {k} of {self._total} steps (steps[k] is step k + 1)")
        return self._first if k == 0 else self._make(k + 1)

    def __repr__(self):
        return f"<hsr.Steps: {self._total} steps>"


def steps(scene, algorithm="zbuffer", lighting="blinn-phong", *, params=None, lighting_params=None, width=None,
          height=None, yaw=None, pitch=None, zoom=None, fov=None, orthographic=None, eye=None, target=None,
          up=None, camera=None, near=None, clip_planes=None, sections=None, lights=None, background=None,
          threads=None, plugin_path=None):
    """The steps of a hidden-surface algorithm one by one, as hsr view shows them: an hsr.Steps
    sequence of hsr.Step (index, text, the picture after it, ...).

    algorithm, lighting, params, lighting_params, width, height, yaw, pitch, zoom, fov, orthographic,
    eye, target, up, camera, near, clip_planes, sections, lights, background, threads and plugin_path
    as render() takes them. The algorithm must show its steps (hsr.plugins(); ABI 1.3).
    """
    words = _view_words(algorithm, params, width, height, yaw, pitch, zoom, fov, orthographic, eye, target, up,
                        camera, near, clip_planes, sections, plugin_path)
    words += ["--lighting", _options.plugin_spec("lighting", lighting, lighting_params)]
    words += _options.words(light=_listed(lights), background=background, threads=threads)
    return Steps(_hsr.StepRun(scene, words))


def limits():
    """The limits on work in force, by name (hsr render --help lists what each bounds)."""
    return _hsr.limits()


def set_limits(settings=None, **named):
    """Set the limits on work of this process, as hsr render --limit NAME=N does: a dict
    {"stored-triangles": 10**8} or keywords (stored_triangles=10**8). Limits not named return to
    their defaults."""
    merged = dict(settings or {})
    merged.update({k.replace("_", "-"): v for k, v in named.items()})
    _hsr.set_limits([f"{name}={_options.integer(name, value)}" for name, value in merged.items()])


def split_job_line(line):
    """One line of an `hsr render --jobs` file split into its words, as hsr splits it."""
    return _hsr.split_job_line(line)


def job_line_arguments(words, folder, defaults=()):
    """The words of an `hsr render --jobs` line as the render's command line: the files the line reads
    (MODEL, --heightmap, --plugin-path), when relative, taken from `folder` (the jobs file's); then the
    options of `defaults` (the command line of hsr render --jobs) that the line does not give itself."""
    return _hsr.job_line_arguments(list(words), os.fspath(folder), list(defaults))


def scene_key(words):
    """The options of `hsr render` that decide the scene it loads, as one string: renders with equal
    keys share one load."""
    return _hsr.scene_key(list(words))


def render_commands(commands):
    """Run `hsr render` command lines (lists of words, without "hsr render") in this process, as a
    --jobs file runs them: the same files, written whole or not at all, each scene loaded once for
    the commands that share it. Returns each command's error message, or None; never raises for a
    command that fails."""
    return _hsr.render_commands([list(c) for c in commands])


def _listed(value):
    return [value] if isinstance(value, str) else value


def _plugin_paths(plugin_path):
    if plugin_path is None:
        return []
    folders = [plugin_path] if isinstance(plugin_path, (str, bytes, os.PathLike)) else plugin_path
    return [_options.model_path(p) for p in folders]


def _view_words(algorithm, params, width, height, yaw, pitch, zoom, fov, orthographic, eye, target, up, camera,
                near, clip_planes, sections, plugin_path):
    words = [_options.LOADED_SCENE, "--algorithm", _options.plugin_spec("algorithm", algorithm, params)]
    return words + _options.words(width=width, height=height, yaw=yaw, pitch=pitch, zoom=zoom, fov=fov,
                                  ortho=orthographic, eye=eye, target=target, up=up, camera=camera, near=near,
                                  clip_plane=clip_planes, section=sections,
                                  plugin_path=_plugin_paths(plugin_path) or None)


from ._arrays import _install as _install_arrays  # noqa: E402  (needs the names above)

_install_arrays()
