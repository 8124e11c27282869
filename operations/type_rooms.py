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
stair. The entry room is ``FloorPlan.entry``; every room is reachable from it.

Stair core (DESIGN §12). A room ``make_floor`` typed already (the stair core, type
``Stair``) keeps its type and is not offered to the rules. Its doors may only open
beside its landing (:mod:`cga.operations.stairs.access`). On an upper floor the core is
the entry (the stair arrives there) and the ``isOutsideConnected`` type is placed next
to the landing, so the stair opens into it (the landing hall of the house rules); on the
ground floor that type is placed, when it can be, both on an outer wall (front door)
and next to the landing. The core gets one ``"stair"`` door into that room, else into a
circulation room, else the largest neighbour. A floor without a core (single storey)
that is not the ground floor is entered in its ``isOutsideConnected`` room, else the
largest.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from cga.errors import DerivationError, NoSolutionError, excerpt
from cga.model import OUTSIDE, Diagnostic, Door, FloorPlan, Room, Wall, Window
from cga.shape import Shape
from cga.table_units import describe_unit, unit_note

from cga.operation import CheckContext, Child, Operation, OperationContext, Param
from .roomtyping.door_states import DOOR_STATE_CHOICES, clear_leaves, with_door_states
from .roomtyping.rules import DEFAULT_TYPE, RuleTable, load_rule_table

if TYPE_CHECKING:
    from shapely.geometry import Polygon

    from .roomtyping.assign import Typing
    from .roomtyping.doors import Interval
    from .roomtyping.room_graph import DoorSites, Pair

# The typing, door and graph modules are imported where a floor is typed, not here:
# ``cga check`` loads this module for its parameters, value and table checks only.

__all__ = ["DOOR_POSITIONS", "DoorPosition", "MAX_REDRAWS", "CIRCULATION_TYPE", "TypeRooms", "type_plan"]

MAX_REDRAWS = 12
"""How many times a floor without a typing is re-drawn before the typing gives up."""

MAX_SIZE_RELAXED = (1.25, 1.5)
"""Factors the table's ``maxSize`` areas are raised by, in turn, when neither the floor
nor any re-draw has rooms small enough for them (:func:`_with_sizes_relaxed`)."""

DOOR_RETRIES = 4
"""How many typings of one layout are tried while their doors cannot reach every room
(before the layout is re-drawn, or the typing gives up)."""

CIRCULATION_TYPE = "Corridor"
"""The type of carved corridors when the table has no circulation rule."""

DoorPosition = Literal["center", "random"]

DOOR_POSITIONS: tuple[DoorPosition, ...] = ("center", "random")
"""Values of ``door_position``: doors centred in their free stretch of wall, or anywhere
in it (keeping the margins)."""

_STAGE = "type_rooms"

