"""Turn a partitioned DCEL into a :class:`cga.model.FloorPlan`.

Both ways of making a floor end here: the BSP of ``make_floor`` and the rectangle tilings
rule authors write in tests (:mod:`.rectangles`). One face becomes one room, one edge one
wall (its id is the DCEL edge number), and outer walls get their windows.
"""

from __future__ import annotations

from collections.abc import Collection

import shapely
from shapely.geometry import Polygon
from shapely.geometry.polygon import orient

from cga.model import FloorPlan, FloorSettings, Room, Wall

from .dcel import DCEL
from .errors import PartitionError
from .openings import place_windows

__all__ = ["plan_from_dcel"]

_GRID = 1e-6
"""Precision grid (m) of room interiors, so a 0.1 m wall leaves 5.9, not 5.8999999."""


def plan_from_dcel(dcel: DCEL, *, settings: FloorSettings, index: int, elevation: float,
                   height: float, circulation: Collection[int] = ()) -> FloorPlan:
    """Build the floor plan of a partitioned DCEL.

    Parameters
    ----------
    dcel
        The partition; face ``i`` becomes room ``i``.
    settings
        Wall thickness and window sizes used for room interiors and windows.
    index, elevation, height
        Floor number, y of the bottom of the floor slab, storey height.
    circulation
        Ids of the faces that are halls or corridors (:attr:`cga.model.Room.circulation`).

    Returns
    -------
    FloorPlan
        Rooms (polygon between wall centre lines with every DCEL vertex, interior
        without the walls: counter-clockwise, no collinear vertices), walls
        (``rooms = (left, right)``; an inner wall runs with its lower-id room on the
        left, an outer wall with its room on the left and the outside on the right),
        windows on the outer walls, and ``dcel``.

    Raises
    ------
    PartitionError
        If a room has no connected free floor left once the walls are subtracted
        (a room narrower than its walls).
    """
    t = settings.wall_thickness
    footprint = Polygon([h.start for h in dcel.outer_boundary()])
    walls = []
    for h in dcel.edges():
        if h.face.is_outside or (not h.twin.face.is_outside and h.twin.face.id < h.face.id):
            h = h.twin
        outer = h.twin.face.is_outside
        walls.append(Wall(h.edge, h.start, h.end, outer, (h.face.id, h.twin.face.id), t))
    walls.sort(key=lambda w: w.id)

    # Inner walls take t/2 off each side of their edge, outer walls t inside the
    # footprint: the room shrunk by t/2 (a mitred offset keeps rectilinear corners
    # square) within the footprint shrunk by t.
    polygons = [Polygon(dcel.points(f)) for f in dcel.faces]
    shrunk = footprint.buffer(-t, join_style="mitre")
    interiors = shapely.intersection(shapely.buffer(polygons, -t / 2, join_style="mitre"), shrunk,
                                     grid_size=_GRID)
    interiors = shapely.simplify(interiors, 0.0)  # drop the collinear vertices of T-junctions
    rooms = []
    for face, polygon, interior in zip(dcel.faces, polygons, interiors):
        if not isinstance(interior, Polygon) or interior.is_empty:
            raise PartitionError(
                f"room {face.id} ({polygon.area:.2f} m²) has no connected free floor inside "
                f"walls {t:.2f} m thick")
        rooms.append(Room(face.id, polygon, orient(interior),
                          circulation=face.id in circulation))

    walls_with_windows, windows = place_windows(tuple(walls), settings)
    return FloorPlan(index=index, elevation=elevation, height=height, footprint=footprint,
                     settings=settings, rooms=tuple(rooms), walls=walls_with_windows,
                     dcel=dcel, windows=windows)
