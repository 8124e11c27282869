"""One storey from several ``make_floor`` pieces: wings.

A grammar may cut a storey into wings (``split("x"){ ~1 : Wing | ~1 : Wing }``) and run
``make_floor`` on each. Each wing is then partitioned, typed and furnished on its own,
and they meet along a *party wall*: the outer wall of one wing back to back with the
outer wall of the other. Every consumer of a build (meshing, checks, exports) expects one
plan per storey, so after the derivation the wings of a storey are joined into one
:class:`~cga.model.FloorPlan` (:func:`join_wings`):

* rooms, walls, doors, windows and furniture keep their order, wing after wing (wings
  ordered by position: x, then z), with ids shifted so they stay unique; the room graphs
  are joined at the outside;
* the footprint is the union of the wings' footprints (the wings must touch along a
  wall: a storey is one building);
* a window in a party wall would look into the neighbouring wing's wall: it is left
  out, with an info;
* the wings are joined by a doorway through the party wall between two circulation
  rooms (halls, corridors) that face each other across it, the widest stretch they
  share, so a robot entering by one front door, or coming up the stair, reaches every
  wing; wings without such a pair are joined through other rooms, a private one last
  (:func:`_join_circulation`), and only wings that share no wall long enough for a
  doorway stay apart, which the plan's diagnostics say;
* last, each stretch where two party walls stand back to back becomes one inner wall
  between the rooms on either side, as thick as both: every door, the doorways between
  wings too, then lies in the wall between the rooms it joins.

A wing's front door may lie in a party wall only if the rules put it there; it then
opens into the neighbour's wall, and the navigability report names that door.
"""

from __future__ import annotations

import itertools
from collections.abc import Collection, Iterator, Sequence
from dataclasses import replace

import networkx as nx
from networkx.utils import UnionFind
import shapely
from shapely.geometry import LineString, Point, Polygon

from .errors import DerivationError
from .model import (DOOR_OPEN_ANGLE, OUTSIDE, Diagnostic, Door, FloorPlan, FurnitureItem, Opening,
                    Room, Wall)

__all__ = ["join_wings"]

_TOUCH = 1e-6
"""Distance (m) within which two wings' walls count as back to back."""


def join_wings(plans: Sequence[FloorPlan]) -> list[FloorPlan]:
    """The plans with every storey's wings joined into one plan (see the module notes);
    storeys of one piece are returned unchanged, in the order given.

    Raises
    ------
    DerivationError
        Wings of one storey stand at different heights or do not touch.
    """
    groups: dict[int, list[FloorPlan]] = {}
    for plan in plans:
        groups.setdefault(plan.index, []).append(plan)
    out = []
    for plan in plans:
        group = groups[plan.index]
        if len(group) == 1:
            out.append(plan)
        elif plan is group[0]:
            out.append(_join(group))
    return out


