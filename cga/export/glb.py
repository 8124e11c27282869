"""``<name>.glb``: the building as binary glTF 2.0 (docs/outputs.md).

A node tree that follows the node paths: ``floor1/room3_Kitchen/wall2`` is a child of
the group node ``floor1/room3_Kitchen``, itself a child of ``floor1``; every node keeps
its full path as its name. Group nodes (floors, rooms, ``…/furniture``, the parts of a
massing grammar's shape path) carry no mesh and no transform; a floor's node carries the
floor's facts (index, elevation, height), a room's its type, area and id.

Structure (walls, slabs, masses) is meshed in the building's frame. Every item is a node
with its own pivot: a furniture item at the centre of its footprint on the floor, turned
by its quarter turns; a door leaf at its hinge, turned by the build's door angle
(:mod:`cga.doors`). Their meshes are given in that local frame, so instances of the same
model (same size) share one glTF mesh, made (normals and all) once, and a viewer or
Blender turns an item or swings a door about the right point. Meshes carry normals. A node's ``extras`` are its semantic
labels plus its ``kind`` and ``static`` flag, its semantic ``class_id`` and ``class`` and
its ``instance_id`` (:mod:`cga.semantics`); y up, metres.

Every primitive has a glTF metallic-roughness material: a node's mesh has one primitive
per material of the node (:mod:`cga.appearance`: wall paint per room, floors per room,
each furniture part's material), base colours linear as glTF wants them; see-through
materials (window glass) blend. Each room's ceiling lights are nodes
(``floor0/room3_Office/light0``) that point at ``KHR_lights_punctual`` point lights
(candela, colour of their temperature; docs/appearance.md).

The bytes are a pure function of the scene: nodes in the given order, no timestamps,
extras with sorted keys. The same seed gives a byte-identical file (tested).

The file is written here with numpy and :mod:`json` (glTF 2.0 §4.4: a 12-byte header, a
JSON chunk, a BIN chunk): importing trimesh, whose exporter wrote it before, costs a third
of a build's CPU (it loads SciPy and networkx). The document is laid out as trimesh 5.2's
exporter (``trimesh.exchange.gltf``) laid it out, key order, accessors, buffer views,
materials and floats, so a file is byte for byte the one trimesh wrote but for
``asset.generator``, which names cga (and the lengths that follow from it); a file
without meshes has no BIN chunk rather than an empty one.
"""

from __future__ import annotations

import json
import math
import struct
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from cga.appearance.material import Material
from cga.errors import ExportError
from cga.fsutil import atomic_write
from cga.mesh import face_normals as unit_normals
from cga.mesh import unitize
from cga.model import FloorPlan, rotation_matrix
from cga.scene import Scene, SceneNode
from cga.semantics import class_names, instance_ids, node_class

from .palette import kind_material

__all__ = ["scene_as_glb", "export_glb", "json_safe", "node_pivot"]

_IDENTITY = np.eye(4)

_PLAIN = frozenset({str, int, float, bool, type(None)})
"""Types :func:`json_safe` returns as they are."""

_STRINGS = frozenset({str})

_GENERATOR = "cga"
"""The glTF ``asset.generator``."""

_ONES = [1.0, 1.0, 1.0]
"""Sums the rows of a ``float[n, 3]`` as trimesh sums them, ``np.dot`` with ones (BLAS),
so the corner angles' rounding is trimesh's."""

_FLAT_ANGLE = 1e-8
"""A triangle with a corner angle (radians) below this is degenerate and weighs nothing in
its vertices' normals (trimesh's ``tol.merge``)."""

_TRIANGLES = 4
"""glTF primitive mode: a triangle list."""

_FLOAT, _UNSIGNED_INT, _UNSIGNED_BYTE = 5126, 5125, 5121
"""glTF accessor component types."""


def json_safe(value: Any) -> Any:
    """``value`` as plain JSON data: numpy scalars/arrays → numbers/lists, tuples → lists,
    mappings with sorted string keys, sets as sorted lists.

    Raises
    ------
    TypeError
        A value with no JSON form (the message names its type).
    """
    kind = type(value)
    if kind in _PLAIN:  # the common cases first: isinstance against ABCs is slow
        return value
    if kind is dict and _STRINGS.issuperset(map(type, value)) and _PLAIN.issuperset(
            map(type, value.values())):  # a node's extras: sorted as they are
        return {k: value[k] for k in sorted(value)}
    if kind is dict:
        return {str(k): json_safe(value[k]) for k in sorted(value, key=str)}
    if kind is list or kind is tuple:
        return [json_safe(v) for v in value]
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, (int, float)):
        return value
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return json_safe(value.tolist())
    if isinstance(value, Mapping):
        return {str(k): json_safe(value[k]) for k in sorted(value, key=str)}
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    if isinstance(value, (set, frozenset)):
        return sorted(json_safe(v) for v in value)
    raise TypeError(f"cannot store a {type(value).__name__} in glTF extras")


