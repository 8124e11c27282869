"""Rectilinear solids cut into boxes on their coordinate grid, without mesh booleans.

A building's walls and slabs are rectilinear: every face lies in a plane ``x``, ``y``
or ``z`` = constant. The planes through such a solid's vertex coordinates cut space
into a grid of cells each wholly inside or outside the solid, so the solid *is* a set
of cells: which ones is read off by casting, along x, through the solid's x-facing
faces (the inside/outside parity of each row of cells). Cutting the solid by a grid
plane then only sorts its cells to either side: each row of cells along x is one Python
integer's bits, which the cut splits or passes whole to one side.

:func:`box_pieces` cuts as :func:`cga.checks._solids.convex_pieces` does with
manifold3d plane splits (the same planes in the same order, the same convexity test),
so on clean input it makes the same pieces in the same order (it does for every
structure node of the demo buildings), in half to three quarters of the time, most of
it spent reading the solid as cells: a piece's convexity is settled by whether it fills
its bounding box, or, when it does not, by an empty cell between two of its cells in a
row (which the hull must hold), and only else by a hull.
A solid it cannot read as cells (a face off the axes, two coordinates closer than
:data:`MIN_SPACING`) gives ``None`` and the caller cuts it with manifold3d. The robot
exports keep cutting with manifold3d (:func:`cga.collision.structure_pieces`): on
clean input the same boxes, and their files stay byte for byte what they were. Where a manifold3d
split leaves a zero-thickness flap on a piece (a face of the solid lying in the cutting
plane), ``convex_pieces`` finds that piece not convex and cuts it once more; cells have
no flaps, so here the pieces may be fewer, and just as exact.
"""

from __future__ import annotations

import functools
import operator
from collections.abc import Iterator, Sequence

import numpy as np

from cga import scene
from cga.manifold import manifold3d
from cga.mesh import MeshLike, is_watertight

from ._solids import _CONVEX_TOLERANCE, cut_pieces

__all__ = ["MIN_SPACING", "PROBE", "box_pieces"]

MIN_SPACING = 2e-3
"""m: grid planes closer than this are left to manifold3d. Every cell is then larger
than the slivers manifold3d drops (``_MIN_VOLUME``, 1e-9 m³), so no piece is dropped."""

PROBE = (0.3183098862, 0.2718281828)
"""Where in each cell (fractions of its y and z extent) the parity ray runs: off the
diagonals along which faces are triangulated. :mod:`cga.checks._rectilinear` reads its
cells at the same point and leaves the same close planes to manifold3d."""

_BOX_FACES = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                       [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]])
"""Triangles of a box whose corners are numbered by bits (x, y, z) = (1, 2, 4),
counter-clockwise seen from outside."""

_CORNERS = (np.arange(8)[:, None] >> np.arange(3)) & 1
"""Box corner by box corner (numbered as in :data:`_BOX_FACES`), whether it lies at the
upper end of x, y and z."""

_Rows = dict[tuple[int, int], int]
"""A piece's cells as rows along x: ``rows[j, k]`` has bit ``i`` set for each of its
cells ``(i, j, k)``; a row without a cell has no entry."""


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
    if any(len(g) < 2 or float(np.diff(g).min()) < MIN_SPACING for g in grid):
        return None
    if not is_watertight(faces):
        return None
    cells = _cells(triangles[flat[:, 0]], grid)
    if cells is None:
        return None
    # each row of cells along x as an integer: its bits as bytes, the lowest first
    packed = np.packbits(cells, axis=0, bitorder="little").transpose(1, 2, 0).tolist()
    rows: _Rows = {(j, k): int.from_bytes(bytes(row), "little")
                   for j, line in enumerate(packed) for k, row in enumerate(line) if any(row)}
    if not rows:  # nothing inside: not a solid this can read
        return None
    whole = _Block(_Grid(grid), rows)
    if whole.convex:
        return [mesh]
    planes = ((axis, index) for axis in (0, 2, 1) for index in range(1, len(grid[axis]) - 1))
    pieces = cut_pieces([whole], planes, _split)
    if pieces is None or not all(piece.convex for piece in pieces):
        return None
    return [piece.box() for piece in pieces]


def _split(piece: _Block, axis: int, index: int) -> list[_Block] | None:
    """The parts of ``piece`` on either side of grid plane ``index`` along ``axis`` (the
    upper first, as manifold3d's split gives them), when the plane passes through it and
    it is not convex. Both parts hold a cell: the plane lies between the piece's end
    cells."""
    # grid planes are MIN_SPACING apart: strictly inside the piece's box (by more
    # than convex_pieces' 1e-9) is strictly between its end planes
    if not (piece.lo[axis] < index <= piece.hi[axis]) or piece.convex:
        return None
    rows = piece.rows
    if axis == 0:  # each row splits at bit index
        below = (1 << index) - 1
        upper = {row: bits & ~below for row, bits in rows.items() if bits >> index}
        lower = {row: bits & below for row, bits in rows.items() if bits & below}
    else:  # each row goes whole to one side
        upper = {row: bits for row, bits in rows.items() if row[axis - 1] >= index}
        lower = {row: bits for row, bits in rows.items() if row[axis - 1] < index}
    return [_Block(piece.grid, upper), _Block(piece.grid, lower)]


