"""Dressing scene nodes: a material for every triangle of every node.

Every node gets :attr:`~cga.scene.SceneNode.materials` (its distinct materials) and
:attr:`~cga.scene.SceneNode.face_materials` (an index into them per triangle), which
every exporter writes (one glTF primitive, OBJ ``usemtl`` run or USD mesh per material):

* a wall's faces take the paint of the room they face (a point a little in front of
  the face, along its normal, lies in that room's interior), the facade outside the
  footprint, and the paint of the wall's first room elsewhere (jambs, tops);
* a slab's walking surface takes each room's floor (:func:`cga.meshing.solids` cuts
  the top room by room, so every top triangle lies in one room), its underside the
  ceiling, its edges ``slab``; a roof slab is ``roof`` with a ``ceiling`` underside;
* a furniture item's faces take the materials of its model's parts, by the part
  (OBJ group) they belong to, and their own colour when the build is neutral;
* stairs, rails, masses and faces one material of their kind.
"""

from __future__ import annotations

from collections.abc import Sequence
from weakref import WeakKeyDictionary

import numpy as np
import shapely

from cga.mesh import corner_means, face_normals
from cga.model import FloorPlan
from cga.scene import SceneNode

from .material import Material
from .palette import Palette

__all__ = ["dress_nodes", "PROBE"]

PROBE = 0.05
"""How far in front of a wall face (m) the room it faces is looked up."""

_UP = 0.5  # a face whose normal's y exceeds this faces up (below -this: down)


def dress_nodes(nodes: Sequence[SceneNode], plans: Sequence[FloorPlan], palette: Palette,
                models: "object | None" = None) -> list[SceneNode]:
    """``nodes`` with their materials set (module notes).

    Parameters
    ----------
    nodes:
        Scene nodes as the meshing layer makes them.
    plans:
        The build's floor plans (rooms and their types).
    palette:
        The build's materials.
    models:
        The furniture model library (:class:`~cga.operations.furniture.library.ModelLibrary`)
        the items were posed from; needed when ``nodes`` has furniture.
    """
    by_floor = {plan.index: plan for plan in plans}
    floors = [_floor_of(node.path) for node in nodes]
    faced = _faced_rooms(nodes, floors, by_floor)
    walls: dict[int, list[Material]] = {}
    items = _ItemDressings()
    out = []
    for k, (node, floor) in enumerate(zip(nodes, floors)):
        plan = by_floor.get(floor) if floor is not None else None
        if k in faced and plan is not None:
            if plan.index not in walls:
                walls[plan.index] = [_room_material(palette, "wall", plan, r)
                                     for r in range(len(plan.rooms))]
            dressing = _compact(*_wall(node, plan, palette, walls[plan.index], *faced[k]))
        elif node.kind == "furniture" and node.item is not None and models is not None:
            dressing = _furniture(node, plan, palette, models, items)
        else:
            dressing = _compact(*_dress(node, plan, palette))
        out.append(_dressed(node, *dressing))
    return out


def _dressed(node: SceneNode, materials: tuple[Material, ...],
             face_materials: np.ndarray) -> SceneNode:
    """``node`` with its materials: ``dataclasses.replace`` written out (every field of
    :class:`~cga.scene.SceneNode` named, :data:`_KEPT` and the two set here), as
    ``replace`` walks the dataclass's fields for each of a house's couple of hundred
    nodes: a fifth of the time dressing took."""
    return SceneNode(path=node.path, kind=node.kind, mesh=node.mesh, extras=node.extras,
                     static=node.static, parts=node.parts, item=node.item, door=node.door,
                     materials=materials, face_materials=face_materials)


_KEPT = ("path", "kind", "mesh", "extras", "static", "parts", "item", "door")
"""The fields of :class:`~cga.scene.SceneNode` that :func:`_dressed` copies (a test checks
they and ``materials``, ``face_materials`` are all of them)."""


