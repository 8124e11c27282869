"""Turn a partitioned DCEL into a :class:`cga.model.FloorPlan`.

Both ways of making a floor end here: the BSP of ``make_floor`` and the rectangle tilings
rule authors write in tests (:mod:`.rectangles`). One face becomes one room, one edge one
wall (its id is the DCEL edge number), and outer walls get their windows.
"""

from __future__ import annotations

import math
from collections.abc import Collection

import numpy as np
import shapely
from shapely.geometry import Polygon
from shapely.geometry.polygon import orient

from cga.model import FloorPlan, FloorSettings, Room, Wall

from .dcel import DCEL
from .errors import PartitionError
from .openings import place_windows

__all__ = ["box_interiors", "plan_from_dcel"]

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
    offsets = shapely.buffer(polygons, -t / 2, join_style="mitre")
    interiors = box_interiors(offsets, shrunk)
    overlay = [i for i, interior in enumerate(interiors) if interior is None]
    if overlay:  # the general case: a 1 µm-grid overlay
        cut = shapely.intersection(offsets[overlay], shrunk, grid_size=_GRID)
        for i, interior in zip(overlay, shapely.simplify(cut, 0.0)):  # drop T-junction vertices
            interiors[i] = orient(interior) if isinstance(interior, Polygon) else interior
    rooms = []
    for face, polygon, interior in zip(dcel.faces, polygons, interiors):
        if not isinstance(interior, Polygon) or interior.is_empty:
            raise PartitionError(
                f"room {face.id} ({polygon.area:.2f} m²) has no connected free floor inside "
                f"walls {t:.2f} m thick")
        rooms.append(Room(face.id, polygon, interior,
                          circulation=face.id in circulation))

    walls_with_windows, windows = place_windows(tuple(walls), settings)
    return FloorPlan(index=index, elevation=elevation, height=height, footprint=footprint,
                     settings=settings, rooms=tuple(rooms), walls=walls_with_windows,
                     dcel=dcel, windows=windows)


def box_interiors(offsets: np.ndarray, shrunk: Polygon) -> list[Polygon | None]:
    """``offset ∩ shrunk`` on the 1 µm grid, counter-clockwise, for every offset where both
    are axis-aligned rectangles (the rooms of a rectangular storey); None for the others.

    The same polygons, coordinates and first vertex included, as GEOS' overlay
    (``shapely.intersection(offset, shrunk, grid_size=1e-6)``, then ``orient``), at a
    fraction of the cost: the overlay's ring follows ``offset``'s direction and starts
    at the far end of the first piece of ``offset``'s boundary that it keeps. Edges
    on each other or nearly (never in a partition: a room would be half a wall wide)
    are left to the overlay, as are empty results (a room narrower than its walls).
    """
    out: list[Polygon | None] = [None] * len(offsets)
    b = _box_corners(shapely.get_coordinates(shrunk).tolist()) \
        if _plain(np.array([shrunk]))[0] else None
    if b is None:
        return out
    plain = _plain(offsets)
    coords = shapely.get_coordinates(offsets[plain]).tolist()
    rings, where = [], []
    for k, i in enumerate(np.flatnonzero(plain).tolist()):
        a = _box_corners(coords[5 * k:5 * k + 4])
        found = _box_ring(a, b) if a is not None else None
        if found is not None:
            rings.append(found)
            where.append(i)
    for i, polygon in zip(where, shapely.polygons(np.array(rings).reshape(-1, 4, 2))):
        out[i] = polygon
    return out


def _plain(polygons: np.ndarray) -> np.ndarray:
    """Which geometries are polygons of four corners without holes."""
    return ((shapely.get_type_id(polygons) == 3) & (shapely.get_num_interior_rings(polygons) == 0)
            & (shapely.get_num_coordinates(polygons) == 5))


def _box_ring(a: tuple[list[tuple[float, float]], tuple[float, float, float, float]],
              b: tuple[list[tuple[float, float]], tuple[float, float, float, float]],
              ) -> list[tuple[float, float]] | None:
    """The overlay's ring of rectangles ``a`` (the offset) and ``b`` (corners and bounds
    from :func:`_box_corners`), or None when it is left to the overlay."""
    (ax0, az0, ax1, az1), (bx0, bz0, bx1, bz1) = a[1], b[1]
    if any(abs(u - v) < _NEAR for u in (ax0, ax1) for v in (bx0, bx1)) or \
            any(abs(u - v) < _NEAR for u in (az0, az1) for v in (bz0, bz1)):
        return None  # edges that the grid makes one
    x0, z0, x1, z1 = max(ax0, bx0), max(az0, bz0), min(ax1, bx1), min(az1, bz1)
    if not (x0 < x1 and z0 < z1):
        return None
    corners = a[0]
    start = None
    for (px, pz), (qx, qz) in zip(corners, corners[1:] + corners[:1]):
        if abs(pz - qz) < _NEAR and bz0 < pz < bz1:  # along x, inside the band kept
            start = (min(qx, x1) if qx > px else max(qx, x0), pz)
        elif abs(px - qx) < _NEAR and bx0 < px < bx1:
            start = (px, min(qz, z1) if qz > pz else max(qz, z0))
        if start is not None:
            break
    if start is None:
        return None
    x0, z0, x1, z1 = map(_snap, (x0, z0, x1, z1))
    ring = [(x0, z0), (x1, z0), (x1, z1), (x0, z1)]
    first = ring.index((_snap(start[0]), _snap(start[1])))
    return ring[first:] + ring[:first]


def _box_corners(coords: list[list[float]]) -> tuple[list[tuple[float, float]],
                                                     tuple[float, float, float, float]] | None:
    """The corners in ring order and the bounds of a ring of four points (without the
    closing one) that is an axis-aligned rectangle (up to the rounding of an offset:
    :data:`_ROUNDING`), else None."""
    corners = [(x, z) for x, z in coords[:4]]
    xs, zs = [x for x, _ in corners], [z for _, z in corners]
    x0, z0, x1, z1 = min(xs), min(zs), max(xs), max(zs)
    ends = [(abs(x - x0) <= _ROUNDING) + 2 * (abs(x - x1) <= _ROUNDING)
            + 4 * (abs(z - z0) <= _ROUNDING) + 8 * (abs(z - z1) <= _ROUNDING) for x, z in corners]
    if sorted(ends) != [5, 6, 9, 10]:  # one corner at each end of each axis
        return None
    return corners, (x0, z0, x1, z1)


_SCALE = round(1 / _GRID)
_NEAR = 10 * _GRID
"""Edges of the two rectangles closer than this are left to the overlay."""
_ROUNDING = 1e-9
"""Coordinates this close count as one (an offset's corners are off by about 1e-16 m)."""


def _snap(value: float) -> float:
    """``value`` on the 1 µm grid as GEOS' fixed precision model rounds it (halves up)."""
    return math.floor(value * _SCALE + 0.5) / _SCALE