def _join(wings: list[FloorPlan]) -> FloorPlan:
    index = wings[0].index
    stacked = [(a, b) for a, b in itertools.combinations(wings, 2)
               if a.elevation != b.elevation and a.footprint.intersection(b.footprint).area > _TOUCH]
    if stacked:
        low, high = stacked[0]
        raise DerivationError(
            f"two storeys, one above the other, are both floor {index} "
            f"({low.elevation:g}–{low.elevation + low.height:g} m and "
            f"{high.elevation:g}–{high.elevation + high.height:g} m): a storey's number comes "
            f"from repeated_split(\"y\", ...), and a piece of split(\"y\") keeps its "
            f"parent's (0 outside any repeated_split)",
            hint='cut every storey of the building with one repeated_split("y", height)')
    if len({(w.elevation, w.height) for w in wings}) > 1:
        raise DerivationError(
            f"the {len(wings)} make_floor pieces of floor {index} stand at different heights "
            f"({', '.join(f'{w.elevation:g}–{w.elevation + w.height:g} m' for w in wings)})",
            hint="split the storey into wings after repeated_split, so they share its height")
    wings = sorted(wings, key=lambda w: (w.footprint.bounds[0], w.footprint.bounds[1]))
    footprint = shapely.union_all([w.footprint for w in wings])
    if not isinstance(footprint, Polygon):
        raise DerivationError(
            f"the {len(wings)} make_floor pieces of floor {index} do not touch: a storey is "
            f"one building, its wings meet along a wall",
            hint="split the storey into wings that share a side, or build separate lots")
    footprint = shapely.simplify(footprint, 0.0)
    shifted = []
    room_base = wall_base = door_base = window_base = 0
    for wing in wings:
        shifted.append(_shift(wing, room_base, wall_base, door_base, window_base))
        room_base += max((r.id for r in wing.rooms), default=-1) + 1
        wall_base += max((w.id for w in wing.walls), default=-1) + 1
        door_base += max((d.id for d in wing.doors), default=-1) + 1
        window_base += max((w.id for w in wing.windows), default=-1) + 1
    first = shifted[0]
    plan = first.with_changes(
        footprint=footprint,
        rooms=tuple(r for w in shifted for r in w.rooms),
        walls=tuple(x for w in shifted for x in w.walls),
        doors=tuple(d for w in shifted for d in w.doors),
        windows=tuple(x for w in shifted for x in w.windows),
        furniture=tuple(f for w in shifted for f in w.furniture),
        room_graph=_joined_graph([w.room_graph for w in shifted]),
        diagnostics=tuple(d for w in shifted for d in w.diagnostics),
        entry=next((w.entry for w in shifted if w.front_door() is not None), first.entry),
        core=next((w.core for w in shifted if w.core is not None), None),
        core_room=next((w.core_room for w in shifted if w.core is not None), None),
        dcel=None, layout=None)
    cores = [w for w in shifted if w.core is not None]
    if len(cores) > 1:
        plan = plan.with_changes(diagnostics=plan.diagnostics + (Diagnostic(
            "info", "make_floor",
            f"{len(cores)} wings of floor {index} reserved a stair core; the building's stair "
            f"stands in the first wing's core (room {cores[0].core_room}), the other cores "
            f"are empty rooms typed Stair: give the other wings' make_floor stair = \"none\"",
            floor=index),))
    owner = {r.id: k for k, w in enumerate(shifted) for r in w.rooms}
    party = _party_walls(plan, owner, shifted)
    plan = _without_party_windows(plan, party)
    had_front = plan.front_door() is not None
    plan, joined, dropped = _party_front_doors(plan, party, owner)
    for lost in sorted(dropped):
        plan = _new_front_door(plan, party, {room for room, k in owner.items() if k == lost})
    front = plan.front_door()
    if front is not None and plan.entry not in front.rooms:  # the first wing's door was left out
        plan = plan.with_changes(entry=next(r for r in front.rooms if r != OUTSIDE))
    plan = _join_circulation(plan, party, owner, len(shifted), joined)
    if had_front and plan.front_door() is None:
        plan = _new_front_door(plan, party)
    return _merged_party_walls(plan, party, owner)


def _shift(plan: FloorPlan, rooms: int, walls: int, doors: int, windows: int) -> FloorPlan:
    def room(r: int) -> int:
        return r if r == OUTSIDE else r + rooms

    def item(i: FurnitureItem) -> FurnitureItem:
        name = i.name
        if i.is_detail and i.door is not None:
            name = f"door{i.door + doors}" if name == f"door{i.door}" else name
        elif i.is_detail and name.startswith("window") and name[6:].isdigit():
            name = f"window{int(name[6:]) + windows}"
        return replace(i, room=room(i.room), name=name,
                       door=i.door + doors if i.door is not None else None)

    return plan.with_changes(
        rooms=tuple(replace(r, id=r.id + rooms) for r in plan.rooms),
        walls=tuple(replace(w, id=w.id + walls, rooms=(room(w.rooms[0]), room(w.rooms[1])))
                    for w in plan.walls),
        doors=tuple(replace(d, id=d.id + doors, wall=d.wall + walls,
                            rooms=(room(d.rooms[0]), room(d.rooms[1])),
                            swing_room=room(d.swing_room)) for d in plan.doors),
        windows=tuple(replace(w, id=w.id + windows, wall=w.wall + walls, room=room(w.room))
                      for w in plan.windows),
        furniture=tuple(item(i) for i in plan.furniture),
        room_graph=_shifted_graph(plan.room_graph, rooms, walls, doors),
        entry=room(plan.entry) if plan.entry is not None else None,
        core_room=room(plan.core_room) if plan.core_room is not None else None,
        diagnostics=tuple(replace(d, room=room(d.room)) if d.room is not None else d
                          for d in plan.diagnostics))


def _shifted_graph(graph: "nx.Graph | None", rooms: int, walls: int, doors: int) -> "nx.Graph | None":
    if graph is None:
        return None
    out = nx.relabel_nodes(graph, {n: n if n == OUTSIDE else n + rooms for n in graph.nodes})
    for _, _, data in out.edges(data=True):
        if data.get("door") is not None:
            data["door"] += doors
        if data.get("wall") is not None:
            data["wall"] += walls
    return out


