"""The cells of many polygons at once, as Pillow's polygon fill draws them.

An occupancy grid marks the cells of a shadow by snapping the polygon's vertices to
their cells and filling it with Pillow (``ImageDraw.polygon``, fill and outline both
set). Drawing every polygon into an image of its own costs about 0.1 ms of Python and
Pillow per polygon, and a floor has hundreds. Most polygons are rectilinear once
snapped (walls, slabs, boxes seen from above, rooms); for those :func:`polygon_patches`
applies Pillow's scan-line rule itself, to all of them in one numpy pass, and gets the
very cells Pillow draws. Polygons with a slanted edge or a hole are still drawn with
Pillow.

Pillow's rule on a rectilinear polygon (``polygon_generic`` in ``libImaging/Draw.c``):
each row ``y`` of the image collects the column ``x`` of every vertical edge spanning it
(twice when the edge ends on that row, unless it is the polygon's last row), sorts them
and fills each pair ``[x₂ᵢ, x₂ᵢ₊₁]`` inclusively; every horizontal edge is drawn as a
line. A cell is thus filled when an odd number of the collected columns lies left of it,
or when it is one of them, or when a horizontal edge covers it. Each row collects an even
number of columns (a closed ring crosses a row an even number of times), so the count
left of a cell can run on from row to row and polygon to polygon: its parity restarts
at each row.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import shapely
from PIL import Image, ImageDraw
from shapely.geometry import Polygon
from shapely.geometry.base import BaseGeometry

__all__ = ["Patch", "polygon_patches", "polygons_of"]

Patch = tuple[int, int, int, int, np.ndarray]
"""``(r0, r1, c0, c1, cells)``: the cells ``[r0:r1, c0:c1]`` of a grid a shape covers."""


def polygons_of(geometry: BaseGeometry) -> list[Polygon]:
    """The polygons of any (multi)polygon or collection; other geometry types are skipped."""
    if geometry.is_empty:
        return []
    if isinstance(geometry, Polygon):
        return [geometry]
    return [g for part in getattr(geometry, "geoms", ()) for g in polygons_of(part)]


def polygon_patches(shape: tuple[int, ...], geometries: Sequence[BaseGeometry], x_min: float,
                    z_min: float, resolution: float) -> list[list[Patch]]:
    """For each geometry (plan x, z), the cells of a grid of ``shape`` (top edge at
    ``z_min``, left edge at ``x_min``) that it covers or crosses: one patch per polygon,
    its bounding box of cells, in the polygons' order."""
    each = [polygons_of(g) for g in geometries]
    polygons = [p for group in each for p in group]
    owner = np.repeat(np.arange(len(geometries)), [len(group) for group in each]).tolist()
    out: list[list[Patch]] = [[] for _ in geometries]
    if not polygons:
        return out
    rings = _Rings(np.array(polygons, dtype=object), shape, x_min, z_min, resolution)
    cells = dict(zip(rings.fast.tolist(), _scanline_cells(rings)))
    for k in np.flatnonzero(rings.drawn).tolist():
        patch = cells.get(k)
        if patch is None:
            patch = _pillow_cells(polygons[k], rings, k, x_min, z_min, resolution)
        out[owner[k]].append((*rings.box(k), patch))
    return out


class _Rings:
    """The exterior rings of polygons snapped to cells (absolute row ``v`` and column
    ``u`` of each vertex), each polygon's box of cells, clipped to the grid, and which
    polygons the scan-line pass fills (:attr:`fast`) or Pillow draws."""

    def __init__(self, polygons: np.ndarray, shape: tuple[int, ...], x_min: float, z_min: float,
                 resolution: float):
        xy, ring = shapely.get_coordinates(shapely.get_exterior_ring(polygons), return_index=True)
        # the operations of Pillow's caller, vertex by vertex: the same cells
        self.u = np.floor((xy[:, 0] - x_min) / resolution).astype(np.int64)
        self.v = np.floor((xy[:, 1] - z_min) / resolution).astype(np.int64)
        self.ring = ring
        starts = np.searchsorted(ring, np.arange(len(polygons)))
        rows, cols = shape[0], shape[1]
        self.c0 = np.maximum(np.minimum.reduceat(self.u, starts), 0)
        self.r0 = np.maximum(np.minimum.reduceat(self.v, starts), 0)
        self.c1 = np.minimum(np.maximum.reduceat(self.u, starts) + 1, cols)
        self.v_max = np.maximum.reduceat(self.v, starts)
        self.r1 = np.minimum(self.v_max + 1, rows)
        self.drawn = (self.c0 < self.c1) & (self.r0 < self.r1)
        edge = ring[:-1] == ring[1:]  # vertex i to i + 1 is an edge of one ring
        slanted = edge & (np.diff(self.u) != 0) & (np.diff(self.v) != 0)
        holed = shapely.get_num_interior_rings(polygons) > 0
        bent = np.bincount(ring[:-1][slanted], minlength=len(polygons)) > 0
        self.fast = np.flatnonzero(self.drawn & ~holed & ~bent)
        self.edge = edge

    def box(self, k: int) -> tuple[int, int, int, int]:
        """``(r0, r1, c0, c1)``: polygon ``k``'s box of cells."""
        return int(self.r0[k]), int(self.r1[k]), int(self.c0[k]), int(self.c1[k])