def node_pivot(node: SceneNode) -> np.ndarray:
    """4×4 world transform of a node's own frame: a door leaf's hinge frame at its angle,
    a furniture item's footprint centre on its floor turned by its quarter turns, the
    identity for structure."""
    if node.door is not None:
        return node.door.frame()
    if node.kind != "furniture":
        return np.eye(4)
    (x0, y0, z0), (x1, _, z1) = np.asarray(node.mesh.bounds).tolist()  # floats: no numpy scalars
    matrix = np.eye(4)
    matrix[:3, :3] = _QUARTER_TURNS[(node.item.rotation if node.item is not None else 0) % 4]
    matrix[:3, 3] = ((x0 + x1) / 2, y0, (z0 + z1) / 2)
    return matrix


_QUARTER_TURNS = [rotation_matrix(turns) for turns in range(4)]
""":func:`~cga.model.rotation_matrix` of 0 to 3 quarter turns, made once."""


def _local_vertices(nodes: Sequence[SceneNode],
                    inverses: Sequence[np.ndarray | None]) -> list[np.ndarray]:
    """Each node's vertices in the frame of its pivot, given as the pivot's inverse
    (None: the identity, for structure), on a micrometre grid, so instances of one model
    land on identical local vertices. Each node is moved alone (one matrix product each)
    and all are rounded at once: rounding is element by element, and per node its calls
    cost more than the arithmetic."""
    moved = []
    for node, inverse in zip(nodes, inverses, strict=True):
        vertices = np.asarray(node.mesh.vertices, dtype=float)
        if inverse is not None:
            vertices = vertices @ inverse[:3, :3].T + inverse[:3, 3]
        moved.append(vertices)
    ends = np.cumsum([len(vertices) for vertices in moved])
    return np.split(np.round(np.concatenate([np.zeros((0, 3)), *moved]), 6) + 0.0, ends[:-1])


def _local_transforms(pivots: Sequence[np.ndarray]) -> list[np.ndarray | None]:
    """The inverse of each pivot, None for the identity (:func:`_local_vertices`): the
    pivots compared with the identity at once, and one batched :func:`numpy.linalg.inv`
    (the same LAPACK solve per matrix as one call each)."""
    stack = np.asarray(pivots, dtype=np.float64).reshape(-1, 4, 4)
    moved = np.flatnonzero((stack != _IDENTITY).any(axis=(1, 2))).tolist()
    out: list[np.ndarray | None] = [None] * len(pivots)
    if moved:
        for i, inverse in zip(moved, np.linalg.inv(stack[moved])):
            out[i] = inverse
    return out


_Source = tuple[bytes, bytes, bytes, tuple[Material, ...]]
"""A dressed node's local vertices, faces and face materials (their bytes) and materials."""


def _source_key(node: SceneNode, vertices: np.ndarray) -> _Source | None:
    """What a dressed node's glTF mesh is made of (local vertices, faces, each face's
    material): nodes with equal keys get equal meshes, so the mesh is made once (the
    instances of a model share it). None for a node without materials. The arrays' bytes
    themselves: a dict hashes them once, where a digest of each cost twice as much."""
    if not node.materials or node.face_materials is None:
        return None
    return (vertices.tobytes(), np.asarray(node.mesh.faces, dtype=np.int64).tobytes(),
            np.asarray(node.face_materials, dtype=np.int64).tobytes(), node.materials)


def _written_matrices(matrices: Sequence[np.ndarray] | np.ndarray) -> list[list[float] | None]:
    """Each 4×4 matrix as a node's glTF ``matrix`` (its columns, as plain floats), or None
    where it is within 1e-8 of the identity by trimesh's measure (the spread of the
    difference, ``np.ptp``) and is not written. All at once: per matrix, the reductions
    and the conversion cost more than the arithmetic."""
    stack = np.asarray(matrices, dtype=np.float64).reshape(-1, 4, 4)
    offsets = (stack - _IDENTITY).reshape(-1, 16)
    near = (offsets.max(axis=1) - offsets.min(axis=1)) < 1e-8
    columns = stack.transpose(0, 2, 1).reshape(-1, 16).tolist()
    return [None if close else column for close, column in zip(near.tolist(), columns)]


class _Array(NamedTuple):
    """An array as the file stores it (little-endian, in its accessor's component type)
    with the maximum and the minimum of each component that its accessor lists."""

    data: np.ndarray
    high: list[Any]
    low: list[Any]


