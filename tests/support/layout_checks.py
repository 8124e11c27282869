"""An independent checker of plans against DESIGN §11 and their typing tables.

It reads the tables with the csv module and the floors' rooms and doors only (never
the typing code or :mod:`cga.quality`), and reports what an architect would object to:
private rooms that are the only way into another room (unless that room lists the
private type in ``enteredFrom``: en-suite), offices and meeting rooms without a door
onto circulation, a front door not into circulation, rooms whose type no rule defines.
The one type no table defines is ``Stair``, the stair core ``make_floor`` reserves on
every storey of a stack (DESIGN §12): it is circulation.
"""

from __future__ import annotations

import csv
from collections import deque
from dataclasses import dataclass
from pathlib import Path

from cga.model import OUTSIDE

STAIR = "Stair"

__all__ = ["Table", "read_table", "floor_problems"]


@dataclass(frozen=True)
class Table:
    types: frozenset[str]
    private: frozenset[str]
    circulation: frozenset[str]
    entered_from: dict[str, frozenset[str]]


def read_table(path: Path) -> Table:
    lines = [line for line in path.read_text(encoding="utf-8").splitlines()
             if not line.startswith("#")]  # a '# units: m' line above the header
    rows = list(csv.DictReader(lines, delimiter=";"))
    def flag(row, key):
        return (row.get(key) or "").strip().lower() in ("1", "true")
    return Table(
        types=frozenset(r["Type"].strip() for r in rows),
        private=frozenset(r["Type"].strip() for r in rows if (r.get("passThrough") or "").strip().lower() in ("0", "false")),
        circulation=frozenset(r["Type"].strip() for r in rows if flag(r, "circulation")),
        entered_from={r["Type"].strip(): frozenset(t.strip() for t in (r.get("enteredFrom") or "").split(",") if t.strip())
                      for r in rows})


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
    return problems
