"""An exploration proxy: how far a frontier-exploring robot drives to see a floor.

Yamauchi's frontier exploration (1997) drives a robot to the nearest boundary between
seen free space and unseen space, senses, and repeats. On the navigability check's grids
(:class:`cga.checks.navigability.DriveSpace`) this module simulates it on a coarse grid
(cells of about :data:`CELL` m): the robot senses every free cell within
:data:`SENSOR_RANGE` m that a straight ray reaches without crossing an obstacle, then
drives along the shortest drivable path to the nearest cell that touches an unseen free
cell, until it has seen ``share`` of the free floor it could ever see. The result, the
path length, grows with the floor's size, its number of rooms and dead ends, and the
furniture that hides corners: the paper's operators reported exactly this cost as
"forces you to repeatedly come back at the same location" (Zwennes 2011, §6).

Docs: docs/difficulty.md ("exploration path").
"""

from __future__ import annotations

import functools
import math
from typing import Literal

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

__all__ = ["CELL", "SENSOR_RANGE", "MAX_GOALS", "exploration_path"]

CELL = 0.25
"""Target size (m) of the coarse grid's cells."""

SENSOR_RANGE = 5.0
"""Range (m) of the simulated 360° range sensor (a small indoor lidar)."""

MAX_GOALS = 400
"""Frontier goals at most; a floor that needs more reports the path driven so far."""

_RAYS = 180


def _coarsen(mask: np.ndarray, factor: int, how: Literal["any", "all"]) -> np.ndarray:
    """Blocks of ``factor`` × ``factor`` cells: true where any (or all) of its cells are.
    The blocks' rows are combined first, then their columns: ``2·factor`` ors (or ands)
    of strided slices, several times faster than numpy's reduction over the blocks'
    two inner axes."""
    rows, cols = (math.ceil(n / factor) * factor for n in mask.shape)
    padded = np.zeros((rows, cols), dtype=bool)
    padded[:mask.shape[0], :mask.shape[1]] = mask
    combine = np.logical_or if how == "any" else np.logical_and
    strips = functools.reduce(combine, [padded[i::factor] for i in range(factor)])
    return functools.reduce(combine, [strips[:, j::factor] for j in range(factor)])


_NEIGHBOURS = ((-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1))
"""The 8 neighbour offsets in row-major order."""


def _grid_graph(drivable: np.ndarray, cell: float) -> tuple[csr_matrix, np.ndarray]:
    """CSR graph of the 8-connected drivable cells (edge weights in metres) and the
    graph index of every drivable cell (-1 elsewhere).

    Every edge is stored both ways, so a search runs it with ``directed=True``: scipy's
    undirected search would transpose the matrix on every call, and the distances are
    the same (each is the least of its settled neighbours' sums, whatever the order).
    The indices sit in a frame of -1 one cell wide, so a cell's 8 neighbours are 8 fixed
    offsets in the flat frame, read in one gather; the rows are built in order (a
    cell's neighbours, row-major, have rising indices), so no sort is needed."""
    rows, cols = drivable.shape
    framed = np.full((rows + 2, cols + 2), -1, dtype=np.int32)
    framed[1:-1, 1:-1][drivable] = 0
    at = np.flatnonzero(framed == 0)  # the drivable cells, row-major, in the frame
    framed.ravel()[at] = np.arange(len(at), dtype=np.int32)
    steps = np.array([dr * (cols + 2) + dc for dr, dc in _NEIGHBOURS])
    heads = framed.ravel()[at[:, None] + steps]
    edges = heads >= 0
    weights = np.empty(heads.shape)
    weights[:] = [cell * math.hypot(dr, dc) for dr, dc in _NEIGHBOURS]
    indptr = np.zeros(len(at) + 1, dtype=np.int64)
    np.cumsum(_row_counts(edges), out=indptr[1:])
    graph = csr_matrix((weights[edges], heads[edges], indptr), shape=(len(at), len(at)))
    return graph, framed[1:-1, 1:-1]


def _row_counts(flags: np.ndarray) -> np.ndarray:
    """``uint64[n]``: the true flags in each row of ``bool[n, 8]``. A row's 8 flags are
    the 8 bytes (0 or 1) of one 64-bit word, and multiplying it by 0x0101…01 adds them
    all up in the top byte (a sum of at most 8 carries into no other byte): a fraction
    of numpy's ``count_nonzero(axis=1)``."""
    words = np.ascontiguousarray(flags).view(np.uint64).ravel()
    return (words * np.uint64(0x0101010101010101)) >> np.uint64(56)


def _round(mask: np.ndarray) -> np.ndarray:
    """The cells of the 3 × 3 squares round the true cells of ``mask``
    (``disc_dilation(mask, 2)``): grown sideways, then up and down, one cell each."""
    wide = mask.copy()
    wide[:, 1:] |= mask[:, :-1]
    wide[:, :-1] |= mask[:, 1:]
    out = wide.copy()
    out[1:] |= wide[:-1]
    out[:-1] |= wide[1:]
    return out


def _ray_offsets(reach: int) -> np.ndarray:
    """``int[rays, steps, 2]``: the cells each ray crosses, nearest first."""
    angles = np.linspace(0.0, 2 * math.pi, _RAYS, endpoint=False)
    steps = np.arange(1, 2 * reach + 1) / 2.0  # half-cell steps: no cell skipped
    dr = np.rint(np.outer(np.sin(angles), steps)).astype(int)
    dc = np.rint(np.outer(np.cos(angles), steps)).astype(int)
    return np.stack([dr, dc], axis=-1)