class _Piece(NamedTuple):
    """Triangles of one look: local ``vertices``, ``faces`` indexing them and the unit
    ``normals`` of the vertices (as a mesh is compared: ``float64``, ``int64``), and the
    same as the file stores them: ``indices`` (``uint32``), ``positions`` and
    ``directions`` (``float32``)."""

    vertices: np.ndarray
    faces: np.ndarray
    normals: np.ndarray
    indices: _Array
    positions: _Array
    directions: _Array


@dataclass(frozen=True, eq=False, slots=True)
class _Primitive:
    """A primitive of a glTF mesh: its ``piece`` and its look: RGBA ``colors`` per vertex
    (a mesh's own colours), else the index of its ``material`` in the document."""

    piece: _Piece
    colors: np.ndarray | None
    material: int | None


def _primitives(node: SceneNode, pieces: Sequence[tuple[int | None, _Piece]],
                gltf: _Gltf) -> list[_Primitive]:
    """The node's mesh as primitives: its ``pieces`` (:func:`_node_pieces`) with their
    looks, a dressed node's pieces the materials they are of (:attr:`SceneNode.materials`),
    an undressed node's one piece its own vertex colours (:func:`_own_colors`), else its
    kind's material."""
    out = []
    for k, piece in pieces:
        if k is not None:
            out.append(_Primitive(piece, None, gltf.material(node.materials[k])))
            continue
        colors = _own_colors(node.mesh, len(piece.vertices))
        look = None if colors is not None else gltf.material(kind_material(node.kind))
        out.append(_Primitive(piece, colors, look))
    return out


def _node_pieces(nodes: Sequence[SceneNode], meshed: Sequence[int],
                 local: Sequence[np.ndarray], faces: Mapping[int, np.ndarray],
                 normals: Mapping[int, np.ndarray]) -> dict[int, list[tuple[int | None, _Piece]]]:
    """The pieces of each meshed node (``nodes[i]`` for ``i`` in ``meshed``) at its
    ``local`` vertices, with their ``faces`` and vertex ``normals``: a dressed node's
    faces split by material (:func:`_material_pieces`), each piece with the index of its
    material; an undressed node's faces as they are, one piece with None (none without
    faces). A mesh without a piece has no primitives (and its node no mesh)."""
    dressed = [i for i in meshed if _dressed(nodes[i])]
    split = dict(zip(dressed, _material_pieces(
        [(len(local[i]), faces[i], np.asarray(nodes[i].face_materials, dtype=np.int64),
          len(nodes[i].materials)) for i in dressed])))
    looks: list[tuple[int, int | None]] = []
    parts = []
    for i in meshed:
        if i in split:
            for k, used, renumbered in split[i]:
                looks.append((i, k))
                parts.append((local[i][used], renumbered, normals[i][used]))
        elif len(faces[i]):
            looks.append((i, None))
            parts.append((local[i], faces[i], normals[i]))
    out: dict[int, list[tuple[int | None, _Piece]]] = {i: [] for i in meshed}
    for (i, look), piece in zip(looks, _pieces(parts)):
        out[i].append((look, piece))
    return out


def _pieces(parts: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray]]) -> list[_Piece]:
    """The pieces of ``(vertices, faces, normals)`` parts (each with a face), their arrays
    cast and bounded for all parts at once: one reduction per array of a house's few
    hundred cost more than the arithmetic."""
    if not parts:
        return []
    vertex_starts = np.cumsum([0, *(len(v) for v, _, _ in parts[:-1])])
    corner_starts = np.cumsum([0, *(np.size(f) for _, f, _ in parts[:-1])])
    indices = _bounded(np.concatenate([np.ravel(f) for _, f, _ in parts]).astype("<u4"),
                       corner_starts)
    positions = _bounded(np.concatenate([v for v, _, _ in parts]).astype("<f4"), vertex_starts)
    directions = _bounded(np.concatenate([n for _, _, n in parts]).astype("<f4"), vertex_starts)
    return [_Piece(v, f, n, *arrays)
            for (v, f, n), arrays in zip(parts, zip(indices, positions, directions))]


def _bounded(data: np.ndarray, starts: np.ndarray) -> list[_Array]:
    """``data`` (rows, or single components) cut into runs at ``starts`` (ascending, each
    run not empty), each run with the maximum and minimum of each component."""
    rows = data.reshape(len(data), -1)
    highs = np.maximum.reduceat(rows, starts, axis=0).tolist()
    lows = np.minimum.reduceat(rows, starts, axis=0).tolist()
    bounds = starts.tolist() + [len(data)]
    return [_Array(data[a:b], high, low)
            for a, b, high, low in zip(bounds, bounds[1:], highs, lows)]


