"""Floor plans from hand-written rectangles, for rule authors' tests (docs/room_typing.md).

A rule author who wants to unit-test a room-typing or furniture table needs a floor with
known rooms. :func:`plan_from_rectangles` builds the same :class:`cga.model.FloorPlan`
that ``make_floor`` makes, from axis-aligned rectangles that tile a rectilinear
footprint; they need not come from a BSP (pinwheel layouts work too)::

    plan = plan_from_rectangles([(0, 0, 6, 10), (6, 0, 14, 5), (6, 5, 14, 10)])
    plan.room(0).area           # 60.0
    plan.dcel.neighbours(0)     # [-1, 1, 2]  (-1 is the outside)
"""

from __future__ import annotations

import itertools
from collections.abc import Collection, Sequence

import shapely
from shapely.geometry import Polygon, box

from cga.errors import UsageError
from cga.model import FloorPlan, FloorSettings

from .assemble import plan_from_dcel
from .dcel import DCEL, EPS
from .errors import PartitionError

__all__ = ["plan_from_rectangles"]

Rectangle = tuple[float, float, float, float]


def plan_from_rectangles(rectangles: Sequence[Rectangle], *, settings: FloorSettings = FloorSettings(),
                         index: int = 0, elevation: float = 0.0, height: float = 3.0,
                         circulation: Collection[int] = ()) -> FloorPlan:
    """A floor whose rooms are the given rectangles.

    Parameters
    ----------
    rectangles
        ``(min_x, min_z, max_x, max_z)`` per room, in metres; room ``i`` is
        ``rectangles[i]``. Together they must tile one simply connected footprint
        without overlapping.
    settings
        Wall thickness and window sizes (windows go on every outer wall segment).
    index, elevation, height
        Floor number, y of the bottom of the floor slab, storey height.
    circulation
        Ids of the rooms that are halls or corridors (as ``make_floor`` carves them).

    Returns
    -------
    FloorPlan
        The plan with its DCEL (T-junctions are vertices), rooms, walls and windows.

    Raises
    ------
    UsageError
        If a rectangle is empty or narrower than two wall thicknesses, rectangles
        overlap, or their union is disconnected, has a hole, or touches itself at a
        corner.

    Notes
    -----
    O(n²) in the number of rectangles (each side is subdivided at every corner lying
    on it).
    """
    rects: list[Rectangle] = [(float(x0), float(z0), float(x1), float(z1))
                              for x0, z0, x1, z1 in rectangles]
    if not rects:
        raise UsageError("plan_from_rectangles needs at least one rectangle")
    _check_rectangles(rects, settings.wall_thickness)
    unknown = sorted(set(circulation) - set(range(len(rects))))
    if unknown:
        raise UsageError(f"circulation names rooms {unknown}, but there are only "
                         f"{len(rects)} rectangles (ids 0..{len(rects) - 1})")
    corners = sorted({corner for x0, z0, x1, z1 in rects
                      for corner in ((x0, z0), (x1, z0), (x1, z1), (x0, z1))})
    rings = [_subdivided_ring(r, corners) for r in rects]
    try:
        dcel = DCEL.from_polygons(rings)
        return plan_from_dcel(dcel, settings=settings, index=index, elevation=elevation, height=height,
                              circulation=circulation)
    except PartitionError as error:
        raise UsageError(f"rectangles do not make a floor: {error}") from None


def _check_rectangles(rects: list[Rectangle], thickness: float) -> None:
    for i, (x0, z0, x1, z1) in enumerate(rects):
        if not (x1 > x0 and z1 > z0):
            raise UsageError(f"rectangle {i} {rects[i]} is empty: write (min_x, min_z, max_x, max_z)")
        if min(x1 - x0, z1 - z0) <= 2 * thickness:
            raise UsageError(f"rectangle {i} {rects[i]} is too narrow for walls {thickness:.2f} m thick "
                             f"(needs more than {2 * thickness:.2f} m)")
    for (i, a), (j, b) in itertools.combinations(enumerate(rects), 2):
        if min(a[2], b[2]) - max(a[0], b[0]) > EPS and min(a[3], b[3]) - max(a[1], b[1]) > EPS:
            raise UsageError(f"rectangles {i} {a} and {j} {b} overlap")
    union = shapely.union_all([box(*r) for r in rects])
    if not isinstance(union, Polygon):
        raise UsageError("the rectangles do not form one connected footprint")
    if union.interiors:
        raise UsageError("the rectangles leave a hole inside the footprint (courtyards are not supported)")


def _subdivided_ring(rect: Rectangle, corners: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """The rectangle's counter-clockwise ring with every other corner lying on its sides."""
    x0, z0, x1, z1 = rect
    sides = [((x0, z0), (x1, z0)), ((x1, z0), (x1, z1)), ((x1, z1), (x0, z1)), ((x0, z1), (x0, z0))]
    ring: list[tuple[float, float]] = []
    for a, b in sides:
        ring.append(a)
        k = 0 if a[1] == b[1] else 1  # the side runs along x (horizontal) or along z
        lo, hi = sorted((a[k], b[k]))
        on = [p for p in corners if abs(p[1 - k] - a[1 - k]) <= EPS and lo + EPS < p[k] < hi - EPS]
        on.sort(key=lambda p: p[k], reverse=b[k] < a[k])
        ring.extend(on)
    return ring
