"""An independent checker of plans against DESIGN §11 and their typing tables.

It reads the tables with the csv module and the floors' rooms and doors only (never
the typing code or :mod:`cga.quality`), and reports what an architect would object to:
private rooms that are the only way into another room (unless that room lists the
private type in ``enteredFrom``: en-suite), offices and meeting rooms without a door
onto circulation, a room whose type needs a window without one (unless a warning names
it), a front door not into circulation, rooms whose type no rule defines,
two doors whose leaves sweep into each other. A table without a ``passThrough`` value
for a type makes it private when its name is a bedroom's or bathroom's (docs/room_typing.md).
The one type no table defines is ``Stair``, the stair core ``make_floor`` reserves on
every storey of a stack (DESIGN §12): it is circulation.
"""

from __future__ import annotations

import csv
import math
from collections import deque
from dataclasses import dataclass
from pathlib import Path

from shapely.geometry import Point, Polygon

from cga.model import OUTSIDE

from typing_checks import PRIVATE_PARTS

STAIR = "Stair"
SWEEP_OVERLAP = 0.01  # m² two leaves' sweeps may share (numerical noise)

__all__ = ["Table", "read_table", "floor_problems"]


@dataclass(frozen=True)
class Table:
    types: frozenset[str]
    private: frozenset[str]
    circulation: frozenset[str]
    entered_from: dict[str, frozenset[str]]
    needs_window: frozenset[str] = frozenset()


def read_table(path: Path) -> Table:
    lines = [line for line in path.read_text(encoding="utf-8").splitlines()
             if not line.startswith("#")]  # a '# units: m' line above the header
    rows = list(csv.DictReader(lines, delimiter=";"))
    def flag(row, key):
        return (row.get(key) or "").strip().lower() in ("1", "true")
    return Table(
        types=frozenset(r["Type"].strip() for r in rows),
        private=frozenset(r["Type"].strip() for r in rows if _private(r)),
        circulation=frozenset(r["Type"].strip() for r in rows if flag(r, "circulation")),
        entered_from={r["Type"].strip(): frozenset(t.strip() for t in (r.get("enteredFrom") or "").split(",") if t.strip())
                      for r in rows},
        needs_window=frozenset(r["Type"].strip() for r in rows if flag(r, "needsWindow")))


def _private(row) -> bool:
    value = (row.get("passThrough") or "").strip().lower()
    if value:
        return value in ("0", "false")
    return any(part in row["Type"].lower() for part in PRIVATE_PARTS)


def _sweep(plan, door) -> Polygon:
    """The quarter circle the leaf sweeps, from the hinge on the wall's centre line,
    clipped to the room it swings into (so the wall's own thickness is left out)."""
    wall = next(w for w in plan.walls if w.id == door.wall)
    (x0, z0), (x1, z1) = wall.start, wall.end
    length = math.dist(wall.start, wall.end)
    ux, uz = (x1 - x0) / length, (z1 - z0) / length
    px, pz = door.position
    sign = -1 if door.hinge == "start" else 1
    hx, hz = px + sign * ux * door.width / 2, pz + sign * uz * door.width / 2
    ax, az = -sign * ux, -sign * uz  # from the hinge to the other jamb
    room = next(r for r in plan.rooms if r.id == door.swing_room)
    nx, nz = -uz, ux
    if not room.polygon.contains(Point(px + nx * 0.3, pz + nz * 0.3)):
        nx, nz = uz, -ux
    arc = [(hx + door.width * (math.cos(t) * ax + math.sin(t) * nx),
            hz + door.width * (math.cos(t) * az + math.sin(t) * nz))
           for t in (k * math.pi / 32 for k in range(17))]
    return Polygon([(hx, hz), *arc]).intersection(room.polygon)


def _reachable(rooms, edges, start, without=None):
    seen = {start}
    todo = deque([start])
    while todo:
        a = todo.popleft()
        for b in edges.get(a, ()):
            if b != without and b not in seen:
                seen.add(b)
                todo.append(b)
    return seen


def floor_problems(plan, table: Table) -> list[str]:
    """Everything wrong with one typed floor, as sentences (empty: nothing)."""
    problems = []
    types = {r.id: r.type for r in plan.rooms}
    edges: dict[int, set[int]] = {r.id: set() for r in plan.rooms}
    for d in plan.doors:
        a, b = d.rooms
        if OUTSIDE not in (a, b):
            edges[a].add(b)
            edges[b].add(a)
    for r in plan.rooms:
        if r.type not in table.types | {STAIR}:
            problems.append(f"room {r.id} has type {r.type}, which no rule defines")
    entry = plan.entry if getattr(plan, "entry", None) is not None else plan.room_graph.graph["entry"]
    if plan.index == 0 and table.circulation:
        front = [d for d in plan.doors if d.is_front]
        if len(front) != 1 or types[front[0].swing_room] not in table.circulation:
            problems.append("the front door does not open into circulation")
    everything = _reachable(types, edges, entry)
    if everything != set(types):
        problems.append(f"rooms {sorted(set(types) - everything)} cannot be reached")
    for p in plan.rooms:
        if p.type not in table.private or p.id == entry:
            continue
        for other in everything - _reachable(types, edges, entry, without=p.id) - {p.id}:
            if p.type not in table.entered_from.get(types[other], ()):
                problems.append(f"{p.type} {p.id} is the only way into {types[other]} {other}")
    for r in plan.rooms:
        if r.type in ("Office", "Meetingroom") and not any(
                types[n] in table.circulation | {STAIR} for n in edges[r.id]):
            problems.append(f"{r.type} {r.id} does not open onto circulation")
    lit = {w.room for w in plan.windows}
    for r in plan.rooms:
        if r.type in table.needs_window and lit and r.id not in lit and not any(
                d.level == "warning" and d.room == r.id and "needs a window" in d.message
                for d in plan.diagnostics):
            problems.append(f"{r.type} {r.id} needs a window and has none, unannounced")
    sweeps = [(d.id, _sweep(plan, d)) for d in plan.doors]
    for i, (a, sweep_a) in enumerate(sweeps):
        for b, sweep_b in sweeps[i + 1:]:
            overlap = sweep_a.intersection(sweep_b).area
            if overlap > SWEEP_OVERLAP:
                problems.append(f"doors {a} and {b} sweep into each other ({overlap:.2f} m²)")
    return problems