def _dressed(node: SceneNode) -> bool:
    """Whether the node has materials, one per face (:attr:`SceneNode.face_materials`)."""
    return bool(node.materials) and node.face_materials is not None


def _own_colors(mesh: Any, count: int) -> np.ndarray | None:
    """A mesh's own RGBA colours of its ``count`` vertices (``uint8[count, 4]``), None when
    it has none: a :class:`cga.mesh.TriangleMesh`'s ``vertex_colors``, or the vertex (or
    face) colours of a trimesh object's visual (a textured visual's material is not
    kept). Only an object of trimesh's own is asked for its visual: any other attribute
    of a TriangleMesh would make a trimesh object and import trimesh (:mod:`cga.mesh`)."""
    if type(mesh).__module__.startswith("trimesh"):
        visual = getattr(mesh, "visual", None)
        colors = visual.vertex_colors if visual is not None and visual.kind in (
            "vertex", "face") else None
    else:
        colors = getattr(mesh, "vertex_colors", None)
    if colors is None or len(colors) != count:
        return None
    return np.asarray(colors, dtype=np.uint8)


def _material_pieces(meshes: Sequence[tuple[int, np.ndarray, np.ndarray, int]]
                     ) -> list[list[tuple[int, np.ndarray, np.ndarray]]]:
    """Each mesh ``(vertex count, faces, face materials, material count)`` split by
    material: for each material ``k`` (ascending) with faces, ``(k, used, local)``, the
    vertices its faces use (ascending) and those faces (in their order) renumbered to
    them, as :func:`numpy.unique` with its inverse gives them. A face whose material is
    not one of the mesh's is left out.

    All meshes at once, without a sort of the vertices: every (mesh, material) pair, a
    slot, gets a run of marks as long as its mesh's vertices; the faces, grouped by slot
    (stable), mark the vertices they use, and a vertex's new number is the count of marks
    before it in its slot. Per piece that is numpy's own work; on the hundred meshes of a
    house, most of a few dozen triangles, one pass over all saves the per-call overhead
    that outweighed it."""
    sizes = np.array([size for size, _, _, _ in meshes], dtype=np.int64)
    counts = np.array([count for _, _, _, count in meshes], dtype=np.int64)
    face_counts = [len(faces) for _, faces, _, _ in meshes]
    slot_start = np.cumsum([0, *counts])
    base = np.cumsum([0, *np.repeat(sizes, counts)])  # each slot's run of marks
    owner = np.repeat(np.arange(len(meshes)), face_counts)
    faces = np.concatenate([np.zeros((0, 3), dtype=np.int64), *(np.reshape(
        f, (-1, 3)) for _, f, _, _ in meshes)])
    materials = np.concatenate([np.zeros(0, dtype=np.int64), *(m for _, _, m, _ in meshes)])
    kept = (materials >= 0) & (materials < counts[owner])
    slots = (materials + slot_start[:-1][owner])[kept]
    order = np.argsort(slots, kind="stable")
    slots, faces = slots[order], faces[kept][order]
    spots = base[slots][:, None] + faces
    marks = np.zeros(base[-1], dtype=bool)
    marks[spots] = True
    before = np.concatenate([[0], np.cumsum(marks)])  # marks before each spot
    local = before[spots] - before[base[slots]][:, None]
    used = np.flatnonzero(marks)
    used -= np.repeat(base[:-1], np.diff(before[base]))
    face_bounds = np.searchsorted(slots, np.arange(len(base)))
    used_bounds = before[base]
    out: list[list[tuple[int, np.ndarray, np.ndarray]]] = []
    for start, count in zip(slot_start[:-1].tolist(), counts.tolist()):
        out.append([(k, used[used_bounds[s]:used_bounds[s + 1]],
                     local[face_bounds[s]:face_bounds[s + 1]])
                    for k, s in enumerate(range(start, start + count))
                    if face_bounds[s + 1] > face_bounds[s]])
    return out


def _corner_angles(corners: np.ndarray) -> np.ndarray:
    """The angle (radians) at each corner of each triangle (``float[m, 3, 3]`` corners),
    all three zero for a triangle with a (nearly) zero angle: trimesh's
    ``triangles.angles``."""
    u = unitize(corners[:, 1] - corners[:, 0])[0]
    v = unitize(corners[:, 2] - corners[:, 0])[0]
    w = unitize(corners[:, 2] - corners[:, 1])[0]
    angles = np.zeros((len(corners), 3))
    angles[:, 0] = np.arccos(np.clip(np.dot(u * v, _ONES), -1, 1))
    angles[:, 1] = np.arccos(np.clip(np.dot(-u * w, _ONES), -1, 1))
    angles[:, 2] = np.pi - angles[:, 0] - angles[:, 1]
    angles[(angles < _FLAT_ANGLE).any(axis=1), :] = 0.0
    return angles