def _scanline_cells(rings: _Rings) -> list[np.ndarray]:
    """The cells of the polygons ``rings.fast`` (rectilinear once snapped, no hole), by
    Pillow's scan-line rule (module docstring), all in one flat buffer: each polygon's
    box row by row, each row with one column before the box (for the columns left of
    it) and one after (for those right of it, and the ends of horizontal edges)."""
    fast = rings.fast
    if not len(fast):
        return []
    r0, r1, c0, c1 = rings.r0[fast], rings.r1[fast], rings.c0[fast], rings.c1[fast]
    height, width = r1 - r0, c1 - c0
    stride = width + 2
    start = np.concatenate([[0], np.cumsum(height * stride)])
    slot = np.full(len(rings.drawn), -1)
    slot[fast] = np.arange(len(fast))
    i = np.flatnonzero(rings.edge & (slot[rings.ring[:-1]] >= 0))
    p = slot[rings.ring[i]]  # the polygon of each edge, by its slot in ``fast``
    u0, u1, v0, v1 = rings.u[i], rings.u[i + 1], rings.v[i], rings.v[i + 1]

    def at(q: np.ndarray, row: np.ndarray, col: np.ndarray) -> np.ndarray:
        """Index in the buffer of polygon ``q``'s cell (row, col), col 0 the one before."""
        return start[q] + (row - r0[q]) * stride[q] + col

    # vertical edges: their column on every row they span, twice on their last row
    vertical = np.flatnonzero(v0 != v1)
    q = p[vertical]
    top, bottom = np.minimum(v0, v1)[vertical], np.maximum(v0, v1)[vertical]
    first, last = np.maximum(top, r0[q]), np.minimum(bottom, r1[q] - 1)
    spans = np.maximum(last - first + 1, 0)
    q, bottom, column = (np.repeat(a, spans) for a in (q, bottom, u0[vertical]))
    row = np.repeat(first - np.cumsum(spans) + spans, spans) + np.arange(int(spans.sum()))
    twice = (row == bottom) & (bottom < rings.v_max[fast][q])
    crossings = np.bincount(at(q, row, np.clip(column - c0[q] + 1, 0, width[q] + 1)),
                            weights=1 + twice, minlength=int(start[-1])).astype(np.int64)
    # horizontal edges (and repeated vertices): lines, clipped to the box
    flat = np.flatnonzero(v0 == v1)
    q, row = p[flat], v0[flat]
    lo, hi = np.minimum(u0, u1)[flat], np.maximum(u0, u1)[flat]
    inside = (row >= r0[q]) & (row < r1[q]) & (hi >= c0[q]) & (lo < c1[q])
    q, row, lo, hi = q[inside], row[inside], lo[inside], hi[inside]
    ends = np.concatenate([at(q, row, np.maximum(lo, c0[q]) - c0[q] + 1),
                           at(q, row, np.minimum(hi, c1[q] - 1) - c0[q] + 2)])
    steps = np.repeat([1.0, -1.0], len(q))
    lines = np.cumsum(np.bincount(ends, weights=steps, minlength=int(start[-1]))) > 0
    left = np.cumsum(crossings) - crossings
    filled = (left % 2 == 1) | (crossings > 0) | lines
    return [filled[start[k]:start[k + 1]].reshape(height[k], stride[k])[:, 1:-1]
            for k in range(len(fast))]


def _pillow_cells(polygon: Polygon, rings: _Rings, k: int, x_min: float, z_min: float,
                  resolution: float) -> np.ndarray:
    """Polygon ``k``'s cells drawn with Pillow in an image the size of its box: the
    exterior filled, each hole cleared and its outline drawn."""
    r0, r1, c0, c1 = rings.box(k)
    image = Image.new("1", (c1 - c0, r1 - r0), 0)
    draw = ImageDraw.Draw(image)
    exterior = rings.ring == k
    draw.polygon(list(zip((rings.u[exterior] - c0).tolist(), (rings.v[exterior] - r0).tolist())),
                 fill=1, outline=1)
    for interior in polygon.interiors:
        xy = np.asarray(interior.coords, dtype=float)[:, :2]
        u = np.floor((xy[:, 0] - x_min) / resolution).astype(int) - c0
        v = np.floor((xy[:, 1] - z_min) / resolution).astype(int) - r0
        draw.polygon(list(zip(u.tolist(), v.tolist())), fill=0, outline=1)
    return np.asarray(image, dtype=bool)

