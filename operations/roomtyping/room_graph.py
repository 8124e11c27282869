"""The room graph: which rooms a door joins, and the fewest extra doors for reachability.

Thesis §3.3 and Algorithm 4 (connectRooms): after typing, two neighbouring rooms are
joined when the rule of one lists the type of the other. Here "neighbouring" means
sharing a wall segment that can take a door (:func:`door_sites`), so every edge of the
graph becomes a real door, and the same adjacency is what the typing's neighbour
requirement checks. One listing is enough (as in the thesis, where the laundry, listing
the bathroom, gets a door to it although the bathroom does not list the laundry): the
rule that placed a room next to a listed type thereby asks for the door.

Rules need not connect every room. :func:`reachability_pairs` adds the fewest doors that
make the floor one connected component (so every room is reachable from the entry): with
``c`` components, ``c - 1`` doors are necessary and, since the door-capable adjacency
of a floor is connected, sufficient. They are chosen as a minimum spanning tree of the
components (Kruskal with :class:`networkx.utils.UnionFind`), preferring doors into hubs:
the room with more rule doors, then the bigger room, then the longer wall.

A connected floor may still be one whose only way into a room passes a bedroom or a
bathroom (DESIGN §11: private rooms are never the only way into another room). Tables
written for the thesis say nothing about access, and their ``Neighbours`` happily join a
laundry to the bathroom alone. :func:`privacy_pairs` therefore adds, after the rule and
reachability doors, the fewest doors it can that give every room a way in from the entry
that passes no private room (the private room itself may be the end of that way).
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from cga.errors import NoSolutionError
from cga.model import OUTSIDE, Door, FloorPlan, Room, Wall

from .doors import Interval, free_intervals
from .rules import RuleTable, TypeRule

if TYPE_CHECKING:  # pragma: no cover
    import networkx as nx

__all__ = ["DoorSites", "NoDoorsError", "door_sites", "rule_pairs", "reachability_pairs",
           "privacy_pairs", "access_pairs", "room_graph"]

Pair = tuple[int, int]


class NoDoorsError(NoSolutionError):
    """The rooms are typed, but no doors the rules allow reach every room from the entry
    (a re-drawn layout may still do; the typing says why when none does)."""


@dataclass(frozen=True)
class DoorSites:
    """Walls that can take a door: ``inner`` maps a room pair (ids, ascending) to its
    shared walls, ``outer`` a room to its outer walls; each wall comes with the
    intervals where a door opening may lie, the wall with the longest interval first."""

    inner: Mapping[Pair, tuple[tuple[Wall, Interval], ...]]
    outer: Mapping[int, tuple[tuple[Wall, Interval], ...]]

    def adjacency(self, room_ids: Sequence[int]) -> tuple[frozenset[int], ...]:
        """Door-capable neighbours of each room, as indices into ``room_ids`` (pairs
        with a room not in ``room_ids`` are left out)."""
        index = {room: i for i, room in enumerate(room_ids)}
        neighbours: list[set[int]] = [set() for _ in room_ids]
        for a, b in self.inner:
            if a not in index or b not in index:
                continue  # a room left out (the stair core is not typed by the rules)
            neighbours[index[a]].add(index[b])
            neighbours[index[b]].add(index[a])
        return tuple(frozenset(n) for n in neighbours)

    def longest(self, pair: Pair) -> float:
        wall_intervals = self.inner[pair]
        lo, hi = wall_intervals[0][1]
        return hi - lo


def door_sites(plan: FloorPlan, spans: Mapping[int, Interval], width: float) -> DoorSites:
    """Find the walls where a door of ``width`` fits.

    Parameters
    ----------
    plan:
        The floor.
    spans:
        Per wall, the stretch a door may occupy (:func:`.doors.door_spans`).
    width:
        The door width (m).

    Notes
    -----
    Outer walls are judged by their whole span, since the front door may take a
    window's place; inner walls keep clear of their openings.
    """
    inner: dict[Pair, list[tuple[Wall, Interval]]] = {}
    outer: dict[int, list[tuple[Wall, Interval]]] = {}
    for wall in plan.walls:
        if wall.outer:
            intervals = [spans[wall.id]]
        else:
            intervals = free_intervals(wall, spans[wall.id])
        best = max(intervals, key=lambda iv: iv[1] - iv[0], default=None)
        if best is None or best[1] - best[0] < width - 1e-9:
            continue
        if wall.outer:
            room = wall.rooms[0] if wall.rooms[1] == OUTSIDE else wall.rooms[1]
            outer.setdefault(room, []).append((wall, best))
        else:
            a, b = sorted(wall.rooms)
            inner.setdefault((a, b), []).append((wall, best))

    def ranked(items: list[tuple[Wall, Interval]]) -> tuple[tuple[Wall, Interval], ...]:
        return tuple(sorted(items, key=lambda item: (item[1][0] - item[1][1], item[0].id)))

    return DoorSites(inner={k: ranked(v) for k, v in sorted(inner.items())},
                     outer={k: ranked(v) for k, v in sorted(outer.items())})


def rule_pairs(types: Mapping[int, str], sites: DoorSites, table: RuleTable) -> list[Pair]:
    """Room pairs the rules connect: door-capable neighbours where either room's rule
    lists the other's type (thesis Algorithm 4), ascending."""
    pairs = []
    for a, b in sites.inner:
        rule_a, rule_b = table.rule_for(types[a]), table.rule_for(types[b])
        if (rule_a is not None and types[b] in rule_a.neighbours) or (
                rule_b is not None and types[a] in rule_b.neighbours):
            pairs.append((a, b))
    return pairs


