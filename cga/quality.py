"""A layout-quality report per floor, read from the Scene alone (DESIGN §11).

What an architect looks at first, in numbers a dataset user can filter on:

* ``circulation_share``: halls, corridors and landings over the floor's room area;
* ``doors_per_room``: doors of every room (the front door counts for its room);
* ``pass_through_private``: private rooms (bedrooms, bathrooms: ``passThrough`` false)
  that are the only way into another room, with the rooms behind them;
* ``reached_only_through_private``: rooms every way to which from the entry passes a
  private room;
* ``area_out_of_range``: rooms whose area lies outside their rule's ``Size`` and
  ``maxSize``;
* ``ruleless``: rooms whose type no rule defines (the default type).

Reachability is computed on the door graph (doors only, not adjacency) from the floor's
entry (``room_graph.graph["entry"]``).
"""

from __future__ import annotations

from typing import Any

import networkx as nx

from .model import OUTSIDE, FloorPlan

__all__ = ["floor_quality", "quality_report"]


def floor_quality(plan: FloorPlan) -> dict[str, Any]:
    """The report of one floor (see the module notes); plain JSON-ready data."""
    area = sum(r.area for r in plan.rooms)
    circulation = sum(r.area for r in plan.rooms if r.circulation)
    doors = {r.id: sum(1 for d in plan.doors if r.id in d.rooms) for r in plan.rooms}
    graph = nx.Graph()
    graph.add_nodes_from(r.id for r in plan.rooms)
    graph.add_edges_from(d.rooms for d in plan.doors if OUTSIDE not in d.rooms)
    entry = plan.entry
    if entry is None and plan.room_graph is not None:
        entry = plan.room_graph.graph.get("entry")
    behind: dict[int, list[int]] = {}
    only_private: list[int] = []
    if entry is not None and entry in graph:
        reached = nx.node_connected_component(graph, entry)
        private = {r.id for r in plan.rooms if r.private and r.id != entry}
        for room in private:
            rest = graph.subgraph(n for n in graph if n != room)
            cut_off = sorted(reached - {room} - nx.node_connected_component(rest, entry))
            if cut_off:
                behind[room] = cut_off
        public = graph.subgraph(n for n in graph if n not in private)
        from_entry = nx.node_connected_component(public, entry)
        only_private = sorted(n for n in reached if n not in from_entry and n not in private)
        only_private += sorted(n for n in private if n in reached and not any(
            m in from_entry for m in graph.neighbors(n)))
    out_of_range = []
    for r in plan.rooms:
        if r.area_range is None:
            continue
        low, high = r.area_range
        if r.area < low - 1e-6 or (high is not None and r.area > high + 1e-6):
            out_of_range.append({"room": r.id, "type": r.type, "area": round(r.area, 2),
                                 "range": [low, high]})
    return {
        "floor": plan.index,
        "circulation_share": round(circulation / area, 4) if area else 0.0,
        "doors_per_room": {str(k): v for k, v in doors.items()},
        "pass_through_private": [{"room": k, "behind": v} for k, v in sorted(behind.items())],
        "reached_only_through_private": sorted(only_private),
        "area_out_of_range": out_of_range,
        "ruleless": [r.id for r in plan.rooms if r.type is not None and r.area_range is None
                     and not r.circulation],
    }


def quality_report(floors: list[FloorPlan]) -> list[dict[str, Any]]:
    """:func:`floor_quality` for every typed floor."""
    return [floor_quality(p) for p in floors if any(r.type for r in p.rooms)]
