"""Independent checks of a typed floor: types, mandatory rules, doors, reachability.

Written against the documented behaviour only (docs/room_typing.md, docs/room_typing.md), not the
typing code: the rule table is read with :mod:`csv`, adjacency comes from the room
polygons (shapely), reachability from the door records (networkx). A bug in the typing
cannot hide behind the same bug here.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import networkx as nx
from shapely.geometry import LineString

__all__ = ["read_rules", "validate_typed_plan"]

OUTSIDE = -1
DEFAULT_TYPE = "Commonroom"
TOL = 1e-6
MARGIN = 0.1
PRIVATE_PARTS = ("bed", "bath", "toilet", "shower", "wc")


def table_in_metres(path: str | Path) -> bool:
    """Whether the table's first line is the documented ``# units: m`` declaration."""
    first = Path(path).read_text(encoding="utf-8-sig").lstrip().splitlines()[0]
    return first.replace(" ", "").rstrip(";").lower() == "#units:m"


def read_rules(path: str | Path) -> list[dict]:
    """The rules of a thesis-format table as dicts (lower-case keys, parsed values);
    ``#`` lines are comments (docs/room_typing.md)."""
    with open(path, newline="", encoding="utf-8-sig") as handle:
        rows = [row for row in csv.reader(handle, delimiter=";")
                if any(c.strip() for c in row) and not row[0].lstrip().startswith("#")]
    header = [h.strip().lower() for h in rows[0]]
    rules = []
    for row in rows[1:]:
        cell = dict(zip(header, (c.strip() for c in row)))
        rules.append({
            "type": cell["type"],
            "size": float(cell["size"].replace(",", ".")),
            "neighbours": {n.strip().lower() for n in cell["neighbours"].split(",") if n.strip()},
            "outside": cell["isoutsideconnected"].lower() in ("1", "true"),
            "appearance": int(float(cell["appearance"])),
            "optional": cell["additionroom"].lower() in ("1", "true"),
            # access columns (docs/room_typing.md): private rooms are nobody's way in
            # without a passThrough value, types named like bedrooms and bathrooms
            "private": (cell.get("passthrough", "").lower() in ("0", "false")
                        or (not cell.get("passthrough")
                            and any(part in cell["type"].lower() for part in PRIVATE_PARTS))),
            "access_table": "enteredfrom" in header,
            "entered_from": {n.strip().lower() for n in cell.get("enteredfrom", "").split(",")
                             if n.strip()},
        })
    return rules


def _shared_length(a, b) -> float:
    return a.polygon.boundary.intersection(b.polygon.boundary).length


