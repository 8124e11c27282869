"""Rectilinear solids cut into boxes on their coordinate grid, without mesh booleans.

A building's walls and slabs are rectilinear: every face lies in a plane ``x``, ``y``
or ``z`` = constant. The planes through such a solid's vertex coordinates cut space
into a grid of cells each wholly inside or outside the solid, so the solid *is* a set
of cells: which ones is read off by casting, along x, through the solid's x-facing
faces (the inside/outside parity of each row of cells). Cutting the solid by a grid
plane then only splits a boolean array.

:func:`box_pieces` cuts as :func:`cga.checks._solids.convex_pieces` does with
manifold3d plane splits (the same planes in the same order, the same convexity test),
so on clean input it makes the same pieces in the same order (it does for every
structure node of the demo buildings), in about two thirds of the time: a piece's convexity is
settled by whether it fills its bounding box, or, when it does not, by an empty cell
between two of its cells in a row (which the hull must hold), and only else by a hull.
A solid it cannot read as cells (a face off the axes, two coordinates closer than
:data:`_MIN_SPACING`) gives ``None`` and the caller cuts it with manifold3d. The robot
exports keep cutting with manifold3d (:func:`cga.collision.structure_pieces`): on
clean input the same boxes, and their files stay byte for byte what they were. Where a manifold3d
split leaves a zero-thickness flap on a piece (a face of the solid lying in the cutting
plane), ``convex_pieces`` finds that piece not convex and cuts it once more; cells have
no flaps, so here the pieces may be fewer, and just as exact.
"""

from __future__ import annotations

from collections.abc import Sequence

import manifold3d
import numpy as np

from cga import scene
from cga.mesh import MeshLike, is_watertight

from ._solids import _CONVEX_TOLERANCE, cut_pieces

__all__ = ["box_pieces"]

_MIN_SPACING = 2e-3
"""m: grid planes closer than this are left to manifold3d. Every cell is then larger
than the slivers manifold3d drops (``_MIN_VOLUME``, 1e-9 m³), so no piece is dropped."""

_PROBE = (0.3183098862, 0.2718281828)
"""Where in each cell (fractions of its y and z extent) the parity ray runs: off the
diagonals along which faces are triangulated."""

_BOX_FACES = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                       [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]])
"""Triangles of a box whose corners are numbered by bits (x, y, z) = (1, 2, 4),
counter-clockwise seen from outside."""


def box_pieces(mesh: MeshLike) -> Sequence[MeshLike] | None:
    """The pieces :func:`~cga.checks._solids.convex_pieces` cuts ``mesh`` into, computed on
    the solid's cell grid; ``None`` when ``mesh`` is not a watertight rectilinear solid
    this can read (the caller then uses ``convex_pieces``).

    Vertices are taken at float32 precision, as manifold3d stores them, so the grid
    planes are the ones ``convex_pieces`` cuts along. A solid that is one box is
    returned as the mesh itself; every other piece is a box of eight corners.
    """
    if len(mesh.faces) == 0:
        return None
    vertices = np.asarray(mesh.vertices, dtype=np.float32).astype(float)
    faces = np.asarray(mesh.faces, dtype=np.int64)
    triangles = vertices[faces]
    # a triangle whose corners are collinear bounds nothing (a T-junction's sliver)
    spans = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    triangles = triangles[np.any(spans != 0, axis=1)]
    flat = (triangles[:, 0] == triangles[:, 1]) & (triangles[:, 0] == triangles[:, 2])
    if not np.all(flat.sum(axis=1) == 1):
        return None
    grid = [np.unique(vertices[:, k]) for k in range(3)]
    if any(len(g) < 2 or float(np.diff(g).min()) < _MIN_SPACING for g in grid):
        return None
    if not is_watertight(faces):
        return None
    cells = _cells(triangles[flat[:, 0]], grid)
    if cells is None:
        return None
    sizes = np.meshgrid(*(np.diff(g) for g in grid), indexing="ij")
    volumes = sizes[0] * sizes[1] * sizes[2]
    whole = _Block(cells, grid, volumes)
    if whole.convex:
        return [mesh]
    planes = ((axis, index) for axis in (0, 2, 1) for index in range(1, len(grid[axis]) - 1))
    pieces = cut_pieces([whole], planes, _split)
    if pieces is None or not all(piece.convex for piece in pieces):
        return None
    return [piece.box() for piece in pieces]


def _split(piece: "_Block", axis: int, index: int) -> "list[_Block] | None":
    """The parts of ``piece`` on either side of grid plane ``index`` along ``axis``,
    when the plane passes through it and it is not convex."""
    # grid planes are _MIN_SPACING apart: strictly inside the piece's box (by more
    # than convex_pieces' 1e-9) is strictly between its end planes
    if not (piece.lo[axis] < index <= piece.hi[axis]) or piece.convex:
        return None
    upper = piece.cells.copy()
    np.moveaxis(upper, axis, 0)[:index] = False
    return [_Block(p, piece.grid, piece.volumes) for p in (upper, piece.cells & ~upper)
            if p.any()]


