"""Tile a footprint with fixed faces and the free pieces around them (docs/architecture.md).

Corridors, entry halls and stair cores are placed before the BSP partitions a floor:
they are *fixed faces* of the half-edge structure that no cut may cross. The rest of the
footprint is the free region the BSP cuts into rooms. A DCEL face has one boundary
cycle, so a free region with a hole (a core standing inside the floor) or several parts
(a corridor running wall to wall) is cut into simple pieces first: a hole is opened by
the line across the middle of the hole, running along the footprint's longer side.

:func:`tile_with_fixed_faces` returns the rings for :meth:`.dcel.DCEL.from_polygons`:
fixed faces first (face ``i`` is ``fixed[i]``), then the free pieces, every ring
counter-clockwise with every other ring's corners that lie on its sides inserted (so
shared walls have the same vertices on both sides: T-junctions are vertices).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence

import shapely
from shapely.geometry import LineString, MultiPolygon, Polygon
from shapely.geometry.polygon import orient
from shapely.ops import split

from .dcel import EPS
from .errors import PartitionError

__all__ = ["tile_with_fixed_faces"]

Point = tuple[float, float]
_MAX_PIECES = 256
"""Bound on free pieces; a plan needs a handful, so more means a malformed input."""


def tile_with_fixed_faces(footprint: Sequence[Point],
                          fixed: Sequence[Sequence[Point]]) -> tuple[list[list[Point]], int]:
    """Rings tiling ``footprint``: the ``fixed`` polygons, then the free pieces.

    Parameters
    ----------
    footprint
        Counter-clockwise simple polygon ``(x, z)``.
    fixed
        Polygons (any orientation) inside the footprint, not overlapping each other.

    Returns
    -------
    (rings, free_count)
        The rings for :meth:`~.dcel.DCEL.from_polygons`, fixed ones first, and how many
        free pieces follow them.

    Raises
    ------
    PartitionError
        A fixed polygon is invalid, leaves the footprint or overlaps another one.

    Notes
    -----
    O(V²) in the total number of vertices (T-junction insertion); plans have dozens.
    Cached: every floor of a building, and every re-draw, asks for the same tiling.
    """
    rings, free = _tile(tuple(map(tuple, footprint)), tuple(tuple(map(tuple, f)) for f in fixed))
    return [list(r) for r in rings], free


@functools.lru_cache(maxsize=64)
def _tile(footprint: tuple[Point, ...],
          fixed: tuple[tuple[Point, ...], ...]) -> tuple[tuple[tuple[Point, ...], ...], int]:
    """:func:`tile_with_fixed_faces` on hashable arguments, cached."""
    outline = Polygon(footprint)
    shapes: list[Polygon] = []
    for i, ring in enumerate(fixed):
        polygon = Polygon(ring)
        if len(ring) < 3 or not polygon.is_valid or polygon.area <= EPS:
            raise PartitionError(f"fixed face {i} is not a simple polygon with an area")
        if polygon.difference(outline).area > 1e-9:
            raise PartitionError(f"fixed face {i} reaches outside the footprint")
        for j, other in enumerate(shapes):
            if polygon.intersection(other).area > 1e-9:
                raise PartitionError(f"fixed faces {j} and {i} overlap")
        shapes.append(orient(polygon, sign=1.0))
    free = outline.difference(shapely.union_all(shapes)) if shapes else outline
    pieces = _simple_pieces(free, outline)
    rings = [_ring(p) for p in shapes] + [_ring(p) for p in pieces]
    corners = sorted({p for ring in rings for p in ring})
    return tuple(tuple(_with_junctions(ring, corners)) for ring in rings), len(pieces)


def _simple_pieces(region: Polygon | MultiPolygon | shapely.Geometry,
                   outline: Polygon) -> list[Polygon]:
    """The region as polygons without holes, largest first (ties by position)."""
    todo = [g for g in getattr(region, "geoms", [region])
            if isinstance(g, Polygon) and g.area > 1e-9]
    done: list[Polygon] = []
    while todo:
        piece = todo.pop()
        if not piece.interiors:
            done.append(shapely.simplify(piece, 0.0))
            if len(done) > _MAX_PIECES:
                raise PartitionError("the fixed faces cut the floor into too many pieces")
            continue
        minx, minz, maxx, maxz = outline.bounds
        hx0, hz0, hx1, hz1 = Polygon(piece.interiors[0]).bounds
        if maxx - minx >= maxz - minz:  # cut across the hole, along the longer side
            line = LineString([((hx0 + hx1) / 2, minz - 1), ((hx0 + hx1) / 2, maxz + 1)])
        else:
            line = LineString([(minx - 1, (hz0 + hz1) / 2), (maxx + 1, (hz0 + hz1) / 2)])
        todo.extend(g for g in split(piece, line).geoms if g.area > 1e-9)
    return sorted(done, key=lambda p: (-round(p.area, 6), p.bounds))


def _ring(polygon: Polygon) -> list[Point]:
    coords = list(orient(polygon, sign=1.0).exterior.coords)[:-1]
    return [(float(x), float(z)) for x, z in coords]


def _with_junctions(ring: list[Point], corners: list[Point]) -> list[Point]:
    """The ring with every corner that lies strictly inside one of its sides inserted."""
    out: list[Point] = []
    n = len(ring)
    for i in range(n):
        a, b = ring[i], ring[(i + 1) % n]
        out.append(a)
        dx, dz = b[0] - a[0], b[1] - a[1]
        length = math.hypot(dx, dz)
        inside = []
        for c in corners:
            along = ((c[0] - a[0]) * dx + (c[1] - a[1]) * dz) / length
            off = abs((c[0] - a[0]) * dz - (c[1] - a[1]) * dx) / length
            if off <= EPS and EPS < along < length - EPS:
                inside.append((along, c))
        out.extend(c for _, c in sorted(inside))
    return out
