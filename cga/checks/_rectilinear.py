"""Band shadows of rectilinear solids (walls, slabs, stairs), many at once, without
manifold3d.

The occupancy grid needs, for each structure node, the plan shadow of the part of its
solid between two heights ``y0`` and ``y1``. manifold3d gets it exactly (trim by two
planes, project), at about 0.3 ms a node. A building's structure is rectilinear: every
face lies in a plane ``x``, ``y`` or ``z`` = constant. The planes through such a
solid's vertex ``x`` and ``z`` coordinates then cut the plan into cells each wholly in
or out of the shadow, and the vertical line through a cell meets the band exactly
when it is inside the solid just above ``y0`` or enters the solid (through a face
looking down) above ``y0`` and below ``y1``. Along that line the faces looking down
count +1 and those looking up −1: their sum at or below ``y0`` is 1 inside the solid,
0 outside. Which faces lie above a cell is read at one point of the cell (as
:mod:`cga.checks._boxes` reads its cells along x), for all the solids' cells at once.

The shadow is the union of its cells, whose corners are the solid's vertex coordinates
at float32 precision, as manifold3d stores them: the region manifold3d's projection
gives, to the bit, so the occupancy grid marks the same cells (which depend on the
region only, not on how its outline is written down).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import shapely
from shapely.geometry import Polygon
from shapely.geometry.base import BaseGeometry

from cga.mesh import MeshLike

from ._boxes import MIN_SPACING, PROBE

__all__ = ["rectilinear_shadows", "union_by_owner"]

_RELATIVE_SPACING = 1e-5
"""Grid planes (and band planes) closer than this fraction of the solid's largest
coordinate are also left to manifold3d: its tolerance, float32's epsilon times that
coordinate (about 1.6e-6 m in a 14 m building), collapses features thinner than that,
which counting faces would keep."""


def rectilinear_shadows(meshes: Sequence[MeshLike], y0: float,
                        y1: float) -> list[BaseGeometry | None]:
    """The plan ``(x, z)`` shadow of the part of each mesh between heights ``y0`` and
    ``y1``, or ``None`` for a mesh that is not a watertight, consistently oriented
    solid with every face in an axis plane, or that has two of its planes, or one and a
    band plane, closer than :data:`~cga.checks._boxes.MIN_SPACING` (the caller then
    uses manifold3d)."""
    solids = _Solids(meshes)
    y = solids.vertices[:, 1]
    gap = solids.gap[solids.vertex_owner]
    near = (np.abs(y - y0) < gap) | (np.abs(y - y1) < gap)
    solids.ok &= np.bincount(solids.vertex_owner[near], minlength=len(meshes)) == 0
    out: list[BaseGeometry | None] = [None] * len(meshes)
    cells = _Cells(solids)
    inside, valid = cells.shadow(solids, y0, y1)
    boxes, owner = cells.runs(inside)
    shadows = union_by_owner(boxes, owner, len(meshes))
    for k in np.flatnonzero(valid).tolist():
        out[k] = shadows[k] if not shadows[k].is_empty else Polygon()
    return out


def union_by_owner(items: np.ndarray, owner: np.ndarray, count: int) -> np.ndarray:
    """The union of each owner's ``items`` (grouped by owner, in order), for owners
    ``0 … count − 1`` in one vectorised call: a table with a row per owner, padded with
    None (which the union ignores); an owner without items gets an empty collection."""
    column = np.arange(len(owner)) - np.searchsorted(owner, owner)
    table = np.full((count, int(column.max(initial=-1)) + 1), None, dtype=object)
    table[owner, column] = items
    return shapely.union_all(table, axis=1) if count else np.zeros(0, dtype=object)


class _Solids:
    """The meshes' triangles at float32 precision, concatenated, and which meshes are
    rectilinear solids (:attr:`ok`)."""

    def __init__(self, meshes: Sequence[MeshLike]):
        vertices = [np.asarray(m.vertices, dtype=np.float32).astype(float) for m in meshes]
        faces = [np.asarray(m.faces, dtype=np.int64).reshape(-1, 3) for m in meshes]
        count = len(meshes)
        sizes = np.array([len(v) for v in vertices], dtype=np.int64)
        offsets = np.concatenate([[0], np.cumsum(sizes)[:-1]])
        self.vertices = np.concatenate(vertices) if count else np.zeros((0, 3))
        self.vertex_owner = np.repeat(np.arange(count), sizes)
        faces_all = (np.concatenate([f + o for f, o in zip(faces, offsets)])
                     if count else np.zeros((0, 3), dtype=np.int64))
        self.owner = np.repeat(np.arange(count), [len(f) for f in faces])
        self.triangles = self.vertices[faces_all]
        t = self.triangles
        spans = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
        solid = np.any(spans != 0, axis=1)  # a collinear triangle bounds nothing
        self.flat = (t[:, 0] == t[:, 1]) & (t[:, 0] == t[:, 2])
        off_axes = solid & (self.flat.sum(axis=1) != 1)
        self.horizontal = solid & self.flat[:, 1]
        scale = np.zeros(count)
        np.maximum.at(scale, self.vertex_owner, np.abs(self.vertices).max(axis=1, initial=0.0))
        self.gap = np.maximum(MIN_SPACING, _RELATIVE_SPACING * scale)
        """Per mesh, how close two grid planes may come for this module to answer."""
        spaced = np.ones(count, dtype=bool)
        for axis in range(3):
            lines, _, _ = _lines(self.vertices[:, axis], self.vertex_owner, count)
            spaced &= _closest(*lines, count) >= self.gap
        self.ok = ((np.bincount(self.owner[off_axes], minlength=count) == 0)
                   & _closed(faces_all, self.owner, count) & spaced
                   & (np.array([len(f) for f in faces]) > 0))


def _closed(faces: np.ndarray, owner: np.ndarray, count: int) -> np.ndarray:
    """Per mesh, whether every edge is shared by exactly two of its triangles, once in
    each direction (a watertight solid manifold3d accepts)."""
    edges = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    edge_owner = np.repeat(owner, 3)
    keys = np.minimum(edges[:, 0], edges[:, 1]) * (int(faces.max(initial=0)) + 1) + np.maximum(
        edges[:, 0], edges[:, 1])
    _, index, counts = np.unique(keys, return_inverse=True, return_counts=True)
    turns = np.bincount(index, weights=np.where(edges[:, 0] < edges[:, 1], 1, -1))
    bad = (counts[index] != 2) | (turns[index] != 0)
    return np.bincount(edge_owner[bad], minlength=count) == 0


class _Cells:
    """Each solid's plan cells (between its consecutive vertex ``x`` and ``z``), row by
    row along z, each row along x, for the solids that are rectilinear."""

    def __init__(self, solids: _Solids):
        count = len(solids.ok)
        keep = solids.ok[solids.vertex_owner]
        (self.xs, _), self.x_start, nx = _lines(solids.vertices[keep, 0],
                                                solids.vertex_owner[keep], count)
        (self.zs, _), self.z_start, nz = _lines(solids.vertices[keep, 2],
                                                solids.vertex_owner[keep], count)
        self.nx, self.nz = np.maximum(nx - 1, 0), np.maximum(nz - 1, 0)
        sizes = self.nx * self.nz
        self.start = np.concatenate([[0], np.cumsum(sizes)])
        self.owner = np.repeat(np.arange(count), sizes)
        local = np.arange(int(self.start[-1])) - self.start[self.owner]
        self.i = local % np.maximum(self.nx[self.owner], 1)
        self.k = local // np.maximum(self.nx[self.owner], 1)
        x0 = self.xs[self.x_start[self.owner] + self.i]
        x1 = self.xs[self.x_start[self.owner] + self.i + 1]
        z0 = self.zs[self.z_start[self.owner] + self.k]
        z1 = self.zs[self.z_start[self.owner] + self.k + 1]
        self.corners = (x0, z0, x1, z1)
        self.probe = np.stack([x0 + PROBE[0] * (x1 - x0), z0 + PROBE[1] * (z1 - z0)], axis=-1)

    def shadow(self, solids: _Solids, y0: float, y1: float) -> tuple[np.ndarray, np.ndarray]:
        """Which cells are in the band's shadow, and per solid whether its faces gave a
        consistent count (0 or 1 inside at every height: else manifold3d decides)."""
        count = len(solids.ok)
        faces = np.flatnonzero(solids.horizontal & solids.ok[solids.owner])
        face_owner = solids.owner[faces]
        per_solid = np.bincount(face_owner, minlength=count)
        face_start = np.concatenate([[0], np.cumsum(per_solid)[:-1]])
        cells = self.start[1:] - self.start[:-1]
        pairs = per_solid * cells
        pair_owner = np.repeat(np.arange(count), pairs)
        local = np.arange(int(pairs.sum())) - np.repeat(np.cumsum(pairs) - pairs, pairs)
        face = faces[face_start[pair_owner] + local // np.maximum(cells[pair_owner], 1)]
        cell = self.start[pair_owner] + local % np.maximum(cells[pair_owner], 1)
        corners = solids.triangles[face][:, :, [0, 2]]
        over = _covers(corners, self.probe[cell])
        a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
        down = _cross(b - a, c - a) > 0  # normal −y: the (x, z) turn is clockwise seen from +y
        height = solids.triangles[face, 0, 1]
        step = np.where(down, 1.0, -1.0) * over
        size = int(self.start[-1])
        below = np.bincount(cell, weights=step * (height <= y0), minlength=size)
        total = np.bincount(cell, weights=step, minlength=size)
        enters = _entered(cell, height, step, over & (height > y0) & (height < y1), size)
        wrong = ((below != 0) & (below != 1)) | (total != 0)
        valid = solids.ok & (np.bincount(self.owner[wrong], minlength=count) == 0)
        return (below == 1) | enters, valid

    def runs(self, inside: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The shadow's cells merged into runs along x, as boxes, with their solids."""
        before = np.concatenate([[False], inside[:-1]]) & (self.i > 0)
        after = np.concatenate([inside[1:], [False]]) & (self.i < self.nx[self.owner] - 1)
        first = np.flatnonzero(inside & ~before)
        last = np.flatnonzero(inside & ~after)
        x0, z0, x1, z1 = self.corners
        return shapely.box(x0[first], z0[first], x1[last], z1[last]), self.owner[first]