def _joined_graph(graphs: list["nx.Graph | None"]) -> "nx.Graph | None":
    present = [g for g in graphs if g is not None]
    return nx.compose_all(present) if present else None


def _party_walls(plan: FloorPlan, owner: dict[int, int],
                 wings: list[FloorPlan]) -> dict[int, LineString]:
    """Outer walls lying on another wing's outline: wall id → the stretch they share."""
    out = {}
    for wall in plan.walls:
        if not wall.outer:
            continue
        mine = owner[wall.rooms[0]]
        line = wall.segment()
        for k, wing in enumerate(wings):
            if k == mine:
                continue
            shared = line.intersection(wing.footprint.exterior.buffer(_TOUCH))
            if shared.length > _TOUCH:
                out[wall.id] = shared
    return out


def _without_party_windows(plan: FloorPlan, party: dict[int, LineString]) -> FloorPlan:
    """The plan less the windows (and their panes) that face a neighbouring wing."""
    gone = [w for w in plan.windows if w.wall in party
            and party[w.wall].buffer(w.width / 2 + _TOUCH).covers(Point(w.position))]
    if not gone:
        return plan
    ids = {w.id for w in gone}
    walls = []
    for wall in plan.walls:
        drop = {(round(w.position[0], 6), round(w.position[1], 6)) for w in gone if w.wall == wall.id}
        kept = tuple(o for o in wall.openings if not (
            o.kind == "window" and tuple(round(c, 6) for c in wall.point_at(o.center)) in drop))
        walls.append(replace(wall, openings=kept) if len(kept) != len(wall.openings) else wall)
    names = {(w.room, f"window{w.id}") for w in gone}
    windows = tuple(w for w in plan.windows if w.id not in ids)
    notes = [Diagnostic("info", "make_floor", f"left out {len(gone)} window(s) in the walls "
                        f"between wings (they would look into the neighbouring wing's wall)",
                        floor=plan.index)]
    dark = sorted({w.room for w in gone} - {w.room for w in windows})
    if dark:  # typed before the wings met, as if those walls looked out
        notes.append(Diagnostic(
            "warning", "make_floor",
            f"{', '.join(plan.room(r).label for r in dark)} lost every window to the walls "
            f"between wings: each wing is typed on its own, as if those walls looked out",
            floor=plan.index))
    return plan.with_changes(
        walls=tuple(walls), windows=windows,
        furniture=tuple(i for i in plan.furniture
                        if not (i.is_detail and (i.room, i.name) in names)),
        diagnostics=plan.diagnostics + tuple(notes))


def _facing(plan: FloorPlan, party: dict[int, LineString], wall: Wall,
            at: tuple[float, float]) -> Wall | None:
    """The party wall of another wing back to back with ``wall`` at point ``at``."""
    point = Point(at)
    return next((plan.wall(w) for w in party if w != wall.id
                 and plan.wall(w).segment().distance(point) < _TOUCH), None)


def _doorway(door: Door, rooms: tuple[int, int]) -> Door:
    """``door`` as an open doorway (no leaf) between two rooms of different wings."""
    return replace(door, rooms=rooms, is_front=False, reason="reachability", state="open",
                   angle=DOOR_OPEN_ANGLE, leaf=False, swing_room=rooms[0])


