"""Independent checks of a furnished floor: overlaps, rooms, doors, windows, pairs.

Written against the documented guarantees only (docs/furniture.md, docs/furniture.md), not the
solver: the rule table is read with :mod:`csv`, door swings and window bands are built
here from the door and window records, and every test is a plain shapely predicate on
the items' footprints (:meth:`cga.model.FurnitureItem.footprint`). A bug in the solver
cannot hide behind the same bug here.

Checked, with a tolerance of 1 mm:

* no two solid items (not details, not non-colliding) overlap;
* every item lies inside the free floor of its room;
* no solid item stands in the quarter circle a door leaf sweeps;
* no ``canCloseWindow`` item stands in the band in front of a window, as deep as the
  item plus its front clearance;
* clearances: the front/back/side boxes of every solid item are free of walls and of
  solid items other than its own parent and children;
* children keep their pair distances (``maxPairDistance`` 0 = unbounded; not checked
  for a child against a wall) and face their parent: ``canBeAround`` children look at
  it, ``isOnTheSide`` children stand beside it turned the same way, other children
  stand in front of it, within its width, turned to face it. With disorder, a child
  may be turned off that by up to ``max_yaw`` radians (the documented largest free
  turn); ``canBeAround`` children must still look at their parent;
* clearance boxes turn with the item (its quarter turns and its free yaw);
* copies of a ``layout`` = ``perimeter`` row are named ``<name>#<k>`` and follow that
  row, their children ``<child>#<k>`` the child's row;
* passage (``passage_width`` > 0): a round robot of that diameter that can go from one
  door of a room to another in the empty room still can with the furniture in. The
  robot's centre may go where the free floor (room interior minus the solid items)
  is at least ``passage_width / 2`` away from everything (a round buffer, i.e. a disc
  robot, where the solver uses a square one: the solver's guarantee is the stronger);
  it enters through a door into the band in front of it, door-wide and ``passage_width
  / 2 + 0.1`` deep. Doors and the pieces of free floor their bands meet form a graph
  (networkx); doors in one component of the empty room's graph must stay in one
  component. The solver's "85 % of the floor stays reachable" is not checked here.
"""

from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import networkx as nx
import numpy as np
from shapely import STRtree
from shapely.geometry import LineString, Point, Polygon
from shapely.ops import unary_union

__all__ = ["read_furniture_rules", "furniture_violations", "passage_violations"]

TOL = 1e-3
OUTSIDE = -1
PASSAGE_WIDTH = 0.6
"""The solver's documented default passage width (m)."""


def _key(header: str) -> str:
    return re.sub(r"[^a-z]", "", header.lower()).replace("paar", "pair")


def read_furniture_rules(path: str | Path, units: float = 1.0) -> dict[tuple[str, str], dict]:
    """``(room type, item name)`` (lower case) → the row's values (distances × units)."""
    text = Path(path).read_text(encoding="utf-8-sig")
    lines = [line for line in text.splitlines() if line.strip()]
    if lines[0].replace(" ", "").lower() == "#units:m":
        units = 1.0  # distances of a metre table are metres under any grammar units
    lines = [line for line in lines if not line.lstrip().startswith("#")]
    delimiter = max(";\t,", key=lines[0].count)
    rows = [r for r in csv.reader(lines, delimiter=delimiter) if any(c.strip() for c in r)]
    header = [_key(h) for h in rows[0]]
    rules = {}
    for row in rows[1:]:
        cell = {h: c.strip() for h, c in zip(header, row) if h}

        def flag(name: str) -> bool:
            return cell.get(name, "").lower() in ("true", "1", "yes")

        def number(name: str) -> float:
            value = cell.get(name, "")
            return 0.0 if value.lower() in ("", "<null>") else float(value.replace(",", ".")) * units

        rules[(cell["room"].lower(), cell["name"].lower())] = {
            "along_wall": flag("isalongwall"),
            "around": flag("canbearound"),
            "side": flag("isontheside"),
            "close_window": flag("canclosewindow"),
            "min": number("minpairdistance"),
            "max": number("maxpairdistance"),
            "front": number("clearancefront"),
            "back": number("clearanceback"),
            "flank": number("clearanceside"),
        }
    return rules


def _side_into(plan, wall, point, room_id) -> np.ndarray:
    """Unit normal of ``wall`` at ``point`` pointing into room ``room_id``."""
    (x0, z0), (x1, z1) = wall.start, wall.end
    length = math.hypot(x1 - x0, z1 - z0)
    normal = np.array([-(z1 - z0), x1 - x0]) / length
    probe = Point(point[0] + normal[0] * 0.01, point[1] + normal[1] * 0.01)
    return normal if plan.room(room_id).polygon.contains(probe) else -normal


