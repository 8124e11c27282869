"""Door leaves and window panes: the detail items placed in a floor's openings.

The thesis added doors and windows as "detail objects" after the furniture (algorithm 7,
line 44). Here every door and window of the floor gets one, whether or not the rule
table lists it: the model comes from a detail row (``isDetail``) of the room's type whose
name mentions ``door`` or ``window``, else the shipped ``door`` / ``window`` model. Each
item fills its opening: width and height of the opening, depth of the wall, centred in
the wall's thickness, front towards the room (for a door: the room its leaf swings into);
a window item is lifted to its sill (:attr:`cga.model.FurnitureItem.elevation`). A door
item names its door (:attr:`cga.model.FurnitureItem.door`): the meshing hangs it on the
door's hinge at the door's angle (:mod:`cga.doors`).
"""

from __future__ import annotations

import numpy as np

from cga.model import OUTSIDE, FloorPlan, FurnitureItem, Wall

from .clearance import face_offset, quarter_turn_towards
from .rules import FurnitureRules

__all__ = ["DEFAULT_DETAIL_MODELS", "detail_items", "detail_model"]

DEFAULT_DETAIL_MODELS = {"door": "door", "window": "window"}
"""Models of doors and windows whose rooms' types have no detail row."""


def detail_model(rules: FurnitureRules, kind: str, room_types: list[str | None]) -> str:
    """The model for a ``kind`` ("door"/"window") opening between rooms of ``room_types``:
    the first matching detail row of the first type that has one, else the default."""
    for room_type in room_types:
        for rule in rules.details(room_type):
            if rule.detail_kind == kind:
                return rule.name
    return DEFAULT_DETAIL_MODELS[kind]


def _in_wall(plan: FloorPlan, wall: Wall, at: tuple[float, float], room: int, other: int) -> tuple[tuple[float, float], float, int]:
    """Centre, depth and rotation of an item filling the wall's thickness at ``at``, its
    front towards ``room``."""
    normal = wall.normal_into(room)
    inner, outer = face_offset(plan, room, at), face_offset(plan, other, at)
    depth = inner + outer if inner + outer > 0 else wall.thickness
    centre = np.asarray(at) + normal * (inner - outer) / 2
    return (float(centre[0]), float(centre[1])), depth, quarter_turn_towards(normal)


def detail_items(plan: FloorPlan, rules: FurnitureRules) -> list[FurnitureItem]:
    """One detail item per door and per window of ``plan``.

    Parameters
    ----------
    plan:
        A floor with doors and windows.
    rules:
        The furniture table; its detail rows name the models.

    Returns
    -------
    list of FurnitureItem
        Doors with a leaf (named ``door<id>``, in the room the leaf swings into, or the inner room of
        a door that opens outwards) then windows (``window<id>``), all ``is_detail``.
    """
    types = {room.id: room.type for room in plan.rooms}
    items = []
    for door in plan.doors:
        if not door.leaf:
            continue
        room = door.swing_room if door.swing_room != OUTSIDE else next(
            r for r in door.rooms if r != OUTSIDE)
        other = next((r for r in door.rooms if r != room), OUTSIDE)
        centre, depth, rotation = _in_wall(plan, plan.wall(door.wall), door.position, room, other)
        model = detail_model(rules, "door", [types.get(room), types.get(other)])
        items.append(FurnitureItem(
            name=f"door{door.id}", model=model, room=room, position=centre,
            rotation=rotation, size=(door.width, door.height, depth), is_detail=True,
            door=door.id))
    for window in plan.windows:
        centre, depth, rotation = _in_wall(plan, plan.wall(window.wall), window.position,
                                           window.room, OUTSIDE)
        model = detail_model(rules, "window", [types.get(window.room)])
        items.append(FurnitureItem(
            name=f"window{window.id}", model=model, room=window.room, position=centre,
            rotation=rotation, size=(window.width, window.height, depth), is_detail=True,
            elevation=window.sill))
    return items
