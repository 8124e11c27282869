"""``type_rooms(rules.csv)``: type the rooms of a floor, build its room graph, cut its doors.

docs/room_typing.md and thesis §3.3/§5.2. The work is split by concern under
:mod:`cga.operations.roomtyping`; :func:`type_plan` wires the steps together on a
:class:`~cga.model.FloorPlan` and :class:`TypeRooms` is the grammar operation around it:

1. find the walls that can take a door (:mod:`~.roomtyping.doors`,
   :mod:`~.roomtyping.room_graph`): they define which rooms are neighbours;
2. type the rooms (:mod:`~.roomtyping.assign`, :mod:`~.roomtyping.backtrack`);
3. join rooms whose rules list each other's type, add the fewest extra doors that make
   every room reachable from the entry, and place the doors.

Entry and front door. The floor whose rule table has an ``isOutsideConnected`` rule gets
the front door in that room's outer wall, if it is the ground floor (``index`` 0).
Upper floors get no front door (it would open into the air); they are entered by the
stair, which arrives in the room of the ``isOutsideConnected`` type when the floor has
one, else in the largest room. The entry room is ``FloorPlan.entry``; every room is
reachable from it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any, Literal

import networkx as nx
import numpy as np

from cga.errors import DerivationError, NoSolutionError, excerpt
from cga.model import OUTSIDE, Diagnostic, Door, FloorPlan, Room, Wall, Window
from cga.shape import Shape

from cga.operation import CheckContext, Child, Operation, OperationContext, Param
from .roomtyping.assign import Typing, assign_types
from .roomtyping.backtrack import RoomSet
from .roomtyping.door_states import DOOR_STATE_CHOICES, with_door_states
from .roomtyping.doors import (Interval, clear_windows, door_centre, door_opening,
                               door_spans, front_door_site, make_door)
from .roomtyping.room_graph import (DoorSites, Pair, access_pairs, door_sites, reachability_pairs,
                                    room_graph, rule_pairs)
from .roomtyping.rules import DEFAULT_TYPE, RuleTable, load_rule_table
from .roomtyping.targets import target_areas

__all__ = ["DOOR_POSITIONS", "DoorPosition", "MAX_REDRAWS", "CIRCULATION_TYPE", "TypeRooms", "type_plan"]

MAX_REDRAWS = 12
"""How many times a floor without a typing is re-drawn before the typing gives up."""

CIRCULATION_TYPE = "Corridor"
"""The type of carved corridors when the table has no circulation rule."""

DoorPosition = Literal["center", "random"]

DOOR_POSITIONS: tuple[DoorPosition, ...] = ("center", "random")
"""Values of ``door_position``: doors centred in their free stretch of wall, or anywhere
in it (keeping the margins)."""

_STAGE = "type_rooms"


def type_plan(plan: FloorPlan, table: RuleTable, rng: np.random.Generator, *,
              units: float = 1.0, strict: bool = False,
              door_position: DoorPosition = "random",
              door_state: str = "closed") -> FloorPlan:
    """Type the rooms of ``plan`` and give it a room graph and doors.

    Parameters
    ----------
    plan:
        An untyped floor (from ``make_floor`` or ``plan_from_rectangles``).
    table:
        The typing rules.
    rng:
        The only source of randomness (first rule, rooms, door positions).
    units:
        Metres per grammar unit; the table's ``Size`` is in grammar units², so it is
        multiplied by ``units²``.
    strict:
        Fail instead of adding doors the rules do not ask for.
    door_position:
        ``"center"`` or ``"random"`` (see :data:`DOOR_POSITIONS`).
    door_state:
        How the doors are left: ``"closed"``, ``"open"``, ``"ajar"`` or ``"random"``
        (one state per door from ``rng``, drawn after every other choice of the floor;
        :mod:`~.roomtyping.door_states`).

    Returns
    -------
    FloorPlan
        A copy with typed rooms, door openings in the walls, ``doors``, ``room_graph``
        (:func:`~.roomtyping.room_graph.room_graph`), fewer ``windows`` if the front door
        took a window's place, and the typing's messages appended to ``diagnostics``.

    Raises
    ------
    NoSolutionError
        The mandatory rules cannot all be satisfied; a room cannot be reached through
        any wall; the ground floor has no outer wall that takes a front door; or, with
        ``strict``, the rules leave a room unreachable.
    """
    if door_position not in DOOR_POSITIONS:
        raise ValueError(f"door_position must be one of {DOOR_POSITIONS}, got {door_position!r}")
    first_error: NoSolutionError | None = None
    fallback: FloorPlan | None = None  # typed, but with rooms no rule takes
    for attempt in range(MAX_REDRAWS + 1):
        try:
            typed = _type_layout(plan, table, rng, units=units, strict=strict,
                                 door_position=door_position, door_state=door_state)
            leftover = [r.id for r in typed.rooms if r.type == DEFAULT_TYPE]
            if not (leftover and table.has_access):
                return _redrawn(typed, attempt, first_error)
            fallback = fallback or _redrawn(typed, attempt, first_error)
            first_error = first_error or NoSolutionError(
                f"room{'s' if len(leftover) > 1 else ''} {', '.join(map(str, leftover))} fit no "
                "rule of the table")
        except NoSolutionError as error:
            first_error = first_error or error
        recipe = plan.layout
        if recipe is None or attempt == MAX_REDRAWS:
            break
        areas = target_areas(table, recipe.free_rooms, _free_area(plan), units ** 2)
        plan = recipe.redraw(attempt + 1, areas).with_changes(diagnostics=plan.diagnostics)
    if fallback is not None:
        return fallback
    assert first_error is not None
    if plan.layout is None:
        raise first_error
    raise NoSolutionError(str(first_error).splitlines()[0], first_error.reasons + [
        f"the floor was re-drawn {MAX_REDRAWS} times (cuts aimed at the table's areas) "
        "without a layout the rules can type"]) from None


def _redrawn(typed: FloorPlan, attempt: int, first_error: NoSolutionError | None) -> FloorPlan:
    """``typed`` with a note on the re-draws it took (none: unchanged)."""
    if not attempt or first_error is None:
        return typed
    why = str(first_error).splitlines()[0]
    return typed.with_changes(diagnostics=typed.diagnostics + (Diagnostic(
        "info", _STAGE, f"re-drew the floor {attempt} time{'s' if attempt > 1 else ''} with "
        f"cuts aimed at the table's areas; the first layout had no typing: {why}",
        floor=typed.index),))


def _free_area(plan: FloorPlan) -> float:
    return sum(r.area for r in plan.rooms if not r.circulation)


def _type_layout(plan: FloorPlan, table: RuleTable, rng: np.random.Generator, *,
                 units: float, strict: bool, door_position: Literal["center", "random"],
                 door_state: str) -> FloorPlan:
    """:func:`type_plan` on one layout, without re-draws."""
    width = plan.settings.door_width
    sites = door_sites(plan, door_spans(plan), width)
    ids = tuple(room.id for room in plan.rooms)
    wants_front_door = table.outside_rule is not None and plan.index == 0
    with_outer_wall = {w.rooms[0] for w in plan.walls if w.outer} | {w.rooms[1] for w in plan.walls if w.outer}
    rooms = RoomSet(areas=tuple(room.area for room in plan.rooms),
                    adjacency=sites.adjacency(ids),
                    entrances=(frozenset(i for i, room in enumerate(ids) if room in sites.outer)
                               if wants_front_door else None),
                    ids=ids,
                    outer=frozenset(i for i, room in enumerate(ids) if room in with_outer_wall))
    circulation = table.circulation_rule
    pinned = {i: circulation.type if circulation is not None else CIRCULATION_TYPE
              for i, room in enumerate(plan.rooms) if room.circulation}
    typing = assign_types(rooms, table, rng, area_scale=units ** 2, pinned=pinned)
    notes = [Diagnostic(n.level, _STAGE, n.message, floor=plan.index, room=n.room)
             for n in typing.notes]
    types = dict(zip(ids, typing.types))
    typed = plan.with_changes(rooms=tuple(_typed_room(r, types[r.id], table, units ** 2)
                                          for r in plan.rooms))

    front_room, entry, entry_notes = _entry(typed, table, typing, sites, wants_front_door)
    notes += entry_notes
    if table.has_access:
        pairs, extra = access_pairs(typed.rooms, sites, table, entry=entry), []
    else:
        pairs = rule_pairs(types, sites, table)
        extra = reachability_pairs(typed.rooms, pairs, sites, entry=entry)
    if extra and strict:
        raise _unreachable_error(typed, pairs, sites, table, entry)

    walls = {wall.id: wall for wall in typed.walls}
    windows: tuple[Window, ...] = typed.windows
    doors: list[Door] = []
    if front_room is not None:
        windows = _add_front_door(doors, walls, windows, typed, sites.outer[front_room],
                                  front_room, rng, door_position, notes)
    batches: tuple[tuple[Literal["rule", "reachability"], list[Pair]], ...] = (
        ("rule", list(pairs)), ("reachability", list(extra)))
    for reason, chosen in batches:
        for pair in chosen:
            wall, interval = sites.inner[pair][0]
            centre = door_centre(interval, width, rng, door_position)
            doors.append(_add_door(len(doors), walls, wall.id, centre, pair, typed, reason))
            if reason == "reachability":
                notes.append(_reachability_note(typed, pair, table))
    doors = with_door_states(doors, door_state, rng)
    result = typed.with_changes(walls=tuple(walls[w.id] for w in typed.walls),
                                windows=windows, doors=tuple(doors),
                                diagnostics=plan.diagnostics + tuple(notes))
    return result.with_changes(room_graph=room_graph(result, doors), entry=entry)


def _add_front_door(doors: list[Door], walls: dict[int, Wall], windows: tuple[Window, ...],
                    plan: FloorPlan, candidates: Sequence[tuple[Wall, Interval]], room: int,
                    rng: np.random.Generator, door_position: DoorPosition,
                    notes: list[Diagnostic]) -> tuple[Window, ...]:
    """Put the front door in ``room``'s outer wall; returns the windows left."""
    width = plan.settings.door_width
    wall, centre, replaces = front_door_site(candidates, width, rng, door_position)
    if replaces:
        walls[wall.id], windows, removed = clear_windows(
            walls[wall.id], windows, centre - width / 2, centre + width / 2)
        notes.append(Diagnostic("info", _STAGE, (
            f"the front door replaces {len(removed)} window{'s' if len(removed) != 1 else ''} "
            f"on wall {wall.id}: no stretch between windows of room {room} takes a "
            f"{width:.2f} m door"), floor=plan.index, room=room))
    doors.append(_add_door(len(doors), walls, wall.id, centre, (room, OUTSIDE), plan, "front"))
    return windows


