"""Semantic classes and instance ids: the labels of every scene node (DESIGN §15).

Training data needs integer labels that mean the same in every build: a wall is class 1
in every scene, a sofa class 39. The table ships as package data,
``cga/schema/classes.csv`` (``id;name;group``), and is documented in docs/render.md. Ids
are stable: a row is never renumbered or removed, a new class gets a new id.

* ``structure`` classes name building parts (wall, floor, ceiling, door, window, stair,
  roof, and ``building`` for the masses and faces of massing grammars);
* ``furniture`` classes are model names in their canonical form
  (:func:`cga.operations.furniture.library.normalize_name`); a model the table does not
  list (a grammar's own model) is class ``furniture``. The shipped door and window
  models are the classes ``door`` and ``window``;
* ``room_type`` classes label the top-down room-type map; a type the table does not list,
  and an untyped room, is ``room``.

Instance ids number the scene nodes 1, 2, … in node order (the meshing layer's
deterministic order), so an id names one node of one build; 0 is "nothing". The scene
JSON and the glb store both ids with every node and furniture item.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache
from importlib.resources import files
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # pragma: no cover
    from cga.scene import SceneNode

__all__ = ["SemanticClass", "UNLABELLED", "class_table", "class_id", "class_names",
           "furniture_class", "node_class", "room_type_class", "instance_ids"]

UNLABELLED = 0
"""The id of "nothing": no surface, no room."""

@dataclass(frozen=True)
class SemanticClass:
    """One row of the class table."""

    id: int
    name: str
    group: str


@cache
def class_table() -> tuple[SemanticClass, ...]:
    """The shipped class table, in id order (``cga/schema/classes.csv``)."""
    text = (files("cga") / "schema" / "classes.csv").read_text(encoding="utf-8")
    rows = [line.split(";") for line in text.splitlines()
            if line.strip() and not line.startswith("#")]
    header, *body = rows
    if header != ["id", "name", "group"]:
        raise ValueError(f"classes.csv: header {header} must be id;name;group")
    table = tuple(SemanticClass(int(i), name, group) for i, name, group in body)
    ids = [c.id for c in table]
    if len(set(ids)) != len(ids) or ids != sorted(ids):
        raise ValueError("classes.csv: ids must be unique and ascending")
    return table


@cache
def _by_name() -> dict[tuple[str, str], int]:
    return {(c.group, c.name): c.id for c in class_table()}


def class_id(name: str, group: str = "structure") -> int:
    """The id of class ``name`` of ``group``.

    Raises
    ------
    KeyError
        The table has no such class.
    """
    return _by_name()[(group, name)]


def furniture_class(model: str) -> int:
    """The class of a furniture model (by canonical name): ``door`` and ``window`` for
    those models, the model's own class when the table lists it, else ``furniture``."""
    from cga.operations.furniture.library import normalize_name

    key = normalize_name(model)
    table = _by_name()
    if key in ("door", "window"):
        return table[("structure", key)]
    return table.get(("furniture", key), table[("furniture", "furniture")])


_KIND_CLASSES = {"wall": "wall", "slab": "floor", "roof": "roof", "ceiling": "roof",
                 "mass": "building", "face": "building", "stair": "stair", "rail": "railing"}
"""Structure node kind → class. A storey's slab is its floor; the ``roof`` (or
``ceiling``) node is the roof slab over the top storey; a stairwell's ``rail`` is a
railing. (Seen from below, any slab is a ceiling: the
renderer labels that side ``ceiling`` pixel by pixel, docs/render.md.)"""


def node_class(node: "SceneNode") -> int:
    """The semantic class of a scene node: a furniture item's by its model (a door leaf
    is ``door``), other nodes' by their kind."""
    if node.door is not None:
        return class_id("door")
    if node.item is not None:
        return furniture_class(node.item.model)
    return class_id(_KIND_CLASSES.get(node.kind, "building"))


def room_type_class(room_type: str | None) -> int:
    """The room-type class of a room type (case-insensitive); ``room`` when the table does
    not list it or the room is untyped."""
    table = _by_name()
    if room_type is None:
        return table[("room_type", "room")]
    from cga.operations.furniture.library import normalize_name

    return table.get(("room_type", normalize_name(room_type)), table[("room_type", "room")])


def instance_ids(nodes: Sequence["SceneNode"]) -> dict[str, int]:
    """Node path → instance id: 1, 2, … in node order (unique within a build)."""
    return {node.path: index for index, node in enumerate(nodes, start=1)}


def class_names() -> dict[int, str]:
    """Class id → name, for legends."""
    return {c.id: c.name for c in class_table()}