def _vertex_normals(meshes: Sequence[tuple[np.ndarray, np.ndarray]]) -> list[np.ndarray]:
    """Unit normals of the vertices of each mesh ``(vertices, faces)``: the mean of the
    normals of the faces around each vertex weighted by their corner angles (Thürrner &
    Wüthrich 1998), as trimesh's ``Trimesh.vertex_normals`` computes it
    (``geometry.weighted_vertex_normals``), bit for bit: the same unit face normals and
    corner angles (:func:`~cga.mesh.unitize`, :func:`_corner_angles`), each vertex's sum taken over
    its faces in ascending order from zero (trimesh's sparse product adds them in that
    order; :func:`numpy.bincount` adds its weights in order too), then made unit.

    All meshes are summed at once, as one mesh of separate pieces: a vertex's sum runs
    over the faces of its own mesh in the same order as for that mesh alone, and every
    other step works face by face or vertex by vertex, so each mesh gets the very normals
    it would get alone.

    A vertex whose mean has (nearly) zero length takes the normal of the last of its
    faces that has one (else +y). A vertex where faces facing opposite ways meet (a
    stair's tread edge on its landing) averages to nothing, and one of only degenerate
    (zero-area) triangles has no normal at all, which glTF forbids (the Khronos
    validator's ACCESSOR_VECTOR3_NON_UNIT). The vertices of a mesh without faces keep
    zero normals (such a mesh is not written)."""
    counts = [len(vertices) for vertices, _ in meshes]
    starts = np.cumsum([0, *counts])
    vertices = np.concatenate([np.zeros((0, 3)), *(v for v, _ in meshes)])
    faces = np.concatenate([np.zeros((0, 3), dtype=np.int64),
                            *(np.reshape(f, (-1, 3)) + start
                              for (_, f), start in zip(meshes, starts))])
    normals = np.zeros((len(vertices), 3))
    if len(faces):
        corners = vertices[faces]
        face_normals = unit_normals(corners)[0]  # degenerate triangles: zero, as trimesh's
        counted = (face_normals ** 2).sum(axis=1) > 0.5
        angles = _corner_angles(corners)[counted]
        terms = (angles[:, :, None] * face_normals[counted][:, None, :]).reshape(-1, 3)
        around = faces[counted].ravel()
        sums = np.column_stack([np.bincount(around, weights=terms[:, axis],
                                            minlength=len(vertices)) for axis in range(3)])
        normals = unitize(sums)[0]
        flat = np.linalg.norm(normals, axis=1) < 0.5
        if flat.any():
            has_faces = np.repeat([np.size(f) > 0 for _, f in meshes], counts)
            _face_normal_where_flat(normals, flat & has_faces, faces, face_normals)
    return [normals[a:b] for a, b in zip(starts[:-1], starts[1:])]


def _unit_once_more(normals: Sequence[np.ndarray]) -> list[np.ndarray]:
    """Each mesh's vertex ``normals`` made unit once more, as trimesh's exporter did: that
    moves a fifth of the float64s by an ulp, which could (in the demos never did) move a
    float32. All meshes at once: :func:`~cga.mesh.unitize` works row by row."""
    ends = np.cumsum([len(n) for n in normals])
    return np.split(unitize(np.concatenate([np.zeros((0, 3)), *normals]))[0], ends[:-1])


def _face_normal_where_flat(normals: np.ndarray, flat: np.ndarray, faces: np.ndarray,
                            face_normals: np.ndarray) -> None:
    """Give each ``flat`` vertex the normal of the last of its ``faces`` that has one,
    else +y, in place. The last: the face the trimesh-based writer took, the first with a
    normal of those trimesh's ``geometry.vertex_face_indices`` lists for the vertex, in
    descending order."""
    corner_faces = np.repeat(np.arange(len(faces)), 3)
    corners = faces.ravel()
    usable = np.linalg.norm(face_normals, axis=1) > 0.5
    keep = usable[corner_faces] & flat[corners]
    last = np.full(len(normals), -1)
    np.maximum.at(last, corners[keep], corner_faces[keep])
    normals[flat] = np.where((last[flat] >= 0)[:, None], face_normals[last[flat]],
                             (0.0, 1.0, 0.0))


_MeshKey = tuple[tuple[bytes, bytes, bytes | int | None], ...]


def _mesh_key(primitives: Sequence[_Primitive]) -> _MeshKey:
    """The primitives of a glTF mesh as a key: the bytes of their vertices and faces, and
    their looks (the bytes of their vertex colours, or their material). The bytes
    themselves: a dict hashes them once, where a digest of each cost three times as
    much."""
    return tuple((np.asarray(p.piece.vertices, dtype=np.float64).tobytes(),
                  np.asarray(p.piece.faces, dtype=np.int64).tobytes(),
                  p.material if p.colors is None else p.colors.tobytes()) for p in primitives)


