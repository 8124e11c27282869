"""Door leaves as scene nodes: the door model hung on its hinge (:mod:`cga.doors`).

A door's detail item (``FurnitureItem.door`` set) is not posed by its quarter turns like
other items: its model is fitted to the leaf's box in the hinge frame and turned by the
build's door angle, so every output shows the door as the build leaves it.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import cache
from weakref import WeakKeyDictionary

import numpy as np

from cga.doors import door_leaf, leaf_model_matrix, slab_range
from cga.mesh import TriangleMesh, mirrors, transform_points
from cga.model import FloorPlan, FurnitureItem
from cga.operations.furniture.library import FurnitureModel, ModelGeometry
from cga.scene import ItemInfo, MeshArrays, SceneNode

__all__ = ["box_arrays", "leaf_node"]


def leaf_node(item: FurnitureItem, plan: FloorPlan, model: FurnitureModel) -> SceneNode:
    """The scene node of a door item (``item.door`` set): the door model hung on its
    door's hinge at the door's angle, static, with :attr:`SceneNode.door` describing the
    hinge (its facts are also the node's ``extras``, for the glTF). ``parts`` is the
    leaf's one collision box, posed; its mass is that box's volume × the model's density.

    Raises
    ------
    KeyError
        ``item.door`` is not a door of ``plan``.
    """
    door = next((d for d in plan.doors if d.id == item.door), None)
    if door is None:
        raise KeyError(f"furniture item {item.name!r} hangs in door {item.door}, which "
                       f"floor {plan.index} does not have")
    geometry = model.geometry
    slab = _slab(geometry)
    leaf = door_leaf(plan, door, slab[1] - slab[0])
    frame = leaf.frame()
    mesh = leaf_mesh(geometry.joined, frame @ leaf_model_matrix(leaf, geometry.joined.bounds, slab))
    centre, extents = leaf.box()
    room = plan.room(item.room)
    return SceneNode(
        path=f"floor{plan.index}/{room.label}/furniture/{item.name}",
        kind="furniture",
        mesh=mesh,
        extras=leaf.labels(),
        static=True,
        parts=(box_arrays(extents, frame @ _translation(centre)),),
        item=ItemInfo(model=model.name, model_path=model.path, room=item.room, name=item.name,
                      parent=item.parent, rotation=item.rotation, density=model.density,
                      mass=float(np.prod(extents)) * model.density, convex_parts=True),
        door=leaf,
    )


_SLABS: "WeakKeyDictionary[ModelGeometry, tuple[float, float]]" = WeakKeyDictionary()


def _slab(geometry: ModelGeometry) -> tuple[float, float]:
    """:func:`~cga.doors.slab_range` of a door model's parts, measured once per model
    (every door of a house hangs the same model; the library shares it among builds)."""
    known = _SLABS.get(geometry)
    if known is None:
        known = _SLABS[geometry] = slab_range(geometry.vertices)
    return known


def box_arrays(extents: np.ndarray, matrix: np.ndarray) -> MeshArrays:
    """The box ``trimesh.creation.box(extents=extents, transform=matrix)`` makes, as
    arrays (its corners moved by ``matrix`` the way trimesh moves them, its triangles),
    without making a mesh. ``matrix`` turns and moves (a hinge frame), so the triangles
    keep their winding."""
    unit = _unit_box()
    return MeshArrays(transform_points(unit.vertices * np.asarray(extents, dtype=float), matrix),
                      unit.faces)


@cache
def _unit_box() -> MeshArrays:
    """trimesh's box of unit extents about the origin (``trimesh.creation.box()``): its
    corners and triangles, written out."""
    corners = np.array([[-1, -1, -1], [-1, -1, 1], [-1, 1, -1], [-1, 1, 1],
                        [1, -1, -1], [1, -1, 1], [1, 1, -1], [1, 1, 1]], dtype=np.float64) / 2
    faces = np.array([[1, 3, 0], [4, 1, 0], [0, 3, 2], [2, 4, 0], [1, 7, 3], [5, 1, 4],
                      [5, 7, 1], [3, 7, 2], [6, 4, 2], [2, 7, 6], [6, 5, 4], [7, 5, 6]],
                     dtype=np.int64)
    return MeshArrays(corners, faces)


def _translation(offset: Sequence[float] | np.ndarray) -> np.ndarray:
    matrix = np.eye(4)
    matrix[:3, 3] = offset
    return matrix


def leaf_mesh(mesh: TriangleMesh, matrix: np.ndarray) -> TriangleMesh:
    """``mesh`` moved by ``matrix``, its triangles turned over when the matrix mirrors
    (a leaf hinged at the model's +x side), colours kept."""
    faces = mesh.faces
    if mirrors(matrix):
        faces = faces[:, ::-1]
    return TriangleMesh(transform_points(mesh.vertices, matrix), faces, mesh.vertex_colors)