def reachability_pairs(rooms: Sequence[Room], pairs: Sequence[Pair], sites: DoorSites, *,
                       entry: int) -> list[Pair]:
    """The fewest extra doors that connect every room to ``entry`` (see module notes).

    Raises
    ------
    NoDoorsError
        Some room shares no door-capable wall with the rest of the floor, so no set of
        doors reaches it.
    """
    degree = {room.id: 0 for room in rooms}
    for a, b in pairs:
        degree[a] += 1
        degree[b] += 1
    degree[entry] += 1  # the front door, or the stair for an upper floor
    area = {room.id: room.area for room in rooms}
    from networkx.utils import UnionFind  # imported here: `cga check` needs no networkx

    components = UnionFind(degree)
    for a, b in pairs:
        components.union(a, b)

    def preference(pair: Pair) -> tuple:
        hub = max(pair, key=lambda r: (degree[r], area[r], -r))
        return (-degree[hub], -area[hub], -sites.longest(pair), pair)

    added = []
    joined = set(pairs)
    for a, b in sorted((p for p in sites.inner if p not in joined), key=preference):
        if components[a] != components[b]:
            components.union(a, b)
            added.append((a, b))
    cut_off = sorted(r for r in degree if components[r] != components[entry])
    if cut_off:
        raise NoDoorsError(
            f"room{'s' if len(cut_off) > 1 else ''} {', '.join(map(str, cut_off))} cannot be "
            "reached from the entry: no wall shared with the rest of the floor is long enough "
            "for a door", [_too_short(room, rooms, sites) for room in cut_off])
    return added


def privacy_pairs(rooms: Sequence[Room], pairs: Sequence[Pair], sites: DoorSites, *,
                  entry: int) -> list[Pair]:
    """Extra doors that give every room a way in from ``entry`` passing no private room
    (see module notes): a door from a room so reached, and not itself private, into a
    room that is not, until every room is; the door into the biggest room first, from
    the room with the most doors, then along the longer wall.

    Raises
    ------
    NoDoorsError
        Some room has no door-capable wall with a room reached that way (a laundry
        whose only neighbour is the bathroom); a re-drawn layout may still give it one.
    """
    by_id = {room.id: room for room in rooms}
    doors: dict[int, set[int]] = {room.id: set() for room in rooms}
    for a, b in pairs:
        doors[a].add(b)
        doors[b].add(a)

    def opens_on(room: int) -> bool:  # a way in may go on through this room
        return room == entry or not by_id[room].private

    reached = {entry}
    stack = [entry]
    added: list[Pair] = []

    def preference(pair: Pair) -> tuple:
        inside, outside = (pair if pair[0] in reached else pair[::-1])
        return (-by_id[outside].area, -len(doors[inside]), -sites.longest(pair), pair)

    while True:
        while stack:
            room = stack.pop()
            if not opens_on(room):
                continue
            for other in doors[room] - reached:
                reached.add(other)
                stack.append(other)
        candidates = [(a, b) for a, b in sites.inner
                      if (a in reached) != (b in reached)
                      and opens_on(a if a in reached else b)]
        if not candidates:
            break
        a, b = min(candidates, key=preference)
        added.append((a, b))
        doors[a].add(b)
        doors[b].add(a)
        inside, outside = (a, b) if a in reached else (b, a)
        reached.add(outside)
        stack.append(outside)
    cut_off = sorted(room.id for room in rooms if room.id not in reached)
    if cut_off:
        raise NoDoorsError(
            f"room{'s' if len(cut_off) > 1 else ''} {', '.join(map(str, cut_off))} can be "
            "reached only through a bedroom or bathroom: no wall shared with a room reached "
            "another way is long enough for a door",
            [f"room {room} ({by_id[room].type}) adjoins "
             + (", ".join(f"room {other} ({by_id[other].type})"
                          for other in sorted(sum(p) - room for p in sites.inner if room in p))
                or "no room")
             for room in cut_off])
    return sorted(tuple(sorted(pair)) for pair in added)  # type: ignore[misc]


