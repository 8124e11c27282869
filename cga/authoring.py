"""A small Python API for rule authors: test a typing or furniture table with pytest.

A rule author builds a floor from rectangles, types (and furnishes) it with a seed and
asserts types, adjacency and doors (docs/room_typing.md, docs/furniture.md)::

    from cga.authoring import floor_from_rectangles, type_floor, rooms_of_type, are_adjacent

    def test_every_room_opens_onto_the_hall():
        plan = floor_from_rectangles([(0, 4, 14, 5.6), (0, 0, 7, 4), (7, 0, 14, 4),
                                      (0, 5.6, 5, 10), (5, 5.6, 9, 10), (9, 5.6, 14, 10)],
                                     circulation=[0])
        for seed in range(20):
            typed = type_floor(plan, "house_types.csv", seed=seed)
            assert rooms_of_type(typed, "Livingroom")
            assert doors_between(typed, "Bedroom", "Hall")

Rooms may be named by id (``int``) or by type (``str``: any room of that type);
:data:`~cga.model.OUTSIDE` or ``"outside"`` names the outside. Everything is in metres
and m² (no grammar ``units``).

Names: these ``*_floor`` functions take paths and seeds, as a rule author has them; each
wraps the operation library's function that takes parsed tables and a random stream
(``plan_from_rectangles``, ``type_plan``, ``add_furniture.furnish``).
"""

from __future__ import annotations

import dataclasses
import difflib
from collections.abc import Collection, Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np

from cga.errors import UsageError
from cga.model import OUTSIDE, Door, FloorPlan, FloorSettings, Room
from cga.operations.add_furniture import furnish
from cga.operations.floorplan.rectangles import plan_from_rectangles
from cga.operations.furniture.library import ModelLibrary, default_library
from cga.operations.furniture.passage import PASSAGE_WIDTH
from cga.operations.furniture.rules import load_furniture_rules
from cga.operations.roomtyping.rules import load_rule_table
from cga.operations.type_rooms import type_plan
from cga.resources import resolve_resource

__all__ = ["floor_from_rectangles", "type_floor", "furnish_floor", "rooms_of_type",
           "are_adjacent", "doors_between"]

RoomRef = int | str
"""A room id, a room type (any room of that type), or ``"outside"``."""


def floor_from_rectangles(rectangles: Sequence[tuple[float, float, float, float]], *,
                          index: int = 0, circulation: Collection[int] = (),
                          **settings: Any) -> FloorPlan:
    """An untyped floor whose room ``i`` is ``rectangles[i]`` = ``(x0, z0, x1, z1)`` (m).

    Parameters
    ----------
    rectangles:
        Axis-aligned rooms tiling a connected footprint without holes.
    index:
        Floor number; 0 (the ground floor) is the one that gets a front door.
    circulation:
        Ids of the rectangles that are halls or corridors (as ``make_floor`` carves
        them): they take the table's circulation type.
    **settings:
        :class:`~cga.model.FloorSettings` fields, e.g. ``door_width=1.0``,
        ``wall_thickness=0.15``, ``windows_per_wall=2``.

    Raises
    ------
    UsageError
        An unknown setting, or rectangles that do not make a floor.
    """
    known = [f.name for f in dataclasses.fields(FloorSettings)]
    for name in settings:
        if name not in known:
            close = difflib.get_close_matches(name, known, n=1)
            hint = f"; did you mean '{close[0]}'?" if close else f"; known: {', '.join(known)}"
            raise UsageError(f"unknown floor setting '{name}'{hint}")
    return plan_from_rectangles(rectangles, settings=FloorSettings(**settings), index=index,
                                circulation=circulation)


