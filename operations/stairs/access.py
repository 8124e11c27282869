"""Where the stair core may take a door: only beside its floor landing.

The core is a room like the others to the room graph, but a door into it anywhere but
at the landing would open onto the flights or into the stairwell. So the stretch of
each core wall where a door may lie (:func:`cga.operations.roomtyping.doors.door_spans`)
is cut down to the part of the wall that borders the landing of this floor
(:func:`.layout.landing_rect`); walls beside the flights take none.
"""

from __future__ import annotations

from collections.abc import Mapping

from shapely.geometry import Point

from cga.model import FloorPlan

from .layout import landing_rect

__all__ = ["core_door_spans", "arrives_at_top"]

Interval = tuple[float, float]


def arrives_at_top(plan: FloorPlan) -> bool:
    """Whether this floor's landing is the top landing of a straight stair (the upper of
    its two storeys); U stairs use one landing strip on every floor."""
    return plan.core is not None and plan.core.kind == "straight" and plan.index > 0


def core_door_spans(plan: FloorPlan, spans: Mapping[int, Interval]) -> dict[int, Interval]:
    """``spans`` with the core room's walls limited to its landing (empty elsewhere).

    An empty stretch is returned as ``(lo, lo - 1)``, which no door fits.
    """
    out = dict(spans)
    if plan.core is None or plan.core_room is None:
        return out
    t = plan.settings.wall_thickness
    # t reaches the wall centre lines; 2 cm more covers the core's rounding to the grid
    landing = landing_rect(plan.core, arrives_at_top(plan), margin=t + 0.02)
    for wall in plan.walls_of(plan.core_room):
        lo, hi = spans[wall.id]
        line = wall.segment()
        piece = line.intersection(landing)
        if piece.is_empty or piece.length < 1e-6:
            out[wall.id] = (lo, lo - 1.0)
            continue
        ends = sorted(line.project(Point(c)) for c in piece.coords) if piece.geom_type == "LineString" \
            else sorted(line.project(Point(c)) for g in piece.geoms for c in g.coords)
        out[wall.id] = (max(lo, ends[0]), min(hi, ends[-1]))
    return out