def _entered(cell: np.ndarray, height: np.ndarray, step: np.ndarray, in_band: np.ndarray,
             size: int) -> np.ndarray:
    """Per cell, whether the line through it enters the solid inside the band: at some
    height there more faces above the cell look down than up. A face looking down with
    one looking up at its very height (a sheet of no thickness, which a boolean of
    manifold3d can leave behind) enters nothing, as manifold3d's trim finds."""
    entered = np.zeros(size, dtype=bool)
    if in_band.any():
        places, at = np.unique(np.column_stack([cell[in_band], height[in_band]]), axis=0,
                               return_inverse=True)
        net = np.bincount(at.ravel(), weights=step[in_band], minlength=len(places))
        entered[places[net > 0, 0].astype(np.int64)] = True
    return entered


def _lines(values: np.ndarray, owner: np.ndarray,
           count: int) -> tuple[tuple[np.ndarray, np.ndarray], np.ndarray, np.ndarray]:
    """Each owner's distinct values, sorted: ``((values, their owners), start of each
    owner's, how many)``."""
    order = np.lexsort((values, owner))
    values, owner = values[order], owner[order]
    new = np.ones(len(values), dtype=bool)
    new[1:] = (owner[1:] != owner[:-1]) | (values[1:] != values[:-1])
    values, owner = values[new], owner[new]
    sizes = np.bincount(owner, minlength=count)
    return (values, owner), np.concatenate([[0], np.cumsum(sizes)[:-1]]), sizes


def _closest(values: np.ndarray, owner: np.ndarray, count: int) -> np.ndarray:
    """Per owner, the least gap between two of its sorted distinct values (inf for one)."""
    same = owner[1:] == owner[:-1]
    least = np.full(count, np.inf)
    np.minimum.at(least, owner[1:][same], np.diff(values)[same])
    return least


def _covers(corners: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Whether each triangle (``float[m, 3, 2]``) holds its point strictly inside."""
    sides = [_cross(corners[:, (j + 1) % 3] - corners[:, j], points - corners[:, j])
             for j in range(3)]
    return (((sides[0] > 0) & (sides[1] > 0) & (sides[2] > 0))
            | ((sides[0] < 0) & (sides[1] < 0) & (sides[2] < 0)))


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
