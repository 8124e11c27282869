"""Furniture items as scene nodes: each item's model posed in world coordinates.

The model library (:mod:`cga.operations.furniture.library`) loads a model once in its own
frame; this module scales, turns and moves a copy of it to the pose the plan gives the
item (docs/architecture.md, "Meshing").
"""

from __future__ import annotations

from functools import lru_cache
from itertools import accumulate
from weakref import WeakKeyDictionary

import numpy as np

from cga.mesh import TriangleMesh, homogeneous, transform_points
from cga.model import FloorPlan, FurnitureItem, rotation_matrix
from cga.operations.furniture.library import FurnitureModel, ModelGeometry, ModelLibrary
from cga.scene import ItemInfo, MeshArrays, SceneNode

__all__ = ["item_node", "item_transform"]

_SIZE_TOLERANCE = 1e-9
"""Item and model sizes closer than this (m) need no scaling."""


def item_transform(item: FurnitureItem, model: FurnitureModel, floor_y: float) -> np.ndarray:
    """4×4 matrix taking ``model``'s frame to the world pose of ``item``.

    The model is scaled per axis to ``item.size`` (when that differs from the model's
    size, e.g. a door leaf sized to its opening, or a jittered item), turned by
    ``item.rotation`` quarter turns plus ``item.yaw`` about +y and moved to ``(x, floor_y + item.elevation, z)``.

    Raises
    ------
    ValueError
        ``item.size`` has an extent that is not positive.
    """
    return _pose(item, model, floor_y)[1]


def _pose(item: FurnitureItem, model: FurnitureModel, floor_y: float
          ) -> tuple[tuple[float, ...], np.ndarray]:
    """:func:`item_transform`'s matrix and its 3×3 linear part (row by row, floats):
    :func:`_linear`, and the move, made into an array once (numpy's overhead on a 4×4
    outweighs the arithmetic); the last row is the identity's."""
    target = tuple(item.size)
    if len(target) != 3 or not all(extent > 0 for extent in target):
        raise ValueError(f"furniture item {item.name!r}: size {item.size} must be three "
                         f"positive extents (width, height, depth) in metres")
    scale = tuple(1.0 if abs(t - own) <= _SIZE_TOLERANCE else t / own
                  for t, own in zip(target, model.size))
    linear = _linear(item.rotation, item.yaw, scale)
    matrix = np.array([*linear[0:3], float(item.position[0]),
                       *linear[3:6], float(floor_y + item.elevation),
                       *linear[6:9], float(item.position[1]),
                       0.0, 0.0, 0.0, 1.0]).reshape(4, 4)
    return linear, matrix


@lru_cache(maxsize=1024)
def _linear(quarter_turns: int, yaw: float, scale: tuple[float, float, float]
            ) -> tuple[float, ...]:
    """``rotation_matrix(quarter_turns, yaw) @ np.diag(scale)`` row by row, on floats.

    Each entry of that product is ``rotation[i][j] * scale[j]`` plus products with
    zero, at least one of them +0 (a turn about +y has a middle row and column of 0, 1,
    0), so it is that term, and +0 where the term is zero (``+ 0.0`` makes the -0 of a
    negative entry times zero +0): the floats of numpy's product, bit for bit
    (tests/property/test_mesh_arithmetic_props.py). Most items of a house are unscaled
    and turned by quarter turns alone, so they share a handful of these."""
    return tuple(r * k + 0.0 for row in rotation_matrix(quarter_turns, yaw).tolist()
                 for r, k in zip(row, scale))


class _Posable:
    """What posing a model needs beside the matrix, the same for every item of it: its
    joined mesh, that mesh's vertices as homogeneous rows (:func:`~cga.mesh.homogeneous`,
    read-only) and where each part's vertices end in it."""

    __slots__ = ("joined", "stack", "ends")

    def __init__(self, geometry: ModelGeometry) -> None:
        self.joined = geometry.joined
        self.stack = homogeneous(self.joined.vertices)
        self.stack.flags.writeable = False
        self.ends = list(accumulate(len(v) for v in geometry.vertices))


_POSABLE: "WeakKeyDictionary[ModelGeometry, _Posable]" = WeakKeyDictionary()
""":class:`_Posable` of each model geometry: the library shares a model among every item
and build of a process, and a house poses a few dozen models a hundred times."""


def _posable(geometry: ModelGeometry) -> _Posable:
    known = _POSABLE.get(geometry)
    if known is None:
        known = _POSABLE[geometry] = _Posable(geometry)
    return known


def _posed(model: FurnitureModel, matrix: np.ndarray
           ) -> tuple[TriangleMesh, tuple[MeshArrays, ...]]:
    """``model`` moved by ``matrix`` (from :func:`item_transform`): its mesh, with its
    colours, and its parts as arrays.

    The model's mesh is its parts one after another, so the parts' posed vertices are
    slices of the mesh's, moved in one pass; the parts and the mesh share the model's
    faces and colours (read-only). The matrix turns and scales by positive factors, so
    the faces keep their winding.
    """
    posable = _posable(model.geometry)
    source = posable.joined
    vertices = transform_points(source.vertices, matrix, stack=posable.stack)
    ends = posable.ends
    pieces = [vertices[start:end] for start, end in zip([0, *ends], ends)]
    parts = tuple(map(MeshArrays, pieces, model.geometry.faces))
    return TriangleMesh(vertices, source.faces, source.vertex_colors), parts


def item_node(item: FurnitureItem, plan: FloorPlan, library: ModelLibrary) -> SceneNode:
    """The scene node of a placed furniture item: its model posed in world coordinates.

    The node is named ``floor{i}/room{id}_{Type}/furniture/{name}`` (``room{id}`` when the
    room is untyped). Solid items are dynamic; details (doors, windows) and
    non-colliding items (rugs) are static. ``parts`` are the posed convex parts (arrays,
    :class:`~cga.scene.MeshArrays`), ``item`` carries the semantic labels and the mass (posed volume × the model's density).

    Raises
    ------
    ResourceNotFoundError
        The item's model is not in the library.
    """
    model = library.get(item.model)
    if item.door is not None:  # a door leaf hangs on its hinge
        from .doors import leaf_node

        return leaf_node(item, plan, model)
    linear, matrix = _pose(item, model, plan.floor_y)
    mesh, parts = _posed(model, matrix)
    room = plan.room(item.room)
    volume = model.volume * _volume_factor(linear)
    return SceneNode(
        path=f"floor{plan.index}/{room.label}/furniture/{item.name}",
        kind="furniture",
        mesh=mesh,
        static=item.is_detail or item.non_collision,
        parts=parts,
        item=ItemInfo(model=model.name, model_path=model.path, room=item.room, name=item.name,
                      parent=item.parent, rotation=item.rotation, density=model.density,
                      mass=volume * model.density, convex_parts=model.convex_parts,
                      geometry=model.geometry, pose=matrix),
    )


@lru_cache(maxsize=1024)
def _volume_factor(linear: tuple[float, ...]) -> float:
    """How an affine map with the 3×3 linear part ``linear`` (row by row) scales every
    volume (and convex hull volume): ``|det|``.

    The items of a house share a few dozen turns and sizes among a hundred poses, so it
    is computed once per linear part: the same LAPACK determinant as for each item, so
    the same float."""
    return abs(float(np.linalg.det(np.reshape(linear, (3, 3)))))