def _party_front_doors(plan: FloorPlan, party: dict[int, LineString], owner: dict[int, int]
                       ) -> tuple[FloorPlan, set[tuple[int, int]], set[int]]:
    """A wing's front door in a party wall would open into the neighbour's wall: it
    becomes the doorway between the two wings (cut through both walls), unless the room
    behind is private (a bedroom must not be the way into a wing): then it is left out,
    for a front door elsewhere in the wing (:func:`_new_front_door`). Returns the plan,
    the pairs of wings so joined and the wings whose front door was left out."""
    joined: set[tuple[int, int]] = set()
    dropped: set[int] = set()
    walls = {w.id: w for w in plan.walls}
    doors, gone, notes = [], set(), []
    graph = plan.room_graph.copy() if plan.room_graph is not None else None
    for door in plan.doors:
        other = _facing(plan, party, walls[door.wall], door.position) \
            if door.is_front and door.wall in party else None
        if other is None:
            doors.append(door)
            continue
        inside = door.rooms[0] if door.rooms[1] == OUTSIDE else door.rooms[1]
        rooms = (inside, other.rooms[0])
        gone.add(door.id)
        if graph is not None and graph.has_edge(inside, OUTSIDE):
            graph.remove_edge(inside, OUTSIDE)
        if plan.room(other.rooms[0]).private:  # never the way into a wing: joined elsewhere
            walls[door.wall] = _without_opening_of(walls[door.wall], door)
            dropped.add(owner[inside])
            notes.append(Diagnostic("info", "make_floor",
                                    f"left out door {door.id}, a wing's front door in the wall "
                                    f"between wings: it would open into "
                                    f"{plan.room(other.rooms[0]).label}, a private room",
                                    floor=plan.index))
            continue
        if any(d.id in gone and set(d.rooms) == set(rooms)
               and Point(d.position).distance(Point(door.position)) < d.width for d in doors):
            # both wings put their front doors here, face to face: one doorway, whose
            # opening in this wall was cut in line with the other's
            walls[door.wall] = _without_opening_of(walls[door.wall], door)
            continue
        walls[other.id] = walls[other.id].with_opening(Opening(
            "door", other.segment().project(Point(door.position)), door.width, door.height))
        doors.append(_doorway(door, rooms))
        first, second = sorted((owner[rooms[0]], owner[rooms[1]]))
        joined.add((first, second))
        if graph is not None:
            graph.add_edge(*rooms, door=door.id, wall=door.wall, reason="wings")
        notes.append(Diagnostic("info", "make_floor",
                                f"door {door.id}, a wing's front door in the wall between "
                                f"wings, is the doorway from {plan.room(inside).label} to "
                                f"{plan.room(other.rooms[0]).label}", floor=plan.index))
    if not gone:
        return plan, joined, dropped
    plan = plan.with_changes(
        walls=tuple(walls[w.id] for w in plan.walls), doors=tuple(doors), room_graph=graph,
        furniture=tuple(i for i in plan.furniture if not (i.is_detail and i.door in gone)),
        diagnostics=plan.diagnostics + tuple(notes))
    return _renumbered_doors(plan), joined, dropped


def _without_opening_of(wall: Wall, door: Door) -> Wall:
    """``wall`` less the opening cut for ``door``."""
    along = wall.segment().project(Point(door.position))
    kept = tuple(o for o in wall.openings if not (
        o.kind == "door" and abs(o.center - along) < _TOUCH and abs(o.width - door.width) < _TOUCH))
    return replace(wall, openings=kept)


def _renumbered_doors(plan: FloorPlan) -> FloorPlan:
    """Door ids 0, 1, … again after doors were merged (items and graph follow)."""
    new = {d.id: k for k, d in enumerate(plan.doors)}
    if all(k == v for k, v in new.items()):
        return plan
    items = []
    for i in plan.furniture:
        if i.door is not None and i.door in new:
            name = f"door{new[i.door]}" if i.name == f"door{i.door}" else i.name
            i = replace(i, door=new[i.door], name=name)
        items.append(i)
    graph = plan.room_graph.copy() if plan.room_graph is not None else None
    for _, _, data in graph.edges(data=True) if graph is not None else ():
        if data.get("door") in new:
            data["door"] = new[data["door"]]
    return plan.with_changes(doors=tuple(replace(d, id=new[d.id]) for d in plan.doors),
                             furniture=tuple(items), room_graph=graph)