def _faced_rooms(nodes: Sequence[SceneNode], floors: list[int | None],
                 by_floor: dict[int, FloorPlan]) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """For each wall node on a known floor (by its index in ``nodes``; ``floors``: each
    node's floor, :func:`_floor_of`), the room each face faces (:func:`_rooms_at` of a
    probe :data:`PROBE` in front of it) and whether it faces the outside of the
    footprint.

    A floor's walls are probed together: one point-in-polygon call per room and floor
    instead of one per room and wall, whose overhead outweighed the few dozen points
    a wall has (the answers, point by point, are the same). Their triangles' centres
    and normals are worked out together too: row by row, so the same floats as wall by
    wall (tests/property/test_mesh_arithmetic_props.py).
    """
    per_floor: dict[int, list[int]] = {}
    for k, (node, floor) in enumerate(zip(nodes, floors)):
        if node.kind == "wall" and floor in by_floor:
            per_floor.setdefault(floor, []).append(k)
    faced = {}
    for floor, members in per_floor.items():
        plan = by_floor[floor]
        triangles = np.concatenate([nodes[k].mesh.triangles for k in members])
        points = corner_means(triangles) + face_normals(triangles)[0] * PROBE
        rooms = _rooms_at(plan, points[:, [0, 2]])
        outside = ~shapely.contains_xy(plan.footprint, points[:, 0], points[:, 2])
        ends = np.cumsum([len(nodes[k].mesh.faces) for k in members])[:-1]
        for k, room, out in zip(members, np.split(rooms, ends), np.split(outside, ends)):
            faced[k] = (room, out)
    return faced


_Dressing = tuple[tuple[Material, ...], np.ndarray]
"""A node's ``materials`` and ``face_materials``."""


def _compact(materials: list[Material], index: np.ndarray) -> _Dressing:
    """The materials the faces use, each once, in candidate order, and the faces'
    indices into them."""
    used = set(index.tolist())  # a few dozen faces: cheaper than numpy's bincount
    unique: dict[str, int] = {}
    order: list[Material] = []
    remap = np.zeros(len(materials), dtype=np.int64)
    for k, m in enumerate(materials):
        if k not in used:
            continue
        if m.name not in unique:
            unique[m.name] = len(order)
            order.append(m)
        remap[k] = unique[m.name]
    return tuple(order), remap[index]


def _floor_of(path: str) -> int | None:
    head = path.split("/", 1)[0]
    return int(head[5:]) if head.startswith("floor") and head[5:].isdigit() else None


def _dress(node: SceneNode, plan: FloorPlan | None, palette: Palette
           ) -> tuple[list[Material], np.ndarray]:
    """Candidate materials and each face's index into them, for a node that is neither
    a wall nor a furniture item."""
    count = len(node.mesh.faces)
    if plan is not None and node.kind in ("slab", "roof"):
        return _slab(node, plan, palette)
    surface = {"stair": "stair", "rail": "rail", "mass": "mass", "face": "face"}.get(node.kind,
                                                                                     "mass")
    return [palette.surface(surface)], np.zeros(count, dtype=np.int64)


def _rooms_at(plan: FloorPlan, points: np.ndarray) -> np.ndarray:
    """The index into ``plan.rooms`` of the room interior holding each plan point
    ``(x, z)``; -1 outside every room."""
    found = np.full(len(points), -1, dtype=np.int64)
    for k, room in enumerate(plan.rooms):
        inside = shapely.contains_xy(room.interior, points[:, 0], points[:, 1])
        found[inside & (found < 0)] = k
    return found


def _room_material(palette: Palette, surface: str, plan: FloorPlan, k: int) -> Material:
    room = plan.rooms[k]
    return palette.surface(surface, room_type=room.type,
                           key=(f"floor{plan.index}", f"room{room.id}"))


def _wall(node: SceneNode, plan: FloorPlan, palette: Palette, paints: list[Material],
          rooms: np.ndarray, outside: np.ndarray) -> tuple[list[Material], np.ndarray]:
    """A wall's faces: the paint of the room each faces (``paints``, one per room of
    ``plan``), the facade outside, else the paint of the wall's first room."""
    own = [r for r in node.extras.get("rooms", []) if r >= 0]
    ids = [room.id for room in plan.rooms]
    default = ids.index(min(own)) if own and min(own) in ids else -1
    materials = [*paints, palette.surface("facade")]
    fallback = materials[default] if default >= 0 else palette.surface("wall")
    materials.append(fallback)
    index = np.where(rooms >= 0, rooms, len(materials) - 1)
    index[(rooms < 0) & outside] = len(materials) - 2
    return materials, index