def _add_door(door_id: int, walls: dict[int, Wall], wall_id: int, centre: float,
              rooms: tuple[int, int], plan: FloorPlan,
              reason: Literal["rule", "reachability", "front"]) -> Door:
    door = make_door(door_id, walls[wall_id], centre, rooms, plan, reason=reason)
    walls[wall_id] = walls[wall_id].with_opening(door_opening(door, plan))
    return door


def _entry(plan: FloorPlan, table: RuleTable, typing: Typing, sites: DoorSites,
           wants_front_door: bool) -> tuple[int | None, int, list[Diagnostic]]:
    """(front-door room or None, entry room, notes): see the module notes."""
    outside = table.outside_rule
    placed = None
    if outside is not None and outside.type in typing.mandatory:
        placed = plan.rooms[typing.mandatory[outside.type]].id
    by_size = sorted(plan.rooms, key=lambda r: (-r.area, r.id))
    notes: list[Diagnostic] = []
    if wants_front_door and outside is not None:
        if placed is not None:
            if placed not in sites.outer:
                raise NoSolutionError(
                    f"{outside.type} (room {placed}) has no outer wall long enough for a "
                    f"{plan.settings.door_width:.2f} m front door and its margins")
            return placed, placed, notes
        candidates = [r for r in by_size if r.id in sites.outer]
        if not candidates:
            raise NoSolutionError(
                f"floor {plan.index} has no outer wall long enough for a "
                f"{plan.settings.door_width:.2f} m front door and its margins")
        room = candidates[0]
        notes.append(Diagnostic("warning", _STAGE, (
            f"no {outside.type} on this floor, so the front door goes into the largest room "
            f"with an outer wall for it: room {room.id} ({room.type})"),
            floor=plan.index, room=room.id))
        return room.id, room.id, notes
    entry = placed if placed is not None else by_size[0].id
    if outside is None and plan.index == 0:
        notes.append(Diagnostic("warning", _STAGE, (
            f"no rule of {table.file} sets isOutsideConnected, so the ground floor gets no "
            f"front door; room {entry} is its entry"), floor=plan.index, room=entry))
    else:
        notes.append(Diagnostic("info", _STAGE, (
            f"upper floor: no front door; the stair arrives in room {entry} "
            f"({plan.room(entry).type})"), floor=plan.index, room=entry))
    return None, entry, notes