def door_swing_area(plan, door) -> Polygon:
    """The quarter circle swept by the door leaf, hinged on the wall face in its room."""
    wall = plan.wall(door.wall)
    normal = _side_into(plan, wall, door.position, door.swing_room)
    direction = np.subtract(wall.end, wall.start) / wall.length
    depth = plan.room(door.swing_room).interior.distance(Point(door.position))
    sign = -1 if door.hinge == "start" else 1
    hinge = np.asarray(door.position) + direction * sign * door.width / 2 + normal * depth
    latch = -sign * direction
    steps = np.linspace(0, math.pi / 2, 33)
    arc = [hinge + door.width * (math.cos(a) * latch + math.sin(a) * normal) for a in steps]
    return Polygon([tuple(hinge), *map(tuple, arc)])


def window_band(plan, window, depth: float) -> Polygon:
    """The band in front of a window in its room, ``depth`` beyond the wall face."""
    wall = plan.wall(window.wall)
    normal = _side_into(plan, wall, window.position, window.room)
    direction = np.subtract(wall.end, wall.start) / wall.length
    face = plan.room(window.room).interior.distance(Point(window.position))
    a = np.asarray(window.position) - direction * window.width / 2
    b = np.asarray(window.position) + direction * window.width / 2
    reach = normal * (face + depth)
    return Polygon([tuple(a), tuple(b), tuple(b + reach), tuple(a + reach)])


def _shrunk(polygon: Polygon) -> Polygon:
    return polygon.buffer(-TOL / 2, join_style="mitre")


def _clearance_boxes(item, rule) -> list[tuple[str, Polygon]]:
    """The item's clearance rectangles, built from its front vector and size."""
    w, _, d = item.size
    fx, fz = item.front
    sx, sz = -fz, fx
    cx, cz = item.position

    def rect(s0, s1, f0, f1):
        corners = [(cx + sx * s + fx * f, cz + sz * s + fz * f)
                   for s, f in ((s0, f0), (s1, f0), (s1, f1), (s0, f1))]
        return Polygon(corners)

    out = []
    if rule["front"] > 0:
        out.append(("front", rect(-w / 2, w / 2, d / 2, d / 2 + rule["front"])))
    if rule["back"] > 0:
        out.append(("back", rect(-w / 2, w / 2, -d / 2 - rule["back"], -d / 2)))
    if rule["flank"] > 0:
        out.append(("side", rect(w / 2, w / 2 + rule["flank"], -d / 2, d / 2)))
        out.append(("side", rect(-w / 2 - rule["flank"], -w / 2, -d / 2, d / 2)))
    return out


def door_band(plan, door, room_id: int, depth: float) -> Polygon:
    """The band in front of ``door`` in room ``room_id``: door-wide, ``depth`` beyond the
    wall face."""
    wall = plan.wall(door.wall)
    normal = _side_into(plan, wall, door.position, room_id)
    direction = np.subtract(wall.end, wall.start) / wall.length
    face = plan.room(room_id).interior.distance(Point(door.position))
    a = np.asarray(door.position) - direction * door.width / 2
    b = np.asarray(door.position) + direction * door.width / 2
    reach = normal * (face + depth)
    return Polygon([tuple(a), tuple(b), tuple(b + reach), tuple(a + reach)])


def _door_components(floor, bands: dict[int, Polygon]) -> list[set[int]]:
    """Doors joined by pieces of ``floor`` their bands meet (with area), as sets of ids."""
    graph = nx.Graph()
    graph.add_nodes_from(("door", d) for d in bands)
    pieces = [p for p in getattr(floor, "geoms", [floor]) if p.area > 1e-9]
    for k, piece in enumerate(pieces):
        for d, band in bands.items():
            if piece.intersection(band).area > 1e-9:
                graph.add_edge(("piece", k), ("door", d))
    return [{d for kind, d in c if kind == "door"} for c in nx.connected_components(graph)]


def passage_violations(plan, width: float = PASSAGE_WIDTH) -> list[str]:
    """Rooms whose furniture cuts doors apart that a robot of diameter ``width`` could
    travel between in the empty room (see the module docstring)."""
    problems = []
    radius = width / 2
    for room in plan.rooms:
        doors = [d for d in plan.doors if room.id in d.rooms]
        if len(doors) < 2:
            continue
        bands = {d.id: door_band(plan, d, room.id, radius + 0.1) for d in doors}
        solid = [i.footprint() for i in plan.furniture
                 if i.room == room.id and not i.is_detail and not i.non_collision]
        empty = _door_components(room.interior.buffer(-radius), bands)
        free = room.interior.difference(unary_union(solid)) if solid else room.interior
        furnished = _door_components(free.buffer(-radius), bands)
        for group in empty:
            if len(group) > 1 and not any(group <= c for c in furnished):
                apart = sorted(sorted(c & group) for c in furnished if c & group)
                problems.append(f"room {room.id}: furniture cuts doors "
                                f"{' from '.join(map(str, apart))} apart")
    return problems