def _slab(node: SceneNode, plan: FloorPlan, palette: Palette) -> tuple[list[Material], np.ndarray]:
    mesh = node.mesh
    normals_y = mesh.face_normals[:, 1]
    top = normals_y > _UP
    down = normals_y < -_UP
    edge_surface = "roof" if node.kind == "roof" else "slab"
    materials = [palette.surface(edge_surface), palette.surface("ceiling")]
    index = np.zeros(len(mesh.faces), dtype=np.int64)
    index[down] = 1
    if node.kind == "roof":
        return materials, index
    rooms = _rooms_at(plan, mesh.triangles_center[top][:, [0, 2]])
    floors = [_room_material(palette, "floor", plan, k) for k in range(len(plan.rooms))]
    top_index = np.where(rooms >= 0, rooms + len(materials), 0)
    index[top] = top_index
    return materials + floors, index


_Parts = tuple[list[tuple[str, tuple[float, float, float]]], np.ndarray]
"""A model's parts as (group name, own colour), and each face's part."""

_MODEL_PARTS: "WeakKeyDictionary[object, _Parts]" = WeakKeyDictionary()
""":func:`_model_parts` of each model: the library shares a model among every build of a
process, and its parts never change."""


def _model_parts(model: object) -> _Parts:
    """The parts of a model (:class:`~cga.operations.furniture.library.FurnitureModel`):
    name and mean vertex colour (else the model's colour) of each, and the part of each
    face of the model's mesh; worked out once per model (:data:`_MODEL_PARTS`)."""
    known = _MODEL_PARTS.get(model)
    if known is None:
        known = _MODEL_PARTS[model] = _parts_of(model)
    return known


def _parts_of(model: object) -> _Parts:
    geometry = model.geometry  # type: ignore[attr-defined]
    counts = [len(f) for f in geometry.faces]
    names = geometry.names or tuple(f"part_{k}" for k in range(len(counts)))
    out = []
    for name, colors in zip(names, geometry.colors):
        if colors is not None and len(colors):
            r, g, b = (float(c) / 255.0 for c in np.asarray(colors)[:, :3].mean(axis=0))
            out.append((name, (r, g, b)))
        else:
            out.append((name, model.color))  # type: ignore[attr-defined]
    index = np.repeat(np.arange(len(counts), dtype=np.int64), counts)
    index.flags.writeable = False
    return out, index


class _ItemDressings:
    """What :func:`_furniture` has worked out in one :func:`dress_nodes` call: per model and
    room (per model alone in a neutral build), the materials, the model's face count and
    the dressing; per look (model and material names), the dressing items of any room
    dressed alike share."""

    def __init__(self) -> None:
        self.by_room: dict[tuple[str, ...], tuple[list[Material], int, _Dressing]] = {}
        self.by_look: dict[tuple[str, ...], _Dressing] = {}


def _furniture(node: SceneNode, plan: FloorPlan | None, palette: Palette, models: object,
               dressed: _ItemDressings) -> _Dressing:
    """A furniture item's materials: its model's parts' (:meth:`Palette.parts`), by the
    part each face belongs to.

    Items of one model in one room (the chairs of a room) have the same materials, so
    they are looked up once per model and room, and once per model in a neutral build
    (whose looks depend on neither the room nor the seed, :meth:`Palette.parts`); items
    dressed alike (in a neutral build, every item of the model) share one answer, kept
    by model and material names; their ``face_materials`` is one read-only array."""
    item = node.item
    assert item is not None
    key = (f"floor{plan.index}", f"room{item.room}") if plan is not None else ()
    place = (item.model,) if palette.mode == "neutral" else (item.model, *key)
    known = dressed.by_room.get(place)
    if known is None:
        parts, index = _model_parts(models.get(item.model))  # type: ignore[attr-defined]
        materials = palette.parts(item.model, parts, key=key)
        look = (item.model, *(m.name for m in materials))
        if look not in dressed.by_look:
            dressing = dressed.by_look[look] = _compact(materials, index)
            dressing[1].flags.writeable = False
        known = dressed.by_room[place] = (materials, len(index), dressed.by_look[look])
    materials, count, dressing = known
    if count != len(node.mesh.faces):  # a mesh not made from the model's parts
        return _compact(materials[:1], np.zeros(len(node.mesh.faces), dtype=np.int64))
    return dressing