def _typed_room(room: Room, type_name: str, table: RuleTable, area_scale: float) -> Room:
    """The room with its type and what its rule says about it (circulation, private,
    area range in m²)."""
    rule = table.rule_for(type_name)
    if rule is None:
        return replace(room, type=type_name)
    top = None if rule.max_size is None else rule.max_size * area_scale
    return replace(room, type=type_name, circulation=room.circulation or rule.circulation,
                   private=not rule.pass_through, area_range=(rule.size * area_scale, top))


def _describe(room: Room) -> str:
    return f"room {room.id} ({room.type})"


def _lists(table: RuleTable, type_name: str | None) -> str:
    rule = table.rule_for(type_name) if type_name else None
    return ", ".join(rule.neighbours) if rule is not None else "nothing (no rule)"


def _reachability_note(plan: FloorPlan, pair: tuple[int, int], table: RuleTable) -> Diagnostic:
    a, b = (plan.room(r) for r in pair)
    return Diagnostic("warning", _STAGE, (
        f"added a door between {_describe(a)} and {_describe(b)} so every room can be "
        f"reached: no rule joins them ({a.type} lists {_lists(table, a.type)}; {b.type} "
        f"lists {_lists(table, b.type)})"), floor=plan.index, room=a.id)


def _unreachable_error(plan: FloorPlan, pairs: list[tuple[int, int]], sites: DoorSites,
                       table: RuleTable, entry: int) -> NoSolutionError:
    graph = nx.Graph(pairs)
    graph.add_nodes_from(r.id for r in plan.rooms)
    reached = nx.node_connected_component(graph, entry)
    reasons = []
    for room in plan.rooms:
        if room.id in reached:
            continue
        beside = [plan.room(sum(p) - room.id) for p in sites.inner if room.id in p]
        reasons.append(f"{_describe(room)} adjoins {', '.join(map(_describe, beside))}; "
                       f"{room.type} lists {_lists(table, room.type)} and none of them lists "
                       f"{room.type}")
    return NoSolutionError(
        f"strict: the doors the rules of {table.file} allow do not reach every room of floor "
        f"{plan.index} from {_describe(plan.room(entry))}", reasons)