def validate_typed_plan(plan, rules_path: str | Path, *, units: float = 1.0,
                        front_door: bool = True) -> None:
    """Assert everything the typing promises about ``plan`` (raises AssertionError)."""
    rules = read_rules(rules_path)
    if table_in_metres(rules_path):
        units = 1.0  # a metre table's sizes are m² under any grammar units
    rooms = {room.id: room for room in plan.rooms}
    types = {rid: room.type for rid, room in rooms.items()}

    # every room typed; appearance caps (the default type fills leftovers uncapped)
    assert all(isinstance(t, str) and t for t in types.values()), types
    known = {r["type"] for r in rules} | {DEFAULT_TYPE}
    assert set(types.values()) <= known, (set(types.values()) - known)
    for rule in rules:
        count = sum(t == rule["type"] for t in types.values())
        if rule["type"] != DEFAULT_TYPE:
            assert count <= rule["appearance"], (rule["type"], count)

    # mandatory rules: present, big enough, next to a listed type (one may go without)
    mandatory = [r for r in rules if not r["optional"]]
    if len(rooms) >= len(mandatory):
        without_neighbour = []
        for rule in mandatory:
            own = [r for r in rooms.values()
                   if r.type == rule["type"] and r.area >= rule["size"] * units ** 2 - TOL]
            assert own, f"no room of type {rule['type']} with ≥ {rule['size'] * units ** 2} m²"
            if not any(_shared_length(r, other) > TOL and other.type.lower() in rule["neighbours"]
                       for r in own for other in rooms.values() if other.id != r.id):
                without_neighbour.append(rule["type"])
        assert len(without_neighbour) <= 1, without_neighbour
        if without_neighbour:
            assert any(without_neighbour[0] in d.message for d in plan.diagnostics), \
                f"{without_neighbour[0]} has no listed neighbour and no diagnostic says so"

    # doors: on a wall the two rooms share, inside it with margins, cut as an opening
    walls = {wall.id: wall for wall in plan.walls}
    for door in plan.doors:
        wall = walls[door.wall]
        assert set(wall.rooms) == set(door.rooms), (door, wall.rooms)
        segment = LineString([wall.start, wall.end])
        centre = math.dist(wall.start, door.position)
        assert segment.distance(LineString([door.position, door.position])) < TOL
        assert MARGIN - TOL <= centre - door.width / 2 and \
            centre + door.width / 2 <= wall.length - MARGIN + TOL, (door, wall.length)
        a, b = door.rooms
        if OUTSIDE in door.rooms:
            inner = rooms[a if b == OUTSIDE else b]
            shared = inner.polygon.boundary.intersection(plan.footprint.boundary)
        else:
            shared = rooms[a].polygon.boundary.intersection(rooms[b].polygon.boundary)
        (x0, z0), (x1, z1) = wall.start, wall.end
        ux, uz = (x1 - x0) / wall.length, (z1 - z0) / wall.length
        leaf = LineString([(x0 + ux * (centre - door.width / 2), z0 + uz * (centre - door.width / 2)),
                           (x0 + ux * (centre + door.width / 2), z0 + uz * (centre + door.width / 2))])
        assert shared.buffer(TOL).covers(leaf), f"door {door.id} is not on a wall shared by {door.rooms}"
        assert door.swing_room in door.rooms and door.swing_room != OUTSIDE
        assert any(o.kind == "door" and abs(o.center - centre) < TOL and abs(o.width - door.width) < TOL
                   for o in wall.openings), f"door {door.id} not cut into wall {wall.id}"
    for wall in plan.walls:
        spans = sorted((o.center - o.width / 2, o.center + o.width / 2) for o in wall.openings)
        for (_, hi), (lo, _) in zip(spans, spans[1:]):
            assert hi <= lo + TOL, f"openings overlap on wall {wall.id}: {wall.openings}"

    # exactly one front door on the floor that has one, into its room
    fronts = [d for d in plan.doors if d.is_front]
    if front_door:
        assert len(fronts) == 1, fronts
        front = fronts[0]
        assert OUTSIDE in front.rooms and walls[front.wall].outer
        outside_rule = next((r for r in rules if r["outside"]), None)
        entry = front.swing_room
        if outside_rule is not None and len(rooms) >= len(mandatory):
            assert rooms[entry].type == outside_rule["type"], rooms[entry].type
    else:
        assert not fronts, fronts
        entry = plan.entry
    assert all(OUTSIDE not in d.rooms for d in plan.doors if not d.is_front)

    # reachability through the doors, from the outside (or the entry room)
    graph = nx.Graph()
    graph.add_nodes_from(rooms)
    graph.add_node(OUTSIDE)
    graph.add_edges_from(d.rooms for d in plan.doors)
    start = OUTSIDE if front_door else entry
    reached = nx.node_connected_component(graph, start)
    assert set(rooms) <= reached, f"unreachable rooms: {sorted(set(rooms) - reached)}"

    # a private room (passThrough false; by default one named like a bedroom or
    # bathroom) is the only way into no other room, but the rooms that name its type in
    # enteredFrom (an en-suite bathroom behind a bedroom); the room the floor is entered
    # by is every other room's way in, whatever its type
    by_type = {r["type"]: r for r in rules}
    for room in rooms.values():
        if not by_type.get(room.type, {}).get("private") or room.id in (start, entry):
            continue
        rest = graph.subgraph(n for n in graph if n != room.id)
        behind = reached - {room.id} - nx.node_connected_component(rest, start)
        for other in sorted(behind):
            allowed = by_type.get(rooms[other].type, {}).get("entered_from", set())
            # the typing's documented last resort for a room no rule takes: warned
            # (any room, for a table without access columns)
            last_resort = rooms[other].type == DEFAULT_TYPE or not rules[0]["access_table"]
            warned = last_resort and any(
                d.level == "warning" and d.room == other and "reached only through" in d.message
                for d in plan.diagnostics)
            assert room.type.lower() in allowed or warned, (
                f"{room.type} room {room.id} is the only way into {rooms[other].type} "
                f"room {other}")

    # the room graph is the door graph, with types
    room_graph = plan.room_graph
    assert set(room_graph.nodes) == set(rooms) | {OUTSIDE}
    assert {frozenset(e) for e in room_graph.edges} == {frozenset(d.rooms) for d in plan.doors}
    assert all(room_graph.nodes[r]["type"] == types[r] for r in rooms)
