"""Door leaves as scene nodes: the door model hung on its hinge (:mod:`cga.doors`).

A door's detail item (``FurnitureItem.door`` set) is not posed by its quarter turns like
other items: its model is fitted to the leaf's box in the hinge frame and turned by the
build's door angle, so every output shows the door as the build leaves it.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import cache

import numpy as np
import trimesh

from cga.doors import door_leaf, leaf_model_matrix, slab_range
from cga.model import FloorPlan, FurnitureItem
from cga.operations.furniture.library import FurnitureModel
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
    slab = slab_range(model.parts)
    leaf = door_leaf(plan, door, slab[1] - slab[0])
    frame = leaf.frame()
    mesh = leaf_mesh(model.mesh, frame @ leaf_model_matrix(leaf, model.mesh.bounds, slab))
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


def box_arrays(extents: np.ndarray, matrix: np.ndarray) -> MeshArrays:
    """The box ``trimesh.creation.box(extents=extents, transform=matrix)`` makes, as
    arrays (its corners moved by ``matrix`` the way trimesh moves them, its triangles),
    without making a mesh. ``matrix`` turns and moves (a hinge frame), so the triangles
    keep their winding."""
    unit = _unit_box()
    return MeshArrays(trimesh.transform_points(unit.vertices * np.asarray(extents, dtype=float),
                                               matrix), unit.faces)


@cache
def _unit_box() -> MeshArrays:
    """trimesh's box of unit extents about the origin."""
    box = trimesh.creation.box()
    return MeshArrays(np.asarray(box.vertices).copy(), np.asarray(box.faces).copy())


def _translation(offset: Sequence[float] | np.ndarray) -> np.ndarray:
    matrix = np.eye(4)
    matrix[:3, 3] = offset
    return matrix


def leaf_mesh(mesh: trimesh.Trimesh, matrix: np.ndarray) -> trimesh.Trimesh:
    """``mesh`` moved by ``matrix``, its triangles turned over when the matrix mirrors
    (a leaf hinged at the model's +x side), colours kept."""
    faces = np.asarray(mesh.faces)
    if np.linalg.det(matrix[:3, :3]) < 0:
        faces = faces[:, ::-1]
    return trimesh.Trimesh(vertices=trimesh.transform_points(mesh.vertices, matrix),
                           faces=faces.copy(),
                           visual=mesh.visual.copy() if mesh.visual is not None else None,
                           process=False)