def _byte_steps(rgba: Sequence[float]) -> list[float]:
    """RGBA in 0..1 on 1/255 steps, as trimesh stored a colour (as 8 bits): each value
    not finite taken as 0, clipped to 0..1, the nearest step (ties to even, as
    :func:`numpy.round`). Plain floats: numpy costs more than the arithmetic on four."""
    return [round(min(max(v * 255, 0.0), 255.0)) / 255 if math.isfinite(v) else 0.0
            for v in rgba]


class _Gltf:
    """A glTF document being written: nodes, meshes, materials, accessors and the bytes
    of its one buffer, laid out as trimesh's exporter laid them out (module notes).

    Equal data is stored once: arrays of equal bytes share a buffer view, equal arrays in
    the same role share an accessor, equal materials are one material, and equal meshes
    (:func:`_mesh_key`) are one mesh. Each array is padded to 4 bytes in the buffer."""

    def __init__(self) -> None:
        self._nodes: dict[str, dict[str, Any]] = {}
        self._parents: dict[str, str] = {}
        self._meshes: list[dict[str, Any]] = []
        self._mesh_index: dict[_MeshKey, int] = {}  # _mesh_key → mesh
        self._mesh_names: set[str] = set()
        self._materials: list[dict[str, Any]] = []
        self._material_index: dict[Material, int] = {}
        self._material_written: dict[str, int] = {}  # material JSON → material
        self._accessors: list[dict[str, Any]] = []
        self._accessor_index: dict[tuple[str, bytes], int] = {}
        self._views: list[dict[str, Any]] = []
        self._view_index: dict[bytes, int] = {}
        self._chunks: list[bytes] = []
        self._length = 0

    def node(self, name: str, parent: str | None, extras: dict[str, Any],
             matrix: list[float] | None = None, mesh: int | None = None,
             extensions: dict[str, Any] | None = None) -> None:
        """Add the node ``name`` under ``parent`` (None: the scene's root), or give the
        node of that name these contents when there is one (a group whose path turns out
        to be a scene node's too). ``matrix`` is as :func:`_written_matrices` gives it
        (None: not written)."""
        node = self._nodes.setdefault(name, {})
        if parent is not None:
            self._parents[name] = parent
        if mesh is not None:
            node["mesh"] = mesh
        node["matrix"] = matrix
        node["extensions"] = extensions
        node["extras"] = extras

    def material(self, material: Material) -> int:
        """The index of ``material`` as a glTF metallic-roughness material, written on
        first use. The base colour is stored in 1/255 steps, as trimesh stored it (as an
        8-bit colour); materials whose glTF forms are equal are written once."""
        index = self._material_index.get(material)
        if index is None:
            written: dict[str, Any] = {"pbrMetallicRoughness": {
                "baseColorFactor": _byte_steps(material.linear_rgba()),
                "roughnessFactor": float(material.roughness),
                "metallicFactor": float(material.metallic)}, "name": material.name}
            if material.transparent:
                written["alphaMode"] = "BLEND"
            written["doubleSided"] = bool(material.transparent)
            index = self._material_written.setdefault(json.dumps(written), len(self._materials))
            if index == len(self._materials):
                self._materials.append(written)
            self._material_index[material] = index
        return index

    def mesh(self, name: str, primitives: Sequence[_Primitive]) -> int | None:
        """The index of the mesh of ``primitives``, written (named ``name``, or
        ``name#<n>`` when another mesh has that name) unless an equal one was; None
        without primitives."""
        if not primitives:
            return None
        key = _mesh_key(primitives)
        index = self._mesh_index.get(key)
        if index is None:
            if name in self._mesh_names:
                name = f"{name}#{len(self._mesh_index)}"
            self._mesh_names.add(name)
            index = self._mesh_index[key] = len(self._meshes)
            self._meshes.append({"name": name, "extras": {},
                                 "primitives": [self._primitive(p) for p in primitives]})
        return index

    def _primitive(self, primitive: _Primitive) -> dict[str, Any]:
        """A primitive's glTF form, its arrays stored (indices, positions, colours,
        normals: trimesh's order, as are the keys of each accessor)."""
        piece = primitive.piece
        indices = self._accessor("indices", {"componentType": _UNSIGNED_INT, "type": "SCALAR"},
                                 piece.indices)
        attributes = {"POSITION": self._accessor(
            "position", {"componentType": _FLOAT, "type": "VEC3", "byteOffset": 0},
            piece.positions)}
        if primitive.colors is not None:
            colors = primitive.colors.astype("<u1")
            attributes["COLOR_0"] = self._accessor(
                "color", {"componentType": _UNSIGNED_BYTE, "normalized": True, "type": "VEC4",
                          "byteOffset": 0}, _bounded(colors, np.zeros(1, dtype=np.int64))[0])
        attributes["NORMAL"] = self._accessor(
            "normal", {"componentType": _FLOAT, "count": len(piece.normals), "type": "VEC3",
                       "byteOffset": 0}, piece.directions)
        out: dict[str, Any] = {"attributes": attributes, "indices": indices, "mode": _TRIANGLES}
        if primitive.material is not None:
            out["material"] = primitive.material
        return out

    def _accessor(self, role: str, blob: dict[str, Any], array: _Array) -> int:
        """The index of the accessor of ``array`` in ``role`` (``blob`` its type), made
        with its count, bounds and buffer view unless an equal one was."""
        raw = array.data.tobytes()
        index = self._accessor_index.get((role, raw))
        if index is None:
            blob["bufferView"] = self._view(raw)
            blob["count"] = len(array.data)
            blob["max"] = array.high
            blob["min"] = array.low
            index = self._accessor_index[(role, raw)] = len(self._accessors)
            self._accessors.append(blob)
        return index

    def _view(self, raw: bytes) -> int:
        """The index of the buffer view of ``raw``, appended (padded to 4 bytes) unless
        equal bytes were."""
        index = self._view_index.get(raw)
        if index is None:
            padded = raw + bytes(-len(raw) % 4)
            index = self._view_index[raw] = len(self._views)
            self._views.append({"buffer": 0, "byteOffset": self._length,
                                "byteLength": len(padded)})
            self._chunks.append(padded)
            self._length += len(padded)
        return index

    def glb(self, extras: dict[str, Any], lights: list[dict[str, Any]]) -> bytes:
        """The binary glTF file: the document with the scene's ``extras`` and its
        ``KHR_lights_punctual`` ``lights``, its JSON padded with spaces so the BIN chunk
        starts on 4 bytes. A document without meshes has no BIN chunk (trimesh wrote an
        empty one, which the Khronos validator notes should be omitted)."""
        number = {name: k for k, name in enumerate(self._nodes)}
        children: dict[str, list[int]] = {}
        for name, parent in self._parents.items():
            children.setdefault(parent, []).append(number[name])
        nodes = []
        for name, contents in self._nodes.items():
            node: dict[str, Any] = {"name": name}
            if name in children:
                node["children"] = children[name]
            if contents.get("mesh") is not None:
                node["mesh"] = contents["mesh"]
            for key in ("matrix", "extensions", "extras"):
                if contents.get(key):
                    node[key] = contents[key]
            nodes.append(node)
        tree: dict[str, Any] = {
            "scene": 0, "scenes": [{"extras": extras, "nodes": [0]}],
            "asset": {"version": "2.0", "generator": _GENERATOR}}
        if self._meshes:
            tree["accessors"] = self._accessors
            tree["meshes"] = self._meshes
        if self._materials:
            tree["materials"] = self._materials
        tree["nodes"] = nodes
        if lights:
            tree["extensionsUsed"] = ["KHR_lights_punctual"]
        if self._length:
            tree["buffers"] = [{"byteLength": self._length}]
            tree["bufferViews"] = self._views
        if lights:
            tree["extensions"] = {"KHR_lights_punctual": {"lights": lights}}
        content = json.dumps(tree, separators=(",", ":"), check_circular=False).encode("ascii")
        content += b" " * (4 - (len(content) + 20) % 4)
        binary = ([struct.pack("<2I", self._length, 0x004E4942), *self._chunks]  # "BIN"
                  if self._length else [])
        header = struct.pack("<5I", 0x46546C67, 2, 20 + len(content) + sum(map(len, binary)),
                             len(content), 0x4E4F534A)  # "glTF", version, length; "JSON"
        return b"".join([header, content, *binary])