class _Block:
    """A piece being cut: its cells, the index range ``lo``…``hi`` it occupies along
    each axis, and (once asked) whether it passes ``convex_pieces``' convexity test."""

    __slots__ = ("cells", "grid", "volumes", "lo", "hi", "_convex")

    def __init__(self, cells: np.ndarray, grid: list[np.ndarray], volumes: np.ndarray):
        self.cells, self.grid, self.volumes = cells, grid, volumes
        plan = np.any(cells, axis=1)  # which (x, z) columns hold a cell
        spans = (np.flatnonzero(plan.any(axis=1)), np.flatnonzero(cells.any(axis=(0, 2))),
                 np.flatnonzero(plan.any(axis=0)))
        self.lo = tuple(int(s[0]) for s in spans)
        self.hi = tuple(int(s[-1]) for s in spans)
        self._convex: bool | None = None

    @property
    def convex(self) -> bool:
        """The piece's volume is within the tolerance of its hull's: it fills its
        bounding box, or the hull of its cells' corners is no larger."""
        if self._convex is None:
            box = self.cells[tuple(slice(lo, hi + 1) for lo, hi in zip(self.lo, self.hi))]
            self._convex = bool(box.all()) or (not self._has_gap(box) and self._hull_test())
        return self._convex

    def _has_gap(self, box: np.ndarray) -> bool:
        """Whether an empty cell lies between two of the piece's cells in one row: the
        hull then holds that whole cell, so the piece fails the convexity test (when the
        cell's volume is above the tolerance)."""
        volumes = self.volumes[tuple(slice(lo, hi + 1) for lo, hi in zip(self.lo, self.hi))]
        limit = _CONVEX_TOLERANCE * float(self.volumes.sum())
        for axis in range(3):
            before = np.logical_or.accumulate(box, axis=axis)
            after = np.flip(np.logical_or.accumulate(np.flip(box, axis), axis=axis), axis)
            gap = before & after & ~box
            if gap.any() and float(volumes[gap].max()) > limit:
                return True
        return False

    def _hull_test(self) -> bool:
        volume = float(self.volumes[self.cells].sum())
        index = np.argwhere(self.cells)
        corners = np.array([[self.grid[k][index[:, k] + ((bit >> k) & 1)] for k in range(3)]
                            for bit in range(8)]).transpose(0, 2, 1).reshape(-1, 3)
        hull = manifold3d.Manifold.hull_points(corners).volume()
        return hull > 0 and volume >= hull * (1.0 - _CONVEX_TOLERANCE)

    def box(self) -> scene.MeshArrays:
        """The piece, which fills its bounding box, as that box's corners and triangles."""
        ends = [(self.grid[k][self.lo[k]], self.grid[k][self.hi[k] + 1]) for k in range(3)]
        corners = np.array([[ends[k][(bit >> k) & 1] for k in range(3)] for bit in range(8)])
        return scene.MeshArrays(corners, _BOX_FACES.copy())


def _cells(x_faces: np.ndarray, grid: list[np.ndarray]) -> np.ndarray | None:
    """Which grid cells lie inside the solid, from its faces in planes x = constant
    (triangles, counter-clockwise seen from outside): along each row of cells, each
    face the row passes through enters the solid (outward normal −x) or leaves it."""
    xs, ys, zs = grid
    py = ys[:-1] + _PROBE[0] * np.diff(ys)
    pz = zs[:-1] + _PROBE[1] * np.diff(zs)
    points = np.stack(np.meshgrid(py, pz, indexing="ij"), axis=-1)[None]  # (1, ny, nz, 2)
    a, b, c = (x_faces[:, k, 1:][:, None, None, :] for k in range(3))
    sides = [_cross(q - p, points - p) for p, q in ((a, b), (b, c), (c, a))]
    inside = ((sides[0] > 0) & (sides[1] > 0) & (sides[2] > 0)) | (
        (sides[0] < 0) & (sides[1] < 0) & (sides[2] < 0))
    normal_x = _cross(x_faces[:, 1, 1:] - x_faces[:, 0, 1:], x_faces[:, 2, 1:] - x_faces[:, 0, 1:])
    step = np.zeros((len(xs), len(py), len(pz)))
    np.add.at(step, np.searchsorted(xs, x_faces[:, 0, 0]),
              -np.sign(normal_x)[:, None, None] * inside)
    count = np.cumsum(step, axis=0)
    if np.any(count[-1] != 0) or not np.all((count == 0) | (count == 1)):
        return None
    return count[:-1] == 1


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