def type_floor(plan: FloorPlan, rules_path: str | Path, *, seed: int = 0, strict: bool = False,
               door_position: Literal["center", "random"] = "random") -> FloorPlan:
    """Type ``plan`` with a rule table, as ``type_rooms`` does in a grammar (``units`` 1).

    Parameters
    ----------
    plan:
        An untyped floor (:func:`floor_from_rectangles`).
    rules_path:
        The table: a path (relative to the working directory) or the name of a shipped
        table such as ``"house_types.csv"``.
    seed:
        Seed of the random stream; the same seed gives the same typing and doors.
    strict:
        Raise :class:`~cga.errors.NoSolutionError` instead of adding doors the rules do
        not ask for.
    door_position:
        ``"center"`` or ``"random"``.

    Raises
    ------
    ResourceNotFoundError, RuleTableError, NoSolutionError
    """
    table = load_rule_table(resolve_resource(rules_path, "rules"))
    return type_plan(plan, table, np.random.default_rng(seed), strict=strict,
                     door_position=door_position)


def furnish_floor(plan: FloorPlan, rules: str | Path, *, seed: int = 0, units: float = 1.0,
                  steering_iterations: int = 10, clearance_tries: int = 20,
                  passage_width: float = PASSAGE_WIDTH, disorder: float = 0.0,
                  library: ModelLibrary | None = None) -> FloorPlan:
    """Furnish a typed floor as ``add_furniture`` does in a grammar.

    Parameters
    ----------
    plan:
        A typed floor, e.g. from :func:`type_floor`.
    rules:
        The furniture table: a path, or the name of a shipped table such as
        ``"furniture_house.csv"``.
    seed:
        Seed of the random stream; the same seed gives the same furniture.
    units:
        Metres per unit of the table's distances.
    steering_iterations, clearance_tries:
        As the operation's ``steeringIterations`` and ``clearanceTries``.
    passage_width:
        As the operation's ``passage_width``, in metres (not scaled by ``units``).
    disorder:
        As the operation's ``disorder``: noise in [0, 1] on the movable items' poses.
    library:
        The models; default: the shipped ones.

    Returns
    -------
    FloorPlan
        A copy with ``furniture`` and the messages about left-out items appended to
        ``diagnostics``.

    Raises
    ------
    ResourceNotFoundError, RuleTableError
        The table or one of its models does not exist, or the table is malformed.
    UsageError
        ``passage_width`` is negative or ``disorder`` is outside [0, 1].
    """
    if passage_width < 0:
        raise UsageError(f"passage_width must not be negative, got {passage_width:g}")
    if not 0 <= disorder <= 1:
        raise UsageError(f"disorder must be in [0, 1], got {disorder:g}")
    table = load_furniture_rules(resolve_resource(rules, "rules"))
    return furnish(plan, table, library or default_library(), np.random.default_rng(seed),
                   units, steering_iterations, clearance_tries, passage_width, disorder)


def _rooms(plan: FloorPlan, ref: RoomRef) -> list[int]:
    if isinstance(ref, str):
        if ref.lower() == "outside":
            return [OUTSIDE]
        return [room.id for room in rooms_of_type(plan, ref)]
    if ref == OUTSIDE:
        return [OUTSIDE]
    plan.room(ref)  # KeyError for an unknown id
    return [ref]


def rooms_of_type(plan: FloorPlan, type_name: str) -> list[Room]:
    """The rooms of a type (exact spelling), in id order."""
    return [room for room in plan.rooms if room.type == type_name]


def are_adjacent(plan: FloorPlan, a: RoomRef, b: RoomRef) -> bool:
    """Whether a room ``a`` and a room ``b`` share a wall (of any length; doors aside).

    With types, whether any room of type ``a`` shares a wall with any room of type ``b``.
    ``"outside"`` is adjacent to every room with an outer wall.
    """
    first, second = set(_rooms(plan, a)), set(_rooms(plan, b))
    return any(wall.rooms[0] in first and wall.rooms[1] in second
               or wall.rooms[1] in first and wall.rooms[0] in second for wall in plan.walls)


def doors_between(plan: FloorPlan, a: RoomRef, b: RoomRef) -> list[Door]:
    """The doors joining a room ``a`` and a room ``b`` (by id, type or ``"outside"``)."""
    first, second = set(_rooms(plan, a)), set(_rooms(plan, b))
    return [door for door in plan.doors
            if door.rooms[0] in first and door.rooms[1] in second
            or door.rooms[1] in first and door.rooms[0] in second]