def _group_extras(scene: Scene) -> dict[str, dict[str, Any]]:
    """The facts of the floor and room group nodes, by group path."""
    out: dict[str, dict[str, Any]] = {}
    for plan in scene.floors:
        out[f"floor{plan.index}"] = {"kind": "floor", "floor": plan.index,
                                     "elevation": plan.elevation, "height": plan.height,
                                     "walking_surface": plan.floor_y}
        for room in plan.rooms:
            out[f"floor{plan.index}/{room.label}"] = _room_extras(plan, room.id)
    return out


def _room_extras(plan: FloorPlan, room_id: int) -> dict[str, Any]:
    room = plan.room(room_id)
    return {"kind": "room", "floor": plan.index, "room": room.id, "type": room.type,
            "area": room.area, "circulation": room.circulation}


def scene_as_glb(scene: Scene, nodes: Sequence[SceneNode]) -> bytes:
    """The scene's nodes as a binary glTF document with a node tree (module notes).

    Raises
    ------
    ExportError
        Two nodes share a path, or a node's extras cannot be stored as JSON.
    """
    root = scene.name
    gltf = _Gltf()
    gltf.node(root, None, json_safe({"kind": "building", "name": scene.name,
                                     "seed": scene.seed}))
    groups = _group_extras(scene)
    made: set[str] = set()
    seen: set[str] = set()
    made_from: dict[_Source, int | None] = {}  # _source_key → mesh
    instances = instance_ids(nodes)
    names = class_names()
    pivots = [node_pivot(node) for node in nodes]
    inverses = _local_transforms(pivots)
    moved = [i for i, inverse in enumerate(inverses) if inverse is not None]
    matrices = dict(zip(moved, _written_matrices([pivots[i] for i in moved])))
    local = _local_vertices(nodes, inverses)
    sources = [_source_key(node, vertices) for node, vertices in zip(nodes, local)]
    first: dict[_Source, int] = {}
    meshed = [i for i, source in enumerate(sources)
              if source is None or first.setdefault(source, i) == i]
    faces = {i: np.asarray(nodes[i].mesh.faces, dtype=np.int64) for i in meshed}
    normals = dict(zip(meshed, _unit_once_more(
        _vertex_normals([(local[i], faces[i]) for i in meshed]))))
    pieces = _node_pieces(nodes, meshed, local, faces, normals)
    for i, node in enumerate(nodes):
        if node.path in seen or node.path == root:
            raise ExportError(f"two scene nodes are both named {node.path!r}")
        seen.add(node.path)
        try:
            cid = node_class(node)
            extras = json_safe({**node.labels, "kind": node.kind, "static": node.static,
                                "class_id": cid, "class": names[cid],
                                "instance_id": instances[node.path]})
        except TypeError as error:
            raise ExportError(f"node {node.path!r}: {error}") from None
        parent = _parent(gltf, node.path, root, groups, made)
        source = sources[i]
        if source is not None and source in made_from:
            mesh = made_from[source]
        else:
            primitives = _primitives(node, pieces[i], gltf)
            mesh = gltf.mesh(node.item.model if node.item is not None else node.path,
                             primitives)
            if source is not None:
                made_from[source] = mesh
        gltf.node(node.path, parent, extras, matrix=matrices.get(i), mesh=mesh)
        made.add(node.path)
    lights = _add_lights(gltf, scene, root, groups, made)
    return gltf.glb(json_safe({"generator": "cga", "name": scene.name, "seed": scene.seed,
                               "units": "metres", "up": "y"}), lights)