def _too_short(room: int, rooms: Sequence[Room], sites: DoorSites) -> str:
    shared = [pair for pair in sites.inner if room in pair]
    if shared:
        return f"room {room} connects only to rooms {', '.join(str(sum(p) - room) for p in shared)}"
    polygon = next(r.polygon for r in rooms if r.id == room)
    touching = [r.id for r in rooms if r.id != room and
                polygon.boundary.intersection(r.polygon.boundary).length > 1e-9]
    return (f"room {room} shares walls with rooms {', '.join(map(str, touching))} but none "
            "leaves room for a door and its margins; make rooms wider or doors narrower")


def room_graph(plan: FloorPlan, doors: Sequence[Door]) -> nx.Graph:
    """The room graph: nodes are room ids and :data:`~cga.model.OUTSIDE` (attribute
    ``type``: the room type, ``"outside"``), one edge per door (attributes ``door``,
    ``wall``, ``reason``, ``state`` and ``angle``: a planner sees which doors it must
    open)."""
    import networkx as nx

    graph = nx.Graph(floor=plan.index)
    graph.add_node(OUTSIDE, type="outside")
    for room in plan.rooms:
        graph.add_node(room.id, type=room.type, area=room.area)
    for door in doors:
        graph.add_edge(*door.rooms, door=door.id, wall=door.wall, reason=door.reason,
                       state=door.state, angle=door.angle)
    return graph


def access_pairs(rooms: Sequence[Room], sites: DoorSites, table: RuleTable, *,
                 entry: int, through_private: bool = False) -> list[Pair]:
    """The doors of a table with access rules: one door into every room (DESIGN §11).

    Every room is entered once, from the room it is reached from on the cheapest way
    from ``entry``: a door from ``a`` into ``b`` needs a door-capable wall and ``b``'s rule
    to allow entering from ``a``'s type; ``a`` must be the entry, circulation, a room its
    rule lets others pass through, or a private room that ``b`` lists explicitly in
    ``enteredFrom`` (an en-suite bathroom). A room no rule takes (the default type) is
    entered from any room but a private one: a bedroom is never the way into it, unless
    ``through_private`` (the typing's last resort, with a warning). Steps out of
    circulation cost 1, out of other rooms 4, so rooms open onto the hall or corridor
    whenever they can. The doors form a tree: no room is entered twice, and adjacency
    alone makes no door.

    Raises
    ------
    NoDoorsError
        Some room cannot be entered from any room the rules allow on a way from the
        entry; the reasons name it and what it may be entered from.

    Notes
    -----
    Dijkstra over the door-capable adjacency, O(E log V).
    """
    by_id = {room.id: room for room in rooms}
    neighbours: dict[int, list[int]] = {room.id: [] for room in rooms}
    for a, b in sites.inner:
        neighbours[a].append(b)
        neighbours[b].append(a)

    def rule(room: int) -> TypeRule | None:
        type_name = by_id[room].type
        return table.rule_for(type_name) if type_name else None

    def passable(room: int) -> bool:
        r = rule(room)
        return room == entry or by_id[room].circulation or r is None or r.pass_through

    def may_enter(a: int, b: int) -> bool:
        if by_id[b].circulation and not passable(a):
            return False  # a hall or stair landing entered through a bedroom makes it a passage
        rb = rule(b)
        if rb is None:  # a room no rule takes is entered like any room, never via a bedroom
            return through_private or passable(a)
        if not rb.may_be_entered_from(by_id[a].type or ""):
            return False
        return passable(a) or (rb.entered_from is not None and by_id[a].type in rb.entered_from)

    cost = {entry: 0.0}
    parent: dict[int, int] = {}
    heap: list[tuple[float, int, int]] = [(0.0, 0, entry)]
    counter = 1
    done: set[int] = set()
    while heap:
        c, _, a = heapq.heappop(heap)
        if a in done:
            continue
        done.add(a)
        step = 1.0 if by_id[a].circulation else 4.0
        for b in sorted(neighbours[a]):
            if b in done or not may_enter(a, b):
                continue
            if c + step < cost.get(b, math.inf):
                cost[b] = c + step
                parent[b] = a
                heapq.heappush(heap, (c + step, counter, b))
                counter += 1
    missing = [room.id for room in rooms if room.id not in done]
    if missing:
        reasons = []
        for room in missing:
            r = rule(room)
            allowed = (", ".join(r.entered_from) if r and r.entered_from else
                       "any neighbour but a private room" if r is None else "its neighbours")
            beside = ", ".join(f"room {b} ({by_id[b].type})" for b in sorted(neighbours[room]))
            reasons.append(f"room {room} ({by_id[room].type}) may be entered from {allowed}; "
                           f"its door-capable neighbours are {beside or 'none'}")
        raise NoDoorsError(f"the access rules of {table.file} leave room"
                           f"{'s' if len(missing) > 1 else ''} "
                           f"{', '.join(map(str, missing))} without a door", reasons)
    return sorted(tuple(sorted((a, b))) for b, a in parent.items())  # type: ignore[misc]