def furniture_violations(plan, rules_path: str | Path, *, units: float = 1.0,
                         passage_width: float = PASSAGE_WIDTH,
                         max_yaw: float = 0.0) -> list[str]:
    """Every broken guarantee of a furnished floor, as readable messages (empty = valid).

    ``passage_width`` 0 skips the passage check (for floors furnished without it);
    ``max_yaw`` is the largest turn (radians) disorder may give a child off facing its
    parent."""
    rules = read_furniture_rules(rules_path, units)
    types = {room.id: (room.type or "").lower() for room in plan.rooms}
    problems: list[str] = []
    items = list(plan.furniture)
    solid = [i for i in items if not i.is_detail and not i.non_collision]
    by_key = {(i.room, i.name): i for i in items if not i.is_detail}

    def rule_of(item):
        return rules.get((types[item.room], item.name.split("#")[0].lower()))

    shrunk = [_shrunk(item.footprint()) for item in solid]
    tree = STRtree(shrunk)
    for item in items:
        if item.is_detail:
            continue
        room = plan.room(item.room)
        if not room.interior.buffer(TOL).covers(item.footprint()):
            problems.append(f"{item.name} (room {item.room}) is not inside its room's free floor")
    pairs = tree.query(shrunk, predicate="intersects") if shrunk else ([], [])
    for i, j in zip(*pairs):
        if i < j:
            a, b = solid[i], solid[j]
            problems.append(f"{a.name} (room {a.room}) overlaps {b.name} (room {b.room})")
    for door in plan.doors:
        if door.swing_room == OUTSIDE:
            continue
        for k in tree.query(_shrunk(door_swing_area(plan, door)), predicate="intersects"):
            problems.append(f"{solid[k].name} (room {solid[k].room}) is in the swing of door {door.id}")
    for item, footprint in zip(solid, shrunk):
        rule = rule_of(item)
        if rule is None:
            problems.append(f"{item.name} (room {item.room}) has no rule")
            continue
        if rule["close_window"]:
            for window in plan.windows:
                if window.room != item.room:
                    continue
                band = window_band(plan, window, item.size[2] + rule["front"])
                if footprint.intersects(_shrunk(band)):
                    problems.append(f"{item.name} (room {item.room}) covers window {window.id}")
        family = {item.parent} | {c.name for c in items if c.parent == item.name and c.room == item.room}
        walls = plan.room(item.room).interior.buffer(TOL)
        for side, clearance in _clearance_boxes(item, rule):
            if not walls.covers(clearance):
                problems.append(f"{item.name} (room {item.room}): clearance {side} reaches into a wall")
            for k in tree.query(_shrunk(clearance), predicate="intersects"):
                other = solid[k]
                if other is item or other.room != item.room or other.name in family:
                    continue
                problems.append(f"{item.name} (room {item.room}): clearance {side} blocked by "
                                f"{other.name}")
    for item in items:
        if item.is_detail or item.parent is None:
            continue
        parent = by_key.get((item.room, item.parent))
        rule = rule_of(item)
        where = f"{item.name} (room {item.room})"
        if parent is None:
            problems.append(f"{where}: parent {item.parent} is not in the room")
            continue
        gap = parent.footprint().distance(item.footprint())
        if gap < rule["min"] - TOL:
            problems.append(f"{where}: {gap:.3f} m from {parent.name}, below {rule['min']:g}")
        if rule["max"] > 0 and not rule["along_wall"] and gap > rule["max"] + TOL:
            problems.append(f"{where}: {gap:.3f} m from {parent.name}, above {rule['max']:g}")
        problems.extend(_orientation_problems(item, parent, rule, where, max_yaw))
    if passage_width > 0:
        problems.extend(passage_violations(plan, passage_width))
    return problems


def _turned_off(front, wanted, max_yaw: float) -> bool:
    """Whether the unit vectors ``front`` and ``wanted`` differ by more than ``max_yaw``."""
    cosine = float(np.clip(np.dot(front, wanted), -1.0, 1.0))
    return math.acos(cosine) > max_yaw + 1e-6


def _orientation_problems(item, parent, rule, where: str, max_yaw: float) -> list[str]:
    to_parent = np.subtract(parent.position, item.position)
    front = np.asarray(item.front)
    if rule["around"]:
        ray = LineString([item.position, tuple(np.asarray(item.position) + front * 100)])
        if not ray.intersects(parent.footprint()):
            return [f"{where} does not face {parent.name}"]
        return []
    if rule["side"]:
        if _turned_off(front, np.asarray(parent.front), max_yaw):
            return [f"{where} is not turned like {parent.name}"]
        lateral = abs(np.dot(to_parent, (-parent.front[1], parent.front[0])))
        if lateral < (parent.size[0] + item.size[0]) / 2 - TOL:
            return [f"{where} is not beside {parent.name}"]
        return []
    problems = []
    if _turned_off(front, -np.asarray(parent.front), max_yaw):
        problems.append(f"{where} does not face {parent.name}")
    ahead = -np.dot(to_parent, parent.front)
    lateral = abs(np.dot(to_parent, (-parent.front[1], parent.front[0])))
    if ahead <= 0:
        problems.append(f"{where} is not in front of {parent.name}")
    if lateral > parent.size[0] / 2 + TOL:
        problems.append(f"{where} is off to the side of {parent.name} by {lateral:.2f} m")
    return problems