def _add_lights(gltf: _Gltf, scene: Scene, root: str, groups: Mapping[str, dict[str, Any]],
                made: set[str]) -> list[dict[str, Any]]:
    """A node per ceiling light (``floor0/room3_Office/light0``) under its room, pointing
    at its ``KHR_lights_punctual`` light; returns the lights' definitions."""
    out = []
    places = np.tile(_IDENTITY, (len(scene.lights), 1, 1))
    places[:, :3, 3] = np.reshape([light.position for light in scene.lights], (-1, 3))
    for k, (light, matrix) in enumerate(zip(scene.lights, _written_matrices(places))):
        parent = _parent(gltf, light.name, root, groups, made)
        extras = json_safe({"kind": "light", "floor": light.floor, "room": light.room,
                            "lumens": light.lumens, "temperature": light.temperature})
        gltf.node(light.name, parent, extras, matrix=matrix,
                  extensions={"KHR_lights_punctual": {"light": k}})
        out.append({"name": light.name, "type": "point", "color": json_safe(list(light.color)),
                    "intensity": json_safe(round(light.intensity, 6))})
    return out


def _parent(gltf: _Gltf, path: str, root: str, groups: Mapping[str, dict[str, Any]],
            made: set[str]) -> str:
    """The group node above ``path``, made (with its own ancestors) when missing; ``made``
    holds the groups and nodes made so far."""
    above = path.rpartition("/")[0]
    if above and above in made:  # the common case; a made group's ancestors are made
        return above
    parent = root
    parts = path.split("/")
    for depth in range(1, len(parts)):
        group = "/".join(parts[:depth])
        if group not in made:
            made.add(group)
            gltf.node(group, parent, json_safe(groups.get(group, {"kind": "group"})))
        parent = group
    return parent


def export_glb(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path, name: str) -> list[Path]:
    """Write ``<out_dir>/<name>.glb`` atomically; returns ``[path]``."""
    return [atomic_write(Path(out_dir) / f"{name}.glb", scene_as_glb(scene, nodes))]
