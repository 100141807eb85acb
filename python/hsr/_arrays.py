"""Scenes made from numpy arrays, and the parts of Scene, Frame and Lines written in Python."""

import numpy as np

from . import _hsr
from ._hsr import Frame, Lines, Scene, UsageError


def _float32(name, array):
    try:
        return np.ascontiguousarray(array, dtype=np.float32)  # no copy when float32 in C order already
    except (TypeError, ValueError):
        raise UsageError(f"{name}: numbers expected") from None


def _indices(name, array, vertex_count):
    array = np.asarray(array)
    if array.size and not np.issubdtype(array.dtype, np.integer):
        raise UsageError(f"{name}: vertex indices must be integers, not {array.dtype}")
    if array.size and (array.min() < 0 or array.max() >= vertex_count):
        bad = array.min() if array.min() < 0 else array.max()
        raise UsageError(f"{name}: vertex index {bad} is out of range (there are {vertex_count} vertices)")
    return np.ascontiguousarray(array, dtype=np.uint32)


def _mesh_dict(vertices, faces, colors=None, transforms=None, *, color=None, name=None, crease_angle=None,
               opacity=None):
    label = name or "mesh"
    vertices = _float32(f"{label}: vertices", vertices)
    mesh = {"vertices": vertices, "name": name, "color": color, "crease_angle": crease_angle, "opacity": opacity}
    try:
        grid = np.asarray(faces)  # every face with as many corners: an (M, K) array
    except ValueError:
        grid = None  # faces with different numbers of corners
    if grid is not None and grid.ndim == 2 and grid.dtype != object:
        if grid.shape[1] < 3:
            raise UsageError(f"{label}: faces of {grid.shape[1]} corners (a face needs at least 3)")
        indices = _indices(f"{label}: faces", grid, len(vertices))
        if grid.shape[1] == 3:
            mesh["triangles"] = indices
        else:
            mesh["corners"] = indices.ravel()
            mesh["face_ends"] = np.arange(1, len(grid) + 1, dtype=np.uint32) * np.uint32(grid.shape[1])
    else:
        polygons = [np.asarray(f).ravel() for f in faces]
        if not polygons:
            raise UsageError(f"{label}: no faces")
        for k, polygon in enumerate(polygons):
            if len(polygon) < 3:
                raise UsageError(f"{label}: face {k} has fewer than 3 corners")
        mesh["corners"] = _indices(f"{label}: faces", np.concatenate(polygons), len(vertices))
        mesh["face_ends"] = np.cumsum([len(p) for p in polygons], dtype=np.uint32)
    if colors is not None:
        colors = np.asarray(colors)
        if np.issubdtype(colors.dtype, np.integer):
            colors = colors / 255.0  # 0-255, as most files and libraries store them
        mesh["face_colors"] = _float32(f"{label}: colors", colors)
    if transforms is not None:
        transforms = np.ascontiguousarray(transforms, dtype=np.float64)
        mesh["transforms"] = transforms.reshape(1, 4, 4) if transforms.shape == (4, 4) else transforms
    return mesh


class Mesh:
    """One mesh for Scene.from_meshes: the arguments of Scene.from_arrays, kept together."""

    def __init__(self, vertices, faces, colors=None, transforms=None, *, color=None, name=None, crease_angle=None,
                 opacity=None):
        self._dict = _mesh_dict(vertices, faces, colors, transforms, color=color, name=name,
                                crease_angle=crease_angle, opacity=opacity)

    def __repr__(self):
        return f"<hsr.Mesh {self._dict.get('name') or ''} of {len(self._dict['vertices'])} vertices>"


def from_arrays(vertices, faces, colors=None, transforms=None, *, color=None, name=None, crease_angle=None,
                opacity=None):
    """A scene of one mesh given as arrays.

    vertices      (N, 3) positions; read where they lie when float32 in C order, else converted
    faces         (M, 3) vertex indices of triangles (read where they lie when uint32 in C order),
                  or a list of polygons (sequences of 3 or more indices, counter-clockwise seen
                  from the front), cut into triangles as a model file's faces are
    colors        one colour per face, (M, 3): floats in [0, 1] or integers 0-255
    transforms    (K, 4, 4) or (4, 4): where the mesh is placed, world = T @ (x, y, z, 1); several
                  are drawn as instances of one stored mesh when each is a rotation, a uniform
                  scale and a shift, else as copies
    color         one colour for the whole mesh (over colors)
    name          the mesh's name in messages and statistics
    crease_angle  degrees: corner normals smooth across edges sharper than this (default 40)
    opacity       0 to 1 (the a-buffer and ray casting show it)

    hsr builds its own scene from the arrays (normals, adjacency): later changes to them do not
    reach it. Raises hsr.UsageError for arrays of the wrong shape or indices out of range.
    """
    return _hsr.scene_from_meshes([_mesh_dict(vertices, faces, colors, transforms, color=color, name=name,
                                              crease_angle=crease_angle, opacity=opacity)])


def from_meshes(meshes):
    """A scene of several meshes (hsr.Mesh, each with the arguments of Scene.from_arrays)."""
    meshes = list(meshes)
    for m in meshes:
        if not isinstance(m, Mesh):
            raise UsageError(f"Scene.from_meshes: hsr.Mesh objects expected, not {type(m).__name__}")
    return _hsr.scene_from_meshes([m._dict for m in meshes])


def _scene_repr(scene):
    return (f"<hsr.Scene {scene.source}: {scene.triangle_count} triangles"
            + (f", {scene.instance_count} instances" if scene.instance_count else "") + ">")


def _frame_repr(frame):
    stats = frame.stats
    return f"<hsr.Frame {frame.width}x{frame.height} {stats['algorithm']} + {stats['lighting']}>"


def _lines_repr(lines):
    return f"<hsr.Lines {lines.width}x{lines.height}: {len(lines.qi)} segments by {lines.stats['algorithm']}>"


def _install():
    import hsr

    Scene.from_arrays = staticmethod(from_arrays)
    Scene.from_meshes = staticmethod(from_meshes)
    Scene.__repr__ = _scene_repr
    Frame.__repr__ = _frame_repr
    Lines.__repr__ = _lines_repr
    Lines.visible = property(lambda self: self.segments[self.qi == 0],
                             doc="(K, 4) the visible segments (qi 0): a copy")
    Lines.hidden = property(lambda self: self.segments[self.qi != 0],
                            doc="(K, 4) the hidden segments (qi not 0, with hidden='dashed'): a copy")
    hsr.Mesh = Mesh