def _new_front_door(plan: FloorPlan, party: dict[int, LineString],
                    rooms: Collection[int] | None = None) -> FloorPlan:
    """A front door, when every wing had its own in a party wall (``rooms`` None) or when
    the wing of ``rooms`` lost its own (it faced a private room): an open doorway in the
    longest stretch of a circulation room's outer wall (not a party wall) that no
    window, door or furniture item takes. It is the floor's entry when the floor had no
    other front door."""
    from cga.operations.roomtyping.doors import door_spans, free_intervals, make_door

    width = plan.settings.door_width
    spans = door_spans(plan)
    taken = shapely.union_all([i.footprint() for i in plan.furniture if not i.is_detail])
    best = None
    for wall in plan.walls:
        if not wall.outer or wall.id in party or not plan.room(wall.rooms[0]).circulation \
                or (rooms is not None and wall.rooms[0] not in rooms):
            continue
        for lo, hi in free_intervals(wall, spans[wall.id]):
            centre = (lo + hi) / 2
            approach = LineString([wall.point_at(centre - width / 2), wall.point_at(centre + width / 2)])
            approach = approach.buffer(1.0, cap_style="flat", single_sided=False)
            if hi - lo >= width and not approach.intersects(taken) \
                    and (best is None or hi - lo > best[0]):
                best = (hi - lo, wall, centre, wall.rooms[0])
    whose = "the floor's" if rooms is None else "the wing's"
    if best is None:
        if rooms is not None:  # the wing is joined to the others inside instead
            return plan
        return plan.with_changes(diagnostics=plan.diagnostics + (Diagnostic(
            "warning", "make_floor", "the wings' front doors were all in the walls between "
            "them, and no hall or corridor has a free outer wall for another: the floor has "
            "no front door", floor=plan.index),))
    _, wall, centre, room = best
    door = make_door(len(plan.doors), wall, centre, (room, OUTSIDE), plan, reason="front")
    door = replace(door, state="open", angle=DOOR_OPEN_ANGLE, leaf=False)
    walls = tuple(w.with_opening(Opening("door", centre, width, plan.settings.door_height))
                  if w.id == wall.id else w for w in plan.walls)
    graph = plan.room_graph.copy() if plan.room_graph is not None else None
    if graph is not None:
        graph.add_edge(room, OUTSIDE, door=door.id, wall=wall.id, reason="front")
    x, z = door.position
    note = Diagnostic("info", "make_floor", f"the wings' front doors were in the walls between "
                      f"them; {whose} front door is door {door.id}, an open doorway at "
                      f"({x:.2f}, {z:.2f}) into {plan.room(room).label}", floor=plan.index)
    entry = room if plan.front_door() is None else plan.entry
    return plan.with_changes(walls=walls, doors=plan.doors + (door,), room_graph=graph,
                             entry=entry, diagnostics=plan.diagnostics + (note,))


def _doorway_spot(plan: FloorPlan, shared: LineString, width: float,
                  thickness: float) -> tuple[Point, list[FurnitureItem]] | None:
    """Where a doorway ``width`` wide goes on ``shared``, clear of the walls' ends: the
    spot nearest the middle with no furniture within a metre on either side (the items
    were placed before the wings were joined), else the middle and the items in its way;
    None when the stretch is too short."""
    items = [i for i in plan.furniture if not i.is_detail]
    margin = width / 2 + thickness + 0.1
    lo, hi = margin, shared.length - margin
    if hi < lo:
        return None

    def in_way(t: float) -> list[FurnitureItem]:
        a, b = shared.interpolate(t - width / 2), shared.interpolate(t + width / 2)
        approach = LineString([a, b]).buffer(1.0, cap_style="flat")
        return [i for i in items if i.footprint().intersects(approach)]

    middle = shared.length / 2
    spots = sorted((lo + k * 0.05 for k in range(int((hi - lo) / 0.05) + 1)),
                   key=lambda t: abs(t - middle))
    for t in spots:
        if not in_way(t):
            return shared.interpolate(t), []
    t = min(max(middle, lo), hi)
    return shared.interpolate(t), in_way(t)


