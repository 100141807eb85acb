"""The Python package hsr against independent answers: hsr render's files for the same options, scenes
built two ways, hand-counted meshes, and the numpy arrays' own bookkeeping."""

import ast
import gc
import inspect
import os
import pathlib
import re
import subprocess
import sys
import threading

import numpy as np
import pytest

import hsr
from conftest import read_png

SIZE = ["--width", "96", "--height", "80"]
SIZE_KW = {"width": 96, "height": 80}


# --- plugins -------------------------------------------------------------------------------------

def test_plugins_list_every_kind_with_schemas(hsr_cli):
    found = hsr.plugins()
    names = {(p["kind"], p["name"]) for p in found}
    listed = hsr_cli("plugins").stdout
    for kind, name in names:
        assert name in listed, f"{name} is not in hsr plugins' list"
    assert ("hidden-surface", "zbuffer") in names
    assert ("hidden-line", "appel") in names
    assert ("lighting", "blinn-phong") in names
    for p in found:
        assert set(p) >= {"kind", "name", "version", "abi", "description", "parameters"}
        for parameter in p["parameters"]:
            assert parameter["type"] in {"bool", "int", "float", "enum", "color"}
            if parameter["type"] == "enum":
                assert parameter["default"] in parameter["choices"]
            if parameter["type"] in {"int", "float"}:
                assert parameter["min"] <= parameter["default"] <= parameter["max"]


# --- loading -------------------------------------------------------------------------------------

@pytest.mark.parametrize("name, triangles", [("cube.obj", 12), ("tetrahedron.off", 4), ("octahedron.ply", 8),
                                             ("pyramid.stl", 6)])
def test_load_reads_each_format(models, name, triangles):
    scene = hsr.load(models / name)
    assert scene.triangle_count == triangles
    assert scene.source.endswith(name)