class TypeRooms(Operation):
    """Type the rooms of a floor, build the room graph and cut the doors (docs/room_typing.md)."""

    name = "type_rooms"
    params = (
        Param("rules", "path", doc="typing rule table (CSV, thesis format)"),
        Param("strict", "bool", default=False, keyword_only=True,
              doc="fail instead of adding doors the rules do not ask for"),
        Param("door_position", "string", default="random", keyword_only=True,
              doc="'center' or 'random': where a door sits in its free stretch of wall"),
        Param("door_state", "string", default="closed", keyword_only=True,
              doc="'closed', 'open', 'ajar' or 'random' (one per door, from the seed): "
                  "how the door leaves are left"),
    )
    doc = ('type_rooms("rules.csv", strict=false, door_position="random", '
           'door_state="closed"): type the rooms, build the room graph, cut the doors')

    def check_values(self, args: dict[str, Any], units: float) -> None:
        position = args["door_position"]
        if isinstance(position, str) and position.lower() not in DOOR_POSITIONS:
            raise DerivationError(f"door_position must be one of "
                                  f"{', '.join(repr(p) for p in DOOR_POSITIONS)}, got "
                                  f"{excerpt(position)}")
        state = args["door_state"]
        if isinstance(state, str) and state.lower() not in DOOR_STATE_CHOICES:
            raise DerivationError(f"door_state must be one of "
                                  f"{', '.join(repr(s) for s in DOOR_STATE_CHOICES)}, got "
                                  f"{excerpt(state)}")

    def check_files(self, args: dict[str, Any], ctx: CheckContext) -> None:
        if isinstance(args["rules"], str):
            _cached_table(ctx.resolve(args["rules"], "rules"), ctx.cache)

    def apply(self, shape: Shape, args: dict[str, Any], ctx: OperationContext) -> list[Child]:
        if shape.plan is None:
            raise DerivationError("type_rooms needs a floor made by make_floor",
                                  hint="apply make_floor(...) to this shape first")
        self.check_values(args, ctx.units)
        written = str(args["door_position"]).lower()
        position = next(p for p in DOOR_POSITIONS if p == written)  # check_values refused others
        state = str(args["door_state"]).lower()
        table = _cached_table(ctx.resolve(args["rules"], "rules"), ctx.cache)
        plan = type_plan(shape.plan, table, ctx.rng, units=ctx.units,
                         strict=bool(args["strict"]) or ctx.strict, door_position=position,
                         door_state=state)
        return [Child(successor=0, geometry=shape.geometry, scope=shape.scope, plan=plan)]


def _cached_table(path: Any, cache: dict[str, Any]) -> RuleTable:
    """Parse each table once per build (every floor of a building usually shares one)."""
    key = f"type_rooms:{path}"
    if key not in cache:
        cache[key] = load_rule_table(path)
    return cache[key]