def _join_circulation(plan: FloorPlan, party: dict[int, LineString], owner: dict[int, int],
                      count: int, joined: set[tuple[int, int]]) -> FloorPlan:
    """Doorways through the party walls, so the wings are one building inside.

    First one between facing circulation rooms (halls, corridors) for every pair of
    wings not yet joined, on the longest stretch they share. Then, while some wings are
    still apart, one doorway joining two of the parts, the best way left
    (:func:`_doorway_rank`): a hall or corridor into a room that may be passed through,
    two such rooms, and last a private room, with a warning, where one of the parts has
    no front door (above the ground floor none has: a wing apart is cut off, its only
    way in would be the stair, which stands in one wing)."""
    width = plan.settings.door_width
    candidates = []
    for wall_a, wall_b, _, _ in _back_to_back(plan, party, owner):
        shared = wall_a.segment().intersection(wall_b.segment().buffer(_TOUCH))
        if plan.core_room in (wall_a.rooms[0], wall_b.rooms[0]):
            shared = _along_landing(plan, shared, max(wall_a.thickness, wall_b.thickness))
        if shared.length >= width + 2 * max(wall_a.thickness, wall_b.thickness):
            rank = _doorway_rank(plan.room(wall_a.rooms[0]), plan.room(wall_b.rooms[0]))
            candidates.append((rank, -shared.length, wall_a.id, wall_b.id, shared))
    candidates.sort(key=lambda c: c[:4])
    cutter = _DoorwayCutter(plan)
    for rank, _, a, b, shared in candidates:
        pair = cutter.wings(a, b, owner)
        if rank == 0 and pair not in joined and cutter.cut(a, b, shared) is not None:
            joined.add(pair)
    parts = UnionFind(range(count))
    for pair in joined:
        parts.union(*pair)
    fronted = {owner[r] for d in plan.doors if d.is_front for r in d.rooms if r != OUTSIDE}

    def entered(wing: int) -> bool:
        """Whether the part ``wing`` is in has a front door of its own."""
        return any(parts[k] == parts[wing] for k in fronted)
    while True:
        apart = []
        for rank, length, a, b, shared in candidates:
            first, second = cutter.wings(a, b, owner)
            if rank >= _PRIVATE and entered(first) and entered(second):
                continue  # both parts have a front door: not through a bedroom
            if parts[first] != parts[second]:
                spot = cutter.spot(a, b, shared)
                if spot is not None:
                    apart.append((rank, bool(spot[1]), length, a, b, shared))
        if not apart:
            break
        rank, _, _, a, b, shared = min(apart, key=lambda c: c[:5])
        door = cutter.cut(a, b, shared)
        assert door is not None  # its spot was found above
        parts.union(*cutter.wings(a, b, owner))
        if rank >= _PRIVATE:
            private = [plan.room(r).label for r in door.rooms if plan.room(r).private]
            cutter.notes.append(Diagnostic(
                "warning", "make_floor",
                f"the wings of floor {plan.index} are joined through {' and '.join(private)} "
                f"(door {door.id}): no hall, corridor or room that may be passed through "
                f"shares a wall with the other wing", floor=plan.index))
    groups = len(list(parts.to_sets()))
    if groups > 1:
        only_private = any(parts[w] != parts[v] for w, v in
                           (cutter.wings(a, b, owner) for _, _, a, b, _ in candidates))
        why = ("only private rooms line the walls they share" if only_private
               else "no wall they share is long enough for a doorway")
        cutter.notes.append(Diagnostic(
            "info" if plan.index == 0 else "warning", "make_floor",
            f"{count} wings on floor {plan.index} stay in {groups} parts inside: {why}; "
            + ("each part is entered by a front door of its own" if plan.index == 0
               else "the wings apart from the stair's cannot be reached"), floor=plan.index))
    return cutter.plan()


def _along_landing(plan: FloorPlan, shared: LineString, thickness: float) -> LineString:
    """The part of ``shared``, a stretch of the stair core's wall, beside the floor
    landing: the flights and the stairwell take the rest of the core's floor, so only a
    doorway there leads anywhere (the top landing of a straight stair above the ground)."""
    from cga.operations.stairs.layout import landing_rect

    assert plan.core is not None
    landing = landing_rect(plan.core, top=plan.index > 0, margin=thickness)
    part = shared.intersection(landing.buffer(thickness + _TOUCH))
    return part if isinstance(part, LineString) else LineString()


_PASSAGE_WIDTH = 0.6
"""Width (m) of the passage kept from a doorway between wings to the door of the room it
opens into (the furniture's passage rule: a robot of 0.5 m and a margin)."""

_PRIVATE = 3
"""The least rank of a doorway into a private room (:func:`_doorway_rank`)."""


def _doorway_rank(a: Room, b: Room) -> int:
    """How well a doorway between rooms ``a`` and ``b`` of two wings joins them, lower
    is better: 0 two circulation rooms, 1 a circulation room and a room that may be
    passed through, 2 two such rooms; from :data:`_PRIVATE` on a private room (a
    bedroom or a bathroom) becomes the way into the other wing: beside a hall or
    corridor, beside another room, and last two private rooms."""
    private = a.private + b.private
    if not private:
        return 2 - a.circulation - b.circulation
    if private == 2:
        return _PRIVATE + 2
    return _PRIVATE + (not (a.circulation or b.circulation))