@functools.lru_cache(maxsize=8)
def _ray_cells(reach: int) -> np.ndarray:
    """``int[rays, steps, 2]``: :func:`_ray_offsets` with each ray's cells kept once and
    the robot's own cell left out, each ray padded with its last cell.

    The same cells are seen: a ray's rounded cells move away from the robot in each
    coordinate, so a cell's repeats follow it (they stop the ray where it does), and the
    own cell, which never stops a ray, is seen anyway. A ray keeps about half its steps.
    """
    rays = []
    for ray in _ray_offsets(reach):
        moved = np.ones(len(ray), dtype=bool)
        moved[1:] = np.any(ray[1:] != ray[:-1], axis=1)
        rays.append(ray[moved & np.any(ray != 0, axis=1)])
    length = max(1, max(len(ray) for ray in rays))
    out = np.zeros((len(rays), length, 2), dtype=int)
    for i, ray in enumerate(rays):
        if len(ray):
            out[i, :len(ray)], out[i, len(ray):] = ray, ray[-1]
    out.flags.writeable = False
    return out


class _Sensor:
    """The 360° range sensor on the coarse grid: :meth:`sense` marks the cells seen.

    The grids sit in a frame of occluding cells as wide as the sensor's reach, so a
    ray's cells are fixed offsets in the flat frame (a ray leaving the grid stops where
    it leaves, as on the bare grid) and one gather reads them all."""

    def __init__(self, occluder: np.ndarray, reach: int) -> None:
        rays = _ray_cells(reach)
        self.margin = margin = int(np.abs(rays).max())
        rows, cols = occluder.shape
        self.width = cols + 2 * margin
        inner = (slice(margin, margin + rows), slice(margin, margin + cols))
        clear = np.zeros((rows + 2 * margin, self.width), dtype=bool)
        clear[inner] = ~occluder
        self.clear = clear.ravel()
        self.steps = rays[..., 0] * self.width + rays[..., 1]
        framed_seen = np.zeros_like(clear)
        self.framed_seen = framed_seen.ravel()
        self.seen = framed_seen[inner]
        """``bool[rows, cols]``: the cells seen so far (a view of the frame)."""

    def sense(self, at: tuple[int, int]) -> None:
        """Marks the robot's cell and the cells each ray reaches before an occluder."""
        here = (at[0] + self.margin) * self.width + at[1] + self.margin
        cells = here + self.steps
        visible = np.logical_and.accumulate(self.clear[cells], axis=1)
        self.framed_seen[cells[visible]] = True
        self.framed_seen[here] = True


def _nearest(graph: csr_matrix, source: int, candidates: np.ndarray,
             near: float) -> tuple[int, float] | None:
    """The candidate (graph index) nearest to ``source`` along the graph, first in
    ``candidates`` among equals, and its distance; None when none is reachable.

    The search stops at ``near`` (scipy's ``limit``) first, and searches the whole
    graph only when no candidate lies within: every cell within the limit gets the
    very distance of a full search (the least of its neighbours' sums, and the
    neighbours that give it lie within too), and farther cells are farther than the
    nearest candidate. Most goals lie within one sensor range (the robot saw that far),
    and a search within it settles a fraction of the floor's cells."""
    for limit in (near, np.inf):
        distances = dijkstra(graph, directed=True, indices=source, limit=limit)
        reachable = candidates[np.isfinite(distances[candidates])]
        if reachable.size:
            goal = int(reachable[np.argmin(distances[reachable])])
            return goal, float(distances[goal])
    return None


def exploration_path(free: np.ndarray, blocked: np.ndarray, drivable: np.ndarray,
                     start: tuple[int, int], resolution: float, *, share: float = 0.95,
                     sensor_range: float = SENSOR_RANGE) -> float:
    """Path length (m) a frontier explorer drives from ``start`` until it has seen
    ``share`` of the free cells it can see from anywhere it can drive.

    Parameters
    ----------
    free
        ``bool[rows, cols]``: the floor to be seen (the free floor of the rooms the
        robot reaches). A coarse cell counts when all its fine cells are free.
    blocked
        Cells that stop a sensor ray (walls, furniture).
    drivable
        Cells the robot's centre can reach from ``start``.
    start
        The robot's first cell on these grids.
    resolution
        Cell size (m) of the grids.

    Returns
    -------
    float
        Metres driven; 0 when the first view already shows ``share``. When no
        frontier is left before ``share`` is seen (floor hidden behind furniture), the
        path driven until then.

    Notes
    -----
    One Dijkstra search over the coarse drivable cells per goal (two when the goal lies
    beyond the sensor range); at most :data:`MAX_GOALS` goals.
    """
    factor = max(1, round(CELL / resolution))
    cell = factor * resolution
    target = _coarsen(free, factor, "all")
    drive = _coarsen(drivable, factor, "any")
    position = (start[0] // factor, start[1] // factor)
    drive[position] = True
    graph, index = _grid_graph(drive, cell)
    cells = np.flatnonzero(drive)  # graph index -> flat cell
    sensor = _Sensor(_coarsen(blocked, factor, "any"), int(sensor_range / cell))
    seen = sensor.seen
    targets = int(target.sum())
    wanted = share * targets
    sensor.sense(position)
    driven = 0.0
    for _ in range(MAX_GOALS):
        unseen = target & ~seen
        if targets - int(unseen.sum()) >= wanted:
            break
        candidates = index[drive & _round(unseen)]
        if candidates.size == 0:
            break
        nearest = _nearest(graph, int(index[position]), candidates, sensor_range)
        if nearest is None:
            break
        goal, distance = nearest
        driven += distance
        position = divmod(int(cells[goal]), target.shape[1])
        sensor.sense(position)
    return driven