_SMALLEST_ROOM_M2 = 2.0
"""Sizes below this (a closet) do not look like m² to :func:`unit_mismatch`."""


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
        Metres per grammar unit; a table's ``Size`` is multiplied by ``units²`` unless
        the table is in metres (``# units: m``, :meth:`RuleTable.area_scale`).
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
    from .roomtyping.room_graph import NoDoorsError
    from .floorplan.treemap import most_rooms
    from .roomtyping.targets import redraw_count, target_areas

    if door_position not in DOOR_POSITIONS:
        raise ValueError(f"door_position must be one of {DOOR_POSITIONS}, got {door_position!r}")
    first_error: NoSolutionError | None = None
    door_error: NoSolutionError | None = None  # the last layout typed but left without doors
    last_resort: FloorPlan | None = None  # typed, a room no rule takes behind a private one
    fallback: FloorPlan | None = None  # typed, but with rooms no rule takes
    unlit: FloorPlan | None = None  # typed, but a room that needs a window has none
    drawn = [plan]  # the floor and its re-draws
    scale = table.area_scale(units)
    for attempt in range(MAX_REDRAWS + 1):
        try:
            typed = _typed_with_doors(plan, table, rng, units=units, strict=strict,
                                      door_position=door_position, door_state=door_state)
        except NoSolutionError as error:
            first_error = first_error or error
            if isinstance(error, NoDoorsError):
                door_error = error
                last_resort = last_resort or _typed_through_private(
                    plan, table, rng, units=units, strict=strict, door_position=door_position,
                    door_state=door_state, redrawn=(attempt, first_error))
        else:
            leftover = [r.id for r in typed.rooms if r.type == DEFAULT_TYPE]
            dark = _dark(typed)
            if not (leftover and table.has_access) and not dark:
                return _redrawn(typed, attempt, first_error, table, units)
            if not (leftover and table.has_access):  # typed, a room without its window
                unlit = unlit or _redrawn(typed, attempt, first_error, table, units)
                first_error = first_error or NoSolutionError(
                    f"room{'s' if len(dark) > 1 else ''} {', '.join(map(str, dark))} need "
                    "a window but have none")
            else:
                fallback = fallback or _redrawn(typed, attempt, first_error, table, units)
                first_error = first_error or NoSolutionError(
                    f"room{'s' if len(leftover) > 1 else ''} {', '.join(map(str, leftover))} "
                    "fit no rule of the table")
        recipe = plan.layout
        if recipe is None or attempt == MAX_REDRAWS:
            break
        free_area = _free_area(plan)
        rooms = min(redraw_count(table, recipe.free_rooms, free_area, scale,
                                 attempt=attempt + 1, attempts=MAX_REDRAWS),
                    most_rooms(free_area, recipe.min_width, recipe.min_area))
        areas = target_areas(table, rooms, free_area, scale) if rooms > 0 else []
        if not areas or min(areas) <= 0:
            break  # fixed rooms fill the floor: no room the partition could draw again
        plan = recipe.redraw(attempt + 1, areas).with_changes(diagnostics=plan.diagnostics)
        drawn.append(plan)
    if unlit is not None:
        return unlit
    if not strict:
        relaxed = _with_sizes_relaxed(drawn, table, rng, units=units,
                                      door_position=door_position, door_state=door_state)
        if relaxed is not None:
            return relaxed
    if fallback is not None:
        return fallback
    if last_resort is not None:
        return last_resort
    assert first_error is not None
    reasons = list(first_error.reasons)
    redraws = len(drawn) - 1
    if redraws:
        reasons.append(f"the floor was re-drawn {redraws} time{'s' if redraws > 1 else ''} "
                       "(cuts aimed at the table's areas) without a layout the rules can type")
        if door_error is not None and door_error is not first_error:
            reasons.append(f"a re-drawn layout was typed, but {str(door_error).splitlines()[0]}"
                           + "".join(f"; {r}" for r in door_error.reasons[:2]))
    reasons += unit_reasons(table, units, _free_area(plan))
    if redraws:
        reasons += _too_big_reasons(plan, table, units)
    if not strict and table.has_max_size:
        reasons.append(f"nor with every maxSize raised by {max(MAX_SIZE_RELAXED):g}x")
    if reasons == first_error.reasons:
        raise first_error
    raise NoSolutionError(str(first_error).splitlines()[0], reasons) from None


def _with_sizes_relaxed(drawn: Sequence[FloorPlan], table: RuleTable,
                        rng: np.random.Generator, *, units: float,
                        door_position: DoorPosition, door_state: str) -> FloorPlan | None:
    """The first of the layouts ``drawn`` (the floor, then its re-draws) that types
    every room under the table's ``maxSize`` areas raised by a factor of
    :data:`MAX_SIZE_RELAXED`, the least factor first (None: none does even under the
    last). Without it a build fails on one seed of a grammar that builds on the next (a
    12 × 9 m house whose straight stair takes most of the hall's side leaves a 48 m²
    room the partition cannot cut, and the smallest room left for its bathroom has
    10 m², not 9), or keeps a room no rule takes, or one entered only through a bedroom.

    The rooms keep the table's own area ranges, so the floor's quality report lists each
    room over its ``maxSize`` (``area_out_of_range``), and each gets a warning. Only
    reached where no layout types as the table is written, and never with ``strict``:
    what types under the table as written is unchanged."""
    if not table.has_max_size:
        return None
    scale = table.area_scale(units)
    for factor in MAX_SIZE_RELAXED:
        loose = replace(table, rules=tuple(
            rule if rule.max_size is None else replace(rule, max_size=rule.max_size * factor)
            for rule in table.rules))
        for plan in drawn:
            try:
                typed = _typed_with_doors(plan, loose, rng, units=units, strict=False,
                                          door_position=door_position, door_state=door_state)
            except NoSolutionError:
                continue
            if table.has_access and any(r.type == DEFAULT_TYPE for r in typed.rooms):
                continue
            rooms = tuple(room if room.type is None else _typed_room(room, room.type, table, scale)
                          for room in typed.rooms)
            notes = [Diagnostic("warning", _STAGE, (
                f"{_describe(room)} has {room.area:.1f} m², over its maxSize of {top:.1f} m²: "
                f"no layout drawn (this floor and {len(drawn) - 1} re-draws) could be typed "
                f"with the sizes as written, so they were raised by {factor:g}x; "
                f"{_SMALLER_ROOMS}"), floor=typed.index, room=room.id)
                for room in rooms if (top := _max_area(room)) is not None and room.area > top]
            typed = typed.with_changes(rooms=rooms,
                                       diagnostics=typed.diagnostics + tuple(notes))
            return _redrawn(typed, 0, None, table, units)
    return None


def _max_area(room: Room) -> float | None:
    """The most area (m²) its rule allows the room, a micrometre² over (None: no cap)."""
    top = room.area_range[1] if room.area_range is not None else None
    return None if top is None else top + 1e-6


_SMALLER_ROOMS = ("make_floor makes smaller rooms with a lower min_room_width, a "
                  "corridor_position that leaves one side shallow, or a higher split count")


def _too_big_reasons(plan: FloorPlan, table: RuleTable, units: float) -> list[str]:
    """When no free room of a drawn floor is as small as a mandatory rule's ``maxSize``
    (a bathroom of at most 9 m² beside a hall whose rooms are 4.75 m deep and at least
    2 m wide), what in the grammar makes rooms smaller: the re-draws cannot, their
    rooms are as deep as the corridor leaves them (docs/make_floor.md)."""
    scale = table.area_scale(units)
    smallest = min((r.area for r in plan.rooms if r.type is None and not r.circulation),
                   default=None)
    if smallest is None:
        return []
    capped = [(r.type, r.max_size * scale) for r in table.mandatory
              if r.max_size is not None and smallest > r.max_size * scale]
    if not capped:
        return []
    names = ", ".join(f"{kind} (at most {top:.1f} m²)" for kind, top in capped)
    return [f"every room the floor was cut into is bigger than {names} may be (the smallest "
            f"has {smallest:.1f} m²): {_SMALLER_ROOMS}"]


def unit_reasons(table: RuleTable, units: float, free_area: float) -> list[str]:
    """What a failed typing's areas were read in when that depends on the grammar
    (``units`` ≠ 1 and a table not in metres), and :func:`unit_mismatch`."""
    if units == 1 or table.unit == "m":
        return []
    mismatch = unit_mismatch(table, units, free_area)
    return [f"the sizes of {table.file} are read in "
            f"{describe_unit(table.unit, units, power=2)}"] + ([mismatch] if mismatch else [])


def unit_mismatch(table: RuleTable, units: float, free_area: float) -> str | None:
    """When a table's mandatory sizes fit a floor of ``free_area`` m² read as m² but not
    scaled by ``units²`` (the table is likely in metres under a grammar whose units are
    not), a sentence saying so and how to fix it (:mod:`cga.table_units`)."""
    if units <= 1 or table.unit == "m":
        return None
    scale = table.area_scale(units)
    sizes = [rule.size for rule in table.mandatory if rule.size > 0]
    total = sum(sizes)  # one room of each, at least
    # m² of real rooms are at least a closet's 2 m² (2 units² at units = 10 is 200 m²)
    if not sizes or min(sizes) < _SMALLEST_ROOM_M2 or not total * scale > free_area >= total:
        return None
    return (f"the sizes of {table.file} look like m²: its mandatory rooms need at least "
            f"{total:g} in the table, {total * scale:,.1f} m² at units = {units:g}, on a floor of "
            f"{free_area:,.1f} m²; if the table is in metres, put the line '# units: m' "
            f"above its header (or set the grammar's units = 1 if its lengths are metres)")


def _redrawn(typed: FloorPlan, attempt: int, first_error: NoSolutionError | None,
             table: RuleTable, units: float) -> FloorPlan:
    """``typed`` with a note on the re-draws it took and a warning when the table's
    sizes look read in the wrong unit (:func:`unit_mismatch`)."""
    notes = []
    if attempt and first_error is not None:
        why = str(first_error).splitlines()[0]
        notes.append(Diagnostic(
            "info", _STAGE, f"re-drew the floor {attempt} time{'s' if attempt > 1 else ''} "
            f"with cuts aimed at the table's areas; the first layout had no typing: {why}",
            floor=typed.index))
    mismatch = unit_mismatch(table, units, _free_area(typed))
    if mismatch is not None:
        notes.append(Diagnostic("warning", _STAGE, mismatch, floor=typed.index))
    return typed.with_changes(diagnostics=typed.diagnostics + tuple(notes)) if notes else typed


_NO_WINDOW = "needs a window (needsWindow)"
"""What the warning on a room typed to need a window without one says (:func:`_dark`)."""


def _dark(plan: FloorPlan) -> list[int]:
    """The rooms typed on this floor that need a window and have none (their warnings)."""
    return [d.room for d in plan.diagnostics
            if d.stage == _STAGE and d.room is not None and _NO_WINDOW in d.message]


def _free_area(plan: FloorPlan) -> float:
    return sum(r.area for r in plan.rooms if not r.circulation)


def _typed_with_doors(plan: FloorPlan, table: RuleTable, rng: np.random.Generator, *,
                      units: float, strict: bool, door_position: DoorPosition,
                      door_state: str) -> FloorPlan:
    """:func:`_type_layout`, typed afresh up to :data:`DOOR_RETRIES` times while its
    doors cannot reach every room the way the rules allow (a room no rule takes beside
    bedrooms only): the typing's draws put the rooms elsewhere, the layout stays."""
    from .roomtyping.room_graph import NoDoorsError

    for _ in range(DOOR_RETRIES - 1):
        try:
            return _type_layout(plan, table, rng, units=units, strict=strict,
                                door_position=door_position, door_state=door_state)
        except NoDoorsError:
            continue
    return _type_layout(plan, table, rng, units=units, strict=strict,
                        door_position=door_position, door_state=door_state)


def _typed_through_private(plan: FloorPlan, table: RuleTable, rng: np.random.Generator, *,
                           units: float, strict: bool, door_position: DoorPosition,
                           door_state: str, redrawn: tuple[int, NoSolutionError | None]
                           ) -> FloorPlan | None:
    """The typing's last resort for a layout whose doors cannot reach a room no rule
    takes except through a private room: typed again with such doors allowed
    (:func:`~.roomtyping.room_graph.access_pairs`), a warning for each (None: that does
    not type either). Kept only when no re-drawn layout does better."""
    from cga.quality import floor_quality

    try:
        typed = _type_layout(plan, table, rng, units=units, strict=strict,
                             door_position=door_position, door_state=door_state,
                             through_private=True)
    except NoSolutionError:
        return None
    # the floor's quality report says which rooms the doors reach only through private
    # ones, and behind which private room each lies when one alone cuts it off
    report = floor_quality(typed)
    gates = {room: entry["room"] for entry in report["pass_through_private"]
             for room in entry["behind"]}
    notes = [Diagnostic("warning", _STAGE, (
        f"{_describe(typed.room(room))} is reached only through "
        + (_describe(typed.room(gates[room])) if room in gates else "private rooms")
        + ": no layout or typing tried gives it a way in that avoids private rooms "
        "(make_floor's corridor= would)"), floor=typed.index, room=room)
        for room in report["reached_only_through_private"]
        # access tables reach other types that way only as their enteredFrom allows
        if typed.room(room).type == DEFAULT_TYPE or not table.has_access]
    typed = typed.with_changes(diagnostics=typed.diagnostics + tuple(notes))
    return _redrawn(typed, *redrawn, table, units)


def _type_layout(plan: FloorPlan, table: RuleTable, rng: np.random.Generator, *,
                 units: float, strict: bool, door_position: Literal["center", "random"],
                 door_state: str, through_private: bool = False) -> FloorPlan:
    """:func:`type_plan` on one layout, without re-draws; ``through_private``: see
    :func:`~.roomtyping.room_graph.access_pairs`."""
    from .roomtyping.assign import assign_types
    from .roomtyping.backtrack import RoomSet
    from .roomtyping.doors import door_centre, door_spans
    from .roomtyping.room_graph import (access_pairs, door_sites, reachability_pairs,
                                        room_graph, rule_pairs)
    from .stairs.access import core_door_spans

    width = plan.settings.door_width
    sites = door_sites(plan, core_door_spans(plan, door_spans(plan)), width)
    fixed = {room.id: room.type for room in plan.rooms if room.type is not None}
    free = [room for room in plan.rooms if room.id not in fixed]
    ids = tuple(room.id for room in free)
    wants_front_door = table.outside_rule is not None and plan.index == 0
    with_outer_wall = {w.rooms[0] for w in plan.walls if w.outer} | {w.rooms[1] for w in plan.walls if w.outer}
    windowed = {w.room for w in plan.windows}
    circulation = table.circulation_rule
    pinned = {i: circulation.type if circulation is not None else CIRCULATION_TYPE
              for i, room in enumerate(free) if room.circulation}
    # Access tables pin circulation and enter every room along it from the entry (the
    # stair core upstairs), so only thesis-style tables steer their entrance room to
    # the landing.
    landing = None if table.has_access else _landing_neighbours(plan, sites)
    choices = _entrance_choices(ids, sites, wants_front_door, landing)

    def typed_with(outer: frozenset[int]) -> Typing:
        """A typing where types that need a window take rooms of ``outer``, trying the
        entrance choices in order; the last one's failure is raised."""
        def typed(entrances: frozenset[int] | None) -> Typing:
            rooms = RoomSet(areas=tuple(room.area for room in free),
                            adjacency=sites.adjacency(ids), entrances=entrances, ids=ids,
                            outer=outer)
            return assign_types(rooms, table, rng, area_scale=table.area_scale(units),
                                pinned=pinned)

        for entrances in choices[:-1]:
            with contextlib.suppress(NoSolutionError):
                return typed(entrances)
        return typed(choices[-1])

    walled = frozenset(i for i, room in enumerate(ids) if room in with_outer_wall)
    lit = frozenset(i for i, room in enumerate(ids) if room in windowed)
    typing = _looking_out(typed_with, lit, walled, rng) if windowed else typed_with(walled)
    notes = [Diagnostic(n.level, _STAGE, n.message, floor=plan.index, room=n.room)
             for n in typing.notes]
    notes += [Diagnostic("warning", _STAGE, (
        f"room {room} ({kind}) {_NO_WINDOW}, but none fits its outer wall: "
        f"no layout drawn for this floor had a typing that gave every such room one"),
        floor=plan.index, room=room)
        for room, kind in zip(ids, typing.types) if windowed and room not in windowed
        and (rule := table.rule_for(kind)) is not None and rule.needs_window]
    types = {**dict(zip(ids, typing.types)), **fixed}
    typed = plan.with_changes(rooms=tuple(
        r if r.id in fixed else _typed_room(r, types[r.id], table, table.area_scale(units))
        for r in plan.rooms))

    front_room, entry, entry_notes = _entry(typed, table, typing, ids, sites, wants_front_door)
    notes += entry_notes
    privacy: list[Pair] = []  # doors that keep a bedroom or bathroom from being a passage
    if table.has_access:  # one door into every room, the stair core's included
        pairs, extra = access_pairs(typed.rooms, sites, table, entry=entry,
                                    through_private=through_private), []
        stair_pair = next((p for p in pairs if typed.core_room in p), None)
    else:
        pairs = rule_pairs(types, sites, table)
        stair_pair = _stair_pair(typed, table, typing, ids, sites)
        if stair_pair is not None:
            pairs.append(stair_pair)
        extra = reachability_pairs(typed.rooms, pairs, sites, entry=entry)
        if extra and strict:
            raise _unreachable_error(typed, pairs, sites, table, entry)
        if not through_private:
            privacy = _privacy_pairs(typed, pairs + extra, sites, entry, strict=strict)
            extra += privacy

    walls = {wall.id: wall for wall in typed.walls}
    windows: tuple[Window, ...] = typed.windows
    doors: list[Door] = []
    sweeps: list[Polygon] = []  # the quarter circles of the doors hung so far
    if front_room is not None:
        windows = _add_front_door(doors, sweeps, walls, windows, typed,
                                  sites.outer[front_room], front_room, rng, door_position,
                                  notes)
    batches: tuple[tuple[Literal["rule", "reachability"], list[Pair]], ...] = (
        ("rule", list(pairs)), ("reachability", list(extra)))
    for reason, chosen in batches:
        for pair in chosen:
            wall, interval = sites.inner[pair][0]
            centre = door_centre(interval, width, rng, door_position)
            kind: Literal["rule", "reachability", "stair"] = (
                "stair" if pair == stair_pair else reason)
            places = [(wall.id, centre)] + [
                (other.id, at) for other, (lo, hi) in sites.inner[pair]
                for at in ((lo + hi) / 2, lo + width / 2, hi - width / 2)]
            doors.append(_add_door(len(doors), walls, places, pair, typed, kind, sweeps))
            if pair in privacy:
                notes.append(_privacy_note(typed, pair))
            elif reason == "reachability":
                notes.append(_reachability_note(typed, pair, table))
    doors, turned_back = clear_leaves(typed, with_door_states(doors, door_state, rng))
    notes += [Diagnostic("info", _STAGE, text, floor=plan.index) for text in turned_back]
    result = typed.with_changes(walls=tuple(walls[w.id] for w in typed.walls),
                                windows=windows, doors=tuple(doors),
                                diagnostics=plan.diagnostics + tuple(notes))
    return result.with_changes(room_graph=room_graph(result, doors), entry=entry)


def _looking_out(typed_with: Callable[[frozenset[int]], Typing], lit: frozenset[int],
                 walled: frozenset[int], rng: np.random.Generator) -> Typing:
    """The typing that gives types needing a window rooms with a window (``lit``) where
    one exists that leaves no more rooms untyped than a typing that takes any room with
    an outer wall (``walled``: a window may not fit a short one); else that one, drawn
    from the stream as it was before the first try (the typing of a floor whose rooms
    all have windows, or that falls back, is the one it always was)."""
    if lit == walled:
        return typed_with(walled)
    before = rng.bit_generator.state
    try:
        typing: Typing | None = typed_with(lit)
    except NoSolutionError:
        typing = None
    if typing is not None and DEFAULT_TYPE not in typing.types:
        return typing
    after = rng.bit_generator.state
    rng.bit_generator.state = before
    try:
        fallback = typed_with(walled)
    except NoSolutionError:
        if typing is None:
            raise
        rng.bit_generator.state = after
        return typing
    if typing is None or fallback.types.count(DEFAULT_TYPE) < typing.types.count(DEFAULT_TYPE):
        return fallback
    rng.bit_generator.state = after
    return typing


def _add_front_door(doors: list[Door], sweeps: list[Polygon], walls: dict[int, Wall],
                    windows: tuple[Window, ...],
                    plan: FloorPlan, candidates: Sequence[tuple[Wall, Interval]], room: int,
                    rng: np.random.Generator, door_position: DoorPosition,
                    notes: list[Diagnostic]) -> tuple[Window, ...]:
    """Put the front door in ``room``'s outer wall; returns the windows left."""
    from .roomtyping.doors import clear_windows, front_door_site

    width = plan.settings.door_width
    wall, centre, replaces = front_door_site(candidates, width, rng, door_position)
    if replaces:
        walls[wall.id], windows, removed = clear_windows(
            walls[wall.id], windows, centre - width / 2, centre + width / 2)
        notes.append(Diagnostic("info", _STAGE, (
            f"the front door replaces {len(removed)} window{'s' if len(removed) != 1 else ''} "
            f"on wall {wall.id}: no stretch between windows of room {room} takes a "
            f"{width:.2f} m door"), floor=plan.index, room=room))
    doors.append(_add_door(len(doors), walls, [(wall.id, centre)], (room, OUTSIDE), plan,
                           "front", sweeps))
    return windows


def _add_door(door_id: int, walls: dict[int, Wall], places: Sequence[tuple[int, float]],
              rooms: tuple[int, int], plan: FloorPlan,
              reason: Literal["rule", "reachability", "front", "stair"],
              sweeps: list[Polygon]) -> Door:
    """The door at the first of ``places`` (wall id, centre), hung clear of ``sweeps``,
    those of the doors hung before it, where another place or way allows
    (:func:`~.roomtyping.doors.place_door`), cut into its wall in ``walls``; its own
    sweep is appended to ``sweeps``."""
    from .roomtyping.doors import door_opening, place_door

    door, sweep = place_door(door_id, [(walls[w], centre) for w, centre in places], rooms,
                             plan, reason=reason, avoid=sweeps)
    walls[door.wall] = walls[door.wall].with_opening(door_opening(door, plan))
    sweeps.append(sweep)
    return door


def _entry(plan: FloorPlan, table: RuleTable, typing: Typing, ids: Sequence[int],
           sites: DoorSites, wants_front_door: bool) -> tuple[int | None, int, list[Diagnostic]]:
    """(front-door room or None, entry room, notes): see the module notes."""
    outside = table.outside_rule
    placed = None
    if outside is not None and outside.type in typing.mandatory:
        placed = ids[typing.mandatory[outside.type]]
    by_size = sorted(plan.rooms, key=lambda r: (-r.area, r.id))
    notes: list[Diagnostic] = []
    if wants_front_door and outside is not None:
        if placed is not None:
            if placed not in sites.outer:
                raise NoSolutionError(
                    f"{outside.type} (room {placed}) has no outer wall long enough for a "
                    f"{plan.settings.door_width:.2f} m front door and its margins")
            return placed, placed, notes
        candidates = [r for r in by_size if r.id in sites.outer and r.id != plan.core_room]
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
    if plan.core_room is not None and plan.index > 0:
        notes.append(Diagnostic("info", _STAGE, (
            f"upper floor: no front door; the stair arrives in its core, room "
            f"{plan.core_room}"), floor=plan.index, room=plan.core_room))
        return None, plan.core_room, notes
    by_size = [r for r in by_size if r.id != plan.core_room]
    entry = placed if placed is not None else by_size[0].id
    if outside is None and plan.index == 0:
        notes.append(Diagnostic("warning", _STAGE, (
            f"no rule of {table.file} sets isOutsideConnected, so the ground floor gets no "
            f"front door; room {entry} is its entry"), floor=plan.index, room=entry))
    else:
        notes.append(Diagnostic("info", _STAGE, (
            f"upper floor without a stair core: no front door; room {entry} "
            f"({plan.room(entry).type}) is its entry"), floor=plan.index, room=entry))
    return None, entry, notes


def _landing_neighbours(plan: FloorPlan, sites: DoorSites) -> frozenset[int] | None:
    """Rooms that can take a door from the stair landing (None: the floor has no core)."""
    if plan.core_room is None:
        return None
    return frozenset(sum(pair) - plan.core_room for pair in sites.inner if plan.core_room in pair)


def _entrance_choices(ids: Sequence[int], sites: DoorSites, front_door: bool,
                      landing: frozenset[int] | None) -> list[frozenset[int] | None]:
    """Rooms the ``isOutsideConnected`` rule may take, most wanted first (as indices
    into ``ids``): by the front door and the stair landing, then by either alone."""
    outer = frozenset(i for i, room in enumerate(ids) if room in sites.outer)
    near = (frozenset(i for i, room in enumerate(ids) if room in landing)
            if landing is not None else None)
    if front_door:
        return [outer & near, outer] if near else [outer]
    return [near, None] if near else [None]


def _stair_pair(plan: FloorPlan, table: RuleTable, typing: Typing, ids: Sequence[int],
                sites: DoorSites) -> tuple[int, int] | None:
    """The room pair of the core's door: into the ``isOutsideConnected`` room, else a
    circulation room, else the largest neighbour of the landing.

    Raises
    ------
    NoSolutionError
        The landing has no wall that takes a door (make_floor redraws such partitions,
        so only hand-made plans get here).
    """
    core = plan.core_room
    if core is None:
        return None
    outside = table.outside_rule
    placed = typing.mandatory.get(outside.type) if outside is not None else None
    placed_id = ids[placed] if placed is not None else None
    neighbours = sorted(_landing_neighbours(plan, sites) or ())
    if not neighbours:
        raise NoSolutionError(f"the stair core (room {core}) of floor {plan.index} has no wall "
                              "at its landing long enough for a door")
    best = min(neighbours, key=lambda r: (r != placed_id, not plan.room(r).circulation,
                                          -plan.room(r).area, r))
    return (min(core, best), max(core, best))


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


def _privacy_note(plan: FloorPlan, pair: tuple[int, int]) -> Diagnostic:
    a, b = (plan.room(r) for r in pair)
    return Diagnostic("info", _STAGE, (
        f"added a door between {_describe(a)} and {_describe(b)}: the rules' doors reached "
        "one of them only through a bedroom or bathroom"), floor=plan.index, room=a.id)


def _privacy_pairs(plan: FloorPlan, pairs: list[tuple[int, int]], sites: DoorSites,
                   entry: int, *, strict: bool) -> list[tuple[int, int]]:
    """:func:`~.roomtyping.room_graph.privacy_pairs` for a floor whose doors follow the
    thesis' rules; with ``strict``, a floor that needs one fails (and is re-drawn)."""
    from .roomtyping.room_graph import NoDoorsError, privacy_pairs

    added = privacy_pairs(plan.rooms, pairs, sites, entry=entry)
    if added and strict:
        raise NoDoorsError(
            f"strict: the doors the rules allow reach some room of floor {plan.index} only "
            "through a bedroom or bathroom",
            [f"{_describe(plan.room(a))} and {_describe(plan.room(b))} would need a door no "
             "rule asks for" for a, b in added])
    return added


def _unreachable_error(plan: FloorPlan, pairs: list[tuple[int, int]], sites: DoorSites,
                       table: RuleTable, entry: int) -> NoSolutionError:
    import networkx as nx  # imported here: `cga check` needs no networkx

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
        table = _cached_table(ctx.resolve(args["rules"], "rules"), ctx.cache, ctx)
        plan = type_plan(shape.plan, table, ctx.rng, units=ctx.units,
                         strict=bool(args["strict"]) or ctx.strict, door_position=position,
                         door_state=state)
        return [Child(successor=0, geometry=shape.geometry, scope=shape.scope, plan=plan)]


def _cached_table(path: Any, cache: dict[str, Any],
                  ctx: OperationContext | None = None) -> RuleTable:
    """Parse each table once per build (every floor of a building usually shares one);
    the first time, say in ``ctx``'s diagnostics how its sizes are read when that
    depends on the grammar's units."""
    key = f"type_rooms:{path}"
    if key not in cache:
        table = cache[key] = load_rule_table(path)
        note = None if ctx is None else unit_note(table.file, table.unit, ctx.units,
                                                  "room sizes")
        if ctx is not None and note is not None:
            ctx.report(Diagnostic("info", _STAGE, note))
    return cache[key]