class _DoorwayCutter:
    """The doorways cut between wings so far: the plan's walls, doors, furniture, room
    graph and notes as they change."""

    def __init__(self, plan: FloorPlan):
        self.base = plan
        self.walls = {w.id: w for w in plan.walls}
        self.doors = list(plan.doors)
        self.furniture = list(plan.furniture)
        self.notes: list[Diagnostic] = []
        self.graph = plan.room_graph.copy() if plan.room_graph is not None else None

    def wings(self, a: int, b: int, owner: dict[int, int]) -> tuple[int, int]:
        """The wings of party walls ``a`` and ``b``, in order."""
        first, second = sorted((owner[self.walls[a].rooms[0]], owner[self.walls[b].rooms[0]]))
        return first, second

    def spot(self, a: int, b: int, shared: LineString) -> tuple[Point, list[FurnitureItem]] | None:
        """Where a doorway through walls ``a`` and ``b`` goes (:func:`_doorway_spot`)."""
        thickness = max(self.walls[a].thickness, self.walls[b].thickness)
        return _doorway_spot(self.base, shared, self.base.settings.door_width, thickness)

    def cut(self, a: int, b: int, shared: LineString) -> Door | None:
        """Cut a doorway through back-to-back walls ``a`` and ``b`` on ``shared`` (None:
        the stretch is too short), leaving out the items in its way, with a warning."""
        spot = self.spot(a, b, shared)
        if spot is None:
            return None
        plan, centre, in_way = self.base, spot[0], [*spot[1], *self._on_the_way(a, b, spot[0])]
        if in_way:
            gone = {(i.room, i.name) for i in in_way}
            gone |= {(i.room, i.name) for i in plan.furniture if (i.room, i.parent) in gone}
            self.furniture = [i for i in self.furniture if (i.room, i.name) not in gone]
            self.notes.append(Diagnostic(
                "warning", "make_floor",
                f"left out {', '.join(sorted(name for _, name in gone))}: in the way of the "
                f"doorway joining the wings at ({centre.x:.2f}, {centre.y:.2f})",
                floor=plan.index))
        wall_a, wall_b = self.walls[a], self.walls[b]
        for wall in (wall_a, wall_b):
            along = wall.segment().project(centre)
            self.walls[wall.id] = wall.with_opening(Opening("door", along, plan.settings.door_width,
                                                            plan.settings.door_height))
        rooms = (wall_a.rooms[0], wall_b.rooms[0])
        door = _doorway(Door(id=len(self.doors), wall=a, rooms=rooms,
                             position=(centre.x, centre.y), width=plan.settings.door_width,
                             height=plan.settings.door_height, swing_room=rooms[0]), rooms)
        self.doors.append(door)
        if self.graph is not None:
            self.graph.add_edge(*rooms, door=door.id, wall=a, reason="wings")
        return door

    def _on_the_way(self, a: int, b: int, centre: Point) -> list[FurnitureItem]:
        """The items of a room that is not circulation standing between the doorway at
        ``centre`` and the room's nearest door: its furniture was placed to keep a
        passage between its own doors, and through this doorway it becomes the way into
        the other wing, so a straight passage (:data:`_PASSAGE_WIDTH`) to that door is
        cleared."""
        out = []
        for room in (self.walls[a].rooms[0], self.walls[b].rooms[0]):
            if self.base.room(room).circulation:
                continue
            doors = [d for d in self.doors if room in d.rooms]
            if not doors:
                continue
            door = min(doors, key=lambda d: centre.distance(Point(d.position)))
            way = LineString([centre, door.position]).buffer(_PASSAGE_WIDTH / 2)
            out += [i for i in self.furniture if i.room == room and not i.is_detail
                    and i.footprint().intersects(way)]
        return out

    def plan(self) -> FloorPlan:
        """The plan with the doorways cut."""
        plan = self.base
        return plan.with_changes(walls=tuple(self.walls[w.id] for w in plan.walls),
                                 doors=tuple(self.doors), furniture=tuple(self.furniture),
                                 room_graph=self.graph,
                                 diagnostics=plan.diagnostics + tuple(self.notes))