def test_load_reads_scene_files_and_gltf(models, tmp_path):
    boxes = hsr.load(models / "boxes.scene")
    assert boxes.triangle_count > 12 and len(boxes.object_names) > 1
    # One triangle in a .gltf with its buffer as a data URI, and a camera.
    import base64
    import json
    import struct as st
    data = st.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    gltf = {
        "asset": {"version": "2.0"}, "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.3, 0.3, 3]}],
        "cameras": [{"name": "front", "type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.1}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteLength": len(data)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
    }
    path = tmp_path / "triangle.gltf"
    path.write_text(json.dumps(gltf))
    scene = hsr.load(path)
    assert scene.triangle_count == 1 and scene.cameras == ["front"]
    frame = hsr.render(scene, camera="front", width=40, height=40)
    assert (frame.face_id[..., 1] == 0).any()


def test_load_options_and_errors(models):
    grid = hsr.load(models / "cube.obj", repeat=(3, 2, 1))
    assert grid.instance_count == 6 and grid.triangle_count == 72
    with pytest.raises(hsr.Error, match="no such file"):
        hsr.load(models / "missing.obj")
    with pytest.raises(hsr.UsageError, match="--opacity must be between 0 and 1") as raised:
        hsr.load(models / "cube.obj", opacity=2)
    assert isinstance(raised.value, ValueError)
    with pytest.raises(hsr.UsageError, match="whole number"):
        hsr.load(models / "cube.obj", repeat=(1.5, 1, 1))


# --- frames against hsr render ---------------------------------------------------------------------

def test_frame_equals_hsr_render_pixel_for_pixel(models, hsr_cli, tmp_path):
    options = ["--algorithm", "zbuffer", "--lighting", "phong", "--yaw", "30", "--pitch", "-15", *SIZE]
    hsr_cli("render", models / "bunny.obj", *options, "-o", tmp_path / "cli.png", "--depth-out", tmp_path / "depth.npy",
            "--id-out", tmp_path / "ids.npy", "--normal-out", tmp_path / "normal.npy")
    frame = hsr.render(hsr.load(models / "bunny.obj"), "zbuffer", "phong", yaw=30, pitch=-15, **SIZE_KW)
    assert frame.color.shape == (80, 96, 3) and frame.color.dtype == np.uint8
    assert np.array_equal(frame.color, read_png(tmp_path / "cli.png"))
    depth = np.load(tmp_path / "depth.npy")
    assert frame.depth.dtype == np.float32 and np.array_equal(frame.depth, depth)
    assert np.isinf(frame.depth).any() and np.isfinite(frame.depth).any()
    ids = np.load(tmp_path / "ids.npy")
    assert frame.face_id.dtype == np.int32 and np.array_equal(frame.face_id, ids)
    assert (frame.face_id[np.isinf(frame.depth)] == -1).all()
    assert np.array_equal(frame.normal, np.load(tmp_path / "normal.npy"))
    frame.save(tmp_path / "python.png")
    assert (tmp_path / "python.png").read_bytes() == (tmp_path / "cli.png").read_bytes()


def test_every_option_kind_reaches_the_renderer(models, hsr_cli, tmp_path):
    cli = ["--algorithm", "painter", "--lighting", "lambert", "--eye", "2,1.5,3", "--target", "0,0.1,0",
           "--fov", "50", "--light", "dir:1,0.5,1,intensity=0.7", "--background", "0.1/0.2/0.3",
           "--samples", "4", "--clip-plane", "0,-1,0,0.12", "--zoom", "1.2", *SIZE]
    hsr_cli("render", models / "bunny.obj", *cli, "-o", tmp_path / "cli.png")
    frame = hsr.render(hsr.load(models / "bunny.obj"), "painter", "lambert", eye=(2, 1.5, 3), target=(0, 0.1, 0),
                       fov=50, lights=["dir:1,0.5,1,intensity=0.7"], background=(0.1, 0.2, 0.3), samples=4,
                       clip_planes=[(0, -1, 0, 0.12)], zoom=1.2, **SIZE_KW)
    assert np.array_equal(frame.color, read_png(tmp_path / "cli.png"))


def test_parameters_as_dict_or_text(models, hsr_cli, tmp_path):
    scene = hsr.load(models / "monkey.obj")
    hsr_cli("render", models / "monkey.obj", "-a", "zbuffer:cull-backfaces=true", "--ortho", *SIZE, "-o", tmp_path / "cli.png")
    by_text = hsr.render(scene, "zbuffer:cull-backfaces=true", orthographic=True, **SIZE_KW)
    by_dict = hsr.render(scene, "zbuffer", params={"cull_backfaces": True}, orthographic=True, **SIZE_KW)
    assert np.array_equal(by_text.color, read_png(tmp_path / "cli.png"))
    assert np.array_equal(by_dict.color, by_text.color)
    assert by_dict.stats["counters"]["triangles-backface-culled"] > 0
    with pytest.raises(hsr.Error, match="no-such-key"):
        hsr.render(scene, "zbuffer", params={"no-such-key": 1}, **SIZE_KW)


def test_transparent_background_gives_rgba(models, hsr_cli, tmp_path):
    hsr_cli("render", models / "cube.obj", "--background", "none", "--yaw", "20", *SIZE, "-o", tmp_path / "cli.png")
    frame = hsr.render(hsr.load(models / "cube.obj"), background="none", yaw=20, **SIZE_KW)
    assert frame.color.shape == (80, 96, 4)
    assert np.array_equal(frame.color, read_png(tmp_path / "cli.png"))
    assert frame.color[0, 0, 3] == 0 and frame.color[40, 48, 3] == 255


def test_repr_png_shows_the_frame(models, tmp_path):
    frame = hsr.render(hsr.load(models / "cube.obj"), yaw=10, **SIZE_KW)
    png = frame._repr_png_()
    (tmp_path / "repr.png").write_bytes(png)
    assert np.array_equal(read_png(tmp_path / "repr.png"), frame.color)


def test_stats(models):
    frame = hsr.render(hsr.load(models / "cube.obj"), "painter", "lambert", **SIZE_KW)
    s = frame.stats
    assert (s["algorithm"], s["lighting"], s["width"], s["height"], s["triangles"]) == ("painter", "lambert", 96, 80, 12)
    assert s["visibility_ms"] >= 0 and isinstance(s["counters"], dict)


# --- arrays are views ------------------------------------------------------------------------------

def test_arrays_are_read_only_views_that_keep_the_frame(models):
    frame = hsr.render(hsr.load(models / "cube.obj"), **SIZE_KW)
    for name in ("color", "depth", "face_id", "normal"):
        a, b = getattr(frame, name), getattr(frame, name)
        assert not a.flags.owndata and not a.flags.writeable, name
        assert a.base is frame, name
        assert a.__array_interface__["data"][0] == b.__array_interface__["data"][0], f"{name} was copied"
    color, depth = frame.color, frame.depth
    expected = color.copy(), depth.copy()
    del frame
    gc.collect()
    junk = [np.ones((80, 96, 3), np.uint8) for _ in range(50)]  # would reuse freed memory
    assert np.array_equal(color, expected[0]) and np.array_equal(depth, expected[1])
    del junk


def test_line_segments_are_views(models):
    drawing = hsr.lines(hsr.load(models / "cube.obj"), yaw=30, pitch=20, **SIZE_KW)
    segments = drawing.segments
    assert segments.dtype == np.float32 and segments.shape[1] == 4 and not segments.flags.owndata
    assert segments.base is drawing and drawing.qi.base is drawing
    assert len(drawing.visible) == int((drawing.qi == 0).sum())


# --- scenes from arrays ----------------------------------------------------------------------------

def cube_arrays():
    vertices = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=np.float32)
    quads = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    triangles = np.array([[q[0], q[1], q[2]] for q in quads] + [[q[0], q[2], q[3]] for q in quads], dtype=np.uint32)
    return vertices, quads, triangles


def test_arrays_make_the_scene_a_file_makes(tmp_path):
    vertices, quads, triangles = cube_arrays()
    lines = [f"v {x} {y} {z}" for x, y, z in vertices] + [f"f {' '.join(str(i + 1) for i in q)}" for q in quads]
    (tmp_path / "cube.obj").write_text("\n".join(lines) + "\n")
    from_file = hsr.render(hsr.load(tmp_path / "cube.obj"), yaw=35, pitch=25, **SIZE_KW)
    from_quads = hsr.render(hsr.Scene.from_arrays(vertices, quads), yaw=35, pitch=25, **SIZE_KW)
    assert np.array_equal(from_quads.color, from_file.color)
    from_triangles = hsr.Scene.from_arrays(vertices, triangles)
    assert from_triangles.triangle_count == 12
    same = hsr.render(from_triangles, yaw=35, pitch=25, **SIZE_KW)
    assert np.array_equal(same.depth, from_file.depth)
    assert np.array_equal(np.unique(same.face_id[..., 0]), [-1, 0])


def test_arrays_are_read_where_they_lie():
    vertices, _, triangles = cube_arrays()
    mesh = hsr.Mesh(vertices, triangles)
    assert np.shares_memory(mesh._dict["vertices"], vertices)
    assert np.shares_memory(mesh._dict["triangles"], triangles)
    converted = hsr.Mesh(vertices.astype(np.float64), triangles.astype(np.int64))
    assert not np.shares_memory(converted._dict["vertices"], vertices)


def test_face_colors_and_instances():
    vertices, _, triangles = cube_arrays()
    colors = np.zeros((12, 3), np.float32)
    colors[:, 0] = 1.0  # red
    red = hsr.render(hsr.Scene.from_arrays(vertices, triangles, colors), "zbuffer", "facecolor", yaw=30, **SIZE_KW)
    covered = red.face_id[..., 0] >= 0
    assert (red.color[covered] == [255, 0, 0]).all()

    shift = np.eye(4)
    shift[0, 3] = 3.0
    placed = np.stack([np.eye(4), shift])
    instanced = hsr.Scene.from_arrays(vertices, triangles, transforms=placed)
    assert instanced.instance_count == 2 and instanced.stored_triangle_count == 12
    shifted = vertices + np.array([3, 0, 0], np.float32)
    copies = hsr.Scene.from_meshes([hsr.Mesh(vertices, triangles), hsr.Mesh(shifted, triangles)])
    assert copies.instance_count == 0 and copies.triangle_count == 24
    a = hsr.render(instanced, yaw=20, pitch=10, **SIZE_KW)
    b = hsr.render(copies, yaw=20, pitch=10, **SIZE_KW)
    differ = (a.face_id[..., 1] != b.face_id[..., 1]).sum()
    assert differ <= 0.01 * a.face_id[..., 0].size  # rounding on the edges at most
    assert set(np.unique(a.face_id[..., 2])) == {-1, 0, 1}


def test_array_mistakes_are_usage_errors():
    vertices, quads, triangles = cube_arrays()
    with pytest.raises(hsr.UsageError, match=r"vertices: an array of shape \(N, 3\) expected"):
        hsr.Scene.from_arrays(vertices[:, :2], triangles)
    with pytest.raises(hsr.UsageError, match="vertex index 8 is out of range"):
        hsr.Scene.from_arrays(vertices, triangles + 1)
    with pytest.raises(hsr.UsageError, match="face 0 has fewer than 3 corners"):
        hsr.Scene.from_arrays(vertices, [[0, 1], [0, 1, 2]])
    with pytest.raises(hsr.UsageError, match="not affine"):
        bad = np.eye(4)
        bad[3, 0] = 1
        hsr.Scene.from_arrays(vertices, triangles, transforms=bad)
    nan = vertices.copy()
    nan[0, 0] = np.nan
    with pytest.raises(hsr.Error, match="not a finite number"):
        hsr.Scene.from_arrays(nan, triangles)


# --- errors and limits -----------------------------------------------------------------------------

def test_errors_carry_the_command_lines_message(models, hsr_cli):
    scene = hsr.load(models / "cube.obj")
    cli = hsr_cli("render", models / "cube.obj", "-a", "no-such-plugin", "-o", "/dev/null", check=False)
    with pytest.raises(hsr.Error) as raised:
        hsr.render(scene, "no-such-plugin")
    assert str(raised.value) in cli.stderr
    with pytest.raises(hsr.UsageError, match="image size 0x1024"):
        hsr.render(scene, width=0)
    with pytest.raises(hsr.UsageError, match="a whole number expected"):
        hsr.render(scene, width=10.5)
    with pytest.raises(hsr.UsageError, match="draws lines"):
        hsr.render(scene, "appel")
    with pytest.raises(hsr.UsageError, match="removes hidden surfaces"):
        hsr.lines(scene, "zbuffer")
    with pytest.raises(TypeError):
        hsr.render(scene, no_such_keyword=1)


def test_plugin_path_must_be_a_folder(models):
    scene = hsr.load(models / "cube.obj")
    with pytest.raises(hsr.UsageError, match="--plugin-path '/nonexistent': no such folder"):
        hsr.render(scene, plugin_path="/nonexistent")
    with pytest.raises(hsr.UsageError, match="no such folder"):
        hsr.plugins(plugin_path=["/nonexistent"])
    with pytest.raises(hsr.UsageError, match="is not a folder"):
        hsr.render(scene, plugin_path=models / "cube.obj")


def test_job_line_arguments_take_inputs_from_the_jobs_folder():
    assert hsr.job_line_arguments(["cube.obj", "-o", "x.png"], "jobs/here") == [
        "--model=jobs/here/cube.obj", "-o", "x.png"]
    assert hsr.job_line_arguments(["cube.obj", "--width", "8"], "", ["--jobs", "f.jobs", "--width", "64", "--ortho"]) == [
        "cube.obj", "--width", "8", "--ortho"]
    with pytest.raises(hsr.UsageError, match=r"unknown option --widht \(did you mean --width\?\)"):
        hsr.job_line_arguments(["cube.obj", "--widht", "8"], "")


def test_limits_hold(models):
    defaults = hsr.limits()
    assert defaults["stored-triangles"] > 0
    try:
        hsr.set_limits(stored_triangles=100)
        assert hsr.limits()["stored-triangles"] == 100
        with pytest.raises(hsr.LimitError, match="over the limit of 100") as raised:
            hsr.load(models / "bunny.obj")
        assert isinstance(raised.value, hsr.UsageError) and isinstance(raised.value, ValueError)
        with pytest.raises(hsr.UsageError, match="unknown"):
            hsr.set_limits({"no-such-limit": 3})
    finally:
        hsr.set_limits()
    assert hsr.limits() == defaults
    with pytest.raises(hsr.UsageError):
        hsr.render(hsr.load(models / "cube.obj"), width=100000, height=100000)


# --- threads ---------------------------------------------------------------------------------------

def test_two_threads_render_at_once(models):
    bunny, monkey = hsr.load(models / "bunny.obj"), hsr.load(models / "monkey.obj")
    alone = [hsr.render(bunny, yaw=40, **SIZE_KW).color, hsr.render(monkey, "painter", **SIZE_KW).color]
    results, errors = [None, None], []
    started = threading.Event()
    order = []

    def long_render():
        try:
            started.set()
            results[0] = hsr.render(bunny, yaw=40, **SIZE_KW).color
            hsr.render(bunny, width=2048, height=2048, threads=1)
            order.append("long")
        except Exception as e:  # noqa: BLE001  (reported below)
            errors.append(e)

    def short_render():
        try:
            started.wait()
            results[1] = hsr.render(monkey, "painter", **SIZE_KW).color
            order.append("short")
        except Exception as e:  # noqa: BLE001
            errors.append(e)

    threads = [threading.Thread(target=long_render), threading.Thread(target=short_render)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    assert np.array_equal(results[0], alone[0]) and np.array_equal(results[1], alone[1])
    # With the GIL held through a render, the short one could not finish inside the long one.
    assert order == ["short", "long"]


# --- line drawings and steps -----------------------------------------------------------------------

def test_lines_equal_hsr_renders_drawing(models, hsr_cli, tmp_path):
    hsr_cli("render", models / "monkey.obj", "-a", "appel", "--hidden", "dashed", "--yaw", "25", *SIZE, "-o", tmp_path / "cli.svg")
    drawing = hsr.lines(hsr.load(models / "monkey.obj"), "appel", hidden="dashed", yaw=25, **SIZE_KW)
    # Cairo numbers the surfaces it makes in a process ("surface1", "surface2", ...).
    def same(svg):
        return re.sub(r"surface\d+", "surface", svg)
    assert same(drawing.svg()) == same((tmp_path / "cli.svg").read_text())
    drawing.save(tmp_path / "python.svg")
    assert same((tmp_path / "python.svg").read_text()) == same((tmp_path / "cli.svg").read_text())
    assert len(drawing.hidden) > 0 and len(drawing.visible) > 0
    assert (drawing.segments >= -1).all() and (drawing.segments[:, 0] <= 97).all()


def test_steps_walk_the_algorithm(models, hsr_cli, tmp_path):
    cube = hsr.load(models / "cube.obj")
    walk = hsr.steps(cube, "zbuffer", yaw=30, pitch=20, **SIZE_KW)
    assert len(walk) == 12  # the z-buffer takes one step per triangle
    texts = [s.text for s in walk]
    assert all(t.startswith(f"triangle {k}:") for k, t in enumerate(texts))
    hsr_cli("render", models / "cube.obj", "--step", "5", "--yaw", "30", "--pitch", "20", *SIZE, "-o", tmp_path / "step5.png")
    assert walk[4].index == 5 and np.array_equal(walk[4].frame.color, read_png(tmp_path / "step5.png"))
    whole = hsr.render(cube, yaw=30, pitch=20, **SIZE_KW)
    assert np.array_equal(walk[-1].frame.color, whole.color)
    with pytest.raises(IndexError):
        walk[12]
    with pytest.raises(hsr.Error, match="cannot show its steps|draws lines"):
        hsr.steps(cube, "appel")


# --- documentation -----------------------------------------------------------------------------------

@pytest.mark.parametrize("function", [hsr.render, hsr.lines, hsr.steps, hsr.load, hsr.Scene.from_arrays])
def test_docstrings_explain_every_keyword(function):
    doc = inspect.getdoc(function)
    for name in inspect.signature(function).parameters:
        if name in {"scene", "path", "vertices", "faces"}:
            continue
        assert name in doc or (name == "lighting_params" and "lighting model's" in doc), \
            f"{function.__name__}: {name} is not explained"


def test_type_stubs_name_what_the_package_has():
    stub = pathlib.Path(hsr.__file__).with_name("__init__.pyi")
    tree = ast.parse(stub.read_text())
    stubbed = {node.name for node in tree.body if isinstance(node, (ast.FunctionDef, ast.ClassDef))}
    for name in hsr.__all__:
        assert name in stubbed, f"{name} has no stub"
    functions = {node.name: node for node in tree.body if isinstance(node, ast.FunctionDef)}
    for name in ("render", "lines", "steps", "load"):
        stub_args = [a.arg for a in functions[name].args.args + functions[name].args.kwonlyargs]
        assert stub_args == list(inspect.signature(getattr(hsr, name)).parameters), name


# --- the README's example and an installed copy ---------------------------------------------------

def run_example(name, models, tmp_path):
    """docs/examples/NAME run as the docs show it, from a folder that has the models."""
    source = pathlib.Path(os.environ.get("HSR_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
    (tmp_path / "models").symlink_to(models)
    return subprocess.run([sys.executable, str(source / "docs/examples" / name)], cwd=tmp_path,
                          capture_output=True, text=True, check=True).stdout


def test_readme_example_prints_the_bunnys_depth_range(models, hsr_cli, tmp_path):
    output = run_example("bunny_depth.py", models, tmp_path)
    match = re.fullmatch(r"the bunny is ([0-9.]+) to ([0-9.]+) away along the view axis\n", output)
    assert match, output
    hsr_cli("render", models / "bunny.obj", "--width", "512", "--height", "512", "-o", tmp_path / "b.png",
            "--depth-out", tmp_path / "depth.npy")
    depth = np.load(tmp_path / "depth.npy")
    finite = depth[np.isfinite(depth)]
    assert (match[1], match[2]) == (f"{finite.min():.3f}", f"{finite.max():.3f}")


def test_python_md_examples_run(models, hsr_cli, tmp_path):
    run_example("python_frame.py", models, tmp_path)
    hsr_cli("render", models / "bunny.obj", "--width", "512", "--height", "512", "-o", tmp_path / "cli.png")
    assert (tmp_path / "bunny.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    folder = tmp_path / "steps"
    folder.mkdir()
    lines = run_example("cube_steps.py", models, folder)
    assert [line.split(" ", 1)[0] for line in lines.splitlines()] == [str(k) for k in range(1, 13)]
    assert all(" triangle " in line and "pixels written" in line for line in lines.splitlines())


def test_installed_package_finds_the_installed_plugins(tmp_path):
    build, site = os.environ.get("HSR_BUILD_DIR"), os.environ.get("HSR_PYTHON_INSTALL_DIR")
    if not build or not site:
        pytest.skip("HSR_BUILD_DIR and HSR_PYTHON_INSTALL_DIR are set by CTest")
    prefix = tmp_path / "prefix"
    subprocess.run(["cmake", "--install", build, "--prefix", str(prefix)], check=True, capture_output=True)
    script = "import hsr, os; print(hsr.__file__); print(sorted({os.path.dirname(p['path']) for p in hsr.plugins()}))"
    env = {k: v for k, v in os.environ.items() if k not in {"PYTHONPATH", "HSR_PLUGIN_PATH"}}
    env["PYTHONPATH"] = str(prefix / site)
    run = subprocess.run([sys.executable, "-c", script], env=env, cwd=tmp_path, capture_output=True, text=True,
                         check=True)
    module, folders = run.stdout.splitlines()
    assert module.startswith(str(prefix / site))
    assert ast.literal_eval(folders) == [str(prefix / "lib/hsr/plugins")]
