"""Stairs on the floor plans, in the usual architectural notation (DESIGN §12).

On the floor a stair leaves, its treads are drawn as lines across the flights up to the
cut line, a zig-zag break where the plan's horizontal cut (:data:`CUT_HEIGHT` above the
floor) passes through the stair; the treads above the cut are dashed. A walking line
runs up the middle of the flights from the bottom landing and ends in an arrow head
labelled "up". On the floor a stair arrives on, the stairwell opening in the slab is
outlined with its diagonals crossed (the usual mark of a void) and labelled "opening".

The functions draw into a :class:`~cga.export.drawing.Drawing` through ``to_paper``,
which maps plan ``(x, z)`` metres to paper pixels.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from shapely.geometry import Polygon

from cga.model import Flight, FloorPlan, Stair

from .drawing import Area, Drawing, Point, Polyline, Style, Text

__all__ = ["CUT_HEIGHT", "draw_stairs"]

CUT_HEIGHT = 1.2
"""Height (m) above the walking surface where a plan cuts through the stair."""

_INK = "#2f2b27"
_FLIGHT = Style(fill="#f3efe7", stroke=_INK, width=1.0)
_TREAD = Style(stroke=_INK, width=0.8)
_HIDDEN = Style(stroke="#7d7369", width=0.7, dash=(3.0, 2.5))
_CUT = Style(stroke=_INK, width=1.2)
_WALK = Style(stroke="#a33b2b", width=1.2)
_HEAD = Style(fill="#a33b2b")
_WELL = Style(stroke="#5d5d5d", width=1.0, dash=(5.0, 3.0))

ToPaper = Callable[[float, float], Point]


def draw_stairs(drawing: Drawing, plan: FloorPlan, to_paper: ToPaper) -> None:
    """Draw the stairwell arriving on ``plan`` and the stair leaving it (layer ``stairs``)."""
    down = plan.stair_down
    if down is not None:
        _draw_opening(drawing, down, to_paper)
    up = plan.stair_up
    if up is not None:
        _draw_stair(drawing, up, plan.floor_y, to_paper)


def _ring(polygon: Polygon, to_paper: ToPaper) -> tuple[Point, ...]:
    return tuple(to_paper(x, z) for x, z in polygon.exterior.coords[:-1])


def _draw_opening(drawing: Drawing, stair: Stair, to_paper: ToPaper) -> None:
    ring = _ring(stair.polygon, to_paper)
    drawing.add("stairs", Polyline(ring, _WELL, closed=True, css_class="stairwell"))
    drawing.add("stairs", Polyline((ring[0], ring[2]), _WELL, css_class="stairwell"))
    drawing.add("stairs", Polyline((ring[1], ring[3]), _WELL, css_class="stairwell"))
    # the label on the half landing, where no flight of the stair above is drawn
    where = stair.half_landing if stair.half_landing is not None else stair.polygon
    cx, cy = to_paper(*where.centroid.coords[0])
    drawing.add("stairs", Text((cx, cy + 4), "opening", 10, "#5d5d5d",
                               css_class="stairwell-label"))


def _draw_stair(drawing: Drawing, stair: Stair, floor_y: float, to_paper: ToPaper) -> None:
    cut = floor_y + CUT_HEIGHT
    for flight in stair.flights:
        drawing.add("stairs", Area((_ring(flight.polygon(), to_paper),), _FLIGHT, css_class="stair"))
    if stair.half_landing is not None:
        drawing.add("stairs", Polyline(_ring(stair.half_landing, to_paper), _HIDDEN, closed=True,
                                       css_class="stair-landing"))
    for flight in stair.flights:
        for k in range(1, flight.risers):
            below = flight.base_y + k * flight.rise <= cut
            line = _across(flight, (k - 1) * flight.going if k > 1 else 0.0, to_paper)
            if k > 1:
                drawing.add("stairs", Polyline(line, _TREAD if below else _HIDDEN,
                                               css_class="stair-tread"))
    _draw_cut(drawing, stair, cut, to_paper)
    _draw_walking_line(drawing, stair, to_paper)


def _across(flight: Flight, along: float, to_paper: ToPaper) -> tuple[Point, Point]:
    """The line across the flight ``along`` metres from its first riser."""
    dx, dz = flight.direction
    h = flight.width / 2
    sx, sz = flight.start
    a = (sx + along * dx + h * dz, sz + along * dz - h * dx)
    b = (sx + along * dx - h * dz, sz + along * dz + h * dx)
    return to_paper(*a), to_paper(*b)


def _draw_cut(drawing: Drawing, stair: Stair, cut: float, to_paper: ToPaper) -> None:
    """A zig-zag break line across the first flight where it rises through the cut."""
    flight = stair.flights[0]
    k = min(flight.risers - 1, max(1, math.floor((cut - flight.base_y) / flight.rise)))
    along = (k - 0.5) * flight.going
    dx, dz = flight.direction
    h = flight.width / 2
    sx, sz = flight.start
    points = []
    for t, lift in ((-h, -0.3), (-0.1 * h, -0.3), (0.0, 0.3), (0.1 * h, -0.3), (h, 0.3)):
        u = along + lift * flight.going
        points.append(to_paper(sx + u * dx - t * dz, sz + u * dz + t * dx))
    drawing.add("stairs", Polyline(tuple(points), _CUT, css_class="stair-cut"))


def _draw_walking_line(drawing: Drawing, stair: Stair, to_paper: ToPaper) -> None:
    """The walking line up the flights' middles, an arrow head at the top and "up"."""
    points = [to_paper(*stair.landing_points[0])]
    for flight in stair.flights:
        dx, dz = flight.direction
        sx, sz = flight.start
        points += [to_paper(sx, sz), to_paper(sx + flight.run * dx, sz + flight.run * dz)]
    drawing.add("stairs", Polyline(tuple(points), _WALK, css_class="stair-arrow"))
    (x0, y0), (x1, y1) = points[-2], points[-1]
    length = math.hypot(x1 - x0, y1 - y0) or 1.0
    ux, uy = (x1 - x0) / length, (y1 - y0) / length
    size = 9.0
    head = ((x1 + ux * size, y1 + uy * size), (x1 - uy * size * 0.5, y1 + ux * size * 0.5),
            (x1 + uy * size * 0.5, y1 - ux * size * 0.5))
    drawing.add("stairs", Area((head,), _HEAD, css_class="stair-arrow"))
    bx, by = points[0]
    drawing.add("stairs", Text((bx, by + 4), "up", 11, "#a33b2b", bold=True,
                               css_class="stair-up"))