def _merged_party_walls(plan: FloorPlan, party: dict[int, LineString],
                        owner: dict[int, int]) -> FloorPlan:
    """Each stretch where two wings' party walls stand back to back becomes one inner
    wall between the two rooms, as thick as both and centred on the line the wings
    meet on: the very solid the two made, and a doorway between the wings is a door in
    the wall between the rooms it joins, like every other door (its opening cut once).
    What is left of a party wall past its stretches stays an outer wall with the
    openings there. Doors, windows and the room graph name the wall that now holds
    them; walls keep their order, the merged ones after them, and new pieces and
    merged walls take new ids."""
    stretches = _back_to_back(plan, party, owner)
    if not stretches:
        return plan
    ids = itertools.count(max(w.id for w in plan.walls) + 1)
    cuts: dict[int, list[tuple[float, float, Wall]]] = {}  # party wall → (from, to, merged)
    merged = []
    for wall_a, wall_b, t0, t1 in stretches:  # outer walls: (room, OUTSIDE), the room on the left
        wall = Wall(next(ids), wall_a.point_at(t0), wall_a.point_at(t1), outer=False,
                    rooms=(wall_a.rooms[0], wall_b.rooms[0]),
                    thickness=wall_a.thickness + wall_b.thickness)
        merged.append(wall)
        for party_wall in (wall_a, wall_b):
            ends = sorted(party_wall.segment().project(Point(p)) for p in (wall.start, wall.end))
            cuts.setdefault(party_wall.id, []).append((ends[0], ends[1], wall))
    walls: list[Wall] = []
    parts: dict[int, list[tuple[float, float, Wall]]] = {}  # cut wall → what holds each stretch
    for wall in plan.walls:
        if wall.id not in cuts:
            walls.append(wall)
            continue
        parts[wall.id] = _parts(wall, sorted(cuts[wall.id], key=lambda c: c[0]), ids)
        walls += [part for _, _, part in parts[wall.id] if part.outer]
    walls += merged
    by_id = {w.id: w for w in walls}

    def holder(wall_id: int, point: tuple[float, float]) -> Wall:
        """The wall that now holds ``point`` of cut wall ``wall_id``."""
        along = plan.wall(wall_id).segment().project(Point(point))
        return next(part for lo, hi, part in parts[wall_id] if lo - _TOUCH <= along <= hi + _TOUCH)

    for old in (w for w in plan.walls if w.id in parts):
        for opening in old.openings:
            point = old.point_at(opening.center)
            target = by_id[holder(old.id, point).id]
            at = target.segment().project(Point(point))
            if not any(o.kind == opening.kind and abs(o.center - at) < _TOUCH
                       for o in target.openings):  # the doorway's two openings in line: one
                by_id[target.id] = target.with_opening(replace(opening, center=at))
    moved = {d.id: holder(d.wall, d.position).id for d in plan.doors if d.wall in parts}
    graph = plan.room_graph.copy() if plan.room_graph is not None else None
    for _, _, data in graph.edges(data=True) if graph is not None else ():
        if data.get("door") in moved:
            data["wall"] = moved[data["door"]]
    return plan.with_changes(
        walls=tuple(by_id[w.id] for w in walls), room_graph=graph,
        doors=tuple(replace(d, wall=moved[d.id]) if d.id in moved else d for d in plan.doors),
        windows=tuple(replace(w, wall=holder(w.wall, w.position).id) if w.wall in parts else w
                      for w in plan.windows))


def _back_to_back(plan: FloorPlan, party: dict[int, LineString],
                  owner: dict[int, int]) -> list[tuple[Wall, Wall, float, float]]:
    """The stretches where party walls of two wings stand back to back: ``(wall a,
    wall b, from, to)``, distances along ``a``, each pair once, in the order of
    ``party``. Walls meeting end to end, or across, share none."""
    out = []
    for a in party:
        wall_a = plan.wall(a)
        line = wall_a.segment()
        (ux, uz), (x0, z0) = wall_a.unit(), wall_a.start
        for b in party:
            wall_b = plan.wall(b)
            if b <= a or owner[wall_a.rooms[0]] == owner[wall_b.rooms[0]]:
                continue
            if any(abs((x - x0) * uz - (z - z0) * ux) > _TOUCH for x, z in (wall_b.start, wall_b.end)):
                continue  # not on a's line
            lo, hi = sorted(line.project(Point(p)) for p in (wall_b.start, wall_b.end))
            if hi - lo > _TOUCH:  # walls meeting end to end share no stretch
                out.append((wall_a, wall_b, lo, hi))
    return out


def _parts(wall: Wall, cuts: list[tuple[float, float, Wall]],
           ids: Iterator[int]) -> list[tuple[float, float, Wall]]:
    """``wall`` cut at its back-to-back stretches (``cuts``, in order along it): each
    stretch with its merged wall, and each piece between them as an outer wall without
    openings (the first keeps the wall's id), as ``(from, to, wall)``."""
    parts: list[tuple[float, float, Wall]] = []
    start = 0.0
    for lo, hi, inner in [*cuts, (wall.length, wall.length, None)]:
        if lo - start > _TOUCH:
            first = not any(p.outer for _, _, p in parts)
            parts.append((start, lo, replace(wall, id=wall.id if first else next(ids),
                                             start=wall.point_at(start), end=wall.point_at(lo),
                                             openings=())))
        if inner is not None:
            parts.append((lo, hi, inner))
        start = hi
    return parts
