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

import math
from typing import Literal

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from cga.checks._distance import disc_dilation

__all__ = ["CELL", "SENSOR_RANGE", "MAX_GOALS", "exploration_path"]

CELL = 0.25
"""Target size (m) of the coarse grid's cells."""

SENSOR_RANGE = 5.0
"""Range (m) of the simulated 360° range sensor (a small indoor lidar)."""

MAX_GOALS = 400
"""Frontier goals at most; a floor that needs more reports the path driven so far."""

_RAYS = 180


def _coarsen(mask: np.ndarray, factor: int, how: Literal["any", "all"]) -> np.ndarray:
    """Blocks of ``factor`` × ``factor`` cells: true where any (or all) of its cells are."""
    rows, cols = (math.ceil(n / factor) * factor for n in mask.shape)
    padded = np.zeros((rows, cols), dtype=bool)
    padded[:mask.shape[0], :mask.shape[1]] = mask
    blocks = padded.reshape(rows // factor, factor, cols // factor, factor)
    return np.asarray(blocks.any(axis=(1, 3)) if how == "any" else blocks.all(axis=(1, 3)))


_NEIGHBOURS = ((-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1))
"""The 8 neighbour offsets in row-major order."""


def _grid_graph(drivable: np.ndarray, cell: float) -> tuple[csr_matrix, np.ndarray]:
    """CSR graph of the 8-connected drivable cells (edge weights in metres) and the
    graph index of every drivable cell (-1 elsewhere).

    Every edge is stored both ways, so a search runs it with ``directed=True``: scipy's
    undirected search would transpose the matrix on every call, and the distances are
    the same (each is the least of its settled neighbours' sums, whatever the order).
    The rows are built in order (a cell's neighbours, row-major, have rising indices),
    so no sort is needed."""
    index = np.full(drivable.shape, -1, dtype=np.int64)
    flat = np.flatnonzero(drivable)
    index.ravel()[flat] = np.arange(len(flat))
    padded = np.pad(index, 1, constant_values=-1)
    at = np.divmod(flat, drivable.shape[1])
    neighbours, weights = [], []
    for dr, dc in _NEIGHBOURS:
        neighbours.append(padded[at[0] + 1 + dr, at[1] + 1 + dc])
        weights.append(cell * math.hypot(dr, dc))
    heads = np.stack(neighbours, axis=1)
    edges = heads >= 0
    indptr = np.zeros(len(flat) + 1, dtype=np.int64)
    np.cumsum(edges.sum(axis=1), out=indptr[1:])
    data = np.broadcast_to(np.asarray(weights), heads.shape)[edges]
    graph = csr_matrix((data, heads[edges], indptr), shape=(len(flat), len(flat)))
    return graph, index


def _ray_offsets(reach: int) -> np.ndarray:
    """``int[rays, steps, 2]``: the cells each ray crosses, nearest first."""
    angles = np.linspace(0.0, 2 * math.pi, _RAYS, endpoint=False)
    steps = np.arange(1, 2 * reach + 1) / 2.0  # half-cell steps: no cell skipped
    dr = np.rint(np.outer(np.sin(angles), steps)).astype(int)
    dc = np.rint(np.outer(np.cos(angles), steps)).astype(int)
    return np.stack([dr, dc], axis=-1)


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
    One Dijkstra search over the coarse drivable cells per goal; at most
    :data:`MAX_GOALS` goals.
    """
    factor = max(1, round(CELL / resolution))
    cell = factor * resolution
    target = _coarsen(free, factor, "all")
    occluder = _coarsen(blocked, factor, "any")
    drive = _coarsen(drivable, factor, "any")
    position = (start[0] // factor, start[1] // factor)
    drive[position] = True
    graph, index = _grid_graph(drive, cell)
    cells = np.flatnonzero(drive)  # graph index -> flat cell
    offsets = _ray_offsets(int(sensor_range / cell))
    rows, cols = target.shape
    seen = np.zeros_like(target)

    def sense(at: tuple[int, int]) -> None:
        r = at[0] + offsets[..., 0]
        c = at[1] + offsets[..., 1]
        inside = (r >= 0) & (r < rows) & (c >= 0) & (c < cols)
        r, c = np.where(inside, r, 0), np.where(inside, c, 0)
        # the robot's own cell never hides anything (it may hold a wall's edge)
        stop = (occluder[r, c] & ((r != at[0]) | (c != at[1]))) | ~inside
        visible = np.cumsum(stop, axis=1) == 0
        seen[r[visible], c[visible]] = True
        seen[at] = True

    wanted = share * int(target.sum())
    sense(position)
    driven = 0.0
    for _ in range(MAX_GOALS):
        if int((seen & target).sum()) >= wanted:
            break
        unseen = target & ~seen
        frontier = drive & disc_dilation(unseen, 2)  # the 3 × 3 cells round each
        candidates = index[frontier]
        if candidates.size == 0:
            break
        distances = dijkstra(graph, directed=True, indices=int(index[position]))
        reachable = candidates[np.isfinite(distances[candidates])]
        if reachable.size == 0:
            break
        goal = int(reachable[np.argmin(distances[reachable])])
        driven += float(distances[goal])
        position = divmod(int(cells[goal]), cols)
        sense(position)
    return driven