class _Grid:
    """The solid's grid planes, and the cell volumes the convexity test weighs gaps by,
    which every piece cut from it shares. The volumes are computed when a piece first
    does not fill its box: a solid that is one box needs none."""

    def __init__(self, planes: list[np.ndarray]):
        self.planes = planes

    @functools.cached_property
    def volumes(self) -> np.ndarray:
        """Each cell's volume, indexed ``[i, j, k]``: the product of its extents."""
        dx, dy, dz = (np.diff(g) for g in self.planes)
        return dx[:, None, None] * dy[None, :, None] * dz[None, None, :]

    @functools.cached_property
    def limit(self) -> float:
        """The volume an empty cell between two cells of a piece must exceed for the
        piece to fail the convexity test: :data:`_CONVEX_TOLERANCE` of the whole grid's."""
        return _CONVEX_TOLERANCE * float(self.volumes.sum())


class _Block:
    """A piece being cut: its cells (:data:`_Rows`), the index range ``lo``…``hi`` it
    occupies along each axis, and (once asked) whether it passes ``convex_pieces``'
    convexity test.

    The cells are bits of Python integers, not a boolean array: a piece spans a few
    cells each way, and integer operations on whole rows cut it and find its gaps in
    less time than the calls numpy needs on arrays that small."""

    __slots__ = ("grid", "rows", "lo", "hi", "_convex")

    def __init__(self, grid: _Grid, rows: _Rows):
        self.grid, self.rows = grid, rows
        ys, zs = zip(*rows)
        xs = functools.reduce(operator.or_, rows.values())
        self.lo = ((xs & -xs).bit_length() - 1, min(ys), min(zs))
        self.hi = (xs.bit_length() - 1, max(ys), max(zs))
        self._convex: bool | None = None

    @property
    def convex(self) -> bool:
        """The piece's volume is within the tolerance of its hull's: it fills its
        bounding box, or the hull of its cells' corners is no larger."""
        if self._convex is None:
            (x0, y0, z0), (x1, y1, z1) = self.lo, self.hi
            full = (2 << x1) - (1 << x0)
            fills = (len(self.rows) == (y1 - y0 + 1) * (z1 - z0 + 1)
                     and all(bits == full for bits in self.rows.values()))
            self._convex = fills or (not self._has_gap() and self._hull_test())
        return self._convex

    def _has_gap(self) -> bool:
        """Whether an empty cell lies between two of the piece's cells in one row: the
        hull then holds that whole cell, so the piece fails the convexity test (when the
        cell's volume is above the tolerance)."""
        volumes, limit = self.grid.volumes, self.grid.limit
        return any(volumes[cell] > limit for cell in self._gaps())

    def _gaps(self) -> Iterator[tuple[int, int, int]]:
        """The empty cells between two of the piece's cells in a row along x, y or z
        (some more than once)."""
        rows = self.rows
        (_, y0, z0), (_, y1, z1) = self.lo, self.hi
        for (j, k), bits in rows.items():  # along x: the bits between a row's end bits
            for i in _indices(((1 << bits.bit_length()) - (bits & -bits)) & ~bits):
                yield i, j, k
        if y1 - y0 > 1:  # along y (three rows or more, to have one between two)
            for k in range(z0, z1 + 1):
                for n, i in _between([rows.get((j, k), 0) for j in range(y0, y1 + 1)]):
                    yield i, y0 + n, k
        if z1 - z0 > 1:  # along z
            for j in range(y0, y1 + 1):
                for n, i in _between([rows.get((j, k), 0) for k in range(z0, z1 + 1)]):
                    yield i, j, z0 + n

    def _hull_test(self) -> bool:
        # the cells in C order, as np.argwhere lists them: the volume is the same sum
        index = np.array(sorted((i, j, k) for (j, k), bits in self.rows.items()
                                for i in _indices(bits)))
        volume = float(self.grid.volumes[tuple(index.T)].sum())
        planes = self.grid.planes
        corners = np.stack([planes[k][index[:, k] + _CORNERS[:, k, None]] for k in range(3)],
                           axis=-1).reshape(-1, 3)  # corner by corner, each over the cells
        hull = manifold3d.Manifold.hull_points(corners).volume()
        return hull > 0 and volume >= hull * (1.0 - _CONVEX_TOLERANCE)

    def box(self) -> scene.MeshArrays:
        """The piece, which fills its bounding box, as that box's corners and triangles."""
        planes = self.grid.planes
        lo = [planes[k][self.lo[k]] for k in range(3)]
        hi = [planes[k][self.hi[k] + 1] for k in range(3)]
        return scene.MeshArrays(np.where(_CORNERS, hi, lo), _BOX_FACES.copy())


def _indices(bits: int) -> Iterator[int]:
    """The indices of the set bits, lowest first."""
    while bits:
        low = bits & -bits
        yield low.bit_length() - 1
        bits ^= low


def _between(line: list[int]) -> Iterator[tuple[int, int]]:
    """``(n, i)`` for each bit ``i`` that row ``line[n]`` lacks and both a row before it
    and a row after it hold: of rows side by side along y (or z), the empty cells between
    two cells in a row along y (or z)."""
    after = [0] * len(line)
    for n in range(len(line) - 1, 0, -1):
        after[n - 1] = after[n] | line[n]
    before = 0
    for n, bits in enumerate(line):
        yield from ((n, i) for i in _indices(before & after[n] & ~bits))
        before |= bits


def _cells(x_faces: np.ndarray, grid: list[np.ndarray]) -> np.ndarray | None:
    """Which grid cells lie inside the solid, from its faces in planes x = constant
    (triangles, counter-clockwise seen from outside): along each row of cells, each
    face the row passes through enters the solid (outward normal −x) or leaves it."""
    xs, ys, zs = grid
    py = ys[:-1] + PROBE[0] * np.diff(ys)
    pz = zs[:-1] + PROBE[1] * np.diff(zs)
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
